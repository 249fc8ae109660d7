/* plant.c - true SPMSM and shaft; see plant.h for the model. */
#include "plant.h"
#include "sim_units.h"

#include <math.h>

#define SQRT3 1.7320508075688772
#define TORQUE_FACTOR 1.5   /* amplitude-invariant dq: Te = 1.5 p psi_f iq */

/* Angles within this distance of the anchor use the series below (its
 * truncation is below 3e-17 there), so libm sin/cos is called about once
 * per 0.1 rad instead of once per period (bench target). */
#define ANCHOR_SPAN_RAD 0.1

static void anchor_at(plant_t *p, double theta_el_rad)
{
    p->anchor_el_rad = theta_el_rad;
    p->anchor_sin = sin(theta_el_rad);
    p->anchor_cos = cos(theta_el_rad);
}

void plant_init(plant_t *p, const plant_cfg_t *cfg, double enc_offset_el_rad)
{
    p->cfg = *cfg;
    p->x.id_A = 0.0;
    p->x.iq_A = 0.0;
    p->x.omega_m_rad_s = cfg->omega0_m_rad_s;
    p->x.theta_m_rad = 0.0;
    p->enc_offset_el_rad = enc_offset_el_rad;
    p->inv_L_per_H = 1.0 / cfg->L_H;
    p->inv_J_per_kgm2 = 1.0 / cfg->J_kgm2;
    plant_acc_clear(p);
    p->per.n_pulses = 0;
    p->per.E_key = -1.0;
    p->shaft_prev_valid = false;
    anchor_at(p, enc_offset_el_rad);
    p->z_cos = p->anchor_cos;
    p->z_sin = p->anchor_sin;
}

/* The series for sin/cos near the anchor (host-only code built with gcc
 * or clang: inlined so the constants stay in registers). */
#if defined(__GNUC__)
#define PLANT_INLINE static inline __attribute__((always_inline))
#else
#define PLANT_INLINE static inline
#endif

/* sin and cos of the unwrapped electrical angle theta_el_rad, from the anchor of *p (moved when too far). */
PLANT_INLINE void sincos_el(plant_t *p, double theta_el_rad, double *s, double *c)
{
    double d = theta_el_rad - p->anchor_el_rad;
    if (fabs(d) > ANCHOR_SPAN_RAD) {
        anchor_at(p, theta_el_rad);
        d = 0.0;
    }
    /* Taylor series to d^8 and d^9, nested (truncation below 3e-17 at the
     * span); constant reciprocals fold, so no division. */
    double d2 = d * d;
    double cd = 1.0 - d2 * (1.0 / 2.0) *
                          (1.0 - d2 * (1.0 / 12.0) * (1.0 - d2 * (1.0 / 30.0) * (1.0 - d2 * (1.0 / 56.0))));
    double sd = d * (1.0 - d2 * (1.0 / 6.0) *
                               (1.0 - d2 * (1.0 / 20.0) * (1.0 - d2 * (1.0 / 42.0) * (1.0 - d2 * (1.0 / 72.0)))));
    *s = p->anchor_sin * cd + p->anchor_cos * sd;
    *c = p->anchor_cos * cd - p->anchor_sin * sd;
}

/* The d axis's unit phasor (cos, sin) of the present angle into p->z_cos/z_sin. */
PLANT_INLINE void phasor_update(plant_t *p)
{
    sincos_el(p, (double)p->cfg.pole_pairs * p->x.theta_m_rad + p->enc_offset_el_rad, &p->z_sin, &p->z_cos);
}

/* Keep theta_m in [0, 2 pi); the anchor follows so the series stays valid. */
static void wrap_theta(plant_t *p)
{
    double turn_el = SIM_TWO_PI * (double)p->cfg.pole_pairs;
    if (p->x.theta_m_rad >= SIM_TWO_PI) {
        p->x.theta_m_rad -= SIM_TWO_PI;
        p->anchor_el_rad -= turn_el;
    } else if (p->x.theta_m_rad < 0.0) {
        p->x.theta_m_rad += SIM_TWO_PI;
        p->anchor_el_rad += turn_el;
    }
}

/* Phase currents of stator-frame currents; the zero sequence is 0 (isolated star). */
static void ab_to_abc(double i_alpha_A, double i_beta_A, double i_abc_A[3])
{
    i_abc_A[0] = i_alpha_A;
    i_abc_A[1] = -0.5 * i_alpha_A + 0.5 * SQRT3 * i_beta_A;
    i_abc_A[2] = -0.5 * i_alpha_A - 0.5 * SQRT3 * i_beta_A;
}

/* RK4 weights 1, 2, 2, 1 over 6. */
static double rk4_sum(double a, double b, double c, double d)
{
    return (a + 2.0 * b + 2.0 * c + d) * (1.0 / 6.0);
}

/* ---- one RK4 step (plant_step_rk4: the averaged inverter's one piece) ---- */

/* State of a piece in the stator frame: currents (alpha, beta), speed and
 * the d axis's phasor z = e^(j theta_el), which obeys dz/dt = j w_el z. */
typedef struct {
    double ia, ib, w, zc, zs;
} stat_t;

/* What a stage needs from the piece: constants, voltage, load. */
typedef struct {
    double pp, R_Ohm, psi_f_Wb, B_Nms, inv_L_per_H, inv_J_per_kgm2, kt_Nm_A, ua_V, ub_V, TL_Nm;
} stage_ctx_t;

/* Derivative of the stator-frame state, eqs. (1)-(3) turned by z:
 * L di_ab/dt = u_ab - R i_ab - j w_el psi_f z; the stage's iq for the torque
 * and id for the mean come out too. */
PLANT_INLINE void deriv_ab(const stage_ctx_t *k, const stat_t *x, stat_t *dx, double *id_A, double *iq_A)
{
    double w_el = k->pp * x->w;
    double emf = w_el * k->psi_f_Wb;
    double iq = x->zc * x->ib - x->zs * x->ia;
    *id_A = x->zc * x->ia + x->zs * x->ib;
    *iq_A = iq;
    dx->ia = (k->ua_V - k->R_Ohm * x->ia + emf * x->zs) * k->inv_L_per_H;
    dx->ib = (k->ub_V - k->R_Ohm * x->ib - emf * x->zc) * k->inv_L_per_H;
    dx->w = (k->kt_Nm_A * iq - k->TL_Nm - k->B_Nms * x->w) * k->inv_J_per_kgm2;   /* 1/J = 0: speed held */
    dx->zc = -w_el * x->zs;
    dx->zs = w_el * x->zc;
}

PLANT_INLINE void axpy_ab(const stat_t *x, double h, const stat_t *dx, stat_t *y)
{
    y->ia = x->ia + h * dx->ia;
    y->ib = x->ib + h * dx->ib;
    y->w = x->w + h * dx->w;
    y->zc = x->zc + h * dx->zc;
    y->zs = x->zs + h * dx->zs;
}

