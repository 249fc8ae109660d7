/* Unit tests for control/svpwm.c: hand values, linear-region accuracy,
 * hexagon limiting, and robustness to extreme and non-finite inputs.
 * The reference computations are independent: double precision, phase
 * voltages from the duties, amplitude-invariant Clarke. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>
#include <float.h>

#include "svpwm.h"

#define TOL 1e-6
#define PI_D 3.141592653589793
#define SQRT3_D 1.7320508075688772

/* Alpha-beta of the average phase voltages the duties produce at vdc. */
static void realised_from_duties(const svpwm_duty_t *d, double vdc, double *a, double *b)
{
    double va = (double)d->a * vdc;
    double vb = (double)d->b * vdc;
    double vc = (double)d->c * vdc;
    double mean = (va + vb + vc) / 3.0;
    va -= mean;
    vb -= mean;
    vc -= mean;
    *a = (2.0 * va - vb - vc) / 3.0;
    *b = (vb - vc) / SQRT3_D;
}

static void assert_duty_in_range(const svpwm_duty_t *d)
{
    assert_true(isfinite(d->a) && isfinite(d->b) && isfinite(d->c));
    assert_true(d->a >= 0.0f && d->a <= 1.0f);
    assert_true(d->b >= 0.0f && d->b <= 1.0f);
    assert_true(d->c >= 0.0f && d->c <= 1.0f);
}

/*
 * u = (Vdc/sqrt3, 0): va = Vdc/sqrt3, vb = vc = -Vdc/(2 sqrt3). Zero
 * sequence -(max+min)/2 = -Vdc/(4 sqrt3), so va + v0 = sqrt3/4 Vdc and
 * vb + v0 = -sqrt3/4 Vdc: duties 0.5 +- sqrt3/4 = (0.9330127, 0.0669873, 0.0669873).
 */
static void hand_value_inscribed_circle_on_alpha(void **state)
{
    (void)state;
    const float vdc = 600.0f;
    ab_t u = { vdc * 0.5773502691896258f, 0.0f };
    svpwm_duty_t d;
    ab_t ur;
    assert_int_equal(svpwm_duty(u, vdc, &d, &ur), SVPWM_OK);
    assert_float_equal(d.a, 0.9330127018922193, TOL);
    assert_float_equal(d.b, 0.0669872981077807, TOL);
    assert_float_equal(d.c, 0.0669872981077807, TOL);
    assert_float_equal(ur.a, 346.41016151377545, 1e-3);
    assert_float_equal(ur.b, 0.0, 1e-3);
}

/*
 * u = (0.6 Vdc, 0), outside the inscribed circle (0.577 Vdc) but inside
 * the hexagon vertex (0.667 Vdc): va = 0.6, vb = vc = -0.3 (x Vdc), v0 = -0.15,
 * duties (0.95, 0.05, 0.05), realised exactly, no saturation flag.
 */
static void hand_value_between_circle_and_vertex_is_exact(void **state)
{
    (void)state;
    const float vdc = 100.0f;
    ab_t u = { 60.0f, 0.0f };
    svpwm_duty_t d;
    ab_t ur;
    assert_int_equal(svpwm_duty(u, vdc, &d, &ur), SVPWM_OK);
    assert_float_equal(d.a, 0.95, TOL);
    assert_float_equal(d.b, 0.05, TOL);
    assert_float_equal(d.c, 0.05, TOL);
    assert_float_equal(ur.a, 60.0, 1e-4);
    assert_float_equal(ur.b, 0.0, 1e-4);
}

/*
 * u = (0, Vdc/sqrt3) lies where the circle touches the hexagon side:
 * va = 0, vb = Vdc/2, vc = -Vdc/2, v0 = 0: duties (0.5, 1, 0).
 */
static void hand_value_on_hexagon_side(void **state)
{
    (void)state;
    const float vdc = 48.0f;
    ab_t u = { 0.0f, vdc * 0.5773502691896258f };
    svpwm_duty_t d;
    ab_t ur;
    (void)svpwm_duty(u, vdc, &d, &ur);
    assert_float_equal(d.a, 0.5, TOL);
    assert_float_equal(d.b, 1.0, TOL);
    assert_float_equal(d.c, 0.0, TOL);
}

