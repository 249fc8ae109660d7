/*
 * drive_params.h - the drive's one parameter set: the motor, its
 * ratings, the board, the limits, the controller's tuning and step 1's
 * speeds and timing, in SI units; the values derived from it
 * (params_design.md); and the one mapping to the app's configuration.
 *
 * The target fills it from the board header (drive_params_board(),
 * firmware/board_cfg.h) and maps it in app_cfg_default(); the SIL takes the
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

#include "app.h"

/* A value marked "derived" that is negative (DRIVE_PARAM_DERIVED) or NaN
 * is derived by drive_params_derive() (firmware/params_design.md) from
 * what the controller is told: the motor, its ratings, the board; one
 * >= 0 is the user's and stays. */
#define DRIVE_PARAM_DERIVED (-1.0f)

typedef struct {
    float R_Ohm;                /* stator phase resistance [Ohm] */
    float L_H;                  /* Ld = Lq [H] */
    float psi_f_Wb;             /* PM flux linkage [Wb] */
    uint16_t pole_pairs;        /* [-] */
    float J_kgm2;               /* rotor and load inertia [kg m^2] */
    float B_Nms;                /* viscous friction [N m s/rad] */
} drive_motor_t;

typedef struct {
    float i_rated_A;            /* continuous current (peak of the phase current) [A] */
    float i_peak_A;             /* short-time current [A] */
    float t_peak_s;             /* how long i_peak may last [s] */
    float n_rated_rad_s;        /* rated speed, mechanical [rad/s] */
    float n_max_rad_s;          /* highest speed, mechanical [rad/s] */
} drive_rating_t;

typedef struct {
    float Ts_s;                 /* control = PWM period [s] */
    float deadtime_s;           /* gate-driver dead time the controller compensates [s] */
    float vdc_nominal_V;        /* nominal DC bus [V] */
    float u_bound_V;            /* bound on |ud|, |uq| the controller's model uses [V] */
    float i_full_scale_A;       /* current ADC range, +- [A] */
    uint32_t enc_lines;         /* encoder lines; x4 counts [-] */
    float enc_offset_el_rad;    /* electrical angle at count 0, as measured [rad el] */
    uint32_t isr_period_cycles; /* control period in hal_cycles() counts [cycles] */
    uint32_t isr_budget_cycles; /* longest allowed ISR run [cycles] */
} drive_board_t;

typedef struct {
    float i_trip_A;             /* software overcurrent trip on |ia|, |ib|, |ic| [A]; derived */
    float i_limit_A;            /* stator-current limit the deadbeat targets respect [A]; derived */
    float vdc_max_V;            /* overvoltage trip [V] */
    float vdc_min_V;            /* undervoltage trip [V] */
    float speed_max_rad_s;      /* overspeed trip, mechanical [rad/s]; derived */
    float te_max_Nm;            /* torque reference limit [N m]; derived */
} drive_limits_t;

typedef struct {
    float speed_bw_rad_s;       /* speed-loop crossover w_c [rad/s] */
    float speed_kp_Nms_rad;     /* speed PI [N m / (rad/s)]; derived */
    float speed_ki_Nm_rad;      /* speed PI [N m / rad]; derived */
    float pll_bw_rad_s;         /* encoder speed-estimator bandwidth [rad/s] */
    float u_margin;             /* steady-state share of Vdc/sqrt(3) for flux weakening [-] */
    float R_min_Ohm;            /* accepted R^ band [Ohm]; < 0: ctrl_rsid_band_with()'s */
    float R_max_Ohm;            /*   <= 0: ctrl_rsid_band_with()'s */
} drive_tuning_t;

typedef struct {                /* step 1 (rsid_seq.h); all derived */
    float settle_1_s;           /* IDENTIFY_R entry (speeds: ramp end) to window 1 [s] */
    float settle_2_s;           /* window 1 to window 2 [s] */
    float speed_1_rad_s;        /* speeds mode: the two points, mechanical [rad/s] */
    float speed_2_rad_s;
    float accel_rad_s2;         /* speeds mode: ramp of the commanded speed [rad/s^2] */
} drive_step1_t;

typedef struct {
    drive_motor_t motor;        /* the controller's model of the motor */
    drive_rating_t rating;
    drive_board_t board;
    drive_limits_t limits;
    drive_tuning_t tuning;
    drive_step1_t step1;
} drive_params_t;

/* r/min per rad/s, for the SIL's derived keys in r/min (tools/sil/scenario_keys.h:
 * each derived key names its field here and the keys it comes from). */
#define DRIVE_RPM_PER_RAD_S 9.54929658551372

/* What drive_params_derive() refused or warns of (a set of bits). */
typedef uint16_t drive_derive_t;
#define DRIVE_DERIVE_OK          ((drive_derive_t)0x0000u)
#define DRIVE_DERIVE_RATINGS     ((drive_derive_t)0x0001u) /* ratings not positive, i_peak < i_rated or n_max < n_rated */
#define DRIVE_DERIVE_ADC_RANGE   ((drive_derive_t)0x0002u) /* the current limit reaches the trip the ADC range allows */
#define DRIVE_DERIVE_OBSERVER    ((drive_derive_t)0x0004u) /* no observer gain meets stability and (36) (the proposed method) */
#define DRIVE_DERIVE_WARN_BEMF   ((drive_derive_t)0x0100u) /* warning: back-EMF at n_max beyond the bus's phase-voltage limit */
#define DRIVE_DERIVE_REFUSED     ((drive_derive_t)0x00FFu) /* the refusals among the bits */

/* Rated torque 1.5 p psi_f i_rated (SPMSM, i_d = 0) [N m]. Any context. */
float drive_rated_torque_Nm(const drive_params_t *p);

/* The speed PI's gains for an inertia J_kgm2 [kg m^2] at the crossover
 * speed_bw_rad_s [rad/s] (params_design.md sec. 3): linear in J. Any context. */
void drive_speed_pi(float J_kgm2, float speed_bw_rad_s, float *kp_Nms_rad, float *ki_Nm_rad);

/* Start-up or host: the values of *p left to derive from the others (the formulas
 * of params_design.md); returns the refusals and warnings. Idempotent. */
drive_derive_t drive_params_derive(drive_params_t *p);

/* Start-up or host: the observer's gains for *p (derived first) and
 * the cap on G = Ks/phi (observer_design.md sec. 3b); false: none. */
bool drive_params_obs_gains(const drive_params_t *p, ctrl_obs_gains_t *g, float *G_max_V_A);

/* Start-up or host: the board's parameter set (firmware/board_cfg.h). */
void drive_params_board(drive_params_t *p);

/* Start-up or host: *p (its values left to derive derived) into the controller's
 * configuration, the protection limits of *cfg (the model bounds derived
 * here: board_cfg.h MODEL_*), the proposed method's settings (the
 * observer's gains, step 2's thresholds, the injections), step 1's timing
 * and speeds, the alignment's voltage and the open-phase thresholds; the
 * rest of *cfg (start-up sequence, watch) is left. */
void drive_params_to_app_cfg(const drive_params_t *p, app_cfg_t *cfg);

#endif /* DRIVE_PARAMS_H */
