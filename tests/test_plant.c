/* Unit tests for hal/sim/plant.c against closed-form expectations:
 * the locked-rotor RL step, the analytic dq steady state under load, and
 * the energy balance over a transient (integrated here, by trapezoid);
 * the period solver against an independent fine RK4 of eqs. (1)-(3) in
 * the rotor frame, through switching periods with large accelerations;
 * the gates off (the diode bridge, plant_design.md sec. 9): no current
 * below the speed where the line back-EMF reaches the bus, the braking
 * torque of the quasi-static bridge (L -> 0) in closed form above it, and
 * the power balance (shaft = bus + copper + diodes) at the motor's L. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>
#include <stdlib.h>

#include "plant.h"
#include "table1.h"

#define REL_TOL 0.005            /* 0.5 % */
#define STEP_S 1.0e-6
#define TWO_PI 6.283185307179586

static double rel_err(double x, double ref)
{
    return fabs(x - ref) / fabs(ref);
}

/* Apply the rotor-frame voltage (ud, uq) for one step: stator frame at the step's mid angle. */
static void step_dq(plant_t *p, double ud_V, double uq_V, double TL_Nm, double h_s)
{
    double th = plant_theta_el_rad(p) + 0.5 * h_s * (double)p->cfg.pole_pairs * p->x.omega_m_rad_s;
    double s = sin(th);
    double c = cos(th);
    plant_step(p, ud_V * c - uq_V * s, ud_V * s + uq_V * c, TL_Nm, h_s);
}

/* Locked rotor, d-axis voltage step U: id(t) = U/R (1 - exp(-t R/L)), iq stays 0. */
static void locked_rotor_d_step_is_first_order(void **state)
{
    (void)state;
    const double U_V = 30.0;
    plant_cfg_t cfg = table1_plant();
    cfg.speed_held = true;
    plant_t p;
    plant_init(&p, &cfg, 0.0);
    const double tau_s = cfg.L_H / cfg.R_Ohm;
    const double check_every_s = 0.5e-3;
    const int n = (int)lround(5.0 * tau_s / STEP_S);
    double worst = 0.0;
    for (int k = 1; k <= n; k++) {
        step_dq(&p, U_V, 0.0, 0.0, STEP_S);
        double t = (double)k * STEP_S;
        if (fmod(t, check_every_s) < STEP_S / 2.0) {
            double expect = U_V / cfg.R_Ohm * (1.0 - exp(-t / tau_s));
            double e = rel_err(p.x.id_A, expect);
            worst = (e > worst) ? e : worst;
            assert_true(e < REL_TOL);
            assert_true(fabs(p.x.iq_A) < REL_TOL * expect);
        }
    }
    print_message("locked-rotor step: worst relative error %.3g\n", worst);
}

/* Locked rotor, id in steady state at U/R1; R changed to R2 (a warm
 * winding): id moves to U/R2 with the time constant L/R2. Non-positive or
 * non-finite R is ignored. */
static void resistance_change_takes_effect(void **state)
{
    (void)state;
    const double U_V = 30.0;
    const double R2_ohm = 3.9;
    plant_cfg_t cfg = table1_plant();
    cfg.speed_held = true;
    plant_t p;
    plant_init(&p, &cfg, 0.0);
    p.x.id_A = U_V / cfg.R_Ohm;
    plant_set_R_Ohm(&p, 0.0);
    plant_set_R_Ohm(&p, NAN);
    assert_float_equal(p.cfg.R_Ohm, cfg.R_Ohm, 0.0);
    plant_set_R_Ohm(&p, R2_ohm);
    const double tau_s = cfg.L_H / R2_ohm;
    const int n = (int)lround(tau_s / STEP_S);
    for (int k = 0; k < n; k++) {
        step_dq(&p, U_V, 0.0, 0.0, STEP_S);
    }
    const double t = (double)n * STEP_S;
    const double expect = U_V / R2_ohm + (U_V / cfg.R_Ohm - U_V / R2_ohm) * exp(-t / tau_s);
    assert_true(rel_err(p.x.id_A, expect) < REL_TOL);
}

