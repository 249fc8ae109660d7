/* smo.c - sliding-mode current and disturbance observer; see smo.h. */
#include "smo.h"

#include "mathx.h"

/* Half of the second-order term of the ZOH decay exp(-Ts R/L). */
#define ZOH_HALF 0.5f
/* Discrete stability of the linear region: a = 1 - Ts (R + G)/L > -1. */
#define STABILITY_TWO 2.0f

static bool all_finite(const smo_cfg_t *c)
{
    const float sum = c->Ts_s + c->R_Ohm + c->L_H + c->psi_f_Wb + c->R_min_Ohm + c->R_max_Ohm +
                      c->L_min_H + c->L_max_H + c->psi_min_Wb + c->psi_max_Wb + c->Ks_V +
                      c->phi_A + c->mu_d_1_s + c->mu_q_1_s + c->ef_max_V + c->f_max_V +
                      c->i_max_A + c->u_max_V + c->omega_max_rad_s;
    return mathx_isfinitef(sum); /* NaN and Inf survive a sum */
}

static bool in_range(float x, float lo, float hi)
{
    return (x >= lo) && (x <= hi);
}

static smo_status_t smo_check(const smo_cfg_t *c)
{
    if (!all_finite(c)) {
        return SMO_CFG_INVALID;
    }
    if (!(c->Ts_s > 0.0f) || !(c->R_min_Ohm >= 0.0f) || !(c->L_min_H > 0.0f) ||
        !(c->psi_min_Wb > 0.0f) || !(c->Ks_V > 0.0f) || !(c->phi_A > 0.0f) ||
        !(c->mu_d_1_s > 0.0f) || !(c->mu_q_1_s > 0.0f) || !(c->ef_max_V >= 0.0f) ||
        !(c->f_max_V > 0.0f) || !(c->i_max_A > 0.0f) || !(c->u_max_V > 0.0f) ||
        !(c->omega_max_rad_s > 0.0f)) {
        return SMO_CFG_INVALID;
    }
    if (!in_range(c->R_Ohm, c->R_min_Ohm, c->R_max_Ohm) || !in_range(c->L_H, c->L_min_H, c->L_max_H) ||
        !in_range(c->psi_f_Wb, c->psi_min_Wb, c->psi_max_Wb)) {
        return SMO_CFG_INVALID;
    }
    /* Linear region (|e| < phi): e(k+1) = (1 - Ts (R^ + G)/L^) e(k) + ...;
     * |.| < 1 at the worst corner of the ranges (smallest L^, largest R^). */
    if (!(c->Ks_V / c->phi_A < STABILITY_TWO * c->L_min_H / c->Ts_s - c->R_max_Ohm)) {
        return SMO_CFG_UNSTABLE;
    }
    /* f^ must not jump past its target in one period (constant term of the
     * characteristic polynomial below 1). */
    if (!(c->mu_d_1_s * c->Ts_s < 1.0f) || !(c->mu_q_1_s * c->Ts_s < 1.0f)) {
        return SMO_CFG_UNSTABLE;
    }
    /* (36) in volts: Ks > |f^ - f| + R^ |e| at the boundary layer's edge. */
    if (!(c->Ks_V > c->ef_max_V + c->R_max_Ohm * c->phi_A)) {
        return SMO_CFG_KS_TOO_SMALL;
    }
    return SMO_CFG_OK;
}

/* g = (Ts/L^)(1 - Ts R^/(2 L^)): Euler gain of (51b)/(55) with the
 * second-order term of the exact ZOH decay (smo_design.md sec. 2). 1 division. */
static void update_gain(smo_t *smo)
{
    if (smo->status != SMO_CFG_OK) {
        smo->g_A_per_V = 0.0f; /* L^ may be 0 in a refused cfg */
        return;
    }
    const float Ts_over_L = smo->cfg.Ts_s / smo->L_H;
    smo->g_A_per_V = Ts_over_L * (1.0f - ZOH_HALF * Ts_over_L * smo->R_Ohm);
}

