/* Unit tests for firmware/app: the ISR's HAL call order and every state
 * transition, against the cmocka mock of the HAL (tests/mock_hal.c). */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>

#include "app.h"
#include "mock_hal.h"

#define I_MAX 12.0f

static app_cfg_t make_cfg(void)
{
    app_cfg_t cfg;
    cfg.ctrl = (ctrl_cfg_t){
        .Ts_s = 1e-4f, .Rs_Ohm = 3.0f, .Ls_H = 0.011f, .psi_f_Wb = 0.24f, .pole_pairs = 3u,
        .enc_lines = 2500u, .enc_offset_el_rad = 0.0f, .enc_pll_bw_rad_s = 500.0f,
        .speed_kp_Nms_rad = 0.5f, .speed_ki_Nm_rad = 20.0f, .te_max_Nm = 12.0f,
        .i_max_A = 60.0f, .u_max_V = 5000.0f, .omega_max_el_rad_s = 3000.0f, .psi_max_Wb = 1.0f,
    };
    cfg.i_max_A = I_MAX;
    return cfg;
}

static hal_sample_t sample(float ia, float ib, float vdc)
{
    hal_sample_t s = { ia, ib, vdc, 1234u };
    return s;
}

static app_t app; /* large: not on the test's stack */

static void init_app(void)
{
    app_cfg_t cfg = make_cfg();
    expect_function_call(hal_pwm_disable);
    app_init(&app, &cfg);
}

/* One ISR call in which nothing but the read, the trip poll and the ack happen. */
static void isr_quiet(const hal_sample_t *s)
{
    expect_function_call(hal_sample_read);
    will_return(hal_sample_read, s);
    expect_function_call(hal_trip_active);
    will_return(hal_trip_active, 0);
    expect_function_call(hal_isr_ack);
    app_isr(&app);
}

/* One ISR call in RUN with healthy samples: read, poll, write, ack. */
static void isr_run(const hal_sample_t *s)
{
    expect_function_call(hal_sample_read);
    will_return(hal_sample_read, s);
    expect_function_call(hal_trip_active);
    will_return(hal_trip_active, 0);
    expect_function_call(hal_pwm_write);
    expect_function_call(hal_isr_ack);
    app_isr(&app);
}

static void start(const hal_sample_t *s)
{
    app_request_start(&app);
    expect_function_call(hal_sample_read);
    will_return(hal_sample_read, s);
    expect_function_call(hal_trip_active);
    will_return(hal_trip_active, 0);
    expect_function_call(hal_pwm_write);
    expect_function_call(hal_pwm_enable); /* after the first duties */
    expect_function_call(hal_isr_ack);
    app_isr(&app);
    assert_int_equal(app.state, APP_STATE_RUN);
}

static void init_is_idle_with_pwm_off(void **state)
{
    (void)state;
    init_app();
    assert_int_equal(app.state, APP_STATE_IDLE);
    assert_int_equal(app.fault, APP_FAULT_NONE);
    hal_sample_t s = sample(0.0f, 0.0f, 311.0f);
    isr_quiet(&s); /* IDLE: no PWM call at all */
    assert_int_equal(app.state, APP_STATE_IDLE);
    assert_int_equal(app.ticks, 1u);
}

static void start_runs_and_stop_idles(void **state)
{
    (void)state;
    init_app();
    hal_sample_t s = sample(0.5f, -0.2f, 311.0f);
    start(&s);
    isr_run(&s);
    assert_true(isfinite(mock_hal_duty[0]) && mock_hal_duty[0] >= 0.0f && mock_hal_duty[0] <= 1.0f);
    /* the duties written are the controller's */
    assert_float_equal(mock_hal_duty[1], app.out.duty[1], 0.0);
    app_request_stop(&app);
    expect_function_call(hal_sample_read);
    will_return(hal_sample_read, &s);
    expect_function_call(hal_trip_active);
    will_return(hal_trip_active, 0);
    expect_function_call(hal_pwm_disable);
    expect_function_call(hal_pwm_write);
    expect_function_call(hal_isr_ack);
    app_isr(&app);
    assert_int_equal(app.state, APP_STATE_IDLE);
    assert_float_equal(mock_hal_duty[0], 0.5, 0.0);
    isr_quiet(&s);
    assert_int_equal(app.state, APP_STATE_IDLE);
}

/* A fault ISR: read, poll (value given), PWM off, ack, nothing else. */
static void isr_fault(const hal_sample_t *s, int trip)
{
    expect_function_call(hal_sample_read);
    will_return(hal_sample_read, s);
    expect_function_call(hal_trip_active);
    will_return(hal_trip_active, trip);
    expect_function_call(hal_pwm_disable);
    expect_function_call(hal_isr_ack);
    app_isr(&app);
    assert_int_equal(app.state, APP_STATE_FAULT);
}

static void assert_snapshot(const hal_sample_t *s)
{
    assert_memory_equal(&app.fault_snapshot, s, sizeof *s);
}

