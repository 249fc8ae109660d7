/* ctrl_cfg.c - the controller's start-up: its blocks from ctrl_cfg_t,
 * the told model for the estimation, the reset, the current limits and
 * the alignment; see ctrl.h. Background only, and (FLASHFUNC) ctrl_reset,
 * ctrl_set_i_lim and ctrl_encoder_align in the start sequence's
 * transitions and ALIGN (runs from flash on the target: target.mk
 * RAMFUNC_ALL_EXCEPT). */
#include "ctrl.h"

#include "mathx.h"
#include "oplim.h"

/* Longest dead time taken as such, in periods, and the largest device drop,
 * x the model's voltage bound: the same share of the bus; beyond either the
 * cfg is refused (0 used). */
#define DEADTIME_FRAC_MAX 0.1f
/* Share of the hexagon's inscribed circle Vdc/sqrt(3) the flux reference
 * leaves for steady state when cfg.u_margin is not in (0, 1]
 * (limits_design.md sec. 2): the rest is the deadbeat's headroom for torque changes. */
#define CTRL_U_MARGIN_DEFAULT 0.92f

void ctrl_cfg_told(const ctrl_cfg_t *cfg, est_told_t *told)
{
    told->Ts_s = cfg->Ts_s;
    told->R_Ohm = cfg->R_Ohm;
    told->L_H = cfg->L_H;
    told->psi_f_Wb = cfg->psi_f_Wb;
    told->pole_pairs = cfg->pole_pairs;
    told->i_max_A = cfg->i_max_A;
    told->u_max_V = cfg->u_max_V;
    told->omega_max_el_rad_s = cfg->omega_max_el_rad_s;
    told->deadtime_s = cfg->deadtime_s;
    told->device_drop_V = cfg->device_drop_V;
    told->enc_counts_per_rev = ENCODER_COUNTS_PER_LINE * cfg->enc_lines;
    told->enc_pll_bw_rad_s = cfg->enc_pll_bw_rad_s;
}

/* The estimation from its settings and the told values and bounds. */
static ctrl_status_t init_est(ctrl_t *c, const ctrl_cfg_t *cfg)
{
    est_told_t told;
    ctrl_cfg_told(cfg, &told);
    told.deadtime_s = c->deadtime_frac * cfg->Ts_s; /* as taken (0 when refused) */
    told.device_drop_V = c->device_drop_V;
    return (ctrl_status_t)est_init(&c->est, &cfg->est_cfg, &told);
}

/* status with bit added unless ok. */
static ctrl_status_t refused_if(bool ok, ctrl_status_t bit, ctrl_status_t status)
{
    return ok ? status : (ctrl_status_t)(status | bit);
}

/* The encoder, the model and the speed PI from *cfg: their refusals. */
static ctrl_status_t init_blocks(ctrl_t *c, const ctrl_cfg_t *cfg)
{
    encoder_cfg_t ec;
    dbdtc_cfg_t dc;
    pi_cfg_t pc;
    ctrl_status_t status = CTRL_CFG_OK;

    ec.counts_per_rev = ENCODER_COUNTS_PER_LINE * cfg->enc_lines;
    ec.pole_pairs = cfg->pole_pairs;
    ec.offset_el_rad = cfg->enc_offset_el_rad;
    ec.Ts_s = cfg->Ts_s;
    ec.pll_bw_rad_s = cfg->enc_pll_bw_rad_s;
    status = refused_if(encoder_init(&c->enc, &ec), CTRL_CFG_ENCODER, status); /* refused: angle 0, speed 0 */

    dc.Ts_s = cfg->Ts_s;
    dc.pole_pairs = cfg->pole_pairs;
    dc.R_Ohm = cfg->R_Ohm;
    dc.L_H = cfg->L_H;
    dc.psi_f_Wb = cfg->psi_f_Wb;
    dc.i_max_A = cfg->i_max_A;
    dc.omega_max_rad_s = cfg->omega_max_el_rad_s;
    dc.u_max_V = cfg->u_max_V;
    /* a bound, not the limit: a te_max that follows kt may reach the model's largest psi_f */
    dc.te_max_Nm = ((cfg->te_max_follows_kt != 0u) ? DBDTC_PARAM_FACTOR_MAX : 1.0f) * cfg->te_max_Nm;
    dc.psi_max_Wb = cfg->psi_max_Wb;
    status = refused_if(dbdtc_init(&c->db, &dc), CTRL_CFG_DBDTC, status);

    pc.Kp = cfg->speed_kp_Nms_rad;
    pc.Ki = cfg->speed_ki_Nm_rad;
    pc.Ts_s = cfg->Ts_s;
    pc.u_min = -cfg->te_max_Nm;
    pc.u_max = cfg->te_max_Nm;
    return refused_if(pi_init(&c->speed_pi, &pc), CTRL_CFG_SPEED_PI, status); /* refused: Te* = 0 */
}

/* The limits, the dead time's and the device drop's shares, the turn's tolerance and the
 * oscillation watch's floor from *cfg: the dead time's refusal. */
