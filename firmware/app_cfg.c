/* app_cfg.c - the board's configuration into the app's: the parameter set
 * (drive_params.h) through its mapping, then the start-up sequence's own
 * settings from firmware/board_cfg.h; see app_cfg_default() in app.h. */
#include "app.h"
#include "board_cfg.h"
#include "drive_params.h"
#include "mathx.h"

#define RAD_PER_DEG (MATHX_PI_F / 180.0f)

void app_cfg_default(app_cfg_t *cfg)
{
    static const app_cfg_t zero; /* a field added later reads 0, not garbage */
    drive_params_t p;

    *cfg = zero;
    drive_params_board(&p);
    drive_params_to_app_cfg(&p, cfg);
    cfg->prot.watch.op_window_s = BOARD_OPEN_PHASE_WINDOW_S;
    cfg->prot.watch.op_ratio = BOARD_OPEN_PHASE_RATIO;
    cfg->prot.watch.stuck_angle_el_rad = BOARD_I_STUCK_ANGLE_EL_DEG * RAD_PER_DEG;
    cfg->prot.watch.stuck_span_A = BOARD_I_STUCK_SPAN_A;
    cfg->prot.watch.stuck_zero_A = BOARD_I_STUCK_ZERO_A;
    cfg->prot.watch.stuck_min_periods = (uint32_t)BOARD_I_STUCK_MIN_PERIODS;
    cfg->prot.watch.enc_lost_counts = BOARD_ENC_LOST_COUNTS;
    cfg->prot.watch.enc_stall_s = BOARD_ENC_STALL_S;
    cfg->prot.watch.enc_stall_te_frac = BOARD_ENC_STALL_TE_FRAC;

    cfg->calibrate = true;
    cfg->cal.settle_s = BOARD_CAL_SETTLE_S;
    cfg->cal.samples = (uint32_t)BOARD_CAL_SAMPLES;
    cfg->cal.offset_max_A = BOARD_I_OFFSET_MAX_A;
    cfg->align = (BOARD_ENC_OFFSET_KNOWN == 0U);
    cfg->aln.prepos_el_rad = BOARD_ALIGN_PREPOS_EL_DEG * RAD_PER_DEG;
    cfg->aln.ramp_s = BOARD_ALIGN_RAMP_S;
    cfg->aln.prepos_s = BOARD_ALIGN_PREPOS_S;
    cfg->aln.settle_s = BOARD_ALIGN_SETTLE_S;

    cfg->ctrl.track_R = BOARD_TRACK_R;
    cfg->rsid.mode = (app_rsid_mode_t)BOARD_RSID_MODE;
    cfg->rsid.window_s = BOARD_RSID_WINDOW_S;
    cfg->rsid.window_max_s = BOARD_RSID_WINDOW_MAX_S;
    cfg->rsid.repeats_max = (uint16_t)BOARD_RSID_REPEATS_MAX;
    cfg->rsid.on_refusal = (app_rsid_refusal_t)BOARD_RSID_ON_REFUSAL;

    cfg->lvl.level = (uint16_t)BOARD_LEVEL;
    cfg->lvl.pwm_duty[0] = BOARD_LEVEL1_DUTY_A;
    cfg->lvl.pwm_duty[1] = BOARD_LEVEL1_DUTY_B;
    cfg->lvl.pwm_duty[2] = BOARD_LEVEL1_DUTY_C;
    cfg->lvl.speed_m_rad_s = BOARD_LEVEL3_SPEED_RPM * MATHX_RAD_S_PER_RPM_F;
    cfg->lvl.ramp_s = BOARD_ALIGN_RAMP_S;
}
