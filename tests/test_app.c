/* Unit tests for firmware/app: the ISR's HAL call order, every state
 * transition, each protection fault (PWM off in the same ISR call,
 * snapshot kept), calibration and alignment with hand values, fault reset
 * refused while the cause persists; against the cmocka mock of the HAL
 * (tests/mock_hal.c). */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>

#include "app.h"
#include "board_cfg.h"
#include "mock_hal.h"

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
#define ALIGN_RAMP  4
#define ALIGN_HOLD  3
#define ALIGN_U_V   9.0f
#define OFFSET_MAX  0.75f
#define COUNT0      1234u

static app_cfg_t make_cfg(bool calibrate, bool align)
{
    app_cfg_t cfg;
    app_cfg_default(&cfg);
    cfg.ctrl = (ctrl_cfg_t){
        .Ts_s = 1e-4f, .Rs_Ohm = 3.0f, .Ls_H = 0.011f, .psi_f_Wb = 0.24f, .pole_pairs = 3u,
        .enc_lines = 2500u, .enc_offset_el_rad = 0.0f, .enc_pll_bw_rad_s = 500.0f,
        .speed_kp_Nms_rad = 0.5f, .speed_ki_Nm_rad = 20.0f, .te_max_Nm = 12.0f,
        .i_max_A = 60.0f, .u_max_V = 5000.0f, .omega_max_el_rad_s = 3000.0f, .psi_max_Wb = 1.0f,
    };
    cfg.i_max_A = I_MAX;
    cfg.vdc_max_V = VDC_MAX;
    cfg.vdc_min_V = VDC_MIN;
    cfg.speed_max_rad_s = SPEED_MAX;
    cfg.isr_period_cycles = PERIOD_CYC;
    cfg.isr_budget_cycles = BUDGET_CYC;
    cfg.calibrate = calibrate;
    cfg.cal_settle_s = CAL_SETTLE * 1e-4f;
    cfg.cal_samples = CAL_N;
    cfg.offset_max_A = OFFSET_MAX;
    cfg.align = align;
    cfg.align_u_V = ALIGN_U_V;
    cfg.align_ramp_s = ALIGN_RAMP * 1e-4f;
    cfg.align_settle_s = ALIGN_HOLD * 1e-4f;
    return cfg;
}

static uint32_t count_now; /* the encoder count sample() gives, COUNT0 after init */

static hal_sample_t sample(float ia, float ib, float vdc)
{
    hal_sample_t s = { ia, ib, vdc, count_now };
    return s;
}

static hal_sample_t sample_at(float ia, float ib, float vdc, uint32_t count)
{
    hal_sample_t s = { ia, ib, vdc, count };
    return s;
}

static app_t app; /* large: not on the test's stack */

static void init_with(bool calibrate, bool align)
{
    app_cfg_t cfg = make_cfg(calibrate, align);
    mock_hal_cycles = 0u;
    mock_hal_cycles_step = 0u;
    count_now = COUNT0;
    expect_function_call(hal_pwm_disable);
    app_init(&app, &cfg);
}

static void init_app(void)
{
    init_with(false, false);
}

/* The read and the protection's trip poll that start every ISR call outside FAULT. */
static void expect_read_poll(const hal_sample_t *s, int trip)
{
    expect_function_call(hal_sample_read);
    will_return(hal_sample_read, s);
    expect_function_call(hal_trip_active);
    will_return(hal_trip_active, trip);
}

/* One ISR call with no PWM call: read, poll, ack. */
static void isr_quiet(const hal_sample_t *s)
{
    expect_read_poll(s, 0);
    expect_function_call(hal_isr_ack);
    app_isr(&app);
}

/* One ISR call writing duties with the outputs already on: read, poll, write, ack. */
static void isr_run(const hal_sample_t *s)
{
    expect_read_poll(s, 0);
    expect_function_call(hal_pwm_write);
    expect_function_call(hal_isr_ack);
    app_isr(&app);
}

/* One ISR call writing the first duties: read, poll, write, enable, ack. */
static void isr_first_write(const hal_sample_t *s)
{
    expect_read_poll(s, 0);
    expect_function_call(hal_pwm_write);
    expect_function_call(hal_pwm_enable); /* after the first duties */
    expect_function_call(hal_isr_ack);
    app_isr(&app);
}

/* Start with calibration and alignment off: RUN in the request's own ISR call. */
static void start(const hal_sample_t *s)
{
    app_request_start(&app);
    isr_first_write(s);
    assert_int_equal(app.state, APP_STATE_RUN);
}

