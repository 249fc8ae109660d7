/* app_harness.h - what the app's tests share (test_app, test_calib,
 * test_align, test_protect, test_rsid_seq): the test configuration, the
 * ISR call patterns against the cmocka mock of the HAL (tests/mock_hal.c),
 * hand values of the calibration and the alignment, and the dyno that
 * answers the duties with obs_plant's currents in IDENTIFY_R; the
 * controller through app.h's and ctrl.h's readers, or tests/app_probe.h
 * where they give nothing. Include it once, in a test runner. */
#ifndef APP_HARNESS_H
#define APP_HARNESS_H

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>

#include "app.h"
#include "app_probe.h"
#include "est_defaults.h"
#include "board_cfg.h"
#include "mock_hal.h"
#include "obs_plant.h"

#define PI_F        3.14159265f
#define I_MAX       12.0f
#define VDC         311.0f
#define VDC_MAX     400.0f
#define VDC_MIN     200.0f
#define SPEED_MAX   251.327412f  /* 2400 r/min [rad/s] */
#define CPR         10000u
/* 2400 r/min = 40 counts per period; x 1.5 + 1 count */
#define JUMP_MAX    61
#define PERIOD_CYC  15000u
#define BUDGET_CYC  12000u
#define LATE_CYC    22500u       /* 1.5 periods */
/* start-up sequence of the test cfg, in periods */
#define CAL_SETTLE  2
#define CAL_N       4
#define ALIGN_RAMP  4            /* ramp from 0, and the turn onto phase a */
#define ALIGN_PREPOS 2           /* hold at the pre-position (+90 deg el) */
#define ALIGN_HOLD  3            /* hold on phase a */
/* the period that aligns: both ramps and both holds done */
#define ALIGN_END   (2 * ALIGN_RAMP + ALIGN_PREPOS + ALIGN_HOLD)
#define ALIGN_U_V   9.0f
#define OFFSET_MAX  0.75f
#define COUNT0      1234u

static inline app_cfg_t make_cfg(bool calibrate, bool align)
{
    app_cfg_t cfg;
    app_cfg_default(&cfg);
    cfg.lvl.level = LEVEL_FULL; /* the drive's sequence (the board starts at level 1: test_app) */
    cfg.ctrl = (ctrl_cfg_t){
        .Ts_s = 1e-4f, .R_Ohm = 3.0f, .L_H = 0.011f, .psi_f_Wb = 0.24f, .pole_pairs = 3u,
        .enc_lines = 2500u, .enc_offset_el_rad = 0.0f, .enc_pll_bw_rad_s = 500.0f,
        .speed_kp_Nms_rad = 0.5f, .speed_ki_Nm_rad = 20.0f, .te_max_Nm = 12.0f,
        .i_max_A = 60.0f, .u_max_V = 5000.0f, .omega_max_el_rad_s = 3000.0f, .psi_max_Wb = 1.0f,
    };
    cfg.prot.i_max_A = I_MAX;
    cfg.prot.vdc_max_V = VDC_MAX;
    cfg.prot.vdc_min_V = VDC_MIN;
    cfg.prot.speed_max_rad_s = SPEED_MAX;
    cfg.prot.isr_period_cycles = PERIOD_CYC;
    cfg.prot.isr_budget_cycles = BUDGET_CYC;
    cfg.calibrate = calibrate;
    cfg.cal.settle_s = CAL_SETTLE * 1e-4f;
    cfg.cal.samples = CAL_N;
    cfg.cal.offset_max_A = OFFSET_MAX;
    cfg.align = align;
    cfg.aln.u_V = ALIGN_U_V;
    cfg.aln.prepos_el_rad = 0.5f * PI_F;
    cfg.aln.ramp_s = ALIGN_RAMP * 1e-4f;
    cfg.aln.prepos_s = ALIGN_PREPOS * 1e-4f;
    cfg.aln.settle_s = ALIGN_HOLD * 1e-4f;
    return cfg;
}

static uint32_t count_now; /* the encoder count sample() gives, COUNT0 after init */

static inline hal_sample_t sample(float ia, float ib, float vdc)
{
    hal_sample_t s = { ia, ib, vdc, count_now };
    return s;
}

static inline hal_sample_t sample_at(float ia, float ib, float vdc, uint32_t count)
{
    hal_sample_t s = { ia, ib, vdc, count };
    return s;
}

static app_t app; /* large: not on the test's stack */

