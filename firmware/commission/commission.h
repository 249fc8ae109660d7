/*
 * commission.h - commissioning: measure the motor and the inverter on a
 * free shaft (the COMMISSION state, app.h), without the controller's told
 * R, L, psi_f. The sequence, its timing and its refusals live here; the
 * motor math (regulators on pi.h, fits, solves) is control/ident.h's.
 *   WIRING   first, before any current loop is closed: a voltage vector
 *            turned faster than the rotor follows, its amplitude
 *            regulated on |i| (no motor constant needed, blind to the
 *            phase order); enc_check.h (the module and fault set of
 *            build level 3) judges the current's sequence: PHASE_ORDER,
 *            or COMM_IMPLAUSIBLE for a current of both sequences (an
 *            open phase);
 *   R        DC injection on phase a (alpha) at two currents under a
 *            DC-current regulator; R = dU/dI (the inverter's constant
 *            voltage error and the device drop cancel). The first
 *            current, ramped at +60 deg and turned onto phase a, pulls
 *            the rotor's d axis there;
 *   L        open-loop voltage steps of +-R^ dI_L on alpha at standstill
 *            (the d axis), L from the integrated voltage balance
 *            L di = (du - R^ di) dt by least squares;
 *   INVERTER the current vector turned half an electrical turn (the rotor
 *            follows), the R stage's two currents again with every phase
 *            current reversed: the inverter's per-leg voltage error
 *            against the current, both polarities (U - R^ I), split into
 *            the board's told dead time and a device drop; the ENCODER
 *            stage starts from there;
 *   ENCODER  a current vector of fixed magnitude swept one mechanical
 *            turn (the told pole pairs' electrical turns) forward:
 *            enc_check.h judges the encoder's direction
 *            (ENCODER_DIRECTION), its counts per turn and the told pole
 *            pairs (POLE_PAIRS), too little travel is COMM_NO_ROTATION;
 *            then one electrical turn back; counts against the vector's
 *            angle over the last turn forward and the turn back by least
 *            squares: the offset (friction's lag cancels);
 *   SPIN     i_d = 0, i_q = +I from standstill to the top speed, -I down
 *            to the top speed backwards, +I back to standstill: psi_f
 *            from (u_q - R^ i_q) against omega_el over the three sweeps
 *            (the inverter's error, odd in i_q and even in the speed,
 *            cancels), J and B from the accelerations forwards;
 *   then the speed PI from J^ (comm_speed_pi).
 * Every stage has a timeout (COMM_TIMEOUT), checks its own plausibility
 * (COMM_IMPLAUSIBLE, COMM_NO_ROTATION); the fault's value and limit in the
 * app's snapshot, the stage in comm_t.stage. Per period only sums and a
 * few products; each stage's small solve (at most 3x3) runs once, in the
 * period its data is complete. Methods, derivations and error budget:
 * firmware/commission/commission_design.md.
 */
#ifndef COMMISSION_H
#define COMMISSION_H

#include <stdbool.h>
#include <stdint.h>

#include "app_step.h"
#include "clarke_park.h"
#include "ctrl.h"
#include "enc_check.h"
#include "ident.h"

typedef enum {
    COMM_STAGE_NONE = 0,
    COMM_STAGE_R = 1,
    COMM_STAGE_L = 2,
    COMM_STAGE_ENCODER = 3,
    COMM_STAGE_SPIN = 4,
    COMM_STAGE_DONE = 5,
    COMM_STAGE_WIRING = 6,      /* the first stage (numbered last: the others kept theirs) */
    COMM_STAGE_INVERTER = 7     /* after L, before ENCODER */
} comm_stage_t;
#define COMM_STAGE_LAST COMM_STAGE_INVERTER   /* the highest stage's value */