/* A fault ISR: read, poll (value given), PWM off, ack, nothing else. */
static void isr_fault(const hal_sample_t *s, int trip)
{
    expect_read_poll(s, trip);
    expect_function_call(hal_pwm_disable);
    expect_function_call(hal_isr_ack);
    app_isr(&app);
    assert_int_equal(app.state, APP_STATE_FAULT);
}

/* Fault reset from the background, then the ISR call that decides it. */
static void expect_reset_isr(const hal_sample_t *s, int trip)
{
    expect_function_call(hal_trip_clear);
    app_fault_reset(&app);
    expect_read_poll(s, trip);
    expect_function_call(hal_isr_ack);
    app_isr(&app);
}

static void assert_snapshot(const hal_sample_t *s, app_state_t st)
{
    assert_memory_equal(&app.snapshot.sample, s, sizeof *s);
    assert_int_equal(app.snapshot.state, st);
}

/* ---- configuration ------------------------------------------------------ */

static void cfg_default_is_the_board(void **state)
{
    (void)state;
    app_cfg_t cfg;
    app_cfg_default(&cfg);
    assert_float_equal(cfg.ctrl.Ts_s, 1e-4, 1e-9);
    assert_float_equal(cfg.ctrl.Rs_Ohm, MOTOR_R_OHM, 0.0);
    assert_int_equal(cfg.ctrl.enc_lines, BOARD_ENC_LINES);
    assert_float_equal(cfg.i_max_A, BOARD_OVERCURRENT_A, 0.0);
    assert_float_equal(cfg.vdc_max_V, BOARD_VDC_MAX_V, 0.0);
    assert_float_equal(cfg.vdc_min_V, BOARD_VDC_MIN_V, 0.0);
    assert_float_equal(cfg.speed_max_rad_s, SPEED_MAX, 1e-3);
    assert_int_equal(cfg.isr_period_cycles, 15000u);
    assert_int_equal(cfg.isr_budget_cycles, BOARD_ISR_BUDGET_CYCLES);
    assert_true(cfg.calibrate);
    assert_int_equal(cfg.cal_samples, BOARD_CAL_SAMPLES);
    assert_float_equal(cfg.offset_max_A, BOARD_I_OFFSET_MAX_A, 0.0);
    assert_true(cfg.align == (BOARD_ENC_OFFSET_KNOWN == 0u));
    assert_float_equal(cfg.align_u_V, BOARD_ALIGN_CURRENT_A * MOTOR_R_OHM, 1e-6); /* 9 V */
}

/* ---- transitions ---------------------------------------------------------- */

static void init_is_init_with_pwm_off(void **state)
{
    (void)state;
    init_app();
    assert_int_equal(app.state, APP_STATE_INIT);
    assert_int_equal(app.fault, APP_FAULT_NONE);
    hal_sample_t s = sample(0.0f, 0.0f, VDC);
    isr_quiet(&s); /* INIT: no PWM call at all */
    assert_int_equal(app.state, APP_STATE_INIT);
    assert_int_equal(app.ticks, 1u);
    app_request_stop(&app); /* nothing to stop */
    isr_quiet(&s);
    assert_int_equal(app.state, APP_STATE_INIT);
}

/* INIT -> RUN -> IDLE -> RUN with both sequence steps off; a start while
 * running is ignored. */
static void start_runs_and_stop_idles(void **state)
{
    (void)state;
    init_app();
    hal_sample_t s = sample(0.5f, -0.2f, VDC);
    start(&s);
    isr_run(&s);
    assert_true(isfinite(mock_hal_duty[0]) && mock_hal_duty[0] >= 0.0f && mock_hal_duty[0] <= 1.0f);
    assert_float_equal(mock_hal_duty[1], app.out.duty[1], 0.0); /* the controller's duties */
    app_request_start(&app);
    isr_run(&s);
    assert_int_equal(app.state, APP_STATE_RUN);
    assert_int_equal(app.req_start, 0u);

    app_request_stop(&app);
    expect_read_poll(&s, 0);
    expect_function_call(hal_pwm_disable);
    expect_function_call(hal_pwm_write);
    expect_function_call(hal_isr_ack);
    app_isr(&app);
    assert_int_equal(app.state, APP_STATE_IDLE);
    assert_float_equal(mock_hal_duty[0], 0.5, 0.0);
    isr_quiet(&s);
    assert_int_equal(app.state, APP_STATE_IDLE);
    start(&s); /* IDLE -> RUN, outputs on again after the first duties */
}

