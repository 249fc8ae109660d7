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

/* RK4 weights 1, 2, 2, 1 over 6. */
static double rk4_sum(double a, double b, double c, double d)
{
    return (a + 2.0 * b + 2.0 * c + d) * (1.0 / 6.0);
}

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

void plant_pieces_begin(plant_t *p)
{
    p->i_alpha_A = p->z_cos * p->x.id_A - p->z_sin * p->x.iq_A;
    p->i_beta_A = p->z_sin * p->x.id_A + p->z_cos * p->x.iq_A;
}

/* One RK4 step in the stator frame: the voltage needs no turning at the
 * stages and the back-EMF's angle rides along as the phasor z, so a piece
 * takes no sin/cos (plant_pieces_end() puts z back on the exact angle).
 * Fourth order; z's own error is (w_el h)^5/120, below 1e-8 at one 100 us
 * step at 2200 r/min. */
void plant_piece(plant_t *p, double u_alpha_V, double u_beta_V, double TL_Nm, double h_s)
{
    const plant_cfg_t *c = &p->cfg;
    const double pp = (double)c->pole_pairs;
    const stage_ctx_t k = { pp, c->R_Ohm, c->psi_f_Wb, c->B_Nms, p->inv_L_per_H,
                            c->speed_held ? 0.0 : p->inv_J_per_kgm2,
                            TORQUE_FACTOR * pp * c->psi_f_Wb, u_alpha_V, u_beta_V, TL_Nm };
    const stat_t x0 = { p->i_alpha_A, p->i_beta_A, p->x.omega_m_rad_s, p->z_cos, p->z_sin };
    stat_t k1, k2, k3, k4, x1, x2, x3;
    double id0, id1, id2, id3, iq0, iq1, iq2, iq3;
    deriv_ab(&k, &x0, &k1, &id0, &iq0);
    axpy_ab(&x0, 0.5 * h_s, &k1, &x1);
    deriv_ab(&k, &x1, &k2, &id1, &iq1);
    axpy_ab(&x0, 0.5 * h_s, &k2, &x2);
    deriv_ab(&k, &x2, &k3, &id2, &iq2);
    axpy_ab(&x0, h_s, &k3, &x3);
    deriv_ab(&k, &x3, &k4, &id3, &iq3);

    p->i_alpha_A = x0.ia + h_s * rk4_sum(k1.ia, k2.ia, k3.ia, k4.ia);
    p->i_beta_A = x0.ib + h_s * rk4_sum(k1.ib, k2.ib, k3.ib, k4.ib);
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

void plant_pieces_end(plant_t *p)
{
    wrap_theta(p);
    phasor_update(p);
    p->x.id_A = p->z_cos * p->i_alpha_A + p->z_sin * p->i_beta_A;
    p->x.iq_A = p->z_cos * p->i_beta_A - p->z_sin * p->i_alpha_A;
}

void plant_step(plant_t *p, double u_alpha_V, double u_beta_V, double TL_Nm, double h_s)
{
    plant_pieces_begin(p);
    plant_piece(p, u_alpha_V, u_beta_V, TL_Nm, h_s);
    plant_pieces_end(p);
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
    th = fmod(th, SIM_TWO_PI);
    return (th < 0.0) ? th + SIM_TWO_PI : th;
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

/* Phase currents of stator-frame currents; the zero sequence is 0 (isolated star). */
static void ab_to_abc(double i_alpha_A, double i_beta_A, double i_abc_A[3])
{
    i_abc_A[0] = i_alpha_A;
    i_abc_A[1] = -0.5 * i_alpha_A + 0.5 * SQRT3 * i_beta_A;
    i_abc_A[2] = -0.5 * i_alpha_A - 0.5 * SQRT3 * i_beta_A;
}

void plant_iabc_A(const plant_t *p, double i_abc_A[3])
{
    ab_to_abc(p->z_cos * p->x.id_A - p->z_sin * p->x.iq_A, p->z_sin * p->x.id_A + p->z_cos * p->x.iq_A, i_abc_A);
}

void plant_piece_iabc_A(const plant_t *p, double i_abc_A[3])
{
    ab_to_abc(p->i_alpha_A, p->i_beta_A, i_abc_A);
}

void plant_acc_clear(plant_t *p)
{
    p->acc.time_s = 0.0;
    p->acc.id_As = 0.0;
    p->acc.iq_As = 0.0;
    p->acc.ud_Vs = 0.0;
    p->acc.uq_Vs = 0.0;
}