static inline void init_with(bool calibrate, bool align)
{
    app_cfg_t cfg = make_cfg(calibrate, align);
    mock_hal_cycles = 0u;
    mock_hal_cycles_step = 0u;
    count_now = COUNT0;
    expect_function_call(hal_pwm_disable);
    app_init(&app, &cfg);
}

static inline void init_app(void)
{
    init_with(false, false);
}

/* The read and the protection's trip poll that start every ISR call outside FAULT. */
static inline void expect_read_poll(const hal_sample_t *s, int trip)
{
    expect_function_call(hal_sample_read);
    will_return(hal_sample_read, s);
    expect_function_call(hal_trip_active);
    will_return(hal_trip_active, trip);
}

/* One ISR call with no PWM call: read, poll, ack. */
static inline void isr_quiet(const hal_sample_t *s)
{
    expect_read_poll(s, 0);
    expect_function_call(hal_isr_ack);
    app_isr(&app);
}

/* One ISR call writing duties with the outputs already on: read, poll, write, ack. */
static inline void isr_run(const hal_sample_t *s)
{
    expect_read_poll(s, 0);
    expect_function_call(hal_pwm_write);
    expect_function_call(hal_isr_ack);
    app_isr(&app);
}

/* One ISR call writing the first duties: read, poll, write, enable, ack. */
static inline void isr_first_write(const hal_sample_t *s)
{
    expect_read_poll(s, 0);
    expect_function_call(hal_pwm_write);
    expect_function_call(hal_pwm_enable); /* after the first duties */
    expect_function_call(hal_isr_ack);
    app_isr(&app);
}

/* Start with calibration and alignment off: RUN in the request's own ISR call. */
static inline void start(const hal_sample_t *s)
{
    app_request_start(&app);
    isr_first_write(s);
    assert_int_equal(app.state, APP_STATE_RUN);
}

/* A stop request and the ISR call that takes it: read, poll, PWM off,
 * zero-voltage duties, ack. */
static inline void isr_stop(const hal_sample_t *s)
{
    app_request_stop(&app);
    expect_read_poll(s, 0);
    expect_function_call(hal_pwm_disable);
    expect_function_call(hal_pwm_write);
    expect_function_call(hal_isr_ack);
    app_isr(&app);
}

/* A fault ISR: read, poll (value given), PWM off, ack, nothing else. */
static inline void isr_fault(const hal_sample_t *s, int trip)
{
    expect_read_poll(s, trip);
    expect_function_call(hal_pwm_disable);
    expect_function_call(hal_isr_ack);
    app_isr(&app);
    assert_int_equal(app.state, APP_STATE_FAULT);
}

/* Fault reset from the background, then the ISR call that decides it. */
static inline void expect_reset_isr(const hal_sample_t *s, int trip)
{
    expect_function_call(hal_trip_clear);
    app_fault_reset(&app);
    expect_read_poll(s, trip);
    expect_function_call(hal_isr_ack);
    app_isr(&app);
}

static inline void assert_snapshot(const hal_sample_t *s, app_state_t st)
{
    assert_memory_equal(&app.snapshot.sample, s, sizeof *s);
    assert_int_equal(app.snapshot.state, st);
}

/* Calibration periods: settle (ignored, a decaying current), then CAL_N
 * hand values; the last one decides. */
static const float CAL_IA[CAL_N] = { 0.10f, 0.12f, 0.08f, 0.14f };  /* mean 0.11 */
static const float CAL_IB[CAL_N] = { -0.05f, -0.03f, -0.06f, -0.02f }; /* mean -0.04 */

static inline void run_calibration(const float *ia, const float *ib, float vdc)
{
    hal_sample_t s[CAL_SETTLE + CAL_N];
    for (int k = 0; k < CAL_SETTLE; k++) {
        s[k] = sample(2.0f, -1.0f, vdc);
    }
    for (int k = 0; k < CAL_N; k++) {
        s[CAL_SETTLE + k] = sample(ia[k], ib[k], vdc);
    }
    app_request_start(&app);
    for (int k = 0; k < CAL_SETTLE + CAL_N; k++) {
        isr_quiet(&s[k]); /* PWM off throughout */
        if (k < CAL_SETTLE + CAL_N - 1) {
            assert_int_equal(app.state, APP_STATE_CALIBRATE);
        }
    }
}

static inline float wrap_dist(float a, float b)
{
    float d = fmodf(a - b, 2.0f * PI_F);
    if (d > PI_F) {
        d -= 2.0f * PI_F;
    } else if (d < -PI_F) {
        d += 2.0f * PI_F;
    }
    return fabsf(d);
}

