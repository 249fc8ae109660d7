/* plant.c - true SPMSM and shaft; see plant.h for the model. */
#include "plant.h"

#include <math.h>

#define TWO_PI 6.283185307179586
#define SQRT3 1.7320508075688772
#define TORQUE_FACTOR 1.5   /* amplitude-invariant dq: Te = 1.5 p psi_f iq */

/* Table I of the paper. */
#define TABLE1_R_OHM 3.0
#define TABLE1_L_H 0.011
#define TABLE1_PSIF_WB 0.24
#define TABLE1_POLE_PAIRS 3u
#define TABLE1_J_KGM2 0.00129

/* Stage angles within this distance of the anchor use the series below;
 * its truncation error is below 1e-13 there, so libm sin/cos is called
 * about once per 0.1 rad instead of four times per step (bench target). */
#define ANCHOR_SPAN_RAD 0.1

typedef struct {
    plant_state_t dx;
    double ud_V, uq_V;
} deriv_t;

void plant_default_cfg(plant_cfg_t *cfg)
{
    cfg->R_Ohm = TABLE1_R_OHM;
    cfg->L_H = TABLE1_L_H;
    cfg->psi_f_Wb = TABLE1_PSIF_WB;
    cfg->pole_pairs = TABLE1_POLE_PAIRS;
    cfg->J_kgm2 = TABLE1_J_KGM2;
    cfg->B_Nms = 0.0;
    cfg->speed_held = false;
    cfg->omega0_m_rad_s = 0.0;
}

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
}

/* The step's inner functions are inlined into plant_step() (host-only code
 * built with gcc or clang): with the constants and the anchor in locals the
 * four stages share them in registers (callgrind: a third fewer
 * instructions per step). */
#if defined(__GNUC__)
#define PLANT_INLINE static inline __attribute__((always_inline))
#else
#define PLANT_INLINE static inline
#endif

/* What a step reads: the motor's constants and the sin/cos anchor (written back by plant_step). */
typedef struct {
    double pp, R_Ohm, L_H, psi_f_Wb, B_Nms, inv_L_per_H, inv_J_per_kgm2, enc_offset_el_rad;
    bool speed_held;
    double anchor_el_rad, anchor_sin, anchor_cos;
    bool anchor_moved;
} step_ctx_t;

/* sin and cos of the unwrapped electrical angle theta_el_rad. */
PLANT_INLINE void sincos_el(step_ctx_t *k, double theta_el_rad, double *s, double *c)
{
    double d = theta_el_rad - k->anchor_el_rad;
    if (fabs(d) > ANCHOR_SPAN_RAD) {
        k->anchor_el_rad = theta_el_rad;
        k->anchor_sin = sin(theta_el_rad);
        k->anchor_cos = cos(theta_el_rad);
        k->anchor_moved = true;
        d = 0.0;
    }
    /* Taylor series to d^6 and d^7, nested; constant reciprocals fold, so no division. */
    double d2 = d * d;
    double cd = 1.0 - d2 * (1.0 / 2.0) * (1.0 - d2 * (1.0 / 12.0) * (1.0 - d2 * (1.0 / 30.0)));
    double sd = d * (1.0 - d2 * (1.0 / 6.0) * (1.0 - d2 * (1.0 / 20.0) * (1.0 - d2 * (1.0 / 42.0))));
    *s = k->anchor_sin * cd + k->anchor_cos * sd;
    *c = k->anchor_cos * cd - k->anchor_sin * sd;
}

PLANT_INLINE void deriv(step_ctx_t *k, const plant_state_t *x, double ua_V, double ub_V, double TL_Nm, deriv_t *out)
{
    double pp = k->pp;
    double s;
    double co;
    sincos_el(k, pp * x->theta_m_rad + k->enc_offset_el_rad, &s, &co);
    double ud = ua_V * co + ub_V * s;
    double uq = -ua_V * s + ub_V * co;
    double w_el = pp * x->omega_m_rad_s;
    out->ud_V = ud;
    out->uq_V = uq;
    out->dx.id_A = (ud - k->R_Ohm * x->id_A + w_el * k->L_H * x->iq_A) * k->inv_L_per_H;
    out->dx.iq_A = (uq - k->R_Ohm * x->iq_A - w_el * (k->L_H * x->id_A + k->psi_f_Wb)) * k->inv_L_per_H;
    double te = TORQUE_FACTOR * pp * k->psi_f_Wb * x->iq_A;
    out->dx.omega_m_rad_s = k->speed_held ? 0.0 : (te - TL_Nm - k->B_Nms * x->omega_m_rad_s) * k->inv_J_per_kgm2;
    out->dx.theta_m_rad = x->omega_m_rad_s;
}

static plant_state_t axpy(const plant_state_t *x, double h, const plant_state_t *dx)
{
    plant_state_t y;
    y.id_A = x->id_A + h * dx->id_A;
    y.iq_A = x->iq_A + h * dx->iq_A;
    y.omega_m_rad_s = x->omega_m_rad_s + h * dx->omega_m_rad_s;
    y.theta_m_rad = x->theta_m_rad + h * dx->theta_m_rad;
    return y;
}

