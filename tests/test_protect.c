/* Unit tests for firmware/protect (protection and the snapshot): the
 * derived limits and each check's value and limit by hand; in the app,
 * each fault with PWM off in the same ISR call and its snapshot, and a
 * fault reset refused while the cause persists. */
#include "app_harness.h"

/* ---- protect on its own -------------------------------------------------- */

/* The history checks' thresholds of the unit tests: the board's, with
 * windows of a few periods. */
#define OP_WINDOW   12           /* OPEN_PHASE window [periods]: 4 parts of 3 */
#define OP_PART     3
#define STALL_N     10           /* ENCODER_LOST at the torque limit [periods] */
#define TE_MAX      12.0f
#define POLES       3u
#define STUCK_MIN_N 8u      /* periods a reading must stay unchanged (below the 14 of the 15 deg case) */
#define PSI_F       0.2f     /* the controller's PM flux [Wb] */
/* OPEN_PHASE's voltage rule's top speed by hand: a back-EMF peak of 0.5 x 25 V at 0.2 Wb is
 * 62.5 rad/s el, 20.83 rad/s mech, 2.083e-3 rad (3.316 counts) a period, 9.947 counts a part of 3 */
#define OP_SLOW_COUNTS_PER_PERIOD (0.5 * 25.0 / 0.2 / 3.0 * 1e-4 * 10000.0 / (2.0 * 3.14159265358979))

static protect_cfg_t prot_cfg(void)
{
    const protect_watch_cfg_t w = { OP_WINDOW * 1e-4f, 1.0f, 0.2f, 25.0f, 3.662e-3f, PI_F / 12.0f, 0.5f, 0.1f,
                                    STUCK_MIN_N, 100.0f, STALL_N * 1e-4f, 0.9f };
    const protect_cfg_t cfg = { I_MAX, VDC_MAX, VDC_MIN, SPEED_MAX, PERIOD_CYC, BUDGET_CYC, w };
    return cfg;
}

static protect_t prot_unit(void)
{
    const protect_cfg_t cfg = prot_cfg();
    const protect_drive_t drv = { 1e-4f, CPR, TE_MAX, POLES, PSI_F };
    protect_t p;
    protect_init(&p, &cfg, &drv);
    return p;
}

static app_step_t check(const protect_t *p, const hal_sample_t *s, float speed)
{
    expect_function_call(hal_trip_active);
    will_return(hal_trip_active, 0);
    return protect_check(p, s, 0.0f, 0.0f, speed);
}

/* The derived limits by hand: 2400 r/min is 40 counts per period, x 1.5
 * + 1 = 61; 1.5 periods = 22500 cycles. Each check's value and limit. */
