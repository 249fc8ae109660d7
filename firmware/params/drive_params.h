/*
 * drive_params.h - the drive's one parameter set: the motor, its
 * ratings, the board, the limits, the controller's tuning and step 1's
 * speeds and timing, in SI units; the values derived from it
 * (params_design.md), the controller's configuration among them. Below
 * the application: the app maps the set into its configuration
 * (drive_params_to_app_cfg, app.h).
 *
 * The target fills it from the board header (drive_params_board(),
 * firmware/params/board_cfg.h) and maps it in app_cfg_default(); the SIL takes the
 * same defaults (tools/sil/scenario_keys.h: the keys whose default is
 * SC_PARAMS, printed by drive_sil --help), puts the scenario's keys on top and maps it with the
 * same drive_params_to_app_cfg(). The start-up sequence's other settings
 * (calibration, the alignment's timing, step 1's windows, the watch
 * checks) are the app's own (app_cfg_default).
 */
#ifndef DRIVE_PARAMS_H
#define DRIVE_PARAMS_H

#include <stdbool.h>
#include <stdint.h>

#include "ctrl.h"

/* A value marked "derived" that is negative (DRIVE_PARAM_DERIVED) or NaN
 * is derived by drive_params_derive() (firmware/params/params_design.md) from
 * what the controller is told: the motor, its ratings, the board; one
 * >= 0 is the user's and stays. */
#define DRIVE_PARAM_DERIVED (-1.0f)

/* The parameter set, one list per group, one line per value:
 *   X(group, field, type, default, to)
 * type    float | uint16_t | uint32_t
 * default its board value (firmware/params/board_cfg.h, expanded in
 *         drive_params_board() only) or DRIVE_PARAM_DERIVED
 * to      DRIVE_TO(path): drive_params_to_app_cfg() (app.h) copies the
 *         value to app_cfg_t's path; DRIVE_TO_NONE: formulas use it
 * The lists generate drive_params_t's fields, drive_params_board() and the
 * copies in drive_params_to_app_cfg(); the SIL's keys name the fields
 * (tools/sil/scenario_keys.h). Adding a parameter: params_design.md sec. 8. */
#define DRIVE_PARAMS_motor(X)  /* the controller's model of the motor */ \
    X(motor, R_Ohm, float, MOTOR_R_OHM, DRIVE_TO(ctrl.R_Ohm))             /* stator phase resistance [Ohm] */ \
    X(motor, L_H, float, MOTOR_L_H, DRIVE_TO(ctrl.L_H))                   /* Ld = Lq [H] */ \
    X(motor, psi_f_Wb, float, MOTOR_PSI_F_WB, DRIVE_TO(ctrl.psi_f_Wb))    /* PM flux linkage [Wb] */ \
    X(motor, pole_pairs, uint16_t, MOTOR_POLE_PAIRS, DRIVE_TO(ctrl.pole_pairs)) /* [-] */ \
    X(motor, J_kgm2, float, MOTOR_J_KGM2, DRIVE_TO_NONE)                  /* rotor and load inertia [kg m^2] */ \
    X(motor, B_Nms, float, MOTOR_B_NMS, DRIVE_TO_NONE)                    /* viscous friction [N m s/rad] */

#define DRIVE_PARAMS_rating(X) \
    X(rating, i_rated_A, float, MOTOR_I_RATED_A, DRIVE_TO(i2t_rated_A))   /* continuous current (peak of the phase current) [A] */ \
    X(rating, i_peak_A, float, MOTOR_I_PEAK_A, DRIVE_TO_NONE)             /* short-time current [A] */ \
    X(rating, t_peak_s, float, MOTOR_T_PEAK_S, DRIVE_TO_NONE)             /* how long i_peak may last [s] */ \
    X(rating, n_rated_rad_s, float, MOTOR_RATED_SPEED_RPM * MATHX_RAD_S_PER_RPM_F, \
      DRIVE_TO(comm.speed_max_rad_s))                                     /* rated speed, mechanical [rad/s] */ \
    X(rating, n_max_rad_s, float, MOTOR_MAX_SPEED_RPM * MATHX_RAD_S_PER_RPM_F, \
      DRIVE_TO_NONE)                                                      /* highest speed, mechanical [rad/s] */

