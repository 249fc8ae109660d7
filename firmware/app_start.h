/*
 * app_start.h - inside the app (app.c and app_start.c only): the start
 * sequence, which runs from flash (app_start.c), and the two outputs of
 * app.c it shares. ISR context, every function.
 */
#ifndef APP_START_H
#define APP_START_H

#include <stdbool.h>

#include "app.h"

/* A start (commission false) or a commissioning taken in INIT or IDLE:
 * the first state of its sequence entered, or skipped within this call. */
void app_start_sequence(app_t *app, const hal_sample_t *s, bool commission);

/* CALIBRATE's period: the offsets; done: the next state of the sequence. */
void app_calibrate_state(app_t *app, const hal_sample_t *s);

/* ALIGN's period: the alignment's vector out; done: the encoder aligned, the next state. */
void app_align_state(app_t *app, const hal_sample_t *s);

/* Background, the ISR held off (app_reconfigure_now): the controller and the start-up steps
 * from app->cfg again (app_request_reconfigure's flags). */
void app_reconfigure(app_t *app, uint16_t flags);

/* The start-up steps and protection from app->cfg (app_init, app_reconfigure; app_bg.c). */
void app_init_steps(app_t *app);

/* PWM off first, then FAULT with the step's fault and its snapshot (app.c). */
void app_latch_fault(app_t *app, const app_step_t *f, const hal_sample_t *s);

/* A step's period written out: the duties unless not finite, then the step's fault (app.c); returns r. */
app_step_t app_output(app_t *app, app_step_t r, const hal_sample_t *s);

#endif
