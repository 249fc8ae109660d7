/* app_cfg.c - the board's configuration (firmware/board_cfg.h) into the
 * app's; see app_cfg_default() in app.h. */
#include "app.h"
#include "board_cfg.h"
#include "mathx.h"

#define RAD_S_PER_RPM (MATHX_TWO_PI_F / 60.0f)
#define RAD_PER_DEG (MATHX_PI_F / 180.0f)
#define S_PER_NS 1.0e-9f

void app_cfg_default(app_cfg_t *cfg)
{
    static const app_cfg_t zero; /* a field added later reads 0, not garbage */
    ctrl_cfg_t *c = &cfg->ctrl;
    float R_min_Ohm;
    float R_max_Ohm;

    *cfg = zero;
    c->Ts_s = 1.0f / (float)BOARD_PWM_FREQ_HZ;
    c->Rs_Ohm = MOTOR_R_OHM;
    c->Ls_H = MOTOR_L_H;
    c->psi_f_Wb = MOTOR_PSI_F_WB;
    c->pole_pairs = (uint16_t)MOTOR_POLE_PAIRS;
    c->enc_lines = (uint32_t)BOARD_ENC_LINES;
    c->enc_offset_el_rad = BOARD_ENC_OFFSET_EL_RAD;
    c->enc_pll_bw_rad_s = TUNE_ENC_PLL_BW_RAD_S;
    c->speed_kp_Nms_rad = TUNE_SPEED_KP_NMS_RAD;
    c->speed_ki_Nm_rad = TUNE_SPEED_KI_NM_RAD;
    c->te_max_Nm = TUNE_TE_MAX_PER_RATED * MOTOR_RATED_TORQUE_NM;
    c->i_max_A = MODEL_I_BOUND_PER_TRIP * BOARD_OVERCURRENT_A;
    c->u_max_V = BOARD_VDC_MAX_V;
    c->omega_max_el_rad_s = MODEL_SPEED_BOUND_RPM * RAD_S_PER_RPM * (float)MOTOR_POLE_PAIRS;
    c->psi_max_Wb = MODEL_PSI_BOUND_PER_PSIF * MOTOR_PSI_F_WB;
    c->deadtime_s = (float)BOARD_DEADTIME_NS * S_PER_NS;
    c->i_lim_A = BOARD_I_LIMIT_A;
    c->u_margin = TUNE_U_MARGIN;

    cfg->i_max_A = BOARD_OVERCURRENT_A;
    cfg->vdc_max_V = BOARD_VDC_MAX_V;
    cfg->vdc_min_V = BOARD_VDC_MIN_V;
    cfg->speed_max_rad_s = BOARD_OVERSPEED_RPM * RAD_S_PER_RPM;
    cfg->isr_period_cycles = (uint32_t)BOARD_ISR_PERIOD_CYCLES;
    cfg->isr_budget_cycles = (uint32_t)BOARD_ISR_BUDGET_CYCLES;
    cfg->watch.op_window_s = BOARD_OPEN_PHASE_WINDOW_S;
    cfg->watch.op_i_min_A = BOARD_OPEN_PHASE_I_MIN_A;
    cfg->watch.op_ratio = BOARD_OPEN_PHASE_RATIO;
    cfg->watch.op_u_min_V = BOARD_OPEN_PHASE_U_MIN_V;
    cfg->watch.stuck_delta_A = BOARD_I_STUCK_DELTA_A;
    cfg->watch.stuck_angle_el_rad = BOARD_I_STUCK_ANGLE_EL_DEG * RAD_PER_DEG;
    cfg->watch.stuck_span_A = BOARD_I_STUCK_SPAN_A;
    cfg->watch.stuck_zero_A = BOARD_I_STUCK_ZERO_A;
    cfg->watch.enc_lost_counts = BOARD_ENC_LOST_COUNTS;
    cfg->watch.enc_stall_s = BOARD_ENC_STALL_S;
    cfg->watch.enc_stall_te_frac = BOARD_ENC_STALL_TE_FRAC;

    cfg->calibrate = true;
    cfg->cal_settle_s = BOARD_CAL_SETTLE_S;
    cfg->cal_samples = (uint32_t)BOARD_CAL_SAMPLES;
    cfg->offset_max_A = BOARD_I_OFFSET_MAX_A;
    cfg->align = (BOARD_ENC_OFFSET_KNOWN == 0U);
    cfg->align_u_V = BOARD_ALIGN_CURRENT_A * MOTOR_R_OHM;
    cfg->align_prepos_el_rad = BOARD_ALIGN_PREPOS_EL_DEG * RAD_PER_DEG;
    cfg->align_ramp_s = BOARD_ALIGN_RAMP_S;
    cfg->align_prepos_s = BOARD_ALIGN_PREPOS_S;
    cfg->align_settle_s = BOARD_ALIGN_SETTLE_S;

    ctrl_rsid_band_default(c, &R_min_Ohm, &R_max_Ohm);
    ctrl_cfg_proposed_defaults(c, R_min_Ohm, R_max_Ohm);
    c->track_R = BOARD_TRACK_R;
    cfg->rsid_mode = (app_rsid_mode_t)BOARD_RSID_MODE;
    cfg->rsid_settle_1_s = BOARD_RSID_SETTLE_1_S;
    cfg->rsid_window_s = BOARD_RSID_WINDOW_S;
    cfg->rsid_settle_2_s = BOARD_RSID_SETTLE_2_S;
    cfg->rsid_speed_1_rad_s = BOARD_RSID_SPEED_1_RPM * RAD_S_PER_RPM;
    cfg->rsid_speed_2_rad_s = BOARD_RSID_SPEED_2_RPM * RAD_S_PER_RPM;
    cfg->rsid_accel_rad_s2 = BOARD_RSID_ACCEL_RPM_S * RAD_S_PER_RPM;
    cfg->rsid_window_max_s = BOARD_RSID_WINDOW_MAX_S;
    cfg->rsid_repeats_max = (uint16_t)BOARD_RSID_REPEATS_MAX;
    cfg->rsid_on_refusal = (app_rsid_refusal_t)BOARD_RSID_ON_REFUSAL;
}
