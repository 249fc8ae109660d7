/*
 * main.c - F28335 target entry: bring up the board, configure the drive
 * from board_cfg.h and the saved parameters (nv_params_load), run the
 * control ISR (ADC SEQ1, 10 kHz) from RAM and the background loop
 * (watchdog via app_background, the operator's command block, the link
 * on SCI-A).
 *
 * Operating the board: drivetool over SCI-A (firmware/link/link_protocol.md,
 * tools/drivetool/README.md), or in CCS: add `g_cmd` to the expressions
 * window and set its fields (see cmd.h): method 0/1 (conventional/
 * proposed), mode 0/1/2 (open loop/torque/speed), the reference, then
 * run = 1. `g_app` shows the state, the latched fault with its snapshot
 * and the monitor (g_app.ctrl.mon); g_cmd.error names a refused command.
 * With run = 0, g_comm.start = 1 measures the motor (firmware/commission/commission.h);
 * g_comm reports the stage, then the values or the fault (they are not
 * written to flash: copy them into board_cfg.h).
 * A reset by the watchdog (the background loop stopped kicking it: a
 * hang, a trap, an endless ISR) is latched as the fault WATCHDOG_RESET
 * (g_reset_by_watchdog and the link's variable reset_by_watchdog also say
 * so; no text goes to the port: one protocol per port); the operator
 * clears it with fault_reset. Before anything runs, the program
 * image is checked against the CRCs the linker recorded
 * (f28335_flash.cmd, crc_table(_flash_crc_table)): a mismatch latches
 * FLASH_CRC (snapshot value: the failing record's index), which no reset
 * clears. The configuration is the board's (board_cfg.h, a motor file's
 * with make board) with the parameter store's saved values over it
 * (flash sector B, firmware/link/link_nv.h: the link's parameters):
 * g_nv.status, the link's nv_status, says what the start-up took (VALID,
 * g_nv.taken values; EMPTY: nothing saved; INVALID: a block that fails its
 * check, the board's values kept); the drive starts either way. drivetool
 * save (the link's action save, the drive stopped) writes the link's
 * parameters as they are (g_params) from the main loop, the control ISR
 * held off for the erase and program (about a second).
 * Not linked on the host (the Makefile filters it out); the make check
 * gates compile it.
 */
#include "app.h"
#include "board_cfg.h"
#include "cmd.h"
#include "drive_params.h"
#include "flash_crc.h"
#include "hal.h"
#include "hal_f28335.h"
#include "hal_f28335_cfg.h"
#include "link.h"
#include "link_nv.h"

#if defined(__TMS320C28XX__)
#include <crc_tbl.h>
/* The linker's CRC records of the program sections (f28335_flash.cmd). */
extern CRC_TABLE flash_crc_table;
#endif

static app_t g_app;          /* the whole drive state, its cfg built in place (one copy in .ebss, none on
                              * the 1K-word stack: tools/check/ram_budget.py); static so CCS can watch it */
static volatile cmd_t g_cmd; /* written by the operator from CCS or through the link */
static cmd_limits_t g_lim;   /* the command's limits: the link keeps a pointer to them */
static link_t g_link;        /* the link on SCI-A (link.h) */
static drive_params_t g_params; /* the drive's parameter set, its derived values derived: the link's
                                 * parameters live in it (link_params.h), the configuration follows it */
static volatile cmd_comm_t g_comm; /* the commissioning: g_comm.start = 1 while stopped; its report */
static comm_t g_commission;  /* the commissioning's state (app_attach_comm) */
/* In M0 (section m0data, f28335_flash.cmd), as .ebss (RAML5L7) keeps its
 * margin only without them: objects whose init functions write every
 * field (app_attach_comm, cmd_init, cmd_comm_init; the pattern-fill test
 * proves it; g_params: drive_params_board; g_lim: its three fields set in
 * main; g_nv: link_nv_init, its block buffer written before it is read),
 * since nothing zeroes M0 (f28335_codestart.asm zeroes .ebss). */
static link_nv_t g_nv;       /* the parameter store: flash sector B through the HAL (hal_f28335_nv.c) */
#if defined(__TMS320C28XX__)
#pragma DATA_SECTION(g_commission, "m0data")
#pragma DATA_SECTION(g_cmd, "m0data")
#pragma DATA_SECTION(g_comm, "m0data")
#pragma DATA_SECTION(g_params, "m0data")
#pragma DATA_SECTION(g_lim, "m0data")
#pragma DATA_SECTION(g_nv, "m0data")
#endif
static volatile bool g_reset_by_watchdog; /* WDCR.WDFLAG at start-up (hal_f28335_watchdog_reset) */
static const char FIRMWARE_ID[] = "f28335 db-dtc";
#define SCI_READ_MAX F28335_SCI_FIFO_DEPTH

/* Background: SCI-A's received bytes into the link, its replies out, never waiting. */
static void link_service(void)
{
    uint16_t rx[SCI_READ_MAX];
    uint16_t b;
    const uint16_t n = hal_f28335_sci_read(rx, SCI_READ_MAX);
    for (uint16_t k = 0U; k < n; k++) {
        (void)link_rx_put(&g_link, rx[k]);   /* a full queue is counted by the link */
    }
    g_link.stats.err_line = (uint16_t)(hal_f28335_sci_errors.word_errors + hal_f28335_sci_errors.fifo_overflows +
                                       hal_f28335_sci_errors.rx_errors);
    link_poll(&g_link);
    while (hal_f28335_sci_tx_free() > 0U && link_tx_get(&g_link, &b)) {
        (void)hal_f28335_sci_putc(b);
    }
    hal_f28335_sci_pump();
}