#define DRIVE_PARAMS_board(X) \
    X(board, Ts_s, float, 1.0f / (float)BOARD_PWM_FREQ_HZ, DRIVE_TO(ctrl.Ts_s)) /* control = PWM period [s] */ \
    X(board, deadtime_s, float, (float)BOARD_DEADTIME_NS * DRIVE_S_PER_NS, \
      DRIVE_TO(ctrl.deadtime_s))                                          /* gate-driver dead time the controller compensates [s] */ \
    X(board, device_drop_V, float, BOARD_DEVICE_DROP_V, \
      DRIVE_TO(ctrl.device_drop_V))                                       /* on-state drop of a leg's conducting device the controller compensates [V] */ \
    X(board, vdc_nominal_V, float, BOARD_VDC_NOMINAL_V, DRIVE_TO_NONE)    /* nominal DC bus [V] */ \
    X(board, u_bound_V, float, BOARD_VDC_MAX_V, DRIVE_TO(ctrl.u_max_V))   /* bound on |ud|, |uq| the controller's model uses [V] */ \
    X(board, i_full_scale_A, float, BOARD_I_FULL_SCALE_A, DRIVE_TO_NONE)  /* current ADC range, +- [A] */ \
    X(board, enc_lines, uint32_t, BOARD_ENC_LINES, DRIVE_TO(ctrl.enc_lines)) /* encoder lines; x4 counts [-] */ \
    X(board, enc_offset_el_rad, float, BOARD_ENC_OFFSET_EL_RAD, \
      DRIVE_TO(ctrl.enc_offset_el_rad))                                   /* electrical angle at count 0, as measured [rad el] */ \
    X(board, isr_period_cycles, uint32_t, BOARD_ISR_PERIOD_CYCLES, \
      DRIVE_TO(prot.isr_period_cycles))                                   /* control period in hal_cycles() counts [cycles] */ \
    X(board, isr_budget_cycles, uint32_t, BOARD_ISR_BUDGET_CYCLES, \
      DRIVE_TO(prot.isr_budget_cycles))                                   /* longest allowed ISR run [cycles] */

#define DRIVE_PARAMS_limits(X) \
    X(limits, i_trip_A, float, DRIVE_PARAM_DERIVED, DRIVE_TO(prot.i_max_A)) /* software overcurrent trip on |ia|, |ib|, |ic| [A] */ \
    X(limits, i_limit_A, float, DRIVE_PARAM_DERIVED, DRIVE_TO(ctrl.i_lim_A)) /* stator-current limit the deadbeat targets respect [A] */ \
    X(limits, vdc_max_V, float, BOARD_VDC_MAX_V, DRIVE_TO(prot.vdc_max_V)) /* overvoltage trip [V] */ \
    X(limits, vdc_min_V, float, BOARD_VDC_MIN_V, DRIVE_TO(prot.vdc_min_V)) /* undervoltage trip [V] */ \
    X(limits, speed_max_rad_s, float, DRIVE_PARAM_DERIVED, \
      DRIVE_TO(prot.speed_max_rad_s))                                     /* overspeed trip, mechanical [rad/s] */ \
    X(limits, te_max_Nm, float, DRIVE_PARAM_DERIVED, DRIVE_TO(ctrl.te_max_Nm)) /* torque reference limit [N m] */