/* RK4 weights 1, 2, 2, 1 over 6. */
static double rk4_sum(double a, double b, double c, double d)
{
    return (a + 2.0 * b + 2.0 * c + d) * (1.0 / 6.0);
}

/* Keep theta_m in [0, 2 pi); the anchor follows so the series stays valid. */
static void wrap_theta(plant_t *p)
{
    double turn_el = TWO_PI * (double)p->cfg.pole_pairs;
    if (p->x.theta_m_rad >= TWO_PI) {
        p->x.theta_m_rad -= TWO_PI;
        p->anchor_el_rad -= turn_el;
    } else if (p->x.theta_m_rad < 0.0) {
        p->x.theta_m_rad += TWO_PI;
        p->anchor_el_rad += turn_el;
    }
}

void plant_step(plant_t *p, double u_alpha_V, double u_beta_V, double TL_Nm, double h_s)
{
    const plant_state_t x0 = p->x;
    const plant_cfg_t *c = &p->cfg;
    step_ctx_t k = { (double)c->pole_pairs, c->R_Ohm, c->L_H, c->psi_f_Wb, c->B_Nms, p->inv_L_per_H,
                     p->inv_J_per_kgm2, p->enc_offset_el_rad, c->speed_held,
                     p->anchor_el_rad, p->anchor_sin, p->anchor_cos, false };
    deriv_t k1;
    deriv_t k2;
    deriv_t k3;
    deriv_t k4;
    deriv(&k, &x0, u_alpha_V, u_beta_V, TL_Nm, &k1);
    plant_state_t x1 = axpy(&x0, 0.5 * h_s, &k1.dx);
    deriv(&k, &x1, u_alpha_V, u_beta_V, TL_Nm, &k2);
    plant_state_t x2 = axpy(&x0, 0.5 * h_s, &k2.dx);
    deriv(&k, &x2, u_alpha_V, u_beta_V, TL_Nm, &k3);
    plant_state_t x3 = axpy(&x0, h_s, &k3.dx);
    deriv(&k, &x3, u_alpha_V, u_beta_V, TL_Nm, &k4);
    if (k.anchor_moved) {
        p->anchor_el_rad = k.anchor_el_rad;
        p->anchor_sin = k.anchor_sin;
        p->anchor_cos = k.anchor_cos;
    }

    p->x.id_A += h_s * rk4_sum(k1.dx.id_A, k2.dx.id_A, k3.dx.id_A, k4.dx.id_A);
    p->x.iq_A += h_s * rk4_sum(k1.dx.iq_A, k2.dx.iq_A, k3.dx.iq_A, k4.dx.iq_A);
    p->x.omega_m_rad_s += h_s * rk4_sum(k1.dx.omega_m_rad_s, k2.dx.omega_m_rad_s,
                                        k3.dx.omega_m_rad_s, k4.dx.omega_m_rad_s);
    p->x.theta_m_rad += h_s * rk4_sum(k1.dx.theta_m_rad, k2.dx.theta_m_rad,
                                      k3.dx.theta_m_rad, k4.dx.theta_m_rad);

    /* Quadratures with the same stages: the RK4 weights are Simpson's rule. */
    p->acc.time_s += h_s;
    p->acc.id_As += h_s * rk4_sum(x0.id_A, x1.id_A, x2.id_A, x3.id_A);
    p->acc.iq_As += h_s * rk4_sum(x0.iq_A, x1.iq_A, x2.iq_A, x3.iq_A);
    p->acc.ud_Vs += h_s * rk4_sum(k1.ud_V, k2.ud_V, k3.ud_V, k4.ud_V);
    p->acc.uq_Vs += h_s * rk4_sum(k1.uq_V, k2.uq_V, k3.uq_V, k4.uq_V);

    wrap_theta(p);
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
    th = fmod(th, TWO_PI);
    return (th < 0.0) ? th + TWO_PI : th;
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
    plant_iabc_at_A(p, plant_theta_el_rad(p), i_abc_A);
}

void plant_iabc_at_A(const plant_t *p, double th, double i_abc_A[3])
{
    double s = sin(th);
    double c = cos(th);
    double i_alpha = p->x.id_A * c - p->x.iq_A * s;
    double i_beta = p->x.id_A * s + p->x.iq_A * c;
    i_abc_A[0] = i_alpha;
    i_abc_A[1] = -0.5 * i_alpha + 0.5 * SQRT3 * i_beta;
    i_abc_A[2] = -0.5 * i_alpha - 0.5 * SQRT3 * i_beta;
}

void plant_acc_clear(plant_t *p)
{
    p->acc.time_s = 0.0;
    p->acc.id_As = 0.0;
    p->acc.iq_As = 0.0;
    p->acc.ud_Vs = 0.0;
    p->acc.uq_Vs = 0.0;
}
