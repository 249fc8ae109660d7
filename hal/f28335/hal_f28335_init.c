/*
 * hal_f28335_init.c - hal.h on the TMS320F28335: start-up order and the
 * control interrupt (ADC SEQ1, PIE INT1.1, 10 kHz). Reference: SPRUFB0
 * "PIE" (vector table, PIEIER/PIEACK, CPU IER) and SPRU812 (SEQ1 interrupt).
 */
#include "DSP2833x_Device.h"
#include "hal.h"
#include "hal_f28335.h"
#include "hal_f28335_internal.h"

void hal_init(void)
{
    f28335_sysctrl_init();
    f28335_pie_init();
    f28335_pwm_init();
    f28335_adc_init();
    f28335_qep_init();
    f28335_timer_init();
    f28335_sci_init();
    f28335_pie_enable();
}

void hal_isr_attach(hal_isr_fn isr)
{
    DINT;
    EALLOW;
    PieVectTable.SEQ1INT = (PINT)isr;  /* isr is declared HAL_INTERRUPT by the caller */
    EDIS;
    /* Drop a sequence finished before the ISR existed, so the first
     * interrupt is a fresh one: conversions have run since TBCLKSYNC and
     * left INT_SEQ1, PIEIFR1.1 and IFR.INT1 set. PIEIER1.1 is still 0 and
     * interrupts are masked, so clearing the PIE flag here is safe (SPRUFB0). */
    AdcRegs.ADCTRL2.bit.RST_SEQ1 = 1U;
    AdcRegs.ADCST.bit.INT_SEQ1_CLR = 1U;
    PieCtrlRegs.PIEIFR1.bit.INTx1 = 0U;
    IFR &= ~M_INT1;
    PieCtrlRegs.PIEIER1.bit.INTx1 = 1U;
    IER |= M_INT1;
    f28335_watchdog_enable();
    EINT;
    ERTM;
}

/* INT1 (SEQ1INT, the control ISR) masked in the CPU's IER: one AND, atomic; a sequence that ends
 * meanwhile leaves its flags set and runs at resume (SPRU430, "Interrupts"). */
void hal_isr_pause(void)
{
    IER &= ~M_INT1;
}

void hal_isr_resume(void)
{
    IER |= M_INT1;
}

RAMFUNC void hal_isr_ack(void)
{
    /* RST_SEQ1 is in hal_sample_read: here, after an overrun, it would abort
     * the next period's conversion. */
    AdcRegs.ADCST.bit.INT_SEQ1_CLR = 1U;   /* clear the SEQ1 interrupt flag */
    PieCtrlRegs.PIEACK.all = PIEACK_GROUP1; /* write-1-to-clear: re-open PIE group 1 */
}
