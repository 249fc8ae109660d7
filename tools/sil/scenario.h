/*
 * scenario.h - SIL scenarios: INI files (parsed with libinih) and
 * "section.key=value" overrides into one scenario_t. Every key is
 * optional; the drive's keys default to its parameter set and the app's
 * configuration of the board (Table I; scenario.c, PARAMS). The keys are
 * one table in scenario.c (a new key is one field here and one line
 * there); the format is documented in hal/sim/README.md and by
 * scenario_print_keys().
 *
 * Errors name the source and key: "FILE:LINE: [section] key: problem"
 * (or "--set section.key=value: problem").
 */
#ifndef SCENARIO_H
#define SCENARIO_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "drive_params.h"
#include "profile.h"

#define SCENARIO_ERR_LEN 512
#define SCENARIO_MAX_KEYS 128
#define SCENARIO_ORIGIN_LEN 96

typedef enum { SC_MODEL_AVERAGED = 0, SC_MODEL_SWITCHING = 1 } sc_model_t;
typedef enum { SC_METHOD_CONVENTIONAL = 0, SC_METHOD_PROPOSED = 1 } sc_method_t;
typedef enum { SC_MODE_SPEED = 0, SC_MODE_TORQUE = 1, SC_MODE_OPEN_LOOP = 2 } sc_mode_t;
typedef enum { SC_OFF = 0, SC_ON = 1 } sc_onoff_t;
/* [identify] mode: as app_rsid_mode_t */
typedef enum { SC_RSID_OFF = 0, SC_RSID_WINDOWS = 1, SC_RSID_SPEEDS = 2, SC_RSID_TRUSTED = 3 } sc_rsid_mode_t;
/* [identify] on_refusal: as app_rsid_refusal_t */
typedef enum { SC_REFUSAL_FAULT = 0, SC_REFUSAL_CONVENTIONAL = 1 } sc_refusal_t;
/* [plant] encoder_direction: "1" | "-1" */
typedef enum { SC_DIRECTION_FORWARD = 0, SC_DIRECTION_REVERSED = 1 } sc_direction_t;
/* [plant] phase_order */
typedef enum { SC_PHASES_ABC = 0, SC_PHASES_ACB = 1 } sc_phase_order_t;
/* [run] level4_i_limit_A's default, x [controller] i_limit_A */
#define SC_LEVEL4_I_LIMIT_PER_LIMIT 0.3


