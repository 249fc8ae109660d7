/* Unit tests for control/clarke_park.h: hand-derived values and round trips. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>

#include "clarke_park.h"

#define TOL 1e-6

/* Balanced set ia = cos(x), ib = cos(x - 120 deg) must give alpha = cos x, beta = sin x. */
static void clarke_of_balanced_set_is_unit_phasor(void **state)
{
    (void)state;
    for (int k = 0; k < 36; k++) {
        float x = (float)k * (MATHX_TWO_PI_F / 36.0f);
        ab_t ab = clarke_2ph(cosf(x), cosf(x - MATHX_TWO_PI_F / 3.0f));
        assert_float_equal(ab.a, cos((double)x), TOL);
        assert_float_equal(ab.b, sin((double)x), TOL);
    }
}

/* Hand value: ia = 1, ib = 0 (so ic = -1) gives alpha = 1, beta = 1/sqrt(3). */
static void clarke_hand_value(void **state)
{
    (void)state;
    ab_t ab = clarke_2ph(1.0f, 0.0f);
    assert_float_equal(ab.a, 1.0, TOL);
    assert_float_equal(ab.b, 0.5773502691896258, TOL);
}

/* At theta = 90 deg the d axis lies on beta: (alpha, beta) = (0, 1) is pure d. */
static void park_at_quarter_turn_hand_value(void **state)
{
    (void)state;
    ab_t x = { 0.0f, 1.0f };
    dq_t dq = park(x, 1.0f, 0.0f);
    assert_float_equal(dq.d, 1.0, TOL);
    assert_float_equal(dq.q, 0.0, TOL);
    x.a = 1.0f;
    x.b = 0.0f;
    dq = park(x, 1.0f, 0.0f);
    assert_float_equal(dq.d, 0.0, TOL);
    assert_float_equal(dq.q, -1.0, TOL);
}

/* park_inv(park(x)) == x for angles around the circle. */
static void park_round_trip_is_identity(void **state)
{
    (void)state;
    for (int k = -20; k <= 20; k++) {
        float th = (float)k * 0.37f;
        float s;
        float c;
        mathx_sincosf(th, &s, &c);
        ab_t x = { 3.0f - 0.1f * (float)k, -1.5f + 0.2f * (float)k };
        ab_t y = park_inv(park(x, s, c), s, c);
        assert_float_equal(y.a, x.a, 1e-5 * fabs((double)x.a) + TOL);
        assert_float_equal(y.b, x.b, 1e-5 * fabs((double)x.b) + TOL);
    }
}

/* Park conserves the vector length (rotation). */
static void park_preserves_magnitude(void **state)
{
    (void)state;
    ab_t x = { 3.0f, 4.0f };
    float s;
    float c;
    mathx_sincosf(1.234f, &s, &c);
    dq_t dq = park(x, s, c);
    assert_float_equal(sqrt((double)(dq.d * dq.d + dq.q * dq.q)), 5.0, 1e-5);
}

/* Inverse Clarke by hand (alpha alone: a = 1, b = c = -1/2; beta alone:
 * b, c = +/- sqrt(3)/2), Clarke of three phases back, a zero sequence
 * dropping out. */
static void clarke_inverse_and_three_phase(void **state)
{
    (void)state;
    const ab_t alpha = { 1.0f, 0.0f };
    const ab_t beta = { 0.0f, 1.0f };
    abc_t p = clarke_inv(alpha);
    assert_float_equal(p.a, 1.0, 1e-7);
    assert_float_equal(p.b, -0.5, 1e-7);
    assert_float_equal(p.c, -0.5, 1e-7);
    p = clarke_inv(beta);
    assert_float_equal(p.a, 0.0, 1e-7);
    assert_float_equal(p.b, 0.8660254037844386, 1e-7);
    assert_float_equal(p.c, -0.8660254037844386, 1e-7);
    const ab_t x = { 2.5f, -1.25f };
    p = clarke_inv(x);
    const ab_t back = clarke_3ph(p.a + 7.0f, p.b + 7.0f, p.c + 7.0f); /* + a zero sequence */
    assert_float_equal(back.a, 2.5, 1e-5);
    assert_float_equal(back.b, -1.25, 1e-5);
    assert_float_equal(p.a + p.b + p.c, 0.0, 1e-6);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(clarke_inverse_and_three_phase),
        cmocka_unit_test(clarke_of_balanced_set_is_unit_phasor),
        cmocka_unit_test(clarke_hand_value),
        cmocka_unit_test(park_at_quarter_turn_hand_value),
        cmocka_unit_test(park_round_trip_is_identity),
        cmocka_unit_test(park_preserves_magnitude),
    };
    return cmocka_run_group_tests_name("clarke_park", tests, NULL, NULL);
}