typedef struct {
    float i_max_A;              /* every current stays within this: the rated current [A] */
    float speed_max_rad_s;      /* the spin stays below this: the rated speed, mechanical [rad/s] */
    uint16_t pole_pairs_max;    /* fewer counts than half an electrical turn at this many pole pairs: no rotation [-] */
    float u_frac;               /* |u| above this share of vdc/sqrt(3): implausible (WIRING, R, L, INVERTER,
                                 * ENCODER), top speed (SPIN) [-] */
    float deadtime_s;           /* the board's dead time the controller is told: INVERTER keeps it in the split [s] */
    /* R */
    float r_i1_frac, r_i2_frac; /* the two DC currents / i_max [-] */
    float r_prepos_el_rad;      /* the first current's pre-position from phase a: sin != 0 [rad el] */
    float r_ramp_s;             /* the first current's ramp from 0 at the pre-position, then its turn onto phase a [s] */
    float r_kp_frac;            /* virtual resistance / (vdc / i_max): bounds the current a swing induces [-] */
    float r_seek_s;             /* first regulator: a full i_max error ramps the voltage through vdc in this time [s] */
    float r_bw_rad_s;           /* integral regulator's bandwidth once R0 = U / I is known [rad/s] */
    float r_settle_s;           /* after each current change, with the rotor still (INVERTER too) [s] */
    float r_still_rad;          /* still: the shaft within this of where the settling began, mechanical [rad] */
    float r_window_s;           /* averaging window at each current (INVERTER too) [s] */
    float r_max_s;              /* stage timeout [s] */
    /* L */
    float l_step_frac;          /* current step / i_max (voltage step R^ x this) [-] */
    float l_rise_frac;          /* a step ends at this share of its final current change [-] */
    uint16_t l_cycles;          /* down-and-up steps [-] */
    float l_max_s;              /* stage timeout [s] */
    /* WIRING: the ENCODER stage's current and hold, the R stage's ramp, seek gain and window */
    float wiring_el_hz;         /* the vector's frequency: the rotor does not follow it [Hz el] */
    /* INVERTER, ENCODER and SPIN: dq current PI with Kp = w L^, Ki = w R^ (ident_cur_init) */
    float i_bw_rad_s;           /* w [rad/s] */
    float enc_frac;             /* swept current / i_max [-] */
    float enc_speed_el_rad_s;   /* sweep speed (INVERTER's half turns too) [rad/s el] */
    float enc_hold_s;           /* hold before, between and after the sweeps [s] */
    float enc_max_s;            /* WIRING, INVERTER, ENCODER: timeout beyond the stage's planned length [s] */
    float spin_frac;            /* |i_q| / i_max while accelerating and braking [-] */
    float spin_top_frac;        /* the spin's highest speed / speed_max: a bound, the braking begins where
                                 * the speed would reach it in speed_lag_s + 1/i_bw_rad_s + two periods [-] */
    float speed_lag_s;          /* the speed estimate's lag behind a constant acceleration [s] (encoder_ramp_lag_s) */
    float spin_lo_frac;         /* fits use speeds above this share of the top [-] */
    float spin_skip_s;          /* fits skip this after each current change: the speed estimate's lag settles [s] */
    float spin_max_s;           /* stage timeout [s] */
    /* speed PI from J^: kp = kp_per_J J^, ki = ki_per_J J^ (comm_speed_pi; the
     * parameter set's rule at its crossover, drive_speed_pi with J = 1) */
    float speed_kp_per_J_1_s;   /* [N m s/rad per kg m^2 = 1/s] */
    float speed_ki_per_J_1_s2;  /* [N m/rad per kg m^2 = 1/s^2] */
} comm_cfg_t;

/* A commissioning's outcome as the operator sees it (app_comm_result). */
typedef enum {
    COMM_NONE = 0,              /* none since power-on (or since the refusal's fault was reset) */
    COMM_RUNNING = 1,           /* in COMMISSION: comm_t.stage says which stage */
    COMM_DONE = 2,              /* measured: comm_t.res valid */
    COMM_REFUSED = 3            /* in FAULT, latched in COMMISSION: the fault and comm_t.stage say why */
} comm_outcome_t;

typedef struct {                /* what the commissioning measured */
    float R_Ohm, L_H, psi_f_Wb;
    uint16_t pole_pairs;
    float J_kgm2, B_Nms;
    float enc_offset_el_rad;    /* electrical angle at count 0, encoder.h's convention, [0, 2 pi) */
    float speed_kp_Nms_rad, speed_ki_Nm_rad;
    float u_err_V;              /* the constant voltage error (dead time, device drop) the R stage cancelled [V] */
    float inv_dv_V;             /* INVERTER: each leg's voltage error against its current, measured [V] */
    float deadtime_s;           /* ... as the controller is to compensate it: the told dead time [s] */
    float device_drop_V;        /* ... and the rest as an on-state drop [V] */
    float untold_deadtime_s;    /* what the measurement leaves uncertain, as a dead time [s] */
    float cpr_per_el;           /* counts per electrical turn, measured [counts] */
} comm_result_t;