/* Calibration periods: settle (ignored, a decaying current), then CAL_N
 * hand values; the last one decides. */
static const float CAL_IA[CAL_N] = { 0.10f, 0.12f, 0.08f, 0.14f };  /* mean 0.11 */
static const float CAL_IB[CAL_N] = { -0.05f, -0.03f, -0.06f, -0.02f }; /* mean -0.04 */

static void run_calibration(const float *ia, const float *ib, float vdc)
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

static float wrap_dist(float a, float b)
{
    float d = fmodf(a - b, 2.0f * PI_F);
    if (d > PI_F) {
        d -= 2.0f * PI_F;
    } else if (d < -PI_F) {
        d += 2.0f * PI_F;
    }
    return fabsf(d);
}

/* INIT -> CALIBRATE -> ALIGN -> RUN: offsets from the hand values, the
 * voltage vector along phase a ramped then held, then the aligned count
 * reads 0 rad and RUN uses the corrected currents. */
static void sequence_calibrates_aligns_runs(void **state)
{
    (void)state;
    init_with(true, true);
    run_calibration(CAL_IA, CAL_IB, VDC);
    assert_int_equal(app.state, APP_STATE_ALIGN);
    assert_float_equal(app.offset_ia_A, 0.11, 1e-6);
    assert_float_equal(app.offset_ib_A, -0.04, 1e-6);
    assert_true(app.uv_armed);

    hal_sample_t s = sample(0.5f, -0.25f, VDC);
    for (int k = 0; k <= ALIGN_RAMP + ALIGN_HOLD; k++) {
        if (k == 0) {
            isr_first_write(&s);
        } else {
            isr_run(&s);
        }
        const float u = ALIGN_U_V * ((k < ALIGN_RAMP) ? (float)k / ALIGN_RAMP : 1.0f);
        /* u_alpha = u, u_beta = 0 with min-max injection: a = 0.5 + 0.75 u / Vdc, b = c */
        assert_float_equal(mock_hal_duty[0], 0.5f + 0.75f * u / VDC, 1e-6);
        assert_float_equal(mock_hal_duty[1], mock_hal_duty[2], 1e-7);
        assert_float_equal(mock_hal_duty[1], 0.5f - 0.75f * u / VDC, 1e-6);
        if (k < ALIGN_RAMP + ALIGN_HOLD) {
            assert_int_equal(app.state, APP_STATE_ALIGN);
        }
    }
    assert_int_equal(app.state, APP_STATE_RUN);
    assert_true(app.aligned);
    /* offset = -(electrical angle of COUNT0) = -((1234 * 3 mod 10000) + 1.5) * 2 pi / 10000:
     * 3702 electrical counts plus the centre of the count's interval (p/2) */
    assert_true(wrap_dist(app.ctrl.enc.offset_rad, -3703.5f * 2.0f * PI_F / CPR) < 1e-5f);

    /* RUN: the aligned count reads 0 rad; the controller gets ia - 0.11, ib + 0.04 */
    hal_sample_t r = sample(0.61f, -0.34f, VDC);
    isr_run(&r);
    assert_int_equal(app.state, APP_STATE_RUN);
    assert_true(wrap_dist(app.ctrl.mon.theta_el_rad, 0.0f) < 1e-5f);
    assert_float_equal(app.ctrl.mon.id_A, 0.5, 1e-4); /* Park at 0 rad: id = ia */
}

/* Calibration on, alignment off (offset configured as known): CALIBRATE -> RUN. */
static void align_skipped_when_offset_known(void **state)
{
    (void)state;
    init_with(true, false);
    run_calibration(CAL_IA, CAL_IB, VDC);
    assert_int_equal(app.state, APP_STATE_RUN);
    hal_sample_t s = sample(0.11f, -0.04f, VDC);
    isr_first_write(&s); /* the controller's duties first */
    assert_float_equal(mock_hal_duty[0], app.out.duty[0], 0.0);
    assert_false(app.aligned);
}

/* Alignment once per power-up: a second start calibrates and runs; an
 * ENCODER fault forgets it, so the start after the reset aligns again. */
