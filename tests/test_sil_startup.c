/* SIL start-up: the app's whole start sequence on the simulated board
 * through sil_run() with [run] calibrate = on, align = on. The plant's
 * current ADC has offsets and noise and its encoder an offset the
 * controller is not told; the app calibrates (PWM off), aligns the rotor
 * (a vector at +90 deg el, then turned onto phase a) and then runs in
 * speed mode to 500 r/min with a load. Asserted: the calibrated offsets
 * against the sim's, the identified encoder offset against the plant's,
 * the start-up's timing, and that the drive then runs on the right angle
 * (speed held, id = 0 as MTPA asks).
 *
 * Where the rotor starts: the plant starts at mechanical angle 0, which is
 * encoder count 0, with its d axis at plant.encoder_offset_el_rad from
 * phase a (hal_sim.h); so that offset is also the rotor's start angle, and
 * pi puts it exactly 180 deg el from phase a: the dead point of the phase-a
 * vector, where a one-step alignment left it (offset pi off, then an
 * overspeed fault in RUN). -pi/2 is the pre-position vector's dead point.
 * app.h derives that no start angle is a dead point of both steps; the
 * sweep checks every 10 deg and both dead points. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>

#include "app.h"
#include "board_cfg.h"
#include "sil.h"

#define TWO_PI       6.283185307179586
#define POLE_PAIRS   3.0
#define CPR          10000.0
/* one encoder count in electrical radians: 2 pi p / cpr = 1.885 mrad */
#define COUNT_EL_RAD (TWO_PI * POLE_PAIRS / CPR)
/* Alignment tolerance beyond the count: the rotor's residual motion after
 * the hold, the ramp's and dead time's effect on where it rests (none with
 * u_beta = 0) - stated allowance, measured well inside it. */
#define ALIGN_TOL_EL_RAD 0.5e-3
#define PI_D         3.141592653589793
#define TS_S         1e-4
/* ALIGN lasts both ramps and both holds, plus the period that aligns */
#define ALIGN_S      (2.0 * BOARD_ALIGN_RAMP_S + BOARD_ALIGN_PREPOS_S + BOARD_ALIGN_SETTLE_S + TS_S)
#define OFFSET_A_A   0.30          /* sim ADC offsets [A] */
#define OFFSET_B_A   -0.20
#define NOISE_A      0.02          /* sim ADC noise, std dev [A] */
#define ADC_LSB_A    (30.0 / 4096.0) /* 12 bit over +-15 A */
/* calibrated offset tolerance: half an LSB of rounding bias plus 4 sigma of the mean of N samples */
#define CAL_TOL_A    (0.5 * ADC_LSB_A + 4.0 * NOISE_A / sqrt((double)BOARD_CAL_SAMPLES))
#define SPEED_RPM    500.0
#define LOAD_NM      2.0
/* after RUN (1.31 s): speed ramp 1.4-1.6 s, load from 1.7 s */
#define WIN_T0_S     2.1           /* steady window [s] */
#define WIN_T1_S     2.3

typedef struct {
    double t_first[7];             /* first t_s in each app_state_t value; NaN if never */
    double speed_err_max_rpm;      /* window: max |speed - 500| */
    double id_sum_A, id_abs_max_A; /* window: true id */
    double iq_sum_A;
    uint32_t n;
} startup_fig_t;

static int on_row(const sil_row_t *row, void *user)
{
    startup_fig_t *f = user;
    const int st = (int)row->state;
    if (st >= 0 && st < 7 && isnan(f->t_first[st])) {
        f->t_first[st] = row->t_s;
    }
    if (row->t_s >= WIN_T0_S && row->t_s < WIN_T1_S) {
        f->speed_err_max_rpm = fmax(f->speed_err_max_rpm, fabs(row->speed_rpm - SPEED_RPM));
        f->id_sum_A += row->id_A;
        f->id_abs_max_A = fmax(f->id_abs_max_A, fabs(row->id_A));
        f->iq_sum_A += row->iq_A;
        f->n++;
    }
    return 0;
}

static double wrap_pi(double x)
{
    return x - TWO_PI * floor(x / TWO_PI + 0.5);
}

