/* Unit tests for control/smo: the sliding-mode observer against the exact
 * test plant of obs_plant.h (true parameters differ from the observer's),
 * the corrected steady-state disturbances, boundary-layer hand values of
 * the gains designed on the discrete model, init checks (the linear
 * region's poles and the discrete reaching condition at the corners of
 * the ranges), finiteness, bumpless R. */
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

/* The designed gains and the boundary layer by hand (discrete_model_design.md
 * sec. 5), Table I, Ts = 1e-4 s, ef_max = 50 V, w = 0, u = 0:
 *   a = Ts R/L = 0.0272727, rho = e^-a = 0.973096, g = (1 - rho)/R = 8.968e-3 A/V
 *   double pole 0.8: G g = rho - 0.6 -> G = 41.60 V/A; mu Ts = 0.04/(rho - 0.6)
 *   Ks = 2 ef_max = 100 V, phi = Ks/G = 2.404 A
 *   e = (+0.5, -1.0) A -> U = G e, f^ = mu Ts U,
 *   i^(k+1) = rho i^ + g (-f^old - U) = -g U (i^ = 0, f^old = 0).
 *   e = 5 A (outside the layer) -> U = Ks (not G e). */
static void boundary_layer_hand_values(void **state)
{
    (void)state;
    smo_t smo;
    smo_cfg_t c = op_smo_cfg(OP_R0, OP_L0, OP_PSI0);
    assert_int_equal(smo_init(&smo, &c), SMO_CFG_OK);
    const double rho = exp(-1e-4 * 3.0 / 0.011);
    const double g = (1.0 - rho) / 3.0;
    const double G = (rho - 0.6) / g;
    const double muTs = 0.04 / (rho - 0.6);
    const double phi = 100.0 / G;
    assert_float_equal(G, 41.60, 0.01);
    assert_float_equal(c.phi_A, phi, 1e-5);
    assert_float_equal(c.Ks_V, G * phi, 1e-4);
    assert_float_equal(c.mu_d_1_s * 1e-4, muTs, 1e-6);
    dq_t ih = smo_step(&smo, dq(0.0, 0.0), 0.0f, dq(0.0, 0.0)); /* seeds i^ = i = 0 */
    assert_float_equal(ih.d, 0.0, 0.0);
    assert_float_equal(smo.U_V.d, 0.0, 0.0);
    ih = smo_step(&smo, dq(-0.5, 1.0), 0.0f, dq(0.0, 0.0));
    assert_float_equal(smo.U_V.d, 0.5 * G, 1e-4);
    assert_float_equal(smo.U_V.q, -1.0 * G, 1e-4);
    assert_float_equal(smo.fd_V, muTs * 0.5 * G, 1e-5);
    assert_float_equal(smo.fq_V, -muTs * G, 1e-5);
    assert_float_equal(ih.d, -g * 0.5 * G, 1e-6);
    assert_float_equal(ih.q, g * G, 1e-6);

    smo_reset(&smo);
    (void)smo_step(&smo, dq(0.0, 0.0), 0.0f, dq(0.0, 0.0));
    (void)smo_step(&smo, dq(-5.0, 5.0), 0.0f, dq(0.0, 0.0));
    assert_float_equal(smo.U_V.d, G * phi, 1e-4);
    assert_float_equal(smo.U_V.q, -G * phi, 1e-4);
}

/* The design refuses a motor below 2 periods of L/R and designs one above
 * (the D5065: 39 mOhm, 15.7 uH, 4 periods; one at 2.1 periods): there the
 * four corners of its ranges ([0.2, 2] R, L from the reaching condition's
 * floor up to 3 L) pass smo_init. */
