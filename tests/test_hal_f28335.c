/*
 * Unit tests for hal/f28335/ against the host register fake: the register
 * values after hal_init(), the duty -> CMPA mapping, sample scaling, the
 * trip-zone latch, the interrupt acknowledge, the cycle counter and the
 * SCI queue. Every expected number is derived by hand in the comments.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>
#include <string.h>

#include "DSP2833x_Device.h"
#include "c2000_fake.h"
#include "hal.h"
#include "hal_f28335.h"
#include "hal_f28335_cfg.h"
#include "hal_f28335_internal.h"

#define TOL 1e-4

static volatile struct EPWM_REGS *const pwm[3] = { &EPwm1Regs, &EPwm2Regs, &EPwm3Regs };

static int isr_calls;
static void fake_ctrl_isr(void) { isr_calls++; }

/* Power-on fake; the PLL "locks" at once (the fake cannot count cycles). */
static int setup(void **state)
{
    (void)state;
    c2000_fake_reset();
    SysCtrlRegs.PLLSTS.bit.PLLLOCKS = 1U;
    hal_init();
    return 0;
}

/* ---- derived constants ---------------------------------------------------- */

static void derived_register_values(void **state)
{
    (void)state;
    /* 150 MHz / (2 * 10 kHz) = 7500 counts. */
    assert_int_equal(F28335_TBPRD, 7500);
    /* 1000 ns * 150 counts/us = 150 counts. */
    assert_int_equal(F28335_DB_COUNTS, 150);
    /* 37.5 MHz / (115200 * 8) - 1 = 39.69 -> 40. */
    assert_int_equal(F28335_SCI_BRR, 40);
    /* 4 * 2500 - 1. */
    assert_int_equal(F28335_QPOSMAX, 9999);
}

/* ---- hal_init: clocks, flash, watchdog ------------------------------------ */

static void init_sets_clocks_flash_watchdog(void **state)
{
    (void)state;
    assert_int_equal(SysCtrlRegs.PLLCR.bit.DIV, 10);     /* 30 MHz x 10 = 300 MHz VCO */
    assert_int_equal(SysCtrlRegs.PLLSTS.bit.DIVSEL, 2);  /* /2 -> 150 MHz */
    assert_int_equal(SysCtrlRegs.PLLSTS.bit.MCLKOFF, 0); /* missing-clock detect back on */
    assert_true(hal_f28335_clock_ok());
    assert_int_equal(SysCtrlRegs.HISPCP.all, 3);         /* 25 MHz HSPCLK */
    assert_int_equal(SysCtrlRegs.LOSPCP.all, 2);         /* 37.5 MHz LSPCLK */
    assert_int_equal(SysCtrlRegs.PCLKCR0.bit.TBCLKSYNC, 1);
    assert_int_equal(SysCtrlRegs.PCLKCR0.bit.ADCENCLK, 1);
    assert_int_equal(SysCtrlRegs.PCLKCR0.bit.SCIAENCLK, 1);
    assert_int_equal(SysCtrlRegs.PCLKCR1.all, 0x4007);   /* EPWM1..3, EQEP1 */
    assert_int_equal(SysCtrlRegs.PCLKCR3.bit.CPUTIMER2ENCLK, 1);
    assert_int_equal(FlashRegs.FOPT.bit.ENPIPE, 1);
    assert_int_equal(FlashRegs.FBANKWAIT.all, 0x0505);   /* PAGEWAIT 5, RANDWAIT 5 */
    assert_int_equal(FlashRegs.FOTPWAIT.bit.OTPWAIT, 8);
    assert_int_equal(SysCtrlRegs.WDCR, 0x0068);          /* off until hal_isr_attach */
    assert_int_equal(c2000_fake_eallow, 0);              /* every EALLOW closed */
    assert_int_equal(c2000_fake_intm, 1);                /* interrupts still masked */
}

static void pll_that_never_locks_is_a_permanent_trip(void **state)
{
    (void)state;
    c2000_fake_reset();  /* PLLLOCKS stays 0: the bounded wait gives up */
    hal_init();
    assert_false(hal_f28335_clock_ok());
    assert_int_equal(SysCtrlRegs.PLLSTS.bit.DIVSEL, 0);  /* stays /4 */
    assert_true(hal_trip_active());
    hal_trip_clear();
    assert_true(hal_trip_active());
    EPwm1Regs.TZCLR.all = 0U;
    hal_pwm_enable();
    assert_int_equal(EPwm1Regs.TZCLR.bit.OST, 0);        /* refused */
}

static void limp_mode_leaves_pllcr_alone(void **state)
{
    (void)state;
    c2000_fake_reset();
    SysCtrlRegs.PLLSTS.bit.MCLKSTS = 1U;
    hal_init();
    assert_int_equal(SysCtrlRegs.PLLCR.all, 0);
    assert_false(hal_f28335_clock_ok());
    assert_true(hal_trip_active());
}

/* ---- hal_init: ePWM, trip zone, pins -------------------------------------- */

