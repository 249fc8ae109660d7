/*
 * main.c - F28335 target entry: bring up the board, configure the drive
 * from board_cfg.h, run the control ISR (ADC SEQ1, 10 kHz) from RAM and
 * the background loop (watchdog via app_background, telemetry pump).
 * Not linked on the host (the Makefile filters it out); the make check
 * gates compile it.
 */
#include "app.h"
#include "board_cfg.h"
#include "hal.h"
#include "hal_f28335.h"
#include "mathx.h"

/* Controller tuning: the SIL scenario defaults (hal/sim/scenario.c). */
#define TUNE_SPEED_KP_NMS_RAD     0.5f    /* speed PI [N m / (rad/s)] */
#define TUNE_SPEED_KI_NM_RAD      20.0f   /* speed PI [N m / rad] */
#define TUNE_ENC_PLL_BW_RAD_S     500.0f  /* speed estimator bandwidth [rad/s] */
#define TUNE_TE_MAX_PER_RATED     2.0f    /* torque limit / rated torque: 12 N m */
/* Bounds on what the controller's model may see (as in hal/sim/sil.c). */
#define MODEL_I_BOUND_PER_TRIP    5.0f    /* x software overcurrent threshold */
#define MODEL_SPEED_BOUND_RPM     6000.0f /* 3x rated speed */
#define MODEL_PSI_BOUND_PER_PSIF  4.0f    /* x psi_f */
#define RAD_S_PER_RPM             (MATHX_TWO_PI_F / 60.0f)

static app_t g_app;  /* the whole drive state; static so CCS can watch it */

/* The drive configuration of this board. Start-up. */
static void target_app_cfg(app_cfg_t *cfg)
{
    ctrl_cfg_t *c = &cfg->ctrl;

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
    cfg->i_max_A = BOARD_OVERCURRENT_A;
}

/* PIE INT1.1 (ADC SEQ1 end of sequence), once per PWM period; app_isr acknowledges. */
#if defined(__TMS320C28XX__)
#pragma CODE_SECTION(ctrl_isr, "ramfuncs")
#endif
static HAL_INTERRUPT void ctrl_isr(void)
{
    hal_f28335_isr_timing_begin();
    app_isr(&g_app);
    hal_f28335_isr_timing_end();
}

int main(void)
{
    app_cfg_t cfg;

    hal_init();
    target_app_cfg(&cfg);
    app_init(&g_app, &cfg);
    hal_isr_attach(ctrl_isr);  /* interrupts and watchdog on from here */
    for (;;) {
        app_background(&g_app);  /* kicks the watchdog (hal_watchdog_kick) */
        hal_f28335_sci_pump();
    }
}