/* Background, the drive stopped: parameter k of g_params was written over the link; the
 * configuration follows (the ISR re-initialises at its next stopped period). */
static void params_apply(void *user, uint16_t k)
{
    (void)user;
    /* no copy of the configuration (RAM): the main loop builds it into g_app.cfg from g_params
     * with the ISR held off (app_reconfigure_now) */
    app_request_reconfigure(&g_app, (k == (uint16_t)LINK_PARAM_ENC_OFFSET) ? APP_RECONF_ENC_OFFSET : 0U);
}

/* The main loop, the control ISR held off: a new configuration from g_params into g_app.cfg
 * (the drive stopped, read again here), the app's pieces from it, the command limits. */
static void reconfigure(void)
{
    if (app_reconfigure_due(&g_app)) {
        app_cfg_from_params(&g_app.cfg, &g_params);
        app_reconfigure_now(&g_app);
        g_lim.te_max_Nm = g_app.cfg.ctrl.te_max_Nm;
        g_lim.u_max_V = g_app.cfg.ctrl.u_max_V;
    }
}

/* The main loop, the control ISR held off: the save the link asked for (link_nv_due), the drive
 * still stopped (read here, where no start can be taken meanwhile; started since: nothing written,
 * SAVE_FAILED); the erase and program run with every interrupt masked (hal_nv_write), the periods
 * missed meanwhile are not tracked: the configuration is taken again (reconfigure, next), as after
 * a parameter's write. */
static void params_save(void)
{
    if (link_nv_due(&g_nv)) {
        const bool stopped = app_stopped(&g_app);
        (void)link_nv_save(&g_nv, &g_params, stopped);
        if (stopped) {
            app_request_reconfigure(&g_app, 0U);
        }
    }
}

/* Start-up, before interrupts: the index of the first CRC record of the
 * image that fails (flash_crc.h), or -1 when all match. */
static int16_t flash_image_bad_record(void)
{
#if defined(__TMS320C28XX__)
    uint16_t k;

    for (k = 0u; k < flash_crc_table.num_recs; k++) {
        const CRC_RECORD *r = &flash_crc_table.recs[k];
        if (!flash_crc_record_ok(r->crc_alg_ID, (const volatile uint16_t *)r->addr, r->size, r->crc_value,
                                 hal_watchdog_kick)) {
            return (int16_t)k;
        }
    }
#endif
    return -1;
}

/* PIE INT1.1 (ADC SEQ1 end of sequence), once per PWM period; app_isr acknowledges. */
RAMFUNC static HAL_INTERRUPT void ctrl_isr(void)
{
    hal_f28335_isr_timing_begin();
    app_isr(&g_app);
    link_isr(&g_link);       /* capture and stream sampling of this period */
    hal_f28335_isr_timing_end();
}

int main(void)
{
    link_cfg_t lc;
    nv_dev_t nv;
    int16_t bad_record;

    hal_init();  /* ramfuncs copied: its CRC record holds at either address */
    bad_record = flash_image_bad_record();
    g_reset_by_watchdog = hal_f28335_watchdog_reset();
    nv.words = hal_nv_words();
    nv.read = hal_nv_read;
    nv.write = hal_nv_write;
    link_nv_init(&g_nv, &nv);
    drive_params_board(&g_params);
    (void)link_nv_load(&g_nv, &g_params);   /* g_nv.status: the link's nv_status */
    (void)drive_params_derive(&g_params);   /* refusals: a start faults CONFIG (params_refused) */
    app_cfg_from_params(&g_app.cfg, &g_params);
    app_init(&g_app, &g_app.cfg);
    app_attach_comm(&g_app, &g_commission);
    if (bad_record >= 0) {
        app_latch_startup_fault(&g_app, APP_FAULT_FLASH_CRC, (float)bad_record, 0.0f);
    } else if (g_reset_by_watchdog) {
        app_latch_startup_fault(&g_app, APP_FAULT_WATCHDOG_RESET, 0.0f, 0.0f);
    }
    cmd_init(&g_cmd);
    cmd_comm_init(&g_comm);
    g_lim.speed_max_rpm = g_app.cfg.comm.speed_max_rad_s / MATHX_RAD_S_PER_RPM_F; /* the rated speed */
    g_lim.te_max_Nm = g_app.cfg.ctrl.te_max_Nm;
    g_lim.u_max_V = g_app.cfg.ctrl.u_max_V;
    link_cfg_default(&lc);   /* the host timeout: BOARD_HOST_TIMEOUT_S */
    lc.Ts_s = g_app.cfg.ctrl.Ts_s;
    lc.baud = F28335_SCI_BAUD_ACTUAL;
    lc.firmware_id = FIRMWARE_ID;
    lc.params.set = &g_params;
    lc.params.apply = params_apply;
    lc.params.store = &g_nv;
    link_init(&g_link, &lc, &g_app, &g_cmd, &g_lim);
    g_link.stats.reset_by_watchdog = g_reset_by_watchdog ? 1U : 0U;
    hal_isr_attach(ctrl_isr);  /* interrupts and watchdog on from here */
    for (;;) {
        cmd_apply(&g_cmd, &g_lim, &g_app);
        cmd_comm_apply(&g_comm, &g_cmd, &g_app);
        app_background(&g_app);  /* kicks the watchdog (hal_watchdog_kick) */
        link_service();
        if (app_reconfigure_due(&g_app) || link_nv_due(&g_nv)) {
            /* the drive's parameters changed or are to be saved (the drive stopped, PWM off):
             * start-up work with the control ISR held off, a few periods, a save's erase about a
             * second (tools/check/ram_budget.py counts it so) */
            hal_isr_pause();
            params_save();
            reconfigure();
            hal_isr_resume();
        }
    }
}