static void init_sets_epwm(void **state)
{
    (void)state;
    for (int k = 0; k < 3; k++) {
        volatile struct EPWM_REGS *p = pwm[k];
        const int master = (k == 0);
        assert_int_equal(p->TBPRD, 7500);
        assert_int_equal(p->TBCTL.bit.CTRMODE, 2);        /* up-down */
        assert_int_equal(p->TBCTL.bit.PRDLD, 0);          /* TBPRD shadowed */
        assert_int_equal(p->TBCTL.bit.HSPCLKDIV, 0);      /* TBCLK = SYSCLKOUT */
        assert_int_equal(p->TBCTL.bit.CLKDIV, 0);
        assert_int_equal(p->TBCTL.bit.PHSEN, master ? 0 : 1);
        assert_int_equal(p->TBCTL.bit.SYNCOSEL, master ? 1 : 0); /* ePWM1 syncs 2, 3 at zero */
        assert_int_equal(p->TBCTL.bit.PHSDIR, 1);
        assert_int_equal(p->TBPHS.half.TBPHS, 0);
        assert_int_equal(p->CMPCTL.bit.SHDWAMODE, 0);     /* CMPA shadowed ... */
        assert_int_equal(p->CMPCTL.bit.LOADAMODE, 0);     /* ... loaded at TBCTR = 0 */
        assert_int_equal(p->CMPA.half.CMPA, 3750);        /* duty 0.5 */
        /* CAU = set (2 << 4 = 0x20), CAD = clear (1 << 6 = 0x40). */
        assert_int_equal(p->AQCTLA.all, 0x0060);
        /* OUT_MODE 3 | POLSEL 2 << 2 | IN_MODE 0 = 0x000B: active-high complementary. */
        assert_int_equal(p->DBCTL.all, 0x000B);
        assert_int_equal(p->DBRED, 150);
        assert_int_equal(p->DBFED, 150);
        assert_int_equal(p->TZSEL.all, 0x0100);           /* OSHT1 */
        assert_int_equal(p->TZCTL.all, 0x000A);           /* TZA = TZB = 2: force low */
        assert_int_equal(p->TZFRC.bit.OST, 1);            /* outputs start off */
        assert_int_equal(p->TZEINT.bit.OST, master ? 1 : 0);
    }
    /* SOCA at TBCTR = 0 (SOCASEL 1 << 8), enabled (1 << 11), every event. */
    assert_int_equal(EPwm1Regs.ETSEL.all, 0x0900);
    assert_int_equal(EPwm1Regs.ETPS.bit.SOCAPRD, 1);
}

/* D8: checked after every EDIS of hal_init: a gate pin muxed to its ePWM
 * while that module is not forced off through the trip zone. */
static int pin_mux_violations;
static int edis_count;
static void gates_muxed_only_when_forced_off(void)
{
    edis_count++;
    for (int k = 0; k < 3; k++) {
        /* GPIO 2k = EPWMkA, 2k+1 = EPWMkB: 2 mux bits each, bits 4k+3:4k. */
        const uint32_t mux = (GpioCtrlRegs.GPAMUX1.all >> (4 * k)) & 0xFUL;
        const int forced = (pwm[k]->TZFRC.bit.OST == 1U) && (pwm[k]->TZCTL.all == 0x000AU);
        if ((mux != 0UL) && !forced) {
            pin_mux_violations++;
        }
    }
}

static void gate_pins_are_muxed_only_once_the_outputs_are_forced_off(void **state)
{
    (void)state;
    c2000_fake_reset();
    SysCtrlRegs.PLLSTS.bit.PLLLOCKS = 1U;
    pin_mux_violations = 0;
    edis_count = 0;
    c2000_fake_set_edis_hook(gates_muxed_only_when_forced_off);
    hal_init();
    c2000_fake_set_edis_hook(NULL);
    assert_true(edis_count > 10);
    assert_int_equal(pin_mux_violations, 0);
    assert_int_equal(GpioCtrlRegs.GPAMUX1.all & 0xFFFUL, 0x555UL); /* and muxed in the end */
}

static void init_sets_pin_mux(void **state)
{
    (void)state;
    /* GPAMUX1: GPIO0..5 = 1 (ePWM, bits 11:0 = 0x555), GPIO12 = 1 (TZ1, bits 25:24). */
    assert_int_equal(GpioCtrlRegs.GPAMUX1.all, 0x01000555UL);
    /* GPAMUX2: GPIO20..23 = 1 (eQEP1, bits 15:8), GPIO28, 29 = 1 (SCI-A, bits 27:24). */
    assert_int_equal(GpioCtrlRegs.GPAMUX2.all, 0x05005500UL);
    assert_int_equal(GpioCtrlRegs.GPAPUD.all, 0x0000003FUL);   /* pull-ups off on gates only */
    assert_int_equal(GpioCtrlRegs.GPAQSEL1.bit.GPIO12, 3);    /* TZ1 asynchronous */
}

/* ---- hal_init: ADC, eQEP, SCI, timer, PIE --------------------------------- */

static void init_sets_adc(void **state)
{
    (void)state;
    /* SMODE_SEL 1 | ADCCLKPS 1 << 1 | ADCPWDN 1 << 5 | ADCBGRFDN 3 << 6 = 0x00E3. */
    assert_int_equal(AdcRegs.ADCTRL3.all, 0x00E3);
    /* ACQ_PS 7 << 8, start-stop, dual sequencer, CPS 0. */
    assert_int_equal(AdcRegs.ADCTRL1.all, 0x0700);
    assert_int_equal(AdcRegs.ADCMAXCONV.bit.MAX_CONV1, 1);    /* two simultaneous pairs */
    assert_int_equal(AdcRegs.ADCCHSELSEQ1.all, 0x0010);       /* CONV00 = A0/B0, CONV01 = A1/B1 */
    assert_int_equal(AdcRegs.ADCTRL2.bit.EPWM_SOCA_SEQ1, 1);
    assert_int_equal(AdcRegs.ADCTRL2.bit.INT_ENA_SEQ1, 1);
    assert_int_equal(AdcRegs.ADCTRL2.bit.INT_MOD_SEQ1, 0);
}