static void align_once_until_encoder_fault(void **state)
{
    (void)state;
    init_with(true, true);
    run_calibration(CAL_IA, CAL_IB, VDC);
    hal_sample_t s = sample(0.11f, -0.04f, VDC);
    isr_first_write(&s);
    for (int k = 1; k <= ALIGN_RAMP + ALIGN_HOLD; k++) {
        isr_run(&s);
    }
    assert_int_equal(app.state, APP_STATE_RUN);
    isr_run(&s);
    app_request_stop(&app);
    expect_read_poll(&s, 0);
    expect_function_call(hal_pwm_disable);
    expect_function_call(hal_pwm_write);
    expect_function_call(hal_isr_ack);
    app_isr(&app);
    assert_int_equal(app.state, APP_STATE_IDLE);

    run_calibration(CAL_IA, CAL_IB, VDC);
    assert_int_equal(app.state, APP_STATE_RUN); /* no second alignment */
    isr_first_write(&s);

    count_now = COUNT0 + 500u;
    hal_sample_t jump = sample(0.11f, -0.04f, VDC);
    isr_fault(&jump, 0);
    assert_int_equal(app.fault, APP_FAULT_ENCODER);
    assert_false(app.aligned);
    count_now = COUNT0 + 600u;
    hal_sample_t again = sample(0.11f, -0.04f, VDC);
    expect_reset_isr(&again, 0); /* still jumping: refused */
    assert_int_equal(app.state, APP_STATE_FAULT);
    expect_reset_isr(&again, 0); /* count steady: cause gone */
    assert_int_equal(app.state, APP_STATE_IDLE);
    run_calibration(CAL_IA, CAL_IB, VDC);
    assert_int_equal(app.state, APP_STATE_ALIGN);
}

/* A stop in CALIBRATE or ALIGN ends in IDLE with the outputs off. */
static void stop_during_calibrate_and_align(void **state)
{
    (void)state;
    init_with(true, true);
    hal_sample_t s = sample(0.0f, 0.0f, VDC);
    app_request_start(&app);
    isr_quiet(&s);
    assert_int_equal(app.state, APP_STATE_CALIBRATE);
    app_request_stop(&app);
    expect_read_poll(&s, 0);
    expect_function_call(hal_pwm_disable);
    expect_function_call(hal_pwm_write);
    expect_function_call(hal_isr_ack);
    app_isr(&app);
    assert_int_equal(app.state, APP_STATE_IDLE);
    assert_float_equal(app.offset_ia_A, 0.0, 0.0); /* aborted: nothing taken */

    run_calibration(CAL_IA, CAL_IB, VDC);
    isr_first_write(&s);
    assert_int_equal(app.state, APP_STATE_ALIGN);
    app_request_stop(&app);
    expect_read_poll(&s, 0);
    expect_function_call(hal_pwm_disable);
    expect_function_call(hal_pwm_write);
    expect_function_call(hal_isr_ack);
    app_isr(&app);
    assert_int_equal(app.state, APP_STATE_IDLE);
    assert_false(app.aligned);
}

/* ---- calibration faults --------------------------------------------------- */

static void calibration_rejects_offset_out_of_band(void **state)
{
    (void)state;
    /* ia mean 0.80 A > 0.75 A */
    const float ia_bad[CAL_N] = { 0.80f, 0.81f, 0.79f, 0.80f };
    /* ib mean -0.76 A */
    const float ib_bad[CAL_N] = { -0.76f, -0.76f, -0.76f, -0.76f };
    const float ib_ok[CAL_N] = { 0.0f, 0.0f, 0.0f, 0.0f };
    for (int c = 0; c < 2; c++) {
        init_with(true, true);
        const float *ia = (c == 0) ? ia_bad : ib_ok;
        const float *ib = (c == 0) ? ib_ok : ib_bad;
        hal_sample_t s[CAL_SETTLE + CAL_N - 1];
        for (int k = 0; k < CAL_SETTLE + CAL_N - 1; k++) {
            const int j = (k < CAL_SETTLE) ? 0 : k - CAL_SETTLE;
            s[k] = sample(ia[j], ib[j], VDC);
        }
        app_request_start(&app);
        for (int k = 0; k < CAL_SETTLE + CAL_N - 1; k++) {
            isr_quiet(&s[k]);
        }
        hal_sample_t last = sample(ia[CAL_N - 1], ib[CAL_N - 1], VDC);
        isr_fault(&last, 0); /* the deciding period: PWM off (again), fault */
        assert_int_equal(app.fault, APP_FAULT_CURRENT_OFFSET);
        assert_snapshot(&last, APP_STATE_CALIBRATE);
        assert_float_equal(app.snapshot.value, (c == 0) ? 0.80 : -0.76, 1e-6);
        assert_float_equal(app.snapshot.limit, OFFSET_MAX, 0.0);
        assert_float_equal(app.offset_ia_A, 0.0, 0.0); /* not taken */
        assert_float_equal(app.offset_ib_A, 0.0, 0.0);
        assert_false(app.uv_armed);
    }
}