/* One RK4 step in the stator frame: the voltage needs no turning at the
 * stages and the back-EMF's angle rides along as the phasor z, so a step
 * takes no sin/cos (plant_step_rk4() puts z back on the exact angle).
 * Fourth order; z's own error is (w_el h)^5/120, below 1e-8 at one 100 us
 * step at 2200 r/min. */
static void rk4_piece(plant_t *p, double *i_alpha_A, double *i_beta_A, double u_alpha_V, double u_beta_V, double TL_Nm,
                      double h_s)
{
    const plant_cfg_t *c = &p->cfg;
    const double pp = (double)c->pole_pairs;
    const stage_ctx_t k = { pp, c->R_Ohm, c->psi_f_Wb, c->B_Nms, p->inv_L_per_H,
                            c->speed_held ? 0.0 : p->inv_J_per_kgm2,
                            TORQUE_FACTOR * pp * c->psi_f_Wb, u_alpha_V, u_beta_V, TL_Nm };
    const stat_t x0 = { *i_alpha_A, *i_beta_A, p->x.omega_m_rad_s, p->z_cos, p->z_sin };
    stat_t k1, k2, k3, k4, x1, x2, x3;
    double id0, id1, id2, id3, iq0, iq1, iq2, iq3;
    deriv_ab(&k, &x0, &k1, &id0, &iq0);
    axpy_ab(&x0, 0.5 * h_s, &k1, &x1);
    deriv_ab(&k, &x1, &k2, &id1, &iq1);
    axpy_ab(&x0, 0.5 * h_s, &k2, &x2);
    deriv_ab(&k, &x2, &k3, &id2, &iq2);
    axpy_ab(&x0, h_s, &k3, &x3);
    deriv_ab(&k, &x3, &k4, &id3, &iq3);

    *i_alpha_A = x0.ia + h_s * rk4_sum(k1.ia, k2.ia, k3.ia, k4.ia);
    *i_beta_A = x0.ib + h_s * rk4_sum(k1.ib, k2.ib, k3.ib, k4.ib);
    p->x.omega_m_rad_s = x0.w + h_s * rk4_sum(k1.w, k2.w, k3.w, k4.w);
    p->x.theta_m_rad += h_s * rk4_sum(x0.w, x1.w, x2.w, x3.w);
    p->z_cos = x0.zc + h_s * rk4_sum(k1.zc, k2.zc, k3.zc, k4.zc);
    p->z_sin = x0.zs + h_s * rk4_sum(k1.zs, k2.zs, k3.zs, k4.zs);

    /* Quadratures with the same stages: the RK4 weights are Simpson's rule;
     * u is constant, so the mean rotor-frame voltage is u turned by the mean of conj(z). */
    const double zc_s = h_s * rk4_sum(x0.zc, x1.zc, x2.zc, x3.zc);
    const double zs_s = h_s * rk4_sum(x0.zs, x1.zs, x2.zs, x3.zs);
    p->acc.time_s += h_s;
    p->acc.id_As += h_s * rk4_sum(id0, id1, id2, id3);
    p->acc.iq_As += h_s * rk4_sum(iq0, iq1, iq2, iq3);
    p->acc.ud_Vs += u_alpha_V * zc_s + u_beta_V * zs_s;
    p->acc.uq_Vs += u_beta_V * zc_s - u_alpha_V * zs_s;
}

void plant_step_rk4(plant_t *p, double u_alpha_V, double u_beta_V, double TL_Nm, double h_s, int n_steps)
{
    double ia = p->z_cos * p->x.id_A - p->z_sin * p->x.iq_A;
    double ib = p->z_sin * p->x.id_A + p->z_cos * p->x.iq_A;
    if (n_steps > 1) {
        const double h = h_s / (double)n_steps;
        for (int k = 0; k < n_steps; k++) {
            rk4_piece(p, &ia, &ib, u_alpha_V, u_beta_V, TL_Nm, h);
        }
    } else {
        rk4_piece(p, &ia, &ib, u_alpha_V, u_beta_V, TL_Nm, h_s);
    }
    wrap_theta(p);
    phasor_update(p);
    p->x.id_A = p->z_cos * ia + p->z_sin * ib;
    p->x.iq_A = p->z_cos * ib - p->z_sin * ia;
    p->shaft_prev_valid = false;   /* the period solver's speed predictor starts again */
}

/* ---- the period solver (hal/sim/plant_design.md) ---------------------------
 * Short series of the functions the closed form needs, nested so constant
 * reciprocals fold. Each keeps its truncation below 3e-17 relative for
 * |x| <= SERIES_MAX (plant_design.md sec. 4); beyond it, libm. */
#define SERIES_MAX 0.1

typedef struct {
    double re, im;
} cpx_t;

PLANT_INLINE cpx_t cmul(cpx_t a, cpx_t b)
{
    cpx_t r = { a.re * b.re - a.im * b.im, a.re * b.im + a.im * b.re };
    return r;
}

/* e^x */
PLANT_INLINE double ser_exp(double x)
{
    if (fabs(x) > SERIES_MAX) {
        return exp(x);
    }
    return 1.0 + x * (1.0 + x * (1.0 / 2.0) * (1.0 + x * (1.0 / 3.0) * (1.0 + x * (1.0 / 4.0) *
           (1.0 + x * (1.0 / 5.0) * (1.0 + x * (1.0 / 6.0) * (1.0 + x * (1.0 / 7.0) *
           (1.0 + x * (1.0 / 8.0) * (1.0 + x * (1.0 / 9.0)))))))));
}

/* sinh(y)/y */
PLANT_INLINE double ser_shc(double y)
{
    if (fabs(y) > SERIES_MAX) {
        return sinh(y) / y;
    }
    const double y2 = y * y;
    return 1.0 + y2 * (1.0 / 6.0) * (1.0 + y2 * (1.0 / 20.0) * (1.0 + y2 * (1.0 / 42.0) * (1.0 + y2 * (1.0 / 72.0))));
}

/* sin(x)/x */
PLANT_INLINE double ser_sinc(double x)
{
    if (fabs(x) > SERIES_MAX) {
        return sin(x) / x;
    }
    const double x2 = x * x;
    return 1.0 - x2 * (1.0 / 6.0) * (1.0 - x2 * (1.0 / 20.0) * (1.0 - x2 * (1.0 / 42.0) * (1.0 - x2 * (1.0 / 72.0))));
}

/* (sin x - x cos x)/x^2, the first moment of e^(-j x s) over s in [-1, 1] is -2j times it */
PLANT_INLINE double ser_q(double x)
{
    if (fabs(x) > SERIES_MAX) {
        return (sin(x) - x * cos(x)) / (x * x);
    }
    const double x2 = x * x;
    return x * (1.0 / 3.0) *
           (1.0 - x2 * (1.0 / 10.0) * (1.0 - x2 * (1.0 / 28.0) * (1.0 - x2 * (1.0 / 54.0) * (1.0 - x2 * (1.0 / 88.0)))));
}

