/*
 * main.c - F28335 target entry: bring up the board, configure the drive
 * from board_cfg.h (app_cfg_default), run the control ISR (ADC SEQ1,
 * 10 kHz) from RAM and the background loop (watchdog via app_background,
 * the operator's command block, telemetry pump).
 *
 * Operating the board: in CCS, add `g_cmd` to the expressions window and
 * set its fields (see cmd.h): method 0/1 (conventional/proposed), mode
 * 0/1/2 (open loop/torque/speed), the reference, then run = 1. `g_app`
 * shows the state, the latched fault with its snapshot and the monitor
 * (g_app.ctrl.mon); g_cmd.error names a refused command.
 * g_reset_by_watchdog is true when the last reset was the watchdog's (the
 * background loop stopped kicking it: a hang, a trap, an endless ISR); it
 * is also sent once on the telemetry line at start-up.
 * Not linked on the host (the Makefile filters it out); the make check
 * gates compile it.
 */
#include "app.h"
#include "board_cfg.h"
#include "cmd.h"
#include "hal.h"
#include "hal_f28335.h"

static app_t g_app;          /* the whole drive state; static so CCS can watch it */
static app_cfg_t g_cfg;      /* static: in .ebss, not on the 1K-word stack (tools/check/ram_budget.py) */
static volatile cmd_t g_cmd; /* written by the operator from CCS (or a telemetry link) */
static volatile bool g_reset_by_watchdog; /* WDCR.WDFLAG at start-up (hal_f28335_watchdog_reset) */
static const char WATCHDOG_RESET_MSG[] = "reset by watchdog\r\n";

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
    cmd_limits_t lim;

    hal_init();
    g_reset_by_watchdog = hal_f28335_watchdog_reset();
    if (g_reset_by_watchdog) {
        (void)hal_f28335_sci_write(WATCHDOG_RESET_MSG, (uint16_t)(sizeof WATCHDOG_RESET_MSG - 1u));
    }
    app_cfg_default(&g_cfg);
    app_init(&g_app, &g_cfg);
    cmd_init(&g_cmd);
    lim.speed_max_rpm = MOTOR_RATED_SPEED_RPM;
    lim.te_max_Nm = g_cfg.ctrl.te_max_Nm;
    lim.u_max_V = g_cfg.ctrl.u_max_V;
    hal_isr_attach(ctrl_isr);  /* interrupts and watchdog on from here */
    for (;;) {
        cmd_apply(&g_cmd, &lim, &g_app);
        app_background(&g_app);  /* kicks the watchdog (hal_watchdog_kick) */
        hal_f28335_sci_pump();
    }
}