static void init_sets_eqep(void **state)
{
    (void)state;
    assert_int_equal(EQep1Regs.QPOSMAX, 9999);
    assert_int_equal(EQep1Regs.QDECCTL.all, 0);               /* quadrature, x4 */
    /* FREE_SOFT 2 << 14 | PCRM 1 << 12 | IEL 1 << 4 | QPEN 1 << 3 = 0x9018. */
    assert_int_equal(EQep1Regs.QEPCTL.all, 0x9018);
}

static void init_sets_sci_and_timer(void **state)
{
    (void)state;
    assert_int_equal(SciaRegs.SCIHBAUD, 0);
    assert_int_equal(SciaRegs.SCILBAUD, 40);
    assert_int_equal(SciaRegs.SCICCR.all, 0x0007);            /* 8N1 */
    assert_int_equal(SciaRegs.SCICTL1.all, 0x0023);           /* RX and TX on, out of reset */
    assert_int_equal(SciaRegs.SCIFFTX.all, 0xE040);
    /* RXFFOVRCLR 1 << 14 | RXFIFORESET 1 << 13 | RXFFINTCLR 1 << 6 = 0x6040: FIFO on, no interrupt */
    assert_int_equal(SciaRegs.SCIFFRX.all, 0x6040);
    assert_int_equal(CpuTimer2Regs.PRD.all, 0xFFFFFFFFUL);
    assert_int_equal(CpuTimer2Regs.TPR.all, 0);
    assert_int_equal(CpuTimer2Regs.TCR.bit.TSS, 0);           /* running */
}

static void init_enables_only_the_trip_interrupt(void **state)
{
    (void)state;
    assert_int_equal(PieCtrlRegs.PIECTRL.bit.ENPIE, 1);
    assert_int_equal(PieCtrlRegs.PIEIER1.all, 0);
    assert_int_equal(PieCtrlRegs.PIEIER2.all, 0x0001);        /* INT2.1 EPWM1_TZINT */
    assert_int_equal(IER, M_INT2);
    assert_non_null(PieVectTable.EPWM1_TZINT);
    assert_true(PieVectTable.EPWM1_TZINT != PieVectTable.ILLEGAL);
    assert_ptr_equal(PieVectTable.SEQ1INT, PieVectTable.ILLEGAL); /* the catch-all until attached */
}

/* D3: TI's InitPieVectTable fills all 128 vectors; PIE RAM is random after
 * power-up. Every vector but the trip ISR's must force all six outputs off
 * and halt (ESTOP0) - an ITRAP, NMI or stray PIE interrupt included. */
static void every_pie_vector_is_set_and_forces_the_outputs_off(void **state)
{
    (void)state;
    PINT *const vec = (PINT *)&PieVectTable;
    const size_t n = sizeof(PieVectTable) / sizeof(PINT);
    assert_int_equal(n, 128);
    for (size_t k = 0; k < n; k++) {
        assert_non_null(vec[k]);
        if (vec[k] == PieVectTable.EPWM1_TZINT) {
            assert_int_equal(k, 40);                          /* INT2.1 only */
            continue;
        }
        hal_pwm_enable();
        for (int m = 0; m < 3; m++) {
            pwm[m]->TZFRC.all = 0U;
        }
        c2000_fake_estop0 = 0U;
        vec[k]();
        for (int m = 0; m < 3; m++) {
            assert_int_equal(pwm[m]->TZFRC.bit.OST, 1);
        }
        assert_int_equal(c2000_fake_estop0, 1);
    }
}

/* D11: PIEACK = 0xFFFF at start-up, no group left blocked, and in TI's
 * order (C2000Ware's EnableInterrupts): the PIE enabled first, then the
 * acknowledge. Checked after every EDIS of hal_init (the fake's memory
 * cannot see a write, a hook can see its result): no acknowledge found
 * while the PIE is still off. */
static int ack_before_enpie;
static void ack_only_with_the_pie_on(void)
{
    if ((PieCtrlRegs.PIEACK.all != 0U) && (PieCtrlRegs.PIECTRL.bit.ENPIE == 0U)) {
        ack_before_enpie++;
    }
}

static void init_enables_the_pie_then_acknowledges_every_group(void **state)
{
    (void)state;
    c2000_fake_reset();
    SysCtrlRegs.PLLSTS.bit.PLLLOCKS = 1U;
    ack_before_enpie = 0;
    c2000_fake_set_edis_hook(ack_only_with_the_pie_on);
    hal_init();
    c2000_fake_set_edis_hook(NULL);
    assert_int_equal(ack_before_enpie, 0);
    assert_int_equal(PieCtrlRegs.PIECTRL.bit.ENPIE, 1);
    assert_int_equal(PieCtrlRegs.PIEACK.all, 0xFFFF);
}

/* D11: conversions run from TBCLKSYNC on; the stale SEQ1 flag in the PIE and
 * the CPU must not fire the ISR at EINT on a sequence it never saw start. */
static void isr_attach_drops_the_stale_adc_interrupt(void **state)
{
    (void)state;
    PieCtrlRegs.PIEIFR1.bit.INTx1 = 1U;
    PieCtrlRegs.PIEIFR1.bit.INTx7 = 1U;                       /* not ours: kept */
    IFR = M_INT1 | M_INT2;
    hal_isr_attach(fake_ctrl_isr);
    assert_int_equal(PieCtrlRegs.PIEIFR1.bit.INTx1, 0);
    assert_int_equal(PieCtrlRegs.PIEIFR1.bit.INTx7, 1);
    assert_int_equal(IFR, M_INT2);
}