/* e^(j x) */
PLANT_INLINE cpx_t ser_cis(double x)
{
    cpx_t r;
    if (fabs(x) > SERIES_MAX) {
        r.re = cos(x);
        r.im = sin(x);
        return r;
    }
    const double x2 = x * x;
    r.re = 1.0 - x2 * (1.0 / 2.0) * (1.0 - x2 * (1.0 / 12.0) * (1.0 - x2 * (1.0 / 30.0) * (1.0 - x2 * (1.0 / 56.0))));
    r.im = x * (1.0 - x2 * (1.0 / 6.0) * (1.0 - x2 * (1.0 / 20.0) * (1.0 - x2 * (1.0 / 42.0) * (1.0 - x2 * (1.0 / 72.0)))));
    return r;
}

/* sinh(y)/y of a complex y */
PLANT_INLINE cpx_t ser_cshc(cpx_t y)
{
    cpx_t r;
    if (fabs(y.re) + fabs(y.im) > SERIES_MAX) {
        const cpx_t s = { sinh(y.re) * cos(y.im), cosh(y.re) * sin(y.im) };
        const double n = y.re * y.re + y.im * y.im;
        r.re = (s.re * y.re + s.im * y.im) / n;
        r.im = (s.im * y.re - s.re * y.im) / n;
        return r;
    }
    const cpx_t y2 = cmul(y, y);
    static const double k[4] = { 1.0 / 72.0, 1.0 / 42.0, 1.0 / 20.0, 1.0 / 6.0 };
    r.re = 1.0;
    r.im = 0.0;
    for (int n = 0; n < 4; n++) {
        const cpx_t t = cmul(y2, r);
        r.re = 1.0 + k[n] * t.re;
        r.im = k[n] * t.im;
    }
    return r;
}

/* Net accelerating force of the shaft at the period's start [N m]. */
static double shaft_force_Nm(const plant_t *p, double TL_Nm)
{
    const plant_cfg_t *c = &p->cfg;
    return TORQUE_FACTOR * (double)c->pole_pairs * c->psi_f_Wb * p->x.iq_A - TL_Nm - c->B_Nms * p->x.omega_m_rad_s;
}

void plant_period_begin(plant_t *p, double T_s, double TL_Nm)
{
    plant_period_t *q = &p->per;
    const plant_cfg_t *c = &p->cfg;
    const double pp = (double)c->pole_pairs;
    q->T_s = T_s;
    q->tau_s = 0.5 * T_s;
    q->TL_Nm = TL_Nm;
    /* The speed held: the middle's at a predicted mean acceleration, the last
     * period's plus the change of the start's force since (the ripple's share
     * of the start's torque cancels); the first period from the start's force. */
    const double inv_J = c->speed_held ? 0.0 : p->inv_J_per_kgm2;
    const double F = shaft_force_Nm(p, TL_Nm);
    if (!p->shaft_prev_valid) {
        p->alpha_prev_el_rad_s2 = pp * F * inv_J;
        p->F_prev_Nm = F;
        p->shaft_prev_valid = true;
    }
    q->alpha_el_rad_s2 = p->alpha_prev_el_rad_s2 + pp * (F - p->F_prev_Nm) * inv_J;
    p->F_prev_Nm = F;
    q->w_el_rad_s = pp * p->x.omega_m_rad_s + q->alpha_el_rad_s2 * q->tau_s;
    const double at = c->R_Ohm * p->inv_L_per_H * q->tau_s;
    if (at != q->E_key) {   /* e^(-a tau) only when R or the period changed */
        q->E_key = at;
        q->E = ser_exp(-at);
    }
    q->walk_zc_ok = false;
    plant_period_clear(p);
}

void plant_period_clear(plant_t *p)
{
    plant_period_t *q = &p->per;
    q->S_a = 0.0;
    q->S_b = 0.0;
    for (int n = 0; n < PLANT_N_MOMENTS; n++) {
        q->M_a[n] = 0.0;
        q->M_b[n] = 0.0;
    }
    q->n_pulses = 0;
    q->n_off = 0;
    q->legs_given = false;
    q->walk_s = -q->tau_s;
    q->walk_g = q->E;
    q->walk_Pa = 0.0;
    q->walk_Pb = 0.0;
}

bool plant_period_pulse(plant_t *p, double u_alpha_V, double u_beta_V, double centre_s, double half_s)
{
    plant_period_t *q = &p->per;
    if (!(half_s > 0.0)) {
        return true;
    }
    if (q->n_pulses >= PLANT_MAX_PULSES) {
        return false;
    }
    plant_pulse_t *pu = &q->pulse[q->n_pulses++];
    pu->ua_V = u_alpha_V;
    pu->ub_V = u_beta_V;
    pu->centre_s = centre_s;
    pu->half_s = half_s;
    if (centre_s == 0.0) {
        /* a centred pulse joins the moments M_n = sum of u 2 r^(2n+1) */
        const double r2 = half_s * half_s;
        double f = 2.0 * half_s;
        for (int n = 0; n < PLANT_N_MOMENTS; n++) {
            q->M_a[n] += f * u_alpha_V;
            q->M_b[n] += f * u_beta_V;
            f *= r2;
        }
    } else {
        q->n_off++;
        /* int e^(a s) u ds, the speed-free sum */
        const double a = p->cfg.R_Ohm * p->inv_L_per_H;
        const double f = 2.0 * half_s * ser_shc(a * half_s) * ser_exp(a * centre_s);
        q->S_a += f * u_alpha_V;
        q->S_b += f * u_beta_V;
    }
    return true;
}

void plant_period_legs(plant_t *p, double vdc_V, const double half_s[3])
{
    plant_period_t *q = &p->per;
    double f[3];
    double r2[3];
    for (int k = 0; k < 3; k++) {
        const double h = (half_s[k] > 0.0) ? half_s[k] : 0.0;
        q->leg_half_s[k] = h;
        f[k] = 2.0 * h;
        r2[k] = h * h;
    }
    q->leg_vdc_V = vdc_V;
    q->legs_given = true;
    /* leg k alone at vdc_V: (2/3, 0), (-1/3, 1/sqrt3), (-1/3, -1/sqrt3) times vdc_V;
     * M_n = sum of u 2 r^(2n+1) */
    const double ka = vdc_V * (1.0 / 3.0);
    const double kb = vdc_V * (1.0 / SQRT3);
    for (int n = 0; n < PLANT_N_MOMENTS; n++) {
        q->M_a[n] += ka * (2.0 * f[0] - f[1] - f[2]);
        q->M_b[n] += kb * (f[1] - f[2]);
        f[0] *= r2[0];
        f[1] *= r2[1];
        f[2] *= r2[2];
    }
}

