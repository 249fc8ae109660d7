/* est_cfg.c - the estimation's settings and its start-up: the observer's
 * gains, the R^ band, the defaults, est_init; see est.h. Background only
 * (runs from flash on the target: target.mk). */
#include "est.h"

#include "mathx.h"

/* The floor of L^: this factor above the lowest L^ at which the
 * observer's reaching condition holds at R_min (smo_L_floor_H), so an
 * estimate near the floor still leaves the linear region a margin. */
#define EST_L_MIN_STABILITY_MARGIN 1.25f

bool est_obs_gains(const est_told_t *told, float ef_max_V, smo_gains_t *g)
{
    return smo_gains_design(told->Ts_s, told->R_Ohm, told->L_H, ef_max_V, g);
}

void est_rsid_band(const est_told_t *told, float *R_min_Ohm, float *R_max_Ohm)
{
    *R_min_Ohm = RS_IDENT_BAND_MIN_FACTOR * told->R_Ohm;
    *R_max_Ohm = RS_IDENT_BAND_MAX_FACTOR * told->R_Ohm;
}

void est_cfg_defaults(est_cfg_t *cfg, const est_told_t *told, const smo_gains_t *g, float R_min_Ohm,
                      float R_max_Ohm)
{
    smo_cfg_t *sc = &cfg->smo;
    param_est_cfg_t *ec = &cfg->pe;

    cfg->R_min_Ohm = R_min_Ohm;
    cfg->R_max_Ohm = R_max_Ohm;
    smo_cfg_defaults(sc, told->Ts_s, told->R_Ohm, told->L_H, told->psi_f_Wb, g);
    const float L_stable_H = EST_L_MIN_STABILITY_MARGIN * smo_L_floor_H(told->Ts_s, R_min_Ohm, g);
    /* not capped at L_max: a floor above it is refused by smo_init */
    sc->L_min_H = (sc->L_min_H >= L_stable_H) ? sc->L_min_H : L_stable_H;
    sc->f_max_V = told->u_max_V; /* a disturbance beyond the voltage bound is no estimate */
    param_est_cfg_defaults(ec, told->Ts_s, told->L_H, told->psi_f_Wb);
    ec->L_min_H = sc->L_min_H; /* clamps = the observer's ranges */
    ec->L_max_H = sc->L_max_H;
    ec->psi_min_Wb = sc->psi_min_Wb;
    ec->psi_max_Wb = sc->psi_max_Wb;
    rs_ident_cfg_defaults(&cfg->rsid, told->R_Ohm);
    r_track_cfg_defaults(&cfg->rtrack);
    cfg->track_R = EST_TRACK_R_OFF;
    cfg->untold_deadtime_s = EST_UNTOLD_DEADTIME_DEFAULT_S;
    est_gate_cfg_defaults(&cfg->gate, told->Ts_s);
    /* above the speed estimate's count quantisation (step2_design.md sec. 5) */
    cfg->gate.accel_floor_rad_s2 =
        est_gate_accel_floor_rad_s2(told->enc_counts_per_rev, told->pole_pairs, told->enc_pll_bw_rad_s);
}

/* The observer with the told values and bounds written in: true when smo_init took it. */
static bool init_observer(est_t *e, const est_cfg_t *c, const est_told_t *t)
{
    smo_cfg_t sc = c->smo;
    sc.Ts_s = t->Ts_s;
    sc.R_Ohm = t->R_Ohm;
    sc.L_H = t->L_H;
    sc.psi_f_Wb = t->psi_f_Wb;
    sc.R_min_Ohm = c->R_min_Ohm;
    sc.R_max_Ohm = c->R_max_Ohm;
    sc.i_max_A = t->i_max_A;
    sc.u_max_V = t->u_max_V;
    sc.omega_max_rad_s = t->omega_max_el_rad_s;
    return smo_init(&e->smo, &sc) == SMO_CFG_OK;
}