/* ---- protection: each fault, PWM off in the same call, snapshot ----------- */

static void overcurrent_on_each_phase_latches(void **state)
{
    (void)state;
    /* ia, ib, and ic = -ia - ib beyond 12 A */
    const hal_sample_t bad[3] = { sample(12.5f, -1.0f, VDC), sample(1.0f, -12.5f, VDC),
                                  sample(6.5f, 6.0f, VDC) };
    const float peak[3] = { 12.5f, 12.5f, 12.5f };
    for (int k = 0; k < 3; k++) {
        init_app();
        hal_sample_t ok = sample(11.9f, -6.0f, VDC); /* ic = -5.9 A */
        start(&ok);
        isr_run(&ok);
        isr_fault(&bad[k], 0);
        assert_int_equal(app.fault, APP_FAULT_OVERCURRENT);
        assert_snapshot(&bad[k], APP_STATE_RUN);
        assert_float_equal(app.snapshot.value, peak[k], 1e-6);
        assert_float_equal(app.snapshot.limit, I_MAX, 0.0);
    }
}

/* The check uses the offset-corrected currents. */
static void overcurrent_after_offset_correction(void **state)
{
    (void)state;
    init_with(true, false);
    const float ia[CAL_N] = { 0.5f, 0.5f, 0.5f, 0.5f };
    const float ib[CAL_N] = { 0.0f, 0.0f, 0.0f, 0.0f };
    run_calibration(ia, ib, VDC);
    hal_sample_t ok = sample(12.4f, -6.0f, VDC); /* 11.9 A after the 0.5 A offset */
    isr_first_write(&ok);
    hal_sample_t bad = sample(-11.6f, 6.0f, VDC); /* -12.1 A */
    isr_fault(&bad, 0);
    assert_int_equal(app.fault, APP_FAULT_OVERCURRENT);
    assert_float_equal(app.snapshot.value, 12.1, 1e-5);
}

static void hardware_trip_latches_in_run_and_init(void **state)
{
    (void)state;
    init_app();
    hal_sample_t s = sample(1.0f, 1.0f, VDC);
    start(&s);
    isr_fault(&s, 1);
    assert_int_equal(app.fault, APP_FAULT_HW_TRIP);
    assert_snapshot(&s, APP_STATE_RUN);

    init_app();
    isr_fault(&s, 1);
    assert_int_equal(app.fault, APP_FAULT_HW_TRIP);
    assert_snapshot(&s, APP_STATE_INIT);
}

static void non_finite_sample_latches(void **state)
{
    (void)state;
    init_app();
    hal_sample_t ok = sample(1.0f, 1.0f, VDC);
    hal_sample_t bad = sample(1.0f, 1.0f, NAN);
    start(&ok);
    isr_fault(&bad, 0);
    assert_int_equal(app.fault, APP_FAULT_NONFINITE_SAMPLE);
    assert_true(isnan(app.snapshot.sample.vdc_V));
}

/* The controller's output turns non-finite (a NaN reference): no write,
 * PWM off in the same call. */
static void non_finite_controller_output_latches(void **state)
{
    (void)state;
    init_app();
    hal_sample_t s = sample(1.0f, 1.0f, VDC);
    start(&s);
    ctrl_ref_t r = { 0.0f, NAN, 0.0f, 0.0f };
    ctrl_set_ref(&app.ctrl, &r);
    isr_fault(&s, 0);
    assert_int_equal(app.fault, APP_FAULT_NONFINITE_OUTPUT);
    assert_snapshot(&s, APP_STATE_RUN);
}

static void overvoltage_latches_in_every_state(void **state)
{
    (void)state;
    hal_sample_t ok = sample(0.0f, 0.0f, VDC_MAX);   /* at the limit: fine */
    hal_sample_t bad = sample(0.0f, 0.0f, 400.5f);
    init_app();
    isr_quiet(&ok);
    isr_fault(&bad, 0); /* INIT: the bus charging too high */
    assert_int_equal(app.fault, APP_FAULT_OVERVOLTAGE);
    assert_snapshot(&bad, APP_STATE_INIT);
    assert_float_equal(app.snapshot.value, 400.5, 1e-4);
    assert_float_equal(app.snapshot.limit, VDC_MAX, 0.0);

    init_app();
    start(&ok);
    isr_fault(&bad, 0);
    assert_int_equal(app.fault, APP_FAULT_OVERVOLTAGE);
    assert_snapshot(&bad, APP_STATE_RUN);
}