/* The legs of plant_period_legs() as pulses, for arguments beyond the series. */
static void legs_to_pulses(plant_period_t *q)
{
    static const double LEG_A[3] = { 2.0 / 3.0, -1.0 / 3.0, -1.0 / 3.0 };
    static const double LEG_B[3] = { 0.0, 1.0 / SQRT3, -1.0 / SQRT3 };
    if (!q->legs_given) {
        return;
    }
    for (int k = 0; k < 3; k++) {
        if (q->leg_half_s[k] > 0.0 && q->n_pulses < PLANT_MAX_PULSES) {
            plant_pulse_t *pu = &q->pulse[q->n_pulses++];
            pu->ua_V = LEG_A[k] * q->leg_vdc_V;
            pu->ub_V = LEG_B[k] * q->leg_vdc_V;
            pu->centre_s = 0.0;
            pu->half_s = q->leg_half_s[k];
        }
    }
    q->legs_given = false;
}

/* sum over n of k_n x^n M_n (n = n0 .. n0 + 4), k_n = prod of f[j], j < n - n0, nested */
PLANT_INLINE cpx_t moment_series(const plant_period_t *q, int n0, double x, const double f[4])
{
    cpx_t r = { q->M_a[n0 + 4], q->M_b[n0 + 4] };
    for (int j = 3; j >= 0; j--) {
        r.re = q->M_a[n0 + j] + x * f[j] * r.re;
        r.im = q->M_b[n0 + j] + x * f[j] * r.im;
    }
    return r;
}

/* Ratios of the series' successive coefficients (plant_design.md sec. 4). */
static const double SHC_RATIO[4] = { 1.0 / 6.0, 1.0 / 20.0, 1.0 / 42.0, 1.0 / 72.0 };
static const double SINC_RATIO[4] = { -1.0 / 6.0, -1.0 / 20.0, -1.0 / 42.0, -1.0 / 72.0 };
static const double Q_RATIO[4] = { -1.0 / 10.0, -1.0 / 28.0, -1.0 / 54.0, -1.0 / 88.0 };

/* One pass at the held electrical speed w (plant_design.md sec. 2-4): the
 * held solution, its parts linear in the acceleration (per rad/s^2) and
 * its derivatives in w; the first moment for the shaft. */
typedef struct {
    cpx_t zc;               /* the held phasor at the middle */
    cpx_t ih;               /* end current [A], held, in zc's frame */
    cpx_t Ih, U;            /* int ir [A s], int u conj(z) [V s], held */
    cpx_t Is;               /* int s ir [A s^2], held */
    cpx_t d1, i1, u1;       /* per unit of acceleration */
    cpx_t dih, dIh, dU;     /* per unit of speed */
} pass_t;

PLANT_INLINE cpx_t cj(cpx_t a)
{
    cpx_t r = { a.re, -a.im };
    return r;
}

/* j a */
PLANT_INLINE cpx_t jm(cpx_t a)
{
    cpx_t r = { -a.im, a.re };
    return r;
}

/* Over the period's pulses at the held electrical speed w:
 * W = int e^(-j w s) u ds, Ws = int s e^(-j w s) u ds,
 * Wq = int (s^2 - tau^2) e^(-j w s) u ds (s from the middle); the centred
 * pulses' share from the moments while |w| tau allows the series. */
static void pulse_integrals(const plant_period_t *q, double w, cpx_t *W_out, cpx_t *Ws_out, cpx_t *Wq_out)
{
    const double tau = q->tau_s;
    cpx_t W = { 0.0, 0.0 };
    cpx_t Ws = { 0.0, 0.0 };
    cpx_t Wq = { 0.0, 0.0 };
    const bool by_moments = fabs(w) * tau <= SERIES_MAX;
    if (by_moments) {
        const double w2 = w * w;
        W = moment_series(q, 0, w2, SINC_RATIO);
        const cpx_t G = moment_series(q, 1, w2, Q_RATIO);   /* Ws = -j (w/3) G */
        Ws.re = w * (1.0 / 3.0) * G.im;
        Ws.im = -w * (1.0 / 3.0) * G.re;
        Wq.re = (1.0 / 3.0) * q->M_a[1] - 0.1 * w2 * q->M_a[2];
        Wq.im = (1.0 / 3.0) * q->M_b[1] - 0.1 * w2 * q->M_b[2];
    }
    if (!by_moments || q->n_off > 0) {
        for (int k = 0; k < q->n_pulses; k++) {
            const plant_pulse_t *pu = &q->pulse[k];
            const double m = pu->centre_s;
            if (by_moments && m == 0.0) {
                continue;
            }
            const double r = pu->half_s;
            const double x = w * r;
            const double f = 2.0 * r * ser_sinc(x);                 /* int e^(-j w s) over [-r, r] */
            const double g = 2.0 * r * r * ser_q(x);                /* its first moment / (-j) */
            const double h = (2.0 / 3.0) * r * r * r * (1.0 - 0.3 * x * x) + m * m * f;
            cpx_t u = { pu->ua_V, pu->ub_V };
            if (m != 0.0) {
                u = cmul(u, ser_cis(-w * m));
                Ws.re += m * f * u.re;
                Ws.im += m * f * u.im;
                Wq.re += 2.0 * m * g * u.im;   /* u (-2j m g) */
                Wq.im -= 2.0 * m * g * u.re;
            }
            W.re += f * u.re;
            W.im += f * u.im;
            Ws.re += g * u.im;   /* u (-j g) */
            Ws.im -= g * u.re;
            Wq.re += h * u.re;
            Wq.im += h * u.im;
        }
    }
    Wq.re -= tau * tau * W.re;
    Wq.im -= tau * tau * W.im;
    *W_out = W;
    *Ws_out = Ws;
    *Wq_out = Wq;
}

/* What the parts of one pass share at the held speed w: the turn over half
 * the period ew and the held phasor at the middle zc, c tau = (a + j w) tau
 * with K = 2 tau shc(c tau), the pulses' integrals turned into zc's frame
 * (W, Ws, Wq of pulse_integrals: U, Us, UQ), the rotor-frame start ir0
 * and 1/(R + j w L), the rotor-frame equation's divisor. */
typedef struct {
    double w, a, ke;            /* ke = (psi_f/L) E */
    cpx_t ew, ewc, zc, zcc;
    cpx_t ct, K;
    cpx_t U, Us, UQ;
    cpx_t ir0, inv_rc;
} pass_terms_t;

