/* app_cfg.c - the board's configuration into the app's: the parameter set
 * (drive_params.h) through its mapping (drive_params_to_app_cfg), then the
 * start-up sequence's own settings from firmware/params/board_cfg.h; see
 * app_cfg_default() and app_cfg_from_params() in app.h. */
#include "app.h"
#include "board_cfg.h"
#include "drive_params.h"
#include "mathx.h"

#define RAD_PER_DEG (MATHX_PI_F / 180.0f)

void app_cfg_default(app_cfg_t *cfg)
{
    drive_params_t p;

    drive_params_board(&p);
    app_cfg_from_params(cfg, &p);
}

/* The watch checks' board settings: open phase, stuck current, encoder. */
static void watch_from_board(protect_watch_cfg_t *w)
{
    w->op_window_s = BOARD_OPEN_PHASE_WINDOW_S;
    w->op_ratio = BOARD_OPEN_PHASE_RATIO;
    w->stuck_angle_el_rad = BOARD_I_STUCK_ANGLE_EL_DEG * RAD_PER_DEG;
    w->stuck_span_A = BOARD_I_STUCK_SPAN_A;
    w->stuck_zero_A = BOARD_I_STUCK_ZERO_A;
    w->stuck_min_periods = (uint32_t)BOARD_I_STUCK_MIN_PERIODS;
    w->enc_lost_counts = BOARD_ENC_LOST_COUNTS;
    w->enc_stall_s = BOARD_ENC_STALL_S;
    w->enc_stall_te_frac = BOARD_ENC_STALL_TE_FRAC;
}

/* The start's first steps from the board: calibration and alignment. */
static void start_from_board(app_cfg_t *cfg)
{
    cfg->calibrate = true;
    cfg->cal.settle_s = BOARD_CAL_SETTLE_S;
    cfg->cal.samples = (uint32_t)BOARD_CAL_SAMPLES;
    /* cal.offset_max_A: drive_params_to_app_cfg(), from the ADC's range */
    cfg->align = (BOARD_ENC_OFFSET_KNOWN == 0U);
    cfg->aln.prepos_el_rad = BOARD_ALIGN_PREPOS_EL_DEG * RAD_PER_DEG;
    cfg->aln.ramp_s = BOARD_ALIGN_RAMP_S;
    cfg->aln.prepos_s = BOARD_ALIGN_PREPOS_S;
    cfg->aln.settle_s = BOARD_ALIGN_SETTLE_S;
}

/* The commissioning's stages (R, L, encoder, spin) as board_cfg.h sets them. */
static void comm_from_board(comm_cfg_t *cm)
{
    cm->pole_pairs_max = (uint16_t)COMM_POLE_PAIRS_MAX;
    cm->u_frac = COMM_U_FRAC;
    cm->r_i1_frac = COMM_R_I1_FRAC;
    cm->r_i2_frac = COMM_R_I2_FRAC;
    cm->r_prepos_el_rad = COMM_R_PREPOS_EL_DEG * RAD_PER_DEG;
    cm->r_ramp_s = COMM_R_RAMP_S;
    cm->r_kp_frac = COMM_R_KP_FRAC;
    cm->r_seek_s = COMM_R_SEEK_S;
    cm->r_bw_rad_s = COMM_R_BW_RAD_S;
    cm->r_settle_s = COMM_R_SETTLE_S;
    cm->r_still_rad = COMM_R_STILL_MECH_DEG * RAD_PER_DEG;
    cm->r_window_s = COMM_R_WINDOW_S;
    cm->r_max_s = COMM_R_MAX_S;
    cm->l_step_frac = COMM_L_STEP_FRAC;
    cm->l_rise_frac = COMM_L_RISE_FRAC;
    cm->l_cycles = (uint16_t)COMM_L_CYCLES;
    cm->l_max_s = COMM_L_MAX_S;
    cm->i_bw_rad_s = COMM_I_BW_RAD_S;
    cm->enc_frac = COMM_ENC_FRAC;
    cm->enc_speed_el_rad_s = COMM_ENC_SPEED_EL_DEG_S * RAD_PER_DEG;
    cm->enc_hold_s = COMM_ENC_HOLD_S;
    cm->enc_max_s = COMM_ENC_MAX_S;
    cm->wiring_el_hz = COMM_WIRING_EL_HZ;
    cm->spin_frac = COMM_SPIN_FRAC;
    cm->spin_top_frac = COMM_SPIN_TOP_FRAC;
    cm->spin_lo_frac = COMM_SPIN_LO_FRAC;
    cm->spin_skip_s = COMM_SPIN_SKIP_S;
    cm->spin_max_s = COMM_SPIN_MAX_S;
}

/* Step 1's sequence (IDENTIFY_R) and its refusal policy from the board. */
static void rsid_from_board(rsid_seq_cfg_t *r)
{
    r->mode = (app_rsid_mode_t)BOARD_RSID_MODE;
    r->window_s = BOARD_RSID_WINDOW_S;
    r->window_max_s = BOARD_RSID_WINDOW_MAX_S;
    r->repeats_max = (uint16_t)BOARD_RSID_REPEATS_MAX;
    r->on_refusal = (app_rsid_refusal_t)BOARD_RSID_ON_REFUSAL;
}

