/*
 * commission.h - commissioning: measure the motor on a free shaft (the
 * COMMISSION state, app.h), without the controller's told R, L, psi_f:
 *   WIRING   first, before any current loop is closed: a voltage vector
 *            turned faster than the rotor follows, its amplitude
 *            regulated on |i| (no motor constant needed, blind to the
 *            phase order); enc_check.h (the module and fault set of
 *            build level 3) judges the current's sequence: PHASE_ORDER,
 *            or COMM_IMPLAUSIBLE for a current of both sequences (an
 *            open phase);
 *   R        DC injection on phase a (alpha) at two currents under an
 *            integral current regulator; R = dU/dI (the inverter's
 *            constant voltage error and the device drop cancel). The
 *            first current, ramped at +60 deg and turned onto phase a,
 *            pulls the rotor's d axis there;
 *   L        open-loop voltage steps of +-R^ dI_L on alpha at standstill
 *            (the d axis), L from the integrated voltage balance
 *            L di = (du - R^ di) dt by least squares;
 *   ENCODER  a current vector of fixed magnitude swept one mechanical
 *            turn (the told pole pairs' electrical turns) forward:
 *            enc_check.h judges the encoder's direction
 *            (ENCODER_DIRECTION), its counts per turn and the told pole
 *            pairs (POLE_PAIRS), too little travel is COMM_NO_ROTATION;
 *            then one electrical turn back; counts against the vector's
 *            angle over the last turn forward and the turn back by least
 *            squares: the offset (friction's lag cancels);
 *   SPIN     i_d = 0, i_q = +I from standstill to the top speed, then -I
 *            down: psi_f from (u_q - R^ i_q) against omega_el, J and B
 *            from the two accelerations;
 *   then the speed PI from J^ (comm_speed_pi).
 * Every stage has a timeout (COMM_TIMEOUT), checks its own plausibility
 * (COMM_IMPLAUSIBLE, COMM_NO_ROTATION); the fault's value and limit in the
 * app's snapshot, the stage in comm_t.stage. Per period only sums and a
 * few products; each stage's small solve (at most 3x3) runs once, in the
 * period its data is complete. Methods, derivations and error budget:
 * firmware/commission_design.md.
 */
#ifndef COMMISSION_H
#define COMMISSION_H

#include <stdbool.h>
#include <stdint.h>

#include "app_step.h"
#include "clarke_park.h"
#include "ctrl.h"
#include "enc_check.h"

typedef enum {
    COMM_STAGE_NONE = 0,
    COMM_STAGE_R = 1,
    COMM_STAGE_L = 2,
    COMM_STAGE_ENCODER = 3,
    COMM_STAGE_SPIN = 4,
    COMM_STAGE_DONE = 5,
    COMM_STAGE_WIRING = 6       /* the first stage (numbered last: the others kept theirs) */
} comm_stage_t;