/* The shared terms of period_pass at the held speed w. */
static void pass_terms(const plant_t *p, double w, pass_terms_t *t)
{
    const plant_period_t *q = &p->per;
    const double L = p->cfg.L_H;
    const double R = p->cfg.R_Ohm;
    const double tau = q->tau_s;
    const double kp = p->cfg.psi_f_Wb * p->inv_L_per_H;
    t->w = w;
    t->a = R * p->inv_L_per_H;
    t->ke = kp * q->E;
    t->ew = ser_cis(w * tau);
    t->ewc = cj(t->ew);
    const cpx_t z0 = { p->z_cos, p->z_sin };
    t->zc = cmul(z0, t->ew);
    t->zcc = cj(t->zc);
    t->ct = (cpx_t){ t->a * tau, w * tau };
    const cpx_t sh = ser_cshc(t->ct);
    t->K = (cpx_t){ 2.0 * tau * sh.re, 2.0 * tau * sh.im };
    cpx_t W;
    cpx_t Ws;
    cpx_t Wq;
    pulse_integrals(q, w, &W, &Ws, &Wq);
    t->U = cmul(t->zcc, W);
    t->Us = cmul(t->zcc, Ws);
    t->UQ = cmul(t->zcc, Wq);
    t->ir0 = (cpx_t){ p->x.id_A, p->x.iq_A };
    const double inv_rc2 = 1.0 / (R * R + w * w * L * L);
    t->inv_rc = (cpx_t){ R * inv_rc2, -w * L * inv_rc2 };
}

/* The end current in the frame of the held phasor at the middle (stator
 * quantities times conj(zc)): ih = E [E ir0 conj(ew) + conj(zc) S/L]
 * - j w (psi_f/L) E K, K = 2 tau shc(c tau), the stator current zc ih;
 * the acceleration's end current d1 = j (psi_f/L) a D E, D = -(2/3) alpha tau^3. */
static void pass_end_current(const plant_t *p, const pass_terms_t *t, pass_t *o)
{
    const plant_period_t *q = &p->per;
    const double E = q->E;
    const double tau = q->tau_s;
    const cpx_t i0c = cmul(t->ir0, t->ewc);
    const cpx_t Sc = cmul(t->zcc, (cpx_t){ q->S_a, q->S_b });
    o->ih.re = E * (E * i0c.re + Sc.re * p->inv_L_per_H) + t->ke * t->w * t->K.im;
    o->ih.im = E * (E * i0c.im + Sc.im * p->inv_L_per_H) - t->ke * t->w * t->K.re;
    o->d1.re = 0.0;
    o->d1.im = t->ke * t->a * (-(2.0 / 3.0)) * tau * tau * tau;
}

/* The held rotor-frame integrals (sec. 2): L (ir1 - ir0) = U - (R + j w L) I
 * - j w psi_f T for I = int ir; the first moment Is from the same times s. */
static void pass_held_integrals(const plant_t *p, const pass_terms_t *t, pass_t *o)
{
    const double L = p->cfg.L_H;
    const double tau = p->per.tau_s;
    const cpx_t ir0 = t->ir0;
    const cpx_t ir1 = cmul(o->ih, t->ewc);
    const double emf = t->w * p->cfg.psi_f_Wb * p->per.T_s;
    o->U = t->U;
    const cpx_t n1 = { o->U.re - L * (ir1.re - ir0.re), o->U.im - emf - L * (ir1.im - ir0.im) };
    o->Ih = cmul(n1, t->inv_rc);
    const cpx_t n2 = { t->Us.re - L * tau * (ir1.re + ir0.re) + L * o->Ih.re,
                       t->Us.im - L * tau * (ir1.im + ir0.im) + L * o->Ih.im };
    o->Is = cmul(n2, t->inv_rc);
}

/* Per unit of acceleration (sec. 4): the voltage turned by dtheta, the end
 * current's d1, the equation's - j L alpha Is. */
static void pass_accel_part(const plant_t *p, const pass_terms_t *t, pass_t *o)
{
    const double L = p->cfg.L_H;
    const double kd = o->d1.im;
    o->u1.re = 0.5 * t->UQ.im;   /* -(j/2) UQ */
    o->u1.im = -0.5 * t->UQ.re;
    const cpx_t d1r = { kd * t->ew.im, kd * t->ew.re };   /* d1 conj(ew) */
    const cpx_t n3 = { o->u1.re - L * d1r.re + L * o->Is.im, o->u1.im - L * d1r.im - L * o->Is.re };
    o->i1 = cmul(n3, t->inv_rc);
}

/* Per unit of speed (sec. 4): dW/dw = -j Ws, dzc/dw = j tau zc,
 * dK/dw = j int s e^(c s) ds = j (2/3) tau^3 c (1 + (c tau)^2/10);
 * d(ir1)/dw = dih conj(ew) - 2j tau ir1,
 * dI/dw = (dU - j psi_f T - L d(ir1)/dw - j L I)/(R + j w L). */
static void pass_speed_part(const plant_t *p, const pass_terms_t *t, pass_t *o)
{
    const double L = p->cfg.L_H;
    const double tau = p->per.tau_s;
    const double w = t->w;
    const cpx_t K = t->K;
    o->dU.re = tau * o->U.im + t->Us.im;   /* -j (tau U + Us) */
    o->dU.im = -tau * o->U.re - t->Us.re;
    const cpx_t c2 = cmul(t->ct, t->ct);
    const cpx_t cq = cmul(t->ct, (cpx_t){ 1.0 + 0.1 * c2.re, 0.1 * c2.im });
    const double k3 = (2.0 / 3.0) * tau * tau;   /* dK/dw = j k3 cq */
    const cpx_t br = { K.re - w * tau * K.im - w * k3 * cq.im, K.im + w * tau * K.re + w * k3 * cq.re };
    o->dih.re = t->ke * br.im;   /* -j (psi_f/L) E br */
    o->dih.im = -t->ke * br.re;
    const cpx_t ir1 = cmul(o->ih, t->ewc);
    const cpx_t dir1 = cmul(o->dih, t->ewc);
    const cpx_t n4 = { o->dU.re - L * (dir1.re + 2.0 * tau * ir1.im) + L * o->Ih.im,
                       o->dU.im - p->cfg.psi_f_Wb * p->per.T_s - L * (dir1.im - 2.0 * tau * ir1.re) - L * o->Ih.re };
    o->dIh = cmul(n4, t->inv_rc);
}

/* One pass (pass_t) at the held speed w from the state at the period's
 * start: plant_period_end's, once or twice a period. */
static void period_pass(const plant_t *p, double w, pass_t *o)
{
    pass_terms_t t;
    pass_terms(p, w, &t);
    o->zc = t.zc;
    pass_end_current(p, &t, o);
    pass_held_integrals(p, &t, o);
    pass_accel_part(p, &t, o);
    pass_speed_part(p, &t, o);
}

/* The shaft over the period from the torque's integral Iq [A s] and first
 * moment Isq [A s^2] about the middle (sec. 3): speed at the end, angle turned. */
