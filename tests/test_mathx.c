/* Unit tests for control/mathx.h: the guards the control code relies on. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>
#include <float.h>

#include "mathx.h"

#define TOL 1e-6

/* NaN is not >= lo, so it takes the lo branch; the ends and the inside pass through. */
static void clamp_nan_maps_to_lo(void **state)
{
    (void)state;
    assert_true(mathx_clampf(NAN, -2.0f, 3.0f) == -2.0f);
    assert_true(mathx_clampf(-NAN, -2.0f, 3.0f) == -2.0f);
    assert_true(mathx_clampf(INFINITY, -2.0f, 3.0f) == 3.0f);
    assert_true(mathx_clampf(-INFINITY, -2.0f, 3.0f) == -2.0f);
    assert_true(mathx_clampf(3.5f, -2.0f, 3.0f) == 3.0f);
    assert_true(mathx_clampf(-2.5f, -2.0f, 3.0f) == -2.0f);
    assert_true(mathx_clampf(1.25f, -2.0f, 3.0f) == 1.25f);
    assert_true(mathx_clampf(3.0f, -2.0f, 3.0f) == 3.0f);
}

/* Negative, -0, NaN give 0; positive values match libm. */
static void sqrt_of_negative_is_zero(void **state)
{
    (void)state;
    assert_true(mathx_sqrtf(-1.0f) == 0.0f);
    assert_true(mathx_sqrtf(-FLT_MIN) == 0.0f);
    assert_true(mathx_sqrtf(-0.0f) == 0.0f);
    assert_true(mathx_sqrtf(NAN) == 0.0f);
    assert_float_equal(mathx_sqrtf(2.0f), 1.4142135623730951, TOL);
    assert_float_equal(mathx_sqrtf(0.0576f), 0.24, TOL);
}

/* Results must lie in [0, 2*pi) and equal the input modulo 2*pi. */
static void wrap_2pi_both_ends(void **state)
{
    (void)state;
    const double two_pi = 6.283185307179586;
    /* Exactly 2*pi (float) is angle 0. */
    assert_true(mathx_wrap_2pi(MATHX_TWO_PI_F) == 0.0f);
    assert_true(mathx_wrap_2pi(0.0f) == 0.0f);
    /* A tiny negative angle rounds onto 2*pi in float: must come out as 0, not 2*pi. */
    float w = mathx_wrap_2pi(-1e-9f);
    assert_true(w >= 0.0f && w < MATHX_TWO_PI_F);
    /* Just below zero by a representable amount stays just below 2*pi. */
    w = mathx_wrap_2pi(-0.001f);
    assert_float_equal(w, two_pi - 0.001, 1e-6);
    /* Several turns either way. */
    assert_float_equal(mathx_wrap_2pi(7.0f), 7.0 - two_pi, 1e-6);
    assert_float_equal(mathx_wrap_2pi(-7.0f), 2.0 * two_pi - 7.0, 1e-6);
    assert_float_equal(mathx_wrap_2pi(20.0f), 20.0 - 3.0 * two_pi, 1e-5);
    assert_float_equal(mathx_wrap_2pi(-20.0f), 4.0 * two_pi - 20.0, 1e-5);
    /* Sweep: in range and congruent to the input. */
    for (int k = -400; k <= 400; k++) {
        float x = (float)k * 0.0917f;
        w = mathx_wrap_2pi(x);
        assert_true(w >= 0.0f && w < MATHX_TWO_PI_F);
        double turns = ((double)x - (double)w) / two_pi;
        assert_float_equal(turns, round(turns), 1e-5);
    }
}

/* Non-finite and huge inputs: bounded time, result in range. */
static void wrap_2pi_non_finite_and_huge(void **state)
{
    (void)state;
    assert_true(mathx_wrap_2pi(NAN) == 0.0f);
    assert_true(mathx_wrap_2pi(INFINITY) == 0.0f);
    assert_true(mathx_wrap_2pi(-INFINITY) == 0.0f);
    const float big[] = { 1e30f, -1e30f, FLT_MAX, -FLT_MAX, 1e7f, -1e7f };
    for (size_t i = 0; i < sizeof big / sizeof big[0]; i++) {
        float w = mathx_wrap_2pi(big[i]);
        assert_true(w >= 0.0f && w < MATHX_TWO_PI_F);
    }
}

