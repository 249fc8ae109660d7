/* Unit tests for control/pi.c: exact discrete step responses, limits,
 * anti-windup on the realised output versus a naive integrator, pi_apply(). */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>
#include <float.h>

#include "pi.h"

#define TOL 1e-5

/* Kp = 2, Ki = 100 1/s, Ts = 1 ms: Ts*Ki = 0.1 per unit error, k_aw = 0.05. */
static pi_cfg_t cfg_with_limits(float lo, float hi)
{
    pi_cfg_t c = { 2.0f, 100.0f, 1.0e-3f, lo, hi };
    return c;
}

/* Unsaturated, e = 1 from rest: u_k = Kp*1 + k*Ts*Ki*1 = 2 + 0.1 k.
 * Then e = -0.5 after three steps (xi = 0.3): u = -1 + 0.3 = -0.7, xi = 0.25,
 * next u = -1 + 0.25 = -0.75. */
static void unsaturated_step_response_exact(void **state)
{
    (void)state;
    pi_t pi;
    pi_cfg_t c = cfg_with_limits(-10.0f, 10.0f);
    assert_true(pi_init(&pi, &c));
    const double expect[] = { 2.0, 2.1, 2.2, 2.3, 2.4 };
    for (int k = 0; k < 5; k++) {
        assert_float_equal(pi_step(&pi, 1.0f), expect[k], TOL);
    }
    pi_reset(&pi, 0.0f);
    for (int k = 0; k < 3; k++) {
        (void)pi_step(&pi, 1.0f);
    }
    assert_float_equal(pi.xi, 0.3, TOL);
    assert_float_equal(pi_step(&pi, -0.5f), -0.7, TOL);
    assert_float_equal(pi.xi, 0.25, TOL);
    assert_float_equal(pi_step(&pi, -0.5f), -0.75, TOL);
}

/* Output and state stay within the limits for any error sequence. */
static void limits_respected(void **state)
{
    (void)state;
    pi_t pi;
    pi_cfg_t c = cfg_with_limits(-3.0f, 5.0f);
    assert_true(pi_init(&pi, &c));
    const float errs[] = { 1e3f, -1e3f, FLT_MAX, -FLT_MAX, 0.3f, -0.7f, 1e30f, 2.0f, -2.0f };
    for (int rep = 0; rep < 200; rep++) {
        for (size_t i = 0; i < sizeof errs / sizeof errs[0]; i++) {
            float u = pi_step(&pi, errs[i]);
            assert_true(u >= -3.0f && u <= 5.0f);
            assert_true(pi.xi >= -3.0f && pi.xi <= 5.0f);
        }
    }
    /* Saturated hand values: e = 100 -> u = 5; xi = 0.05*5 = 0.25. */
    pi_reset(&pi, 0.0f);
    assert_float_equal(pi_step(&pi, 100.0f), 5.0, TOL);
    assert_float_equal(pi.xi, 0.25, TOL);
    assert_float_equal(pi_step(&pi, -100.0f), -3.0, TOL);
    /* xi = 0.25 + 0.05*(-3 - 0.25) = 0.0875 */
    assert_float_equal(pi.xi, 0.0875, TOL);
}

/*
 * Limits +-1, e = +5 for 1000 steps: the output sits at 1 and
 * xi_k = 1 - 0.95^k (0.05, 0.0975, 0.142625, ... -> 1). Then e = -0.3:
 * u = -0.6 + xi = 0.4, inside the limits at the very first step.
 * A naive integrator (xi += Ts*Ki*e, no anti-windup) reaches xi = 1000*0.5
 * = 500 and then needs -0.6 + 500 - 0.03 k < 1, i.e. k > 16613.3:
 * it leaves the limit only at step 16614.
 */
static void no_windup_after_long_saturation(void **state)
{
    (void)state;
    pi_t pi;
    pi_cfg_t c = cfg_with_limits(-1.0f, 1.0f);
    assert_true(pi_init(&pi, &c));

    double naive_xi = 0.0;
    const double ts_ki = (double)c.Ts_s * (double)c.Ki;
    for (int k = 0; k < 1000; k++) {
        assert_float_equal(pi_step(&pi, 5.0f), 1.0, 0.0);
        if (k == 0) {
            assert_float_equal(pi.xi, 0.05, TOL);
        } else if (k == 2) {
            assert_float_equal(pi.xi, 0.142625, TOL);
        }
        naive_xi += ts_ki * 5.0;
    }
    assert_float_equal(pi.xi, 1.0, 1e-6);
    assert_float_equal(naive_xi, 500.0, 1e-6);

    /* Anti-windup: leaves the limit at the first step after the sign change. */
    const float u0 = pi_step(&pi, -0.3f);
    assert_true(u0 < 1.0f);
    assert_float_equal(u0, 0.4, TOL);

    int naive_leave = -1;
    for (int k = 0; k < 100000; k++) {
        double u = 2.0 * -0.3 + naive_xi;
        if (u < 1.0) {
            naive_leave = k;
            break;
        }
        naive_xi += ts_ki * -0.3;
    }
    assert_int_equal(naive_leave, 16614);
}