/* Constant (ud = 0, uq) with load TL, B = 0: at steady state Te = TL, so
 * iq = TL / (1.5 p psi_f); ud = 0 gives id = w L iq / R; the q equation
 * uq = R iq + w psi_f + w^2 L^2 iq / R is a quadratic in w (electrical). */
static void steady_state_under_load_matches_analytic(void **state)
{
    (void)state;
    const double uq_V = 60.0;
    const double TL_Nm = 2.0;
    const double run_s = 0.5;
    const double h_s = 10.0e-6;
    plant_cfg_t cfg = table1_plant();
    plant_t p;
    plant_init(&p, &cfg, 0.0);
    for (int k = 0; k < (int)lround(run_s / h_s); k++) {
        step_dq(&p, 0.0, uq_V, TL_Nm, h_s);
    }
    const double pp = (double)cfg.pole_pairs;
    const double iq = TL_Nm / (1.5 * pp * cfg.psi_f_Wb);
    const double a = cfg.L_H * cfg.L_H * iq / cfg.R_Ohm;
    const double b = cfg.psi_f_Wb;
    const double c = cfg.R_Ohm * iq - uq_V;
    const double w_el = (-b + sqrt(b * b - 4.0 * a * c)) / (2.0 * a);
    const double id = w_el * cfg.L_H * iq / cfg.R_Ohm;
    const double w_m = w_el / pp;
    print_message("steady state: w_m %.4f (analytic %.4f), id %.4f (%.4f), iq %.4f (%.4f)\n",
                  p.x.omega_m_rad_s, w_m, p.x.id_A, id, p.x.iq_A, iq);
    print_message("steady state: relative errors w %.3g id %.3g iq %.3g\n",
                  rel_err(p.x.omega_m_rad_s, w_m), rel_err(p.x.id_A, id), rel_err(p.x.iq_A, iq));
    assert_true(rel_err(p.x.omega_m_rad_s, w_m) < REL_TOL);
    assert_true(rel_err(p.x.id_A, id) < REL_TOL);
    assert_true(rel_err(p.x.iq_A, iq) < REL_TOL);
}

/* Electrical input = copper loss + load and friction work + change of
 * magnetic (0.75 L |i|^2) and kinetic (0.5 J w^2) energy, over a start-up. */
static void energy_balance_over_transient(void **state)
{
    (void)state;
    const double ud_V = 10.0;
    const double uq_V = 50.0;
    const double TL_Nm = 1.0;
    const double run_s = 0.05;
    plant_cfg_t cfg = table1_plant();
    cfg.B_Nms = 1.0e-3;
    plant_t p;
    plant_init(&p, &cfg, 0.3);

    double e_in = 0.0;
    double e_cu = 0.0;
    double e_mech = 0.0;
    const double R = cfg.R_Ohm;
    for (int k = 0; k < (int)lround(run_s / STEP_S); k++) {
        double th = plant_theta_el_rad(&p) + 0.5 * STEP_S * (double)cfg.pole_pairs * p.x.omega_m_rad_s;
        double ua = ud_V * cos(th) - uq_V * sin(th);
        double ub = ud_V * sin(th) + uq_V * cos(th);
        double i0[3];
        plant_iabc_A(&p, i0);
        double i2_0 = p.x.id_A * p.x.id_A + p.x.iq_A * p.x.iq_A;
        double w0 = p.x.omega_m_rad_s;
        plant_step(&p, ua, ub, TL_Nm, STEP_S);
        double i1[3];
        plant_iabc_A(&p, i1);
        double i2_1 = p.x.id_A * p.x.id_A + p.x.iq_A * p.x.iq_A;
        double w1 = p.x.omega_m_rad_s;
        /* p = 1.5 (ua ialpha + ub ibeta), ibeta = (ia + 2 ib)/sqrt(3) */
        double pin0 = 1.5 * (ua * i0[0] + ub * (i0[0] + 2.0 * i0[1]) / sqrt(3.0));
        double pin1 = 1.5 * (ua * i1[0] + ub * (i1[0] + 2.0 * i1[1]) / sqrt(3.0));
        e_in += 0.5 * STEP_S * (pin0 + pin1);
        e_cu += 0.5 * STEP_S * 1.5 * R * (i2_0 + i2_1);
        e_mech += 0.5 * STEP_S * (TL_Nm * (w0 + w1) + cfg.B_Nms * (w0 * w0 + w1 * w1));
    }
    double e_mag = 0.75 * cfg.L_H * (p.x.id_A * p.x.id_A + p.x.iq_A * p.x.iq_A);
    double e_kin = 0.5 * cfg.J_kgm2 * p.x.omega_m_rad_s * p.x.omega_m_rad_s;
    double out = e_cu + e_mech + e_mag + e_kin;
    print_message("energy: in %.5f J, cu %.5f, mech %.5f, mag %.5f, kin %.5f, residual %.3g\n",
                  e_in, e_cu, e_mech, e_mag, e_kin, rel_err(out, e_in));
    assert_true(e_kin > 0.1 * e_in);   /* a real transient: the shaft took a share */
    assert_true(rel_err(out, e_in) < REL_TOL);
}