static void isr_attach_installs_and_enables(void **state)
{
    (void)state;
    hal_isr_attach(fake_ctrl_isr);
    assert_ptr_equal(PieVectTable.SEQ1INT, fake_ctrl_isr);
    assert_int_equal(PieCtrlRegs.PIEIER1.bit.INTx1, 1);       /* INT1.1 ADC SEQ1 */
    assert_int_equal(IER, M_INT1 | M_INT2);
    assert_int_equal(c2000_fake_intm, 0);                     /* EINT */
    assert_int_equal(SysCtrlRegs.WDCR, 0x002C);               /* watchdog on, /8 */
    assert_int_equal(SysCtrlRegs.WDKEY, 0xAA);                /* kicked before enabling */
    assert_int_equal(SysCtrlRegs.SCSR, 0x0001);               /* D12: WDOVERRIDE cleared: locked */
    isr_calls = 0;
    PieVectTable.SEQ1INT();
    assert_int_equal(isr_calls, 1);
}

static void isr_ack_clears_adc_flag_and_acks_group1(void **state)
{
    (void)state;
    AdcRegs.ADCTRL2.bit.RST_SEQ1 = 0U;
    AdcRegs.ADCST.all = 0U;
    PieCtrlRegs.PIEACK.all = 0U;
    hal_isr_ack();
    assert_int_equal(PieCtrlRegs.PIEACK.all, PIEACK_GROUP1);
    assert_int_equal(AdcRegs.ADCST.bit.INT_SEQ1_CLR, 1);
    /* D13: no sequencer reset at the end of the ISR: after an overrun it
     * would abort the conversion the next SOCA already started. */
    assert_int_equal(AdcRegs.ADCTRL2.bit.RST_SEQ1, 0);
}

/* D13: the sequencer is rewound right after the results are read. */
static void sample_read_rewinds_the_sequencer_after_reading(void **state)
{
    (void)state;
    hal_sample_t s;
    AdcRegs.ADCTRL2.bit.RST_SEQ1 = 0U;
    hal_sample_read(&s);
    assert_int_equal(AdcRegs.ADCTRL2.bit.RST_SEQ1, 1);
}

/* D12: a watchdog reset is reported (WDFLAG read before the first WDCR
 * write, then cleared by writing it as 1 with the disable value). */
static void watchdog_reset_is_reported_and_its_flag_cleared(void **state)
{
    (void)state;
    assert_false(hal_f28335_watchdog_reset());                /* setup: power-on reset */
    c2000_fake_reset();
    SysCtrlRegs.PLLSTS.bit.PLLLOCKS = 1U;
    SysCtrlRegs.WDCR = 0x0080U;                               /* WDFLAG after a watchdog reset */
    hal_init();
    assert_true(hal_f28335_watchdog_reset());
    assert_int_equal(SysCtrlRegs.WDCR, 0x00E8);               /* 0x0068 | WDFLAG (write 1 to clear) */
}

/* D6: ADC_cal (factory trims) runs in hal_init, with the ADC clock on, as
 * TI's InitAdc does: a debugger load that skips the boot ROM needs it. */
static void init_runs_adc_cal_with_the_adc_clock_on(void **state)
{
    (void)state;
    assert_int_equal(c2000_fake_adc_cal.calls, 1);
    assert_int_equal(c2000_fake_adc_cal.adc_clock_on, 1);
    assert_int_equal(AdcRegs.ADCOFFTRIM, C2000_FAKE_ADCOFFTRIM_TRIM);
    assert_int_equal(AdcRegs.ADCREFSEL, C2000_FAKE_ADCREFSEL_TRIM);
}

/* D5: the flash set-up is a global function (cl2000 cannot inline it into
 * the flash-resident hal_init; FUNC_CANNOT_INLINE on the target). */
static void flash_init_is_callable_on_its_own(void **state)
{
    (void)state;
    FlashRegs.FBANKWAIT.all = 0x0F0FU;                        /* reset value: maximum */
    FlashRegs.FOTPWAIT.all = 0x001FU;
    FlashRegs.FOPT.all = 0U;
    f28335_flash_init();
    assert_int_equal(FlashRegs.FBANKWAIT.all, 0x0505);
    assert_int_equal(FlashRegs.FOTPWAIT.bit.OTPWAIT, 8);
    assert_int_equal(FlashRegs.FOPT.bit.ENPIPE, 1);
    assert_int_equal(c2000_fake_eallow, 0);
}

/* D7: limp mode after start-up (oscillator lost) is a permanent trip: the
 * ISR's every timing check scales with the slow clock and cannot see it. */
static void limp_mode_at_run_time_is_a_permanent_trip(void **state)
{
    (void)state;
    hal_pwm_enable();
    assert_false(hal_trip_active());
    SysCtrlRegs.PLLSTS.bit.MCLKSTS = 1U;
    assert_true(hal_trip_active());
    assert_false(hal_f28335_clock_ok());
    SysCtrlRegs.PLLSTS.bit.MCLKSTS = 0U;                      /* latched: a reset ends it */
    hal_trip_clear();
    assert_true(hal_trip_active());
    EPwm1Regs.TZCLR.all = 0U;
    hal_pwm_enable();
    assert_int_equal(EPwm1Regs.TZCLR.bit.OST, 0);             /* refused */
}

