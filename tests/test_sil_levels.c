/* SIL: the build levels (firmware/app/level.h) through sil_run(), each on a
 * right board showing what it should, and level 3 on the wrong boards.
 *   1 PWM_CHECK with the bus down to 1 V from the start ([faults] vdc_sag:
 *     the board's limits stay the 311 V bus's): the legs at 0.25, 0.5,
 *     0.75 from the start request on, no undervoltage trip (level 5 on the
 *     same bus trips UNDERVOLTAGE at once), no other fault.
 *   1, 2 on the charged 311 V bus: BUS_CHARGED at the start, PWM never on;
 *     level 1 on a 12 V bus switches; a 28 V bus surging to 34 V while it
 *     does trips BUS_CHARGED within that period.
 *   2 ADC_CHECK: PWM never on; the offsets measured and the readings
 *     reported against the plant's ADC offsets (within one LSB, 30 A /
 *     4096) and the 1 V bus (within one LSB, 600 V / 4096).
 *   3 ENC_CHECK: calibration, the 0.2 s ramp, one electrical turn to fall
 *     in, then one mechanical turn at 60 r/min (3 electrical turns of
 *     the 3-pole-pair motor, 10000 counts): p^ = 3, the current's positive
 *     sequence the 3 A the amplitude aims at (level.h's steady state:
 *     within 10 %, the rotor's oscillation and friction-free load angle),
 *     its negative sequence near 0; then IDLE, PWM off. Told 4 or 2 pole
 *     pairs, an encoder counting down, legs b and c swapped: POLE_PAIRS
 *     (p^ = 3 against 4 or 2), ENCODER_DIRECTION (about -10000 counts),
 *     PHASE_ORDER. The operator's mode and method do not matter.
 *   4 torque control (the scenario's speed mode ignored), shaft held at
 *     300 r/min: 2 N m followed; 6 N m asked, the current held to the
 *     level's limit 0.3 x i_peak 11.11 A = 3.333 A, the torque to kt 3.333 A =
 *     1.5 x 3 x 0.24 x 3.333 = 3.6 N m.
 *   5 the full drive: speed mode to 500 r/min, as without levels. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>

#include "app.h"
#include "hal_sim.h"
#include "sil.h"

#define MAX_ROWS     4000
#define I_LSB_A      (30.0 / 4096.0)    /* the sim's current ADC step (+-15 A, 12 bit) */
#define VDC_LSB_V    (600.0 / 4096.0)   /* its bus ADC step */
#define KT_NM_A      (1.5 * 3.0 * 0.24)  /* Table I */
#define I_LEVEL4_A   (0.3 * 2.0 * 6.0 / KT_NM_A) /* 0.3 x the current limit i_peak = 2 x rated */
#define PI_D         3.14159265358979323846

static sil_row_t g_rows[MAX_ROWS];
static size_t g_n;

static int on_row(const sil_row_t *r, void *user)
{
    (void)user;
    if (g_n < MAX_ROWS) {
        g_rows[g_n++] = *r;
    }
    return 0;
}

/* A run from the defaults with sets[] (a row every 10 periods). */
static void run(const char *const *sets, size_t n, sil_result_t *res)
{
    static scenario_t sc; /* large */
    char err[SCENARIO_ERR_LEN];
    scenario_defaults(&sc);
    for (size_t i = 0; i < n; i++) {
        if (scenario_set(&sc, sets[i], err, sizeof err) != 0) {
            fail_msg("%s", err);
        }
    }
    if (scenario_finish(&sc, err, sizeof err) != 0) {
        fail_msg("%s", err);
    }
    g_n = 0u;
    assert_int_equal(sil_run(&sc, on_row, NULL, res), 0);
}

static void level1_pwm_pattern_without_bus(void **state)
{
    (void)state;
    static const char *const sets[] = { "run.level=1", "faults.vdc_sag_s=0", "faults.vdc_sag_V=1",
                                        "run.duration_s=0.05" };
    sil_result_t res;
    run(sets, 4, &res);
    assert_int_equal(res.final_state, APP_STATE_PWM_CHECK);
    assert_int_equal(res.final_fault, APP_FAULT_NONE);
    assert_int_equal(res.pwm_periods, res.periods);   /* on from the start request's period */
    hal_sim_truth_t tr;
    hal_sim_truth(&tr);
    assert_float_equal(tr.duty[0], 0.25, 1e-6);
    assert_float_equal(tr.duty[1], 0.50, 1e-6);
    assert_float_equal(tr.duty[2], 0.75, 1e-6);
    for (size_t k = 0; k < g_n; k++) {
        assert_int_equal((int)g_rows[k].state, APP_STATE_PWM_CHECK);
    }
    /* the same bus at level 5: undervoltage, at the start */
    static const char *const full[] = { "run.level=5", "faults.vdc_sag_s=0", "faults.vdc_sag_V=1",
                                        "run.duration_s=0.05" };
    run(full, 4, &res);
    assert_int_equal(res.final_fault, APP_FAULT_UNDERVOLTAGE);
    assert_int_equal(res.pwm_periods, 0u);
}

