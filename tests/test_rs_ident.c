/* Unit tests for control/rs_ident: step-1 resistance from two steady
 * operating points, on analytic steady-state disturbances
 * (corrected_model_design.md sec. 2, in double) and on the smo observer running against the exact test plant of
 * obs_plant.h (the paper's R = 4.3 R0 case); acceptance checks. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "obs_plant.h"
#include "rs_ident.h"
#include "smo.h"

#define R_NOM (4.3 * OP_R0) /* the controller's resistance in step 1 */

static rs_ident_t make(double R_nom)
{
    rs_ident_cfg_t c;
    rs_ident_t ri;
    rs_ident_cfg_defaults(&c, (float)R_nom);
    assert_true(rs_ident_init(&ri, &c));
    return ri;
}

/* n constant samples of the analytic steady state at (id, iq, w) into win,
 * the observer holding Rh, Lh, psih against the true Table I motor. */
static void feed_analytic(rs_ident_t *ri, rs_ident_window_t win, double Rh, double Lh,
                          double psih, double id, double iq, double w, int n)
{
    op_plant_t p = { OP_R0, OP_L0, OP_PSI0, 0.0, 0.0 };
    double fd, fq;
    op_f_cont(&p, Rh, Lh, psih, id, iq, w, &fd, &fq);
    for (int k = 0; k < n; k++) {
        rs_ident_step(ri, win, (float)fd, (float)fq, (float)id, (float)iq, (float)w);
    }
}

/* Literal (42): R - (w1 fq2 - w2 fq1)/(iq2 w1 - iq1 w2), on the same means. */
static double literal_42(const rs_ident_out_t *o, double R)
{
    const double w1 = o->mean_w_rad_s[0], w2 = o->mean_w_rad_s[1];
    const double den = o->mean_iq_A[1] * w1 - o->mean_iq_A[0] * w2;
    return R - (w1 * o->mean_fq_V[1] - w2 * o->mean_fq_V[0]) / den;
}

/* R = 4.3 R0, 500 r/min, 2 and 4 N m: R^ within 1 % of R0 (here exact to
 * float); the literal (42) gives 2R - R0 = 7.6 R0, which is not it. */
static void analytic_paper_case(void **state)
{
    (void)state;
    rs_ident_t ri = make(R_NOM);
    rs_ident_out_t o;
    const double w = op_w_el(500.0);
    feed_analytic(&ri, RS_IDENT_WINDOW_1, R_NOM, OP_L0, OP_PSI0, 0.0, op_iq_of_te(2.0), w, 500);
    feed_analytic(&ri, RS_IDENT_WINDOW_2, R_NOM, OP_L0, OP_PSI0, 0.0, op_iq_of_te(4.0), w, 500);
    assert_int_equal(rs_ident_solve(&ri, &o), RS_IDENT_OK);
    printf("    analytic: R^ = %.5f Ohm (R0 = 3), literal (42) = %.4f Ohm\n", o.R_est_Ohm,
           literal_42(&o, R_NOM));
    assert_float_equal(o.R_est_Ohm, OP_R0, 0.01 * OP_R0);
    assert_float_equal(o.dR_Ohm, R_NOM - OP_R0, 1e-3);
    assert_float_equal(literal_42(&o, R_NOM), 2.0 * R_NOM - OP_R0, 1e-3); /* 7.6 R0 */
    assert_true(fabs(o.R_est_Ohm - literal_42(&o, R_NOM)) > 5.0 * OP_R0); /* 7.6 R0 vs R0 */
}

/* All three wrong and id != 0 at both points: the iteration's d-axis
 * correction (dL w id in fq) recovers R0, dL and dpsi; equal-load points at
 * two speeds work too (dpsi w cancels). */