static void watchdog_kick_writes_key_sequence_last_0xaa(void **state)
{
    (void)state;
    SysCtrlRegs.WDKEY = 0U;
    hal_watchdog_kick();
    assert_int_equal(SysCtrlRegs.WDKEY, 0xAA);
}

/* ---- duties --------------------------------------------------------------- */

static void duty_maps_to_cmpa(void **state)
{
    (void)state;
    /* CMPA = TBPRD * (1 - d): 7500 * 0.75 = 5625, 7500 * 0.5 = 3750, 7500 * 0.25 = 1875. */
    const float d[3] = { 0.25f, 0.5f, 0.75f };
    hal_pwm_write(d);
    assert_int_equal(EPwm1Regs.CMPA.half.CMPA, 5625);
    assert_int_equal(EPwm2Regs.CMPA.half.CMPA, 3750);
    assert_int_equal(EPwm3Regs.CMPA.half.CMPA, 1875);
    /* Rounded, not truncated: 7500 * (1 - 1/3) = 4999.9999 in float -> 5000. */
    const float e[3] = { 1.0f / 3.0f, 0.0f, 1.0f };
    hal_pwm_write(e);
    assert_int_equal(EPwm1Regs.CMPA.half.CMPA, 5000);
    assert_int_equal(EPwm2Regs.CMPA.half.CMPA, 7500);         /* duty 0: high side never on */
    assert_int_equal(EPwm3Regs.CMPA.half.CMPA, 1);            /* duty 1: CMPA_MIN (D1) */
}

/* D1: SPRUG04, up-down count with CMPA loaded at TBCTR = 0: CMPA >= 1. */
static void cmpa_never_below_one(void **state)
{
    (void)state;
    /* 7500 * (1 - 0.99995) = 0.375 rounds to 0 -> 1; 7500 * (1 - 0.9997) = 2.25 -> 2. */
    const float d[3] = { 1.0f, 0.99995f, 0.9997f };
    hal_pwm_write(d);
    assert_int_equal(EPwm1Regs.CMPA.half.CMPA, 1);
    assert_int_equal(EPwm2Regs.CMPA.half.CMPA, 1);
    assert_int_equal(EPwm3Regs.CMPA.half.CMPA, 2);
}

static void duty_out_of_range_is_clamped(void **state)
{
    (void)state;
    const float d[3] = { 1.5f, -0.2f, 1e30f };
    hal_pwm_write(d);
    assert_int_equal(EPwm1Regs.CMPA.half.CMPA, 1);
    assert_int_equal(EPwm2Regs.CMPA.half.CMPA, 7500);
    assert_int_equal(EPwm3Regs.CMPA.half.CMPA, 1);
    assert_int_equal(hal_f28335_nonfinite_duty_count(), 0);
}

static void nonfinite_duty_disables_outputs(void **state)
{
    (void)state;
    hal_pwm_enable();
    for (int k = 0; k < 3; k++) {
        pwm[k]->TZFRC.all = 0U;
    }
    const float d[3] = { 0.3f, NAN, 0.6f };
    hal_pwm_write(d);
    for (int k = 0; k < 3; k++) {
        assert_int_equal(pwm[k]->TZFRC.bit.OST, 1);           /* all six outputs forced low */
        assert_int_equal(pwm[k]->CMPA.half.CMPA, 3750);       /* untouched */
    }
    const float e[3] = { INFINITY, 0.5f, 0.5f };
    hal_pwm_write(e);
    assert_int_equal(hal_f28335_nonfinite_duty_count(), 2);
    assert_false(hal_trip_active());                          /* not a hardware trip */
}

/* ---- enable, disable, trip ------------------------------------------------ */

static void enable_and_disable_use_trip_zone_one_shot(void **state)
{
    (void)state;
    hal_pwm_enable();
    for (int k = 0; k < 3; k++) {
        assert_int_equal(pwm[k]->TZCLR.bit.OST, 1);
        pwm[k]->TZFRC.all = 0U;
    }
    assert_false(hal_trip_active());
    hal_pwm_disable();
    for (int k = 0; k < 3; k++) {
        assert_int_equal(pwm[k]->TZFRC.bit.OST, 1);
    }
    assert_int_equal(c2000_fake_eallow, 0);
}

static void hardware_trip_is_latched_by_its_interrupt(void **state)
{
    (void)state;
    hal_pwm_enable();
    EPwm1Regs.TZFLG.bit.OST = 1U;  /* TZ1 pulled low: hardware sets OST */
    PieCtrlRegs.PIEACK.all = 0U;
    PieVectTable.EPWM1_TZINT();
    assert_true(hal_trip_active());
    assert_int_equal(PieCtrlRegs.PIEACK.all, PIEACK_GROUP2);
    assert_int_equal(EPwm1Regs.TZCLR.bit.INT, 1);
    /* No enable while tripped. */
    EPwm1Regs.TZCLR.all = 0U;
    hal_pwm_enable();
    assert_int_equal(EPwm1Regs.TZCLR.bit.OST, 0);
    /* Clearing keeps the outputs off (software force) and ends the trip. */
    EPwm1Regs.TZFRC.all = 0U;
    hal_trip_clear();
    assert_false(hal_trip_active());
    assert_int_equal(EPwm1Regs.TZFRC.bit.OST, 1);
}

static void trip_still_present_at_enable_trips_again(void **state)
{
    (void)state;
    hal_pwm_enable();
    EPwm1Regs.TZFLG.bit.OST = 1U;
    PieVectTable.EPWM1_TZINT();
    hal_trip_clear();
    /* TZ1 still low: the hardware sets OST again right after TZCLR (the fake keeps it set). */
    hal_pwm_enable();
    assert_true(hal_trip_active());
}