/*
 * Outer stage limits further: e = 4 gives u = 8 (limits +-10) and, without
 * pi_apply, xi = 0.05*8 = 0.4. Applied 5 instead: xi = 0.05*5 = 0.25, the
 * next output with e = 4 is 8.25 (8.4 without). Applying twice is the same
 * as once; a value beyond the limits is limited (50 -> 10: xi = 0.5).
 */
static void apply_rebases_on_realised_output(void **state)
{
    (void)state;
    pi_t pi;
    pi_cfg_t c = cfg_with_limits(-10.0f, 10.0f);
    assert_true(pi_init(&pi, &c));
    assert_float_equal(pi_step(&pi, 4.0f), 8.0, TOL);
    assert_float_equal(pi.xi, 0.4, TOL);
    pi_apply(&pi, 5.0f);
    assert_float_equal(pi.xi, 0.25, TOL);
    pi_apply(&pi, 5.0f);
    assert_float_equal(pi.xi, 0.25, TOL);
    assert_float_equal(pi_step(&pi, 4.0f), 8.25, TOL);

    pi_reset(&pi, 0.0f);
    (void)pi_step(&pi, 4.0f);
    pi_apply(&pi, 50.0f);
    assert_float_equal(pi.xi, 0.5, TOL);
    pi_apply(&pi, NAN);
    assert_float_equal(pi.xi, 0.5, TOL);

    /* Applying exactly what pi_step returned changes nothing. */
    pi_reset(&pi, 0.0f);
    float u = pi_step(&pi, 4.0f);
    float xi = pi.xi;
    pi_apply(&pi, u);
    assert_float_equal(pi.xi, xi, 1e-7);
}

/* Non-finite error holds the output (counts as 0). */
static void non_finite_error_counts_as_zero(void **state)
{
    (void)state;
    pi_t pi;
    pi_cfg_t c = cfg_with_limits(-10.0f, 10.0f);
    assert_true(pi_init(&pi, &c));
    for (int k = 0; k < 3; k++) {
        (void)pi_step(&pi, 1.0f);
    }
    assert_float_equal(pi_step(&pi, NAN), 0.3, TOL);
    assert_float_equal(pi_step(&pi, INFINITY), 0.3, TOL);
    assert_float_equal(pi_step(&pi, -INFINITY), 0.3, TOL);
}

/* Reset presets the integral state, limited. */
static void reset_presets_limited_state(void **state)
{
    (void)state;
    pi_t pi;
    pi_cfg_t c = cfg_with_limits(-1.0f, 2.0f);
    assert_true(pi_init(&pi, &c));
    pi_reset(&pi, 0.7f);
    assert_float_equal(pi_step(&pi, 0.0f), 0.7, TOL);
    pi_reset(&pi, 100.0f);
    assert_float_equal(pi_step(&pi, 0.0f), 2.0, TOL);
    pi_reset(&pi, NAN);
    assert_float_equal(pi_step(&pi, 0.0f), -1.0, TOL);
}

/* Invalid configurations are rejected and give a PI whose output is 0. */
static void invalid_cfg_rejected_and_safe(void **state)
{
    (void)state;
    pi_t pi;
    pi_cfg_t bad[6];
    for (int i = 0; i < 6; i++) {
        bad[i] = cfg_with_limits(-1.0f, 1.0f);
    }
    bad[0].Kp = 0.0f;
    bad[1].Ki = -1.0f;
    bad[2].Ts_s = 0.0f;
    bad[3].u_min = 2.0f;
    bad[4].Ki = 3000.0f; /* Ts*Ki = 3 > Kp = 2 */
    bad[5].u_max = NAN;
    for (int i = 0; i < 6; i++) {
        assert_false(pi_init(&pi, &bad[i]));
        assert_true(pi_step(&pi, 5.0f) == 0.0f);
        assert_true(pi_step(&pi, -5.0f) == 0.0f);
    }
    /* Ts*Ki == Kp is the edge that is still allowed. */
    pi_cfg_t edge = cfg_with_limits(-1.0f, 1.0f);
    edge.Ki = 2000.0f;
    assert_true(pi_init(&pi, &edge));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(unsaturated_step_response_exact),
        cmocka_unit_test(limits_respected),
        cmocka_unit_test(no_windup_after_long_saturation),
        cmocka_unit_test(apply_rebases_on_realised_output),
        cmocka_unit_test(non_finite_error_counts_as_zero),
        cmocka_unit_test(reset_presets_limited_state),
        cmocka_unit_test(invalid_cfg_rejected_and_safe),
    };
    return cmocka_run_group_tests_name("pi", tests, NULL, NULL);
}
