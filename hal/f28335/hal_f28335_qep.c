/*
 * hal_f28335_qep.c - eQEP1: quadrature position counter over one
 * revolution with the index position latched. References: SPRUG05
 * sections "Quadrature Decoder Unit", "Position Counter and Control Unit"
 * and the QDECCTL/QEPCTL register descriptions.
 *
 * x4 counting (QSRC = 0, both edges of A and B), QPOSMAX = 4 * lines - 1,
 * PCRM = 1: the counter wraps to 0 after QPOSMAX (and to QPOSMAX below 0),
 * so QPOSCNT is always 0 .. 4 * lines - 1. IEL = 1 latches QPOSCNT into
 * QPOSILAT at each rising index edge (for alignment; not used by hal.h).
 */
#include "DSP2833x_Device.h"
#include "hal_f28335_cfg.h"
#include "hal_f28335_internal.h"

#define QEP_QSRC_QUADRATURE   0U
#define QEP_PCRM_AT_MAX       1U
#define QEP_IEL_RISING        1U
#define QEP_FREE_RUN          2U   /* keep counting on an emulation halt */
#define GPIO_MUX_PERIPH1      1U
#define GPIO_QSEL_SYNC        0U

void f28335_qep_init(void)
{
    EALLOW;
    /* GPIO20..23 = EQEP1A, EQEP1B, EQEP1S, EQEP1I; pull-ups on, synchronised to SYSCLKOUT. */
    GpioCtrlRegs.GPAPUD.bit.GPIO20 = 0U;
    GpioCtrlRegs.GPAPUD.bit.GPIO21 = 0U;
    GpioCtrlRegs.GPAPUD.bit.GPIO22 = 0U;
    GpioCtrlRegs.GPAPUD.bit.GPIO23 = 0U;
    GpioCtrlRegs.GPAQSEL2.bit.GPIO20 = GPIO_QSEL_SYNC;
    GpioCtrlRegs.GPAQSEL2.bit.GPIO21 = GPIO_QSEL_SYNC;
    GpioCtrlRegs.GPAQSEL2.bit.GPIO22 = GPIO_QSEL_SYNC;
    GpioCtrlRegs.GPAQSEL2.bit.GPIO23 = GPIO_QSEL_SYNC;
    GpioCtrlRegs.GPAMUX2.bit.GPIO20 = GPIO_MUX_PERIPH1;
    GpioCtrlRegs.GPAMUX2.bit.GPIO21 = GPIO_MUX_PERIPH1;
    GpioCtrlRegs.GPAMUX2.bit.GPIO22 = GPIO_MUX_PERIPH1;
    GpioCtrlRegs.GPAMUX2.bit.GPIO23 = GPIO_MUX_PERIPH1;
    EDIS;

    EQep1Regs.QEPCTL.bit.QPEN = 0U;  /* configure with the counter stopped */
    EQep1Regs.QDECCTL.all = 0U;
    EQep1Regs.QDECCTL.bit.QSRC = QEP_QSRC_QUADRATURE;
    EQep1Regs.QPOSINIT = 0UL;
    EQep1Regs.QPOSMAX = F28335_QPOSMAX;
    EQep1Regs.QPOSCNT = 0UL;
    EQep1Regs.QEPCTL.bit.PCRM = QEP_PCRM_AT_MAX;
    EQep1Regs.QEPCTL.bit.IEL = QEP_IEL_RISING;
    EQep1Regs.QEPCTL.bit.FREE_SOFT = QEP_FREE_RUN;
    EQep1Regs.QEPCTL.bit.QPEN = 1U;
}