/* Duties of SVPWM with min-max injection, by hand: phase voltages by the
 * inverse Clarke transform, their mid-range moved to duty 0.5. */
static inline void minmax_duty(float ua, float ub, float vdc, float d[3])
{
    const float v[3] = { ua, -0.5f * ua + 0.8660254f * ub, -0.5f * ua - 0.8660254f * ub };
    const float mid = 0.5f * (fmaxf(v[0], fmaxf(v[1], v[2])) + fminf(v[0], fminf(v[1], v[2])));
    for (int j = 0; j < 3; j++) {
        d[j] = 0.5f + (v[j] - mid) / vdc;
    }
}

/* The alignment's vector in its period k, by hand: +90 deg (u_beta)
 * ramped over ALIGN_RAMP, held ALIGN_PREPOS, cross-faded onto phase a over
 * ALIGN_RAMP, held ALIGN_HOLD and the aligning period. */
static inline void align_u(int k, float *ua, float *ub)
{
    const int turn = ALIGN_RAMP + ALIGN_PREPOS;
    if (k < ALIGN_RAMP) {
        *ua = 0.0f;
        *ub = ALIGN_U_V * (float)k / ALIGN_RAMP;
    } else if (k < turn) {
        *ua = 0.0f;
        *ub = ALIGN_U_V;
    } else if (k < turn + ALIGN_RAMP) {
        const float f = (float)(k - turn) / ALIGN_RAMP;
        *ua = ALIGN_U_V * f;
        *ub = ALIGN_U_V * (1.0f - f);
    } else {
        *ua = ALIGN_U_V;
        *ub = 0.0f;
    }
}

/* ---- IDENTIFY_R ------------------------------------------------------------ */

/* Step 1's timeline of the test cfg, in periods: settle 1, window 1,
 * settle 2, window 2; from IDENTIFY_R's first period (k = 0). */
#define RSID_SETTLE_1 500
#define RSID_WIN      200
#define RSID_SETTLE_2 300
#define RSID_WIN1     RSID_SETTLE_1                           /* 500 */
#define RSID_WIN2     (RSID_WIN1 + RSID_WIN + RSID_SETTLE_2)  /* 1000 */
#define RSID_END      (RSID_WIN2 + RSID_WIN)                  /* 1200: periods in IDENTIFY_R */
#define R_BAND_MIN    0.6f        /* accepted R^ band [Ohm] */
#define R_BAND_MAX    6.0f
#define R_TRUE        3.6         /* the dyno's motor: 1.2 x the controller's 3 Ohm */
/* the dyno: 5 counts per period = 300 r/min, 94.25 rad/s el */
#define DYNO_COUNTS   5u
#define DYNO_W_EL     ((double)DYNO_COUNTS * 3.0 * 2.0 * OP_PI / CPR / OP_TS)

static inline app_cfg_t rsid_cfg(app_rsid_mode_t mode, bool align)
{
    app_cfg_t cfg = make_cfg(false, align);
    test_est_defaults(&cfg.ctrl, R_BAND_MIN, R_BAND_MAX);
    cfg.rsid.mode = mode;
    cfg.rsid.settle_1_s = RSID_SETTLE_1 * 1e-4f;
    cfg.rsid.window_s = RSID_WIN * 1e-4f;
    cfg.rsid.settle_2_s = RSID_SETTLE_2 * 1e-4f;
    return cfg;
}

static inline void init_cfg(const app_cfg_t *cfg)
{
    mock_hal_cycles = 0u;
    mock_hal_cycles_step = 0u;
    count_now = COUNT0;
    expect_function_call(hal_pwm_disable);
    app_init(&app, cfg);
}

/* Start and the alignment (shaft still at COUNT0, no current): ALIGN_END + 1 calls. */
static inline void start_and_align(void)
{
    hal_sample_t s = sample(0.0f, 0.0f, VDC);
    app_request_start(&app);
    isr_first_write(&s);
    for (int k = 1; k <= ALIGN_END; k++) {
        assert_int_equal(app.state, APP_STATE_ALIGN);
        isr_run(&s);
    }
}

/* The dyno: shaft at DYNO_COUNTS per period from COUNT0 (where the
 * alignment put the d axis on phase a; the rotor at the count's centre,
 * so the controller's angle is exact), currents of obs_plant's motor under
 * the duties the app wrote the period before (the DSP's timing). */