/* The transfer laws and psi_f's band (after the observer): true when both took theirs. */
static bool init_laws(est_t *e, const est_cfg_t *c, const est_told_t *t)
{
    param_est_cfg_t pc = c->pe;
    pc.Ts_s = t->Ts_s;
    const bool pe_ok = param_est_init(&e->pe, &pc, &e->smo);
    psi_band_cfg_t bc;
    psi_band_cfg_defaults(&bc, t->Ts_s, c->pe.w_min_rad_s, c->pe.psi_min_Wb, c->pe.psi_max_Wb);
    /* the band's own guard of 1/w: where even the noise alone (unc_abs) fakes
     * unexplained_max of the largest psi_f the model may take, no band can pass;
     * above it the band decides (the psi^ law's floor stays pe's) */
    bc.w_min_rad_s = bc.unc_abs_V / (bc.unexplained_max * c->pe.psi_max_Wb);
    bc.ve_told_per_vdc = (t->Ts_s > 0.0f) ? (EST_FUNDAMENTAL_OF_SQUARE * t->deadtime_s / t->Ts_s) : 0.0f;
    bc.ve_told_drop_V = EST_FUNDAMENTAL_OF_SQUARE * t->device_drop_V;
    bc.ve_prior_per_vdc = (t->Ts_s > 0.0f) ? (EST_FUNDAMENTAL_OF_SQUARE * c->untold_deadtime_s / t->Ts_s) : 0.0f;
    return psi_band_init(&e->pb, &bc) && pe_ok;
}

est_status_t est_init(est_t *e, const est_cfg_t *cfg, const est_told_t *told)
{
    const rs_ident_out_t no_result = { 0 };
    const est_cfg_t *c = cfg;
    const est_told_t *t = told;
    est_status_t status;

    e->cfg.R_Ohm = t->R_Ohm;
    e->cfg.L_H = t->L_H;
    e->cfg.psi_f_Wb = t->psi_f_Wb;
    e->cfg.R_min_Ohm = c->R_min_Ohm;
    e->cfg.R_max_Ohm = c->R_max_Ohm;
    e->cfg.w_min_rad_s = c->pe.w_min_rad_s;
    e->cfg.wiq_min_A_rad_s = c->pe.wiq_min_A_rad_s;
    e->cfg.track_R = c->track_R;
    e->cfg.auto_delay_periods = c->rtrack.auto_delay_periods;
    e->cfg.deadtime_frac = (t->Ts_s > 0.0f) ? (t->deadtime_s / t->Ts_s) : 0.0f;
    e->cfg.device_drop_V = t->device_drop_V;
    e->cfg.untold_frac = (t->Ts_s > 0.0f) ? (c->untold_deadtime_s / t->Ts_s) : 0.0f;
    /* each block's settings with the told values and bounds written in, one
     * block at a time (the start-up stack holds one block's settings) */
    est_status_t gate;
    bool obs_ok;
    bool rt_ok;
    bool pe_ok;
    bool ri_ok;
    {
        est_gate_cfg_t gc = c->gate;
        gc.Ts_s = t->Ts_s;
        gate = est_gate_init(&e->gate, &gc) ? EST_CFG_OK : EST_CFG_GATE;
    }
    obs_ok = init_observer(e, c, t);
    {
        r_track_cfg_t rc = c->rtrack;
        rc.Ts_s = t->Ts_s;
        rt_ok = r_track_init(&e->rt, &rc);
    }
    /* every block initialised; the first refusal in this order names the cause (a refused
     * observer also freezes the estimator: not reported again) */
    pe_ok = init_laws(e, c, t);
    {
        rs_ident_cfg_t ic = c->rsid;
        ic.R_nom_Ohm = t->R_Ohm;
        ic.Ts_s = t->Ts_s;
        ic.R_min_Ohm = c->R_min_Ohm;
        ic.R_max_Ohm = c->R_max_Ohm;
        ri_ok = rs_ident_init(&e->ri, &ic);
    }
    if (!obs_ok) {
        status = (est_status_t)(EST_CFG_OBSERVER | gate);
    } else if (!rt_ok) {
        status = EST_CFG_RTRACK;
    } else if (!pe_ok) {
        status = (est_status_t)(EST_CFG_ESTIMATOR | gate);
    } else {
        status = (est_status_t)((ri_ok ? EST_CFG_OK : EST_CFG_RSID) | gate);
    }
    e->status = status;
    e->rsid_out = no_result;
    e->rsid_out.R_est_Ohm = t->R_Ohm;
    est_reset(e);
    return status;
}