/*
 * u = (Vdc, 0): spread 1.5 Vdc, scaled by 2/3 onto the vertex (2/3 Vdc, 0):
 * va = 2/3, vb = vc = -1/3 (x Vdc), v0 = -1/6: duties (1, 0, 0).
 */
static void hand_value_saturated_onto_vertex(void **state)
{
    (void)state;
    const float vdc = 300.0f;
    ab_t u = { 300.0f, 0.0f };
    svpwm_duty_t d;
    ab_t ur;
    assert_int_equal(svpwm_duty(u, vdc, &d, &ur), SVPWM_SATURATED);
    assert_float_equal(d.a, 1.0, TOL);
    assert_float_equal(d.b, 0.0, TOL);
    assert_float_equal(d.c, 0.0, TOL);
    assert_float_equal(ur.a, 200.0, 1e-3);
    assert_float_equal(ur.b, 0.0, 1e-3);
}

/* Inside the inscribed circle the phase-voltage average reproduces the command within 0.1 %. */
static void linear_region_reproduces_command(void **state)
{
    (void)state;
    const float vdcs[] = { 24.0f, 311.0f, 600.0f };
    for (size_t v = 0; v < sizeof vdcs / sizeof vdcs[0]; v++) {
        const double vdc = (double)vdcs[v];
        for (int m = 0; m <= 10; m++) {
            const double mag = (m == 10 ? 0.999 : 0.1 * m) * vdc / SQRT3_D;
            for (int k = 0; k < 72; k++) {
                const double th = k * (2.0 * PI_D / 72.0);
                ab_t u = { (float)(mag * cos(th)), (float)(mag * sin(th)) };
                svpwm_duty_t d;
                ab_t ur;
                assert_int_equal(svpwm_duty(u, vdcs[v], &d, &ur), SVPWM_OK);
                assert_duty_in_range(&d);
                double a;
                double b;
                realised_from_duties(&d, vdc, &a, &b);
                const double tol = 1e-3 * mag + 1e-6 * vdc;
                assert_float_equal(a, (double)u.a, tol);
                assert_float_equal(b, (double)u.b, tol);
                assert_float_equal((double)ur.a, (double)u.a, tol);
                assert_float_equal((double)ur.b, (double)u.b, tol);
                /* Min-max injection centres the legs: max + min duty == 1. */
                double hi = fmax(fmax(d.a, d.b), d.c);
                double lo = fmin(fmin(d.a, d.b), d.c);
                assert_float_equal(hi + lo, 1.0, TOL);
            }
        }
    }
}

/* Hexagon radius at angle th for a bus of vdc: inscribed radius over cos of
 * the angle to the nearest side normal (normals at 30 deg + k*60 deg). */
static double hexagon_radius(double th, double vdc)
{
    double phi = fmod(th, PI_D / 3.0);
    if (phi < 0.0) {
        phi += PI_D / 3.0;
    }
    phi -= PI_D / 6.0;
    return vdc / SQRT3_D / cos(phi);
}

/* Beyond the hexagon: on the boundary, same angle, flag set, out param consistent. */
static void overmodulation_lands_on_hexagon_with_same_angle(void **state)
{
    (void)state;
    const double vdc = 540.0;
    const double mags[] = { 0.7, 1.0, 2.0, 10.0, 1e3, 1e6 };
    for (size_t m = 0; m < sizeof mags / sizeof mags[0]; m++) {
        for (int k = 0; k < 72; k++) {
            const double th = k * (2.0 * PI_D / 72.0) + 0.01;
            ab_t u = { (float)(mags[m] * vdc * cos(th)), (float)(mags[m] * vdc * sin(th)) };
            svpwm_duty_t d;
            ab_t ur;
            assert_int_equal(svpwm_duty(u, (float)vdc, &d, &ur), SVPWM_SATURATED);
            assert_duty_in_range(&d);
            double hi = fmax(fmax(d.a, d.b), d.c);
            double lo = fmin(fmin(d.a, d.b), d.c);
            assert_float_equal(hi - lo, 1.0, TOL);
            double a;
            double b;
            realised_from_duties(&d, vdc, &a, &b);
            double mag = sqrt(a * a + b * b);
            assert_float_equal(mag, hexagon_radius(th, vdc), 1e-5 * vdc);
            double dth = remainder(atan2(b, a) - atan2((double)u.b, (double)u.a), 2.0 * PI_D);
            assert_float_equal(dth, 0.0, 1e-5);
            assert_float_equal((double)ur.a, a, 1e-5 * vdc);
            assert_float_equal((double)ur.b, b, 1e-5 * vdc);
        }
    }
}