/* Angle stays in [0, 2 pi) and torque/flux follow the state over many turns. */
static void angle_wraps_and_outputs_follow_state(void **state)
{
    (void)state;
    plant_cfg_t cfg = table1_plant();
    cfg.speed_held = true;
    cfg.omega0_m_rad_s = -200.0;
    plant_t p;
    plant_init(&p, &cfg, 0.0);
    double angle = 0.0;
    const double h_s = 1.0e-4;
    for (int k = 0; k < 1000; k++) {
        plant_step(&p, 0.0, 0.0, 0.0, h_s);
        angle += cfg.omega0_m_rad_s * h_s;
        assert_true(p.x.theta_m_rad >= 0.0 && p.x.theta_m_rad < TWO_PI);
        assert_true(plant_theta_el_rad(&p) >= 0.0 && plant_theta_el_rad(&p) < TWO_PI);
    }
    double expect = fmod(angle, TWO_PI) + TWO_PI;
    assert_float_equal(p.x.theta_m_rad, expect, 1e-9);
    assert_float_equal(plant_te_Nm(&p), 1.5 * 3.0 * 0.24 * p.x.iq_A, 1e-12);
    double psi_d = cfg.L_H * p.x.id_A + cfg.psi_f_Wb;
    double psi_q = cfg.L_H * p.x.iq_A;
    assert_float_equal(plant_psi_s_Wb(&p), sqrt(psi_d * psi_d + psi_q * psi_q), 1e-12);
}

/* The motor the tests (and drive_sil) give the plant is the paper's Table I
 * in exactly the doubles of its decimals: the parameter set's floats reach
 * the double plant as the decimals board_cfg.h spells (0.011f as 0.011). */
static void table1_plant_is_the_papers_table(void **state)
{
    (void)state;
    const plant_cfg_t cfg = table1_plant();
    assert_true(cfg.R_Ohm == 3.0);
    assert_true(cfg.L_H == 0.011);
    assert_true(cfg.psi_f_Wb == 0.24);
    assert_int_equal(cfg.pole_pairs, 3u);
    assert_true(cfg.J_kgm2 == 0.00129);
    assert_true(cfg.B_Nms == 0.0);
    assert_false(cfg.speed_held);
    assert_true(cfg.omega0_m_rad_s == 0.0);
}


/* ---- the period solver against a fine RK4 of the dq model -------------- */

#define REF_VDC_V 311.0
#define REF_STEP_S 5.0e-8   /* RK4's local error (|c| h)^5 / 120 is below 1e-20 */
#define REF_OFFSET_EL_RAD 0.3   /* the d axis's electrical angle at theta_m = 0 */

/* The dq model, eqs. (1)-(3), the stator voltage turned into the rotor frame at theta_el. */
typedef struct {
    double id, iq, w_m, th_m;
} ref_x_t;