static void analytic_all_mismatched_and_two_speeds(void **state)
{
    (void)state;
    const double Lh = 0.66 * OP_L0, psih = 1.5 * OP_PSI0;
    rs_ident_out_t o;
    rs_ident_t ri = make(R_NOM);
    feed_analytic(&ri, RS_IDENT_WINDOW_1, R_NOM, Lh, psih, -1.0, op_iq_of_te(2.0), op_w_el(500.0), 500);
    feed_analytic(&ri, RS_IDENT_WINDOW_2, R_NOM, Lh, psih, -1.0, op_iq_of_te(4.0), op_w_el(500.0), 500);
    assert_int_equal(rs_ident_solve(&ri, &o), RS_IDENT_OK);
    printf("    analytic, L x0.66 psi x1.5 id = -1 A: R^ %.5f, dL %.3e (exp %.3e), dpsi %.4f (exp %.4f)\n",
           o.R_est_Ohm, o.dL_H, Lh - OP_L0, o.dpsi_Wb, psih - OP_PSI0);
    assert_float_equal(o.R_est_Ohm, OP_R0, 0.001 * OP_R0);
    assert_float_equal(o.dL_H, Lh - OP_L0, 0.001 * OP_L0);
    assert_float_equal(o.dpsi_Wb, psih - OP_PSI0, 0.001 * OP_PSI0);

    rs_ident_reset(&ri);
    feed_analytic(&ri, RS_IDENT_WINDOW_1, R_NOM, Lh, psih, 0.0, op_iq_of_te(4.0), op_w_el(500.0), 500);
    feed_analytic(&ri, RS_IDENT_WINDOW_2, R_NOM, Lh, psih, 0.0, op_iq_of_te(4.0), op_w_el(1000.0), 500);
    assert_int_equal(rs_ident_solve(&ri, &o), RS_IDENT_OK);
    printf("    analytic, 500/1000 r/min at 4 N m: R^ %.5f Ohm\n", o.R_est_Ohm);
    assert_float_equal(o.R_est_Ohm, OP_R0, 0.01 * OP_R0);
}

/* Step 1 as the firmware runs it: observer with R^ = 4.3 R0 (and the given
 * L^, psi^) on the true plant; open-loop voltages for (id, iq1) over
 * 0-0.10 s at w1 and (id, iq2) from 0.10 s at w2; windows 0.05-0.10 s and
 * 0.15-0.20 s; solve at 0.20 s, then the bumpless smo_set_R(). */
static rs_ident_result_t step1_with_plant(double Lh, double psih, double id, double iq1, double iq2,
                                          double w1, double w2, rs_ident_out_t *o)
{
    const smo_cfg_t c = op_smo_cfg(R_NOM, Lh, psih); /* its R range holds R0 and 4.3 R0 */
    smo_t smo;
    assert_int_equal(smo_init(&smo, &c), SMO_CFG_OK);

    rs_ident_cfg_t rc;
    rs_ident_t ri;
    rs_ident_cfg_defaults(&rc, (float)R_NOM);
    rc.R_min_Ohm = c.R_min_Ohm; /* an accepted R^ is one smo_set_R() takes */
    rc.R_max_Ohm = c.R_max_Ohm;
    assert_true(rs_ident_init(&ri, &rc));

    op_plant_t p = { OP_R0, OP_L0, OP_PSI0, 0.0, 0.0 };
    for (int k = 0; k < 2000; k++) {
        const bool second = k >= 1000;
        const double w = second ? w2 : w1;
        double ud, uq;
        op_u_for(&p, id, second ? iq2 : iq1, w, &ud, &uq);
        dq_t i = { (float)p.id, (float)p.iq };
        dq_t u = { (float)ud, (float)uq };
        (void)smo_step(&smo, i, (float)w, u);
        rs_ident_window_t win = RS_IDENT_WINDOW_NONE;
        if (k >= 500 && k < 1000) {
            win = RS_IDENT_WINDOW_1;
        } else if (k >= 1500) {
            win = RS_IDENT_WINDOW_2;
        }
        rs_ident_step(&ri, win, smo.fd_V, smo.fq_V, i.d, i.q, (float)w);
        op_step(&p, ud, uq, w);
    }
    const rs_ident_result_t res = rs_ident_solve(&ri, o);
    if (res == RS_IDENT_OK) {
        const float fq_before = smo.fq_V;
        assert_true(smo_set_R(&smo, o->R_est_Ohm));
        /* bumpless: fq^ += dR iq^ */
        assert_float_equal(smo.fq_V, fq_before + o->dR_Ohm * smo.i_hat_A.q, 1e-4);
    }
    return res;
}