static void shaft_period(const plant_t *p, double Iq, double Isq, double *w1_m, double *dtheta_m)
{
    const plant_cfg_t *c = &p->cfg;
    const plant_period_t *q = &p->per;
    const double w0 = p->x.omega_m_rad_s;
    const double T = q->T_s;
    if (c->speed_held) {
        *w1_m = w0;
        *dtheta_m = w0 * T;
        return;
    }
    const double kt = TORQUE_FACTOR * (double)c->pole_pairs * c->psi_f_Wb;
    const double F0 = kt * Iq - q->TL_Nm * T;
    const double F1 = kt * (q->tau_s * Iq - Isq) - q->TL_Nm * T * T * 0.5;
    const double inv_J = p->inv_J_per_kgm2;
    const double w1f = w0 + F0 * inv_J;
    *dtheta_m = w0 * T + (F1 - c->B_Nms * T * T * (2.0 * w0 + w1f) * (1.0 / 6.0)) * inv_J;
    *w1_m = w1f - c->B_Nms * *dtheta_m * inv_J;
}

/* How the shaft's end speed and angle move with the torque's integral Iq (the
 * first moment held): shaft_period() is linear in it. */
static void shaft_sensitivity(const plant_t *p, double *dw1_dIq, double *dth_dIq)
{
    const plant_cfg_t *c = &p->cfg;
    if (c->speed_held) {
        *dw1_dIq = 0.0;
        *dth_dIq = 0.0;
        return;
    }
    const double T = p->per.T_s;
    const double inv_J = p->inv_J_per_kgm2;
    const double kt = TORQUE_FACTOR * (double)c->pole_pairs * c->psi_f_Wb;
    const double dw1f = kt * inv_J;
    *dth_dIq = (kt * p->per.tau_s - c->B_Nms * T * T * dw1f * (1.0 / 6.0)) * inv_J;
    *dw1_dIq = dw1f - c->B_Nms * *dth_dIq * inv_J;
}

/* Largest |w - w_held| tau the linear update in the speed covers: its
 * neglected term, (psi_f/L) (2 (w - w_held) tau)^2, stays below 1e-8 A. */
#define LINEAR_SPEED_MAX 1.0e-5

/* S = int e^(a s) u ds, a = R/L: the centred pulses' share, from the
 * moments while a tau allows the series, else pulse by pulse. */
static void centred_share(plant_t *p)
{
    plant_period_t *q = &p->per;
    const double a = p->cfg.R_Ohm * p->inv_L_per_H;
    if (a * q->tau_s <= SERIES_MAX) {
        const cpx_t S = moment_series(q, 0, a * a, SHC_RATIO);
        q->S_a += S.re;
        q->S_b += S.im;
    } else {
        legs_to_pulses(q);   /* beyond the series: pulse by pulse */
        for (int k = 0; k < q->n_pulses; k++) {
            const plant_pulse_t *pu = &q->pulse[k];
            if (pu->centre_s == 0.0) {
                const double f = 2.0 * pu->half_s * ser_shc(a * pu->half_s);
                q->S_a += f * pu->ua_V;
                q->S_b += f * pu->ub_V;
            }
        }
    }
}

void plant_period_end(plant_t *p)
{
    plant_period_t *q = &p->per;
    const double pp = (double)p->cfg.pole_pairs;
    centred_share(p);
    q->ir0_d_A = p->x.id_A;   /* the rotor-frame start: the state itself */
    q->ir0_q_A = p->x.iq_A;

    /* the held speed, then the shaft, then the mean speed and acceleration it gives */
    double w = q->w_el_rad_s;
    if (fabs(w) * q->tau_s > SERIES_MAX) {
        legs_to_pulses(q);
    }
    pass_t o;
    period_pass(p, w, &o);
    double alpha = q->alpha_el_rad_s2;
    double w1 = 0.0;
    double dth = 0.0;
    const double Iq_p = o.Ih.im + alpha * o.i1.im;
    shaft_period(p, Iq_p, o.Is.im, &w1, &dth);
    const double pp_T = pp / q->T_s;
    const double w_mean = pp_T * dth;
    alpha = pp_T * (w1 - p->x.omega_m_rad_s);
    double dw = w_mean - w;
    double Iq_ref = Iq_p;
    if (fabs(dw) * q->tau_s > LINEAR_SPEED_MAX) {   /* too far for the linear update: once more */
        w = w_mean;
        if (fabs(w) * q->tau_s > SERIES_MAX) {
            legs_to_pulses(q);
        }
        period_pass(p, w, &o);
        dw = 0.0;
        shaft_period(p, o.Ih.im + alpha * o.i1.im, o.Is.im, &w1, &dth);
        Iq_ref = o.Ih.im + alpha * o.i1.im;
    }
    const cpx_t ihc = { o.ih.re + dw * o.dih.re + alpha * o.d1.re, o.ih.im + dw * o.dih.im + alpha * o.d1.im };
    const cpx_t i_end = cmul(o.zc, ihc);
    const cpx_t I = { o.Ih.re + dw * o.dIh.re + alpha * o.i1.re, o.Ih.im + dw * o.dIh.im + alpha * o.i1.im };
    const cpx_t U = { o.U.re + dw * o.dU.re + alpha * o.u1.re, o.U.im + dw * o.dU.im + alpha * o.u1.im };
    double dw1_dIq;
    double dth_dIq;
    shaft_sensitivity(p, &dw1_dIq, &dth_dIq);
    w1 += dw1_dIq * (I.im - Iq_ref);   /* the shaft with the corrected torque integral */
    dth += dth_dIq * (I.im - Iq_ref);
    p->alpha_prev_el_rad_s2 = pp_T * (w1 - p->x.omega_m_rad_s);

    p->x.omega_m_rad_s = w1;
    p->x.theta_m_rad += dth;
    wrap_theta(p);
    phasor_update(p);
    p->x.id_A = p->z_cos * i_end.re + p->z_sin * i_end.im;
    p->x.iq_A = p->z_cos * i_end.im - p->z_sin * i_end.re;
    p->acc.time_s += q->T_s;
    p->acc.id_As += I.re;
    p->acc.iq_As += I.im;
    p->acc.ud_Vs += U.re;
    p->acc.uq_Vs += U.im;
}

/* The phasor at the middle for the walker, at pass 1's speed. */
static void walk_phasor(plant_t *p)
{
    plant_period_t *q = &p->per;
    const cpx_t ew = ser_cis(q->w_el_rad_s * q->tau_s);
    q->zc_c = p->z_cos * ew.re - p->z_sin * ew.im;
    q->zc_s = p->z_sin * ew.re + p->z_cos * ew.im;
    q->ia0_A = p->z_cos * p->x.id_A - p->z_sin * p->x.iq_A;
    q->ib0_A = p->z_sin * p->x.id_A + p->z_cos * p->x.iq_A;
    q->walk_zc_ok = true;
}

/* Walker: i(s) = e^(-a s) [E i0 + P(s)/L - j w (psi_f/L) zc int_{-tau}^{s} e^(c s') ds'],
 * P(s) = int_{-tau}^{s} e^(a s') u ds', at the held speed and the predicted acceleration. */
