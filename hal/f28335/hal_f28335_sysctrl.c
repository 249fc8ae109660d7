/*
 * hal_f28335_sysctrl.c - start-up of the F28335: watchdog, copy of the RAM
 * functions, PLL (30 MHz x 10 / 2 = 150 MHz), flash wait states,
 * peripheral clocks, PIE reset and vector table, the watchdog (enable,
 * lock, service, reset cause) and the missing-clock (limp mode) watch.
 * References: SPRUFB0 "Clocking" (PLL, PLLSTS, PCLKCRx, HISPCP/LOSPCP),
 * "Watchdog Block", "PIE"; SPRS439 flash timing.
 */
#include <string.h>

#include "DSP2833x_Device.h"
#include "hal.h"
#include "hal_f28335.h"
#include "hal_f28335_cfg.h"
#include "hal_f28335_internal.h"

F28335_STATIC_ASSERT(sysclk_matches_pll,
                     BOARD_XTAL_HZ * BOARD_PLL_MULT / 2UL == BOARD_SYSCLK_HZ);
F28335_STATIC_ASSERT(pll_mult_in_range, BOARD_PLL_MULT >= 1U && BOARD_PLL_MULT <= 10U);

#if defined(__TMS320C28XX__)
/* Defined by firmware/f28335/f28335_flash.cmd (LOAD_START, LOAD_SIZE, RUN_START). */
extern Uint16 RamfuncsLoadStart;
extern Uint16 RamfuncsLoadSize;
extern Uint16 RamfuncsRunStart;
#endif

static volatile bool s_clock_ok;
static bool s_watchdog_reset;  /* WDCR.WDFLAG was set at start-up */

/* Copy the code that must run from RAM (ISR path, flash set-up) out of flash. */
static void ramfuncs_copy(void)
{
#if defined(__TMS320C28XX__)
    memcpy(&RamfuncsRunStart, &RamfuncsLoadStart, (size_t)&RamfuncsLoadSize);
#endif
}

/* SPRUFB0 PLL procedure: no change in limp mode; DIVSEL = /4 while PLLCR
 * changes; missing-clock detection off until locked; then DIVSEL = /2. */
static bool pll_init(void)
{
    bool locked = true;
    uint32_t polls = 0U;

    if (SysCtrlRegs.PLLSTS.bit.MCLKSTS != 0U) {
        return false;  /* oscillator missing: running on the limp-mode clock */
    }
    EALLOW;
    SysCtrlRegs.PLLSTS.bit.DIVSEL = 0U;
    if (SysCtrlRegs.PLLCR.bit.DIV != BOARD_PLL_MULT) {
        SysCtrlRegs.PLLSTS.bit.MCLKOFF = 1U;
        SysCtrlRegs.PLLCR.bit.DIV = BOARD_PLL_MULT;
        EDIS;
        while ((SysCtrlRegs.PLLSTS.bit.PLLLOCKS == 0U) && (polls < F28335_PLL_LOCK_POLLS)) {
            polls++;
        }
        locked = (SysCtrlRegs.PLLSTS.bit.PLLLOCKS != 0U);
        EALLOW;
        SysCtrlRegs.PLLSTS.bit.MCLKOFF = 0U;
    }
    if (locked) {
        SysCtrlRegs.PLLSTS.bit.DIVSEL = F28335_PLL_DIVSEL_2;
    }
    EDIS;
    return locked;
}

/* Flash wait states for 150 MHz, as TI's InitFlash: a global function in
 * ramfuncs that cl2000 may not inline into hal_init (flash-resident). */
#if defined(__TMS320C28XX__)
#pragma FUNC_CANNOT_INLINE(f28335_flash_init)
#endif
RAMFUNC void f28335_flash_init(void)
{
    EALLOW;
    FlashRegs.FOPT.bit.ENPIPE = 1U;  /* prefetch pipeline on */
    FlashRegs.FBANKWAIT.bit.PAGEWAIT = F28335_FLASH_PAGEWAIT;
    FlashRegs.FBANKWAIT.bit.RANDWAIT = F28335_FLASH_RANDWAIT;
    FlashRegs.FOTPWAIT.bit.OTPWAIT = F28335_FLASH_OTPWAIT;
    FlashRegs.FSTDBYWAIT.bit.STDBYWAIT = F28335_FLASH_FALLBACK_WAIT;
    FlashRegs.FACTIVEWAIT.bit.ACTIVEWAIT = F28335_FLASH_FALLBACK_WAIT;
    EDIS;
#if defined(__TMS320C28XX__)
    __asm(" RPT #7 || NOP");  /* let the new wait states take effect before returning to flash */
#endif
}

static void peripheral_clocks_init(void)
{
    EALLOW;
    SysCtrlRegs.HISPCP.all = F28335_HISPCP;
    SysCtrlRegs.LOSPCP.all = F28335_LOSPCP;
    SysCtrlRegs.PCLKCR0.bit.TBCLKSYNC = 0U;  /* ePWM time bases held until all are set up */
    SysCtrlRegs.PCLKCR0.bit.ADCENCLK = 1U;
    SysCtrlRegs.PCLKCR0.bit.SCIAENCLK = 1U;
    SysCtrlRegs.PCLKCR1.bit.EPWM1ENCLK = 1U;
    SysCtrlRegs.PCLKCR1.bit.EPWM2ENCLK = 1U;
    SysCtrlRegs.PCLKCR1.bit.EPWM3ENCLK = 1U;
    SysCtrlRegs.PCLKCR1.bit.EQEP1ENCLK = 1U;
    SysCtrlRegs.PCLKCR3.bit.CPUTIMER2ENCLK = 1U;
    SysCtrlRegs.PCLKCR3.bit.GPIOINENCLK = 1U;
    EDIS;
}

