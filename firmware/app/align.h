/*
 * align.h - two-step rotor alignment (the ALIGN state, app.h): the d axis
 * onto phase a, so that encoder_align() can make that count read 0 rad.
 * Stationary voltage vectors, open loop:
 *   1. the vector at prepos_el_rad (90 deg: u_beta), ramped from 0 to u_V
 *      over ramp_s, held prepos_s;
 *   2. turned onto phase a over ramp_s (cross-fade: (1 - f) x step 1's
 *      vector + f x u_V on alpha, f = 0..1), held settle_s and one more
 *      period, the aligning one.
 * No start angle is a dead point of both steps; the derivation and why
 * open-loop voltage is exact in the final hold are in
 * firmware/app/startup_design.md ("Alignment").
 */
#ifndef ALIGN_H
#define ALIGN_H

#include <stdint.h>

#include "app_step.h"
#include "clarke_park.h"

typedef struct {
    float u_V;                  /* magnitude of both vectors [V] */
    float prepos_el_rad;        /* step 1's vector from phase a: sin != 0 [rad el] */
    float ramp_s;               /* ramp from 0 at the pre-position, and the turn onto phase a [s] */
    float prepos_s;             /* hold at the pre-position after its ramp [s] */
    float settle_s;             /* hold on phase a after the turn [s] */
} align_cfg_t;

typedef struct {
    align_cfg_t cfg;
    uint32_t ramp_ticks, prepos_ticks, settle_ticks;  /* the times in periods */
    float prepos_cos, prepos_sin;                     /* of prepos_el_rad */
    uint32_t ticks;             /* periods since align_start */
} align_t;

/* Start-up: copy *cfg, derive the periods at Ts_s [s]. */
void align_init(align_t *a, const align_cfg_t *cfg, float Ts_s);

/* ISR, on entering ALIGN. */
void align_start(align_t *a);

/* ISR, once per period: the stationary-frame voltage to apply over the
 * coming period into *u_ab_V [V]; DONE in the aligning period (its vector
 * is still applied; the rotor's d axis is on phase a), else RUNNING. */
app_step_t align_step(align_t *a, ab_t *u_ab_V);

#endif /* ALIGN_H */