static void levels_1_and_2_refuse_a_charged_bus(void **state)
{
    (void)state;
    static const char *const l1[] = { "run.level=1", "run.duration_s=0.05" };
    static const char *const l2[] = { "run.level=2", "run.duration_s=0.05" };
    sil_result_t res;
    run(l1, 2, &res);
    assert_int_equal(res.final_fault, APP_FAULT_BUS_CHARGED);
    assert_int_equal(res.pwm_periods, 0u);
    assert_float_equal(res.fault_value, 311.0, VDC_LSB_V);
    assert_float_equal(res.fault_limit, 30.0, 0.0);
    run(l2, 2, &res);
    assert_int_equal(res.final_fault, APP_FAULT_BUS_CHARGED);
    assert_int_equal(res.pwm_periods, 0u);
    /* an extra-low bus: level 1 switches */
    static const char *const low[] = { "run.level=1", "plant.vdc_V=12", "run.duration_s=0.05" };
    run(low, 3, &res);
    assert_int_equal(res.final_state, APP_STATE_PWM_CHECK);
    assert_int_equal(res.final_fault, APP_FAULT_NONE);
    assert_int_equal(res.pwm_periods, res.periods);
    /* charged while it switches: the fault in the surge's period, PWM off from there (a 28 V
     * bus: its overvoltage trip, 400 V x 28 / 311 = 36 V, above the 34 V) */
    static const char *const surge[] = { "run.level=1", "plant.vdc_V=28", "faults.vdc_surge_s=0.02",
                                         "faults.vdc_surge_V=34", "run.duration_s=0.05" };
    run(surge, 5, &res);
    assert_int_equal(res.final_fault, APP_FAULT_BUS_CHARGED);
    assert_int_equal(res.fault_state, APP_STATE_PWM_CHECK);
    assert_float_equal(res.t_fault_s, 0.02, 1.5e-4);
    assert_float_equal(res.fault_value, 34.0, VDC_LSB_V);
    assert_int_equal(res.gates_on_in_fault, 0u);
}

static void level2_adc_offsets_and_readings(void **state)
{
    (void)state;
    static const char *const sets[] = { "run.level=2", "faults.vdc_sag_s=0", "faults.vdc_sag_V=1",
                                        "plant.adc_offset_a_A=0.2", "plant.adc_offset_b_A=-0.1",
                                        "run.duration_s=0.15" };
    sil_result_t res;
    run(sets, 6, &res);
    const sil_row_t *r = &g_rows[g_n - 1];
    print_message("level 2: offsets %+.4f %+.4f A, readings %+.4f %+.4f A, bus %.3f V\n", r->ia_offset_A,
                  r->ib_offset_A, r->ia_adc_A, r->ib_adc_A, r->vdc_adc_V);
    assert_int_equal(res.final_state, APP_STATE_ADC_CHECK);
    assert_int_equal(res.final_fault, APP_FAULT_NONE);
    assert_int_equal(res.pwm_periods, 0u);
    assert_float_equal(r->ia_offset_A, 0.2, I_LSB_A);
    assert_float_equal(r->ib_offset_A, -0.1, I_LSB_A);
    assert_float_equal(r->ia_adc_A, 0.2, I_LSB_A);
    assert_float_equal(r->ib_adc_A, -0.1, I_LSB_A);
    assert_float_equal(r->vdc_adc_V, 1.0, VDC_LSB_V);
    assert_float_equal(res.i_offset_a_A, r->ia_offset_A, 0.0);
}

/* Level 3 with the board's wrong parts in sets[]; the result. */
static void level3(const char *const *extra, size_t n, sil_result_t *res)
{
    const char *sets[8] = { "run.level=3", "run.calibrate=on", "run.duration_s=2.0",
                            "controller.mode=torque", "controller.method=proposed", "identify.mode=windows" };
    size_t m = 6;
    for (size_t i = 0; i < n; i++) {
        sets[m++] = extra[i];
    }
    run(sets, m, res);
    print_message("level 3 %-30s: fault %2d, counts %+7.0f over %.3f rad el, p^ %.4f, i+ %.3f A, i- %.3f A\n",
                  (n > 0) ? extra[0] : "(right board)", res->final_fault, res->enc_counts, res->enc_angle_el_rad,
                  res->enc_pole_pairs, res->enc_i_pos_A, res->enc_i_neg_A);
}

static void level3_right_board_passes(void **state)
{
    (void)state;
    sil_result_t res;
    level3(NULL, 0, &res);
    assert_int_equal(res.final_state, APP_STATE_IDLE);
    assert_int_equal(res.final_fault, APP_FAULT_NONE);
    assert_float_equal(res.enc_angle_el_rad, 6.0 * PI_D, 1e-3);
    assert_float_equal(res.enc_counts, 10000.0, 30.0);        /* the lag's change over the turn: < 1 deg mech */
    assert_float_equal(res.enc_pole_pairs, 3.0, 0.01);
    assert_float_equal(res.enc_i_pos_A, 3.0, 0.3);
    assert_true(res.enc_i_neg_A < 0.05 * res.enc_i_pos_A);
    assert_true(res.pwm_periods > 0u);
    assert_int_equal((int)g_rows[g_n - 1].pwm, 0);
}