void plant_walk_iabc_A(const plant_t *p, double i_abc_A[3])
{
    const plant_period_t *q = &p->per;
    if (!q->walk_zc_ok) {   /* at the period's start: the state's */
        plant_iabc_A(p, i_abc_A);
        return;
    }
    const double a = p->cfg.R_Ohm * p->inv_L_per_H;
    const double w = q->w_el_rad_s;
    const double s = q->walk_s;
    const double m = 0.5 * (s - q->tau_s);   /* the integral's middle and half length */
    const double r = 0.5 * (s + q->tau_s);
    const cpx_t cr = { a * r, w * r };
    const cpx_t sh = ser_cshc(cr);
    const cpx_t em = ser_cis(w * m);
    const double ea = ser_exp(a * m) * 2.0 * r;
    const cpx_t zc = { q->zc_c, q->zc_s };
    const cpx_t k = cmul(cmul(zc, em), sh);     /* zc int e^(c s') ds' / (2 r e^(a m)) */
    const double kp = w * p->cfg.psi_f_Wb * p->inv_L_per_H * ea;
    const double inv_g = 1.0 / q->walk_g;
    /* the speed's change at alpha: -j (psi_f/L) zc alpha (s^2 - tau^2)/2 to first order */
    const double kd = 0.5 * q->alpha_el_rad_s2 * (s * s - q->tau_s * q->tau_s) * p->cfg.psi_f_Wb * p->inv_L_per_H;
    const double ia = inv_g * (q->E * q->ia0_A + q->walk_Pa * p->inv_L_per_H + kp * k.im) + kd * q->zc_s;
    const double ib = inv_g * (q->E * q->ib0_A + q->walk_Pb * p->inv_L_per_H - kp * k.re) - kd * q->zc_c;
    ab_to_abc(ia, ib, i_abc_A);
}

void plant_walk_advance(plant_t *p, double u_alpha_V, double u_beta_V, double t_s)
{
    plant_period_t *q = &p->per;
    const double s1 = t_s - q->tau_s;
    if (!(s1 > q->walk_s)) {
        return;
    }
    if (!q->walk_zc_ok) {
        walk_phasor(p);
    }
    const double a = p->cfg.R_Ohm * p->inv_L_per_H;
    const double m = 0.5 * (s1 + q->walk_s);
    const double r = 0.5 * (s1 - q->walk_s);
    const double f = ser_exp(a * m) * 2.0 * r * ser_shc(a * r);
    q->walk_Pa += f * u_alpha_V;
    q->walk_Pb += f * u_beta_V;
    q->walk_s = s1;
    q->walk_g = ser_exp(a * s1);
}

void plant_step(plant_t *p, double u_alpha_V, double u_beta_V, double TL_Nm, double h_s)
{
    plant_period_begin(p, h_s, TL_Nm);
    (void)plant_period_pulse(p, u_alpha_V, u_beta_V, 0.0, 0.5 * h_s);
    plant_period_end(p);
}

/* ---- the gates off: the legs' freewheeling diodes into the bus (plant_design.md sec. 9) ---- */

/* The shaft alone over h_s with no current: J dw/dt = -TL - B w (RK4: linear in w); the terminals
 * at the back-EMF (the diodes block), so the period's mean voltage is the EMF's. */
static void shaft_open(plant_t *p, double TL_Nm, double h_s)
{
    const plant_cfg_t *c = &p->cfg;
    const double w0 = p->x.omega_m_rad_s;
    double a1 = 0.0;
    double a2 = 0.0;
    double a3 = 0.0;
    double a4 = 0.0;
    if (!c->speed_held) {
        a1 = (-TL_Nm - c->B_Nms * w0) * p->inv_J_per_kgm2;
        a2 = (-TL_Nm - c->B_Nms * (w0 + 0.5 * h_s * a1)) * p->inv_J_per_kgm2;
        a3 = (-TL_Nm - c->B_Nms * (w0 + 0.5 * h_s * a2)) * p->inv_J_per_kgm2;
        a4 = (-TL_Nm - c->B_Nms * (w0 + h_s * a3)) * p->inv_J_per_kgm2;
    }
    p->x.id_A = 0.0;
    p->x.iq_A = 0.0;
    p->x.omega_m_rad_s += h_s * rk4_sum(a1, a2, a3, a4);
    const double dtheta = h_s * rk4_sum(w0, w0 + 0.5 * h_s * a1, w0 + 0.5 * h_s * a2, w0 + h_s * a3);
    p->x.theta_m_rad += dtheta;
    p->acc.uq_Vs += (double)c->pole_pairs * dtheta * c->psi_f_Wb;   /* u_q = w_el psi_f, integrated */
    p->acc.time_s += h_s;
    wrap_theta(p);
    phasor_update(p);
}

/* A leg's diodes: the lower one conducts (i > 0, into the motor: the leg at -drop), the upper
 * one (i < 0: at the bus + drop), or neither (i = 0, the terminal floats between). */
enum { LEG_OPEN = 0, LEG_LOW_DIODE = 1, LEG_HIGH_DIODE = -1 };

/* The three legs' states to try, one per row (sec. 9: no current, two conducting, three). */
static const signed char LEG_PATTERNS[][3] = {
    { 0, 0, 0 },
    { 1, -1, 0 }, { -1, 1, 0 }, { 1, 0, -1 }, { -1, 0, 1 }, { 0, 1, -1 }, { 0, -1, 1 },
    { 1, 1, -1 }, { 1, -1, 1 }, { -1, 1, 1 }, { -1, -1, 1 }, { -1, 1, -1 }, { 1, -1, -1 },
};
#define N_LEG_PATTERNS ((int)(sizeof LEG_PATTERNS / sizeof LEG_PATTERNS[0]))

/* One backward-Euler step of the phase currents with the diodes (sec. 9): each phase x obeys
 * w_x = G i_x + c_x (w_x its terminal voltage over the star, G = L/h + R, c_x = e_x - L i0_x / h);
 * pattern by pattern the terminals' voltages follow (v_x = -vd or vdc + vd where a diode
 * conducts, the star's v_n from the currents' sum of zero), and the one whose currents have the
 * diodes' signs and whose open terminals lie between the rails is the step's: the end currents
 * into i[], the terminal voltages over the star into w[]. The system is monotone (G > 0): one
 * pattern holds; a rounding at a boundary takes the one that misses least. */
