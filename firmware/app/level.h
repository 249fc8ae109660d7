/*
 * level.h - the build levels of the first power-up (app.h, as TI's motor
 * kits stage it), and level 3's open-loop rotation.
 *
 *   1 PWM_CHECK  fixed duties, one per phase (pwm_duty): on a scope each
 *                leg's duty and both dead-time edges; no DC bus needed
 *                (undervoltage off at levels 1-2, every other check live)
 *   2 ADC_CHECK  PWM off: the current offsets measured (CALIBRATE, always
 *                at this level), then the ADC's readings and the offsets
 *                reported every period (app_t.adc, the command block)
 *   3 ENC_CHECK  a voltage vector turning at speed_m_rad_s drags the rotor
 *                round; enc_check.h judges the encoder's direction, counts
 *                per turn, the pole pairs and the phase order against the
 *                commanded angle; then IDLE, or the fault
 *   4            torque control (torque mode, the conventional method, no
 *                step 1) with the current limit i_lim_4_A
 *   5            the full drive
 * Levels 1-3 ignore the operator's mode and method; level 4 holds its own
 * until a start at another level.
 *
 * Levels 1-2 are meant for a board without its DC bus: with the bus above
 * vdc_max_12_V (a safe extra-low voltage) a start at either latches the
 * fault BUS_CHARGED before any gate switches, and so does a bus that rises
 * above it while PWM_CHECK or ADC_CHECK runs (PWM off). Level 1's fixed
 * duties on a charged bus and a connected motor put about half the bus
 * across two windings, limited only by the overcurrent trip.
 *
 * Level 3's rotation: the vector's amplitude ramps up at angle 0 over
 * ramp_s, then the vector turns at w = p speed_m_rad_s (p the controller's
 * pole pairs); one electrical turn lets the rotor fall in, then the check
 * runs over p electrical turns (one mechanical turn if p is right). The
 * amplitude is what drives i_A through the unloaded motor following the
 * vector at w (steady state, the current on the rotor's d axis):
 *   u = sqrt((R i)^2 + (w (L i + psi_f))^2)
 * from the controller's R, L, psi_f: a current limit, not a torque one.
 */
#ifndef LEVEL_H
#define LEVEL_H

#include <stdint.h>

#include "app_step.h"
#include "clarke_park.h"
#include "ctrl.h"
#include "enc_check.h"

#define LEVEL_MIN 1u
#define LEVEL_MAX 5u
#define LEVEL_PWM 1u
#define LEVEL_ADC 2u
#define LEVEL_ROTATE 3u
#define LEVEL_TORQUE 4u
#define LEVEL_FULL 5u

typedef struct {
    uint16_t level;             /* at power-on (LEVEL_MIN .. LEVEL_MAX) */
    float vdc_max_12_V;         /* levels 1-2: BUS_CHARGED above this bus [V] */
    float pwm_duty[3];          /* level 1's duties of legs a, b, c [0..1] */
    float i_lim_4_A;            /* level 4's current limit [A] */
    float speed_m_rad_s;        /* level 3's commanded speed [rad/s mech] */
    float i_A;                  /* level 3's current [A] */
    float ramp_s;               /* level 3's amplitude ramp at angle 0 [s] */
} level_cfg_t;

typedef enum { ROT_RAMP = 0, ROT_SETTLE = 1, ROT_MEASURE = 2 } level_rot_phase_t;

/* Level 3's rotation and its check. */
typedef struct {
    float u_V;                  /* the vector's amplitude (above) [V] */
    float dangle_el_rad;        /* its step per period [rad el] */
    float du_V;                 /* the ramp's step per period [V] */
    uint32_t turn_ticks;        /* periods of one electrical turn */
    uint16_t pole_pairs;        /* the controller's */
    level_rot_phase_t phase;
    uint32_t ticks;             /* periods in this phase */
    float u_now_V;              /* the amplitude now [V] */
    float angle_el_rad;         /* the vector's angle, [0, 2 pi) [rad el] */
    enc_check_t chk;
    enc_check_out_t out;        /* the last check's figures */
} level_rot_t;

/* Start-up: the rotation's figures from *cfg, the controller's *c and Ts_s [s]. */
void level_rot_init(level_rot_t *r, const level_cfg_t *cfg, const ctrl_cfg_t *c, float Ts_s);

/* ISR, entering ENC_CHECK: amplitude 0 at angle 0. */
void level_rot_start(level_rot_t *r);

/* ISR, once per ENC_CHECK period: the vector for this period into *u_ab_V
 * [V], the check fed with the currents i_alpha_A, i_beta_A [A] (offsets
 * removed) and the count; DONE or enc_check's fault after the measurement. */
app_step_t level_rot_step(level_rot_t *r, float i_alpha_A, float i_beta_A, uint32_t enc_count, ab_t *u_ab_V);

#endif /* LEVEL_H */