static void software_force_is_not_a_trip(void **state)
{
    (void)state;
    /* After hal_init the outputs are held by TZFRC, which also sets OST and raises the interrupt. */
    EPwm1Regs.TZFLG.bit.OST = 1U;
    PieVectTable.EPWM1_TZINT();
    assert_false(hal_trip_active());
    /* Same after an explicit disable. */
    hal_pwm_enable();
    EPwm1Regs.TZFLG.bit.OST = 0U;
    hal_pwm_disable();
    EPwm1Regs.TZFLG.bit.OST = 1U;
    PieVectTable.EPWM1_TZINT();
    assert_false(hal_trip_active());
}

static void trip_seen_before_disable_is_not_lost(void **state)
{
    (void)state;
    hal_pwm_enable();
    EPwm1Regs.TZFLG.bit.OST = 1U;  /* tripped, interrupt not yet taken */
    hal_pwm_disable();
    PieVectTable.EPWM1_TZINT();
    assert_true(hal_trip_active());
}

/* ---- samples -------------------------------------------------------------- */

static void samples_are_scaled_from_left_justified_results(void **state)
{
    (void)state;
    hal_sample_t s;
    /* 2048 counts = 1.5 V = the offset: 0 A. */
    AdcRegs.ADCRESULT0 = (Uint16)(2048U << 4);
    /* 3000 counts = 2.197265625 V: (2.197265625 - 1.5) * 10 = 6.97265625 A; low nibble ignored. */
    AdcRegs.ADCRESULT1 = (Uint16)((3000U << 4) | 0xFU);
    /* 1500 counts = 1.0986328125 V * 200 = 219.7265625 V. */
    AdcRegs.ADCRESULT2 = (Uint16)(1500U << 4);
    EQep1Regs.QPOSCNT = 1234UL;
    hal_sample_read(&s);
    assert_float_equal(s.ia_A, 0.0, TOL);
    assert_float_equal(s.ib_A, 6.97265625, TOL);
    assert_float_equal(s.vdc_V, 219.7265625, 1e-3);
    assert_int_equal(s.enc_count, 1234);
    /* 1000 counts = 0.732421875 V: (0.732421875 - 1.5) * 10 = -7.67578125 A. Full scale
     * 4095 counts = 2.999267578 V: 14.99267578 A. */
    AdcRegs.ADCRESULT0 = (Uint16)(1000U << 4);
    AdcRegs.ADCRESULT1 = (Uint16)(4095U << 4);
    hal_sample_read(&s);
    assert_float_equal(s.ia_A, -7.67578125, TOL);
    assert_float_equal(s.ib_A, 14.99267578125, TOL);
}

/* ---- cycles and ISR timing ------------------------------------------------ */

static void cycles_count_up_from_the_down_counter(void **state)
{
    (void)state;
    CpuTimer2Regs.TIM.all = 0xFFFFFFFFUL - 1000UL;
    assert_int_equal(hal_cycles(), 1000);
    CpuTimer2Regs.TIM.all = 0UL;
    assert_int_equal(hal_cycles(), 0xFFFFFFFFUL);
}

static void isr_timing_records_last_min_max(void **state)
{
    (void)state;
    assert_int_equal(hal_f28335_isr_timing.count, 0);
    CpuTimer2Regs.TIM.all = 100000UL;
    hal_f28335_isr_timing_begin();
    CpuTimer2Regs.TIM.all = 100000UL - 500UL;   /* 500 cycles later */
    hal_f28335_isr_timing_end();
    CpuTimer2Regs.TIM.all = 50000UL;
    hal_f28335_isr_timing_begin();
    CpuTimer2Regs.TIM.all = 50000UL - 300UL;
    hal_f28335_isr_timing_end();
    assert_int_equal(hal_f28335_isr_timing.last_cycles, 300);
    assert_int_equal(hal_f28335_isr_timing.min_cycles, 300);
    assert_int_equal(hal_f28335_isr_timing.max_cycles, 500);
    assert_int_equal(hal_f28335_isr_timing.count, 2);
    /* Across the reload: TIM 10 -> 0 -> 0xFFFFFFFF -> 0xFFFFFFFF - 20 is 11 + 20 = 31 cycles. */
    CpuTimer2Regs.TIM.all = 10UL;
    hal_f28335_isr_timing_begin();
    CpuTimer2Regs.TIM.all = 0xFFFFFFFFUL - 20UL;
    hal_f28335_isr_timing_end();
    assert_int_equal(hal_f28335_isr_timing.last_cycles, 31);
    hal_f28335_isr_timing_reset();
    assert_int_equal(hal_f28335_isr_timing.count, 0);
    assert_int_equal(hal_f28335_isr_timing.min_cycles, 0xFFFFFFFFUL);
}

/* ---- SCI ------------------------------------------------------------------ */

