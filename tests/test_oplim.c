/* Unit tests for control/oplim: torque and flux targets inside the current
 * limit (MTPA and weakened flux) and the voltage-feedback weakening loop.
 * Expectations from the machine equations (eq. 11, 12) in double: the
 * current the deadbeat step aims at, id = (psi_d - psi_f)/L with
 * psi_d = sqrt(psi_s*^2 - psi_q*^2), iq = psi_q* / L, psi_q* = L Te* / kt. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>

#include "oplim.h"

#define TS    1e-4
#define R0    3.0
#define L0    0.011
#define PSI0  0.24
#define PP    3u
#define KT0   (1.5 * 3.0 * PSI0)
#define I_LIM 12.0
#define RATE  5.0
#define HYST  0.97

static dbdtc_t db;
static oplim_t o;

static void setup(void)
{
    const dbdtc_cfg_t c = { (float)TS, PP, (float)R0, (float)L0, (float)PSI0, 70.0f, 3000.0f, 400.0f, 12.0f, 1.0f };
    assert_true(dbdtc_init(&db, &c));
    oplim_init(&o, (float)TS, (float)RATE, (float)HYST);
}

/* |i| of the current the targets aim at. */
static double i_aimed(oplim_out_t t)
{
    const double psiq = L0 * (double)t.te_Nm / KT0;
    const double psid = sqrt((double)t.psi_Wb * t.psi_Wb - psiq * psiq);
    const double id = (psid - PSI0) / L0;
    const double iq = psiq / L0;
    return sqrt(id * id + iq * iq);
}

static void mtpa_below_the_limits(void **state)
{
    (void)state;
    setup();
    const oplim_out_t t = oplim_targets(&o, &db.par, (float)I_LIM, 6.0f);
    const double iq = 6.0 / KT0;
    assert_float_equal(t.te_Nm, 6.0f, 1e-6f);
    assert_float_equal(t.psi_Wb, (float)sqrt(PSI0 * PSI0 + L0 * L0 * iq * iq), 1e-6f);
    assert_float_equal((float)i_aimed(t), (float)iq, 1e-3f); /* id = 0 */
}

/* 20 N m asked: kt i_lim = 1.08 x 12 = 12.96 N m, |i| = 12 A on q. */
static void current_limit_at_mtpa(void **state)
{
    (void)state;
    setup();
    const oplim_out_t t = oplim_targets(&o, &db.par, (float)I_LIM, -20.0f);
    assert_float_equal(t.te_Nm, (float)(-KT0 * I_LIM), 1e-4f);
    assert_float_equal((float)i_aimed(t), (float)I_LIM, 1e-3f);
}

/* The loop: n periods of too much voltage lower psi_s* by n rate Ts; at
 * that flux the torque is cut so that the aimed current is i_lim, with
 * id < 0. */
static void weakening_keeps_current_at_limit(void **state)
{
    const dq_t u_big = { 0.0f, 200.0f };
    const int n = 100;                    /* 100 x 5e-4 Wb = 0.05 Wb */
    (void)state;
    setup();
    (void)oplim_targets(&o, &db.par, (float)I_LIM, 12.0f);
    for (int k = 0; k < n; k++) {
        oplim_fw_update(&o, u_big, 180.0f);
    }
    assert_float_equal(o.dpsi_Wb, (float)(n * RATE * TS), 1e-5f);
    const oplim_out_t t = oplim_targets(&o, &db.par, (float)I_LIM, 12.0f);
    const double iq = 12.0 / KT0;
    const double psi_mtpa = sqrt(PSI0 * PSI0 + L0 * L0 * iq * iq);
    assert_float_equal(t.psi_Wb, (float)(psi_mtpa - n * RATE * TS), 1e-5f);
    assert_true(t.te_Nm < 12.0f);
    assert_float_equal((float)i_aimed(t), (float)I_LIM, 2e-3f);
    const double psiq = L0 * (double)t.te_Nm / KT0;
    assert_true(sqrt((double)t.psi_Wb * t.psi_Wb - psiq * psiq) < PSI0); /* id < 0 */
    /* a small torque at that flux is not cut */
    const oplim_out_t s = oplim_targets(&o, &db.par, (float)I_LIM, 1.0f);
    assert_float_equal(s.te_Nm, 1.0f, 1e-6f);
}

/* Floor psi_f - L i_lim (no torque left there), and back to MTPA below
 * hyst u_lim; inside the band [hyst u_lim, u_lim] dpsi holds. */
static void weakening_floor_and_recovery(void **state)
{
    const dq_t u_big = { 0.0f, 200.0f };
    const dq_t u_band = { 0.0f, 176.0f };  /* 0.97 x 180 = 174.6 < 176 < 180 */
    const dq_t u_low = { 0.0f, 100.0f };
    (void)state;
    setup();
    (void)oplim_targets(&o, &db.par, (float)I_LIM, 0.0f);
    for (int k = 0; k < 1000; k++) {
        oplim_fw_update(&o, u_big, 180.0f);
    }
    const oplim_out_t t = oplim_targets(&o, &db.par, (float)I_LIM, 0.0f);
    assert_float_equal(t.psi_Wb, (float)(PSI0 - L0 * I_LIM), 1e-5f);
    /* asking for torque there: no more than the limit's current */
    const oplim_out_t t5 = oplim_targets(&o, &db.par, (float)I_LIM, 5.0f);
    assert_true(t5.psi_Wb >= (float)(PSI0 - L0 * I_LIM));
    assert_true(t5.te_Nm < 5.0f);
    assert_float_equal((float)i_aimed(t5), (float)I_LIM, 2e-3f);
    const float d = o.dpsi_Wb;
    oplim_fw_update(&o, u_band, 180.0f);
    assert_float_equal(o.dpsi_Wb, d, 1e-9f);
    for (int k = 0; k < 1000; k++) {
        oplim_fw_update(&o, u_low, 180.0f);
    }
    assert_float_equal(o.dpsi_Wb, 0.0f, 1e-9f);
    const oplim_out_t m = oplim_targets(&o, &db.par, (float)I_LIM, 0.0f);
    assert_float_equal(m.psi_Wb, (float)PSI0, 1e-6f);
}

/* A refused loop (rate 0) never weakens; the current limit still holds. */
static void refused_loop_never_weakens(void **state)
{
    const dq_t u_big = { 0.0f, 200.0f };
    (void)state;
    setup();
    oplim_init(&o, (float)TS, 0.0f, (float)HYST);
    (void)oplim_targets(&o, &db.par, (float)I_LIM, 0.0f);
    oplim_fw_update(&o, u_big, 180.0f);
    assert_float_equal(o.dpsi_Wb, 0.0f, 1e-9f);
    assert_float_equal(oplim_targets(&o, &db.par, (float)I_LIM, 20.0f).te_Nm, (float)(KT0 * I_LIM), 1e-4f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(mtpa_below_the_limits),
        cmocka_unit_test(current_limit_at_mtpa),
        cmocka_unit_test(weakening_keeps_current_at_limit),
        cmocka_unit_test(weakening_floor_and_recovery),
        cmocka_unit_test(refused_loop_never_weakens),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
