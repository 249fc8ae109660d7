/* Unit tests for control/inverr.h: the ripple at each leg's edges against
 * an independent computation (the phase voltage's waveform of the
 * centre-aligned period integrated in double precision), the dead band
 * and the drop by hand, and the stator-frame error against the hard sign
 * where the ripple is small. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>

#include "inverr.h"

#define PI_D 3.141592653589793
#define TS_D 1e-4
#define L_D 15.7e-6  /* the D5065's: a ripple comparable with its current */
#define VDC_D 24.0
#define N_SUB 200000 /* integration steps per period */

/* The ripple of each phase current at its leg's turn-on edge, by
 * integrating (v_xn(t) - u_x)/L over [0, t_x]: legs high over
 * |t - Ts/2| < d Ts/2 (min-max duties), v_xn the leg's voltage minus the
 * three legs' mean. Returns -Delta(t_x) (the current is below its mean
 * there), independent of inverr.h's closed form. */
static void ripple_by_integration(const double u[3], double r[3])
{
    const double hi = fmax(u[0], fmax(u[1], u[2]));
    const double lo = fmin(u[0], fmin(u[1], u[2]));
    const double cm = 0.5 * (hi + lo);
    double d[3];
    double t_on[3];
    double delta[3] = { 0.0, 0.0, 0.0 };
    int done[3] = { 0, 0, 0 };
    for (int x = 0; x < 3; x++) {
        d[x] = 0.5 + (u[x] - cm) / VDC_D;
        t_on[x] = 0.5 * (1.0 - d[x]) * TS_D;
        r[x] = 0.0;
    }
    const double dt = TS_D / N_SUB;
    for (int n = 0; n < N_SUB / 2; n++) {
        const double t = (n + 0.5) * dt;
        double s[3];
        for (int x = 0; x < 3; x++) {
            s[x] = (fabs(t - 0.5 * TS_D) < 0.5 * d[x] * TS_D) ? 1.0 : 0.0;
        }
        const double mean = (s[0] + s[1] + s[2]) / 3.0;
        for (int x = 0; x < 3; x++) {
            if (!done[x] && (t >= t_on[x])) {
                r[x] = -delta[x];
                done[x] = 1;
            }
            delta[x] += (VDC_D * (s[x] - mean) - u[x]) * dt / L_D;
        }
    }
}

static void phase_voltages(double m_V, double ang_rad, double u[3])
{
    u[0] = m_V * cos(ang_rad);
    u[1] = m_V * cos(ang_rad - 2.0 * PI_D / 3.0);
    u[2] = m_V * cos(ang_rad + 2.0 * PI_D / 3.0);
}

/* (8.1) against the integrated waveform at low and high modulation and
 * angles through every sector: within 1 % of the largest ripple. */
static void ripple_matches_the_integrated_waveform(void **state)
{
    (void)state;
    const float k = inverr_k_A_V((float)TS_D, (float)(1.0 / L_D));
    const double mags[3] = { 1.0, 4.0, 11.0 }; /* V: modulation 0.07 .. 0.8 */
    for (int im = 0; im < 3; im++) {
        for (int ia = 0; ia < 12; ia++) {
            double u[3];
            double r_ref[3];
            float u_f[3];
            float r[3];
            phase_voltages(mags[im], 0.1 + ia * PI_D / 6.0, u);
            ripple_by_integration(u, r_ref);
            for (int x = 0; x < 3; x++) {
                u_f[x] = (float)u[x];
            }
            const float r_max = inverr_ripples_A(u_f, (float)(1.0 / VDC_D), k, r);
            const double scale = fmax(r_ref[0], fmax(r_ref[1], r_ref[2]));
            for (int x = 0; x < 3; x++) {
                assert_true(r_ref[x] >= 0.0);
                assert_float_equal(r[x], r_ref[x], 0.01 * scale);
            }
            assert_float_equal(r_max, scale, 0.01 * scale);
        }
    }
}

/* By hand: u = (4, -2, -2) V at 24 V: min-max zero sequence cm = 1 V,
 * d = (0.625, 0.375, 0.375), Ts/(2L) = 3.1847 A/V; leg a (hi):
 * 3.1847 x 4 (1 - 0.625) = 4.777 A; legs b, c (lo, and mid equal to it):
 * 3.1847 x 2 x 0.375 = 2.389 A and 3.1847 ((4 + 2)/3 - 2 (0.5 + 1.5 x 2/24))
 * = 2.389 A. */