typedef struct {
    float i_max_A;              /* every current stays within this: the rated current [A] */
    float speed_max_rad_s;      /* the spin stays below this: the rated speed, mechanical [rad/s] */
    uint16_t pole_pairs_max;    /* fewer counts than half an electrical turn at this many pole pairs: no rotation [-] */
    float u_frac;               /* |u| above this share of vdc/sqrt(3): implausible (WIRING, R, L, ENCODER), top speed (SPIN) [-] */
    /* R */
    float r_i1_frac, r_i2_frac; /* the two DC currents / i_max [-] */
    float r_prepos_el_rad;      /* the first current's pre-position from phase a: sin != 0 [rad el] */
    float r_ramp_s;             /* the first current's ramp from 0 at the pre-position, then its turn onto phase a [s] */
    float r_kp_frac;            /* virtual resistance / (vdc / i_max): bounds the current a swing induces [-] */
    float r_seek_s;             /* first regulator: a full i_max error ramps the voltage through vdc in this time [s] */
    float r_bw_rad_s;           /* integral regulator's bandwidth once R0 = U / I is known [rad/s] */
    float r_settle_s;           /* after each current change, with the rotor still [s] */
    float r_still_rad;          /* still: the shaft within this of where the settling began, mechanical [rad] */
    float r_window_s;           /* averaging window at each current [s] */
    float r_max_s;              /* stage timeout [s] */
    /* L */
    float l_step_frac;          /* current step / i_max (voltage step R^ x this) [-] */
    float l_rise_frac;          /* a step ends at this share of its final current change [-] */
    uint16_t l_cycles;          /* down-and-up steps [-] */
    float l_max_s;              /* stage timeout [s] */
    /* WIRING: the ENCODER stage's current and hold, the R stage's ramp, seek gain and window */
    float wiring_el_hz;         /* the vector's frequency: the rotor does not follow it [Hz el] */
    /* ENCODER and SPIN: dq current PI with Kp = w L^, Ki = w R^ */
    float i_bw_rad_s;           /* w [rad/s] */
    float enc_frac;             /* swept current / i_max [-] */
    float enc_speed_el_rad_s;   /* sweep speed [rad/s el] */
    float enc_hold_s;           /* hold before, between and after the sweeps [s] */
    float enc_max_s;            /* WIRING, ENCODER: timeout beyond the stage's planned length [s] */
    float spin_frac;            /* |i_q| / i_max while accelerating and braking [-] */
    float spin_top_frac;        /* top speed / speed_max [-] */
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
    float cpr_per_el;           /* counts per electrical turn, measured [counts] */
} comm_result_t;

/* Least-squares sums of y against up to two regressors (x1, x2) and a constant. */
typedef struct {
    float n, s1, s2, sy, s11, s12, s22, s1y, s2y;
} comm_ls_t;

typedef struct {
    comm_cfg_t cfg;
    float Ts_s;
    uint32_t enc_cpr;           /* encoder counts per mechanical turn [counts] */
    uint16_t pole_pairs;        /* the controller's, checked by ENCODER [-] */
    comm_stage_t stage;
    uint16_t phase;             /* step within the stage */
    uint32_t ticks;             /* periods in this phase */
    uint32_t stage_ticks;       /* periods in this stage */
    uint16_t cycles;            /* L: steps done */
    /* regulator */
    float u_a_V, u_b_V;         /* R, L: alpha-beta voltage (integral regulator's states) */
    float xd_V, xq_V;           /* ENCODER, SPIN: PI integral states, dq [V] */
    float ki_V_As;              /* R: alpha's integral gain [V/(A s)] */
    float ki0_V_As;             /* R: the seek's (beta's throughout) [V/(A s)] */
    float kp_V_A;               /* R, L: the virtual resistance of both axes (L: beta's) [V/A] */
    float out_a_V, out_b_V;     /* R, L: the alpha-beta voltage commanded [V] */
    float i_ref_A;
    float err_abs_A;            /* R seek: summed |error| over a block */
    /* windows and fits */
    float sum_u, sum_i, n_win;
    float U1_V, I1_A, U2_V, I2_A, R0_Ohm;
    float y_Vs;                 /* L: integrated voltage balance [V s] */
    float u_prev_V, u_prev2_V;  /* R, L: alpha voltage commanded one and two calls ago [V] */
    float di_prev_A;
    comm_ls_t ls;               /* L: y = L di + b t + c; ENCODER: counts = a + s theta */
    comm_ls_t ls2;              /* SPIN: accel fit omega = a t + c; psi fit */
    comm_ls_t ls3;              /* SPIN: decel fit */
    float iq_sum1, w_sum1, iq_sum2, w_sum2; /* SPIN: mean i_q and speed of each fit */
    float theta_c_rad;          /* ENCODER: the vector's angle (unwrapped) [rad el] */
    uint32_t count0;            /* ENCODER: count at the sweep's start */
    uint32_t count_last;
    float dcount;               /* unwrapped counts since count0 */
    float top_rad_s;            /* SPIN: top speed reached */
    float w_ref_rad_s;          /* SPIN: speed at the fits' start (centring) */
    float y_ref_V;
    /* WIRING */
    float w_u_V;                /* the vector's amplitude [V] */
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
