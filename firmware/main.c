/*
 * main.c - F28335 target entry: bring up the board, configure the drive
 * from board_cfg.h (app_cfg_default), run the control ISR (ADC SEQ1,
 * 10 kHz) from RAM and the background loop (watchdog via app_background,
 * telemetry pump).
 * Not linked on the host (the Makefile filters it out); the make check
 * gates compile it.
 */
#include "app.h"
#include "hal.h"
#include "hal_f28335.h"

static app_t g_app;  /* the whole drive state; static so CCS can watch it */

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
    app_cfg_default(&cfg);
    app_init(&g_app, &cfg);
    hal_isr_attach(ctrl_isr);  /* interrupts and watchdog on from here */
    for (;;) {
        app_background(&g_app);  /* kicks the watchdog (hal_watchdog_kick) */
        hal_f28335_sci_pump();
    }
}