static void plant_and_observer_paper_case(void **state)
{
    (void)state;
    rs_ident_out_t o;
    const double w = op_w_el(500.0);
    assert_int_equal(step1_with_plant(OP_L0, OP_PSI0, 0.0, op_iq_of_te(2.0), op_iq_of_te(4.0), w, w, &o),
                     RS_IDENT_OK);
    printf("    plant+smo, R = 4.3 R0, 2/4 N m: R^ %.5f Ohm (err %+.4f %%), iq std %.1e/%.1e A\n",
           o.R_est_Ohm, 100.0 * (o.R_est_Ohm / OP_R0 - 1.0), o.iq_std_A[0], o.iq_std_A[1]);
    assert_float_equal(o.R_est_Ohm, OP_R0, 0.01 * OP_R0);
    assert_true(fabs(o.R_est_Ohm - literal_42(&o, R_NOM)) > 5.0 * OP_R0); /* 7.6 R0 vs R0 */

    assert_int_equal(step1_with_plant(0.66 * OP_L0, 1.5 * OP_PSI0, -1.0, op_iq_of_te(2.0),
                                      op_iq_of_te(4.0), w, w, &o),
                     RS_IDENT_OK);
    printf("    plant+smo, also L x0.66 psi x1.5, id = -1 A: R^ %.5f Ohm (err %+.4f %%)\n",
           o.R_est_Ohm, 100.0 * (o.R_est_Ohm / OP_R0 - 1.0));
    assert_float_equal(o.R_est_Ohm, OP_R0, 0.01 * OP_R0);

    assert_int_equal(step1_with_plant(OP_L0, 1.5 * OP_PSI0, 0.0, op_iq_of_te(4.0), op_iq_of_te(4.0),
                                      op_w_el(500.0), op_w_el(1000.0), &o),
                     RS_IDENT_OK);
    printf("    plant+smo, 500/1000 r/min at 4 N m: R^ %.5f Ohm (err %+.4f %%)\n", o.R_est_Ohm,
           100.0 * (o.R_est_Ohm / OP_R0 - 1.0));
    assert_float_equal(o.R_est_Ohm, OP_R0, 0.01 * OP_R0);
}

/* Equal (or too similar) operating points: degenerate; R^ stays nominal. */
static void equal_operating_points_are_degenerate(void **state)
{
    (void)state;
    rs_ident_out_t o;
    const double w = op_w_el(500.0);
    rs_ident_t ri = make(R_NOM);
    feed_analytic(&ri, RS_IDENT_WINDOW_1, R_NOM, OP_L0, OP_PSI0, 0.0, 3.7, w, 500);
    feed_analytic(&ri, RS_IDENT_WINDOW_2, R_NOM, OP_L0, OP_PSI0, 0.0, 3.7, w, 500);
    assert_int_equal(rs_ident_solve(&ri, &o), RS_IDENT_DEGENERATE);
    assert_float_equal(o.R_est_Ohm, R_NOM, 1e-5);
    rs_ident_reset(&ri);
    /* |den| = 0.5 w < 0.3 * 3.7 w */
    feed_analytic(&ri, RS_IDENT_WINDOW_1, R_NOM, OP_L0, OP_PSI0, 0.0, 3.2, w, 500);
    feed_analytic(&ri, RS_IDENT_WINDOW_2, R_NOM, OP_L0, OP_PSI0, 0.0, 3.7, w, 500);
    assert_int_equal(rs_ident_solve(&ri, &o), RS_IDENT_DEGENERATE);
    rs_ident_reset(&ri);
    /* both at standstill */
    feed_analytic(&ri, RS_IDENT_WINDOW_1, R_NOM, OP_L0, OP_PSI0, 0.0, 1.0, 0.0, 500);
    feed_analytic(&ri, RS_IDENT_WINDOW_2, R_NOM, OP_L0, OP_PSI0, 0.0, 3.7, 0.0, 500);
    assert_int_equal(rs_ident_solve(&ri, &o), RS_IDENT_DEGENERATE);
}

/* Window 2 at 3.7 A with fq^ off the model by +a in even batches and -a in
 * odd ones (10 batches of 50): by hand the batch means of the residual are
 * +-a, their sample variance 10 a^2 / 9, se(r2) = a / 3, and with equal
 * speeds se(R^) = w se(r2) / |w (iq2 - iq1)| = a / (3 x 1.85 A); window 1
 * is exact (share 0). a = 0.5 V: se 0.090 Ohm > 1 % of 3 Ohm, refused;
 * a = 0.05 V: 0.009 Ohm, taken, and R^ is still exact (the +-a cancel). */
static void feed_batch_square(rs_ident_t *ri, double a, double w)
{
    const double iq = 3.7;
    for (int k = 0; k < 500; k++) {
        const double fq = -(R_NOM - OP_R0) * iq + (((k / (int)RS_IDENT_N_BATCH_DEFAULT) % 2 == 0) ? a : -a);
        rs_ident_step(ri, RS_IDENT_WINDOW_2, 0.0f, (float)fq, 0.0f, (float)iq, (float)w);
    }
}