static ctrl_status_t init_limits(ctrl_t *c, const ctrl_cfg_t *cfg)
{
    ctrl_status_t status = CTRL_CFG_OK;
    /* td/Ts; a non-finite or implausible dead time is refused (and not compensated) */
    c->deadtime_frac = cfg->deadtime_s / cfg->Ts_s;
    if (!((c->deadtime_frac >= 0.0f) && (c->deadtime_frac <= DEADTIME_FRAC_MAX))) {
        c->deadtime_frac = 0.0f;
        status = refused_if(false, CTRL_CFG_DEADTIME, status);
    }
    c->device_drop_V = cfg->device_drop_V;
    if (!((c->device_drop_V >= 0.0f) && (c->device_drop_V <= DEADTIME_FRAC_MAX * cfg->u_max_V))) {
        c->device_drop_V = 0.0f;
        status = refused_if(false, CTRL_CFG_DEADTIME, status);
    }
    c->i_lim_A = ((cfg->i_lim_A > 0.0f) && (cfg->i_lim_A <= cfg->i_max_A)) ? cfg->i_lim_A : cfg->i_max_A;
    c->u_lim_per_vdc = MATHX_INV_SQRT3_F * (((cfg->u_margin > 0.0f) && (cfg->u_margin <= 1.0f))
                                                ? cfg->u_margin : CTRL_U_MARGIN_DEFAULT);
    oplim_init(&c->lim, cfg->Ts_s, OPLIM_FW_RATE_DEFAULT_WB_S, OPLIM_FW_HYST_DEFAULT);
    c->turn_tol_rad_s = ZOH_THETA_TOL_RAD / cfg->Ts_s;
    c->omega_lo_rad_s = -cfg->omega_max_el_rad_s;
    /* te_max / psi_f(told): the limit of a model's psi_f when it follows kt (0: a fixed cap) */
    c->te_per_psi_Nm_Wb = ((cfg->te_max_follows_kt != 0u) && (cfg->psi_f_Wb > 0.0f)) ? (cfg->te_max_Nm / cfg->psi_f_Wb)
                                                                                    : 0.0f;
    c->te_lim_Nm = 0.0f; /* taken at the reset */
    c->osc_den_min_A2 = (cfg->osc_i_min_A > 0.0f) ? (cfg->osc_i_min_A * cfg->osc_i_min_A) : 0.0f;
    return status;
}

ctrl_status_t ctrl_init(ctrl_t *c, const ctrl_cfg_t *cfg)
{
    c->cfg.Ts_s = cfg->Ts_s;
    c->cfg.i_max_A = cfg->i_max_A;
    c->cfg.i_lim_A = cfg->i_lim_A;
    c->cfg.u_max_V = cfg->u_max_V;
    c->cfg.omega_max_el_rad_s = cfg->omega_max_el_rad_s;
    c->cfg.te_max_Nm = cfg->te_max_Nm;
    c->cfg.te_max_follows_kt = cfg->te_max_follows_kt;
    const ctrl_status_t status = (ctrl_status_t)(init_blocks(c, cfg) | init_limits(c, cfg));
    c->status = (ctrl_status_t)(status | init_est(c, cfg));
    c->mode = CTRL_MODE_TORQUE;
    c->mode_req = CTRL_MODE_TORQUE;
    c->method = CTRL_METHOD_CONVENTIONAL;
    c->ref.speed_ref_rad_s = 0.0f;
    c->ref.te_ref_Nm = 0.0f;
    c->ref.ud_ref_V = 0.0f;
    c->ref.uq_ref_V = 0.0f;
    c->tracked = false;
    ctrl_reset(c);
    return c->status;
}

FLASHFUNC void ctrl_reset(ctrl_t *c)
{
    zoh_turn(0.0f, 0.0f, &c->turn); /* at standstill until the first period takes w(k) */
    c->osc.pred_A.d = 0.0f;
    c->osc.pred_A.q = 0.0f;
    c->osc.eps_A = c->osc.pred_A;
    c->osc.phase = 0u;
    c->osc.num_A2 = 0.0f;
    c->osc.den_A2 = 0.0f;
    dbdtc_reset(&c->db);
    ctrl_take_te_limit(c);
    c->model_src = CTRL_MODEL_NOMINAL;
    est_reset(&c->est);
    oplim_reset(&c->lim);
    c->flags_last = 0u;
    pi_reset(&c->speed_pi, 0.0f);
    c->mode = c->mode_req;
    c->u_applied_V.d = 0.0f;
    c->u_applied_V.q = 0.0f;
    c->ripple_A = 0.0f;
    c->mon.theta_el_rad = 0.0f;
    c->mon.omega_el_rad_s = 0.0f;
    c->mon.speed_mech_rad_s = 0.0f;
    c->mon.id_A = 0.0f;
    c->mon.iq_A = 0.0f;
    c->mon.i_aim_alpha_A = 0.0f;
    c->mon.i_aim_beta_A = 0.0f;
    c->mon.ud_V = 0.0f;
    c->mon.uq_V = 0.0f;
    c->mon.te_ref_Nm = 0.0f;
    c->mon.te_est_Nm = 0.0f;
    c->te_ref_last_Nm = 0.0f;
    c->te_est_last_Nm = 0.0f;
    c->mon.psi_ref_Wb = 0.0f;
    c->mon.psi_est_Wb = 0.0f;
    c->mon.model_from_observer = 0u;
}

FLASHFUNC void ctrl_set_i_lim(ctrl_t *c, float i_lim_A)
{
    c->i_lim_A = ((i_lim_A > 0.0f) && (i_lim_A <= c->cfg.i_max_A)) ? i_lim_A : c->cfg.i_max_A;
}

void ctrl_set_i_limit(ctrl_t *c, float i_lim_A)
{
    const float cfg_A = ((c->cfg.i_lim_A > 0.0f) && (c->cfg.i_lim_A <= c->cfg.i_max_A)) ? c->cfg.i_lim_A
                                                                                         : c->cfg.i_max_A;
    c->i_lim_A = ((i_lim_A > 0.0f) && (i_lim_A <= cfg_A)) ? i_lim_A : cfg_A;
}

FLASHFUNC void ctrl_encoder_align(ctrl_t *c, uint32_t enc_count)
{
    encoder_align(&c->enc, enc_count);
}
