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

/* RK4 weights 1, 2, 2, 1 over 6 (the open stator's shaft). */
static double rk4_sum(double a, double b, double c, double d)
{
    return (a + 2.0 * b + 2.0 * c + d) * (1.0 / 6.0);
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

void plant_period_begin(plant_t *p, double T_s, double TL_Nm)
{
    plant_period_t *q = &p->per;
    const plant_cfg_t *c = &p->cfg;
    const double pp = (double)c->pole_pairs;
    q->T_s = T_s;
    q->tau_s = 0.5 * T_s;
    q->TL_Nm = TL_Nm;
    q->ia0_A = p->z_cos * p->x.id_A - p->z_sin * p->x.iq_A;
    q->ib0_A = p->z_sin * p->x.id_A + p->z_cos * p->x.iq_A;
    /* pass 1's speed: the middle's, from the torque at the start */
    const double inv_J = c->speed_held ? 0.0 : p->inv_J_per_kgm2;
    const double alpha_m = (TORQUE_FACTOR * pp * c->psi_f_Wb * p->x.iq_A - TL_Nm - c->B_Nms * p->x.omega_m_rad_s) * inv_J;
    q->alpha_el_rad_s2 = pp * alpha_m;
    q->w_el_rad_s = pp * (p->x.omega_m_rad_s + alpha_m * q->tau_s);
    q->E = ser_exp(-c->R_Ohm * p->inv_L_per_H * q->tau_s);
    const cpx_t ew = ser_cis(q->w_el_rad_s * q->tau_s);
    q->zc_c = p->z_cos * ew.re - p->z_sin * ew.im;
    q->zc_s = p->z_sin * ew.re + p->z_cos * ew.im;
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
        /* int e^(a s) u ds, the speed-free sum */
        const double a = p->cfg.R_Ohm * p->inv_L_per_H;
        const double f = 2.0 * half_s * ser_shc(a * half_s) * ser_exp(a * centre_s);
        q->S_a += f * u_alpha_V;
        q->S_b += f * u_beta_V;
    }
    return true;
}

/* What one pass gives: the current at the end (stator frame), the
 * rotor-frame integrals of current and voltage, the shaft at the end. */
typedef struct {
    cpx_t i_end;     /* [A] */
    cpx_t I_r;       /* [A s] */
    cpx_t U_r;       /* [V s] */
    double w1_m;     /* [rad/s] */
    double dtheta_m; /* [rad] */
} pass_t;

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

/* One pass at the held electrical speed w with the acceleration alpha for
 * the first-order corrections (plant_design.md sec. 2-3). */