/* Undervoltage: not checked in INIT nor while calibrating (bus charging);
 * armed when calibration ends, checked on that period's samples before
 * the motor is energised, and from then on in every state. */
static void undervoltage_armed_after_calibration(void **state)
{
    (void)state;
    init_with(true, true);
    hal_sample_t low = sample(0.0f, 0.0f, 100.0f);
    isr_quiet(&low);
    assert_int_equal(app.state, APP_STATE_INIT);
    app_request_start(&app);
    for (int k = 0; k < CAL_SETTLE + CAL_N - 1; k++) {
        isr_quiet(&low);
        assert_int_equal(app.state, APP_STATE_CALIBRATE);
    }
    isr_fault(&low, 0); /* calibration done, bus still low: no alignment */
    assert_int_equal(app.fault, APP_FAULT_UNDERVOLTAGE);
    assert_snapshot(&low, APP_STATE_CALIBRATE);
    assert_float_equal(app.snapshot.value, 100.0, 0.0);
    assert_float_equal(app.snapshot.limit, VDC_MIN, 0.0);

    /* bus lost during the alignment */
    init_with(true, true);
    run_calibration(CAL_IA, CAL_IB, VDC);
    hal_sample_t ok = sample(0.0f, 0.0f, VDC);
    isr_first_write(&ok);
    hal_sample_t dip = sample(0.0f, 0.0f, 199.0f);
    isr_fault(&dip, 0);
    assert_int_equal(app.fault, APP_FAULT_UNDERVOLTAGE);
    assert_snapshot(&dip, APP_STATE_ALIGN);

    /* without calibration the start arms it and checks its own samples */
    init_app();
    isr_quiet(&low);
    app_request_start(&app);
    isr_fault(&low, 0);
    assert_int_equal(app.fault, APP_FAULT_UNDERVOLTAGE);
    assert_snapshot(&low, APP_STATE_INIT);
}

/* The count may change by up to JUMP_MAX (61) per period either way (across
 * the wrap too); 62 is a jump. */
static void encoder_jump_latches(void **state)
{
    (void)state;
    init_app();
    hal_sample_t s0 = sample_at(0.0f, 0.0f, VDC, 9990u);
    hal_sample_t s1 = sample_at(0.0f, 0.0f, VDC, (9990u + JUMP_MAX - 1u) % CPR); /* +60, across the wrap */
    hal_sample_t s2 = sample_at(0.0f, 0.0f, VDC, 9990u);                          /* -60 */
    hal_sample_t s3 = sample_at(0.0f, 0.0f, VDC, (9990u + JUMP_MAX + 1u) % CPR);  /* +62 */
    start(&s0);
    isr_run(&s1);
    isr_run(&s2);
    isr_fault(&s3, 0);
    assert_int_equal(app.fault, APP_FAULT_ENCODER);
    assert_snapshot(&s3, APP_STATE_RUN);
    assert_float_equal(app.snapshot.value, JUMP_MAX + 1, 0.0);
    assert_float_equal(app.snapshot.limit, JUMP_MAX, 1e-3);

    init_app(); /* also when stopped */
    isr_quiet(&s0);
    isr_fault(&s3, 0);
    assert_int_equal(app.fault, APP_FAULT_ENCODER);
    assert_snapshot(&s3, APP_STATE_INIT);
}

/* Overspeed on the encoder's speed estimate, stepped by the app outside
 * RUN: a shaft turning at 45 counts per period (2700 r/min) while stopped;
 * the PLL is replayed here to know the period it crosses 2400 r/min in.
 * A reset is refused while it turns that fast and taken once it stands. */