void smo_cfg_defaults(smo_cfg_t *cfg, float Ts_s, float R_Ohm, float L_H, float psi_f_Wb)
{
    cfg->Ts_s = Ts_s;
    cfg->R_Ohm = R_Ohm;
    cfg->L_H = L_H;
    cfg->psi_f_Wb = psi_f_Wb;
    cfg->R_min_Ohm = SMO_R_MIN_FACTOR * R_Ohm;
    cfg->R_max_Ohm = SMO_R_MAX_FACTOR * R_Ohm;
    cfg->L_min_H = SMO_LPSI_MIN_FACTOR * L_H;
    cfg->L_max_H = SMO_LPSI_MAX_FACTOR * L_H;
    cfg->psi_min_Wb = SMO_LPSI_MIN_FACTOR * psi_f_Wb;
    cfg->psi_max_Wb = SMO_LPSI_MAX_FACTOR * psi_f_Wb;
    cfg->Ks_V = SMO_KS_DEFAULT_V;
    cfg->phi_A = SMO_PHI_DEFAULT_A;
    cfg->mu_d_1_s = SMO_MU_DEFAULT_1_S;
    cfg->mu_q_1_s = SMO_MU_DEFAULT_1_S;
    cfg->ef_max_V = SMO_EF_MAX_DEFAULT_V;
    cfg->f_max_V = 0.0f;
    cfg->i_max_A = 0.0f;
    cfg->u_max_V = 0.0f;
    cfg->omega_max_rad_s = 0.0f;
}

smo_status_t smo_init(smo_t *smo, const smo_cfg_t *cfg)
{
    smo->cfg = *cfg;
    smo->status = smo_check(cfg);
    if (smo->status == SMO_CFG_OK) {
        smo->G_V_per_A = cfg->Ks_V / cfg->phi_A;
        smo->inv_phi_1_A = 1.0f / cfg->phi_A;
        smo->mu_d_Ts = cfg->mu_d_1_s * cfg->Ts_s;
        smo->mu_q_Ts = cfg->mu_q_1_s * cfg->Ts_s;
    } else {
        /* smo_step() passes the measurement through, the setters do nothing. */
        smo->G_V_per_A = 0.0f;
        smo->inv_phi_1_A = 0.0f;
        smo->mu_d_Ts = 0.0f;
        smo->mu_q_Ts = 0.0f;
    }
    smo_reset(smo);
    return smo->status;
}

void smo_reset(smo_t *smo)
{
    smo->seeded = false;
    smo->R_Ohm = smo->cfg.R_Ohm;
    smo->L_H = smo->cfg.L_H;
    smo->psi_f_Wb = smo->cfg.psi_f_Wb;
    update_gain(smo);
    smo->i_hat_A.d = 0.0f;
    smo->i_hat_A.q = 0.0f;
    smo->fd_V = 0.0f;
    smo->fq_V = 0.0f;
    smo->U_V.d = 0.0f;
    smo->U_V.q = 0.0f;
}

/* Boundary-layer switching term Ks sat(e/phi) [V] (replaces sign() of (32)). */
static float switching(const smo_t *smo, float e_A)
{
    return smo->cfg.Ks_V * mathx_clampf(e_A * smo->inv_phi_1_A, -1.0f, 1.0f);
}

