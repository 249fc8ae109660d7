/*
 * hal.h - the thin hardware abstraction, at the granularity of one control
 * period. One implementation per target, chosen at link time:
 *   hal/f28335/  the TMS320F28335 board (registers)
 *   hal/sim/     the simulated board (plant, inverter, sensors)
 * No function-pointer table: the build links exactly one of them.
 *
 * Timing contract (both targets): hal_sample_read() returns what was
 * sampled at the start of the current period; duties written with
 * hal_pwm_write() take effect at the start of the next period (shadowed
 * compare registers loaded at counter zero). This is the one-period
 * computation delay the controller compensates.
 */
#ifndef HAL_H
#define HAL_H

#include <stdint.h>
#include <stdbool.h>

/* One period's sampled inputs, in SI units after the board's scaling. */
typedef struct {
    float ia_A;          /* phase-a current, positive into the motor */
    float ib_A;          /* phase-b current, positive into the motor */
    float vdc_V;         /* DC-bus voltage */
    uint32_t enc_count;  /* encoder position count, 0 .. lines*4 - 1 */
} hal_sample_t;

/* The control ISR: called once per PWM period after the current samples are taken. */
typedef void (*hal_isr_fn)(void);

/* Interrupt-function qualifier for the control ISR (TI: __interrupt; host: none). */
#if defined(__TMS320C28XX__)
#define HAL_INTERRUPT __interrupt
#else
#define HAL_INTERRUPT
#endif

/* Bring up clocks, PWM (outputs off), ADC, encoder, fault input. Start-up, before interrupts. */
void hal_init(void);

/* Install the control ISR and enable its interrupt (10 kHz). Start-up context, after hal_init(). */
void hal_isr_attach(hal_isr_fn isr);

/* Read this period's samples into *out. ISR context, first HAL call of the ISR. */
void hal_sample_read(hal_sample_t *out);

/* Set the three duty cycles in [0, 1] (clamped), applied from the next period. ISR context. */
void hal_pwm_write(const float duty[3]);

/* Enable the six gate outputs. ISR or background context, only with no trip active. */
void hal_pwm_enable(void);

/* Force all six gate outputs off at once. Any context; safe to call repeatedly. */
void hal_pwm_disable(void);

/* True while the hardware fault input (trip zone) has latched a trip. Any context. */
bool hal_trip_active(void);

/* Clear a latched hardware trip (outputs stay disabled). Background context. */
void hal_trip_clear(void);

/* Hold the control interrupt off (a period that comes meanwhile runs at hal_isr_resume) and let
 * it run again: background work that must not be interrupted by the ISR, short (a few periods;
 * a parameter save's erase, about a second) and only with the outputs off (app_reconfigure_now,
 * link_nv_save). Background context, in pairs. */
void hal_isr_pause(void);
void hal_isr_resume(void);

/* Acknowledge the control interrupt so the next one can be taken. ISR context, last HAL call. */
void hal_isr_ack(void);

/* Free-running CPU cycle counter, for measuring the ISR. Any context. */
uint32_t hal_cycles(void);

/* Service the watchdog. Background loop only. */
void hal_watchdog_kick(void);

/* ---- the parameter store's sector (firmware/params/nv_store.h) --------------
 * One flash sector reserved for the saved parameters (the F28335's sector
 * B, 32K words: hal/f28335/hal_f28335_nv.c; the SIL's: drive_sil --nv
 * FILE), read and programmed in 16-bit words; an erased word reads
 * 0xFFFF, a program only clears bits. */

/* The sector's size [words]. Any context. */
uint32_t hal_nv_words(void);

/* n words from word off of the sector into dst; false when they do not all
 * lie in it. Start-up or background context. */
bool hal_nv_read(uint32_t off, uint16_t *dst, uint16_t n);

/* One block: n words from src (in RAM) programmed at word off, the sector
 * erased first when erase_first; false when the flash refused (an erase,
 * a program or the verify failed, or a range outside the sector).
 * Background context, the drive stopped: the outputs are forced off and
 * every interrupt held off while the flash is erased or programmed (the
 * F28335: an erase takes about a second, the watchdog serviced
 * meanwhile); on return interrupts are enabled and a control period that
 * came meanwhile runs at once, late: the caller keeps the drive's
 * tracking from counting the gap (the encoder, the ISR's interval). */
bool hal_nv_write(uint32_t off, const uint16_t *src, uint16_t n, bool erase_first);

#endif /* HAL_H */
