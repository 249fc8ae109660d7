/*
 * scenario.h - SIL scenarios: INI files (parsed with libinih) and
 * "section.key=value" overrides into one scenario_t. Every key is
 * optional; the drive's keys default to its parameter set and the app's
 * configuration of the board (Table I). The keys are one table,
 * scenario_keys.h (a new key is one line there: its field here, its
 * parsing, default, target, --help and the documented list follow); the
 * format is documented in tools/sil/README.md, the keys in
 * tools/sil/SCENARIO_KEYS.md (drive_sil --list-keys --markdown).
 *
 * Errors name the source and key: "FILE:LINE: [section] key: problem"
 * (or "--set section.key=value: problem").
 */
#ifndef SCENARIO_H
#define SCENARIO_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "app.h"
#include "drive_params.h"
#include "link.h"
#include "profile.h"
#include "scenario_keys.h"

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


/* The fields of the keys (scenario_keys.h: the key's name, double, uint32_t
 * or profile_t; [plant] R_ohm also R_ohm_profile). NaN: not set, left to
 * scenario_finish (the controller's values, the derived keys) or to its
 * target (a fault's time: never; [motor] i_peak_A, n_max_rpm: scenario_params). */
typedef struct {
    struct { SC_KEYS_plant(SC_FIELD) } plant;           /* the TRUE motor, inverter and sensors */
    struct { SC_KEYS_motor(SC_FIELD) } motor;           /* the ratings (default: the paper motor's) */
    struct { SC_KEYS_controller(SC_FIELD) } controller; /* what the controller is told */
    struct { SC_KEYS_identify(SC_FIELD) } identify;     /* step 1 of the proposed method (app IDENTIFY_R) */
    struct { SC_KEYS_reference(SC_FIELD) } reference;
    struct { SC_KEYS_load(SC_FIELD) } load;
    struct {
        SC_KEYS_run(SC_FIELD)
        bool endless_ok;           /* set by the caller after scenario_defaults: duration_s = 0 accepted (drive_sil --link) */
    } run;
    struct { SC_KEYS_faults(SC_FIELD) } faults;         /* injected on the simulated board (hal_sim_faults_t) */
    struct { SC_KEYS_link(SC_FIELD) } link;             /* drive_sil --link */
    uint32_t derive_status;        /* drive_derive_t of scenario_finish (warnings) */
    /* where each key was last set ("" = default), for messages */
    char origin[SCENARIO_MAX_KEYS][SCENARIO_ORIGIN_LEN];
} scenario_t;

/* All keys at their defaults. */
void scenario_defaults(scenario_t *sc);

/* A section of the file that is no scenario's and is skipped unread: a campaign's
 * tolerance distributions (tools/drivekit/CAMPAIGN_KEYS.md), so one file serves both. */
#define SCENARIO_IGNORED_SECTION "campaign"

/* Apply the INI file at path on top of *sc (SCENARIO_IGNORED_SECTION skipped).
 * Returns 0, or -1 with err filled (first error). */
int scenario_load(scenario_t *sc, const char *path, char *err, size_t errlen);

/* Apply one "section.key=value" override. Returns 0, or -1 with err filled. */
int scenario_set(scenario_t *sc, const char *assignment, char *err, size_t errlen);

/* The same, the value's origin (messages, the key's source) named where ("--nv FILE"). */
int scenario_set_from(scenario_t *sc, const char *assignment, const char *where, char *err, size_t errlen);

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

/* Where a key's value goes (scenario_keys.h, TO) and how it is converted. */
typedef enum { SC_TO_NONE, SC_TO_SAME, SC_TO_PARAMS, SC_TO_APP, SC_TO_SIM, SC_TO_FAULTS, SC_TO_LINK } sc_target_t;
typedef enum {
    SC_CONV_NONE,
    SC_CONV_F32,      /* float, value / scale */
    SC_CONV_F64,      /* double, value / scale */
    SC_CONV_U16,      /* uint16_t */
    SC_CONV_U32,      /* uint32_t */
    SC_CONV_U64,      /* uint64_t */
    SC_CONV_I32,      /* int32_t, rounded */
    SC_CONV_ENUM,     /* an enum whose values are the key's names' indices */
    SC_CONV_BOOL,     /* bool: value != 0 */
    SC_CONV_PERIODS   /* uint32_t periods of Ts_s, rounded, from seconds */
} sc_conv_t;

typedef struct {
    sc_target_t target;
    size_t offset;             /* of the value in the target's struct */
    sc_conv_t conv;
    double scale;              /* key unit per target unit */
    const char *path;          /* the field's path in the target's struct ("rsid.mode"), or NULL */
} sc_loc_t;

/* One key of the table, for the runner's outputs and tests. */
typedef enum { SC_KEY_REAL, SC_KEY_UINT, SC_KEY_ENUM, SC_KEY_PROFILE } sc_key_type_t;
typedef struct {
    const char *section, *name, *help;
    sc_key_type_t type;
    double lo, hi;             /* SC_KEY_REAL, SC_KEY_UINT: the accepted range */
    const char *const *names;  /* SC_KEY_ENUM: the values, NULL-terminated */
    const char *from_keys;     /* a derived key: the keys it is derived from; else NULL */
    sc_loc_t to;               /* where its value goes (SC_TO_SAME resolved) */
} scenario_key_info_t;

/* The number of keys; key i's description (0 <= i < scenario_key_count()). */
int scenario_key_count(void);
void scenario_key_info(int i, scenario_key_info_t *out);

/* The values of the keys whose target is `target` into *cfg: a
 * drive_params_t (SC_TO_PARAMS), app_cfg_t (SC_TO_APP), hal_sim_cfg_t
 * (SC_TO_SIM), hal_sim_faults_t (SC_TO_FAULTS) or link_cfg_t (SC_TO_LINK), on top of what it holds;
 * a NaN value leaves its field. Ts_s: the period of a SC_CONV_PERIODS key. */
void scenario_map(const scenario_t *sc, sc_target_t target, void *cfg, double Ts_s);

/* The value at loc in *cfg (the struct loc->target names), in the key's unit. */
double scenario_loc_read(const sc_loc_t *loc, const void *cfg, double Ts_s);

/* Key i's value in a scenario: a REAL's (NaN: not set, not derived), a
 * UINT's, an ENUM's index; NaN for a profile. */
double scenario_key_value(const scenario_t *sc, int i);

/* Key i's value in a finished scenario as JSON: a number (null if NaN), an
 * enum's name, or a profile's points [[t_s, value, ramp], ...]. */
void scenario_key_json(FILE *f, const scenario_t *sc, int i);

/* The key table as a Markdown document (tools/sil/SCENARIO_KEYS.md). */
void scenario_print_keys_markdown(FILE *f);

#endif /* SCENARIO_H */