static void scattered_window_is_refused_by_its_standard_error(void **state)
{
    (void)state;
    rs_ident_out_t o;
    const double w = op_w_el(500.0);
    rs_ident_t ri = make(R_NOM);
    feed_analytic(&ri, RS_IDENT_WINDOW_1, R_NOM, OP_L0, OP_PSI0, 0.0, 1.85, w, 500);
    feed_batch_square(&ri, 0.5, w);
    assert_int_equal(rs_ident_solve(&ri, &o), RS_IDENT_NOT_STEADY);
    printf("    batch square wave 0.5 V: se(R^) %.5f Ohm (hand %.5f), limit %.4f Ohm\n", o.R_se_Ohm,
           0.5 / (3.0 * 1.85), o.R_se_max_Ohm);
    assert_int_equal(o.batches[0], 10u);
    assert_int_equal(o.batches[1], 10u);
    assert_float_equal(o.r_se_V[1], 0.5 / 3.0, 1e-3);
    assert_float_equal(o.R_se_part_Ohm[0], 0.0, 1e-4);
    assert_float_equal(o.R_se_Ohm, 0.5 / (3.0 * 1.85), 1e-3);
    assert_float_equal(o.R_se_max_Ohm, RS_IDENT_R_SE_MAX_REL_DEFAULT * OP_R0, 1e-4);
    assert_float_equal(o.R_est_Ohm, R_NOM, 1e-5); /* refused: nominal */

    rs_ident_reset(&ri);
    feed_analytic(&ri, RS_IDENT_WINDOW_1, R_NOM, OP_L0, OP_PSI0, 0.0, 1.85, w, 500);
    feed_batch_square(&ri, 0.05, w);
    assert_int_equal(rs_ident_solve(&ri, &o), RS_IDENT_OK);
    assert_float_equal(o.R_se_Ohm, 0.05 / (3.0 * 1.85), 1e-4);
    assert_float_equal(o.R_est_Ohm, OP_R0, 1e-3);
    /* solving does not change the windows: more samples, solve again */
    assert_int_equal(rs_ident_solve(&ri, &o), RS_IDENT_OK);
}

#define RIPPLE_1_V 0.2 /* the first harmonic's amplitude [V] */
#define RIPPLE_6_V 0.5 /* the 6th harmonic's [V] */

/* 600 periods of window win at iq, w: fq^ = -(R - R0) iq + amp_V cos(h theta + 0.7),
 * with cos, sin theta given to the fit when with_angle. */
static void feed_ripple(rs_ident_t *ri, rs_ident_window_t win, double iq, double w, bool with_angle, double amp_V,
                        double h)
{
    const double phi = 0.7;
    for (int k = 0; k < 600; k++) {
        const double th = w * OP_TS * k;
        const double fq = -(R_NOM - OP_R0) * iq + amp_V * cos(h * th + phi);
        const float c = with_angle ? (float)cos(th) : 0.0f;
        const float s = with_angle ? (float)sin(th) : 0.0f;
        rs_ident_step_el(ri, win, 0.0f, (float)fq, 0.0f, (float)iq, (float)w, c, s);
    }
}

/* An electrical-frequency ripple of 0.2 V on fq^ (what ADC offsets give)
 * over 60 ms windows at 500 r/min: 1.5 turns, so the plain means keep part
 * of it and the batch means scatter with it. With the angle the fit
 * alpha + a C + b S is exact for a first harmonic: R^ exact, se(R^) ~ 0;
 * without it (no fit) the scatter counts as noise. */
static void electrical_ripple_is_fitted_not_counted_as_noise(void **state)
{
    (void)state;
    rs_ident_out_t fit;
    rs_ident_out_t plain;
    const double w = op_w_el(500.0);
    rs_ident_t ri = make(R_NOM);
    feed_ripple(&ri, RS_IDENT_WINDOW_1, 1.85, w, true, RIPPLE_1_V, 1.0);
    feed_ripple(&ri, RS_IDENT_WINDOW_2, 3.7, w, true, RIPPLE_1_V, 1.0);
    (void)rs_ident_solve(&ri, &fit);
    rs_ident_reset(&ri);
    feed_ripple(&ri, RS_IDENT_WINDOW_1, 1.85, w, false, RIPPLE_1_V, 1.0);
    feed_ripple(&ri, RS_IDENT_WINDOW_2, 3.7, w, false, RIPPLE_1_V, 1.0);
    (void)rs_ident_solve(&ri, &plain);
    printf("    0.2 V ripple at 25 Hz, 1.5 turns: fitted R^ %.5f Ohm, se %.2e; plain R^ %.5f, se %.4f Ohm\n",
           fit.R_est_Ohm, fit.R_se_Ohm, R_NOM - plain.dR_Ohm, plain.R_se_Ohm);
    assert_true(fit.ripple_fit[0] && fit.ripple_fit[1]);
    assert_false(plain.ripple_fit[0] || plain.ripple_fit[1]);
    assert_float_equal(fit.R_est_Ohm, OP_R0, 1e-3 * OP_R0);
    assert_true(fit.R_se_Ohm < 1e-3);
    assert_true(plain.R_se_Ohm > 10.0 * fit.R_se_Ohm);
    assert_true(plain.R_se_Ohm > 5e-3);
}