static void ripple_by_hand(void **state)
{
    (void)state;
    const float k = inverr_k_A_V((float)TS_D, (float)(1.0 / L_D));
    const float u[3] = { 4.0f, -2.0f, -2.0f };
    float r[3];
    const float r_max = inverr_ripples_A(u, 1.0f / 24.0f, k, r);
    assert_float_equal(k, 3.18471f, 1e-4);
    assert_float_equal(r[0], 4.7771f, 1e-3);
    assert_float_equal(r[1], 2.3885f, 1e-3);
    assert_float_equal(r[2], 2.3885f, 1e-3);
    assert_float_equal(r_max, 4.7771f, 1e-3);
}

/* A leg: beyond the ripple both the dead band and the drop against the
 * current; between r/2 and r the drop only (the dead bands of the two
 * edges cancel); below r/2 nothing; at i = 0 nothing. */
static void leg_dead_zone_and_drop(void **state)
{
    (void)state;
    const float dead = 0.24f;
    const float drop = 0.1f;
    assert_float_equal(inverr_leg_V(3.0f, 2.0f, dead, drop), -(dead + drop), 1e-7);
    assert_float_equal(inverr_leg_V(-3.0f, 2.0f, dead, drop), dead + drop, 1e-7);
    assert_float_equal(inverr_leg_V(1.5f, 2.0f, dead, drop), -drop, 1e-7);
    assert_float_equal(inverr_leg_V(-1.5f, 2.0f, dead, drop), drop, 1e-7);
    assert_float_equal(inverr_leg_V(0.9f, 2.0f, dead, drop), 0.0f, 1e-7);
    assert_float_equal(inverr_leg_V(0.0f, 0.0f, dead, drop), 0.0f, 1e-7);
    assert_float_equal(inverr_leg_V(0.1f, 0.0f, dead, drop), -(dead + drop), 1e-7);
}

/* No ripple (k = 0): the hard sign. i = (1, -0.5, -0.5) A: legs (-dv, dv,
 * dv), alpha = (2/3)(-dv - dv) = -(4/3) dv, beta 0; the largest ripple 0. */
static void no_ripple_is_the_hard_sign(void **state)
{
    (void)state;
    const abc_t i = { 1.0f, -0.5f, -0.5f };
    const ab_t u = { 5.0f, 3.0f };
    float r_max = -1.0f;
    const ab_t e = inverr_error_V(i, u, 1.0f / 24.0f, 0.0f, 0.24f, 0.1f, &r_max);
    assert_float_equal(e.a, -(4.0f / 3.0f) * 0.34f, 1e-6);
    assert_float_equal(e.b, 0.0f, 1e-6);
    assert_float_equal(r_max, 0.0f, 1e-7);
}

/* The ripple of ripple_by_hand (4.78, 2.39, 2.39 A) above twice each
 * leg's current, i = (0.5, -0.25, -0.25) A: every leg's current crosses
 * zero between its edges, neither the dead bands nor the drop are left:
 * e = 0. */
static void ripple_above_the_current_cancels_the_error(void **state)
{
    (void)state;
    const float k = inverr_k_A_V((float)TS_D, (float)(1.0 / L_D));
    const abc_t i = { 0.5f, -0.25f, -0.25f };
    const ab_t u = { 4.0f, 0.0f }; /* phases (4, -2, -2) V */
    float r_max = 0.0f;
    const ab_t e = inverr_error_V(i, u, 1.0f / 24.0f, k, 0.24f, 0.1f, &r_max);
    assert_float_equal(e.a, 0.0f, 1e-7);
    assert_float_equal(e.b, 0.0f, 1e-7);
    assert_float_equal(r_max, 4.7771f, 1e-3);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(ripple_matches_the_integrated_waveform),
        cmocka_unit_test(ripple_by_hand),
        cmocka_unit_test(leg_dead_zone_and_drop),
        cmocka_unit_test(no_ripple_is_the_hard_sign),
        cmocka_unit_test(ripple_above_the_current_cancels_the_error),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