static void ref_deriv(const plant_cfg_t *c, const ref_x_t *x, double ua, double ub, double TL, ref_x_t *dx)
{
    const double pp = (double)c->pole_pairs;
    const double th = pp * x->th_m + REF_OFFSET_EL_RAD;
    const double w = pp * x->w_m;
    const double ud = ua * cos(th) + ub * sin(th);
    const double uq = -ua * sin(th) + ub * cos(th);
    dx->id = (ud - c->R_Ohm * x->id + w * c->L_H * x->iq) / c->L_H;
    dx->iq = (uq - c->R_Ohm * x->iq - w * (c->L_H * x->id + c->psi_f_Wb)) / c->L_H;
    dx->w_m = c->speed_held ? 0.0 : (1.5 * pp * c->psi_f_Wb * x->iq - TL - c->B_Nms * x->w_m) / c->J_kgm2;
    dx->th_m = x->w_m;
}

static void ref_axpy(const ref_x_t *x, double h, const ref_x_t *d, ref_x_t *y)
{
    y->id = x->id + h * d->id;
    y->iq = x->iq + h * d->iq;
    y->w_m = x->w_m + h * d->w_m;
    y->th_m = x->th_m + h * d->th_m;
}

/* One RK4 step; also the step's integrals of id, iq (Simpson on the stages). */
static void ref_rk4(const plant_cfg_t *c, ref_x_t *x, double ua, double ub, double TL, double h, double *id_s, double *iq_s)
{
    ref_x_t k1, k2, k3, k4, y;
    ref_deriv(c, x, ua, ub, TL, &k1);
    ref_axpy(x, 0.5 * h, &k1, &y);
    const double id2 = y.id, iq2 = y.iq;
    ref_deriv(c, &y, ua, ub, TL, &k2);
    ref_axpy(x, 0.5 * h, &k2, &y);
    const double id3 = y.id, iq3 = y.iq;
    ref_deriv(c, &y, ua, ub, TL, &k3);
    ref_axpy(x, h, &k3, &y);
    *id_s += h * (x->id + 2.0 * id2 + 2.0 * id3 + y.id) / 6.0;
    *iq_s += h * (x->iq + 2.0 * iq2 + 2.0 * iq3 + y.iq) / 6.0;
    ref_deriv(c, &y, ua, ub, TL, &k4);
    x->id += h * (k1.id + 2.0 * k2.id + 2.0 * k3.id + k4.id) / 6.0;
    x->iq += h * (k1.iq + 2.0 * k2.iq + 2.0 * k3.iq + k4.iq) / 6.0;
    x->w_m += h * (k1.w_m + 2.0 * k2.w_m + 2.0 * k3.w_m + k4.w_m) / 6.0;
    x->th_m += h * (k1.th_m + 2.0 * k2.th_m + 2.0 * k3.th_m + k4.th_m) / 6.0;
}

static int cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a;
    const double y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Leg k's stator voltage at the bus, the others at 0. */
static void leg_ab(int k, double *ua, double *ub)
{
    static const double ca[3] = { 2.0 / 3.0, -1.0 / 3.0, -1.0 / 3.0 };
    static const double cb[3] = { 0.0, 0.5773502691896258, -0.5773502691896258 };
    *ua = ca[k] * REF_VDC_V;
    *ub = cb[k] * REF_VDC_V;
}

/* A period of T: three legs high over |t - T/2| < d T/2, plus (extra_V != 0)
 * a beta-axis voltage extra_V over [T/8, 3T/8), off the middle. */
typedef struct {
    double T, d[3], extra_V;
} ref_period_t;

static void ref_voltage(const ref_period_t *r, double t, double *ua, double *ub)
{
    *ua = 0.0;
    *ub = 0.0;
    for (int k = 0; k < 3; k++) {
        if (fabs(t - 0.5 * r->T) < r->d[k] * 0.5 * r->T) {
            double a, b;
            leg_ab(k, &a, &b);
            *ua += a;
            *ub += b;
        }
    }
    if (t >= 0.125 * r->T && t < 0.375 * r->T) {
        *ub += r->extra_V;
    }
}