/* sin/cos against double libm over several turns. */
static void sincos_matches_libm(void **state)
{
    (void)state;
    for (int k = -200; k <= 200; k++) {
        float th = (float)k * 0.0713f;
        float s;
        float c;
        mathx_sincosf(th, &s, &c);
        assert_float_equal(s, sin((double)th), 2e-6);
        assert_float_equal(c, cos((double)th), 2e-6);
    }
}

/* atan2 quadrants and fabs, against hand values. */
static void atan2_and_fabs_hand_values(void **state)
{
    (void)state;
    assert_float_equal(mathx_atan2f(1.0f, 1.0f), 0.7853981633974483, TOL);
    assert_float_equal(mathx_atan2f(1.0f, -1.0f), 2.356194490192345, TOL);
    assert_float_equal(mathx_atan2f(-1.0f, -1.0f), -2.356194490192345, TOL);
    assert_float_equal(mathx_atan2f(0.0f, -1.0f), 3.141592653589793, TOL);
    assert_true(mathx_fabsf(-2.5f) == 2.5f);
    assert_true(mathx_fabsf(2.5f) == 2.5f);
    assert_true(mathx_isfinitef(FLT_MAX));
    assert_false(mathx_isfinitef(NAN));
    assert_false(mathx_isfinitef(-INFINITY));
    assert_true(mathx_isfinitef(-FLT_MAX));
    assert_true(mathx_isfinitef(FLT_MIN / 4.0f));            /* denormal */
    assert_true(mathx_isfinitef(-0.0f));
    assert_false(mathx_isfinitef(-NAN));
}

/* mathx_umod_u32 against the C operator (independent): the in-range fast
 * path, exact multiples, the 32-bit ends, and divisors above 2^31 where the
 * shift-and-subtract carries out of 32 bits. */
static void umod_matches_the_c_operator(void **state)
{
    (void)state;
    const uint32_t m[] = { 1u, 2u, 3u, 7u, 10000u, 65536u, 16777216u, 0x7FFFFFFFu,
                           0x80000000u, 0x80000001u, 0xFFFFFFFEu, 0xFFFFFFFFu };
    const uint32_t x[] = { 0u, 1u, 9999u, 10000u, 10001u, 39999u, 12345678u, 0x7FFFFFFFu,
                           0x80000000u, 0xC0000001u, 0xFFFFFFFEu, 0xFFFFFFFFu };
    for (size_t i = 0; i < sizeof m / sizeof m[0]; i++) {
        for (size_t j = 0; j < sizeof x / sizeof x[0]; j++) {
            assert_int_equal(mathx_umod_u32(x[j], m[i]), x[j] % m[i]);
        }
    }
    /* A pseudo-random sweep (LCG) over both arguments. */
    uint32_t s = 12345u;
    for (int n = 0; n < 20000; n++) {
        s = s * 1664525u + 1013904223u;
        const uint32_t a = s;
        s = s * 1664525u + 1013904223u;
        const uint32_t b = (s >> (s & 31u)) | 1u;
        assert_int_equal(mathx_umod_u32(a, b), a % b);
    }
    assert_int_equal(mathx_umod_u32(5u, 0u), 0u);            /* defined: no trap */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(clamp_nan_maps_to_lo),
        cmocka_unit_test(sqrt_of_negative_is_zero),
        cmocka_unit_test(wrap_2pi_both_ends),
        cmocka_unit_test(wrap_2pi_non_finite_and_huge),
        cmocka_unit_test(sincos_matches_libm),
        cmocka_unit_test(atan2_and_fabs_hand_values),
        cmocka_unit_test(umod_matches_the_c_operator),
    };
    return cmocka_run_group_tests_name("mathx", tests, NULL, NULL);
}
