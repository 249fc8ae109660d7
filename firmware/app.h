/*
 * app.h - the ISR glue and the drive state machine.
 *
 *   IDLE --start--> RUN --stop--> IDLE
 *   IDLE, RUN --hardware trip | overcurrent | non-finite--> FAULT
 *   FAULT --fault reset, cause gone--> IDLE
 *
 * Background requests (start, stop, fault reset) only set a flag; the ISR
 * carries them out at the start of its next period, so the controller
 * state is only ever touched from the ISR. A fault turns the PWM off in
 * the same ISR call that detected it and keeps that period's samples.
 */
#ifndef APP_H
#define APP_H

#include <stdint.h>

#include "ctrl.h"
#include "hal.h"

typedef enum { APP_STATE_IDLE = 0, APP_STATE_RUN = 1, APP_STATE_FAULT = 2 } app_state_t;
typedef enum {
    APP_FAULT_NONE = 0,
    APP_FAULT_HW_TRIP = 1,
    APP_FAULT_OVERCURRENT = 2,
    APP_FAULT_NONFINITE = 3
} app_fault_t;

typedef struct {
    ctrl_cfg_t ctrl;
    float i_max_A;              /* software overcurrent threshold on |ia|, |ib|, |ic| */
} app_cfg_t;

typedef struct {
    app_cfg_t cfg;
    app_state_t state;
    app_fault_t fault;
    hal_sample_t fault_snapshot;   /* samples of the period that faulted */
    ctrl_t ctrl;
    ctrl_out_t out;
    uint32_t ticks;                /* ISR calls since app_init */
    /* Requests: one word each, so that setting (background) and clearing
     * (ISR) are single stores and cannot lose one another. */
    volatile uint16_t req_start;
    volatile uint16_t req_stop;
    volatile uint16_t req_fault_reset;
} app_t;

/* Start-up: copy *cfg, init the controller, PWM off, state IDLE. */
void app_init(app_t *app, const app_cfg_t *cfg);

/* ISR context, once per period: hal_sample_read -> protection -> requests
 * -> ctrl_step -> hal_pwm_write / enable / disable -> hal_isr_ack. */
void app_isr(app_t *app);

/* Background loop: services the watchdog. */
void app_background(app_t *app);

/* Background: IDLE -> RUN at the next ISR (controller reset, PWM on). */
void app_request_start(app_t *app);

/* Background: -> IDLE at the next ISR, PWM off. */
void app_request_stop(app_t *app);

/* Background: clears a latched hardware trip; FAULT -> IDLE at the next
 * ISR when no trip is active and the currents are below the threshold. */
void app_fault_reset(app_t *app);

#endif /* APP_H */