static void design_two_periods_floor(void **state)
{
    (void)state;
    smo_gains_t g;
    assert_false(smo_gains_design(1e-4f, 0.1f, 19.0e-6f, 3.86f, &g));
    const float motors[][2] = { { 0.039f, 15.7e-6f }, { 0.1f, 21.0e-6f }, { 3.0f, 0.011f } };
    for (size_t k = 0; k < sizeof motors / sizeof motors[0]; k++) {
        const float R = motors[k][0];
        const float L = motors[k][1];
        assert_true(smo_gains_design(1e-4f, R, L, 3.86f, &g));
        smo_cfg_t c;
        smo_cfg_defaults(&c, 1e-4f, R, L, 0.003f, &g);
        const float L_floor = smo_L_floor_H(1e-4f, c.R_min_Ohm, &g);
        c.L_min_H = (c.L_min_H > 1.25f * L_floor) ? c.L_min_H : 1.25f * L_floor;
        c.f_max_V = 24.0f;
        c.i_max_A = 100.0f;
        c.u_max_V = 24.0f;
        c.omega_max_rad_s = 5000.0f;
        smo_t smo;
        assert_int_equal(smo_init(&smo, &c), SMO_CFG_OK);
        /* at the floor the reaching condition's upper side holds, and the
         * floor is within 1 % of its equality, L = Ts R / ln((c + R)/(c - R))
         * (none where R^ alone keeps it: c = G + ef_max/phi <= R_min) */
        if (L_floor > 0.0f) {
            zoh_model_t m;
            assert_true(zoh_model(c.R_min_Ohm, L_floor, 1e-4f, &m));
            assert_true(g.phi_A * (1.0 + (double)m.rho) >= m.gamma_A_V * (g.ef_max_V + g.Ks_V));
            const double cc = (double)g.Ks_V / g.phi_A + (double)g.ef_max_V / g.phi_A;
            const double Rm = c.R_min_Ohm;
            const double exact = 1e-4 * Rm / log((cc + Rm) / (cc - Rm));
            assert_float_equal(L_floor, exact, 0.01 * exact);
        } else {
            assert_true(g.Ks_V / g.phi_A + g.ef_max_V / g.phi_A <= c.R_min_Ohm);
        }
    }
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

/* Init: the default design passes; a boundary layer ten times thinner
 * (G 416 V/A, beyond (1 + rho)/g = 220 V/A at L_min) is refused as
 * unstable, so is mu Ts near 1 (the constant term p + k of the error's
 * polynomial past 1); a disturbance bound the switching gain cannot
 * dominate fails the reaching condition (Ks + R_min phi < ef_max); and
 * non-finite or out-of-order fields are invalid. A refused observer
 * passes the measurement through. */
static void init_checks_stability_and_reaching(void **state)
{
    (void)state;
    smo_t smo;
    smo_cfg_t c = op_smo_cfg(OP_R0, OP_L0, OP_PSI0);
    assert_int_equal(smo_init(&smo, &c), SMO_CFG_OK);

    smo_cfg_t u = c;
    u.phi_A = 0.1f * c.phi_A;
    assert_int_equal(smo_init(&smo, &u), SMO_CFG_UNSTABLE);
    u = c;
    u.mu_q_1_s = 2.0f / u.Ts_s; /* f^ past its target in a period: p + k > 1 at L_min */
    assert_int_equal(smo_init(&smo, &u), SMO_CFG_UNSTABLE);

    u = c;
    u.ef_max_V = c.Ks_V + c.R_min_Ohm * c.phi_A + 1.0f;
    assert_int_equal(smo_init(&smo, &u), SMO_CFG_KS_TOO_SMALL);
    u.ef_max_V = 0.75f * c.Ks_V; /* in: Ks > ef_max; out: g (1.75 Ks) < (1 + rho) phi at L_min */
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
                assert_true(isfinite(smo.zm.gamma_A_V) && smo.zm.gamma_A_V > 0.0f && smo.zm.rho > 0.0f);
                assert_true(smo.L_H >= c.L_min_H && smo.L_H <= c.L_max_H);
                assert_true(smo.R_Ohm >= c.R_min_Ohm && smo.R_Ohm <= c.R_max_Ohm);
            }
        }
    }
}

/* Bumpless R: f^ += (R^old - R^new) i^ keeps -R^ i^ - f^ exactly, so in
 * steady state the next prediction is unchanged but for the inverter
 * voltage's gain ratio g_u/g_c, which depends on R^ at second order (w Ts
 * Ts R/L / 12 of u: 0.5 mA here, from 12.9 to 3 Ohm); during a transient
 * it moves by at most the change of the decay times the predicted
 * increment. Out-of-range R is refused without any change. */
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
    assert_float_equal(pa.d, pb.d, 5e-4);
    assert_float_equal(pa.q, pb.q, 5e-4);

    /* transient: bounded by the change of the decay times the increment */
    a = smo;
    b = smo;
    assert_true(smo_set_R(&b, (float)OP_R0));
    const dq_t i0 = a.i_hat_A;
    pa = smo_step(&a, dq(p.id, p.iq), (float)w, dq(ud + 50.0, uq - 30.0));
    pb = smo_step(&b, dq(p.id, p.iq), (float)w, dq(ud + 50.0, uq - 30.0));
    const double rel_g = fabs((double)b.zm.gamma_A_V / a.zm.gamma_A_V - 1.0);
    assert_true(fabs(pb.d - pa.d) <= rel_g * fabs(pa.d - i0.d) + 5e-4);
    assert_true(fabs(pb.q - pa.q) <= rel_g * fabs(pa.q - i0.q) + 5e-4);

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
        cmocka_unit_test(init_checks_stability_and_reaching),
        cmocka_unit_test(design_two_periods_floor),
        cmocka_unit_test(finite_for_any_finite_input),
        cmocka_unit_test(bumpless_R_update),
    };
    return cmocka_run_group_tests_name("smo", tests, NULL, NULL);
}