/* The build levels from the board: the level, level 1's duties, level 2's
 * bus limit, level 3's speed and ramp. */
static void levels_from_board(level_cfg_t *lv)
{
    lv->level = (uint16_t)BOARD_LEVEL;
    lv->vdc_max_12_V = BOARD_LEVEL12_VDC_MAX_V;
    lv->pwm_duty[0] = BOARD_LEVEL1_DUTY_A;
    lv->pwm_duty[1] = BOARD_LEVEL1_DUTY_B;
    lv->pwm_duty[2] = BOARD_LEVEL1_DUTY_C;
    lv->speed_m_rad_s = BOARD_LEVEL3_SPEED_RPM * MATHX_RAD_S_PER_RPM_F;
    lv->ramp_s = BOARD_ALIGN_RAMP_S;
}

void app_cfg_from_params(app_cfg_t *cfg, const drive_params_t *p)
{
    static const app_cfg_t zero; /* a field added later reads 0, not garbage */

    *cfg = zero;
    drive_params_to_app_cfg(p, cfg);
    watch_from_board(&cfg->prot.watch);
    start_from_board(cfg);
    cfg->ctrl.est_cfg.track_R = BOARD_TRACK_R;
    comm_from_board(&cfg->comm);
    rsid_from_board(&cfg->rsid);
    levels_from_board(&cfg->lvl);
    DRIVE_CONFIG_APP(cfg); /* a motor file's settings (make board), else nothing */
}

/* DRIVE_TO(path): cfg->path = the value; DRIVE_TO_NONE: no copy. */
#define DRIVE_COPY_DRIVE_TO(path) cfg->path =
#define DRIVE_COPY_DRIVE_TO_NONE(value)
#define DRIVE_PARAM_COPY(group, field, type, dflt, to) DRIVE_COPY_##to(p->group.field);

void drive_params_to_app_cfg(const drive_params_t *p_in, app_cfg_t *cfg)
{
    drive_params_t d = *p_in;
    const drive_params_t *p = &d;

    cfg->comm.i_max_A = p->rating.i_rated_A; /* the commissioning's bounds: the ratings (and n_rated) */
    cfg->comm.deadtime_s = p->board.deadtime_s; /* the told dead time the inverter's split keeps */
    cfg->comm.speed_lag_s = encoder_ramp_lag_s(p->tuning.pll_bw_rad_s); /* the spin's top within its bound */
    /* the speed PI from the measured J: the parameter set's rule, linear in J */
    drive_speed_pi(1.0f, p->tuning.speed_bw_rad_s, &cfg->comm.speed_kp_per_J_1_s, &cfg->comm.speed_ki_per_J_1_s2);
    /* params_design.md sec. 3: the I^2t budget of the short-time current (and i2t_rated_A) */
    cfg->i2t_budget_A2s = (p->rating.i_peak_A * p->rating.i_peak_A - p->rating.i_rated_A * p->rating.i_rated_A) *
                          p->rating.t_peak_s;
    cfg->params_refused =
        (uint16_t)(drive_params_derive(&d) & (DRIVE_DERIVE_RATINGS | DRIVE_DERIVE_ADC_RANGE | DRIVE_DERIVE_I_LIMIT));
    /* a derived torque limit is the told kt at i_peak: it follows the learned psi_f (params_design.md sec. 3) */
    cfg->ctrl.te_max_follows_kt = ((p->derived & DRIVE_DERIVED_TE_MAX) != 0u) ? 1u : 0u;
    /* the plain copies (drive_params.h's lists' DRIVE_TO), the derived values derived */
    DRIVE_PARAMS(DRIVE_PARAM_COPY)

    /* the offsets calibration accepts: the share of the range drive_i_readable_A() leaves */
    cfg->cal.offset_max_A = drive_scaled(BOARD_I_OFFSET_MAX_A, p->board.i_full_scale_A, BOARD_I_FULL_SCALE_A);
    /* half an ADC step of the current range (+- full scale over the counts) */
    cfg->prot.watch.stuck_delta_A = p->board.i_full_scale_A / BOARD_ADC_COUNTS;
    cfg->prot.watch.op_i_min_A = drive_scaled(REF_OPEN_PHASE_I_MIN_A, p->rating.i_rated_A, REF_I_RATED_A);
    cfg->prot.watch.op_u_min_V = drive_scaled(REF_OPEN_PHASE_U_MIN_V, p->board.vdc_nominal_V, REF_VDC_V);
    cfg->aln.u_V = drive_scaled(REF_ALIGN_CURRENT_A, p->rating.i_rated_A, REF_I_RATED_A) * p->motor.R_Ohm;
    /* level 3 turns the rotor with the alignment's current; level 4 runs at a fraction of the limit */
    cfg->lvl.i_A = drive_scaled(REF_ALIGN_CURRENT_A, p->rating.i_rated_A, REF_I_RATED_A);
    cfg->lvl.i_lim_4_A = BOARD_LEVEL4_I_LIMIT_PER_LIMIT * cfg->ctrl.i_lim_A;
    drive_params_to_ctrl_cfg(p, &cfg->ctrl);
}