typedef struct {
    struct {                       /* [plant]: the TRUE motor, inverter and sensors */
        double R_ohm, L_H, psif_Wb;        /* R_ohm: at t = 0 (R_profile's first point) */
        profile_t R_profile;               /* R over the run (a warming winding); key R_ohm */
        double device_drop_V;              /* on-state drop of the conducting device [V] */
        uint32_t pole_pairs;
        double J_kgm2, B_Nms;
        uint32_t speed_held;       /* 1: shaft held at speed0_rpm (locked rotor at 0) */
        double speed0_rpm;
        double vdc_V;
        uint32_t model;            /* sc_model_t */
        double deadtime_s, substep_s;
        uint32_t encoder_lines;
        double encoder_offset_el_rad;
        uint32_t encoder_direction;        /* sc_direction_t */
        uint32_t phase_order;              /* sc_phase_order_t */
        double adc_full_scale_A, adc_offset_a_A, adc_offset_b_A, adc_noise_A;
        uint32_t seed;
        double trip_A;
    } plant;
    struct {                       /* [motor]: the ratings (default: the paper motor's) */
        double i_rated_A, i_peak_A, t_peak_s;  /* i_peak NaN: 2 x i_rated */
        double n_rated_rpm, n_max_rpm;         /* n_max NaN: n_rated */
    } motor;
    struct {                       /* [controller]: the controller's values */
        double R_ohm, L_H, psif_Wb;            /* NaN: factor x plant value */
        double J_kgm2, B_Nms;                  /* NaN: the plant's */
        double speed_bw_rad_s;                 /* speed-loop crossover [rad/s] */
        double R_factor, L_factor, psif_factor;
        uint32_t method;           /* sc_method_t */
        uint32_t mode;             /* sc_mode_t */
        /* speed_kp, speed_ki, te_max, i_max, i_limit, overspeed and
         * [identify]'s settle, speeds and accel: NaN until scenario_finish
         * derives them (drive_params_derive) */
        double speed_kp_Nms_rad, speed_ki_Nm_rad, pll_bw_rad_s, te_max_Nm, i_max_A;
        double i_limit_A, overspeed_rpm;   /* current limit, overspeed trip */
        double R_min_ohm, R_max_ohm;           /* R^ band; NaN: the board's factors x R_ohm */
        double deadtime_s;                     /* dead time the controller compensates; NaN: the plant's */
        double untold_deadtime_s;              /* speed floor's prior on an untold inverter error [s]; NaN: the ctrl default */
        double encoder_offset_el_rad;          /* encoder offset the controller is told [rad el]; NaN: the plant's */
        uint32_t pole_pairs;                   /* pole pairs the controller is told; 0 (default): the plant's */
    } controller;
    struct {                       /* [identify]: step 1 of the proposed method (app IDENTIFY_R) */
        uint32_t mode;             /* sc_rsid_mode_t */
        double settle_1_s, window_s, settle_2_s;
        double speed_1_rpm, speed_2_rpm, accel_rpm_s;
        /* step 1 on a real ADC */
        double R_se_max_rel, batch_s, window_max_s;
        uint32_t repeats_max;
        uint32_t on_refusal;       /* sc_refusal_t */
        uint32_t track_R;          /* off | on | auto: R^ tracked in step 2 (ctrl_cfg_t.track_R, CTRL_TRACK_R_*) */
    } identify;
    struct {
        profile_t speed_rpm, torque_Nm, ud_V, uq_V;
    } reference;
    struct {
        profile_t torque_Nm;
    } load;
    struct {
        double duration_s;         /* 0 only when endless_ok: until the host ends the run */
        bool endless_ok;           /* set by the caller after scenario_defaults: duration_s = 0 accepted (drive_sil --link) */
        uint32_t log_every;        /* periods between logged rows */
        uint32_t calibrate;        /* 1: the app measures the current offsets at start (sc_onoff_t) */
        uint32_t align;            /* 1: the app aligns the rotor; the controller is not told the encoder offset */
        uint32_t level;            /* build level 1..5 (app.h) */
        double level4_i_limit_A;   /* level 4's current limit; NaN: SC_LEVEL4_I_LIMIT_PER_LIMIT x i_limit_A */
    } run;
    struct {                       /* [faults]: injected on the simulated board (hal_sim_faults_t); times NaN: never */
        double open_phase_s;
        uint32_t open_phase;       /* 0 a, 1 b, 2 c */
        double short_s;
        uint32_t short_phases;     /* 0 ab, 1 bc, 2 ca */
        double short_ohm, short_H;
        double adc_stuck_s;
        uint32_t adc_stuck;        /* 0 a, 1 b */
        double encoder_lost_s, encoder_jump_s, encoder_jump_counts;
        double vdc_sag_s, vdc_sag_V, vdc_surge_s, vdc_surge_V;
        double gate_trip_s;
        double isr_overrun_s, isr_overrun_run_s;
    } faults;
    uint32_t derive_status;        /* drive_derive_t of scenario_finish (warnings) */
    /* where each key was last set ("" = default), for messages */
    char origin[SCENARIO_MAX_KEYS][SCENARIO_ORIGIN_LEN];
} scenario_t;

/* All keys at their defaults. */
void scenario_defaults(scenario_t *sc);

/* Apply the INI file at path on top of *sc. Returns 0, or -1 with err filled (first error). */
int scenario_load(scenario_t *sc, const char *path, char *err, size_t errlen);

/* Apply one "section.key=value" override. Returns 0, or -1 with err filled. */
int scenario_set(scenario_t *sc, const char *assignment, char *err, size_t errlen);

/* Cross-key checks (absolute vs factor; plausibility bounds, the controller's after its factor;
 * method = proposed needs step 1 or a trusted R: no silent fallback to the conventional method),
 * resolution of the controller's R, L, psi_f, J, B to absolute values and of the derived keys
 * (drive_params_derive: a motor the drive cannot run refused, naming the keys; warnings in
 * derive_status). Call once after loading. Returns 0, or -1 with err. */
int scenario_finish(scenario_t *sc, char *err, size_t errlen);

/* 1 when [section] name is a scenario key, else 0. */
int scenario_key_known(const char *section, const char *name);

/* The drive's parameter set of a finished scenario (Ts: the simulated board's).
 * The derived values left to derive (DRIVE_PARAM_DERIVED) unless finished. */
void scenario_params(const scenario_t *sc, drive_params_t *p);

/* 1 when [section] key was set by the scenario or an override, 0 when default or derived. */
int scenario_key_set(const scenario_t *sc, const char *section, const char *name);

/* The warnings of derive_status as text ("" if none), naming the keys. */
void scenario_warnings(const scenario_t *sc, char *buf, size_t len);

/* The key table as help text: section, key, default, meaning. */
void scenario_print_keys(FILE *f);

/* The plausibility bounds scenario_finish() checks, as help text. */
void scenario_print_bounds(FILE *f);

#endif /* SCENARIO_H */