typedef struct {
    double i_A, mean_A, w_rad_s, th_rad, walk_A;   /* worst differences */
} ref_worst_t;

/* One period through the plant (legs, the extra pulse, the walker at every
 * piece's start) and through RK4 of the dq model at REF_STEP_S. */
static void ref_period(plant_t *p, ref_x_t *x, const ref_period_t *r, double TL, ref_worst_t *wst)
{
    const plant_cfg_t *cfg = &p->cfg;
    const double pp = (double)cfg->pole_pairs;
    const double tau = 0.5 * r->T;
    plant_acc_clear(p);
    plant_period_begin(p, r->T, TL);
    const double half[3] = { r->d[0] * tau, r->d[1] * tau, r->d[2] * tau };
    plant_period_legs(p, REF_VDC_V, half);
    if (r->extra_V != 0.0) {
        assert_true(plant_period_pulse(p, 0.0, r->extra_V, -0.5 * tau, 0.25 * tau));
    }
    double br[9];
    int nb = 0;
    for (int k = 0; k < 3; k++) {
        br[nb++] = (1.0 - r->d[k]) * tau;
        br[nb++] = (1.0 + r->d[k]) * tau;
    }
    br[nb++] = 0.125 * r->T;
    br[nb++] = 0.375 * r->T;
    br[nb++] = r->T;
    qsort(br, (size_t)nb, sizeof br[0], cmp_double);
    double id_s = 0.0, iq_s = 0.0;
    double t0 = 0.0;
    for (int j = 0; j < nb; j++) {
        const double t1 = br[j];
        if (!(t1 > t0)) {
            continue;
        }
        double i_abc[3];
        plant_walk_iabc_A(p, i_abc);
        const double thr = pp * x->th_m + REF_OFFSET_EL_RAD;
        wst->walk_A = fmax(wst->walk_A, fabs(i_abc[0] - (x->id * cos(thr) - x->iq * sin(thr))));
        double u_a, u_b;
        ref_voltage(r, 0.5 * (t0 + t1), &u_a, &u_b);
        plant_walk_advance(p, u_a, u_b, t1);
        const int steps = (int)ceil((t1 - t0) / REF_STEP_S);
        for (int s = 0; s < steps; s++) {
            ref_rk4(cfg, x, u_a, u_b, TL, (t1 - t0) / steps, &id_s, &iq_s);
        }
        t0 = t1;
    }
    plant_period_end(p);
    wst->i_A = fmax(wst->i_A, fmax(fabs(p->x.id_A - x->id), fabs(p->x.iq_A - x->iq)));
    wst->w_rad_s = fmax(wst->w_rad_s, fabs(p->x.omega_m_rad_s - x->w_m));
    double dth = p->x.theta_m_rad - fmod(x->th_m, TWO_PI);
    dth -= TWO_PI * round(dth / TWO_PI);
    wst->th_rad = fmax(wst->th_rad, fabs(dth));
    wst->mean_A = fmax(wst->mean_A, fmax(fabs(p->acc.id_As - id_s), fabs(p->acc.iq_As - iq_s)) / r->T);
}

/* Duties of a rotor-frame voltage (ud, uq) at the period's middle angle, clamped. */
static void ref_duties(const plant_cfg_t *c, const ref_x_t *x, double T, double ud, double uq, double d[3])
{
    const double pp = (double)c->pole_pairs;
    const double th = pp * (x->th_m + 0.5 * T * x->w_m) + REF_OFFSET_EL_RAD;
    const double ua = ud * cos(th) - uq * sin(th);
    const double ub = ud * sin(th) + uq * cos(th);
    const double v[3] = { ua, -0.5 * ua + 0.8660254037844386 * ub, -0.5 * ua - 0.8660254037844386 * ub };
    for (int k = 0; k < 3; k++) {
        d[k] = fmin(fmax(0.5 + v[k] / REF_VDC_V, 0.0), 1.0);
    }
}

