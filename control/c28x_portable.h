/*
 * c28x_portable.h - forced include (-include) for every portable source:
 * control/, firmware/ and hal/f28335/.
 *
 * The C28x has CHAR_BIT == 16, so the exact-width 8-bit types do not exist
 * there. Poisoning them on the host makes any use a compile error here,
 * before it becomes one on the DSP.
 */
#ifndef C28X_PORTABLE_H
#define C28X_PORTABLE_H

#include <stdint.h>
#include <stdbool.h>

#if defined(__GNUC__) && !defined(__TMS320C28XX__)
#pragma GCC poison uint8_t int8_t uint_least8_t int_least8_t uint_fast8_t int_fast8_t
#endif

#endif /* C28X_PORTABLE_H */