static void diode_step(double G, const double c[3], double vdc_V, double vd_V, double i[3], double w[3])
{
    const double lo = -vd_V;
    const double hi = vdc_V + vd_V;
    double best = INFINITY;
    for (int k = 0; k < N_LEG_PATTERNS; k++) {
        const signed char *pat = LEG_PATTERNS[k];
        double v[3];
        double vn = 0.0;
        int n = 0;
        for (int x = 0; x < 3; x++) {
            if (pat[x] != LEG_OPEN) {
                v[x] = (pat[x] == LEG_LOW_DIODE) ? lo : hi;
                vn += v[x] - c[x];
                n++;
            }
        }
        if (n == 0) {   /* all blocking: a star voltage exists keeping every terminal between the rails */
            const double spread = fmax(c[0], fmax(c[1], c[2])) - fmin(c[0], fmin(c[1], c[2]));
            const double miss = fmax(0.0, spread - (hi - lo));
            if (miss < best) {
                best = miss;
                for (int x = 0; x < 3; x++) {
                    i[x] = 0.0;
                    w[x] = c[x];
                }
            }
            continue;
        }
        vn /= (double)n;
        double miss = 0.0;
        double ik[3];
        for (int x = 0; x < 3; x++) {
            if (pat[x] == LEG_OPEN) {
                ik[x] = 0.0;
                const double vx = vn + c[x];
                miss += fmax(0.0, lo - vx) + fmax(0.0, vx - hi);
            } else {
                ik[x] = (v[x] - vn - c[x]) / G;
                miss += fmax(0.0, -(double)pat[x] * ik[x]) * G;   /* a diode's current against it, as a voltage */
            }
        }
        if (miss < best) {
            best = miss;
            for (int x = 0; x < 3; x++) {
                i[x] = ik[x];
                w[x] = G * ik[x] + c[x];
            }
        }
        if (!(best > 0.0)) {
            return;
        }
    }
}

/* The line back-EMF's peak below the bus with the diodes' drops: no diode can conduct while the
 * currents are zero (sec. 9: sqrt(3) w_el psi_f < vdc + 2 vd). */
static bool diodes_block(const plant_t *p, double omega_m_rad_s, double vdc_V, double vd_V)
{
    const double line_peak = SQRT3 * fabs((double)p->cfg.pole_pairs * omega_m_rad_s) * p->cfg.psi_f_Wb;
    return line_peak < vdc_V + 2.0 * vd_V;
}

void plant_step_rectified(plant_t *p, double vdc_V, double vd_V, double TL_Nm, double h_s)
{
    const plant_cfg_t *c = &p->cfg;
    const double inv_J = c->speed_held ? 0.0 : p->inv_J_per_kgm2;
    const int n_sub = (int)ceil(h_s / PLANT_OFF_SUBSTEP_MAX_S);
    const double h = h_s / (double)n_sub;
    const double pp = (double)c->pole_pairs;
    const double G = c->L_H / h + c->R_Ohm;
    p->shaft_prev_valid = false;   /* the speed's predictor starts again with the next gates-on period */
    for (int m = 0; m < n_sub; m++) {
        const double w0 = p->x.omega_m_rad_s;
        const bool no_current = !(p->x.id_A != 0.0) && !(p->x.iq_A != 0.0);
        const double w_end = w0 + (double)(n_sub - m) * h * (-TL_Nm - c->B_Nms * w0) * inv_J;
        if (no_current && diodes_block(p, w0, vdc_V, vd_V) && diodes_block(p, w_end, vdc_V, vd_V)) {
            shaft_open(p, TL_Nm, (double)(n_sub - m) * h);   /* the rest of the period: the shaft alone */
            return;
        }
        double i0[3];
        double e[3];
        double zs;
        double zc;
        plant_iabc_A(p, i0);
        /* the back-EMF j w_el psi_f z at the step's middle, by phase */
        sincos_el(p, pp * (p->x.theta_m_rad + 0.5 * h * w0) + p->enc_offset_el_rad, &zs, &zc);
        const double emf = pp * w0 * c->psi_f_Wb;
        ab_to_abc(-emf * zs, emf * zc, e);
        double cx[3];
        for (int x = 0; x < 3; x++) {
            cx[x] = e[x] - c->L_H / h * i0[x];
        }
        double i1[3] = { 0.0, 0.0, 0.0 };
        double wx[3] = { cx[0], cx[1], cx[2] };
        diode_step(G, cx, vdc_V, vd_V, i1, wx);
        /* the shaft over the step with the end current's torque; then the angle, the currents in it */
        const double ia = i1[0];
        const double ib = (i1[1] - i1[2]) / SQRT3;
        const double ua = wx[0];
        const double ub = (wx[1] - wx[2]) / SQRT3;
        const double iq_mid = zc * ib - zs * ia;
        const double w1 = w0 + h * (TORQUE_FACTOR * pp * c->psi_f_Wb * iq_mid - TL_Nm - c->B_Nms * w0) * inv_J;
        p->x.omega_m_rad_s = w1;
        p->x.theta_m_rad += 0.5 * h * (w0 + w1);
        wrap_theta(p);
        phasor_update(p);
        p->x.id_A = p->z_cos * ia + p->z_sin * ib;
        p->x.iq_A = p->z_cos * ib - p->z_sin * ia;
        p->acc.time_s += h;
        p->acc.id_As += h * p->x.id_A;
        p->acc.iq_As += h * p->x.iq_A;
        p->acc.ud_Vs += h * (zc * ua + zs * ub);
        p->acc.uq_Vs += h * (zc * ub - zs * ua);
    }
}

void plant_set_speed(plant_t *p, double omega_m_rad_s)
{
    p->x.omega_m_rad_s = omega_m_rad_s;
    p->shaft_prev_valid = false;   /* a step of the speed: the predictor starts again */
}

void plant_set_R_Ohm(plant_t *p, double R_Ohm)
{
    if (isfinite(R_Ohm) && R_Ohm > 0.0) {
        p->cfg.R_Ohm = R_Ohm;
    }
}

double plant_theta_el_rad(const plant_t *p)
{
    double th = (double)p->cfg.pole_pairs * p->x.theta_m_rad + p->enc_offset_el_rad;
    th -= SIM_TWO_PI * floor(th * (1.0 / SIM_TWO_PI));   /* cheaper than fmod; rounding fixed below */
    if (th >= SIM_TWO_PI) {
        th -= SIM_TWO_PI;
    } else if (th < 0.0) {
        th += SIM_TWO_PI;
    }
    return th;
}

double plant_te_Nm(const plant_t *p)
{
    return TORQUE_FACTOR * (double)p->cfg.pole_pairs * p->cfg.psi_f_Wb * p->x.iq_A;
}

double plant_psi_s_Wb(const plant_t *p)
{
    double psi_d = p->cfg.L_H * p->x.id_A + p->cfg.psi_f_Wb;
    double psi_q = p->cfg.L_H * p->x.iq_A;
    return sqrt(psi_d * psi_d + psi_q * psi_q);
}

void plant_iabc_A(const plant_t *p, double i_abc_A[3])
{
    ab_to_abc(p->z_cos * p->x.id_A - p->z_sin * p->x.iq_A, p->z_sin * p->x.id_A + p->z_cos * p->x.iq_A, i_abc_A);
}

void plant_acc_clear(plant_t *p)
{
    p->acc.time_s = 0.0;
    p->acc.id_As = 0.0;
    p->acc.iq_As = 0.0;
    p->acc.ud_Vs = 0.0;
    p->acc.uq_Vs = 0.0;
}