/* From 20 rad/s, a rotating voltage of rising amplitude in switching
 * periods of 100 us (three centred leg pulses, and an off-centre pulse in
 * every fourth), the load stepping 0.5 -> 3 N m: the shaft accelerates at
 * up to 2000 rad/s^2. Error bound (hal/sim/plant_design.md sec. 5): the
 * solver neglects the acceleration's change inside the period, (psi_f/L)
 * |d alpha_el/dt| tau^4 ~ 1e-8 A a period, forgotten with L/R (37 periods):
 * under 4e-7 A. The tolerances are that with a margin: 1e-6 A (currents,
 * period means), and what it does to the shaft over the run. */
static void period_solver_matches_fine_rk4(void **state)
{
    (void)state;
    const double tol_i_A = 1.0e-6;
    const double tol_w_rad_s = 1.0e-5;
    const double tol_th_rad = 1.0e-7;
    /* the walker holds the acceleration of the period's start: its error is
     * (psi_f/L) |d alpha_el/dt| tau^3 / 6 <= 21.8 A/rad x (3 x 837 x 28000) rad/s^3 x
     * 1.25e-13 s^3 / 6 = 3.2e-5 A (|diq/dt| <= Vdc/L); it only decides current signs */
    const double tol_walk_A = 5.0e-5;
    const int periods = 300;
    plant_cfg_t cfg = table1_plant();
    cfg.omega0_m_rad_s = 20.0;
    plant_t p;
    plant_init(&p, &cfg, REF_OFFSET_EL_RAD);
    ref_x_t x = { 0.0, 0.0, cfg.omega0_m_rad_s, 0.0 };
    ref_worst_t wst = { 0.0, 0.0, 0.0, 0.0, 0.0 };
    for (int n = 0; n < periods; n++) {
        ref_period_t r = { 1.0e-4, { 0.0, 0.0, 0.0 }, (n % 4 == 0) ? 20.0 : 0.0 };
        ref_duties(&cfg, &x, r.T, -20.0 + 5.0 * sin(0.1 * n), 40.0 + 0.4 * n, r.d);
        ref_period(&p, &x, &r, (n < periods / 2) ? 0.5 : 3.0, &wst);
    }
    print_message("period solver vs RK4 at 50 ns steps: |di| %.3g A, |dw| %.3g rad/s, |dtheta| %.3g rad, "
                  "|d mean i| %.3g A, walker %.3g A; final speed %.1f rad/s, iq %.2f A\n",
                  wst.i_A, wst.w_rad_s, wst.th_rad, wst.mean_A, wst.walk_A, x.w_m, x.iq);
    assert_true(x.w_m > 100.0);   /* a real run-up */
    assert_true(wst.i_A < tol_i_A);
    assert_true(wst.mean_A < tol_i_A);
    assert_true(wst.w_rad_s < tol_w_rad_s);
    assert_true(wst.th_rad < tol_th_rad);
    assert_true(wst.walk_A < tol_walk_A);
}

/* Periods of 1 ms at a held 1000 r/min: w_el tau = 0.16 and a tau = 0.14,
 * beyond the short series (SERIES_MAX 0.1), so the solver takes libm and
 * sums pulse by pulse; at a held speed it is exact, so the tolerance is
 * rounding's (1e-9 A) over the RK4's. */
static void period_solver_exact_at_held_speed_beyond_the_series(void **state)
{
    (void)state;
    const double tol_A = 1.0e-9;
    plant_cfg_t cfg = table1_plant();
    cfg.speed_held = true;
    cfg.omega0_m_rad_s = 1000.0 * TWO_PI / 60.0;
    plant_t p;
    plant_init(&p, &cfg, REF_OFFSET_EL_RAD);
    ref_x_t x = { 0.0, 0.0, cfg.omega0_m_rad_s, 0.0 };
    ref_worst_t wst = { 0.0, 0.0, 0.0, 0.0, 0.0 };
    for (int n = 0; n < 12; n++) {
        ref_period_t r = { 1.0e-3, { 0.0, 0.0, 0.0 }, (n % 2 == 0) ? 30.0 : 0.0 };
        ref_duties(&cfg, &x, r.T, -30.0, 120.0, r.d);
        ref_period(&p, &x, &r, 0.0, &wst);
    }
    print_message("1 ms periods at 1000 r/min held vs RK4: |di| %.3g A, |d mean i| %.3g A, walker %.3g A; iq %.2f A\n",
                  wst.i_A, wst.mean_A, wst.walk_A, x.iq);
    assert_true(fabs(x.iq) > 1.0);
    assert_true(wst.i_A < tol_A);
    assert_true(wst.mean_A < tol_A);
    assert_true(wst.walk_A < tol_A);
    assert_true(wst.th_rad < 1e-12);
}