#define DRIVE_PARAMS_tuning(X) \
    X(tuning, speed_bw_rad_s, float, TUNE_SPEED_BW_RAD_S, DRIVE_TO_NONE)  /* speed-loop crossover w_c [rad/s] */ \
    X(tuning, speed_kp_Nms_rad, float, DRIVE_PARAM_DERIVED, \
      DRIVE_TO(ctrl.speed_kp_Nms_rad))                                    /* speed PI [N m / (rad/s)] */ \
    X(tuning, speed_ki_Nm_rad, float, DRIVE_PARAM_DERIVED, \
      DRIVE_TO(ctrl.speed_ki_Nm_rad))                                     /* speed PI [N m / rad] */ \
    X(tuning, pll_bw_rad_s, float, TUNE_ENC_PLL_BW_RAD_S, \
      DRIVE_TO(ctrl.enc_pll_bw_rad_s))                                    /* encoder speed-estimator bandwidth [rad/s] */ \
    X(tuning, u_margin, float, TUNE_U_MARGIN, DRIVE_TO(ctrl.u_margin))    /* steady-state share of Vdc/sqrt(3) for flux weakening [-] */ \
    X(tuning, R_min_Ohm, float, DRIVE_DEFAULT_BAND, DRIVE_TO_NONE)        /* accepted R^ band [Ohm]; < 0: est_rsid_band()'s */ \
    X(tuning, R_max_Ohm, float, DRIVE_DEFAULT_BAND, DRIVE_TO_NONE)        /*   <= 0: est_rsid_band()'s */

#define DRIVE_PARAMS_step1(X)  /* step 1 (rsid_seq.h); all derived */ \
    X(step1, settle_1_s, float, DRIVE_PARAM_DERIVED, DRIVE_TO(rsid.settle_1_s)) /* IDENTIFY_R entry (speeds: ramp end) to window 1 [s] */ \
    X(step1, settle_2_s, float, DRIVE_PARAM_DERIVED, DRIVE_TO(rsid.settle_2_s)) /* window 1 to window 2 [s] */ \
    X(step1, speed_1_rad_s, float, DRIVE_PARAM_DERIVED, \
      DRIVE_TO(rsid.speed_1_rad_s))                                       /* speeds mode: the two points, mechanical [rad/s] */ \
    X(step1, speed_2_rad_s, float, DRIVE_PARAM_DERIVED, DRIVE_TO(rsid.speed_2_rad_s)) \
    X(step1, accel_rad_s2, float, DRIVE_PARAM_DERIVED, \
      DRIVE_TO(rsid.accel_rad_s2))                                        /* speeds mode: ramp of the commanded speed [rad/s^2] */

/* All the groups, in drive_params_t's order. */
#define DRIVE_PARAMS(X) \
    DRIVE_PARAMS_motor(X) DRIVE_PARAMS_rating(X) DRIVE_PARAMS_board(X) \
    DRIVE_PARAMS_limits(X) DRIVE_PARAMS_tuning(X) DRIVE_PARAMS_step1(X)

#define DRIVE_PARAM_FIELD(group, field, type, dflt, to) type field;

typedef struct { DRIVE_PARAMS_motor(DRIVE_PARAM_FIELD) } drive_motor_t;
typedef struct { DRIVE_PARAMS_rating(DRIVE_PARAM_FIELD) } drive_rating_t;
typedef struct { DRIVE_PARAMS_board(DRIVE_PARAM_FIELD) } drive_board_t;
typedef struct { DRIVE_PARAMS_limits(DRIVE_PARAM_FIELD) } drive_limits_t;
typedef struct { DRIVE_PARAMS_tuning(DRIVE_PARAM_FIELD) } drive_tuning_t;
typedef struct { DRIVE_PARAMS_step1(DRIVE_PARAM_FIELD) } drive_step1_t;

typedef struct {
    drive_motor_t motor;
    drive_rating_t rating;
    drive_board_t board;
    drive_limits_t limits;
    drive_tuning_t tuning;
    drive_step1_t step1;
    uint16_t derived;           /* DRIVE_DERIVED_*: values drive_params_derive() derived rather than
                                 * took from the user, kept when the set is derived in place */
} drive_params_t;