typedef struct {
    comm_cfg_t cfg;
    float Ts_s;
    uint32_t enc_cpr;           /* encoder counts per mechanical turn [counts] */
    uint16_t pole_pairs;        /* the controller's, checked by ENCODER [-] */
    comm_stage_t stage;
    uint16_t phase;             /* step within the stage */
    uint32_t ticks;             /* periods of this phase before this call */
    uint32_t stage_ticks;       /* periods of this stage before this call */
    bool phase_new, stage_new;  /* the phase, the stage began in this call: its first is the next */
    uint16_t cycles;            /* L: steps done */
    bool in_window;             /* R, INVERTER: settled, the window running */
    /* regulators (ident.h, on pi.h) */
    pi_t wiring;                /* WIRING: the vector's amplitude on |i| [V] */
    ident_dc_t dc;              /* R, L: the alpha-beta DC-current regulator */
    ident_cur_t cur;            /* INVERTER, ENCODER, SPIN: the dq current PI */
    float u_a_V;                /* L: alpha's open-loop voltage [V] */
    float u_prev_V, u_prev2_V;  /* alpha voltage commanded one and two calls ago [V] */
    float i_ref_A;              /* R, INVERTER: the DC current's magnitude [A] */
    float err_abs_A;            /* R seek: summed |error| over a block */
    float u_lim_V;              /* the stage's plausibility bound u_frac vdc / sqrt 3, at its start [V] */
    /* windows and fits */
    ident_win_t win;
    ident_point_t pos[2];       /* R: alpha's points at +I1, +I2 */
    ident_point_t neg[2];       /* INVERTER: at -I2, -I1 */
    ident_l_t l;                /* L */
    ident_ls_t ls;              /* ENCODER: counts = a + s theta */
    ident_spin_t spin;          /* SPIN */
    float sweep_n;              /* SPIN: the sweep's fitted periods [-] */
    float sweep_t0_s, sweep_w0_rad_s; /* ... its first fitted period's time and speed [s, rad/s] */
    float theta_c_rad;          /* INVERTER, ENCODER: the vector's angle (unwrapped) [rad el] */
    float theta0_rad;           /* ENCODER: the vector's angle the sweeps start from (INVERTER's end) [rad el] */
    uint32_t count0;            /* ENCODER: count at the sweep's start */
    uint32_t count_last;        /* ENCODER: the last period's count */
    uint32_t still_count;       /* R, INVERTER, ENCODER: where the rotor was last seen to move [counts] */
    float dcount;               /* unwrapped counts since count0 */
    /* WIRING */
    float w_angle_el_rad;       /* the vector's angle [rad el, wrapped] */
    uint32_t w_turn_ticks;      /* periods per turn of the vector [-] */
    uint32_t w_turns;           /* turns measured [-] */
    float w_dangle_el_rad;      /* its step per period: whole turns in whole periods [rad el] */
    enc_check_t chk;
    enc_check_out_t chk_out;    /* what the check measured */
    comm_result_t res;
} comm_t;

/* Start-up: copy *cfg; the period Ts_s [s], the encoder's counts per
 * turn enc_cpr and the pole pairs are the controller's (app_init). */
void comm_init(comm_t *m, const comm_cfg_t *cfg, float Ts_s, uint32_t enc_cpr, uint16_t pole_pairs);

/* ISR, on entering COMMISSION (PWM about to go on, rotor at rest). */
void comm_start(comm_t *m);

/* ISR, once per period, on the period's samples *in (currents offset-
 * corrected) and the encoder PLL's mechanical speed speed_m_rad_s
 * [rad/s]: the stationary-frame voltage to apply over the coming period
 * into *u_ab_V [V]; DONE in the period the last stage's results are in
 * m->res (the sequence then turns the gates off), FAULT (COMM_*) with the
 * measured value and its limit, else RUNNING. */
app_step_t comm_step(comm_t *m, const ctrl_in_t *in, float speed_m_rad_s, ab_t *u_ab_V);

/* The longest a commissioning can last [s]: every stage's timeout. Any context. */
float comm_max_s(const comm_t *m);

/* The speed PI's gains from an inertia [kg m^2]: the parameter set's
 * rule (drive_speed_pi, linear in J) through cfg's gains per kg m^2. Any context. */
void comm_speed_pi(const comm_cfg_t *cfg, float J_kgm2, float *kp_Nms_rad, float *ki_Nm_rad);

#endif /* COMMISSION_H */