/* A 6th-harmonic ripple of 0.5 V on fq^ (what an untold dead time leaves,
 * step1_design.md sec. 4) over 60 ms windows at 200 r/min: 60 Hz, 3.6 periods, 0.3
 * of one per 5 ms batch. Its batch means are A (cos phi C6_i - sin phi
 * S6_i) exactly, so the fit with the 6th harmonic leaves no residual: R^
 * exact, se(R^) ~ 0. Without the angle the batch means scatter with it
 * (batch means' spread ~ 0.86 A / sqrt 2 = 0.3 V, se(r) 0.09 V a window,
 * se(R^) ~ sqrt 2 x 0.09 / 1.85 = 0.07 Ohm, above the 1.5 % limit of
 * 0.045 Ohm: the refusal this fit removes). */
static void sixth_harmonic_ripple_is_fitted_not_counted_as_noise(void **state)
{
    (void)state;
    rs_ident_out_t fit;
    rs_ident_out_t plain;
    const double w = op_w_el(200.0);
    rs_ident_t ri = make(R_NOM);
    feed_ripple(&ri, RS_IDENT_WINDOW_1, 1.85, w, true, RIPPLE_6_V, 6.0);
    feed_ripple(&ri, RS_IDENT_WINDOW_2, 3.7, w, true, RIPPLE_6_V, 6.0);
    assert_int_equal(rs_ident_solve(&ri, &fit), RS_IDENT_OK);
    rs_ident_reset(&ri);
    feed_ripple(&ri, RS_IDENT_WINDOW_1, 1.85, w, false, RIPPLE_6_V, 6.0);
    feed_ripple(&ri, RS_IDENT_WINDOW_2, 3.7, w, false, RIPPLE_6_V, 6.0);
    assert_int_equal(rs_ident_solve(&ri, &plain), RS_IDENT_NOT_STEADY);
    printf("    0.5 V ripple at 60 Hz, 3.6 periods: fitted R^ %.5f Ohm, se %.2e; plain R^ %.5f, se %.4f Ohm\n",
           fit.R_est_Ohm, fit.R_se_Ohm, plain.R_raw_Ohm, plain.R_se_Ohm);
    assert_true(fit.ripple6_fit[0] && fit.ripple6_fit[1]);
    assert_float_equal(fit.R_est_Ohm, OP_R0, 1e-3 * OP_R0);
    assert_true(fit.R_se_Ohm < 1e-3);
    assert_true(plain.R_se_Ohm > plain.R_se_max_Ohm);
}

/* At 666.7 r/min (33.3 Hz) a 5 ms batch is one whole period of the 6th
 * harmonic: C6_i = S6_i = 0, the 6th is not conditioned and the fit keeps
 * (1, C, S) alone (1/6 turn per batch), exact for a first harmonic. */
static void sixth_harmonic_left_out_on_whole_periods(void **state)
{
    (void)state;
    rs_ident_out_t o;
    const double w = op_w_el(2000.0 / 3.0); /* 33.3 Hz electrical: the 6th at 200 Hz, one per 5 ms batch */
    rs_ident_t ri = make(R_NOM);
    feed_ripple(&ri, RS_IDENT_WINDOW_1, 1.85, w, true, RIPPLE_1_V, 1.0);
    feed_ripple(&ri, RS_IDENT_WINDOW_2, 3.7, w, true, RIPPLE_1_V, 1.0);
    assert_int_equal(rs_ident_solve(&ri, &o), RS_IDENT_OK);
    assert_true(o.ripple_fit[0] && o.ripple_fit[1]);
    assert_false(o.ripple6_fit[0] || o.ripple6_fit[1]);
    assert_float_equal(o.R_est_Ohm, OP_R0, 1e-3 * OP_R0);
    assert_true(o.R_se_Ohm < 1e-3);
}

/* Window 1 while iq still ramps at 20 A/s (a slow speed loop), L^ = 1.5
 * L0: fq^ carries -dL diq/dt = -0.11 V, fd^ = dL w iq (corrected_model_design.md sec. 2, id = 0).
 * By hand the bias in R^ without the correction is dL s / (iq2 - iq1)
 * (equal speeds): 0.0055 x 20 / 1.85 = 0.059 Ohm (2 %); with Ts given the
 * least-squares slope of iq's batch means (exact for a ramp) and the
 * estimated dL take it out. */
static void feed_ramp(rs_ident_t *ri, rs_ident_window_t win, double iq0, double slope, double w)
{
    const double dR = R_NOM - OP_R0;
    const double dL = 0.5 * OP_L0;
    for (int k = 0; k < 600; k++) {
        const double iq = iq0 + slope * OP_TS * k;
        rs_ident_step(ri, win, (float)(dL * w * iq), (float)(-dR * iq - dL * slope), 0.0f, (float)iq, (float)w);
    }
}