/* Every finite input, however extreme, gives finite duties in [0,1]. */
static void extreme_finite_inputs_stay_bounded(void **state)
{
    (void)state;
    const float us[] = { 0.0f, -0.0f, 1e-45f, -1e-45f, FLT_MIN, 1.0f, -1.0f, 1e30f, -1e30f,
                         FLT_MAX, -FLT_MAX };
    const float vdcs[] = { SVPWM_VDC_MIN_V, 1.0f, 600.0f, 1e30f, FLT_MAX };
    const size_t nu = sizeof us / sizeof us[0];
    for (size_t v = 0; v < sizeof vdcs / sizeof vdcs[0]; v++) {
        for (size_t i = 0; i < nu; i++) {
            for (size_t j = 0; j < nu; j++) {
                ab_t u = { us[i], us[j] };
                svpwm_duty_t d;
                ab_t ur;
                uint16_t f = svpwm_duty(u, vdcs[v], &d, &ur);
                assert_int_equal(f & SVPWM_INVALID_INPUT, 0);
                assert_duty_in_range(&d);
                assert_true(isfinite(ur.a) && isfinite(ur.b));
            }
        }
    }
}

static void assert_invalid(ab_t u, float vdc)
{
    svpwm_duty_t d = { -1.0f, -1.0f, -1.0f };
    ab_t ur = { NAN, NAN };
    assert_int_equal(svpwm_duty(u, vdc, &d, &ur), SVPWM_INVALID_INPUT);
    assert_true(d.a == 0.5f && d.b == 0.5f && d.c == 0.5f);
    assert_true(ur.a == 0.0f && ur.b == 0.0f);
}

/* NaN/Inf anywhere, or a bus below the minimum, gives 50 % duties and the flag. */
static void invalid_inputs_give_half_duty_and_flag(void **state)
{
    (void)state;
    const float bad[] = { NAN, INFINITY, -INFINITY };
    for (size_t i = 0; i < 3; i++) {
        assert_invalid((ab_t){ bad[i], 1.0f }, 600.0f);
        assert_invalid((ab_t){ 1.0f, bad[i] }, 600.0f);
        assert_invalid((ab_t){ 1.0f, 1.0f }, bad[i]);
    }
    const float low_vdc[] = { 0.0f, -0.0f, -600.0f, 1e-45f, 0.5f * SVPWM_VDC_MIN_V, -FLT_MAX };
    for (size_t i = 0; i < sizeof low_vdc / sizeof low_vdc[0]; i++) {
        assert_invalid((ab_t){ 1.0f, -2.0f }, low_vdc[i]);
    }
}

/* Zero command: all legs at 50 %. */
static void zero_command_is_half_duty(void **state)
{
    (void)state;
    svpwm_duty_t d;
    ab_t ur;
    assert_int_equal(svpwm_duty((ab_t){ 0.0f, 0.0f }, 600.0f, &d, &ur), SVPWM_OK);
    assert_true(d.a == 0.5f && d.b == 0.5f && d.c == 0.5f);
    assert_true(ur.a == 0.0f && ur.b == 0.0f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(hand_value_inscribed_circle_on_alpha),
        cmocka_unit_test(hand_value_between_circle_and_vertex_is_exact),
        cmocka_unit_test(hand_value_on_hexagon_side),
        cmocka_unit_test(hand_value_saturated_onto_vertex),
        cmocka_unit_test(linear_region_reproduces_command),
        cmocka_unit_test(overmodulation_lands_on_hexagon_with_same_angle),
        cmocka_unit_test(extreme_finite_inputs_stay_bounded),
        cmocka_unit_test(invalid_inputs_give_half_duty_and_flag),
        cmocka_unit_test(zero_command_is_half_duty),
    };
    return cmocka_run_group_tests_name("svpwm", tests, NULL, NULL);
}