/* ---- the gates off: the diode bridge ---------------------------------- */

#define BUS_V 311.0
#define DROP_V 1.2
#define PERIOD_S 1.0e-4

/* The speed where the line back-EMF's peak sqrt(3) p w psi_f reaches the bus and both drops
 * (sec. 9): below it no diode can conduct. [rad/s mechanical] */
static double bus_limited_speed(const plant_cfg_t *c)
{
    return (BUS_V + 2.0 * DROP_V) / (sqrt(3.0) * (double)c->pole_pairs * c->psi_f_Wb);
}

/* Gates off at a held speed for `periods`, then `avg` more periods averaged: the mean torque,
 * and (pointers may be NULL) the mean power into the bus, the copper's and the diodes'. */
static double rectified_mean(plant_t *p, int periods, int avg, double *p_bus_W, double *p_cu_W, double *p_d_W)
{
    for (int k = 0; k < periods; k++) {
        plant_step_rectified(p, BUS_V, DROP_V, 0.0, PERIOD_S);
    }
    double te = 0.0;
    double bus = 0.0;
    double cu = 0.0;
    double dio = 0.0;
    const int sub = (int)lround(PERIOD_S / PLANT_OFF_SUBSTEP_MAX_S);
    for (int k = 0; k < avg * sub; k++) {
        plant_step_rectified(p, BUS_V, DROP_V, 0.0, PLANT_OFF_SUBSTEP_MAX_S);
        double i[3];
        plant_iabc_A(p, i);
        te += plant_te_Nm(p);
        for (int x = 0; x < 3; x++) {
            bus += BUS_V * fmax(-i[x], 0.0);   /* an upper diode carries -i_x into the bus's + rail */
            cu += p->cfg.R_Ohm * i[x] * i[x];
            dio += DROP_V * fabs(i[x]);
        }
    }
    const double n = (double)(avg * sub);
    if (p_bus_W != NULL) {
        *p_bus_W = bus / n;
        *p_cu_W = cu / n;
        *p_d_W = dio / n;
    }
    return te / n;
}

/* Just below the bus-limited speed every diode blocks (no current at all); just above, the
 * bridge conducts and the torque brakes the shaft (opposes its turning). */
static void diodes_conduct_from_the_bus_limited_speed(void **state)
{
    (void)state;
    const double margin = 0.01;
    plant_cfg_t cfg = table1_plant();
    cfg.speed_held = true;
    const double w_on = bus_limited_speed(&cfg);
    plant_t p;
    cfg.omega0_m_rad_s = (1.0 - margin) * w_on;
    plant_init(&p, &cfg, 0.0);
    const double below = rectified_mean(&p, 2000, 200, NULL, NULL, NULL);
    assert_true(!(p.x.id_A != 0.0) && !(p.x.iq_A != 0.0));
    assert_float_equal(below, 0.0, 0.0);
    cfg.omega0_m_rad_s = (1.0 + margin) * w_on;
    plant_init(&p, &cfg, 0.0);
    const double above = rectified_mean(&p, 2000, 200, NULL, NULL, NULL);
    assert_true(above < 0.0);
    print_message("bus-limited speed %.1f r/min: torque %.3g N m below, %.3g N m 1 %% above\n",
                  w_on * 60.0 / TWO_PI, below, above);
}

