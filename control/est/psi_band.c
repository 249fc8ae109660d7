/* psi_band.c - the model's psi_f through a dead band; see psi_band.h. */
#include "psi_band.h"

#include "mathx.h"

void psi_band_cfg_defaults(psi_band_cfg_t *cfg, float Ts_s, float w_min_rad_s, float psi_min_Wb, float psi_max_Wb)
{
    cfg->Ts_s = Ts_s;
    cfg->tau_s = PSI_BAND_TAU_DEFAULT_S;
    cfg->w_min_rad_s = w_min_rad_s;
    cfg->psi_min_Wb = psi_min_Wb;
    cfg->psi_max_Wb = psi_max_Wb;
    cfg->unc_told_frac = PSI_BAND_UNC_TOLD_FRAC_DEFAULT;
    cfg->unc_ident_frac = PSI_BAND_UNC_IDENT_FRAC_DEFAULT;
    cfg->unc_found_frac = PSI_BAND_UNC_FOUND_FRAC_DEFAULT;
    cfg->unc_found_sync_frac = PSI_BAND_UNC_FOUND_SYNC_FRAC_DEFAULT;
    cfg->unc_abs_V = PSI_BAND_UNC_ABS_DEFAULT_V;
    cfg->ve_told_per_vdc = 0.0f;
    cfg->ve_told_drop_V = 0.0f;
    cfg->ve_prior_per_vdc = 0.0f;
    cfg->settle_s = PSI_BAND_SETTLE_DEFAULT_S;
    cfg->settle_frac = PSI_BAND_SETTLE_FRAC_DEFAULT;
    cfg->unexplained_max = PSI_BAND_UNEXPLAINED_MAX_DEFAULT;
}

bool psi_band_init(psi_band_t *pb, const psi_band_cfg_t *cfg)
{
    const float sum = cfg->Ts_s + cfg->tau_s + cfg->w_min_rad_s + cfg->psi_min_Wb + cfg->psi_max_Wb +
                      cfg->unc_told_frac + cfg->unc_ident_frac + cfg->unc_found_frac + cfg->unc_found_sync_frac + cfg->unc_abs_V +
                      cfg->ve_told_per_vdc + cfg->ve_told_drop_V + cfg->ve_prior_per_vdc + cfg->settle_s + cfg->settle_frac + cfg->unexplained_max;
    const bool ok = mathx_isfinitef(sum) && (cfg->Ts_s > 0.0f) && (cfg->tau_s > cfg->Ts_s) &&
                    (cfg->w_min_rad_s > 0.0f) && (cfg->psi_min_Wb > 0.0f) && (cfg->psi_min_Wb <= cfg->psi_max_Wb) &&
                    (cfg->unc_told_frac >= 0.0f) && (cfg->unc_ident_frac >= 0.0f) &&
                    (cfg->unc_found_frac >= 0.0f) && (cfg->unc_found_sync_frac >= 0.0f) && (cfg->unc_abs_V >= 0.0f) &&
                    (cfg->ve_told_per_vdc >= 0.0f) && (cfg->ve_told_drop_V >= 0.0f) && (cfg->ve_prior_per_vdc >= 0.0f) &&
                    (cfg->settle_s >= cfg->Ts_s * (float)PSI_BAND_DECIDE_PERIODS) &&
                    (cfg->settle_s <= 1.0f) && (cfg->settle_frac >= 0.0f) && (cfg->unexplained_max > 0.0f);

    pb->cfg = *cfg;
    pb->a = ok ? (cfg->Ts_s / cfg->tau_s) : 0.0f;
    pb->settle_n = ok ? (uint16_t)(cfg->settle_s / (cfg->Ts_s * (float)PSI_BAND_DECIDE_PERIODS) + 0.5f) : 1u;
    psi_band_start(pb, ok ? cfg->psi_min_Wb : 1.0f);
    return ok;
}

RAMFUNC void psi_band_start(psi_band_t *pb, float psi_Wb)
{
    pb->k_per_vdc = pb->cfg.unc_told_frac * pb->cfg.ve_told_per_vdc;
    pb->k_V = pb->cfg.unc_told_frac * pb->cfg.ve_told_drop_V;
    pb->found_frac = pb->cfg.unc_found_frac;
    pb->r_unc_V = 0.0f;
    pb->track = false;
    pb->taken = false;
    pb->low = 0u;
    pb->final = false;
    pb->unknown = false;
    pb->trust = false;
    pb->n = 0u;
    pb->k = 0u;
    pb->anchor_Wb = psi_Wb;
    pb->h_Wb = psi_Wb;
    pb->inv_w_s_rad = 0.0f;
    pb->P_Wb = psi_Wb;
    pb->P_snap_Wb = psi_Wb;
    pb->psi_Wb = psi_Wb;
}