static void sci_queue_feeds_fifo_without_waiting(void **state)
{
    (void)state;
    assert_int_equal(hal_f28335_sci_write("hi!", 3), 3);
    hal_f28335_sci_pump();                       /* FIFO empty (TXFFST 0): all three go */
    assert_int_equal(SciaRegs.SCITXBUF, '!');
    SciaRegs.SCITXBUF = 0U;
    hal_f28335_sci_pump();                       /* nothing left */
    assert_int_equal(SciaRegs.SCITXBUF, 0);

    assert_int_equal(hal_f28335_sci_write("ab", 2), 2);
    SciaRegs.SCIFFTX.bit.TXFFST = 16U;           /* FIFO full: nothing moves */
    hal_f28335_sci_pump();
    assert_int_equal(SciaRegs.SCITXBUF, 0);
    SciaRegs.SCIFFTX.bit.TXFFST = 15U;           /* one free word: only 'a' */
    hal_f28335_sci_pump();
    assert_int_equal(SciaRegs.SCITXBUF, 'a');
    SciaRegs.SCIFFTX.bit.TXFFST = 0U;
    hal_f28335_sci_pump();
    assert_int_equal(SciaRegs.SCITXBUF, 'b');
}

static void sci_queue_reports_what_fits(void **state)
{
    (void)state;
    char big[300];
    memset(big, 'x', sizeof big);
    /* 32 slots, one kept empty to tell full from empty: 31 fit. */
    assert_int_equal(hal_f28335_sci_write(big, 300), 31);
    assert_int_equal(hal_f28335_sci_write(big, 1), 0);
    SciaRegs.SCIFFTX.bit.TXFFST = 0U;
    hal_f28335_sci_pump();                       /* 16 leave for the FIFO */
    assert_int_equal(hal_f28335_sci_write(big, 300), 16);
}

static void sci_baud_from_lspclk_with_its_error(void **state)
{
    (void)state;
    /* 37.5 MHz / (8 x 41) = 114329 baud: -0.76 %, -75 parts in 10000 (integer division) */
    assert_int_equal(F28335_SCI_BAUD_ACTUAL, 114329);
    assert_int_equal(F28335_SCI_ERROR_PER_10K, -75);
}

static void sci_read_takes_the_fifo_without_waiting(void **state)
{
    (void)state;
    uint16_t buf[32];
    /* the fake's FIFO holds 3 words reading 'A' (the register keeps its value) */
    SciaRegs.SCIFFRX.bit.RXFFST = 3U;
    SciaRegs.SCIRXBUF.all = 'A';
    assert_int_equal(hal_f28335_sci_read(buf, 32), 3);
    assert_int_equal(buf[0], 'A');
    assert_int_equal(buf[2], 'A');
    /* no more than asked */
    assert_int_equal(hal_f28335_sci_read(buf, 2), 2);
    /* an empty FIFO: nothing, at once */
    SciaRegs.SCIFFRX.bit.RXFFST = 0U;
    assert_int_equal(hal_f28335_sci_read(buf, 32), 0);
    assert_int_equal(hal_f28335_sci_errors.word_errors, 0);
}

static void sci_read_drops_garbled_words_and_clears_errors(void **state)
{
    (void)state;
    uint16_t buf[32];
    SciaRegs.SCIFFRX.bit.RXFFST = 2U;
    SciaRegs.SCIRXBUF.all = 0x8041U;             /* SCIFFFE: a framing error on this word */
    assert_int_equal(hal_f28335_sci_read(buf, 32), 0);
    assert_int_equal(hal_f28335_sci_errors.word_errors, 2);
    SciaRegs.SCIFFRX.bit.RXFFST = 0U;
    SciaRegs.SCIFFRX.bit.RXFFOVF = 1U;           /* a word was lost */
    SciaRegs.SCIRXST.bit.RXERROR = 1U;           /* break or overrun */
    SciaRegs.SCICTL1.bit.SWRESET = 1U;
    assert_int_equal(hal_f28335_sci_read(buf, 32), 0);
    assert_int_equal(hal_f28335_sci_errors.fifo_overflows, 1);
    assert_int_equal(SciaRegs.SCIFFRX.bit.RXFFOVRCLR, 1);     /* cleared by writing 1 */
    assert_int_equal(hal_f28335_sci_errors.rx_errors, 1);
    assert_int_equal(SciaRegs.SCICTL1.bit.SWRESET, 1);        /* reset, then running again */
}

static void sci_putc_queues_bytes(void **state)
{
    (void)state;
    assert_int_equal(hal_f28335_sci_tx_free(), 31);
    assert_true(hal_f28335_sci_putc(0x1FFU));     /* the low 8 bits */
    assert_int_equal(hal_f28335_sci_tx_free(), 30);
    SciaRegs.SCIFFTX.bit.TXFFST = 0U;
    hal_f28335_sci_pump();
    assert_int_equal(SciaRegs.SCITXBUF, 0xFF);
}

/* Above 1.5 Mbaud the transmit FIFO is fed from its interrupt. At the top rate,
 * 2.34 Mbaud: BRR = 37.5 MHz / (8 x 2343750) - 1 = 1, actual 37.5 MHz / 16 = 2343750
 * baud, error 0. The fake's TXFFST does not move by itself: the test sets it. */