static void settling_window_is_corrected_by_its_mean_slope(void **state)
{
    (void)state;
    rs_ident_out_t o;
    rs_ident_cfg_t c;
    rs_ident_t ri;
    const double w = op_w_el(500.0);
    const double s = 20.0;
    const double bias = 0.5 * OP_L0 * s / 1.85;

    rs_ident_cfg_defaults(&c, (float)R_NOM);
    assert_true(rs_ident_init(&ri, &c)); /* Ts_s = 0: no correction */
    feed_ramp(&ri, RS_IDENT_WINDOW_1, 1.85 - 0.5 * s * 0.06, s, w);
    feed_ramp(&ri, RS_IDENT_WINDOW_2, 3.7, 0.0, w);
    (void)rs_ident_solve(&ri, &o);
    const double R_plain = R_NOM - o.dR_Ohm;
    c.Ts_s = (float)OP_TS;
    assert_true(rs_ident_init(&ri, &c));
    feed_ramp(&ri, RS_IDENT_WINDOW_1, 1.85 - 0.5 * s * 0.06, s, w);
    feed_ramp(&ri, RS_IDENT_WINDOW_2, 3.7, 0.0, w);
    assert_int_equal(rs_ident_solve(&ri, &o), RS_IDENT_OK);
    printf("    iq ramping 20 A/s in window 1, L^ = 1.5 L0: R^ %.4f Ohm uncorrected (hand %.4f), %.5f corrected; "
           "slope %.2f A/s, dL %.3e H\n", R_plain, OP_R0 + bias, o.R_est_Ohm, o.diq_dt_A_s[0], o.dL_H);
    assert_float_equal(R_plain, OP_R0 + bias, 0.01 * bias);
    assert_float_equal(o.diq_dt_A_s[0], s, 0.01 * s);
    assert_float_equal(o.diq_dt_A_s[1], 0.0, 1e-3);
    assert_float_equal(o.R_est_Ohm, OP_R0, 1e-3 * OP_R0);
    c.Ts_s = -1e-4f;
    assert_false(rs_ident_init(&ri, &c));
}

/* A scatter that follows the model (iq and fq^ moving together, as in a
 * speed-loop ripple) is no uncertainty: the residual stays 0. The std of
 * iq comes from sums relative to the first sample: exact at a large
 * offset, where float sum(x^2) - n mean^2 would be all rounding. */
static void scatter_along_the_model_is_taken(void **state)
{
    (void)state;
    rs_ident_out_t o;
    const double w = op_w_el(500.0);
    rs_ident_t ri = make(R_NOM);
    feed_analytic(&ri, RS_IDENT_WINDOW_1, R_NOM, OP_L0, OP_PSI0, 0.0, 1.85, w, 500);
    for (int k = 0; k < 500; k++) {
        const double iq = 3.7 + (((k / 20) & 1) ? 0.3 : -0.3);
        rs_ident_step(&ri, RS_IDENT_WINDOW_2, 0.0f, (float)(-(R_NOM - OP_R0) * iq), 0.0f,
                      (float)iq, (float)w);
    }
    assert_int_equal(rs_ident_solve(&ri, &o), RS_IDENT_OK);
    assert_float_equal(o.iq_std_A[1], 0.3, 1e-3);
    assert_true(o.R_se_Ohm < 1e-4);
    assert_float_equal(o.R_est_Ohm, OP_R0, 1e-3);

    rs_ident_reset(&ri);
    for (int k = 0; k < 1000; k++) {
        const double iq = 1000.0 + ((k & 1) ? 0.01 : -0.01);
        rs_ident_step(&ri, RS_IDENT_WINDOW_1, 0.0f, 0.0f, 0.0f, (float)iq, (float)w);
    }
    feed_analytic(&ri, RS_IDENT_WINDOW_2, R_NOM, OP_L0, OP_PSI0, 0.0, 3.7, w, 500);
    (void)rs_ident_solve(&ri, &o);
    assert_float_equal(o.iq_std_A[0], 0.01, 0.001); /* float spacing at 1000 A is 6e-5 */
    assert_float_equal(o.iq_std_A[1], 0.0, 1e-6);
}

/* R^ outside the band [0.1, 6] x R_nom: refused with the value in dR and
 * R_raw_Ohm (R_est_Ohm stays R_nom). */