static void startup(double enc_offset_el_rad, const char *model)
{
    char sets[12][96];
    char err[SCENARIO_ERR_LEN];
    scenario_t sc;
    scenario_defaults(&sc);
    int n = 0;
    snprintf(sets[n++], sizeof sets[0], "plant.encoder_offset_el_rad=%.17g", enc_offset_el_rad);
    snprintf(sets[n++], sizeof sets[0], "plant.adc_offset_a_A=%.3f", OFFSET_A_A);
    snprintf(sets[n++], sizeof sets[0], "plant.adc_offset_b_A=%.3f", OFFSET_B_A);
    snprintf(sets[n++], sizeof sets[0], "plant.adc_noise_A=%.3f", NOISE_A);
    snprintf(sets[n++], sizeof sets[0], "plant.model=%s", model);
    snprintf(sets[n++], sizeof sets[0], "plant.deadtime_s=1e-6");
    snprintf(sets[n++], sizeof sets[0], "controller.mode=speed");
    /* start-up takes 1.31 s (0.11 s calibration, 1.2 s alignment); then ramp and load */
    snprintf(sets[n++], sizeof sets[0], "reference.speed_rpm=0:0, 1.4:0, 1.6:%.0f~", SPEED_RPM);
    snprintf(sets[n++], sizeof sets[0], "load.torque_Nm=0:0, 1.7:%.1f", LOAD_NM);
    snprintf(sets[n++], sizeof sets[0], "run.duration_s=%.2f", WIN_T1_S);
    snprintf(sets[n++], sizeof sets[0], "run.calibrate=on");
    snprintf(sets[n++], sizeof sets[0], "run.align=on");
    for (int i = 0; i < n; i++) {
        if (scenario_set(&sc, sets[i], err, sizeof err) != 0) {
            fail_msg("%s", err);
        }
    }
    sc.run.log_every = 1u;
    assert_int_equal(scenario_finish(&sc, err, sizeof err), 0);

    startup_fig_t f = { 0 };
    for (int s = 0; s < 7; s++) {
        f.t_first[s] = NAN;
    }
    sil_result_t res;
    assert_int_equal(sil_run(&sc, on_row, &f, &res), 0);

    const double enc_err = wrap_pi(res.enc_offset_el_rad - enc_offset_el_rad);
    const double cal_err_a = res.i_offset_a_A - OFFSET_A_A;
    const double cal_err_b = res.i_offset_b_A - OFFSET_B_A;
    const double id_mean = f.id_sum_A / (double)f.n;
    const double iq_mean = f.iq_sum_A / (double)f.n;
    print_message("SIL start-up (%s, encoder offset %.3f rad): CALIBRATE at %.4f s, ALIGN at %.4f s, "
                  "RUN at %.4f s; calibrated offsets err a %+.2f mA, b %+.2f mA (tol %.2f mA); "
                  "encoder offset err %+.3f mrad el (count %.3f mrad + tol %.3f mrad); "
                  "window: max |speed err| %.2f r/min, id mean %+.4f A, max |id| %.3f A, iq mean %.3f A\n",
                  model, enc_offset_el_rad, f.t_first[APP_STATE_CALIBRATE], f.t_first[APP_STATE_ALIGN],
                  f.t_first[APP_STATE_RUN], 1e3 * cal_err_a, 1e3 * cal_err_b, 1e3 * CAL_TOL_A,
                  1e3 * enc_err, 1e3 * COUNT_EL_RAD, 1e3 * ALIGN_TOL_EL_RAD, f.speed_err_max_rpm, id_mean,
                  f.id_abs_max_A, iq_mean);

    assert_int_equal(res.final_state, APP_STATE_RUN);
    assert_int_equal(res.final_fault, APP_FAULT_NONE);
    /* the sequence in order, starting with the first ISR */
    assert_true(f.t_first[APP_STATE_CALIBRATE] == 0.0);
    assert_true(f.t_first[APP_STATE_ALIGN] > f.t_first[APP_STATE_CALIBRATE]);
    assert_true(f.t_first[APP_STATE_RUN] > f.t_first[APP_STATE_ALIGN]);
    assert_true(fabs(f.t_first[APP_STATE_RUN] - f.t_first[APP_STATE_ALIGN] - ALIGN_S) < 0.5 * TS_S);
    assert_true(f.t_first[APP_STATE_RUN] < 1.4);

    assert_true(fabs(cal_err_a) <= CAL_TOL_A);
    assert_true(fabs(cal_err_b) <= CAL_TOL_A);
    assert_true(fabs(enc_err) <= COUNT_EL_RAD + ALIGN_TOL_EL_RAD);

    /* the right angle: speed held under load, id = 0 (MTPA of an SPMSM);
     * an angle error d would show as id = -iq sin d (0.1 rad: -0.19 A) */
    assert_true(f.speed_err_max_rpm < 5.0);
    assert_true(fabs(id_mean) < 0.02);
    assert_true(fabs(iq_mean - LOAD_NM / (1.5 * POLE_PAIRS * 0.24)) < 0.05);
}

static void startup_offset_2rad_averaged(void **state)
{
    (void)state;
    startup(2.0, "averaged");
}

/* the other way round, nearly half a turn (the rotor turns by +2.9 rad el) */
static void startup_offset_minus_2_9rad_averaged(void **state)
{
    (void)state;
    startup(-2.9, "averaged");
}

static void startup_offset_2rad_switching(void **state)
{
    (void)state;
    startup(2.0, "switching");
}

/* The rotor exactly 180 deg el from phase a: the phase-a vector's dead point. */
static void startup_rotor_180deg_from_phase_a_averaged(void **state)
{
    (void)state;
    startup(PI_D, "averaged");
}

static void startup_rotor_180deg_from_phase_a_switching(void **state)
{
    (void)state;
    startup(PI_D, "switching");
}

/* The rotor exactly on the pre-position vector's dead point (-90 deg el):
 * step 1 leaves it there, the turn onto phase a moves it. */
static void startup_rotor_on_prepos_dead_point(void **state)
{
    (void)state;
    startup(-0.5 * PI_D, "averaged");
}

