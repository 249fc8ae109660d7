/* param_est.c - online L^ and psi_f^ by transfer laws; see param_est.h. */
#include "param_est.h"

#include "mathx.h"

static bool cfg_valid(const param_est_cfg_t *c, const smo_t *smo)
{
    const float sum = c->Ts_s + c->gamma_L_1_s + c->gamma_L_slow_1_s + c->L_fast_s + c->gamma_psi_1_s +
                      c->wiq_min_A_rad_s + c->w_min_rad_s + c->L_min_H + c->L_max_H + c->psi_min_Wb +
                      c->psi_max_Wb + c->L_rate_max_H_s + c->psi_rate_max_Wb_s;
    if (!mathx_isfinitef(sum) || (smo->status != SMO_CFG_OK)) {
        return false;
    }
    if (!(c->Ts_s > 0.0f) || !(c->gamma_L_1_s > 0.0f) || !(c->gamma_L_slow_1_s > 0.0f) ||
        !(c->gamma_L_slow_1_s <= c->gamma_L_1_s) || !(c->L_fast_s >= 0.0f) ||
        !(c->L_fast_s <= PARAM_EST_L_FAST_MAX_S) || !(c->gamma_psi_1_s > 0.0f) ||
        !(c->wiq_min_A_rad_s > 0.0f) || !(c->w_min_rad_s > 0.0f) || !(c->L_rate_max_H_s > 0.0f) ||
        !(c->psi_rate_max_Wb_s > 0.0f)) {
        return false;
    }
    /* gamma Tu < 1: one update never moves more than the whole of f^ */
    if (!(c->gamma_L_1_s * PARAM_EST_LAW_PERIODS * c->Ts_s < 1.0f) ||
        !(c->gamma_psi_1_s * PARAM_EST_LAW_PERIODS * c->Ts_s < 1.0f)) {
        return false;
    }
    /* clamps inside the observer's ranges, so smo_set_L/psi never clip
     * differently from what this module reports */
    return (c->L_min_H >= smo->cfg.L_min_H) && (c->L_min_H <= c->L_max_H) &&
           (c->L_max_H <= smo->cfg.L_max_H) && (c->psi_min_Wb >= smo->cfg.psi_min_Wb) &&
           (c->psi_min_Wb <= c->psi_max_Wb) && (c->psi_max_Wb <= smo->cfg.psi_max_Wb);
}

void param_est_cfg_defaults(param_est_cfg_t *cfg, float Ts_s, float L_H, float psi_f_Wb)
{
    cfg->Ts_s = Ts_s;
    cfg->gamma_L_1_s = PARAM_EST_GAMMA_L_DEFAULT_1_S;
    cfg->gamma_L_slow_1_s = PARAM_EST_GAMMA_L_SLOW_DEFAULT_1_S;
    cfg->L_fast_s = PARAM_EST_L_FAST_DEFAULT_S;
    cfg->gamma_psi_1_s = PARAM_EST_GAMMA_PSI_DEFAULT_1_S;
    cfg->wiq_min_A_rad_s = PARAM_EST_WIQ_MIN_DEFAULT_A_RAD_S;
    cfg->w_min_rad_s = PARAM_EST_W_MIN_DEFAULT_RAD_S;
    cfg->L_min_H = SMO_LPSI_MIN_FACTOR * L_H; /* the observer's bands (smo.h) */
    cfg->L_max_H = SMO_LPSI_MAX_FACTOR * L_H;
    cfg->psi_min_Wb = SMO_LPSI_MIN_FACTOR * psi_f_Wb;
    cfg->psi_max_Wb = SMO_LPSI_MAX_FACTOR * psi_f_Wb;
    cfg->L_rate_max_H_s = PARAM_EST_RATE_MAX_FACTOR_1_S * L_H;
    cfg->psi_rate_max_Wb_s = PARAM_EST_RATE_MAX_FACTOR_1_S * psi_f_Wb;
}

bool param_est_init(param_est_t *pe, const param_est_cfg_t *cfg, const smo_t *smo)
{
    pe->cfg = *cfg;
    pe->valid = cfg_valid(cfg, smo);
    /* per update, every PARAM_EST_LAW_PERIODS periods */
    const float Tu_s = PARAM_EST_LAW_PERIODS * cfg->Ts_s;
    pe->kpsi = pe->valid ? cfg->gamma_psi_1_s * Tu_s : 0.0f;
    pe->dL_max_H = pe->valid ? cfg->L_rate_max_H_s * Tu_s : 0.0f;
    pe->dpsi_max_Wb = pe->valid ? cfg->psi_rate_max_Wb_s * Tu_s : 0.0f;
    param_est_reset(pe);
    return pe->valid;
}

RAMFUNC void param_est_set_gain_L(param_est_t *pe)
{
    const float gamma = (pe->L_fast_left != 0u) ? pe->cfg.gamma_L_1_s : pe->cfg.gamma_L_slow_1_s;
    pe->gamma_L_Tu = (pe->valid && !pe->L_held) ? gamma * (PARAM_EST_LAW_PERIODS * pe->cfg.Ts_s) : 0.0f;
}

/* The L law's updates at gamma_L from a (re)start: L_fast_s of running. */
RAMFUNC static void restart_fast_L(param_est_t *pe)
{
    pe->L_fast_left = pe->valid ? (uint32_t)(pe->cfg.L_fast_s / (PARAM_EST_LAW_PERIODS * pe->cfg.Ts_s)) : 0u;
    param_est_set_gain_L(pe);
}

FLASHFUNC void param_est_reset(param_est_t *pe)
{
    pe->running = false;
    pe->phase_psi = true; /* the first update is L^'s */
    pe->flags_last = 0u;
    pe->L_held = false;
    restart_fast_L(pe);
}

RAMFUNC void param_est_hold_L(param_est_t *pe, bool hold)
{
    pe->L_held = hold;
    param_est_set_gain_L(pe);
}

RAMFUNC void param_est_run(param_est_t *pe, bool run)
{
    pe->running = run && pe->valid;
    if (pe->running) {
        restart_fast_L(pe); /* L^ starts again from the observer's value: converge first */
    }
}
