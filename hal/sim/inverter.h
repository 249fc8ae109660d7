/*
 * inverter.h - the simulated two-level voltage-source inverter: turns one
 * period's three duties into stator voltages and integrates the plant over
 * that period. Host-only, double precision.
 *
 * Centre-aligned up-down PWM, period Ts starting at counter zero: phase x
 * is high (upper switch on) from (1 - d) Ts/2 to (1 + d) Ts/2. With dead
 * time td the upper switch turns on td late and the lower switch turns on
 * td after the upper one turns off; while both are off the freewheeling
 * diode sets the leg: low for a current into the motor (i > 0), high for
 * i < 0. Zero-current clamping inside the dead band is not modelled.
 *
 * On-state drop: the conducting device of a leg (upper switch or lower
 * diode for i > 0, lower switch or upper diode for i < 0, in the dead band
 * too) drops device_drop_V, switch and diode alike, so the leg voltage is
 * lowered by device_drop_V * sign(i) in every state (0 at i = 0 exactly).
 * Over a period this is a per-phase error of the dead time's shape: both
 * give a fundamental (4/pi) dV along -i in the rotor frame.
 *
 * Models:
 *   INV_AVERAGED  the period-average phase voltages (including the average
 *                 dead-time error, current sign at the period start) held
 *                 over the whole period.
 *   INV_SWITCHING the leg states between switching instants, piecewise
 *                 constant: each switching leg a pulse centred in the
 *                 period, which the plant superposes (plant.h); with dead
 *                 time or drop the current's sign at each piece's start
 *                 decides (the plant's walker, plant_design.md sec. 6).
 * The zero-sequence voltage does not drive a current (isolated star), so
 * only the alpha-beta part of the phase voltages reaches the plant.
 */
#ifndef INVERTER_H
#define INVERTER_H

#include <stdbool.h>

#include "plant.h"

typedef enum { INV_AVERAGED = 0, INV_SWITCHING = 1 } inv_model_t;

typedef struct {
    inv_model_t model;
    double vdc_V;           /* ideal DC bus */
    double Ts_s;            /* PWM period */
    double deadtime_s;      /* 0: ideal switches */
    double device_drop_V;   /* on-state drop of the conducting switch or diode [V]; 0: ideal */
    double substep_max_s;   /* longest time the plant solves at once (< Ts: equal sub-periods) */
} inv_cfg_t;

/* Leg state over a piece of the period. */
typedef enum { LEG_LOW = 0, LEG_HIGH = 1, LEG_DEAD = 2 } leg_state_t;

/* State of a leg with duty d at time t_s in [0, Ts) of the period (before the diode decides LEG_DEAD). */
leg_state_t inv_leg_state(const inv_cfg_t *cfg, double duty, double t_s);

/* Switching instants of a leg with duty d inside (0, Ts): writes up to 4 into t_s[], returns the count. */
int inv_leg_edges(const inv_cfg_t *cfg, double duty, double t_s[4]);

/* Integrate *plant over one period with duties duty[3] (clamped to [0, 1]) and load TL_Nm. */
void inv_period(const inv_cfg_t *cfg, const double duty[3], double TL_Nm, plant_t *plant);

#endif /* INVERTER_H */
