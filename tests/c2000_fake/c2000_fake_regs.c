/* c2000_fake_regs.c - the register objects of the host fake. On the target
 * C2000Ware's DSP2833x_GlobalVariableDefs.c defines them and the header
 * linker command file places them at the peripheral addresses. */
#include <stddef.h>
#include <string.h>

#include "DSP2833x_Device.h"
#include "c2000_fake.h"

volatile Uint16 c2000_fake_eallow;
volatile Uint16 c2000_fake_intm = 1U;
volatile Uint16 IER;
volatile Uint16 IFR;
volatile Uint16 c2000_fake_estop0;
c2000_fake_adc_cal_t c2000_fake_adc_cal;

static void (*s_edis_hook)(void);

volatile struct ADC_REGS AdcRegs;
volatile struct CPUTIMER_REGS CpuTimer2Regs;
volatile struct EPWM_REGS EPwm1Regs;
volatile struct EPWM_REGS EPwm2Regs;
volatile struct EPWM_REGS EPwm3Regs;
volatile struct EQEP_REGS EQep1Regs;
volatile struct GPIO_CTRL_REGS GpioCtrlRegs;
volatile struct PIE_CTRL_REGS PieCtrlRegs;
struct PIE_VECT_TABLE PieVectTable;
volatile struct SCI_REGS SciaRegs;
volatile struct SYS_CTRL_REGS SysCtrlRegs;
volatile struct FLASH_REGS FlashRegs;

/* The fake objects are plain host memory, so dropping volatile for the reset is safe. */
#define ZERO(obj) memset((void *)&(obj), 0, sizeof(obj))

void c2000_fake_reset(void)
{
    ZERO(AdcRegs);
    ZERO(CpuTimer2Regs);
    ZERO(EPwm1Regs);
    ZERO(EPwm2Regs);
    ZERO(EPwm3Regs);
    ZERO(EQep1Regs);
    ZERO(GpioCtrlRegs);
    ZERO(PieCtrlRegs);
    ZERO(PieVectTable);
    ZERO(SciaRegs);
    ZERO(SysCtrlRegs);
    ZERO(FlashRegs);
    c2000_fake_eallow = 0U;
    c2000_fake_intm = 1U;
    c2000_fake_estop0 = 0U;
    IER = 0U;
    IFR = 0U;
    s_edis_hook = NULL;
    c2000_fake_adc_cal.calls = 0U;
    c2000_fake_adc_cal.adc_clock_on = 1U;
    for (Uint32 k = 0U; k < C2000_FAKE_FLASH_B_WORDS; k++) {
        c2000_fake_flash_b[k] = 0xFFFFU;
    }
    memset(&c2000_fake_flash, 0, sizeof c2000_fake_flash);
    c2000_fake_flash.callbacks_per_erase = 3U;
}

void c2000_fake_set_edis_hook(void (*hook)(void))
{
    s_edis_hook = hook;
}

void c2000_fake_edis(void)
{
    c2000_fake_eallow = 0U;
    if (s_edis_hook != NULL) {
        s_edis_hook();
    }
}

void ADC_cal(void)
{
    c2000_fake_adc_cal.calls++;
    if (SysCtrlRegs.PCLKCR0.bit.ADCENCLK == 0U) {
        c2000_fake_adc_cal.adc_clock_on = 0U;
    }
    AdcRegs.ADCREFSEL = C2000_FAKE_ADCREFSEL_TRIM;
    AdcRegs.ADCOFFTRIM = C2000_FAKE_ADCOFFTRIM_TRIM;
}