static void overcurrent_on_each_phase_latches(void **state)
{
    (void)state;
    /* ia, ib, and ic = -ia - ib beyond 12 A */
    const hal_sample_t bad[3] = { sample(12.5f, -1.0f, 311.0f), sample(1.0f, -12.5f, 311.0f),
                                  sample(6.5f, 6.0f, 311.0f) };
    for (int k = 0; k < 3; k++) {
        init_app();
        hal_sample_t ok = sample(11.9f, -6.0f, 311.0f); /* ic = -5.9 A */
        start(&ok);
        isr_run(&ok);
        isr_fault(&bad[k], 0);
        assert_int_equal(app.fault, APP_FAULT_OVERCURRENT);
        assert_snapshot(&bad[k]);
    }
}

static void hardware_trip_latches_in_run_and_idle(void **state)
{
    (void)state;
    init_app();
    hal_sample_t s = sample(1.0f, 1.0f, 311.0f);
    start(&s);
    isr_fault(&s, 1);
    assert_int_equal(app.fault, APP_FAULT_HW_TRIP);
    assert_snapshot(&s);

    init_app();
    isr_fault(&s, 1);
    assert_int_equal(app.fault, APP_FAULT_HW_TRIP);
}

static void non_finite_sample_latches(void **state)
{
    (void)state;
    init_app();
    hal_sample_t ok = sample(1.0f, 1.0f, 311.0f);
    hal_sample_t bad = sample(1.0f, 1.0f, NAN);
    start(&ok);
    isr_fault(&bad, 0);
    assert_int_equal(app.fault, APP_FAULT_NONFINITE);
    assert_true(isnan(app.fault_snapshot.vdc_V));
}

/* The controller's output turns non-finite (a NaN reference): no write,
 * PWM off in the same call. */
static void non_finite_controller_output_latches(void **state)
{
    (void)state;
    init_app();
    hal_sample_t s = sample(1.0f, 1.0f, 311.0f);
    start(&s);
    ctrl_ref_t r = { 0.0f, NAN, 0.0f, 0.0f };
    ctrl_set_ref(&app.ctrl, &r);
    isr_fault(&s, 0);
    assert_int_equal(app.fault, APP_FAULT_NONFINITE);
    assert_snapshot(&s);
}

/* FAULT holds: later ISRs read and ack only, keep the snapshot, ignore a
 * start; a reset with the trip still active stays; without, goes IDLE. */
static void fault_holds_until_reset_and_cause_gone(void **state)
{
    (void)state;
    init_app();
    hal_sample_t s = sample(1.0f, 1.0f, 311.0f);
    hal_sample_t bad = sample(20.0f, 0.0f, 311.0f);
    start(&s);
    isr_fault(&bad, 0);
    app_request_start(&app);
    for (int k = 0; k < 3; k++) {
        expect_function_call(hal_sample_read);
        will_return(hal_sample_read, &s);
        expect_function_call(hal_isr_ack);
        app_isr(&app);
        assert_int_equal(app.state, APP_STATE_FAULT);
        assert_snapshot(&bad);
    }
    /* reset while the currents are still too high: stays */
    expect_function_call(hal_trip_clear);
    app_fault_reset(&app);
    expect_function_call(hal_sample_read);
    will_return(hal_sample_read, &bad);
    expect_function_call(hal_trip_active);
    will_return(hal_trip_active, 0);
    expect_function_call(hal_isr_ack);
    app_isr(&app);
    assert_int_equal(app.state, APP_STATE_FAULT);
    /* reset with a trip still active: stays */
    expect_function_call(hal_trip_clear);
    app_fault_reset(&app);
    expect_function_call(hal_sample_read);
    will_return(hal_sample_read, &s);
    expect_function_call(hal_trip_active);
    will_return(hal_trip_active, 1);
    expect_function_call(hal_isr_ack);
    app_isr(&app);
    assert_int_equal(app.state, APP_STATE_FAULT);
    /* cause gone */
    expect_function_call(hal_trip_clear);
    app_fault_reset(&app);
    expect_function_call(hal_sample_read);
    will_return(hal_sample_read, &s);
    expect_function_call(hal_trip_active);
    will_return(hal_trip_active, 0);
    expect_function_call(hal_isr_ack);
    app_isr(&app);
    assert_int_equal(app.state, APP_STATE_IDLE);
    assert_int_equal(app.fault, APP_FAULT_NONE);
    /* the start asked for while faulted was dropped */
    isr_quiet(&s);
    assert_int_equal(app.state, APP_STATE_IDLE);
    start(&s);
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
        cmocka_unit_test(init_is_idle_with_pwm_off),
        cmocka_unit_test(start_runs_and_stop_idles),
        cmocka_unit_test(overcurrent_on_each_phase_latches),
        cmocka_unit_test(hardware_trip_latches_in_run_and_idle),
        cmocka_unit_test(non_finite_sample_latches),
        cmocka_unit_test(non_finite_controller_output_latches),
        cmocka_unit_test(fault_holds_until_reset_and_cause_gone),
        cmocka_unit_test(background_kicks_watchdog),
    };
    return cmocka_run_group_tests_name("app", tests, NULL, NULL);
}
