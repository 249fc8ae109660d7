/*
 * hal_f28335.h - what the F28335 HAL offers beyond hal/hal.h: the ISR
 * timing record (for CCS watch windows), the SCI-A link's transmit
 * and receive queues, and start-up diagnostics. Target firmware only; portable code
 * uses hal.h.
 */
#ifndef HAL_F28335_H
#define HAL_F28335_H

#include <stdint.h>
#include <stdbool.h>

/* Control ISR duration in SYSCLKOUT cycles (6.67 ns each), from CPU timer 2. */
typedef struct {
    uint32_t last_cycles;   /* latest measured ISR */
    uint32_t min_cycles;    /* shortest since reset (0xFFFFFFFF before the first) */
    uint32_t max_cycles;    /* longest since reset */
    uint32_t count;         /* ISRs measured since reset */
} hal_f28335_isr_timing_t;

/* Readable from CCS (Expressions window); written only by the two calls below. */
extern volatile hal_f28335_isr_timing_t hal_f28335_isr_timing;

/* Start timing the control ISR. ISR context, first statement of the ISR. */
void hal_f28335_isr_timing_begin(void);

/* Stop timing and update last/min/max/count. ISR context, last statement. */
void hal_f28335_isr_timing_end(void);

/* Forget min/max/count (e.g. after start-up transients). Background context. */
void hal_f28335_isr_timing_reset(void);

/* Queue up to len characters for SCI-A (8N1 at F28335_SCI_BAUD); returns how many were
 * queued (the rest did not fit). One producer context only (ISR or background). */
uint16_t hal_f28335_sci_write(const char *data, uint16_t len);

/* Queue one byte (its low 8 bits); false when the queue is full. Background, as sci_write. */
bool hal_f28335_sci_putc(uint16_t c);

/* Bytes the transmit queue can take now. Background. */
uint16_t hal_f28335_sci_tx_free(void);

/* Move queued characters into the SCI-A transmit FIFO, never waiting; above
 * F28335_SCI_TX_IRQ_MIN_BAUD only enable the transmit interrupt, which moves them. Background loop. */
void hal_f28335_sci_pump(void);

/* Take up to max received bytes (at most the FIFO's 16) into buf, one per word; returns the
 * count. Never waits. Garbled words are dropped and errors cleared, both counted in
 * hal_f28335_sci_errors. Background loop. */
uint16_t hal_f28335_sci_read(uint16_t *buf, uint16_t max);

/* Receive errors since hal_init (saturating): for the link's status. */
typedef struct {
    uint16_t word_errors;      /* characters with a framing or parity error, dropped */
    uint16_t fifo_overflows;   /* RXFFOVF: characters lost to a full FIFO (the background was late) */
    uint16_t rx_errors;        /* RXERROR (break, overrun): the SCI was reset */
} hal_f28335_sci_errors_t;
extern hal_f28335_sci_errors_t hal_f28335_sci_errors;

/* False when the PLL did not lock or the oscillator is missing, at start-up
 * or since (PLLSTS.MCLKSTS, limp mode, polled by every call and by
 * hal_trip_active()); the HAL then reports a trip that hal_trip_clear()
 * cannot clear. Any context. */
bool hal_f28335_clock_ok(void);

/* True when the last reset was a watchdog reset (WDCR.WDFLAG, read and
 * cleared by hal_init). Any context after hal_init. */
bool hal_f28335_watchdog_reset(void);

/* Number of hal_pwm_write() calls that got a NaN or infinite duty (each
 * disabled the outputs). Any context. */
uint32_t hal_f28335_nonfinite_duty_count(void);

#endif /* HAL_F28335_H */
