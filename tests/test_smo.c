/* Unit tests for control/smo: the sliding-mode observer against the exact
 * test plant of obs_plant.h (true parameters differ from the observer's),
 * the corrected steady-state disturbances, boundary-layer hand values,
 * init checks (stability bound, condition (36)), finiteness, bumpless R. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <float.h>
#include <math.h>
#include <stdio.h>

#include "obs_plant.h"
#include "smo.h"

static dq_t dq(double d, double q)
{
    dq_t x = { (float)d, (float)q };
    return x;
}

/* Exact parameters: after the start-up the one-step prediction matches the
 * plant's next sample to 1 mA, including a torque step (2 -> 4 N m) and a
 * speed step of the voltage pattern. */
static void exact_parameters_predict_next_sample(void **state)
{
    (void)state;
    smo_t smo;
    smo_cfg_t c = op_smo_cfg(OP_R0, OP_L0, OP_PSI0);
    assert_int_equal(smo_init(&smo, &c), SMO_CFG_OK);
    op_plant_t p = { OP_R0, OP_L0, OP_PSI0, 0.0, 0.0 };
    const double w = op_w_el(500.0);
    double worst_settled = 0.0;
    double worst_step = 0.0;
    for (int k = 0; k < 3000; k++) {
        const double iq_ref = (k < 1000) ? op_iq_of_te(2.0) : op_iq_of_te(4.0);
        double ud, uq;
        op_u_for(&p, -0.5, iq_ref, w, &ud, &uq);
        dq_t ih = smo_step(&smo, dq(p.id, p.iq), (float)w, dq(ud, uq));
        op_step(&p, ud, uq, w);
        const double err = fmax(fabs(ih.d - p.id), fabs(ih.q - p.iq));
        if (k >= 500 && k < 1000) {
            worst_settled = fmax(worst_settled, err);
        }
        if (k >= 1000) {
            worst_step = fmax(worst_step, err);
        }
    }
    printf("    exact params: max |i^(k+1) - i(k+1)| settled %.2e A, through torque step %.2e A\n",
           worst_settled, worst_step);
    assert_true(worst_settled < 1e-4);
    assert_true(worst_step < 1e-3);
}

/* Runs the observer with Rh, Lh, psih against the true plant at (id, iq, w)
 * for n periods; returns fd^, fq^ and the prediction error at the end. */
static void run_mismatch(double Rh, double Lh, double psih, double id, double iq, double w, int n,
                         double *fd, double *fq, double *err)
{
    smo_t smo;
    smo_cfg_t c = op_smo_cfg(Rh, Lh, psih);
    assert_int_equal(smo_init(&smo, &c), SMO_CFG_OK);
    op_plant_t p = { OP_R0, OP_L0, OP_PSI0, id, iq };
    double ud, uq;
    op_u_for(&p, id, iq, w, &ud, &uq);
    dq_t ih = { 0.0f, 0.0f };
    for (int k = 0; k < n; k++) {
        ih = smo_step(&smo, dq(p.id, p.iq), (float)w, dq(ud, uq));
        op_step(&p, ud, uq, w);
    }
    *fd = smo.fd_V;
    *fq = smo.fq_V;
    *err = fmax(fabs(ih.d - p.id), fabs(ih.q - p.iq));
}

/* With R/L/psi_f mismatch, f^ converges to the corrected disturbances of
 * corrected_model_design.md sec. 2, fd = dL w iq - dR id,
 * fq = -dR iq - dL w id - dpsi w, within 1 %, and the prediction stays
 * exact (the observer absorbs the mismatch).
 * The signs are the opposite of the printed (26)-(27). */