static op_plant_t dyno;
static float dyno_duty[3];
static hal_sample_t dyno_last;  /* the last call's sample, for the snapshot */

static inline void dyno_start(double R_true)
{
    dyno = (op_plant_t){ R_true, OP_L0, OP_PSI0, 0.0, 0.0 };
    for (int j = 0; j < 3; j++) {
        dyno_duty[j] = mock_hal_duty[j]; /* the alignment's last, active in IDENTIFY_R's first period */
    }
}

static inline double dyno_theta(void)
{
    return (double)((count_now - COUNT0) * 3u % CPR) * 2.0 * OP_PI / CPR;
}

/* One ISR call with the torque reference te_Nm from outside: read, poll,
 * write (and PWM off when it faults), ack; then the motor over the period. */
static inline void dyno_isr(float te_Nm, bool faults)
{
    const double th = dyno_theta();
    const double ial = dyno.id * cos(th) - dyno.iq * sin(th);
    const double ibe = dyno.id * sin(th) + dyno.iq * cos(th);
    dyno_last = sample((float)ial, (float)(-0.5 * ial + 0.5 * sqrt(3.0) * ibe), VDC);
    ctrl_ref_t r = *ctrl_ref(app_ctrl(&app));
    r.te_ref_Nm = te_Nm;
    ctrl_set_ref(probe_ctrl_rw(&app), &r);
    expect_read_poll(&dyno_last, 0);
    expect_function_call(hal_pwm_write);
    if (faults) {
        expect_function_call(hal_pwm_disable);
    }
    expect_function_call(hal_isr_ack);
    app_isr(&app);
    /* the inverter's stator voltage, into the rotor frame at the period's middle */
    const double ua = VDC * (2.0 / 3.0) * (dyno_duty[0] - 0.5 * (dyno_duty[1] + dyno_duty[2]));
    const double ub = VDC * (dyno_duty[1] - dyno_duty[2]) / sqrt(3.0);
    const double tm = th + 0.5 * DYNO_W_EL * OP_TS;
    op_step(&dyno, ua * cos(tm) + ub * sin(tm), -ua * sin(tm) + ub * cos(tm), DYNO_W_EL);
    for (int j = 0; j < 3; j++) {
        dyno_duty[j] = mock_hal_duty[j];
    }
    count_now = (count_now + DYNO_COUNTS) % CPR;
}

typedef enum { TE_TWO_LOADS, TE_ONE_LOAD, TE_UNSTEADY_WIN2 } te_plan_t;

/* The outside torque reference in IDENTIFY_R's period k: 2 N m, then 4 N m
 * from window 1's end (WINDOWS mode: the operating points are the
 * outside's); or 2 N m throughout; or 3 / 5 N m alternating in window 2. */
static inline float te_plan(te_plan_t plan, int k)
{
    if (plan == TE_ONE_LOAD || k < RSID_WIN1 + RSID_WIN) {
        return 2.0f;
    }
    if (plan == TE_UNSTEADY_WIN2 && k >= RSID_WIN2) {
        return ((k % 2) == 0) ? 3.0f : 5.0f;
    }
    return 4.0f;
}

/* The period that acts on the check of the windows taken in period
 * RSID_END - 1 (their nominal end): the staged solve's (rsid_seq.h). */
#define RSID_LAST     (RSID_END - 1 + (int)RSID_CHECK_PERIODS)

/* IDENTIFY_R's periods from .. to - 1 with the window each one goes into
 * (window 2 on past its nominal end while the check is solved). */
static inline void identify_periods(int from, int to, te_plan_t plan)
{
    for (int k = from; k < to; k++) {
        dyno_isr(te_plan(plan, k), false);
        assert_int_equal(app.state, APP_STATE_IDENTIFY_R);
        const rs_ident_window_t w = (k >= RSID_WIN1 && k < RSID_WIN1 + RSID_WIN) ? RS_IDENT_WINDOW_1
                                  : ((k >= RSID_WIN2) ? RS_IDENT_WINDOW_2 : RS_IDENT_WINDOW_NONE);
        assert_int_equal(probe_rsid_window(&app), w);
    }
}

/* IDENTIFY_R's periods 0 .. RSID_LAST - 1. */
static inline void identify_until_last(te_plan_t plan)
{
    identify_periods(0, RSID_LAST, plan);
    assert_int_equal(probe_rsid_samples(&app, 0), RSID_WIN);
    assert_int_equal(probe_rsid_samples(&app, 1), RSID_LAST - RSID_WIN2);
}

#endif /* APP_HARNESS_H */