static void out_of_band_is_refused(void **state)
{
    (void)state;
    rs_ident_out_t o;
    const double w = op_w_el(500.0);
    /* true R0 = 3, observer nominal 20x: R^ = 0.05 R_nom */
    rs_ident_t ri = make(20.0 * OP_R0);
    feed_analytic(&ri, RS_IDENT_WINDOW_1, 20.0 * OP_R0, OP_L0, OP_PSI0, 0.0, 1.85, w, 500);
    feed_analytic(&ri, RS_IDENT_WINDOW_2, 20.0 * OP_R0, OP_L0, OP_PSI0, 0.0, 3.7, w, 500);
    assert_int_equal(rs_ident_solve(&ri, &o), RS_IDENT_OUT_OF_BAND);
    assert_float_equal(o.R_est_Ohm, 20.0 * OP_R0, 1e-4);
    assert_float_equal(o.dR_Ohm, 19.0 * OP_R0, 1e-3);
    assert_float_equal(o.R_raw_Ohm, OP_R0, 1e-3); /* the refused R^ itself: the motor's */
    /* observer nominal 0.1 R0: R^ = 10 R_nom */
    ri = make(0.1 * OP_R0);
    feed_analytic(&ri, RS_IDENT_WINDOW_1, 0.1 * OP_R0, OP_L0, OP_PSI0, 0.0, 1.85, w, 500);
    feed_analytic(&ri, RS_IDENT_WINDOW_2, 0.1 * OP_R0, OP_L0, OP_PSI0, 0.0, 3.7, w, 500);
    assert_int_equal(rs_ident_solve(&ri, &o), RS_IDENT_OUT_OF_BAND);
}

/* Too few samples, NaN in a window, an invalid cfg, samples outside a
 * window ignored. */
static void other_refusals(void **state)
{
    (void)state;
    rs_ident_out_t o;
    const double w = op_w_el(500.0);
    rs_ident_t ri = make(R_NOM);
    feed_analytic(&ri, RS_IDENT_WINDOW_1, R_NOM, OP_L0, OP_PSI0, 0.0, 1.85, w, 500);
    feed_analytic(&ri, RS_IDENT_WINDOW_2, R_NOM, OP_L0, OP_PSI0, 0.0, 3.7, w, 50);
    assert_int_equal(rs_ident_solve(&ri, &o), RS_IDENT_TOO_FEW);
    feed_analytic(&ri, RS_IDENT_WINDOW_NONE, R_NOM, OP_L0, OP_PSI0, 0.0, 100.0, w, 500);
    assert_int_equal(rs_ident_solve(&ri, &o), RS_IDENT_TOO_FEW);
    feed_analytic(&ri, RS_IDENT_WINDOW_2, R_NOM, OP_L0, OP_PSI0, 0.0, 3.7, w, 450);
    assert_int_equal(rs_ident_solve(&ri, &o), RS_IDENT_OK);
    rs_ident_step(&ri, RS_IDENT_WINDOW_2, NAN, 0.0f, 0.0f, 3.7f, (float)w);
    assert_int_equal(rs_ident_solve(&ri, &o), RS_IDENT_NON_FINITE);
    assert_float_equal(o.R_est_Ohm, R_NOM, 1e-5);

    rs_ident_cfg_t c;
    rs_ident_cfg_defaults(&c, (float)R_NOM);
    c.den_ratio_min = 1.5f;
    assert_false(rs_ident_init(&ri, &c));
    assert_int_equal(rs_ident_solve(&ri, &o), RS_IDENT_INVALID_CFG);
    rs_ident_cfg_defaults(&c, (float)R_NOM);
    c.n_batch = 1u;
    assert_false(rs_ident_init(&ri, &c));
    rs_ident_cfg_defaults(&c, (float)R_NOM);
    c.R_se_max_rel = 0.0f;
    assert_false(rs_ident_init(&ri, &c));
    rs_ident_cfg_defaults(&c, (float)R_NOM);
    c.R_max_Ohm = (float)(0.5 * R_NOM);
    assert_false(rs_ident_init(&ri, &c));
    rs_ident_cfg_defaults(&c, NAN);
    assert_false(rs_ident_init(&ri, &c));
}

/* The staged solve: done after exactly RS_IDENT_SOLVE_STAGES calls, OK
 * or refused in its first stage, with rs_ident_solve's result and *out
 * (the paper case's R^ as analytic_paper_case checks it); more calls
 * change nothing. */
