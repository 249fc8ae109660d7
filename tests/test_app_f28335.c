/*
 * The application on the real F28335 HAL over the register fake: what the
 * operator's commands and the protection do to the registers. Covers
 * a fault reset written outside FAULT and limp mode at
 * run time end to end: cmd_apply -> app -> hal/f28335 -> ePWM registers.
 * Samples are set as ADC results; every expected value is derived in the
 * comments.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include "DSP2833x_Device.h"
#include "app.h"
#include "c2000_fake.h"
#include "cmd.h"
#include "hal.h"

static volatile struct EPWM_REGS *const pwm[3] = { &EPwm1Regs, &EPwm2Regs, &EPwm3Regs };
static const cmd_limits_t LIM = { 2000.0f, 12.0f, 300.0f };
static app_t app;          /* large: not on the stack */
static volatile cmd_t cmd;

/* 12-bit counts, left-justified in ADCRESULTn. 0 A is the 1.5 V offset:
 * 1.5 / 3 * 4096 = 2048. 311 V bus: 311 / 200 = 1.555 V -> 2123 counts
 * (310.99 V). Full scale 4095 counts: (2.99927 - 1.5) * 10 = 14.99 A, above
 * the 14 A software overcurrent limit. */
#define COUNTS_0A     2048U
#define COUNTS_311V   2123U
#define COUNTS_15A    4095U

static void samples(Uint16 ia_counts)
{
    AdcRegs.ADCRESULT0 = (Uint16)(ia_counts << 4);
    AdcRegs.ADCRESULT1 = (Uint16)(COUNTS_0A << 4);
    AdcRegs.ADCRESULT2 = (Uint16)(COUNTS_311V << 4);
    EQep1Regs.QPOSCNT = 1234UL;
}

/* Power-up, then a start straight into RUN (calibration, alignment and
 * step 1 off: the start request's ISR call is already a RUN period). */
static int setup(void **state)
{
    app_cfg_t cfg;
    (void)state;
    c2000_fake_reset();
    SysCtrlRegs.PLLSTS.bit.PLLLOCKS = 1U;
    hal_init();
    app_cfg_default(&cfg);
    cfg.lvl.level = LEVEL_FULL; /* the drive itself (the board starts at level 1) */
    cfg.calibrate = false;
    cfg.align = false;
    cfg.rsid.mode = APP_RSID_OFF;
    app_init(&app, &cfg);
    cmd_init(&cmd);
    samples(COUNTS_0A);
    CpuTimer2Regs.TIM.all = 0x80000000UL; /* frozen: 0 cycles per ISR, no overrun */
    cmd.run = 1u;
    cmd_apply(&cmd, &LIM, &app);
    app_isr(&app);
    assert_int_equal(app.state, APP_STATE_RUN);
    for (int k = 0; k < 3; k++) {
        assert_int_equal(pwm[k]->TZCLR.bit.OST, 1);   /* outputs released */
        pwm[k]->TZFRC.all = 0U;                         /* from here: a write means "forced off" */
    }
    return 0;
}

static int outputs_forced_off(void)
{
    return (pwm[0]->TZFRC.bit.OST == 1U) && (pwm[1]->TZFRC.bit.OST == 1U) &&
           (pwm[2]->TZFRC.bit.OST == 1U);
}

/* D2: fault_reset = 1 written while running. Before: hal_trip_clear()
 * forced all outputs off while the app stayed in RUN with pwm_on (the drive
 * stopped switching silently). Now nothing reaches the HAL. */
static void fault_reset_while_running_leaves_the_outputs_alone(void **state)
{
    (void)state;
    cmd.fault_reset = 1u;
    cmd_apply(&cmd, &LIM, &app);
    assert_int_equal(cmd.fault_reset, 0u);
    assert_false(outputs_forced_off());
    for (int n = 0; n < 3; n++) {
        app_isr(&app);
    }
    assert_int_equal(app.state, APP_STATE_RUN);
    assert_true(app.pwm_on);
    assert_false(outputs_forced_off());
}

/* D2: before, the request stayed latched, and the next real fault was
 * cleared on the following ISR with no operator action. Now the fault
 * (overcurrent for one period, then gone) stays latched with the outputs
 * off until the operator resets it. */
static void stale_fault_reset_does_not_clear_the_next_fault(void **state)
{
    (void)state;
    cmd.fault_reset = 1u;
    cmd_apply(&cmd, &LIM, &app);
    app_isr(&app);

    samples(COUNTS_15A);
    app_isr(&app);
    assert_int_equal(app.state, APP_STATE_FAULT);
    assert_int_equal(app.fault, APP_FAULT_OVERCURRENT);
    assert_true(outputs_forced_off());                  /* in the same ISR call */

    samples(COUNTS_0A);                                 /* the cause is gone */
    for (int n = 0; n < 5; n++) {
        app_isr(&app);
    }
    assert_int_equal(app.state, APP_STATE_FAULT);
    assert_int_equal(app.fault, APP_FAULT_OVERCURRENT);

    cmd.fault_reset = 1u;                               /* the operator's reset */
    cmd_apply(&cmd, &LIM, &app);
    app_isr(&app);
    assert_int_equal(app.state, APP_STATE_IDLE);
    assert_int_equal(app.fault, APP_FAULT_NONE);
    assert_int_equal(app.req_fault_reset, 0u);
}

/* D2: the ISR drops a reset request it finds outside FAULT (one set
 * between the background's state check and a fault, say). */
static void reset_request_outside_fault_is_dropped_by_the_isr(void **state)
{
    (void)state;
    app.req_fault_reset = 1u;
    app_isr(&app);
    assert_int_equal(app.req_fault_reset, 0u);
    assert_int_equal(app.state, APP_STATE_RUN);
}

/* D7 end to end: the oscillator lost while running (limp mode) latches a
 * hardware-trip fault with the outputs off, and no reset clears it. */
static void limp_mode_while_running_latches_a_trip(void **state)
{
    (void)state;
    SysCtrlRegs.PLLSTS.bit.MCLKSTS = 1U;
    app_isr(&app);
    assert_int_equal(app.state, APP_STATE_FAULT);
    assert_int_equal(app.fault, APP_FAULT_HW_TRIP);
    assert_true(outputs_forced_off());
    SysCtrlRegs.PLLSTS.bit.MCLKSTS = 0U;
    cmd.fault_reset = 1u;
    cmd_apply(&cmd, &LIM, &app);
    app_isr(&app);
    assert_int_equal(app.state, APP_STATE_FAULT);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(fault_reset_while_running_leaves_the_outputs_alone, setup),
        cmocka_unit_test_setup(stale_fault_reset_does_not_clear_the_next_fault, setup),
        cmocka_unit_test_setup(reset_request_outside_fault_is_dropped_by_the_isr, setup),
        cmocka_unit_test_setup(limp_mode_while_running_latches_a_trip, setup),
    };
    return cmocka_run_group_tests_name("app_f28335", tests, NULL, NULL);
}