static void period_pass(const plant_t *p, double w, double alpha, pass_t *o)
{
    const plant_period_t *q = &p->per;
    const plant_cfg_t *c = &p->cfg;
    const double L = c->L_H;
    const double R = c->R_Ohm;
    const double a = R * p->inv_L_per_H;
    const double tau = q->tau_s;
    const cpx_t ew = ser_cis(w * tau);
    const cpx_t z0 = { p->z_cos, p->z_sin };
    const cpx_t zc = cmul(z0, ew);

    /* Over the pulses: W = int e^(-j w s) u ds, Ws = int s e^(-j w s) u ds,
     * Wq = int (s^2 - tau^2) e^(-j w s) u ds; the centred ones from the
     * moments while |w| tau allows the series. */
    cpx_t W = { 0.0, 0.0 };
    cpx_t Ws = { 0.0, 0.0 };
    cpx_t Wq = { 0.0, 0.0 };
    const bool by_moments = fabs(w) * tau <= SERIES_MAX;
    if (by_moments) {
        const double w2 = w * w;
        W = moment_series(q, 0, w2, SINC_RATIO);
        const cpx_t G = moment_series(q, 1, w2, Q_RATIO);   /* x/3 - x^3/30 ...: w G/3 = int s e^(-jws) u j */
        Ws.re = w * (1.0 / 3.0) * G.im;
        Ws.im = -w * (1.0 / 3.0) * G.re;
        Wq.re = (1.0 / 3.0) * q->M_a[1] - 0.1 * w2 * q->M_a[2];
        Wq.im = (1.0 / 3.0) * q->M_b[1] - 0.1 * w2 * q->M_b[2];
    }
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
    Wq.re -= tau * tau * W.re;
    Wq.im -= tau * tau * W.im;

    /* i(tau) = E [E i0 + S/L - j w (psi_f/L) zc K] + di, K = 2 tau shc(c tau),
     * di = j (psi_f/L) a D zc E, D = int dtheta ds = -(2/3) alpha tau^3 */
    const cpx_t ct = { a * tau, w * tau };
    const cpx_t sh = ser_cshc(ct);
    const cpx_t zk = cmul(zc, sh);
    const double kp = c->psi_f_Wb * p->inv_L_per_H;
    const double E = q->E;
    const double kw = kp * w * 2.0 * tau;
    const cpx_t ih = { E * (E * q->ia0_A + q->S_a * p->inv_L_per_H + kw * zk.im),
                       E * (E * q->ib0_A + q->S_b * p->inv_L_per_H - kw * zk.re) };
    const double kd = kp * a * E * (-(2.0 / 3.0) * alpha * tau * tau * tau);
    o->i_end.re = ih.re - kd * zc.im;
    o->i_end.im = ih.im + kd * zc.re;

    /* Rotor-frame integrals from the rotor-frame equation integrated over the
     * period: L (ir1 - ir0) = int u conj(z) - R int ir - j L int w ir - j psi_f int w.
     * Held frame (for the shaft's first moment): w constant. True frame (the
     * means): the voltage turned by the true angle, the end current with di,
     * int w ir = w int ir + alpha int s ir. */
    const cpx_t ezc = cmul(zc, ew);
    const cpx_t zec = { ezc.re, -ezc.im };
    const cpx_t z0c = { z0.re, -z0.im };
    const cpx_t zcc = { zc.re, -zc.im };
    const cpx_t i0 = { q->ia0_A, q->ib0_A };
    const cpx_t ir0 = cmul(i0, z0c);
    const cpx_t ir1h = cmul(ih, zec);
    const cpx_t ir1 = cmul(o->i_end, zec);
    const cpx_t U = cmul(zcc, W);
    const cpx_t UQ = cmul(zcc, Wq);
    const double ha = 0.5 * alpha;
    o->U_r.re = U.re + ha * UQ.im;   /* U - j (alpha/2) UQ */
    o->U_r.im = U.im - ha * UQ.re;
    const double emf = w * c->psi_f_Wb * 2.0 * tau;
    cpx_t Is;
    const double rc2 = R * R + w * w * L * L;
    if (rc2 > 0.0) {
        const cpx_t inv_rc = { R / rc2, -w * L / rc2 };
        const cpx_t nh = { U.re - L * (ir1h.re - ir0.re), U.im - emf - L * (ir1h.im - ir0.im) };
        const cpx_t Ih = cmul(nh, inv_rc);
        const cpx_t Us = cmul(zcc, Ws);
        const cpx_t n2 = { Us.re - L * tau * (ir1h.re + ir0.re) + L * Ih.re,
                           Us.im - L * tau * (ir1h.im + ir0.im) + L * Ih.im };
        Is = cmul(n2, inv_rc);
        const double la = L * alpha;   /* - j L alpha Is */
        const cpx_t n1 = { o->U_r.re - L * (ir1.re - ir0.re) + la * Is.im,
                           o->U_r.im - emf - L * (ir1.im - ir0.im) - la * Is.re };
        o->I_r = cmul(n1, inv_rc);
    } else {   /* R = 0 at standstill: trapezoid */
        o->I_r.re = tau * (ir0.re + ir1.re);
        o->I_r.im = tau * (ir0.im + ir1.im);
        Is.re = tau * tau * (ir1.re - ir0.re) * (1.0 / 3.0);
        Is.im = tau * tau * (ir1.im - ir0.im) * (1.0 / 3.0);
    }

    /* the shaft: J dw/dt = kt iq - TL - B w, from the torque's integral and first moment */
    const double pp = (double)c->pole_pairs;
    const double w0 = p->x.omega_m_rad_s;
    const double T = q->T_s;
    if (c->speed_held) {
        o->w1_m = w0;
        o->dtheta_m = w0 * T;
        return;
    }
    const double kt = TORQUE_FACTOR * pp * c->psi_f_Wb;
    const double F0 = kt * o->I_r.im - q->TL_Nm * T;
    const double F1 = kt * (tau * o->I_r.im - Is.im) - q->TL_Nm * T * T * 0.5;
    const double inv_J = p->inv_J_per_kgm2;
    const double w1f = w0 + F0 * inv_J;
    o->dtheta_m = w0 * T + (F1 - c->B_Nms * T * T * (2.0 * w0 + w1f) * (1.0 / 6.0)) * inv_J;
    o->w1_m = w1f - c->B_Nms * o->dtheta_m * inv_J;
}

