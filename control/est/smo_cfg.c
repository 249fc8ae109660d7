/* smo_cfg.c - the observer's configuration: its gains designed on the
 * exact discrete model, the defaults and the checks of smo_init; see
 * smo.h. Background only (runs from flash on the target: target.mk). */
#include "smo.h"

#include "mathx.h"

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

bool smo_gains_design(float Ts_s, float R_Ohm, float L_H, float ef_max_V, smo_gains_t *g)
{
    zoh_model_t m;
    const float p = 2.0f * SMO_POLE_DEFAULT - 1.0f; /* the first root of the double pole */
    const float one_m_z = 1.0f - SMO_POLE_DEFAULT;

    g->Ks_V = 0.0f;
    g->phi_A = 0.0f;
    g->mu_1_s = 0.0f;
    g->ef_max_V = ef_max_V;
    if (!zoh_model(R_Ohm, L_H, Ts_s, &m) || !(ef_max_V > 0.0f) || !mathx_isfinitef(ef_max_V)) {
        return false;
    }
    const float Gg = m.rho - p; /* G g: the feedback's share of the error's decay */
    if (!(L_H >= SMO_LR_MIN_PERIODS * Ts_s * R_Ohm) || !(Gg > 0.0f)) {
        return false;
    }
    const float G = Gg / m.gamma_A_V;
    g->mu_1_s = one_m_z * one_m_z / (Ts_s * Gg);
    /* the reaching condition towards the layer at any R^ >= 0: Ks > ef_max, (36) (discrete_model_design.md sec. 5) */
    g->Ks_V = SMO_KS_PER_EF * ef_max_V;
    g->phi_A = g->Ks_V / G;
    return true;
}

float smo_L_floor_H(float Ts_s, float R_Ohm, const smo_gains_t *g)
{
    const float c = g->Ks_V / g->phi_A + g->ef_max_V / g->phi_A; /* G + ef_max/phi [V/A] */
    if (!(c > R_Ohm)) {
        return 0.0f; /* (1 + rho)/g = R coth(Ts R/(2 L)) > R >= c at any L^: no floor */
    }
    /* ln((c + R)/(c - R)) = 2 atanh(y), y = R/c < 1: its series to y^5 is
     * below it, so the floor is at or above the exact one (within 1 % for
     * y <= 0.5, y^7/7 of it); R^ -> 0 gives the limit Ts c / 2 */
    const float y = R_Ohm / c;
    const float y2 = y * y;
    return 0.5f * Ts_s * c / (1.0f + y2 * ((1.0f / 3.0f) + y2 * 0.2f));
}

void smo_cfg_defaults(smo_cfg_t *cfg, float Ts_s, float R_Ohm, float L_H, float psi_f_Wb, const smo_gains_t *g)
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
    cfg->Ks_V = g->Ks_V;
    cfg->phi_A = g->phi_A;
    cfg->mu_d_1_s = g->mu_1_s;
    cfg->mu_q_1_s = g->mu_1_s;
    cfg->ef_max_V = g->ef_max_V;
    cfg->f_max_V = 0.0f;
    cfg->i_max_A = 0.0f;
    cfg->u_max_V = 0.0f;
    cfg->omega_max_rad_s = 0.0f;
}

/* The linear region at R^, L^ (a corner of the ranges): the error's
 * z^2 - (1 + p) z + p + k, p = rho - g G, k = mu Ts g G, inside the unit
 * circle (Jury); and the reaching condition at the layer's edge:
 * Ks + R^ phi > ef_max (towards the layer) and phi (1 + rho) > g
 * (ef_max + Ks) (not past it). */
static smo_status_t corner_check(const smo_cfg_t *c, float R_Ohm, float L_H)
{
    zoh_model_t m;
    if (!zoh_model(R_Ohm, L_H, c->Ts_s, &m)) {
        return SMO_CFG_INVALID;
    }
    const float G = c->Ks_V / c->phi_A;
    const float mu_Ts = ((c->mu_d_1_s > c->mu_q_1_s) ? c->mu_d_1_s : c->mu_q_1_s) * c->Ts_s;
    const float p = m.rho - m.gamma_A_V * G;
    const float k = mu_Ts * m.gamma_A_V * G;
    if (!((p + k < 1.0f) && (p + k > -1.0f) && (2.0f + 2.0f * p + k > 0.0f))) {
        return SMO_CFG_UNSTABLE;
    }
    if (!((c->Ks_V + R_Ohm * c->phi_A > c->ef_max_V) &&
          (c->phi_A * (1.0f + m.rho) > m.gamma_A_V * (c->ef_max_V + c->Ks_V)))) {
        return SMO_CFG_KS_TOO_SMALL;
    }
    return SMO_CFG_OK;
}

static smo_status_t smo_check(const smo_cfg_t *c)
{
    if (!all_finite(c)) {
        return SMO_CFG_INVALID;
    }
    if (!(c->Ts_s > 0.0f) || !(c->R_min_Ohm > 0.0f) || !(c->L_min_H > 0.0f) ||
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
    const float R[2] = { c->R_min_Ohm, c->R_max_Ohm };
    const float L[2] = { c->L_min_H, c->L_max_H };
    smo_status_t worst = SMO_CFG_OK;
    for (uint16_t a = 0u; a < 2u; a++) {
        for (uint16_t b = 0u; b < 2u; b++) {
            const smo_status_t st = corner_check(c, R[a], L[b]);
            worst = (st > worst) ? st : worst;
        }
    }
    return worst;
}

smo_status_t smo_init(smo_t *smo, const smo_cfg_t *cfg)
{
    smo->cfg = *cfg;
    smo->i_lo_A = -cfg->i_max_A;
    smo->f_lo_V = -cfg->f_max_V;
    smo->omega_lo_rad_s = -cfg->omega_max_rad_s;
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

dq_t smo_step(smo_t *smo, dq_t i_A, float omega_el_rad_s, dq_t u_V)
{
    const float w = mathx_clampf(omega_el_rad_s, -smo->cfg.omega_max_rad_s, smo->cfg.omega_max_rad_s);
    zoh_turn_t t;
    zoh_turn(w * smo->cfg.Ts_s, w, &t);
    return smo_step_turn(smo, i_A, u_V, w, &t);
}
