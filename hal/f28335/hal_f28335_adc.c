/*
 * hal_f28335_adc.c - ADC sequencer 1 started by ePWM1 SOCA at TBCTR = 0,
 * simultaneous sampling of the two phase currents, and the sample read.
 * References: SPRU812 sections "Simultaneous Sampling Mode", "ePWM SOC",
 * "ADC Power-Up Sequence", "ADC Clock Prescaler" and the register section.
 *
 * Channels (SMODE_SEL = 1: CONVnn = k samples ADCINAk and ADCINBk at the
 * same instant, results in the order A, B):
 *   CONV00 = 0: ADCINA0 = ia -> ADCRESULT0, ADCINB0 = ib -> ADCRESULT1
 *   CONV01 = 1: ADCINA1 = vdc -> ADCRESULT2, ADCINB1 spare -> ADCRESULT3
 * ADCRESULTn holds the 12-bit value left-justified: counts = ADCRESULTn >> 4,
 * volts at the pin = counts * 3.0 V / 4096.
 */
#include "DSP2833x_Device.h"
#include "hal.h"
#include "hal_f28335_cfg.h"
#include "hal_f28335_internal.h"

#define ADC_BGRF_POWER_UP   3U   /* ADCBGRFDN: bandgap and reference on */
#define ADC_SEQ_CONV_PAIRS  2U   /* (ia, ib), (vdc, spare) */
#define ADC_PAIR_CURRENTS   0U   /* ADCINA0 / ADCINB0 */
#define ADC_PAIR_VDC        1U   /* ADCINA1 / ADCINB1 */

/* TI's factory trim routine in TI-reserved OTP (0x380080, section .adc_cal
 * of C2000Ware's DSP2833x_ADC_cal.asm): writes ADCREFSEL and ADCOFFTRIM. */
extern void ADC_cal(void);

void f28335_adc_init(void)
{
    /* As TI's InitAdc: the boot ROM runs ADC_cal only when it boots the
     * device; a debugger load-and-run skips it and leaves the reference and
     * offset trims at their reset values. The ADC clock is on already
     * (peripheral_clocks_init). */
    EALLOW;
    ADC_cal();
    EDIS;
    AdcRegs.ADCTRL3.bit.ADCBGRFDN = ADC_BGRF_POWER_UP;
    AdcRegs.ADCTRL3.bit.ADCPWDN = 1U;
    f28335_delay_us(F28335_ADC_POWERUP_US);
    AdcRegs.ADCTRL3.bit.ADCCLKPS = F28335_ADC_CLKPS;
    AdcRegs.ADCTRL3.bit.SMODE_SEL = 1U;

    AdcRegs.ADCTRL1.bit.SEQ_CASC = 0U;   /* dual sequencers: SEQ1 alone */
    AdcRegs.ADCTRL1.bit.CONT_RUN = 0U;   /* start-stop: one sequence per SOC */
    AdcRegs.ADCTRL1.bit.CPS = 0U;
    AdcRegs.ADCTRL1.bit.ACQ_PS = F28335_ADC_ACQ_PS;

    AdcRegs.ADCMAXCONV.bit.MAX_CONV1 = ADC_SEQ_CONV_PAIRS - 1U;
    AdcRegs.ADCCHSELSEQ1.bit.CONV00 = ADC_PAIR_CURRENTS;
    AdcRegs.ADCCHSELSEQ1.bit.CONV01 = ADC_PAIR_VDC;

    AdcRegs.ADCTRL2.bit.EPWM_SOCA_SEQ1 = 1U;
    AdcRegs.ADCTRL2.bit.INT_MOD_SEQ1 = 0U;  /* interrupt at every end of sequence */
    AdcRegs.ADCTRL2.bit.INT_ENA_SEQ1 = 1U;
    AdcRegs.ADCTRL2.bit.RST_SEQ1 = 1U;
}

RAMFUNC static float current_from_result(Uint16 result)
{
    const float counts = (float)(result >> F28335_ADC_RESULT_SHIFT);
    return counts * F28335_I_A_PER_COUNT - F28335_I_OFFSET_A;
}

RAMFUNC void hal_sample_read(hal_sample_t *out)
{
    const float vdc_counts = (float)(AdcRegs.ADCRESULT2 >> F28335_ADC_RESULT_SHIFT);

    out->ia_A = current_from_result(AdcRegs.ADCRESULT0);
    out->ib_A = current_from_result(AdcRegs.ADCRESULT1);
    /* Results read: rewind SEQ1 to CONV00 now, 100 us before the next SOCA,
     * not at the end of the ISR where an overrunning ISR would abort it. */
    AdcRegs.ADCTRL2.bit.RST_SEQ1 = 1U;
    out->vdc_V = vdc_counts * F28335_VDC_V_PER_COUNT - F28335_VDC_OFFSET_V;
    out->enc_count = EQep1Regs.QPOSCNT;
}