RAMFUNC void psi_band_rebase(psi_band_t *pb, float dfq_V, bool sync)
{
    pb->found_frac = sync ? pb->cfg.unc_found_sync_frac : pb->cfg.unc_found_frac;
    pb->P_Wb += dfq_V * pb->inv_w_s_rad;
    pb->k_per_vdc = pb->cfg.unc_ident_frac * pb->cfg.ve_told_per_vdc;
    pb->k_V = pb->cfg.unc_ident_frac * pb->cfg.ve_told_drop_V;
    pb->track = false;
    pb->taken = false;
    pb->final = true;
    pb->h_Wb = pb->anchor_Wb;
}

RAMFUNC void psi_band_r_moved(psi_band_t *pb, float dfq_V)
{
    pb->P_Wb += dfq_V * pb->inv_w_s_rad;
    pb->r_unc_V = mathx_fabsf(dfq_V); /* R^'s error is of the order of its last correction */
    if (pb->taken && !pb->track) {
        /* held since P settled on the R^ before: decided again on this one (tracking: P carries it) */
        pb->h_Wb = mathx_clampf(pb->P_Wb, pb->cfg.psi_min_Wb, pb->cfg.psi_max_Wb);
    }
}

RAMFUNC void psi_band_hold(psi_band_t *pb, bool hold)
{
    pb->low = hold ? (uint16_t)(pb->low | PSI_BAND_LOW_HELD) : (uint16_t)(pb->low & (uint16_t)~PSI_BAND_LOW_HELD);
}

FLASHFUNC void psi_band_bound_measured(psi_band_t *pb)
{
    pb->k_per_vdc = pb->cfg.unc_ident_frac * pb->cfg.ve_told_per_vdc + pb->cfg.ve_prior_per_vdc;
    pb->k_V = pb->cfg.unc_ident_frac * pb->cfg.ve_told_drop_V;
    pb->final = true;
}

RAMFUNC void psi_band_bound_unknown(psi_band_t *pb)
{
    pb->final = true;
    pb->unknown = true;
    pb->trust = false;
    pb->low = (uint16_t)(pb->low | PSI_BAND_LOW_BAND);
}

RAMFUNC void psi_band_pause(psi_band_t *pb, float omega_el_rad_s)
{
    pb->k = 0u;
    pb->low = (mathx_fabsf(omega_el_rad_s) > pb->cfg.w_min_rad_s) ? (uint16_t)(pb->low & (uint16_t)~PSI_BAND_LOW_W)
                                                                   : (uint16_t)(pb->low | PSI_BAND_LOW_W);
}

RAMFUNC bool psi_band_decide(psi_band_t *pb, float vdc_V, float ve_found_V)
{
    const float inv_w = pb->inv_w_s_rad;
    pb->k = 0u;
    /* Vb/|w|: the flux the voltage nobody can explain may fake at this speed */
    const float abs_inv_w = mathx_fabsf(inv_w);
    const float vdc = mathx_fabsf(vdc_V);
    const float band = (pb->k_per_vdc * vdc + pb->k_V + pb->found_frac * mathx_fabsf(ve_found_V) +
                        pb->r_unc_V + pb->cfg.unc_abs_V) * abs_inv_w;
    /* the floor: the final bound, or before it the prior on what nobody told (holds_design.md sec. 6) */
    const float floor_band = pb->final ? band : ((pb->cfg.ve_prior_per_vdc * vdc + pb->cfg.unc_abs_V) * abs_inv_w);
    const float band_max = pb->cfg.unexplained_max * mathx_fabsf(pb->P_Wb);
    const float band_in = ((pb->low & PSI_BAND_LOW_BAND) != 0u) ? (PSI_BAND_LOW_HYST * floor_band) : floor_band;
    pb->low = (uint16_t)(((pb->unknown || (band_in > band_max)) ? PSI_BAND_LOW_BAND : 0u) |
                         (pb->low & PSI_BAND_LOW_HELD));
    pb->trust = pb->final && (pb->low == 0u);
    if (!pb->track && (mathx_fabsf(pb->P_Wb - pb->h_Wb) > 2.0f * band)) {
        pb->track = true; /* h is off by more than P can be */
        pb->taken = true;
        pb->n = 0u;
        pb->P_snap_Wb = pb->P_Wb;
    }
    if (pb->track) {
        pb->n++;
        if (pb->n >= pb->settle_n) {
            if (mathx_fabsf(pb->P_Wb - pb->P_snap_Wb) <= pb->cfg.settle_frac * band) {
                pb->track = false; /* settled: hold it */
            }
            pb->n = 0u;
            pb->P_snap_Wb = pb->P_Wb;
        }
        pb->h_Wb = mathx_clampf(pb->P_Wb, pb->cfg.psi_min_Wb, pb->cfg.psi_max_Wb);
    }
    const bool moved = (pb->h_Wb < pb->psi_Wb) || (pb->h_Wb > pb->psi_Wb);
    pb->psi_Wb = pb->h_Wb;
    return moved;
}
