/* Unit tests for control/mtpa.h: Table I hand values (reference computed in
 * double), symmetry in the torque sign, guards. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>
#include <float.h>

#include "mtpa.h"

#define TOL 1e-6

/* Table I: L = 0.011 H, psi_f = 0.24 Wb, p = 3. */
#define L_TAB 0.011f
#define PSI_F_TAB 0.24f
#define P_TAB 3u

static double psi_ref_double(double L, double psi_f, double p, double te)
{
    double psi_q = L * te / (1.5 * p * psi_f);
    return sqrt(psi_f * psi_f + psi_q * psi_q);
}

/*
 * Te = 0: psi_s = psi_f = 0.24 Wb.
 * Te = 4: iq = 4/(1.5*3*0.24) = 3.7037 A, L*iq = 0.040741 Wb,
 *         psi_s = sqrt(0.0576 + 0.0016598) = 0.2434334 Wb.
 * Te = 6: iq = 5.5556 A, L*iq = 0.061111 Wb, psi_s = 0.2476582 Wb.
 */
static void table1_hand_values(void **state)
{
    (void)state;
    assert_float_equal(mtpa_psi_s_ref(L_TAB, PSI_F_TAB, P_TAB, 0.0f), 0.24, TOL);
    assert_float_equal(mtpa_psi_s_ref(L_TAB, PSI_F_TAB, P_TAB, 4.0f), 0.24343337477861215, TOL);
    assert_float_equal(mtpa_psi_s_ref(L_TAB, PSI_F_TAB, P_TAB, 6.0f), 0.24765816744301927, TOL);
    for (int k = -40; k <= 40; k++) {
        double te = 0.5 * k;
        assert_float_equal(mtpa_psi_s_ref(L_TAB, PSI_F_TAB, P_TAB, (float)te),
                           psi_ref_double(0.011, 0.24, 3.0, te), TOL);
    }
}

/* Only |Te| matters. */
static void symmetric_in_torque_sign(void **state)
{
    (void)state;
    for (int k = 0; k <= 40; k++) {
        float te = 0.37f * (float)k;
        float pos = mtpa_psi_s_ref(L_TAB, PSI_F_TAB, P_TAB, te);
        float neg = mtpa_psi_s_ref(L_TAB, PSI_F_TAB, P_TAB, -te);
        assert_float_equal(pos, neg, 0.0);
        assert_true(pos >= PSI_F_TAB);
    }
}

/* Online estimates: a different L and psi_f change the result as the formula says. */
static void follows_estimated_parameters(void **state)
{
    (void)state;
    assert_float_equal(mtpa_psi_s_ref(0.0088f, 0.2f, P_TAB, 6.0f),
                       psi_ref_double((double)0.0088f, (double)0.2f, 3.0, 6.0), TOL);
    /* Pole pairs 4 instead of 3 lowers the torque term. */
    assert_float_equal(mtpa_psi_s_ref(L_TAB, PSI_F_TAB, 4u, 6.0f),
                       psi_ref_double(0.011, 0.24, 4.0, 6.0), TOL);
    /* Pole pairs 0 counts as 1. */
    assert_float_equal(mtpa_psi_s_ref(L_TAB, PSI_F_TAB, 0u, 6.0f),
                       psi_ref_double(0.011, 0.24, 1.0, 6.0), TOL);
}

/*
 * psi_f at or below MTPA_PSI_F_MIN_WB (1 mWb), negative or NaN, is replaced
 * by 1 mWb: with L = 0.011 H, p = 3, Te = 4 N*m, psi_q = 0.044/0.0045 =
 * 9.7778 Wb, psi_s = sqrt(1e-6 + 95.605) = 9.77778 Wb. Finite, never NaN.
 */
static void small_psi_f_guarded(void **state)
{
    (void)state;
    const float bad[] = { 0.0f, -0.24f, 1e-9f, MTPA_PSI_F_MIN_WB, NAN, -INFINITY };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        assert_float_equal(mtpa_psi_s_ref(L_TAB, bad[i], P_TAB, 4.0f), 9.77777782891414, 1e-4);
        assert_float_equal(mtpa_psi_s_ref(L_TAB, bad[i], P_TAB, 0.0f), (double)MTPA_PSI_F_MIN_WB,
                           1e-9);
    }
}

/* Non-finite or absurd inputs: result finite and within [min, max]. */
static void output_saturated(void **state)
{
    (void)state;
    /* NaN torque or inductance: torque term dropped, psi_f returned. */
    assert_float_equal(mtpa_psi_s_ref(L_TAB, PSI_F_TAB, P_TAB, NAN), 0.24, TOL);
    assert_float_equal(mtpa_psi_s_ref(NAN, PSI_F_TAB, P_TAB, 4.0f), 0.24, TOL);
    /* Infinite or huge torque: the ceiling. */
    assert_float_equal(mtpa_psi_s_ref(L_TAB, PSI_F_TAB, P_TAB, INFINITY), MTPA_PSI_MAX_WB, 0.0);
    assert_float_equal(mtpa_psi_s_ref(L_TAB, PSI_F_TAB, P_TAB, -FLT_MAX), MTPA_PSI_MAX_WB, 0.0);
    assert_float_equal(mtpa_psi_s_ref(FLT_MAX, PSI_F_TAB, P_TAB, FLT_MAX), MTPA_PSI_MAX_WB, 0.0);
    assert_float_equal(mtpa_psi_s_ref(L_TAB, 1e30f, P_TAB, 0.0f), MTPA_PSI_MAX_WB, 0.0);
    /* Negative L (a bad estimate) acts through its magnitude. */
    assert_float_equal(mtpa_psi_s_ref(-L_TAB, PSI_F_TAB, P_TAB, 4.0f), 0.24343337477861215, TOL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(table1_hand_values),
        cmocka_unit_test(symmetric_in_torque_sign),
        cmocka_unit_test(follows_estimated_parameters),
        cmocka_unit_test(small_psi_f_guarded),
        cmocka_unit_test(output_saturated),
    };
    return cmocka_run_group_tests_name("mtpa", tests, NULL, NULL);
}