/* L -> 0 (L/R 3.3 us against an electrical turn of 5 ms): the bridge is resistive. At
 * E = 1.1 (vdc + 2 vd) (E the line EMF's peak) only the pair with the largest line EMF e_L =
 * E cos(phi) conducts (a third phase joins only above E = 2/sqrt(3) of it), with current
 * (e_L - V) / 2R: the shaft gives P = (3 / (2 pi R)) [E^2 (a + sin a cos a) - 2 E V sin a],
 * a = acos(V / E), averaged over a sixth of the turn; the mean torque is -P / w. */
static void braking_torque_of_the_quasi_static_bridge(void **state)
{
    (void)state;
    const double over = 1.1;
    const double tol = 0.005;
    plant_cfg_t cfg = table1_plant();
    cfg.L_H = 1.0e-5;
    cfg.speed_held = true;
    cfg.omega0_m_rad_s = over * bus_limited_speed(&cfg);
    plant_t p;
    plant_init(&p, &cfg, 0.0);
    const double V = BUS_V + 2.0 * DROP_V;
    const double E = sqrt(3.0) * (double)cfg.pole_pairs * cfg.omega0_m_rad_s * cfg.psi_f_Wb;
    const double a = acos(V / E);
    const double P = 3.0 / (TWO_PI * cfg.R_Ohm) * (E * E * (a + sin(a) * cos(a)) - 2.0 * E * V * sin(a));
    /* an average over whole electrical turns: 1 / (p w) * 2 pi of them, in periods */
    const double turn_s = TWO_PI / ((double)cfg.pole_pairs * cfg.omega0_m_rad_s);
    const int turns = 8;
    const double te = rectified_mean(&p, 100, (int)lround(turns * turn_s / PERIOD_S), NULL, NULL, NULL);
    const double expect = -P / cfg.omega0_m_rad_s;
    print_message("quasi-static bridge at %.0f r/min: torque %.5g N m, closed form %.5g N m\n",
                  cfg.omega0_m_rad_s * 60.0 / TWO_PI, te, expect);
    assert_true(rel_err(te, expect) < tol);
}

/* The motor's own L (L/R 3.7 ms) at 1.3 x the bus-limited speed, in steady state: the power the
 * shaft gives, -Te w, goes into the bus, the copper and the diodes' drops (commutation overlap
 * and all: no closed form, the balance holds whatever the diodes do). */
static void rectified_power_balances(void **state)
{
    (void)state;
    const double over = 1.3;
    const double tol = 0.01;
    plant_cfg_t cfg = table1_plant();
    cfg.speed_held = true;
    cfg.omega0_m_rad_s = over * bus_limited_speed(&cfg);
    plant_t p;
    plant_init(&p, &cfg, 0.0);
    const double turn_s = TWO_PI / ((double)cfg.pole_pairs * cfg.omega0_m_rad_s);
    const int turns = 8;
    double bus;
    double cu;
    double dio;
    const double te = rectified_mean(&p, 3000, (int)lround(turns * turn_s / PERIOD_S), &bus, &cu, &dio);
    const double shaft = -te * cfg.omega0_m_rad_s;
    print_message("at %.0f r/min: shaft %.4g W = bus %.4g + copper %.4g + diodes %.4g W (torque %.4g N m)\n",
                  cfg.omega0_m_rad_s * 60.0 / TWO_PI, shaft, bus, cu, dio, te);
    assert_true(shaft > 0.0);
    assert_true(rel_err(bus + cu + dio, shaft) < tol);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(table1_plant_is_the_papers_table),
        cmocka_unit_test(locked_rotor_d_step_is_first_order),
        cmocka_unit_test(resistance_change_takes_effect),
        cmocka_unit_test(steady_state_under_load_matches_analytic),
        cmocka_unit_test(energy_balance_over_transient),
        cmocka_unit_test(angle_wraps_and_outputs_follow_state),
        cmocka_unit_test(period_solver_matches_fine_rk4),
        cmocka_unit_test(period_solver_exact_at_held_speed_beyond_the_series),
        cmocka_unit_test(diodes_conduct_from_the_bus_limited_speed),
        cmocka_unit_test(braking_torque_of_the_quasi_static_bridge),
        cmocka_unit_test(rectified_power_balances),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
