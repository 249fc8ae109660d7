/* Unit tests for firmware/calib (the CALIBRATE step): calib_step with
 * hand values, NaN refused, a restart clears; in the app, an offset out
 * of band faults CURRENT_OFFSET with its snapshot and nothing taken. */
#include "app_harness.h"

/* ---- calib_step on its own --------------------------------------------- */

static calib_t cal_unit(void)
{
    const calib_cfg_t cfg = { CAL_SETTLE * 1e-4f, CAL_N, OFFSET_MAX };
    calib_t c;
    calib_init(&c, &cfg, 1e-4f);
    return c;
}

/* Settle periods ignored (a decaying 2 A), then the mean of CAL_N hand
 * values: RUNNING until the last averaged period, DONE there. */
static void calib_step_averages_after_settle(void **state)
{
    (void)state;
    calib_t c = cal_unit();
    assert_int_equal(c.settle_ticks, CAL_SETTLE);
    for (int k = 0; k < CAL_SETTLE; k++) {
        assert_int_equal(calib_step(&c, 2.0f, -1.0f).status, APP_STEP_RUNNING);
    }
    for (int k = 0; k < CAL_N; k++) {
        const app_step_t r = calib_step(&c, CAL_IA[k], CAL_IB[k]);
        assert_int_equal(r.status, (k < CAL_N - 1) ? APP_STEP_RUNNING : APP_STEP_DONE);
    }
    assert_float_equal(c.offset_ia_A, 0.11, 1e-6);
    assert_float_equal(c.offset_ib_A, -0.04, 1e-6);
}

/* A NaN sample makes the mean NaN: refused with the limit; a restart
 * clears the sums, so the next calibration is the hand mean again. */
static void calib_step_refuses_nan_and_restarts_clean(void **state)
{
    (void)state;
    calib_t c = cal_unit();
    app_step_t r = app_step_running();
    for (int k = 0; k < CAL_SETTLE + CAL_N; k++) {
        r = calib_step(&c, (k == CAL_SETTLE) ? NAN : 0.0f, 0.0f);
    }
    assert_int_equal(r.status, APP_STEP_FAULT);
    assert_int_equal(r.fault, APP_FAULT_CURRENT_OFFSET);
    assert_true(isnan(r.value));
    assert_float_equal(r.limit, OFFSET_MAX, 0.0);
    assert_float_equal(c.offset_ia_A, 0.0, 0.0); /* not taken */

    calib_start(&c);
    for (int k = 0; k < CAL_SETTLE + CAL_N; k++) {
        const int j = (k < CAL_SETTLE) ? 0 : k - CAL_SETTLE;
        r = calib_step(&c, CAL_IA[j], CAL_IB[j]);
    }
    assert_int_equal(r.status, APP_STEP_DONE);
    assert_float_equal(c.offset_ia_A, 0.11, 1e-6);
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
        assert_false(app.prot.uv_armed);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(calib_step_averages_after_settle),
        cmocka_unit_test(calib_step_refuses_nan_and_restarts_clean),
        cmocka_unit_test(calibration_rejects_offset_out_of_band),
    };
    return cmocka_run_group_tests_name("calib", tests, NULL, NULL);
}