static void protect_limits_and_values_by_hand(void **state)
{
    (void)state;
    protect_t p = prot_unit();
    assert_float_equal(p.enc_jump_max, JUMP_MAX, 1e-3);
    assert_int_equal(p.isr_late_cycles, LATE_CYC);
    hal_sample_t ok = sample_at(1.0f, -1.0f, VDC, 0u);
    assert_int_equal(check(&p, &ok, 0.0f).status, APP_STEP_RUNNING);
    hal_sample_t low = sample_at(1.0f, -1.0f, VDC_MIN - 1.0f, 0u);
    assert_int_equal(check(&p, &low, 0.0f).status, APP_STEP_RUNNING); /* not armed */
    protect_arm_uv(&p);
    app_step_t r = check(&p, &low, 0.0f);
    assert_int_equal(r.fault, APP_FAULT_UNDERVOLTAGE);
    assert_float_equal(r.value, VDC_MIN - 1.0f, 0.0);
    assert_float_equal(r.limit, VDC_MIN, 0.0);
    r = check(&p, &ok, -SPEED_MAX - 1.0f);
    assert_int_equal(r.fault, APP_FAULT_OVERSPEED);
    assert_float_equal(r.value, SPEED_MAX + 1.0f, 1e-4);
    protect_track(&p, CPR - 31u, 0u);
    protect_track(&p, 31u, PERIOD_CYC); /* 62 counts forward across the wrap */
    assert_int_equal(p.enc_delta, 62);
    r = check(&p, &ok, 0.0f);
    assert_int_equal(r.fault, APP_FAULT_ENCODER);
    assert_float_equal(r.value, 62.0, 0.0);
    assert_int_equal(protect_run_time(&p, 100u, 100u + BUDGET_CYC).status, APP_STEP_RUNNING);
    r = protect_run_time(&p, 100u, 101u + BUDGET_CYC);
    assert_int_equal(r.fault, APP_FAULT_OVERRUN);
    assert_float_equal(r.value, BUDGET_CYC + 1.0f, 0.0);
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
    ctrl_set_ref(probe_ctrl_rw(&app), &r);
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

/* In RUN too the check reads this period's estimate (ctrl_track runs
 * first in every state): the PLL put at -300 rad/s with the prediction
 * landing on the count, so this period's error is 0 and the estimate
 * stays -300 rad/s (exact in float). */
static void overspeed_in_run(void **state)
{
    (void)state;
    init_app();
    hal_sample_t s = sample(0.0f, 0.0f, VDC);
    start(&s);
    probe_put_pll(&app, -300.0f, COUNT0);
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

/* ---- the history checks (protect_watch) ---------------------------------- */

/* ... with the controller's aimed current (id_aim, iq_aim) at the rotor angle theta_el */
static protect_watch_in_t watch_in_at(float ia, float ib, const float *duty, bool running, float theta_el,
                                      float id_aim, float iq_aim)
{
    const float al = id_aim * cosf(theta_el) - iq_aim * sinf(theta_el);
    const float be = id_aim * sinf(theta_el) + iq_aim * cosf(theta_el);
    const protect_watch_in_t in = { ia, ib, ia, ib, VDC, duty, running, 0.0f, 0.0f, al, be };
    return in;
}

static protect_watch_in_t watch_in(float ia, float ib, const float *duty, bool running, float speed, float te_ref)
{
    const protect_watch_in_t in = { ia, ib, ia, ib, VDC, duty, running, speed, te_ref, 0.0f, 0.0f };
    return in;
}

/* The voltage rule (not field-oriented, as in the alignment: the cone rule
 * is not judged). Phase a given 0.1 x 311 = 31.1 V (>= 25) but carrying
 * 0 A while ib = 2 A: |i| (the three |i_x| summed over sqrt 3) = 4 /
 * sqrt(3) = 2.309 A, exactly |i_beta|; the first whole window ends at its
 * 12th period: value mean |i_a| / mean |i| = 0, limit 0.2. The same
 * current with phase a at zero voltage (a vector across the phase) is
 * healthy, and so is ia = ib = 1 A (|i| taken as 4 / sqrt(3) = 2.309 A,
 * truly 2: mean |i_a| / |i| = 0.433). The window slides by a part (3
 * periods): after 12 healthy periods (ia = 1 A) phase a opens; the window
 * of the last 4 parts is judged after each part: with 1, 2, 3 open parts
 * mean |i_a| = 0.75, 0.5, 0.25 A against 0.2 x 2.309 = 0.462 A: the third
 * open part (9 periods) trips, value 0.25 / 2.309 = 0.1083. The rule's top
 * speed by hand (OP_SLOW_COUNTS_PER_PERIOD): the first case turning 4
 * counts a period (12 a part, above 9.947) is not judged, at 3 (9 a part)
 * it is. */
static void open_phase_voltage_rule_at_the_window_end(void **state)
{
    (void)state;
    const float d_open[3] = { 0.6f, 0.5f, 0.4f };
    const float d_across[3] = { 0.5f, 0.6f, 0.4f };
    protect_t p = prot_unit();
    assert_float_equal(p.op_slow_counts, OP_PART * OP_SLOW_COUNTS_PER_PERIOD, 1e-4);
    for (int k = 1; k < OP_WINDOW; k++) {
        const protect_watch_in_t in = watch_in(0.0f, 2.0f, d_open, false, 0.0f, 0.0f);
        assert_int_equal(protect_watch(&p, &in).status, APP_STEP_RUNNING);
    }
    const protect_watch_in_t in = watch_in(0.0f, 2.0f, d_open, false, 0.0f, 0.0f);
    app_step_t r = protect_watch(&p, &in);
    assert_int_equal(r.fault, APP_FAULT_OPEN_PHASE);
    assert_float_equal(r.value, 0.0f, 1e-6);
    assert_float_equal(r.limit, 0.2f, 1e-6);
    assert_int_equal(p.op_phase, 0);

    p = prot_unit();
    for (int k = 0; k < 3 * OP_WINDOW; k++) {
        const protect_watch_in_t across = watch_in(0.0f, 2.0f, d_across, false, 0.0f, 0.0f);
        const protect_watch_in_t carries = watch_in(1.0f, 1.0f, d_open, false, 0.0f, 0.0f);
        assert_int_equal(protect_watch(&p, (k < OP_WINDOW) ? &across : &carries).status, APP_STEP_RUNNING);
    }
    /* sliding: 12 healthy periods, then open: trips at the end of the third open part */
    p = prot_unit();
    for (int k = 0; k < OP_WINDOW; k++) {
        const protect_watch_in_t carries = watch_in(1.0f, 1.0f, d_open, false, 0.0f, 0.0f);
        assert_int_equal(protect_watch(&p, &carries).status, APP_STEP_RUNNING);
    }
    for (int k = 1; k < 3 * OP_PART; k++) {
        const protect_watch_in_t open = watch_in(0.0f, 2.0f, d_open, false, 0.0f, 0.0f);
        assert_int_equal(protect_watch(&p, &open).status, APP_STEP_RUNNING);
    }
    {
        const protect_watch_in_t open = watch_in(0.0f, 2.0f, d_open, false, 0.0f, 0.0f);
        r = protect_watch(&p, &open);
        assert_int_equal(r.fault, APP_FAULT_OPEN_PHASE);
        assert_float_equal(r.value, 0.25f / (4.0f / sqrtf(3.0f)), 1e-5);
        assert_float_equal(r.limit, 0.2f, 1e-6);
    }
    /* outputs off (no duties) restart the window: 11 + off + 11 periods do not end one */
    p = prot_unit();
    for (int k = 0; k < 2 * OP_WINDOW - 1; k++) {
        const protect_watch_in_t in2 = watch_in(0.0f, 2.0f, (k == OP_WINDOW - 1) ? NULL : d_open, false, 0.0f, 0.0f);
        assert_int_equal(protect_watch(&p, &in2).status, APP_STEP_RUNNING);
    }
    /* the top speed: 4 counts a period is above it, 3 below */
    for (uint32_t per_period = 3u; per_period <= 4u; per_period++) {
        uint32_t count = 0u;
        int k;
        p = prot_unit();
        r = app_step_running();
        for (k = 0; (k < 2 * OP_WINDOW) && (r.status == APP_STEP_RUNNING); k++) {
            protect_track(&p, count, (uint32_t)k * PERIOD_CYC);
            count += per_period;
            const protect_watch_in_t o = watch_in(0.0f, 2.0f, d_open, false, 0.0f, 0.0f);
            r = protect_watch(&p, &o);
        }
        assert_true((double)(per_period * OP_PART) != OP_PART * OP_SLOW_COUNTS_PER_PERIOD);
        if ((double)(per_period * OP_PART) < OP_PART * OP_SLOW_COUNTS_PER_PERIOD) {
            assert_int_equal(r.fault, APP_FAULT_OPEN_PHASE);
            assert_int_equal(k, OP_WINDOW);
        } else {
            assert_int_equal(r.status, APP_STEP_RUNNING);
        }
    }
}

/* Phase a at 0 A while its voltage flips +-31.1 V every period (the
 * deadbeat's answer to ADC noise): each 3-period part averages to
 * 31.1 / 3 V, the window to 10.4 V < 25 V: no fault at standstill. */
static void open_phase_voltage_averaged_per_part(void **state)
{
    (void)state;
    const float d_pos[3] = { 0.6f, 0.5f, 0.4f };
    const float d_neg[3] = { 0.4f, 0.5f, 0.6f };
    protect_t p = prot_unit();
    for (int k = 0; k < 3 * OP_WINDOW; k++) {
        const protect_watch_in_t in = watch_in(0.0f, 2.0f, (k % 2 == 0) ? d_pos : d_neg, false, 0.0f, 0.0f);
        assert_int_equal(protect_watch(&p, &in).status, APP_STEP_RUNNING);
    }
}

/* The cone rule (field-oriented). The rotor at theta = 115 deg el, the
 * controller aiming 3 A along its q axis (at 205 deg, 25 deg from phase
 * a's negative axis): i*_alpha = -3 sin 115 = -2.719 A, i*_beta = 3 cos 115
 * = -1.268 A; projected on the phases' axes -2.719, 0.261, 2.458 A, only
 * a's at least cos 30 deg x 3 = 2.598 A: phase a's cone. Healthy, the
 * current is the aim, ia = -2.719 A >= 0.2 x 3 A. Phase a open: the b-c
 * current alone, ia = 0, ib = sqrt(3) / 2 i_beta: a carries nothing. 12
 * healthy periods, then open: the window of the last 4 parts holds 12
 * cone periods; with 1, 2, 3 open parts 3, 6, 9 carry nothing, more than
 * half (6) at the third: the fault there, value the share phase a carried
 * 3 / 12 = 0.25, limit 0.5. Not field-oriented (the alignment) and
 * turning faster than the voltage rule's top speed: no fault. Across: the
 * rotor at 10 deg, the aim along q at 100 deg, 80 deg from a's axis
 * (projections -0.521, 2.819, -2.298 A: phase b's cone), turning fast
 * (160 counts a period) with phase a given 31.1 V and carrying nothing
 * (a healthy a carries |cos 80 deg| = 0.17 < 0.2 of |i| there: the old
 * half-turn rule's false trip): no fault. Field weakening: the rotor at
 * 65 deg (its q axis at 155 deg, 25 deg from a's negative axis),
 * generating, the aim (-2.573, -1.2) A mostly on -d: (0.000, -2.839) A in
 * the stator frame, across phase a, which carries nothing, healthy: no
 * fault (the q axis alone would have put the period in a's cone, -1.2 A
 * projected 1.088 A on a's axis, >= cos 30 deg x 1.2 A, carrying nothing). */
static void open_phase_cone_rule_by_hand(void **state)
{
    (void)state;
    const float d_open[3] = { 0.6f, 0.5f, 0.4f };
    const float th = 115.0f * PI_F / 180.0f;
    const float aim = 3.0f;
    const float i_alpha = -3.0f * sinf(th);
    const float i_beta = 3.0f * cosf(th);
    const float ib_healthy = -0.5f * i_alpha + 0.5f * sqrtf(3.0f) * i_beta;
    const float ib_open = 0.5f * sqrtf(3.0f) * i_beta;
    protect_t p = prot_unit();
    assert_int_equal(p.op_cone_min, 1u); /* 0.125 x 12 periods, whole */
    app_step_t r;
    for (int k = 0; k < OP_WINDOW + 3 * OP_PART - 1; k++) {
        const protect_watch_in_t in = (k < OP_WINDOW) ? watch_in_at(i_alpha, ib_healthy, d_open, true, th, 0.0f, aim)
                                                      : watch_in_at(0.0f, ib_open, d_open, true, th, 0.0f, aim);
        assert_int_equal(protect_watch(&p, &in).status, APP_STEP_RUNNING);
    }
    {
        const protect_watch_in_t in = watch_in_at(0.0f, ib_open, d_open, true, th, 0.0f, aim);
        r = protect_watch(&p, &in);
    }
    assert_int_equal(r.fault, APP_FAULT_OPEN_PHASE);
    assert_int_equal(p.op_phase, 0);
    assert_float_equal(r.value, 0.25f, 1e-6);
    assert_float_equal(r.limit, 0.5f, 0.0f);
    /* the same, not field-oriented (the alignment): the aim says nothing, and
     * the rotor turning 4 counts a period keeps the voltage rule out: no fault */
    p = prot_unit();
    {
        uint32_t count = 0u;
        for (int k = 0; k < 4 * OP_WINDOW; k++) {
            protect_track(&p, count, (uint32_t)k * PERIOD_CYC);
            count += 4u;
            const protect_watch_in_t in = watch_in_at(0.0f, ib_open, d_open, false, th, 0.0f, aim);
            assert_int_equal(protect_watch(&p, &in).status, APP_STEP_RUNNING);
        }
    }
    /* across, turning fast */
    p = prot_unit();
    {
        const float th2 = 10.0f * PI_F / 180.0f;
        const float a2 = -3.0f * sinf(th2);
        const float b2 = 3.0f * cosf(th2);
        uint32_t count = 0u;
        assert_true(fabsf(a2) < 0.2f * 3.0f);
        for (int k = 0; k < 4 * OP_WINDOW; k++) {
            protect_track(&p, count, (uint32_t)k * PERIOD_CYC);
            count += 160u;
            const protect_watch_in_t in = watch_in_at(0.0f, 0.5f * sqrtf(3.0f) * b2, d_open, true, th2, 0.0f, aim);
            assert_int_equal(protect_watch(&p, &in).status, APP_STEP_RUNNING);
        }
    }
    /* field weakening, turning fast */
    p = prot_unit();
    {
        const float th3 = 65.0f * PI_F / 180.0f;
        const float id3 = -2.573f;
        const float iq3 = -1.2f;
        const float ia3 = id3 * cosf(th3) - iq3 * sinf(th3); /* the healthy current: the aim */
        const float ib3 = -0.5f * ia3 + 0.5f * sqrtf(3.0f) * (id3 * sinf(th3) + iq3 * cosf(th3));
        uint32_t count = 0u;
        assert_float_equal(ia3, 0.0f, 1e-3);
        assert_float_equal(ib3, 0.5f * sqrtf(3.0f) * -2.839f, 1e-3);
        assert_true(-iq3 * sinf(th3) >= cosf(PI_F / 6.0f) * -iq3); /* the q axis in a's cone */
        for (int k = 0; k < 4 * OP_WINDOW; k++) {
            protect_track(&p, count, (uint32_t)k * PERIOD_CYC);
            count += 160u;
            const protect_watch_in_t in = watch_in_at(ia3, ib3, d_open, true, th3, id3, iq3);
            assert_int_equal(protect_watch(&p, &in).status, APP_STEP_RUNNING);
        }
    }
}

/* The cone rule against an independent count: the rotor turning 40
 * counts a period (0.0754 rad el; 4.3 deg), the controller aiming 3 A
 * along its q axis, the current that with +-0.05 A of noise, parts of 8
 * periods, a window of 32; phase a opens at period 141 (ia = 0, ib =
 * sqrt(3) / 2 i_beta). The reference, in double precision over the raw
 * periods, counts per part end's window the periods with the aim in phase
 * a's cone (the q axis within 30 deg of a's: |sin theta| >= cos 30 deg),
 * and those with |i_a| < 0.2 x 3 A; the first part end with
 * enough such periods (1/8 of the window) and more than half carrying
 * nothing is the fault, with the share carried: within a window and a
 * part of the opening. protect_watch must agree period by period. */
/* protect_watch over the periods of in[] (the encoder at counts[k]): RUNNING in every period
 * before trip, then OPEN_PHASE of phase a with the value (within tol) and the limit. */
static void assert_open_phase_a_at(protect_t *p, const protect_watch_in_t *in, const uint32_t *counts, int trip,
                                   double value, double tol, double limit)
{
    for (int k = 0; k < trip; k++) {
        protect_track(p, counts[k], (uint32_t)k * PERIOD_CYC);
        assert_int_equal(protect_watch(p, &in[k]).status, APP_STEP_RUNNING);
    }
    protect_track(p, counts[trip], (uint32_t)trip * PERIOD_CYC);
    const app_step_t r = protect_watch(p, &in[trip]);
    assert_int_equal(r.fault, APP_FAULT_OPEN_PHASE);
    assert_int_equal(p->op_phase, 0);
    assert_float_equal(r.value, value, tol);
    assert_float_equal(r.limit, limit, 1e-6);
}

#define CONE_PART 8
#define CONE_WINDOW (4 * CONE_PART)
#define CONE_OPEN_AT 141
#define CONE_PERIODS (CONE_OPEN_AT + 8 * CONE_WINDOW)
#define CONE_TURN_COUNTS 40u

static uint32_t lcg_next(uint32_t *x)
{
    *x = *x * 1664525u + 1013904223u;
    return *x >> 8;
}

static double lcg_unit(uint32_t *x) /* [0, 1) */
{
    return (double)lcg_next(x) / 16777216.0;
}

static void open_phase_cone_rule_against_a_count(void **state)
{
    (void)state;
    static float ia[CONE_PERIODS], ib[CONE_PERIODS], th[CONE_PERIODS];
    static protect_watch_in_t ins[CONE_PERIODS];
    static uint32_t counts[CONE_PERIODS];
    const float duty[3] = { 0.6f, 0.5f, 0.4f };
    protect_cfg_t cfg = prot_cfg();
    cfg.watch.op_window_s = CONE_WINDOW * 1e-4f;
    const protect_drive_t drv = { 1e-4f, CPR, TE_MAX, POLES, PSI_F };
    const double cone_cos = cos(30.0 * 3.14159265358979 / 180.0);
    protect_t p;
    uint32_t seed = 777u;
    int trip_ref = -1;
    double value_ref = 0.0;

    for (int k = 0; k < CONE_PERIODS; k++) {
        const double t = (double)((uint32_t)k * CONE_TURN_COUNTS % CPR) * 2.0 * 3.14159265358979 * POLES / CPR;
        const double ial = -3.0 * sin(t) + 0.1 * (lcg_unit(&seed) - 0.5);
        const double ibe = 3.0 * cos(t) + 0.1 * (lcg_unit(&seed) - 0.5);
        th[k] = (float)t;
        ia[k] = (k < CONE_OPEN_AT) ? (float)ial : 0.0f;
        ib[k] = (float)(((k < CONE_OPEN_AT) ? -0.5 * ial : 0.0) + 0.5 * sqrt(3.0) * ibe);
    }
    for (int end = CONE_WINDOW - 1; end < CONE_PERIODS && trip_ref < 0; end += CONE_PART) {
        int cone = 0, none = 0;
        for (int k = end - CONE_WINDOW + 1; k <= end; k++) {
            if (fabs(sin((double)th[k])) >= cone_cos) {
                cone++;
                none += (fabs((double)ia[k]) < 0.2 * 3.0) ? 1 : 0;
            }
        }
        if ((cone >= CONE_WINDOW / 8) && (2 * none > cone)) {
            trip_ref = end;
            value_ref = 1.0 - (double)none / cone;
        }
    }
    assert_true(trip_ref > CONE_OPEN_AT);
    assert_true(trip_ref - CONE_OPEN_AT <= CONE_WINDOW + CONE_PART);

    protect_init(&p, &cfg, &drv);
    assert_int_equal(p.op_part_ticks, CONE_PART);
    for (int k = 0; k < CONE_PERIODS; k++) {
        ins[k] = watch_in_at(ia[k], ib[k], duty, true, th[k], 0.0f, 3.0f);
        counts[k] = (uint32_t)k * CONE_TURN_COUNTS % CPR;
    }
    assert_open_phase_a_at(&p, ins, counts, trip_ref, value_ref, 1e-6, 0.5);
}

/* The window's parts longer than its preparation steps (as on the board,
 * 250 periods a part): parts of 8 periods, a window of 32, the steps in
 * the parts' first periods and none left for a part's end. Random healthy
 * currents and voltages (phase a given >= 25 V, all three carrying
 * current), then phase a opens at period 133 (4 windows and 5 periods in),
 * turning at 3 counts per period (24 a part, under the voltage rule's top
 * speed of 26.5; not field-oriented: the voltage rule alone judges).
 * Independently, in double precision over the raw periods: each part
 * end's window (its last 4 parts, |u_a| per part). protect_watch must
 * answer RUNNING in every period until the first part end the reference
 * finds open, and trip there, with the reference's mean |i_a| / mean |i|
 * and limit: at a part's end, within one window and a part of the opening
 * (the documented time), never a period later. */
#define SPREAD_PART 8
#define SPREAD_WINDOW (4 * SPREAD_PART)
#define SPREAD_OPEN_AT (4 * SPREAD_WINDOW + 5)
#define SPREAD_PERIODS (SPREAD_OPEN_AT + 3 * SPREAD_WINDOW)
#define SPREAD_TURN_COUNTS 3u

static void open_phase_spread_steps_trip_at_the_documented_part_end(void **state)
{
    (void)state;
    static float ia[SPREAD_PERIODS], ib[SPREAD_PERIODS], duty[SPREAD_PERIODS][3];
    static protect_watch_in_t ins[SPREAD_PERIODS];
    static uint32_t counts[SPREAD_PERIODS];
    protect_cfg_t cfg = prot_cfg();
    cfg.watch.op_window_s = SPREAD_WINDOW * 1e-4f;
    const protect_drive_t drv = { 1e-4f, CPR, TE_MAX, POLES, PSI_F };
    protect_t p;
    uint32_t seed = 12345u;
    int trip_ref = -1;
    double value_ref = 0.0;

    for (int k = 0; k < SPREAD_PERIODS; k++) {
        const double th = 2.0 * 3.14159265358979 * lcg_unit(&seed);
        const double amp = 1.5 + lcg_unit(&seed);
        const double a = (k < SPREAD_OPEN_AT) ? amp * cos(th) : 0.0;
        const double b = (k < SPREAD_OPEN_AT) ? amp * cos(th - 2.0943951023932) : amp * (0.5 + 0.5 * lcg_unit(&seed));
        ia[k] = (float)a;
        ib[k] = (float)b;
        duty[k][0] = (float)(0.6 + 0.05 * lcg_unit(&seed));
        duty[k][1] = (float)(0.45 + 0.1 * lcg_unit(&seed));
        duty[k][2] = (float)(0.4 + 0.05 * lcg_unit(&seed));
    }
    /* the reference: each part end's window of the last 4 parts */
    for (int end = SPREAD_WINDOW - 1; end < SPREAD_PERIODS && trip_ref < 0; end += SPREAD_PART) {
        double i_sum = 0.0, ia_sum = 0.0, ua_parts = 0.0;
        for (int part = 0; part < 4; part++) {
            double ua = 0.0;
            for (int j = 0; j < SPREAD_PART; j++) {
                const int k = end - SPREAD_WINDOW + 1 + part * SPREAD_PART + j;
                const double dm = ((double)duty[k][0] + duty[k][1] + duty[k][2]) / 3.0;
                i_sum += (fabs((double)ia[k]) + fabs((double)ib[k]) + fabs((double)ia[k] + ib[k])) / sqrt(3.0);
                ia_sum += fabs((double)ia[k]);
                ua += ((double)duty[k][0] - dm) * VDC;
            }
            ua_parts += fabs(ua);
        }
        const double n = SPREAD_WINDOW;
        assert_true(SPREAD_TURN_COUNTS < OP_SLOW_COUNTS_PER_PERIOD);  /* the voltage rule judges */
        assert_true(ua_parts / n >= 25.0 * 1.001);                    /* phase a given voltage */
        assert_true(i_sum / n >= 1.0 * 1.001);
        if (ia_sum / n < 0.2 * i_sum / n) {
            trip_ref = end;
            value_ref = ia_sum / i_sum;
        } else {
            assert_true(ia_sum / n >= 0.2 * i_sum / n * 1.001); /* not a rounding's call */
        }
    }
    assert_true(trip_ref > SPREAD_OPEN_AT);
    assert_true(trip_ref - SPREAD_OPEN_AT <= SPREAD_WINDOW + SPREAD_PART);

    protect_init(&p, &cfg, &drv);
    assert_int_equal(p.op_part_ticks, SPREAD_PART);
    for (int k = 0; k < SPREAD_PERIODS; k++) {
        ins[k] = watch_in(ia[k], ib[k], duty[k], false, 0.0f, 0.0f);
        counts[k] = (uint32_t)k * SPREAD_TURN_COUNTS;
    }
    assert_open_phase_a_at(&p, ins, counts, trip_ref, value_ref, 1e-5, 0.2);
}

/* ia frozen at 1 A while the count moves 10 per period (10 x 2 pi x 3 /
 * 10000 = 0.01885 rad el) and ib sweeps 0.1 A per period: the turn since
 * the first period reaches 15 deg (0.2618 rad) after 14 periods (0.2639).
 * A count jittering +-10 turns nothing. */
static void frozen_current_reading_found_after_15_deg(void **state)
{
    (void)state;
    const float step_rad = 10.0f * 2.0f * PI_F * 3.0f / (float)CPR;
    protect_t p = prot_unit();
    uint32_t count = 0u;
    app_step_t r = app_step_running();
    int k;
    for (k = 0; (k < 20) && (r.status == APP_STEP_RUNNING); k++) {
        protect_track(&p, count, (uint32_t)k * PERIOD_CYC);
        count += 10u;
        const protect_watch_in_t in = watch_in(1.0f, 0.1f * (float)k, NULL, true, 0.0f, 0.0f);
        r = protect_watch(&p, &in);
    }
    assert_int_equal(r.fault, APP_FAULT_CURRENT_SENSOR);
    assert_int_equal(k, 15); /* the 15th period: 14 turns after the first */
    assert_float_equal(r.value, 14.0f * step_rad, 1e-4);
    assert_float_equal(r.limit, PI_F / 12.0f, 1e-6);

    /* the same near 0 A (an open phase's reading), or not in RUN, or at standstill, or jittering: no fault */
    for (int variant = 0; variant < 4; variant++) {
        p = prot_unit();
        count = 100u;
        for (k = 0; k < 40; k++) {
            protect_track(&p, count, (uint32_t)k * PERIOD_CYC);
            count = (variant == 2) ? count : ((variant == 3) ? ((k % 2 == 0) ? 110u : 100u) : count + 10u);
            const protect_watch_in_t in = watch_in((variant == 0) ? 0.05f : 1.0f, 0.1f * (float)k, NULL, variant != 1,
                                                   0.0f, 0.0f);
            assert_int_equal(protect_watch(&p, &in).status, APP_STEP_RUNNING);
        }
    }
}

/* A fast turn: the same frozen reading, the turn at 15 deg after 14
 * periods, but at least 20 periods unchanged asked for: the fault at the
 * 21st period, not before (noise keeps an ADC code a few periods by chance). */
static void frozen_current_reading_needs_its_periods(void **state)
{
    (void)state;
    protect_cfg_t cfg = prot_cfg();
    cfg.watch.stuck_min_periods = 20u;
    const protect_drive_t drv = { 1e-4f, CPR, TE_MAX, POLES, PSI_F };
    protect_t p;
    protect_init(&p, &cfg, &drv);
    uint32_t count = 0u;
    app_step_t r = app_step_running();
    int k;
    for (k = 0; (k < 40) && (r.status == APP_STEP_RUNNING); k++) {
        protect_track(&p, count, (uint32_t)k * PERIOD_CYC);
        count += 10u;
        const protect_watch_in_t in = watch_in(1.0f, 0.1f * (float)k, NULL, true, 0.0f, 0.0f);
        r = protect_watch(&p, &in);
    }
    assert_int_equal(r.fault, APP_FAULT_CURRENT_SENSOR);
    assert_int_equal(k, 21);
}

/* The count stops at 94.25 rad/s (15 counts per period by the estimate):
 * 105 missed counts at the 7th frozen period cross 100. At the torque limit
 * (11 N m >= 0.9 x 12) with no count for STALL_N periods: the stall rule;
 * at 10 N m (< 10.8) none. */
static void lost_encoder_found_moving_and_at_the_torque_limit(void **state)
{
    (void)state;
    const float speed = 15.0f * 2.0f * PI_F / ((float)CPR * 1e-4f);
    protect_t p = prot_unit();
    protect_track(&p, 500u, 0u);
    app_step_t r = app_step_running();
    int k;
    for (k = 1; (k < 20) && (r.status == APP_STEP_RUNNING); k++) {
        protect_track(&p, 500u, (uint32_t)k * PERIOD_CYC);
        const protect_watch_in_t in = watch_in(0.0f, 0.0f, NULL, false, speed, 0.0f);
        r = protect_watch(&p, &in);
    }
    assert_int_equal(r.fault, APP_FAULT_ENCODER_LOST);
    assert_int_equal(k - 1, 7);
    assert_float_equal(r.value, 105.0f, 1e-3);
    assert_float_equal(r.limit, 100.0f, 0.0);

    for (int te = 0; te < 2; te++) {
        const float te_ref = (te == 0) ? 11.0f : 10.0f;
        p = prot_unit();
        r = app_step_running();
        for (k = 0; (k < 3 * STALL_N) && (r.status == APP_STEP_RUNNING); k++) {
            protect_track(&p, 500u, (uint32_t)k * PERIOD_CYC);
            const protect_watch_in_t in = watch_in(0.0f, 0.0f, NULL, true, 0.0f, te_ref);
            r = protect_watch(&p, &in);
        }
        if (te == 0) {
            assert_int_equal(r.fault, APP_FAULT_ENCODER_LOST);
            assert_int_equal(k, STALL_N);
            assert_float_equal(r.value, STALL_N * 1e-4f, 1e-7);
        } else {
            assert_int_equal(r.status, APP_STEP_RUNNING);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(protect_limits_and_values_by_hand),
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
        cmocka_unit_test(open_phase_voltage_rule_at_the_window_end),
        cmocka_unit_test(open_phase_voltage_averaged_per_part),
        cmocka_unit_test(open_phase_cone_rule_by_hand),
        cmocka_unit_test(open_phase_cone_rule_against_a_count),
        cmocka_unit_test(open_phase_spread_steps_trip_at_the_documented_part_end),
        cmocka_unit_test(frozen_current_reading_found_after_15_deg),
        cmocka_unit_test(frozen_current_reading_needs_its_periods),
        cmocka_unit_test(lost_encoder_found_moving_and_at_the_torque_limit),
    };
    return cmocka_run_group_tests_name("protect", tests, NULL, NULL);
}
