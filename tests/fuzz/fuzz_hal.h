/*
 * fuzz_hal.h - the HAL stub of the ISR fuzz harness (tests/fuzz/): hal.h
 * on a board whose samples, trip input and ISR timing come from the fuzz
 * input, and which checks the app's outputs as real hardware would take
 * them. A broken rule aborts (a libFuzzer finding) with the rule named:
 *   - a duty written that is not finite;
 *   - a duty outside [0, 1] written, or left, while the outputs are on;
 *   - the outputs enabled while the trip input is active;
 *   - the outputs on after an ISR that ends in FAULT (checked by the harness);
 *   - hal_isr_ack() not the last HAL call of the ISR, or not exactly once.
 * Host-only, one board per process.
 */
#ifndef FUZZ_HAL_H
#define FUZZ_HAL_H

#include <stdbool.h>
#include <stdint.h>

#include "hal.h"

typedef struct {
    hal_sample_t sample;       /* what hal_sample_read() returns in the coming ISR */
    bool trip;                 /* trip-zone input level; latches as the hardware does */
    uint32_t entry_cycles;     /* hal_cycles() at the ISR's first call */
    uint32_t run_cycles;       /* added to hal_cycles() for every later call in the ISR */
} fuzz_hal_period_t;

/* Power-on: outputs off, no trip, duties 0.5, counters zero. */
void fuzz_hal_reset(void);

/* Set up the coming ISR call (before app_isr). */
void fuzz_hal_begin_isr(const fuzz_hal_period_t *p);

/* After app_isr: checks the ack and returns whether the outputs are on. */
bool fuzz_hal_end_isr(void);

/* Report a broken rule and abort (libFuzzer then keeps the input). */
void fuzz_hal_fail(const char *rule);

#endif /* FUZZ_HAL_H */