static void overspeed_latches_and_reset_waits(void **state)
{
    (void)state;
    init_app();
    encoder_t ref;
    encoder_cfg_t ec = { CPR, 3u, 0.0f, 1e-4f, 500.0f };
    assert_true(encoder_init(&ref, &ec));
    uint32_t count = 0u;
    int k;
    for (k = 0; k < 1000; k++) {
        encoder_step(&ref, count);
        hal_sample_t s = sample_at(0.0f, 0.0f, VDC, count);
        if (fabsf(ref.omega_m_rad_s) > SPEED_MAX) {
            isr_fault(&s, 0);
            assert_int_equal(app.fault, APP_FAULT_OVERSPEED);
            assert_snapshot(&s, APP_STATE_INIT);
            assert_float_equal(app.snapshot.value, fabsf(ref.omega_m_rad_s), 1e-3);
            assert_float_equal(app.snapshot.limit, SPEED_MAX, 0.0);
            break;
        }
        isr_quiet(&s);
        count = (count + 45u) % CPR;
    }
    assert_true(k > 5 && k < 1000);
    count = (count + 45u) % CPR;
    hal_sample_t fast = sample_at(0.0f, 0.0f, VDC, count);
    expect_reset_isr(&fast, 0);
    assert_int_equal(app.state, APP_STATE_FAULT);
    hal_sample_t still = sample_at(0.0f, 0.0f, VDC, count);
    for (k = 0; k < 200; k++) { /* FAULT without a reset: read and ack only */
        expect_function_call(hal_sample_read);
        will_return(hal_sample_read, &still);
        expect_function_call(hal_isr_ack);
        app_isr(&app);
    }
    expect_reset_isr(&still, 0);
    assert_int_equal(app.state, APP_STATE_IDLE);
}

/* In RUN the check reads the estimate the last ctrl_step left. */
static void overspeed_in_run(void **state)
{
    (void)state;
    init_app();
    hal_sample_t s = sample(0.0f, 0.0f, VDC);
    start(&s);
    app.ctrl.enc.omega_m_rad_s = -300.0f;
    isr_fault(&s, 0);
    assert_int_equal(app.fault, APP_FAULT_OVERSPEED);
    assert_snapshot(&s, APP_STATE_RUN);
    assert_float_equal(app.snapshot.value, 300.0, 0.0);
}

/* Run time over the budget: the fault comes at the ISR's exit, after the
 * duties, before the ack. */
static void overrun_run_time_latches(void **state)
{
    (void)state;
    init_app();
    hal_sample_t s = sample(0.0f, 0.0f, VDC);
    mock_hal_cycles_step = BUDGET_CYC; /* exit - entry = budget: fine */
    start(&s);
    mock_hal_cycles = PERIOD_CYC; /* each entry one period after the last */
    isr_run(&s);
    mock_hal_cycles = 2u * PERIOD_CYC;
    mock_hal_cycles_step = BUDGET_CYC + 1u;
    expect_read_poll(&s, 0);
    expect_function_call(hal_pwm_write);
    expect_function_call(hal_pwm_disable);
    expect_function_call(hal_isr_ack);
    app_isr(&app);
    assert_int_equal(app.state, APP_STATE_FAULT);
    assert_int_equal(app.fault, APP_FAULT_OVERRUN);
    assert_snapshot(&s, APP_STATE_RUN);
    assert_float_equal(app.snapshot.value, BUDGET_CYC + 1u, 0.0);
    assert_float_equal(app.snapshot.limit, BUDGET_CYC, 0.0);
}

/* A missed period: the entry-to-entry interval beyond 1.5 periods. */
static void overrun_missed_period_latches(void **state)
{
    (void)state;
    init_app();
    hal_sample_t s = sample(0.0f, 0.0f, VDC);
    start(&s);
    mock_hal_cycles += LATE_CYC; /* 1.5 periods: still fine */
    isr_run(&s);
    mock_hal_cycles += 2u * PERIOD_CYC;
    isr_fault(&s, 0);
    assert_int_equal(app.fault, APP_FAULT_OVERRUN);
    assert_float_equal(app.snapshot.value, 2u * PERIOD_CYC, 0.0);
    assert_float_equal(app.snapshot.limit, LATE_CYC, 0.0);
}

/* ---- fault reset ------------------------------------------------------------ */

/* FAULT holds: later ISRs read and ack only, keep the snapshot, ignore a
 * start; a reset while a cause persists (overcurrent, trip, bus low,
 * run time) stays; without, goes IDLE. */
