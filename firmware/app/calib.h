/*
 * calib.h - current-offset calibration (the CALIBRATE state, app.h), PWM
 * off: wait settle_s (a current decays through the diodes), average
 * samples periods of ia and ib; the means are the offsets when both lie
 * within +/- offset_max_A, else CURRENT_OFFSET with the mean and the
 * limit. Runs at every start: sensor offsets drift with temperature.
 */
#ifndef CALIB_H
#define CALIB_H

#include <stdint.h>

#include "app_step.h"

typedef struct {
    float settle_s;             /* PWM off this long before averaging [s] */
    uint32_t samples;           /* periods averaged (0 is taken as 1) [-] */
    float offset_max_A;         /* accepted |offset| of ia and ib [A] */
} calib_cfg_t;

typedef struct {
    calib_cfg_t cfg;
    uint32_t settle_ticks;      /* settle_s in periods */
    uint32_t ticks;             /* periods since calib_start */
    float sum_ia_A, sum_ib_A;   /* sums so far [A] */
    float offset_ia_A, offset_ib_A;  /* the accepted means, valid after DONE [A] */
} calib_t;

/* Start-up: copy *cfg, derive the periods at Ts_s [s]. */
void calib_init(calib_t *c, const calib_cfg_t *cfg, float Ts_s);

/* ISR, on entering CALIBRATE: sums cleared. */
void calib_start(calib_t *c);

/* ISR, once per period with PWM off: the raw samples ia, ib [A]. DONE in
 * the last averaged period (offsets in c->offset_*), or CURRENT_OFFSET. */
app_step_t calib_step(calib_t *c, float ia_A, float ib_A);

#endif /* CALIB_H */