static void mismatch_disturbances_match_corrected_formulas(void **state)
{
    (void)state;
    const double w = op_w_el(500.0);
    const double id = -1.0;
    const double iq = 3.0;
    const double cases[][3] = {
        { 4.3 * OP_R0, OP_L0, OP_PSI0 },        /* R only */
        { OP_R0, 1.5 * OP_L0, OP_PSI0 },        /* L only */
        { OP_R0, 0.66 * OP_L0, OP_PSI0 },
        { OP_R0, OP_L0, 2.0 * OP_PSI0 },        /* psi only */
        { OP_R0, OP_L0, 0.5 * OP_PSI0 },
        { 4.3 * OP_R0, 0.66 * OP_L0, 1.5 * OP_PSI0 }, /* all three */
    };
    op_plant_t p = { OP_R0, OP_L0, OP_PSI0, 0.0, 0.0 };
    for (size_t m = 0; m < sizeof cases / sizeof cases[0]; m++) {
        double fd, fq, err, fd_x, fq_x;
        run_mismatch(cases[m][0], cases[m][1], cases[m][2], id, iq, w, 2000, &fd, &fq, &err);
        op_f_ss(&p, cases[m][0], cases[m][1], cases[m][2], id, iq, w, &fd_x, &fq_x);
        printf("    case %zu: fd^ %.4f (exp %.4f)  fq^ %.4f (exp %.4f)  pred err %.1e A\n", m, fd,
               fd_x, fq, fq_x, err);
        assert_float_equal(fd, fd_x, 0.01 * fabs(fd_x) + 1e-3);
        assert_float_equal(fq, fq_x, 0.01 * fabs(fq_x) + 1e-3);
        assert_true(err < 1e-4);
        /* printed (26)-(27) have every term's sign the other way */
        if (fabs(fq_x) > 1.0) {
            assert_true(fq * fq_x > 0.0);
        }
    }
}

/* Inside the boundary layer U = Ks e/phi (linear observer, G = 40 V/A),
 * outside U = Ks sign(e). Hand values with Ks = 100 V, phi = 2.5 A,
 * mu = 1100/s, Ts = 1e-4 s, L^ = 11 mH, R^ = 3 Ohm, w = 0, u = 0:
 *   g = (1e-4/0.011)(1 - 1e-4*3/(2*0.011)) = 8.96694e-3 A/V
 *   e = (+0.5, -1.0) A -> U = (20, -40) V, f^ = mu Ts U = (2.2, -4.4) V,
 *   i^(k+1) = i^ + g(-R i^ - f^old - U) = -g U (i^ = 0, f^old = 0).
 *   e = 5 A (outside) -> U = 100 V (not 200). */
static void boundary_layer_hand_values(void **state)
{
    (void)state;
    smo_t smo;
    smo_cfg_t c = op_smo_cfg(OP_R0, OP_L0, OP_PSI0);
    assert_int_equal(smo_init(&smo, &c), SMO_CFG_OK);
    const double g = (1e-4 / 0.011) * (1.0 - 1e-4 * 3.0 / (2.0 * 0.011));
    assert_float_equal(smo.g_A_per_V, g, 1e-9);
    dq_t ih = smo_step(&smo, dq(0.0, 0.0), 0.0f, dq(0.0, 0.0)); /* seeds i^ = i = 0 */
    assert_float_equal(ih.d, 0.0, 0.0);
    assert_float_equal(smo.U_V.d, 0.0, 0.0);
    ih = smo_step(&smo, dq(-0.5, 1.0), 0.0f, dq(0.0, 0.0));
    assert_float_equal(smo.U_V.d, 20.0, 1e-5);
    assert_float_equal(smo.U_V.q, -40.0, 1e-5);
    assert_float_equal(smo.fd_V, 2.2, 1e-6);
    assert_float_equal(smo.fq_V, -4.4, 1e-6);
    assert_float_equal(ih.d, -g * 20.0, 1e-7);
    assert_float_equal(ih.q, g * 40.0, 1e-7);

    smo_reset(&smo);
    (void)smo_step(&smo, dq(0.0, 0.0), 0.0f, dq(0.0, 0.0));
    (void)smo_step(&smo, dq(-5.0, 5.0), 0.0f, dq(0.0, 0.0));
    assert_float_equal(smo.U_V.d, 100.0, 1e-6);
    assert_float_equal(smo.U_V.q, -100.0, 1e-6);
}

/* The first step after reset seeds i^(k) = i(k): no switching kick. */
static void first_step_seeds_without_kick(void **state)
{
    (void)state;
    smo_t smo;
    smo_cfg_t c = op_smo_cfg(OP_R0, OP_L0, OP_PSI0);
    assert_int_equal(smo_init(&smo, &c), SMO_CFG_OK);
    (void)smo_step(&smo, dq(1.0, 3.0), 157.0f, dq(-10.0, 50.0));
    assert_float_equal(smo.U_V.d, 0.0, 0.0);
    assert_float_equal(smo.U_V.q, 0.0, 0.0);
    assert_float_equal(smo.fd_V, 0.0, 0.0);
}