void plant_period_end(plant_t *p)
{
    plant_period_t *q = &p->per;
    const double pp = (double)p->cfg.pole_pairs;
    /* S = int e^(a s) u ds: the centred pulses' share from the moments */
    const double a = p->cfg.R_Ohm * p->inv_L_per_H;
    if (a * q->tau_s <= SERIES_MAX) {
        const cpx_t S = moment_series(q, 0, a * a, SHC_RATIO);
        q->S_a += S.re;
        q->S_b += S.im;
    } else {
        for (int k = 0; k < q->n_pulses; k++) {
            const plant_pulse_t *pu = &q->pulse[k];
            if (pu->centre_s == 0.0) {
                const double f = 2.0 * pu->half_s * ser_shc(a * pu->half_s);
                q->S_a += f * pu->ua_V;
                q->S_b += f * pu->ub_V;
            }
        }
    }
    pass_t o;
    period_pass(p, q->w_el_rad_s, q->alpha_el_rad_s2, &o);
    if (!p->cfg.speed_held) {
        /* pass 2 at the mean speed and acceleration pass 1 found */
        const double w0 = p->x.omega_m_rad_s;
        const double w_mean = pp * o.dtheta_m / q->T_s;
        const double alpha = pp * (o.w1_m - w0) / q->T_s;
        period_pass(p, w_mean, alpha, &o);
    }
    p->x.omega_m_rad_s = o.w1_m;
    p->x.theta_m_rad += o.dtheta_m;
    wrap_theta(p);
    phasor_update(p);
    p->x.id_A = p->z_cos * o.i_end.re + p->z_sin * o.i_end.im;
    p->x.iq_A = p->z_cos * o.i_end.im - p->z_sin * o.i_end.re;
    p->acc.time_s += q->T_s;
    p->acc.id_As += o.I_r.re;
    p->acc.iq_As += o.I_r.im;
    p->acc.ud_Vs += o.U_r.re;
    p->acc.uq_Vs += o.U_r.im;
}

/* Walker: i(s) = e^(-a s) [E i0 + P(s)/L - j w (psi_f/L) zc int_{-tau}^{s} e^(c s') ds'],
 * P(s) = int_{-tau}^{s} e^(a s') u ds', at pass 1's speed and acceleration. */
void plant_walk_iabc_A(const plant_t *p, double i_abc_A[3])
{
    const plant_period_t *q = &p->per;
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

void plant_step_open(plant_t *p, double TL_Nm, double h_s)
{
    p->x.id_A = 0.0;
    p->x.iq_A = 0.0;
    const plant_cfg_t *c = &p->cfg;
    double w0 = p->x.omega_m_rad_s;
    double a1 = 0.0;
    double a2 = 0.0;
    double a3 = 0.0;
    double a4 = 0.0;
    if (!c->speed_held) {
        /* Linear in w: RK4 stages of J dw/dt = -TL - B w. */
        a1 = (-TL_Nm - c->B_Nms * w0) * p->inv_J_per_kgm2;
        a2 = (-TL_Nm - c->B_Nms * (w0 + 0.5 * h_s * a1)) * p->inv_J_per_kgm2;
        a3 = (-TL_Nm - c->B_Nms * (w0 + 0.5 * h_s * a2)) * p->inv_J_per_kgm2;
        a4 = (-TL_Nm - c->B_Nms * (w0 + h_s * a3)) * p->inv_J_per_kgm2;
    }
    p->x.omega_m_rad_s += h_s * rk4_sum(a1, a2, a3, a4);
    p->x.theta_m_rad += h_s * rk4_sum(w0, w0 + 0.5 * h_s * a1, w0 + 0.5 * h_s * a2, w0 + h_s * a3);
    p->acc.time_s += h_s;
    wrap_theta(p);
    phasor_update(p);
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
