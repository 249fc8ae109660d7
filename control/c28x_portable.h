/*
 * c28x_portable.h - forced include (-include) for every portable source:
 * control/, firmware/ and hal/f28335/.
 *
 * The C28x has CHAR_BIT == 16, so the exact-width 8-bit types do not exist
 * there. Poisoning them on the host makes any use a compile error here,
 * before it becomes one on the DSP. It also defines the placement
 * markers RAMFUNC and FLASHFUNC.
 */
#ifndef C28X_PORTABLE_H
#define C28X_PORTABLE_H

#include <stdint.h>
#include <stdbool.h>

#if defined(__GNUC__) && !defined(__TMS320C28XX__)
#pragma GCC poison uint8_t int8_t uint_least8_t int_least8_t uint_fast8_t int_fast8_t
#endif

/* Where a function of firmware/ or hal/f28335/ runs on the F28335, said at
 * its definition (control/ runs from RAM whole: firmware/f28335/target.mk):
 *   RAMFUNC    RAM (cl2000's ramfunc attribute: section .TI.ramfunc, copied
 *              from flash at start-up): the control ISR's path
 *   FLASHFUNC  flash, on the ISR path on purpose: only in a state that does
 *              not control the motor for the user (start-up steps,
 *              commissioning, build levels), with the flash's wait states;
 *              never inlined, so that a RAM caller does not take it in
 *   neither    flash, never on the ISR path
 * tools/check/isr_path.sh and ram_budget.py read the markers. RAMFUNC is
 * empty on the host. */
#if defined(__TMS320C28XX__)
#define RAMFUNC __attribute__((ramfunc))
#else
#define RAMFUNC
#endif
#define FLASHFUNC __attribute__((noinline))

#endif /* C28X_PORTABLE_H */