static void fault_holds_until_reset_and_cause_gone(void **state)
{
    (void)state;
    init_app();
    hal_sample_t s = sample(1.0f, 1.0f, VDC);
    hal_sample_t bad = sample(20.0f, 0.0f, VDC);
    hal_sample_t low = sample(1.0f, 1.0f, 150.0f);
    start(&s);
    isr_fault(&bad, 0);
    app_request_start(&app);
    for (int k = 0; k < 3; k++) {
        expect_function_call(hal_sample_read);
        will_return(hal_sample_read, &s);
        expect_function_call(hal_isr_ack);
        app_isr(&app);
        assert_int_equal(app.state, APP_STATE_FAULT);
        assert_snapshot(&bad, APP_STATE_RUN);
    }
    expect_reset_isr(&bad, 0); /* currents still too high */
    assert_int_equal(app.state, APP_STATE_FAULT);
    expect_reset_isr(&s, 1);   /* trip still active */
    assert_int_equal(app.state, APP_STATE_FAULT);
    expect_reset_isr(&low, 0); /* bus below the armed undervoltage limit */
    assert_int_equal(app.state, APP_STATE_FAULT);
    mock_hal_cycles_step = BUDGET_CYC + 1u; /* a call over budget, so the next one also comes late */
    expect_function_call(hal_sample_read);
    will_return(hal_sample_read, &s);
    expect_function_call(hal_isr_ack);
    app_isr(&app);
    mock_hal_cycles_step = 0u;
    expect_reset_isr(&s, 0);
    assert_int_equal(app.state, APP_STATE_FAULT);
    assert_int_equal(app.fault, APP_FAULT_OVERCURRENT); /* the reason stays the first */
    expect_reset_isr(&s, 0);   /* cause gone */
    assert_int_equal(app.state, APP_STATE_IDLE);
    assert_int_equal(app.fault, APP_FAULT_NONE);
    /* the start asked for while faulted was dropped */
    isr_quiet(&s);
    assert_int_equal(app.state, APP_STATE_IDLE);
    start(&s);
}

/* ---- ISR call order ---------------------------------------------------- */

/* read -> protection (trip poll) -> ctrl_step -> write -> ack: the duties
 * written are the ones this call's ctrl_step computed from this call's
 * samples; a protection fault stops before ctrl_step and the write. */
static void isr_call_order(void **state)
{
    (void)state;
    init_app();
    count_now = 0u; /* angle 0 with offset 0: id = ia */
    hal_sample_t s = sample(0.0f, 0.0f, VDC);
    start(&s);
    hal_sample_t r = sample(2.0f, -1.0f, VDC);
    expect_function_call(hal_sample_read);
    will_return(hal_sample_read, &r);
    expect_function_call(hal_trip_active);
    will_return(hal_trip_active, 0);
    expect_function_call(hal_pwm_write);
    expect_function_call(hal_isr_ack);
    app_isr(&app);
    assert_float_equal(app.ctrl.mon.id_A, 2.0, 1e-3); /* ctrl_step saw this call's sample */
    for (int j = 0; j < 3; j++) {
        assert_float_equal(mock_hal_duty[j], app.out.duty[j], 0.0);
    }
    const float id_before = app.ctrl.mon.id_A;
    hal_sample_t bad = sample(5.0f, 0.0f, 500.0f);
    isr_fault(&bad, 0);
    assert_float_equal(app.ctrl.mon.id_A, id_before, 0.0); /* no ctrl_step */
}

static void background_kicks_watchdog(void **state)
{
    (void)state;
    init_app();
    expect_function_call(hal_watchdog_kick);
    app_background(&app);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(cfg_default_is_the_board),
        cmocka_unit_test(init_is_init_with_pwm_off),
        cmocka_unit_test(start_runs_and_stop_idles),
        cmocka_unit_test(sequence_calibrates_aligns_runs),
        cmocka_unit_test(align_skipped_when_offset_known),
        cmocka_unit_test(align_once_until_encoder_fault),
        cmocka_unit_test(stop_during_calibrate_and_align),
        cmocka_unit_test(calibration_rejects_offset_out_of_band),
        cmocka_unit_test(overcurrent_on_each_phase_latches),
        cmocka_unit_test(overcurrent_after_offset_correction),
        cmocka_unit_test(hardware_trip_latches_in_run_and_init),
        cmocka_unit_test(non_finite_sample_latches),
        cmocka_unit_test(non_finite_controller_output_latches),
        cmocka_unit_test(overvoltage_latches_in_every_state),
        cmocka_unit_test(undervoltage_armed_after_calibration),
        cmocka_unit_test(encoder_jump_latches),
        cmocka_unit_test(overspeed_latches_and_reset_waits),
        cmocka_unit_test(overspeed_in_run),
        cmocka_unit_test(overrun_run_time_latches),
        cmocka_unit_test(overrun_missed_period_latches),
        cmocka_unit_test(fault_holds_until_reset_and_cause_gone),
        cmocka_unit_test(isr_call_order),
        cmocka_unit_test(background_kicks_watchdog),
    };
    return cmocka_run_group_tests_name("app", tests, NULL, NULL);
}