void f28335_sysctrl_init(void)
{
    /* WDFLAG tells a watchdog reset from a power-on/XRS reset; read it
     * before anything writes WDCR, clear it (write 1) with the disable. */
    s_watchdog_reset = (SysCtrlRegs.WDCR & F28335_WDCR_WDFLAG) != 0U;
    EALLOW;
    /* PLL lock and ADC power-up outlast a 4 ms watchdog */
    SysCtrlRegs.WDCR = s_watchdog_reset ? (F28335_WDCR_DISABLE | F28335_WDCR_WDFLAG) : F28335_WDCR_DISABLE;
    EDIS;
    ramfuncs_copy();
    s_clock_ok = pll_init();
    f28335_flash_init();
    peripheral_clocks_init();
}

/* Every one of the 128 vectors (SPRUFB0 "PIE Vector Table": reserved
 * entries, the CPU's own interrupts and traps, groups 1..12), as TI's
 * InitPieVectTable fills them: PIE RAM holds random data after power-up, and
 * an ITRAP or NMI taken through it would jump anywhere with the PWM running. */
static void pie_vectors_init(void)
{
    /* volatile: every store is a write to PIE RAM the CPU fetches vectors
     * from, never to be merged or dropped by the optimiser */
    volatile PINT *const vec = (volatile PINT *)&PieVectTable;
    const uint16_t n = (uint16_t)(sizeof(PieVectTable) / sizeof(PINT));
    uint16_t k;

    EALLOW;
    for (k = 0U; k < n; k++) {
        vec[k] = &f28335_unexpected_isr;
    }
    EDIS;
}

RAMFUNC HAL_INTERRUPT void f28335_unexpected_isr(void)
{
    hal_pwm_disable();  /* TZ one-shot force on all three legs: both gates low */
    ESTOP0;
#if defined(__TMS320C28XX__)
    for (;;) {
        /* no kick: the watchdog resets the device (35 ms, once enabled) */
    }
#endif
}

void f28335_pie_init(void)
{
    DINT;
    PieCtrlRegs.PIECTRL.bit.ENPIE = 0U;
    PieCtrlRegs.PIEIER1.all = 0U;  PieCtrlRegs.PIEIFR1.all = 0U;
    PieCtrlRegs.PIEIER2.all = 0U;  PieCtrlRegs.PIEIFR2.all = 0U;
    PieCtrlRegs.PIEIER3.all = 0U;  PieCtrlRegs.PIEIFR3.all = 0U;
    PieCtrlRegs.PIEIER4.all = 0U;  PieCtrlRegs.PIEIFR4.all = 0U;
    PieCtrlRegs.PIEIER5.all = 0U;  PieCtrlRegs.PIEIFR5.all = 0U;
    PieCtrlRegs.PIEIER6.all = 0U;  PieCtrlRegs.PIEIFR6.all = 0U;
    PieCtrlRegs.PIEIER7.all = 0U;  PieCtrlRegs.PIEIFR7.all = 0U;
    PieCtrlRegs.PIEIER8.all = 0U;  PieCtrlRegs.PIEIFR8.all = 0U;
    PieCtrlRegs.PIEIER9.all = 0U;  PieCtrlRegs.PIEIFR9.all = 0U;
    PieCtrlRegs.PIEIER10.all = 0U; PieCtrlRegs.PIEIFR10.all = 0U;
    PieCtrlRegs.PIEIER11.all = 0U; PieCtrlRegs.PIEIFR11.all = 0U;
    PieCtrlRegs.PIEIER12.all = 0U; PieCtrlRegs.PIEIFR12.all = 0U;
    IER = 0x0000U;
    IFR = 0x0000U;
    pie_vectors_init();
}

/* TI's order (C2000Ware DSP2833x_PieCtrl.c, EnableInterrupts): the PIE
 * enabled first, then every group acknowledged, so that none is left
 * blocked by a stale ACK bit and the acknowledge reaches an enabled PIE. */
void f28335_pie_enable(void)
{
    PieCtrlRegs.PIECTRL.bit.ENPIE = 1U;
    PieCtrlRegs.PIEACK.all = F28335_PIEACK_ALL;
}

void f28335_watchdog_enable(void)
{
    hal_watchdog_kick();
    EALLOW;
    SysCtrlRegs.WDCR = F28335_WDCR_ENABLE_DIV8;
    SysCtrlRegs.SCSR = F28335_SCSR_WD_LOCK;  /* WDOVERRIDE cleared: WDDIS is locked until reset */
    EDIS;
}

bool hal_f28335_watchdog_reset(void)
{
    return s_watchdog_reset;
}

void f28335_delay_us(uint32_t us)
{
    /* At least one SYSCLKOUT cycle per pass, at most 150 MHz: n passes last >= us. */
    volatile uint32_t pass;
    const uint32_t n = us * (BOARD_SYSCLK_HZ / 1000000UL);

    for (pass = 0U; pass < n; pass++) {
    }
}

RAMFUNC bool hal_f28335_clock_ok(void)
{
    /* Limp mode at run time (oscillator lost after start-up): every timing
     * scales with the slow clock, so the HAL latches it; only a reset, not
     * MCLKCLR from here, brings the clock back. */
    if (SysCtrlRegs.PLLSTS.bit.MCLKSTS != 0U) {
        s_clock_ok = false;
    }
    return s_clock_ok;
}

void hal_watchdog_kick(void)
{
    EALLOW;
    SysCtrlRegs.WDKEY = F28335_WDKEY_1;
    SysCtrlRegs.WDKEY = F28335_WDKEY_2;
    EDIS;
}