static void sci_fast_rate_feeds_the_fifo_from_its_interrupt(void **state)
{
    (void)state;
    const uint16_t brr = (uint16_t)((F28335_LSPCLK_HZ + 4UL * 2343750UL) / (8UL * 2343750UL) - 1UL);
    assert_int_equal(brr, 1);
    assert_int_equal(F28335_LSPCLK_HZ / (8UL * (brr + 1UL)), 2343750UL);
    assert_false(F28335_SCI_TX_IRQ);                    /* the default build (115200) polls */
    IER = 0U;
    f28335_sci_init_at(brr, true);
    assert_int_equal(SciaRegs.SCILBAUD, 1);
    assert_int_equal(SciaRegs.SCIHBAUD, 0);
    /* SCIRST, SCIFFENA, TXFIFOXRESET, TXFFINTCLR, TXFFIL = 8; TXFFIENA (bit 5) still off */
    assert_int_equal(SciaRegs.SCIFFTX.all, 0xE040 | 8);
    assert_int_equal(PieCtrlRegs.PIEIER9.all, 0x0002);  /* INT9.2 SCITXINTA */
    assert_int_equal(IER, M_INT9);
    assert_non_null(PieVectTable.SCITXINTA);
    assert_true(PieVectTable.SCITXINTA != PieVectTable.ILLEGAL);

    /* 20 bytes queued: the pump only enables the interrupt, nothing is written by it */
    assert_int_equal(hal_f28335_sci_write("0123456789abcdefghij", 20), 20);
    SciaRegs.SCITXBUF = 0U;
    hal_f28335_sci_pump();
    assert_int_equal(SciaRegs.SCITXBUF, 0);
    assert_int_equal(SciaRegs.SCIFFTX.bit.TXFFIENA, 1);
    /* the interrupt at the level (8 words left): 8 written, '0'..'7' */
    SciaRegs.SCIFFTX.bit.TXFFST = 8U;
    PieCtrlRegs.PIEACK.all = 0U;
    PieVectTable.SCITXINTA();
    assert_int_equal(SciaRegs.SCITXBUF, '7');
    assert_int_equal(hal_f28335_sci_tx_free(), 31 - 12);
    assert_int_equal(SciaRegs.SCIFFTX.bit.TXFFIENA, 1);  /* more to send */
    assert_int_equal(PieCtrlRegs.PIEACK.all, PIEACK_GROUP9);
    /* the next: 8 more, '8'..'f' */
    PieVectTable.SCITXINTA();
    assert_int_equal(SciaRegs.SCITXBUF, 'f');
    /* the last 4 ('g'..'j'), then the ring is empty: the interrupt disables itself */
    PieVectTable.SCITXINTA();
    assert_int_equal(SciaRegs.SCITXBUF, 'j');
    assert_int_equal(hal_f28335_sci_tx_free(), 31);
    assert_int_equal(SciaRegs.SCIFFTX.bit.TXFFIENA, 0);
    /* an empty ring: the pump leaves it off */
    hal_f28335_sci_pump();
    assert_int_equal(SciaRegs.SCIFFTX.bit.TXFFIENA, 0);
}

/* The polled build (<= 1.5 Mbaud) never enables the transmit interrupt. */
static void sci_polled_rate_leaves_the_interrupt_off(void **state)
{
    (void)state;
    assert_int_equal(hal_f28335_sci_write("xy", 2), 2);
    hal_f28335_sci_pump();
    assert_int_equal(SciaRegs.SCITXBUF, 'y');
    assert_int_equal(SciaRegs.SCIFFTX.bit.TXFFIENA, 0);
    assert_int_equal(SciaRegs.SCIFFTX.bit.TXFFIL, 0);
    assert_int_equal(PieCtrlRegs.PIEIER9.all, 0);
}

#define T(fn) cmocka_unit_test_setup(fn, setup)

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(derived_register_values),
        T(init_sets_clocks_flash_watchdog),
        T(pll_that_never_locks_is_a_permanent_trip),
        T(limp_mode_leaves_pllcr_alone),
        T(init_sets_epwm),
        T(init_sets_pin_mux),
        T(init_sets_adc),
        T(init_sets_eqep),
        cmocka_unit_test(sci_baud_from_lspclk_with_its_error),
        T(sci_read_takes_the_fifo_without_waiting),
        T(sci_read_drops_garbled_words_and_clears_errors),
        T(sci_putc_queues_bytes),
        T(sci_fast_rate_feeds_the_fifo_from_its_interrupt),
        T(sci_polled_rate_leaves_the_interrupt_off),
        T(init_sets_sci_and_timer),
        T(init_enables_only_the_trip_interrupt),
        T(every_pie_vector_is_set_and_forces_the_outputs_off),
        T(init_enables_the_pie_then_acknowledges_every_group),
        T(isr_attach_drops_the_stale_adc_interrupt),
        T(sample_read_rewinds_the_sequencer_after_reading),
        T(watchdog_reset_is_reported_and_its_flag_cleared),
        T(init_runs_adc_cal_with_the_adc_clock_on),
        T(flash_init_is_callable_on_its_own),
        T(limp_mode_at_run_time_is_a_permanent_trip),
        T(gate_pins_are_muxed_only_once_the_outputs_are_forced_off),
        T(cmpa_never_below_one),
        T(isr_attach_installs_and_enables),
        T(isr_ack_clears_adc_flag_and_acks_group1),
        T(watchdog_kick_writes_key_sequence_last_0xaa),
        T(duty_maps_to_cmpa),
        T(duty_out_of_range_is_clamped),
        T(nonfinite_duty_disables_outputs),
        T(enable_and_disable_use_trip_zone_one_shot),
        T(hardware_trip_is_latched_by_its_interrupt),
        T(trip_still_present_at_enable_trips_again),
        T(software_force_is_not_a_trip),
        T(trip_seen_before_disable_is_not_lost),
        T(samples_are_scaled_from_left_justified_results),
        T(cycles_count_up_from_the_down_counter),
        T(isr_timing_records_last_min_max),
        T(sci_queue_feeds_fifo_without_waiting),
        T(sci_queue_reports_what_fits),
    };
    return cmocka_run_group_tests_name("hal_f28335", tests, NULL, NULL);
}