/* Init: the default design passes; a boundary layer so thin that
 * Ks/phi >= 2 L_min/Ts - R_max is refused as unstable (here G = 400 V/A >
 * 2*3.3e-3/1e-4 - 15 = 51 V/A); mu Ts >= 1 too; a disturbance bound
 * Ks cannot dominate violates (36) (ef 70 + 15*2.5 = 107.5 > 100 V); and
 * non-finite or out-of-order fields are invalid. A refused observer
 * passes the measurement through. */
static void init_checks_stability_and_condition_36(void **state)
{
    (void)state;
    smo_t smo;
    smo_cfg_t c = op_smo_cfg(OP_R0, OP_L0, OP_PSI0);
    assert_int_equal(smo_init(&smo, &c), SMO_CFG_OK);

    smo_cfg_t u = c;
    u.phi_A = 0.25f;
    assert_int_equal(smo_init(&smo, &u), SMO_CFG_UNSTABLE);
    u = c;
    u.Ks_V = 60.0f;
    u.phi_A = 1.0f; /* G = 60 > 51 */
    u.ef_max_V = 0.0f;
    assert_int_equal(smo_init(&smo, &u), SMO_CFG_UNSTABLE);
    u.phi_A = 1.2f; /* G = 50 < 51: stable, (36): 60 > 0 + 15*1.2 */
    assert_int_equal(smo_init(&smo, &u), SMO_CFG_OK);
    u = c;
    u.mu_q_1_s = 1.0e4f;
    assert_int_equal(smo_init(&smo, &u), SMO_CFG_UNSTABLE);

    u = c;
    u.ef_max_V = 70.0f;
    assert_int_equal(smo_init(&smo, &u), SMO_CFG_KS_TOO_SMALL);
    u.ef_max_V = 60.0f; /* 60 + 37.5 < 100 */
    assert_int_equal(smo_init(&smo, &u), SMO_CFG_OK);

    u = c;
    u.L_min_H = NAN;
    assert_int_equal(smo_init(&smo, &u), SMO_CFG_INVALID);
    u = c;
    u.R_Ohm = 20.0f; /* outside [R_min, R_max] */
    assert_int_equal(smo_init(&smo, &u), SMO_CFG_INVALID);
    u = c;
    u.L_H = 0.0f;
    assert_int_equal(smo_init(&smo, &u), SMO_CFG_INVALID);
    u = c;
    u.i_max_A = 0.0f; /* smo_cfg_defaults leaves the bounds to the caller */
    assert_int_equal(smo_init(&smo, &u), SMO_CFG_INVALID);
    dq_t ih = smo_step(&smo, dq(1.5, -2.5), 100.0f, dq(10.0, 10.0));
    assert_true(isfinite(ih.d) && isfinite(ih.q));
    assert_false(smo_set_R(&smo, 3.0f));
}

/* Any finite input, extremes included, keeps the state finite and bounded. */
static void finite_for_any_finite_input(void **state)
{
    (void)state;
    const float v[] = { -FLT_MAX, -1e20f, -3.0f, -FLT_MIN, 0.0f, FLT_MIN, 2.0f, 1e20f, FLT_MAX };
    const int n = (int)(sizeof v / sizeof v[0]);
    smo_t smo;
    smo_cfg_t c = op_smo_cfg(OP_R0, OP_L0, OP_PSI0);
    assert_int_equal(smo_init(&smo, &c), SMO_CFG_OK);
    for (int a = 0; a < n; a++) {
        for (int b = 0; b < n; b++) {
            for (int d = 0; d < n; d++) {
                dq_t i = { v[a], v[b] };
                dq_t u = { v[d], v[a] };
                dq_t ih = smo_step(&smo, i, v[d], u);
                assert_true(isfinite(ih.d) && isfinite(ih.q));
                assert_true(fabsf(ih.d) <= 60.0f && fabsf(ih.q) <= 60.0f);
                assert_true(fabsf(smo.fd_V) <= 400.0f && fabsf(smo.fq_V) <= 400.0f);
                (void)smo_set_L(&smo, v[b], v[d], v[a]);
                (void)smo_set_psi(&smo, v[a], v[b]);
                (void)smo_set_R(&smo, v[d]);
                assert_true(isfinite(smo.g_A_per_V) && smo.g_A_per_V > 0.0f);
                assert_true(smo.L_H >= c.L_min_H && smo.L_H <= c.L_max_H);
                assert_true(smo.R_Ohm >= c.R_min_Ohm && smo.R_Ohm <= c.R_max_Ohm);
            }
        }
    }
}

