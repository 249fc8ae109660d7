/* Unit tests for firmware/align (the ALIGN step): align_step's vector in
 * every period against hand values, ctrl's output path it drives
 * (ctrl_step_ab: SVPWM duties, the NaN guard); in the app, the duties of
 * each phase as numbers, alignment skipped when the offset is known and
 * repeated only after an ENCODER fault. */
#include "app_harness.h"

/* ---- align_step on its own --------------------------------------------- */

/* The vector of every period against the hand values of align_u(), DONE
 * exactly in the aligning period ALIGN_END. */
static void align_step_vectors_by_period(void **state)
{
    (void)state;
    const align_cfg_t cfg = { ALIGN_U_V, 0.5f * PI_F, ALIGN_RAMP * 1e-4f, ALIGN_PREPOS * 1e-4f, ALIGN_HOLD * 1e-4f };
    align_t a;
    align_init(&a, &cfg, 1e-4f);
    for (int round = 0; round < 2; round++) { /* align_start begins again at period 0 */
        align_start(&a);
        for (int k = 0; k <= ALIGN_END; k++) {
            ab_t u;
            float ua;
            float ub;
            const app_step_t r = align_step(&a, &u);
            align_u(k, &ua, &ub);
            assert_float_equal(u.a, ua, 1e-5);
            assert_float_equal(u.b, ub, 1e-5);
            assert_int_equal(r.status, (k < ALIGN_END) ? APP_STEP_RUNNING : APP_STEP_DONE);
        }
    }
}

/* The alignment's output path is ctrl's: a NaN vector or no bus gives
 * 50 % duties and CTRL_FLAG_NONFINITE (the app latches NONFINITE_OUTPUT
 * and writes nothing); a finite one the SVPWM duties. */
static void align_nan_vector_latches_without_write(void **state)
{
    (void)state;
    ctrl_t c;
    ctrl_out_t out;
    const app_cfg_t cfg = make_cfg(false, true);
    (void)ctrl_init(&c, &cfg.ctrl);
    const ab_t nan_u = { NAN, 0.0f };
    ctrl_step_ab(&c, nan_u, VDC, &out);
    assert_true((out.flags & CTRL_FLAG_NONFINITE) != 0u);
    const ab_t u = { ALIGN_U_V, 0.0f };
    ctrl_step_ab(&c, u, 0.0f, &out);
    assert_true((out.flags & CTRL_FLAG_NONFINITE) != 0u);
    for (int j = 0; j < 3; j++) {
        assert_float_equal(out.duty[j], 0.5, 0.0);
    }
    ctrl_step_ab(&c, u, VDC, &out); /* u_alpha 9 V at 311 V: a = 0.5 + 0.75 u / Vdc */
    assert_int_equal(out.flags, 0u);
    assert_float_equal(out.duty[0], 0.5217042, 1e-6);

}

/* The duties of each alignment phase as numbers (9 V at 311 V), which
 * also pins minmax_duty: u_beta alone puts phase a at 0.5 and b, c at
 * 0.5 +/- (sqrt(3)/2) u / Vdc; u_alpha alone gives a = 0.5 + 0.75 u / Vdc,
 * b = c = 0.5 - 0.75 u / Vdc; half-way through the turn, u = (4.5, 4.5):
 * v = (4.5, 1.647, -6.147) V, mid-range -0.824 V. */
static void align_duties_by_phase(void **state)
{
    (void)state;
    static const struct { int k; float d[3]; } want[] = {
        { 2, { 0.5f, 0.5125309f, 0.4874691f } },                         /* ramp: u_beta 4.5 V */
        { ALIGN_RAMP, { 0.5f, 0.5250618f, 0.4749382f } },                /* pre-position held: u_beta 9 V */
        { ALIGN_RAMP + ALIGN_PREPOS + 2, { 0.5171175f, 0.5079443f, 0.4828825f } }, /* turn, f = 1/2 */
        { ALIGN_END, { 0.5217042f, 0.4782958f, 0.4782958f } },            /* on phase a: u_alpha 9 V */
    };
    init_with(false, true);
    hal_sample_t s = sample(0.0f, 0.0f, VDC);
    app_request_start(&app);
    size_t w = 0;
    for (int k = 0; k <= ALIGN_END; k++) {
        if (k == 0) {
            isr_first_write(&s);
        } else {
            isr_run(&s);
        }
        if (w < sizeof want / sizeof want[0] && want[w].k == k) {
            for (int j = 0; j < 3; j++) {
                assert_float_equal(mock_hal_duty[j], want[w].d[j], 1e-6);
            }
            w++;
        }
    }
    assert_int_equal(w, sizeof want / sizeof want[0]);
    assert_int_equal(app.state, APP_STATE_RUN);
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
    for (int k = 1; k <= ALIGN_END; k++) {
        isr_run(&s);
    }
    assert_int_equal(app.state, APP_STATE_RUN);
    isr_run(&s);
    isr_stop(&s);
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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(align_step_vectors_by_period),
        cmocka_unit_test(align_nan_vector_latches_without_write),
        cmocka_unit_test(align_duties_by_phase),
        cmocka_unit_test(align_skipped_when_offset_known),
        cmocka_unit_test(align_once_until_encoder_fault),
    };
    return cmocka_run_group_tests_name("align", tests, NULL, NULL);
}
