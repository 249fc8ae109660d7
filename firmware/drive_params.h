/*
 * drive_params.h - the drive's one parameter set: the motor, the board,
 * the limits and the controller's tuning, in SI units, and the one
 * mapping from it to the app's configuration.
 *
 * The target fills it from the board header (drive_params_board(),
 * firmware/board_cfg.h) and maps it in app_cfg_default(); the SIL takes the
 * same defaults (tools/sil/scenario.c: the keys marked "params", printed by
 * drive_sil --help), puts the scenario's keys on top and maps it with the
 * same drive_params_to_app_cfg(). The start-up sequence's settings
 * (calibration, alignment, step 1, the watch checks) are the app's own
 * (app_cfg_default).
 */
#ifndef DRIVE_PARAMS_H
#define DRIVE_PARAMS_H

#include <stdint.h>

#include "app.h"

typedef struct {
    float R_Ohm;                /* stator phase resistance [Ohm] */
    float L_H;                  /* Ld = Lq [H] */
    float psi_f_Wb;             /* PM flux linkage [Wb] */
    uint16_t pole_pairs;        /* [-] */
    float J_kgm2;               /* rotor inertia [kg m^2] (the SIL plant's) */
    float rated_torque_Nm;      /* [N m] */
} drive_motor_t;

typedef struct {
    float Ts_s;                 /* control = PWM period [s] */
    float deadtime_s;           /* gate-driver dead time the controller compensates [s] */
    float vdc_nominal_V;        /* nominal DC bus [V] */
    float u_bound_V;            /* bound on |ud|, |uq| the controller's model uses [V] */
    uint32_t enc_lines;         /* encoder lines; x4 counts [-] */
    float enc_offset_el_rad;    /* electrical angle at count 0, as measured [rad el] */
    uint32_t isr_period_cycles; /* control period in hal_cycles() counts [cycles] */
    uint32_t isr_budget_cycles; /* longest allowed ISR run [cycles] */
} drive_board_t;

typedef struct {
    float i_trip_A;             /* software overcurrent trip on |ia|, |ib|, |ic| [A] */
    float i_limit_A;            /* stator-current limit the deadbeat targets respect [A] */
    float vdc_max_V;            /* overvoltage trip [V] */
    float vdc_min_V;            /* undervoltage trip [V] */
    float speed_max_rad_s;      /* overspeed trip, mechanical [rad/s] */
    float te_max_Nm;            /* torque reference limit [N m] */
} drive_limits_t;

typedef struct {
    float speed_kp_Nms_rad;     /* speed PI [N m / (rad/s)] */
    float speed_ki_Nm_rad;      /* speed PI [N m / rad] */
    float pll_bw_rad_s;         /* encoder speed-estimator bandwidth [rad/s] */
    float u_margin;             /* steady-state share of Vdc/sqrt(3) for flux weakening [-] */
    float R_min_Ohm;            /* accepted R^ band [Ohm]; < 0: ctrl_rsid_band_default()'s */
    float R_max_Ohm;            /*   <= 0: ctrl_rsid_band_default()'s */
} drive_tuning_t;

typedef struct {
    drive_motor_t motor;        /* the controller's model of the motor */
    drive_board_t board;
    drive_limits_t limits;
    drive_tuning_t tuning;
} drive_params_t;

/* Start-up or host: the board's parameter set (firmware/board_cfg.h). */
void drive_params_board(drive_params_t *p);

/* Start-up or host: *p into the controller's configuration and the
 * protection limits of *cfg (the model bounds derived here: board_cfg.h
 * MODEL_*), the proposed method's settings from ctrl's defaults for
 * them; the rest of *cfg (start-up sequence, step 1, watch) is left. */
void drive_params_to_app_cfg(const drive_params_t *p, app_cfg_t *cfg);

#endif /* DRIVE_PARAMS_H */