static void staged_solve_takes_its_stages(void **state)
{
    (void)state;
    const double w = op_w_el(500.0);
    rs_ident_t ri = make(R_NOM);
    feed_analytic(&ri, RS_IDENT_WINDOW_1, R_NOM, OP_L0, OP_PSI0, 0.0, op_iq_of_te(2.0), w, 500);
    for (int pass = 0; pass < 2; pass++) {
        rs_ident_out_t whole, staged;
        rs_ident_solver_t s;
        memset(&whole, 0, sizeof whole); /* the padding compared too */
        memset(&staged, 0, sizeof staged);
        const rs_ident_result_t r = rs_ident_solve(&ri, &whole);
        assert_int_equal(r, (pass == 0) ? RS_IDENT_TOO_FEW : RS_IDENT_OK);
        rs_ident_solve_begin(&s, &ri, NULL);
        for (unsigned k = 1u; k < RS_IDENT_SOLVE_STAGES; k++) {
            assert_false(rs_ident_solve_step(&s, &staged));
        }
        assert_true(rs_ident_solve_step(&s, &staged));
        assert_int_equal(s.result, r);
        assert_memory_equal(&staged, &whole, sizeof whole);
        assert_true(rs_ident_solve_step(&s, &staged));
        assert_int_equal(s.result, r);
        assert_memory_equal(&staged, &whole, sizeof whole);
        /* window 2 for the second pass */
        feed_analytic(&ri, RS_IDENT_WINDOW_2, R_NOM, OP_L0, OP_PSI0, 0.0, op_iq_of_te(4.0), w, 500);
    }
}

/* A staged solve begun at a batch boundary of window 2, whose sample sums
 * are copied (rs_ident_copy_head) while window 2 goes on filling for every
 * stage (with other values, a batch not yet complete: n_batch >
 * RS_IDENT_SOLVE_STAGES), gives rs_ident_solve's *out as at the begin: the
 * 6th-harmonic fit on both windows. Inside a batch no begin is allowed. */
static void staged_solve_holds_while_window_2_fills(void **state)
{
    (void)state;
    const double w = op_w_el(200.0);
    rs_ident_t ri = make(R_NOM);
    rs_ident_out_t whole, staged;
    rs_ident_solver_t s;
    rs_ident_head_t head;

    feed_ripple(&ri, RS_IDENT_WINDOW_1, op_iq_of_te(2.0), w, true, RIPPLE_6_V, 6.0);
    feed_ripple(&ri, RS_IDENT_WINDOW_2, op_iq_of_te(4.0), w, true, RIPPLE_6_V, 6.0);
    assert_true(rs_ident_batch_closed(&ri, RS_IDENT_WINDOW_2)); /* 600 samples: 12 whole batches */
    memset(&whole, 0, sizeof whole);
    memset(&staged, 0, sizeof staged);
    assert_int_equal(rs_ident_solve(&ri, &whole), RS_IDENT_OK);
    assert_true(whole.ripple6_fit[0] && whole.ripple6_fit[1]);
    rs_ident_copy_head(&head, &ri, RS_IDENT_WINDOW_2);
    rs_ident_solve_begin(&s, &ri, &head);
    for (unsigned k = 0u; k < RS_IDENT_SOLVE_STAGES; k++) {
        rs_ident_step_el(&ri, RS_IDENT_WINDOW_2, 1.0f, 2.0f, 3.0f, 4.0f, 5.0f, 1.0f, 0.0f);
        assert_false(rs_ident_batch_closed(&ri, RS_IDENT_WINDOW_2));
        assert_true(rs_ident_solve_step(&s, &staged) == (k + 1u == RS_IDENT_SOLVE_STAGES));
    }
    assert_int_equal(s.result, RS_IDENT_OK);
    assert_memory_equal(&staged, &whole, sizeof whole);
    /* and batches as short as the stages are refused */
    rs_ident_cfg_t c;
    rs_ident_cfg_defaults(&c, (float)R_NOM);
    c.n_batch = RS_IDENT_SOLVE_STAGES;
    assert_false(rs_ident_init(&ri, &c));
    c.n_batch = RS_IDENT_SOLVE_STAGES + 1u;
    assert_true(rs_ident_init(&ri, &c));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(analytic_paper_case),
        cmocka_unit_test(analytic_all_mismatched_and_two_speeds),
        cmocka_unit_test(plant_and_observer_paper_case),
        cmocka_unit_test(equal_operating_points_are_degenerate),
        cmocka_unit_test(scattered_window_is_refused_by_its_standard_error),
        cmocka_unit_test(electrical_ripple_is_fitted_not_counted_as_noise),
        cmocka_unit_test(sixth_harmonic_ripple_is_fitted_not_counted_as_noise),
        cmocka_unit_test(sixth_harmonic_left_out_on_whole_periods),
        cmocka_unit_test(settling_window_is_corrected_by_its_mean_slope),
        cmocka_unit_test(scatter_along_the_model_is_taken),
        cmocka_unit_test(out_of_band_is_refused),
        cmocka_unit_test(other_refusals),
        cmocka_unit_test(staged_solve_takes_its_stages),
        cmocka_unit_test(staged_solve_holds_while_window_2_fills),
    };
    return cmocka_run_group_tests_name("rs_ident", tests, NULL, NULL);
}
