/* hal_f28335_internal.h - start-up steps shared between the F28335 HAL
 * files; not for use outside hal/f28335/. */
#ifndef HAL_F28335_INTERNAL_H
#define HAL_F28335_INTERNAL_H

#include <stdint.h>

#include "hal.h"

/* Compile-time check usable in C99 (negative array size on failure). */
#define F28335_STATIC_ASSERT(name, cond) typedef char f28335_assert_##name[(cond) ? 1 : -1]

/* Watchdog off, RAM functions copied, PLL to 150 MHz, flash wait states,
 * peripheral clocks. Start-up, first step of hal_init(). */
void f28335_sysctrl_init(void);

/* Flash wait states and pipeline for 150 MHz (TI's InitFlash). Runs from
 * RAM and is never inlined into a flash-resident caller: flash must not be
 * read while its wait states change. Start-up, after the PLL. */
void f28335_flash_init(void);

/* PIE off and cleared, every vector pointing at f28335_unexpected_isr,
 * CPU interrupts masked. Start-up, before any vector is set. */
void f28335_pie_init(void);

/* PIE on (PIECTRL.ENPIE), then every group acknowledged (PIEACK), in TI's
 * order. Start-up, last step of hal_init(). */
void f28335_pie_enable(void);

/* Any interrupt or trap nobody installed (ILLEGAL, NMI, USER1..12, an
 * unexpected PIE interrupt): all six gate outputs off, then halt (ESTOP0 for
 * a debugger, then wait for the watchdog reset). Interrupt context. */
HAL_INTERRUPT void f28335_unexpected_isr(void);

/* Watchdog on (35 ms). Start-up, last step before the background loop. */
void f28335_watchdog_enable(void);

/* Busy-wait at least us microseconds (bounded loop). Start-up only. */
void f28335_delay_us(uint32_t us);

/* Peripheral set-ups, each including its pins. Start-up, in hal_init(). */
void f28335_pwm_init(void);
void f28335_adc_init(void);
void f28335_qep_init(void);
void f28335_timer_init(void);
void f28335_sci_init(void);

/* SCI-A 8N1 at BRR brr (hal_f28335_cfg.h), its transmit FIFO fed by the SCITXINTA interrupt
 * (tx_irq) or by hal_f28335_sci_pump() alone; f28335_sci_init() calls it with the build's
 * F28335_SCI_BRR and F28335_SCI_TX_IRQ. Start-up. */
void f28335_sci_init_at(uint16_t brr, bool tx_irq);

#endif /* HAL_F28335_INTERNAL_H */