/* Bumpless R: f^ += (R^old - R^new) i^ keeps -R^ i^ - f^ exactly, so in
 * steady state the next prediction is unchanged (to float rounding); during
 * a transient it moves only by (g'/g - 1) times the predicted increment
 * (the ZOH factor 1 - Ts R^/(2L^) of g depends on R^). Out-of-range R is
 * refused without any change. */
static void bumpless_R_update(void **state)
{
    (void)state;
    smo_t smo;
    smo_cfg_t c = op_smo_cfg(4.3 * OP_R0, OP_L0, OP_PSI0);
    assert_int_equal(smo_init(&smo, &c), SMO_CFG_OK);
    op_plant_t p = { OP_R0, OP_L0, OP_PSI0, 0.0, 0.0 };
    const double w = op_w_el(500.0);
    double ud, uq;
    op_u_for(&p, -0.5, op_iq_of_te(4.0), w, &ud, &uq);
    for (int k = 0; k < 2000; k++) {
        (void)smo_step(&smo, dq(p.id, p.iq), (float)w, dq(ud, uq));
        op_step(&p, ud, uq, w);
    }
    smo_t a = smo;
    smo_t b = smo;
    const double inv_before_d = -(double)b.R_Ohm * b.i_hat_A.d - b.fd_V;
    const double inv_before_q = -(double)b.R_Ohm * b.i_hat_A.q - b.fq_V;
    assert_true(smo_set_R(&b, (float)OP_R0));
    assert_float_equal(-(double)b.R_Ohm * b.i_hat_A.d - b.fd_V, inv_before_d, 1e-5);
    assert_float_equal(-(double)b.R_Ohm * b.i_hat_A.q - b.fq_V, inv_before_q, 1e-5);
    assert_float_equal(b.i_hat_A.d, a.i_hat_A.d, 0.0); /* the stored prediction is untouched */
    assert_float_equal(b.i_hat_A.q, a.i_hat_A.q, 0.0);
    dq_t pa = smo_step(&a, dq(p.id, p.iq), (float)w, dq(ud, uq));
    dq_t pb = smo_step(&b, dq(p.id, p.iq), (float)w, dq(ud, uq));
    printf("    bumpless R 12.9 -> 3 Ohm, steady: next prediction moved by %.1e / %.1e A\n",
           fabs(pa.d - pb.d), fabs(pa.q - pb.q));
    assert_float_equal(pa.d, pb.d, 1e-5);
    assert_float_equal(pa.q, pb.q, 1e-5);

    /* transient: bounded by the change of g times the increment */
    a = smo;
    b = smo;
    assert_true(smo_set_R(&b, (float)OP_R0));
    const dq_t i0 = a.i_hat_A;
    pa = smo_step(&a, dq(p.id, p.iq), (float)w, dq(ud + 50.0, uq - 30.0));
    pb = smo_step(&b, dq(p.id, p.iq), (float)w, dq(ud + 50.0, uq - 30.0));
    const double rel_g = fabs((double)b.g_A_per_V / a.g_A_per_V - 1.0);
    assert_true(fabs(pb.d - pa.d) <= rel_g * fabs(pa.d - i0.d) + 1e-5);
    assert_true(fabs(pb.q - pa.q) <= rel_g * fabs(pa.q - i0.q) + 1e-5);

    const float R_keep = b.R_Ohm;
    const float fd_keep = b.fd_V;
    assert_false(smo_set_R(&b, 100.0f));
    assert_false(smo_set_R(&b, NAN));
    assert_float_equal(b.R_Ohm, R_keep, 0.0);
    assert_float_equal(b.fd_V, fd_keep, 0.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(exact_parameters_predict_next_sample),
        cmocka_unit_test(mismatch_disturbances_match_corrected_formulas),
        cmocka_unit_test(boundary_layer_hand_values),
        cmocka_unit_test(first_step_seeds_without_kick),
        cmocka_unit_test(init_checks_stability_and_condition_36),
        cmocka_unit_test(finite_for_any_finite_input),
        cmocka_unit_test(bumpless_R_update),
    };
    return cmocka_run_group_tests_name("smo", tests, NULL, NULL);
}