/* drive_params_t.derived */
#define DRIVE_DERIVED_TE_MAX 0x0001u /* te_max_Nm, the told kt at i_peak: it follows the learned psi_f */

/* r/min per rad/s, for the SIL's derived keys in r/min (tools/sil/scenario_keys.h:
 * each derived key names its field here and the keys it comes from). */
#define DRIVE_RPM_PER_RAD_S 9.54929658551372

/* What drive_params_derive() refused or warns of (a set of bits). */
typedef uint16_t drive_derive_t;
#define DRIVE_DERIVE_OK          ((drive_derive_t)0x0000u)
#define DRIVE_DERIVE_RATINGS     ((drive_derive_t)0x0001u) /* ratings not positive, i_peak < i_rated or n_max < n_rated */
#define DRIVE_DERIVE_ADC_RANGE   ((drive_derive_t)0x0002u) /* the current limit plus drive_trip_margin_A() above the trip (the ADC's readable range) */
#define DRIVE_DERIVE_OBSERVER    ((drive_derive_t)0x0004u) /* no observer gain: the told L/R below SMO_LR_MIN_PERIODS periods (the proposed method) */
#define DRIVE_DERIVE_I_LIMIT     ((drive_derive_t)0x0008u) /* a set current limit above the peak rating i_peak */
#define DRIVE_DERIVE_WARN_BEMF   ((drive_derive_t)0x0100u) /* warning: back-EMF at n_max beyond the bus's phase-voltage limit */
#define DRIVE_DERIVE_REFUSED     ((drive_derive_t)0x00FFu) /* the refusals among the bits */

/* The largest current the ADC can read [A]: the range less the offset the
 * calibration accepts (a reading tops out there). Any context. */
float drive_i_readable_A(const drive_params_t *p);

/* The least the trip must stay above the current limit [A]: the ADC's
 * noise on a sample at the limit, BOARD_TRIP_NOISE_SIGMAS of it
 * (params_design.md sec. 3). Any context. */
float drive_trip_margin_A(const drive_params_t *p);

/* Rated torque 1.5 p psi_f i_rated (SPMSM, i_d = 0) [N m]. Any context. */
float drive_rated_torque_Nm(const drive_params_t *p);

/* The speed PI's gains for an inertia J_kgm2 [kg m^2] at the crossover
 * speed_bw_rad_s [rad/s] (params_design.md sec. 4): linear in J. Any context. */
void drive_speed_pi(float J_kgm2, float speed_bw_rad_s, float *kp_Nms_rad, float *ki_Nm_rad);

/* Start-up or host: the values of *p left to derive from the others (the formulas
 * of params_design.md); returns the refusals and warnings. Idempotent. */
drive_derive_t drive_params_derive(drive_params_t *p);

/* Start-up or host: the observer's gains for *p's told R, L at Ts, the
 * disturbance bound in proportion to the bus (smo_gains_design,
 * control/discrete_model_design.md sec. 5); false: the told L/R is below
 * SMO_LR_MIN_PERIODS periods (the proposed method refused). */
bool drive_params_obs_gains(const drive_params_t *p, smo_gains_t *g);

/* Start-up or host: the board's parameter set (firmware/params/board_cfg.h). */
void drive_params_board(drive_params_t *p);

/* Start-up or host: the controller's settings derived from *p (derived
 * first): the model's bounds (board_cfg.h MODEL_*), the proposed method's
 * settings (the observer's gains, the R^ band, step 2's thresholds, the
 * injections). The plain copies are drive_params_to_app_cfg's (the
 * lists' DRIVE_TO), which calls this after them. */
void drive_params_to_ctrl_cfg(const drive_params_t *p, ctrl_cfg_t *c);

/* ref_value x (q / q_ref): a value in proportion to q, ref_value at the
 * reference to the bit (q / q_ref is 1 there). Any context. */
float drive_scaled(float ref_value, float q, float q_ref);

#endif /* DRIVE_PARAMS_H */