/* Alignment only, from every 10 deg and both dead points: the offset
 * found within the tolerance each time (1 us dead time, ADC offsets and
 * noise, no friction). */
static void alignment_from_every_start_angle(void **state)
{
    (void)state;
    double worst = 0.0;
    double worst_at = 0.0;
    for (int i = 0; i < 38; i++) {
        const double start = (i < 36) ? -PI_D + (double)i * PI_D / 18.0 : ((i == 36) ? PI_D : -0.5 * PI_D);
        char sets[9][96];
        char err[SCENARIO_ERR_LEN];
        scenario_t sc;
        scenario_defaults(&sc);
        int n = 0;
        snprintf(sets[n++], sizeof sets[0], "plant.encoder_offset_el_rad=%.17g", start);
        snprintf(sets[n++], sizeof sets[0], "plant.adc_offset_a_A=%.3f", OFFSET_A_A);
        snprintf(sets[n++], sizeof sets[0], "plant.adc_offset_b_A=%.3f", OFFSET_B_A);
        snprintf(sets[n++], sizeof sets[0], "plant.adc_noise_A=%.3f", NOISE_A);
        snprintf(sets[n++], sizeof sets[0], "plant.deadtime_s=1e-6");
        snprintf(sets[n++], sizeof sets[0], "controller.mode=speed");
        snprintf(sets[n++], sizeof sets[0], "run.duration_s=1.35");
        snprintf(sets[n++], sizeof sets[0], "run.calibrate=on");
        snprintf(sets[n++], sizeof sets[0], "run.align=on");
        for (int j = 0; j < n; j++) {
            if (scenario_set(&sc, sets[j], err, sizeof err) != 0) {
                fail_msg("%s", err);
            }
        }
        assert_int_equal(scenario_finish(&sc, err, sizeof err), 0);
        sil_result_t res;
        assert_int_equal(sil_run(&sc, NULL, NULL, &res), 0);
        assert_int_equal(res.final_state, APP_STATE_RUN);
        const double e = fabs(wrap_pi(res.enc_offset_el_rad - start));
        if (e > worst) {
            worst = e;
            worst_at = start;
        }
        assert_true(e <= COUNT_EL_RAD + ALIGN_TOL_EL_RAD);
    }
    print_message("alignment from 36 start angles and both dead points: worst |offset err| %.3f mrad el "
                  "(start %.3f rad; count %.3f mrad + tol %.3f mrad)\n",
                  1e3 * worst, worst_at, 1e3 * COUNT_EL_RAD, 1e3 * ALIGN_TOL_EL_RAD);
}

/* [controller] encoder_offset_el_rad: what the controller is told. Align
 * off: the told value, not the plant's, is the controller's offset (by
 * default the plant's); align on: the alignment's measurement replaces it. */
static double told_offset(const char *const *sets)
{
    char err[SCENARIO_ERR_LEN];
    scenario_t sc;
    scenario_defaults(&sc);
    for (int i = 0; sets[i] != NULL; i++) {
        if (scenario_set(&sc, sets[i], err, sizeof err) != 0) {
            fail_msg("%s", err);
        }
    }
    assert_int_equal(scenario_finish(&sc, err, sizeof err), 0);
    sil_result_t res;
    assert_int_equal(sil_run(&sc, NULL, NULL, &res), 0);
    return res.enc_offset_el_rad;
}

static void controller_encoder_offset_told(void **state)
{
    (void)state;
    const char *const told[] = { "plant.encoder_offset_el_rad=0.3", "controller.encoder_offset_el_rad=0.2",
                                 "run.duration_s=0.01", NULL };
    const char *const dflt[] = { "plant.encoder_offset_el_rad=0.3", "run.duration_s=0.01", NULL };
    const char *const aligned[] = { "plant.encoder_offset_el_rad=0.3", "controller.encoder_offset_el_rad=0.2",
                                    "run.align=on", "reference.speed_rpm=0", "run.duration_s=1.35", NULL };
    const double a = told_offset(told);
    const double b = told_offset(dflt);
    const double c = told_offset(aligned);
    print_message("controller's encoder offset: told 0.2 -> %.4f, default -> %.4f, aligned (plant 0.3) -> %.4f rad\n",
                  a, b, c);
    assert_float_equal(a, 0.2, 1e-6);
    assert_float_equal(b, 0.3, 1e-6);
    assert_float_equal(c, 0.3, 0.01); /* a count of 2500 lines is 7.5 mrad el */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(controller_encoder_offset_told),
        cmocka_unit_test(startup_offset_2rad_averaged),
        cmocka_unit_test(startup_offset_minus_2_9rad_averaged),
        cmocka_unit_test(startup_offset_2rad_switching),
        cmocka_unit_test(startup_rotor_180deg_from_phase_a_averaged),
        cmocka_unit_test(startup_rotor_180deg_from_phase_a_switching),
        cmocka_unit_test(startup_rotor_on_prepos_dead_point),
        cmocka_unit_test(alignment_from_every_start_angle),
    };
    return cmocka_run_group_tests_name("sil_startup", tests, NULL, NULL);
}
