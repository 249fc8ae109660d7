/* drive_params.c - the one parameter set and its mapping; see drive_params.h. */
#include "drive_params.h"

#include "board_cfg.h"
#include "mathx.h"

#define S_PER_NS 1.0e-9f
#define DEFAULT_BAND (-1.0f) /* R^ band end: ctrl_rsid_band_default()'s */

void drive_params_board(drive_params_t *p)
{
    p->motor.R_Ohm = MOTOR_R_OHM;
    p->motor.L_H = MOTOR_L_H;
    p->motor.psi_f_Wb = MOTOR_PSI_F_WB;
    p->motor.pole_pairs = (uint16_t)MOTOR_POLE_PAIRS;
    p->motor.J_kgm2 = MOTOR_J_KGM2;
    p->motor.rated_torque_Nm = MOTOR_RATED_TORQUE_NM;

    p->board.Ts_s = 1.0f / (float)BOARD_PWM_FREQ_HZ;
    p->board.deadtime_s = (float)BOARD_DEADTIME_NS * S_PER_NS;
    p->board.vdc_nominal_V = BOARD_VDC_NOMINAL_V;
    p->board.u_bound_V = BOARD_VDC_MAX_V;
    p->board.enc_lines = (uint32_t)BOARD_ENC_LINES;
    p->board.enc_offset_el_rad = BOARD_ENC_OFFSET_EL_RAD;
    p->board.isr_period_cycles = (uint32_t)BOARD_ISR_PERIOD_CYCLES;
    p->board.isr_budget_cycles = (uint32_t)BOARD_ISR_BUDGET_CYCLES;

    p->limits.i_trip_A = BOARD_OVERCURRENT_A;
    p->limits.i_limit_A = BOARD_I_LIMIT_A;
    p->limits.vdc_max_V = BOARD_VDC_MAX_V;
    p->limits.vdc_min_V = BOARD_VDC_MIN_V;
    p->limits.speed_max_rad_s = BOARD_OVERSPEED_RPM * MATHX_RAD_S_PER_RPM_F;
    p->limits.te_max_Nm = TUNE_TE_MAX_PER_RATED * MOTOR_RATED_TORQUE_NM;

    p->tuning.speed_kp_Nms_rad = TUNE_SPEED_KP_NMS_RAD;
    p->tuning.speed_ki_Nm_rad = TUNE_SPEED_KI_NM_RAD;
    p->tuning.pll_bw_rad_s = TUNE_ENC_PLL_BW_RAD_S;
    p->tuning.u_margin = TUNE_U_MARGIN;
    p->tuning.R_min_Ohm = DEFAULT_BAND;
    p->tuning.R_max_Ohm = DEFAULT_BAND;
}

void drive_params_to_app_cfg(const drive_params_t *p, app_cfg_t *cfg)
{
    ctrl_cfg_t *c = &cfg->ctrl;
    float R_min_Ohm;
    float R_max_Ohm;

    c->Ts_s = p->board.Ts_s;
    c->R_Ohm = p->motor.R_Ohm;
    c->L_H = p->motor.L_H;
    c->psi_f_Wb = p->motor.psi_f_Wb;
    c->pole_pairs = p->motor.pole_pairs;
    c->enc_lines = p->board.enc_lines;
    c->enc_offset_el_rad = p->board.enc_offset_el_rad;
    c->enc_pll_bw_rad_s = p->tuning.pll_bw_rad_s;
    c->speed_kp_Nms_rad = p->tuning.speed_kp_Nms_rad;
    c->speed_ki_Nm_rad = p->tuning.speed_ki_Nm_rad;
    c->te_max_Nm = p->limits.te_max_Nm;
    /* the model's bounds: generous, never the active limit */
    c->i_max_A = MODEL_I_BOUND_PER_TRIP * p->limits.i_trip_A;
    c->u_max_V = p->board.u_bound_V;
    c->omega_max_el_rad_s = MODEL_SPEED_BOUND_RPM * MATHX_RAD_S_PER_RPM_F * (float)p->motor.pole_pairs;
    c->psi_max_Wb = MODEL_PSI_BOUND_PER_PSIF * p->motor.psi_f_Wb;
    c->deadtime_s = p->board.deadtime_s;
    c->i_lim_A = p->limits.i_limit_A;
    c->u_margin = p->tuning.u_margin;

    cfg->prot.i_max_A = p->limits.i_trip_A;
    cfg->prot.vdc_max_V = p->limits.vdc_max_V;
    cfg->prot.vdc_min_V = p->limits.vdc_min_V;
    cfg->prot.speed_max_rad_s = p->limits.speed_max_rad_s;
    cfg->prot.isr_period_cycles = p->board.isr_period_cycles;
    cfg->prot.isr_budget_cycles = p->board.isr_budget_cycles;

    /* the proposed method's settings for these values; the R^ band in ohms */
    ctrl_rsid_band_default(c, &R_min_Ohm, &R_max_Ohm);
    if (p->tuning.R_min_Ohm >= 0.0f) {
        R_min_Ohm = p->tuning.R_min_Ohm;
    }
    if (p->tuning.R_max_Ohm > 0.0f) {
        R_max_Ohm = p->tuning.R_max_Ohm;
    }
    ctrl_cfg_proposed_defaults(c, R_min_Ohm, R_max_Ohm);
}