static void level3_reversed_encoder(void **state)
{
    (void)state;
    static const char *const x[] = { "plant.encoder_direction=-1" };
    sil_result_t res;
    level3(x, 1, &res);
    assert_int_equal(res.final_fault, APP_FAULT_ENCODER_DIRECTION);
    assert_int_equal(res.fault_state, APP_STATE_ENC_CHECK);
    assert_float_equal(res.fault_value, -10000.0, 30.0);
    assert_int_equal(res.gates_on_in_fault, 0u);
}

static void level3_wrong_pole_pairs(void **state)
{
    (void)state;
    static const char *const x4[] = { "controller.pole_pairs=4" };
    static const char *const x2[] = { "controller.pole_pairs=2" };
    sil_result_t res;
    level3(x4, 1, &res);
    assert_int_equal(res.final_fault, APP_FAULT_POLE_PAIRS);
    assert_float_equal(res.fault_value, 3.0, 0.01);
    assert_float_equal(res.fault_limit, 4.0, 0.0);
    level3(x2, 1, &res);
    assert_int_equal(res.final_fault, APP_FAULT_POLE_PAIRS);
    assert_float_equal(res.fault_value, 3.0, 0.01);
    assert_float_equal(res.fault_limit, 2.0, 0.0);
}

static void level3_swapped_phase_pair(void **state)
{
    (void)state;
    static const char *const x[] = { "plant.phase_order=acb" };
    sil_result_t res;
    level3(x, 1, &res);
    assert_int_equal(res.final_fault, APP_FAULT_PHASE_ORDER);
    assert_true(res.fault_value > res.fault_limit);
    assert_float_equal(res.fault_value, 3.0, 0.3);   /* the current, turning the other way */
}

/* Mean of te over rows with t in [t0, t1), and the largest true |i| there. */
static void window(double t0, double t1, double *te, double *i_max)
{
    double sum = 0.0;
    int n = 0;
    *i_max = 0.0;
    for (size_t k = 0; k < g_n; k++) {
        const sil_row_t *r = &g_rows[k];
        if (r->t_s >= t0 && r->t_s < t1) {
            sum += r->te_Nm;
            n++;
            const double i = hypot(r->id_A, r->iq_A);
            *i_max = (i > *i_max) ? i : *i_max;
        }
    }
    assert_true(n > 0);
    *te = sum / n;
}

static void level4_torque_control_at_reduced_limit(void **state)
{
    (void)state;
    static const char *const sets[] = { "run.level=4", "run.calibrate=on", "controller.mode=speed",
                                        "reference.speed_rpm=1500", "reference.torque_Nm=0:0, 0.15:2, 0.3:6",
                                        "plant.speed_held=1", "plant.speed0_rpm=300", "run.duration_s=0.45" };
    sil_result_t res;
    run(sets, 8, &res);
    double te2, te6, i2, i6;
    window(0.25, 0.3, &te2, &i2);
    window(0.4, 0.45, &te6, &i6);
    print_message("level 4: te %.3f N m at 2 N m (|i| <= %.3f A), %.3f N m at 6 N m (|i| <= %.3f A)\n", te2, i2,
                  te6, i6);
    assert_int_equal(res.final_state, APP_STATE_RUN);
    assert_int_equal(res.final_fault, APP_FAULT_NONE);
    assert_float_equal(te2, 2.0, 0.04);
    assert_float_equal(te6, KT_NM_A * I_LEVEL4_A, 0.04 * KT_NM_A * I_LEVEL4_A);
    assert_true(i6 < I_LEVEL4_A * 1.05);
}

static void level5_full_drive(void **state)
{
    (void)state;
    static const char *const sets[] = { "controller.mode=speed", "reference.speed_rpm=0:0, 0.05:500~",
                                        "run.duration_s=0.4" };
    sil_result_t res;
    run(sets, 3, &res);
    assert_int_equal(res.level, 5);
    assert_int_equal(res.final_state, APP_STATE_RUN);
    assert_int_equal(res.final_fault, APP_FAULT_NONE);
    assert_float_equal(g_rows[g_n - 1].speed_rpm, 500.0, 5.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(level1_pwm_pattern_without_bus),
        cmocka_unit_test(levels_1_and_2_refuse_a_charged_bus),
        cmocka_unit_test(level2_adc_offsets_and_readings),
        cmocka_unit_test(level3_right_board_passes),
        cmocka_unit_test(level3_reversed_encoder),
        cmocka_unit_test(level3_wrong_pole_pairs),
        cmocka_unit_test(level3_swapped_phase_pair),
        cmocka_unit_test(level4_torque_control_at_reduced_limit),
        cmocka_unit_test(level5_full_drive),
    };
    return cmocka_run_group_tests_name("sil_levels", tests, NULL, NULL);
}