dq_t smo_step(smo_t *smo, dq_t i_A, float omega_el_rad_s, dq_t u_V)
{
    const smo_cfg_t *c = &smo->cfg;
    const float id = mathx_clampf(i_A.d, -c->i_max_A, c->i_max_A);
    const float iq = mathx_clampf(i_A.q, -c->i_max_A, c->i_max_A);
    const float w = mathx_clampf(omega_el_rad_s, -c->omega_max_rad_s, c->omega_max_rad_s);
    const float ud = mathx_clampf(u_V.d, -c->u_max_V, c->u_max_V);
    const float uq = mathx_clampf(u_V.q, -c->u_max_V, c->u_max_V);
    dq_t next;

    if (smo->status != SMO_CFG_OK) {
        smo->i_hat_A.d = id;
        smo->i_hat_A.q = iq;
        return smo->i_hat_A;
    }
    if (!smo->seeded) {
        /* i^(k) = i(k) at enable: no error, no switching kick. */
        smo->i_hat_A.d = id;
        smo->i_hat_A.q = iq;
        smo->seeded = true;
    }

    /* (30): e = i^ - i, with i^(k) the previous prediction */
    const float Ud = switching(smo, smo->i_hat_A.d - id);
    const float Uq = switching(smo, smo->i_hat_A.q - iq);
    const float wL = w * smo->L_H;

    /* (55) d axis, as corrected: cross term w L^ iq with the MEASURED iq,
     * ZOH gain g instead of Ts/L, U with + sign from the error dynamics */
    next.d = smo->i_hat_A.d + smo->g_A_per_V * (ud - smo->R_Ohm * smo->i_hat_A.d + wL * iq -
                                                 smo->fd_V - Ud);
    /* (51b) q axis, same corrections; -w psi^ with the psi^ in use */
    next.q = smo->i_hat_A.q + smo->g_A_per_V * (uq - smo->R_Ohm * smo->i_hat_A.q - wL * id -
                                                 w * smo->psi_f_Wb - smo->fq_V - Uq);
    /* (51b), (55): f^ += mu Ts U, the sign that makes (37) converge */
    smo->fd_V = mathx_clampf(smo->fd_V + smo->mu_d_Ts * Ud, -c->f_max_V, c->f_max_V);
    smo->fq_V = mathx_clampf(smo->fq_V + smo->mu_q_Ts * Uq, -c->f_max_V, c->f_max_V);

    smo->i_hat_A.d = mathx_clampf(next.d, -c->i_max_A, c->i_max_A);
    smo->i_hat_A.q = mathx_clampf(next.q, -c->i_max_A, c->i_max_A);
    smo->U_V.d = Ud;
    smo->U_V.q = Uq;
    return smo->i_hat_A;
}

void smo_shift_f(smo_t *smo, float dfd_V, float dfq_V)
{
    smo->fd_V += dfd_V;
    smo->fq_V += dfq_V;
}

bool smo_set_R(smo_t *smo, float R_Ohm)
{
    const smo_cfg_t *c = &smo->cfg;
    if ((smo->status != SMO_CFG_OK) || !mathx_isfinitef(R_Ohm) ||
        !in_range(R_Ohm, c->R_min_Ohm, c->R_max_Ohm)) {
        return false;
    }
    /* step1_design.md sec. 1: f^ += dR i^ with dR = R^old - R^new */
    const float dR = smo->R_Ohm - R_Ohm;
    smo->fd_V = mathx_clampf(smo->fd_V + dR * smo->i_hat_A.d, -c->f_max_V, c->f_max_V);
    smo->fq_V = mathx_clampf(smo->fq_V + dR * smo->i_hat_A.q, -c->f_max_V, c->f_max_V);
    smo->R_Ohm = R_Ohm;
    update_gain(smo);
    return true;
}

float smo_set_L(smo_t *smo, float L_H, float omega_el_rad_s, float iq_A)
{
    const smo_cfg_t *c = &smo->cfg;
    if (smo->status != SMO_CFG_OK) {
        return smo->L_H;
    }
    const float w = mathx_clampf(omega_el_rad_s, -c->omega_max_rad_s, c->omega_max_rad_s);
    const float iq = mathx_clampf(iq_A, -c->i_max_A, c->i_max_A);
    /* NaN maps to L_min: never a division by ~0 below */
    const float L_new = mathx_clampf(L_H, c->L_min_H, c->L_max_H);

    /* step2_design.md sec. 1: w L^ iq - fd^ unchanged */
    smo->fd_V = mathx_clampf(smo->fd_V + (L_new - smo->L_H) * w * iq, -c->f_max_V, c->f_max_V);
    smo->L_H = L_new;
    update_gain(smo);
    return L_new;
}

float smo_set_psi(smo_t *smo, float psi_f_Wb, float omega_el_rad_s)
{
    const smo_cfg_t *c = &smo->cfg;
    if (smo->status != SMO_CFG_OK) {
        return smo->psi_f_Wb;
    }
    const float w = mathx_clampf(omega_el_rad_s, -c->omega_max_rad_s, c->omega_max_rad_s);
    const float psi_new = mathx_clampf(psi_f_Wb, c->psi_min_Wb, c->psi_max_Wb);

    /* step2_design.md sec. 2: w psi^ + fq^ unchanged */
    smo->fq_V = mathx_clampf(smo->fq_V - (psi_new - smo->psi_f_Wb) * w, -c->f_max_V, c->f_max_V);
    smo->psi_f_Wb = psi_new;
    return psi_new;
}
