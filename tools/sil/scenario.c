/* scenario.c - the scenario key table, INI loading (libinih) and overrides; see scenario.h. */
#include "scenario.h"
#include "sim_units.h"

#include <errno.h>
#include <ini.h>
#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "drive_params.h"
#include "hal_sim.h"

/* K_RPROFILE: a positive profile starting at t = 0 (a bare number is a
 * constant); its value at t = 0 also goes to the double at offset_t0. */
typedef enum { K_REAL, K_UINT, K_ENUM, K_PROFILE, K_RPROFILE } key_kind_t;

typedef struct {
    const char *section;
    const char *name;
    key_kind_t kind;
    size_t offset;             /* of the field in scenario_t */
    const char *def;           /* default as text; NULL: unset (NaN, resolved in scenario_finish) */
    double lo, hi;             /* K_REAL, K_UINT: allowed range */
    bool lo_open;              /* K_REAL: lo itself excluded */
    const char *const *names;  /* K_ENUM: value k is names[k] */
    const char *help;
    size_t offset_t0;          /* K_RPROFILE: the double that takes the value at t = 0 */
} sc_key_t;

static const char *const MODEL_NAMES[] = { "averaged", "switching", NULL };
static const char *const METHOD_NAMES[] = { "conventional", "proposed", NULL };
static const char *const MODE_NAMES[] = { "speed", "torque", "open_loop", NULL };
static const char *const ONOFF_NAMES[] = { "off", "on", NULL };
static const char *const RSID_NAMES[] = { "off", "windows", "speeds", "trusted", NULL };
static const char *const PHASE_NAMES[] = { "a", "b", "c", NULL };
static const char *const PAIR_NAMES[] = { "ab", "bc", "ca", NULL };
static const char *const CHANNEL_NAMES[] = { "a", "b", NULL };
static const char *const REFUSAL_NAMES[] = { "fault", "conventional", NULL };
static const char *const TRACK_NAMES[] = { "off", "on", "auto", NULL };
static const char *const DIRECTION_NAMES[] = { "1", "-1", NULL };   /* sc_direction_t */
static const char *const ORDER_NAMES[] = { "abc", "acb", NULL };   /* sc_phase_order_t */

/* Keys whose default is not text of this table but a configuration's
 * value: the drive's parameter set (firmware/drive_params.h, the board's
 * values), the app's configuration of the board (app_cfg_default), or,
 * for the simulated board's own settings (ideal inverter and ADC), its
 * defaults (hal_sim_default_cfg). See params_default(). */
static const char PARAMS[] = "(drive_params)";
/* Keys derived in scenario_finish from the motor's data (drive_params_derive;
 * firmware/params_design.md) unless set: NaN until then. */
static const char DERIVED[] = "(derived)";

#define UINT32_MAX_D 4294967295.0
#define UINT16_MAX_D 65535.0        /* drive_params_t's pole_pairs is 16 bits */
#define F(field) offsetof(scenario_t, field)
/* One line per key. POS: > 0, NN: >= 0, ANY: finite, OPT: like POS, default unset. */
#define POS(s, k, f, d, h) { s, k, K_REAL, F(f), d, 0.0, HUGE_VAL, true, NULL, h, 0 }
#define NN(s, k, f, d, h) { s, k, K_REAL, F(f), d, 0.0, HUGE_VAL, false, NULL, h, 0 }
#define ANY(s, k, f, d, h) { s, k, K_REAL, F(f), d, -HUGE_VAL, HUGE_VAL, false, NULL, h, 0 }
#define OPT(s, k, f, h) { s, k, K_REAL, F(f), NULL, 0.0, HUGE_VAL, true, NULL, h, 0 }
#define UINT(s, k, f, d, lo, hi, h) { s, k, K_UINT, F(f), d, lo, hi, false, NULL, h, 0 }
#define ENUM(s, k, f, d, n, h) { s, k, K_ENUM, F(f), d, 0.0, 0.0, false, n, h, 0 }
#define PROF(s, k, f, h) { s, k, K_PROFILE, F(f), "", 0.0, 0.0, false, NULL, h, 0 }
/* [faults]: a time >= 0, default unset (NaN: the fault never happens). */
/* DRV: > 0 (DRVNN >= 0, DRVANY finite), derived unless set; TOLD: > 0 (TOLDNN >= 0), default the plant's. */
#define DRV(s, k, f, h) { s, k, K_REAL, F(f), DERIVED, 0.0, HUGE_VAL, true, NULL, h, 0 }
#define DRVNN(s, k, f, h) { s, k, K_REAL, F(f), DERIVED, 0.0, HUGE_VAL, false, NULL, h, 0 }
#define DRVANY(s, k, f, h) { s, k, K_REAL, F(f), DERIVED, -HUGE_VAL, HUGE_VAL, false, NULL, h, 0 }
#define TOLDNN(s, k, f, h) { s, k, K_REAL, F(f), NULL, 0.0, HUGE_VAL, false, NULL, h, 0 }
#define WHEN(k, f, h) { "faults", k, K_REAL, F(f), NULL, 0.0, HUGE_VAL, false, NULL, h, 0 }

static const sc_key_t KEYS[] = {
    { "plant", "R_ohm", K_RPROFILE, F(plant.R_profile), PARAMS, 0.0, HUGE_VAL, true, NULL,
      "true stator resistance R0 [ohm]; a profile from t = 0 warms the winding (\"0:3.0, 2:3.9~\")",
      F(plant.R_ohm) },
    POS("plant", "L_H", plant.L_H, PARAMS, "true inductance L0 = Ld = Lq [H]"),
    POS("plant", "psif_Wb", plant.psif_Wb, PARAMS, "true PM flux linkage psi_f0 [Wb]"),
    UINT("plant", "pole_pairs", plant.pole_pairs, PARAMS, 1.0, UINT16_MAX_D, "pole pairs"),
    POS("plant", "J_kgm2", plant.J_kgm2, PARAMS, "inertia [kg m^2]"),
    NN("plant", "B_Nms", plant.B_Nms, PARAMS, "viscous friction [N m s/rad]"),
    UINT("plant", "speed_held", plant.speed_held, PARAMS, 0.0, 1.0, "1: shaft held at speed0_rpm (0: free)"),
    ANY("plant", "speed0_rpm", plant.speed0_rpm, PARAMS, "initial (or held) speed [r/min]"),
    POS("plant", "vdc_V", plant.vdc_V, PARAMS, "DC-bus voltage [V]"),
    ENUM("plant", "model", plant.model, PARAMS, MODEL_NAMES, "inverter model: averaged | switching"),
    NN("plant", "deadtime_s", plant.deadtime_s, PARAMS, "inverter dead time [s]"),
    NN("plant", "device_drop_V", plant.device_drop_V, PARAMS,
       "on-state drop of the conducting switch or diode [V], by the current's sign"),
    POS("plant", "substep_s", plant.substep_s, PARAMS, "longest time the plant solves at once; below the PWM period it splits it [s]"),
    UINT("plant", "encoder_lines", plant.encoder_lines, PARAMS, 1.0, 1.0e6, "encoder lines (x4 counts)"),
    ANY("plant", "encoder_offset_el_rad", plant.encoder_offset_el_rad, PARAMS,
        "electrical angle of the d axis at count 0 [rad]; the controller is told the same unless run.align = on"),
    ENUM("plant", "encoder_direction", plant.encoder_direction, "1", DIRECTION_NAMES,
         "1 | -1: the encoder counts up (1) or down (-1, A and B swapped) as the rotor turns forward"),
    ENUM("plant", "phase_order", plant.phase_order, "abc", ORDER_NAMES,
         "abc | acb: acb swaps the inverter's legs b and c on their way to the current sensors and the motor"),
    POS("plant", "adc_full_scale_A", plant.adc_full_scale_A, PARAMS, "current ADC range +-[A] (12 bit)"),
    ANY("plant", "adc_offset_a_A", plant.adc_offset_a_A, PARAMS, "phase-a ADC offset [A]"),
    ANY("plant", "adc_offset_b_A", plant.adc_offset_b_A, PARAMS, "phase-b ADC offset [A]"),
    NN("plant", "adc_noise_A", plant.adc_noise_A, PARAMS, "current ADC Gaussian noise, std dev [A]"),
    UINT("plant", "seed", plant.seed, PARAMS, 0.0, UINT32_MAX_D, "noise seed"),
    POS("plant", "trip_A", plant.trip_A, PARAMS, "hardware overcurrent trip level [A]"),

    POS("motor", "i_rated_A", motor.i_rated_A, PARAMS, "continuous current, peak of the phase current [A]; T_rated = 1.5 p psi_f i_rated"),
    OPT("motor", "i_peak_A", motor.i_peak_A, "short-time current [A] (default 2 x i_rated_A)"),
    POS("motor", "t_peak_s", motor.t_peak_s, PARAMS, "how long i_peak_A may last [s]"),
    POS("motor", "n_rated_rpm", motor.n_rated_rpm, PARAMS, "rated speed [r/min]"),
    OPT("motor", "n_max_rpm", motor.n_max_rpm, "highest speed [r/min] (default n_rated_rpm)"),

    OPT("controller", "R_ohm", controller.R_ohm, "controller's R [ohm] (default R_factor x plant)"),
    OPT("controller", "L_H", controller.L_H, "controller's L [H] (default L_factor x plant)"),
    OPT("controller", "psif_Wb", controller.psif_Wb, "controller's psi_f [Wb] (default psif_factor x plant)"),
    OPT("controller", "R_factor", controller.R_factor, "controller's R / plant R (default 1)"),
    OPT("controller", "L_factor", controller.L_factor, "controller's L / plant L (default 1)"),
    OPT("controller", "psif_factor", controller.psif_factor, "controller's psi_f / plant psi_f (default 1)"),
    OPT("controller", "J_kgm2", controller.J_kgm2, "controller's inertia [kg m^2] (default the plant's)"),
    TOLDNN("controller", "B_Nms", controller.B_Nms, "controller's viscous friction [N m s/rad] (default the plant's)"),
    POS("controller", "speed_bw_rad_s", controller.speed_bw_rad_s, PARAMS,
        "speed-loop crossover [rad/s]: speed_kp = J w_c, speed_ki = kp w_c 0.103"),
    UINT("controller", "pole_pairs", controller.pole_pairs, "0", 0.0, 64.0,
         "pole pairs the controller is told (0: the plant's)"),
    ENUM("controller", "method", controller.method, "conventional", METHOD_NAMES, "conventional | proposed"),
    ENUM("controller", "mode", controller.mode, "speed", MODE_NAMES, "speed | torque | open_loop"),
    DRV("controller", "speed_kp_Nms_rad", controller.speed_kp_Nms_rad, "speed PI proportional gain (J_kgm2 x speed_bw_rad_s)"),
    DRV("controller", "speed_ki_Nm_rad", controller.speed_ki_Nm_rad, "speed PI integral gain (speed_kp x speed_bw_rad_s x 0.103)"),
    POS("controller", "pll_bw_rad_s", controller.pll_bw_rad_s, PARAMS, "speed estimator bandwidth [rad/s]"),
    DRV("controller", "te_max_Nm", controller.te_max_Nm, "torque reference limit [N m] (1.5 p psi_f i_peak_A)"),
    DRV("controller", "i_max_A", controller.i_max_A,
        "software overcurrent threshold [A] (1.26 i_peak_A, at most 14/15 adc_full_scale_A)"),
    DRV("controller", "i_limit_A", controller.i_limit_A, "stator-current limit the targets respect [A] (1.08 i_peak_A)"),
    DRV("controller", "overspeed_rpm", controller.overspeed_rpm, "overspeed trip [r/min] (1.2 n_max_rpm)"),
    { "controller", "deadtime_s", K_REAL, F(controller.deadtime_s), NULL, 0.0, HUGE_VAL, false, NULL, "dead time the controller compensates [s] (default the plant's, >= 0)", 0 },
    { "controller", "untold_deadtime_s", K_REAL, F(controller.untold_deadtime_s), NULL, 0.0, 1e-5, false, NULL,
      "proposed: until the inverter error is identified, the least error nobody told, as a dead time [s] "
      "(the speed floor's prior; default 0.15e-6: EST_UNTOLD_DEADTIME_DEFAULT_S, >= 0)", 0 },
    { "controller", "encoder_offset_el_rad", K_REAL, F(controller.encoder_offset_el_rad), NULL, -HUGE_VAL, HUGE_VAL, false, NULL,
      "encoder offset the controller is told [rad, electrical], sign as plant.encoder_offset_el_rad "
      "(default the plant's; run.align = on: the alignment's measurement replaces it)", 0 },
    OPT("controller", "R_min_ohm", controller.R_min_ohm, "accepted R^ band, low end [ohm] (default 0.1 x controller's R: ctrl_rsid_band_default)"),
    OPT("controller", "R_max_ohm", controller.R_max_ohm, "accepted R^ band, high end [ohm] (default 6 x controller's R, at most the observer's eq. (36) bound)"),

    ENUM("identify", "mode", identify.mode, PARAMS, RSID_NAMES, "step 1 of the proposed method: off | windows | speeds | trusted"),
    DRVNN("identify", "settle_1_s", identify.settle_1_s, "start of IDENTIFY_R to window 1 [s] (2 x settle_2_s)"),
    POS("identify", "window_s", identify.window_s, PARAMS, "each averaging window [s]"),
    DRVNN("identify", "settle_2_s", identify.settle_2_s,
          "end of window 1 to window 2 [s] (5.6 / w_i, the speed PI's integral corner)"),
    DRVANY("identify", "speed_1_rpm", identify.speed_1_rpm, "speeds mode: speed of point 1 [r/min] (0.25 n_rated_rpm)"),
    DRVANY("identify", "speed_2_rpm", identify.speed_2_rpm, "speeds mode: speed of point 2 [r/min] (0.5 n_rated_rpm)"),
    DRV("identify", "accel_rpm_s", identify.accel_rpm_s,
        "speeds mode: ramp of the commanded speed [r/min/s] (speed_1 in 0.2 s, at most 0.25 T_rated / J)"),
    /* step 1 on a real ADC (rs_ident.h, observer_design.md sec. 6) */
    POS("identify", "R_se_max_rel", identify.R_se_max_rel, PARAMS, "largest standard error of R^ accepted, x R^"),
    POS("identify", "batch_s", identify.batch_s, PARAMS, "batch of the standard error's batch means [s]"),
    NN("identify", "window_max_s", identify.window_max_s, PARAMS,
       "window 2 is lengthened up to this while the standard error of R^ is too large [s]"),
    UINT("identify", "repeats_max", identify.repeats_max, PARAMS, 0.0, 100.0,
         "speeds mode: both windows repeated at most this often while window 1's share of se(R^) is too large"),
    ENUM("identify", "on_refusal", identify.on_refusal, PARAMS, REFUSAL_NAMES,
         "a refused step 1: fault (PWM off, RSID_* fault) | conventional (runs on, warning STEP1_REFUSED)"),
    ENUM("identify", "track_R", identify.track_R, PARAMS, TRACK_NAMES,
         "off | on | auto: R^ tracked in step 2 by a d-current injection (a warming winding); auto: from 1 s after step 2; both held while the field is weakened or the voltage at its limit"),

    PROF("reference", "speed_rpm", reference.speed_rpm, "speed reference [r/min] (speed mode)"),
    PROF("reference", "torque_Nm", reference.torque_Nm, "torque reference [N m] (torque mode)"),
    PROF("reference", "ud_V", reference.ud_V, "d voltage [V] (open_loop mode)"),
    PROF("reference", "uq_V", reference.uq_V, "q voltage [V] (open_loop mode)"),

    PROF("load", "torque_Nm", load.torque_Nm, "load torque [N m], opposing positive speed"),

    POS("run", "duration_s", run.duration_s, "1.2", "simulated time [s]"),
    UINT("run", "log_every", run.log_every, "10", 1.0, UINT32_MAX_D, "periods between CSV rows"),
    ENUM("run", "calibrate", run.calibrate, "off", ONOFF_NAMES,
         "off | on: current-offset calibration at start (both off: RUN at t = 0)"),
    ENUM("run", "align", run.align, "off", ONOFF_NAMES,
         "off | on: rotor alignment identifies the encoder offset (off: the controller is told it)"),
    UINT("run", "level", run.level, "5", 1.0, 5.0,
         "build level (app.h): 1 PWM pattern, 2 ADC readings, 3 open-loop rotation and encoder check, "
         "4 torque control at level4_i_limit_A, 5 the full drive"),
    OPT("run", "level4_i_limit_A", run.level4_i_limit_A,
        "level 4's current limit [A] (default 0.3 x [controller] i_limit_A)"),

    /* [faults]: fault injection on the simulated board (hal_sim.h); each from its time on */
    WHEN("open_phase_s", faults.open_phase_s, "time the phase `open_phase` opens [s] (default never)"),
    ENUM("faults", "open_phase", faults.open_phase, "a", PHASE_NAMES, "the open phase: a | b | c"),
    WHEN("short_s", faults.short_s, "time the outputs `short_phases` short together [s] (default never)"),
    ENUM("faults", "short_phases", faults.short_phases, "bc", PAIR_NAMES, "the shorted pair: ab | bc | ca"),
    POS("faults", "short_ohm", faults.short_ohm, "0.1", "the short's loop resistance [ohm]"),
    POS("faults", "short_H", faults.short_H, "1e-5", "the short's loop inductance [H]"),
    WHEN("adc_stuck_s", faults.adc_stuck_s, "time the current channel `adc_stuck` freezes at its reading [s] (default never)"),
    ENUM("faults", "adc_stuck", faults.adc_stuck, "a", CHANNEL_NAMES, "the stuck channel: a | b"),
    WHEN("encoder_lost_s", faults.encoder_lost_s, "time the encoder count stops (A/B lost) [s] (default never)"),
    WHEN("encoder_jump_s", faults.encoder_jump_s, "time the encoder count jumps by encoder_jump_counts [s] (default never)"),
    ANY("faults", "encoder_jump_counts", faults.encoder_jump_counts, "2500", "the jump [counts] (whole)"),
    WHEN("vdc_sag_s", faults.vdc_sag_s, "time the DC bus steps to vdc_sag_V [s] (default never)"),
    POS("faults", "vdc_sag_V", faults.vdc_sag_V, "150", "bus after the sag [V]"),
    WHEN("vdc_surge_s", faults.vdc_surge_s, "time the DC bus steps to vdc_surge_V [s] (default never)"),
    POS("faults", "vdc_surge_V", faults.vdc_surge_V, "450", "bus after the surge [V]"),
    WHEN("gate_trip_s", faults.gate_trip_s, "time the gate driver pulls the trip input [s] (default never)"),
    WHEN("isr_overrun_s", faults.isr_overrun_s, "time of the control ISR call that overruns [s] (default never)"),
    POS("faults", "isr_overrun_run_s", faults.isr_overrun_run_s, "1.2e-4", "run time of that ISR call [s]"),
};

#define N_KEYS ((int)(sizeof KEYS / sizeof KEYS[0]))

typedef char sc_key_table_fits[(N_KEYS <= SCENARIO_MAX_KEYS) ? 1 : -1];

static void *field(scenario_t *sc, const sc_key_t *k)
{
    return (char *)sc + k->offset;
}

/* A K_REAL key's value in a scenario read only. */
static double real_value(const scenario_t *sc, const sc_key_t *k)
{
    return *(const double *)(const void *)((const char *)sc + k->offset);
}

static int find_key(const char *section, const char *name, int *section_known)
{
    *section_known = 0;
    for (int i = 0; i < N_KEYS; i++) {
        if (strcmp(KEYS[i].section, section) == 0) {
            *section_known = 1;
            if (strcmp(KEYS[i].name, name) == 0) {
                return i;
            }
        }
    }
    return -1;
}

int scenario_key_known(const char *section, const char *name)
{
    int known;
    return find_key(section, name, &known) >= 0;
}

/* ---- plausibility ----------------------------------------------------------
 * Bounds that refuse the absurd (a unit slip: mH written as H, a typo), not
 * the merely beyond-limit: a value past the drive's ratings or trips runs and
 * may fault (a speed reference above overspeed_rpm trips OVERSPEED). Each
 * bound holds for the plant's value and for the controller's after its
 * factor, on every point of a profile; scenario_finish() checks them, drive_sil
 * --help prints them (scenario_print_bounds). This table is their one home. */
#define R_PLAUSIBLE_OHM 1e-3, 1e3
#define L_PLAUSIBLE_H 1e-6, 10.0
#define PSIF_PLAUSIBLE_WB 1e-4, 10.0
#define SPEED_PLAUSIBLE_RPM -1e5, 1e5

typedef enum { B_REAL, B_UINT, B_PROFILE } bound_kind_t;

typedef struct {
    const char *section, *name;   /* the key */
    bound_kind_t kind;
    size_t offset;                /* of its double, uint32_t or profile_t in scenario_t */
    double lo, hi;                /* plausible: lo <= value <= hi */
    const char *unit;
    const char *factor;           /* [controller] key whose factor x the plant's value it may be, or NULL */
} sc_bound_t;

static const sc_bound_t BOUNDS[] = {
    { "plant", "R_ohm", B_PROFILE, F(plant.R_profile), R_PLAUSIBLE_OHM, "ohm", NULL },
    { "plant", "L_H", B_REAL, F(plant.L_H), L_PLAUSIBLE_H, "H", NULL },
    { "plant", "psif_Wb", B_REAL, F(plant.psif_Wb), PSIF_PLAUSIBLE_WB, "Wb", NULL },
    { "plant", "pole_pairs", B_UINT, F(plant.pole_pairs), 1.0, 64.0, "", NULL },
    { "plant", "J_kgm2", B_REAL, F(plant.J_kgm2), 1e-8, 100.0, "kg m^2", NULL },
    { "plant", "vdc_V", B_REAL, F(plant.vdc_V), 5.0, 1500.0, "V", NULL },
    { "plant", "speed0_rpm", B_REAL, F(plant.speed0_rpm), SPEED_PLAUSIBLE_RPM, "r/min", NULL },
    { "controller", "R_ohm", B_REAL, F(controller.R_ohm), R_PLAUSIBLE_OHM, "ohm", "R_factor" },
    { "controller", "L_H", B_REAL, F(controller.L_H), L_PLAUSIBLE_H, "H", "L_factor" },
    { "controller", "psif_Wb", B_REAL, F(controller.psif_Wb), PSIF_PLAUSIBLE_WB, "Wb", "psif_factor" },
    { "identify", "speed_1_rpm", B_REAL, F(identify.speed_1_rpm), SPEED_PLAUSIBLE_RPM, "r/min", NULL },
    { "identify", "speed_2_rpm", B_REAL, F(identify.speed_2_rpm), SPEED_PLAUSIBLE_RPM, "r/min", NULL },
    { "reference", "speed_rpm", B_PROFILE, F(reference.speed_rpm), SPEED_PLAUSIBLE_RPM, "r/min", NULL },
};
#define N_BOUNDS ((int)(sizeof BOUNDS / sizeof BOUNDS[0]))

static int parse_real(const sc_key_t *k, const char *v, double *out, char *err, size_t errlen)
{
    char *end;
    errno = 0;
    double x = strtod(v, &end);
    while (*end == ' ' || *end == '\t') {
        end++;
    }
    if (end == v || *end != '\0' || errno == ERANGE || !isfinite(x)) {
        snprintf(err, errlen, "\"%s\" is not a number", v);
        return -1;
    }
    if (x < k->lo || (k->lo_open && x <= k->lo) || x > k->hi) {
        snprintf(err, errlen, "%g is out of range (must be %s %g)", x, k->lo_open ? ">" : ">=", k->lo);
        return -1;
    }
    *out = x;
    return 0;
}

static int parse_uint(const sc_key_t *k, const char *v, uint32_t *out, char *err, size_t errlen)
{
    const char *p = v;
    while (*p >= '0' && *p <= '9') {
        p++;
    }
    if (p == v || *p != '\0') {
        snprintf(err, errlen, "\"%s\" is not a whole number", v);
        return -1;
    }
    errno = 0;
    double x = strtod(v, NULL);
    if (x < k->lo || x > k->hi) {
        snprintf(err, errlen, "%s is out of range (%g .. %g)", v, k->lo, k->hi);
        return -1;
    }
    *out = (uint32_t)x;
    return 0;
}

static int parse_enum(const sc_key_t *k, const char *v, uint32_t *out, char *err, size_t errlen)
{
    for (uint32_t i = 0; k->names[i] != NULL; i++) {
        if (strcmp(k->names[i], v) == 0) {
            *out = i;
            return 0;
        }
    }
    int n = snprintf(err, errlen, "unknown value \"%s\" (one of:", v);
    for (uint32_t i = 0; k->names[i] != NULL && n > 0 && (size_t)n < errlen; i++) {
        n += snprintf(err + n, errlen - (size_t)n, " %s", k->names[i]);
    }
    if (n > 0 && (size_t)n < errlen) {
        snprintf(err + n, errlen - (size_t)n, ")");
    }
    return -1;
}

/* K_RPROFILE: text into the profile (appended or replacing), which must
 * start at t = 0 with every value > 0; *t0 = its value at t = 0. */
static int parse_rprofile(const sc_key_t *k, profile_t *p, double *t0, const char *v, bool append,
                          char *err, size_t errlen)
{
    profile_t q = *p;
    if (!append) {
        q.n = 0u;
    }
    if (profile_parse_append(&q, v, err, errlen) != 0) {
        return -1;
    }
    if (q.n == 0u || q.pt[0].t_s > 0.0) {
        snprintf(err, errlen, "\"%s\": the profile must start at t = 0", v);
        return -1;
    }
    for (uint32_t j = 0; j < q.n; j++) {
        if (!(q.pt[j].value > k->lo)) {
            snprintf(err, errlen, "%g is out of range (must be > %g)", q.pt[j].value, k->lo);
            return -1;
        }
    }
    *p = q;
    *t0 = q.pt[0].value;
    return 0;
}

/* Set key i from text v; append: extend a profile instead of replacing it. */
/* True when v spells the number zero ("0", "0.0", "0e3"). */
static bool zero_text(const char *v)
{
    char *end;
    const double x = strtod(v, &end);
    while (*end == ' ' || *end == '\t') {
        end++;
    }
    return end != v && *end == '\0' && !(x < 0.0) && !(x > 0.0);
}

static int set_value(scenario_t *sc, int i, const char *v, bool append, char *err, size_t errlen)
{
    const sc_key_t *k = &KEYS[i];
    switch (k->kind) {
    case K_REAL:
        if (sc->run.endless_ok && (double *)field(sc, k) == &sc->run.duration_s && zero_text(v)) {
            sc->run.duration_s = 0.0;   /* run until the link's host ends it (drive_sil --link) */
            return 0;
        }
        return parse_real(k, v, (double *)field(sc, k), err, errlen);
    case K_UINT:
        return parse_uint(k, v, (uint32_t *)field(sc, k), err, errlen);
    case K_ENUM:
        return parse_enum(k, v, (uint32_t *)field(sc, k), err, errlen);
    case K_PROFILE: {
        profile_t *p = (profile_t *)field(sc, k);
        if (!append) {
            p->n = 0u;
        }
        return profile_parse_append(p, v, err, errlen);
    }
    case K_RPROFILE:
        return parse_rprofile(k, (profile_t *)field(sc, k), (double *)((char *)sc + k->offset_t0), v, append,
                              err, errlen);
    }
    return -1;
}

/* The value of each PARAMS key, in the key's unit: from the parameter
 * set (motor, board, limits, tuning), for step 1's settings from the app's
 * configuration (app_cfg_default), for the simulated board's own from
 * hal_sim_default_cfg(). */
typedef enum {
    PK_FLOAT,                  /* float [parameter unit] */
    PK_U16,                    /* uint16_t */
    PK_U32,                    /* uint32_t */
    PK_ENUM,                   /* an enum: the key's names[value] */
    PK_PERIODS,                /* uint32_t periods of the app's ctrl.Ts_s: in seconds */
    PK_DOUBLE,                 /* double [parameter unit] */
    PK_BOOL                    /* bool: 0 or 1 */
} sc_param_kind_t;

typedef struct {
    const char *section, *name;
    int src;                   /* 0 drive_params_t, 1 app_cfg_t, 2 hal_sim_cfg_t */
    size_t offset;             /* of the value in it */
    sc_param_kind_t kind;
    double scale;              /* key unit per parameter unit */
} sc_param_t;

#define P(s, k, f, kind, scale) { s, k, 0, offsetof(drive_params_t, f), kind, scale }
#define A(s, k, f, kind, scale) { s, k, 1, offsetof(app_cfg_t, f), kind, scale }
#define S(s, k, f, kind, scale) { s, k, 2, offsetof(hal_sim_cfg_t, f), kind, scale }
static const sc_param_t PARAM_KEYS[] = {
    P("plant", "R_ohm", motor.R_Ohm, PK_FLOAT, 1.0),
    P("plant", "L_H", motor.L_H, PK_FLOAT, 1.0),
    P("plant", "psif_Wb", motor.psi_f_Wb, PK_FLOAT, 1.0),
    P("plant", "pole_pairs", motor.pole_pairs, PK_U16, 1.0),
    P("plant", "J_kgm2", motor.J_kgm2, PK_FLOAT, 1.0),
    P("motor", "i_rated_A", rating.i_rated_A, PK_FLOAT, 1.0),
    P("motor", "t_peak_s", rating.t_peak_s, PK_FLOAT, 1.0),
    P("motor", "n_rated_rpm", rating.n_rated_rad_s, PK_FLOAT, SIM_RPM_PER_RAD_S),
    P("controller", "speed_bw_rad_s", tuning.speed_bw_rad_s, PK_FLOAT, 1.0),
    P("plant", "vdc_V", board.vdc_nominal_V, PK_FLOAT, 1.0),
    P("plant", "encoder_lines", board.enc_lines, PK_U32, 1.0),
    P("plant", "encoder_offset_el_rad", board.enc_offset_el_rad, PK_FLOAT, 1.0),
    S("plant", "B_Nms", plant.B_Nms, PK_DOUBLE, 1.0),
    S("plant", "speed_held", plant.speed_held, PK_BOOL, 1.0),
    S("plant", "speed0_rpm", plant.omega0_m_rad_s, PK_DOUBLE, SIM_RPM_PER_RAD_S),
    S("plant", "model", inv.model, PK_ENUM, 1.0),
    S("plant", "deadtime_s", inv.deadtime_s, PK_DOUBLE, 1.0),
    S("plant", "device_drop_V", inv.device_drop_V, PK_DOUBLE, 1.0),
    S("plant", "substep_s", inv.substep_max_s, PK_DOUBLE, 1.0),
    S("plant", "adc_full_scale_A", sens.adc_full_scale_A, PK_DOUBLE, 1.0),
    S("plant", "adc_offset_a_A", sens.adc_offset_a_A, PK_DOUBLE, 1.0),
    S("plant", "adc_offset_b_A", sens.adc_offset_b_A, PK_DOUBLE, 1.0),
    S("plant", "adc_noise_A", sens.adc_noise_A, PK_DOUBLE, 1.0),
    S("plant", "seed", sens.seed, PK_U32, 1.0),
    S("plant", "trip_A", trip_current_A, PK_DOUBLE, 1.0),
    P("controller", "pll_bw_rad_s", tuning.pll_bw_rad_s, PK_FLOAT, 1.0),
    A("identify", "mode", rsid.mode, PK_ENUM, 1.0),
    A("identify", "window_s", rsid.window_s, PK_FLOAT, 1.0),
    A("identify", "R_se_max_rel", ctrl.rsid.R_se_max_rel, PK_FLOAT, 1.0),
    A("identify", "batch_s", ctrl.rsid.n_batch, PK_PERIODS, 1.0),
    A("identify", "window_max_s", rsid.window_max_s, PK_FLOAT, 1.0),
    A("identify", "repeats_max", rsid.repeats_max, PK_U16, 1.0),
    A("identify", "on_refusal", rsid.on_refusal, PK_ENUM, 1.0),
    A("identify", "track_R", ctrl.track_R, PK_U16, 1.0),
};
#undef P
#undef A
#undef S

/* The value at q in its kind, in the key's unit. */
static double param_value(const sc_param_t *q, const char *at, const app_cfg_t *ac)
{
    switch (q->kind) {
    case PK_U16:
        return (double)*(const uint16_t *)(const void *)at;
    case PK_U32:
        return (double)*(const uint32_t *)(const void *)at;
    case PK_ENUM:
        return (double)*(const unsigned int *)(const void *)at;
    case PK_PERIODS:
        return (double)*(const uint32_t *)(const void *)at * (double)ac->ctrl.Ts_s;
    case PK_DOUBLE:
        return *(const double *)(const void *)at * q->scale;
    case PK_BOOL:
        return *(const bool *)(const void *)at ? 1.0 : 0.0;
    case PK_FLOAT:
        break;
    }
    return (double)*(const float *)(const void *)at * q->scale;
}

/* The default of a PARAMS key as text: the board's value in the key's
 * unit, to 6 significant digits (the decimal board_cfg.h spells: 0.011f
 * reads 0.011, not 0.0109999999); an enum key's value (or an on/off
 * key's 0/1) by its name. "" for a key not in PARAM_KEYS or a value
 * with no name. */
static const char *params_default(const sc_key_t *k, char *buf, size_t len)
{
    drive_params_t p;
    static app_cfg_t ac; /* large: not on the stack */
    static hal_sim_cfg_t hs;
    drive_params_board(&p);
    app_cfg_default(&ac);
    hal_sim_default_cfg(&hs);
    buf[0] = '\0';
    for (size_t j = 0; j < sizeof PARAM_KEYS / sizeof PARAM_KEYS[0]; j++) {
        const sc_param_t *q = &PARAM_KEYS[j];
        if (strcmp(q->section, k->section) == 0 && strcmp(q->name, k->name) == 0) {
            const char *const src[] = { (const char *)&p, (const char *)&ac, (const char *)&hs };
            const char *at = src[q->src] + q->offset;
            const double v = param_value(q, at, &ac);
            if (k->kind != K_ENUM) {
                snprintf(buf, len, "%.6g", v);
                /* a float read back from 6 digits that is not the same float
                 * (a derived constant): every digit of it */
                if (q->kind == PK_FLOAT &&
                    (float)(strtod(buf, NULL) / q->scale) != *(const float *)(const void *)at) {
                    snprintf(buf, len, "%.9g", v);
                }
                continue;
            }
            for (size_t n = 0; k->names[n] != NULL; n++) {
                if ((double)n == v) {
                    snprintf(buf, len, "%s", k->names[n]);
                }
            }
        }
    }
    return buf;
}

/* A key's default as text: the table's, or the parameter set's; NULL: unset. */
static const char *default_text(const sc_key_t *k, char *buf, size_t len)
{
    if (k->def == DERIVED) {
        return NULL;
    }
    return (k->def == PARAMS) ? params_default(k, buf, len) : k->def;
}

void scenario_defaults(scenario_t *sc)
{
    memset(sc, 0, sizeof *sc);
    char err[SCENARIO_ERR_LEN];
    char buf[32];
    for (int i = 0; i < N_KEYS; i++) {
        const char *def = default_text(&KEYS[i], buf, sizeof buf);
        if (def == NULL) {
            *(double *)field(sc, &KEYS[i]) = NAN;
        } else if (set_value(sc, i, def, false, err, sizeof err) != 0) {
            /* a PARAMS key missing from PARAM_KEYS, or a value with no
             * name: a bug of this table, not of the user's input */
            fprintf(stderr, "scenario.c: the default of [%s] %s does not parse: %s\n", KEYS[i].section,
                    KEYS[i].name, err);
            abort();
        }
    }
}

/* After n = snprintf(err, errlen, ...): a message cut to errlen ends in
 * "..." so that it does not read as complete. */
static void err_mark_cut(int n, char *err, size_t errlen)
{
    static const char CUT[] = "...";
    if (n >= 0 && (size_t)n >= errlen && errlen >= sizeof CUT) {
        memcpy(err + errlen - sizeof CUT, CUT, sizeof CUT);
    }
}

/* Apply one key; on failure write "WHERE: [section] key: problem" to err. */
static int apply(scenario_t *sc, const char *where, const char *section, const char *name,
                 const char *value, bool append, char *err, size_t errlen)
{
    int known = 0;
    int i = find_key(section, name, &known);
    char why[SCENARIO_ERR_LEN];
    if (section[0] == '\0') {
        snprintf(err, errlen, "%s: %s: a key before any [section] line", where, name);
        return -1;
    }
    if (i < 0) {
        snprintf(err, errlen, "%s: [%s] %s: %s", where, section, name,
                 known ? "unknown key" : "unknown section");
        return -1;
    }
    if (value[0] == '\0') {
        snprintf(err, errlen, "%s: [%s] %s: no value (give one, or leave the key out for its default)", where,
                 section, name);
        return -1;
    }
    if (set_value(sc, i, value, append, why, sizeof why) != 0) {
        /* where and why may each fill their buffers: err takes what fits */
        err_mark_cut(snprintf(err, errlen, "%s: [%s] %s: %s", where, section, name, why), err, errlen);
        return -1;
    }
    snprintf(sc->origin[i], SCENARIO_ORIGIN_LEN, "%s", where);
    return 0;
}

/* ---- INI files ------------------------------------------------------------- */

typedef struct {
    scenario_t *sc;
    const char *path;
    FILE *f;
    int lineno;                      /* of the line inih is handling */
    bool indented;                   /* that line starts with a blank: a continuation */
    bool seen[SCENARIO_MAX_KEYS];    /* set earlier in this file */
    int first_line[SCENARIO_MAX_KEYS];   /* where, when seen */
    char err[SCENARIO_ERR_LEN];      /* first error, "" if none */
} load_ctx_t;

/* A line "[name" without its "]": inih would name no error before the next
 * key, as one in section "" - this names the line. */
static void header_check(load_ctx_t *ctx, const char *line)
{
    const char *p = line + strspn(line, " \t");
    if (*p != '[' || strchr(p, ']') != NULL || ctx->err[0] != '\0') {
        return;
    }
    const int len = (int)strcspn(p, "\r\n");
    snprintf(ctx->err, sizeof ctx->err, "%s:%d: section line \"%.*s\" has no closing ']'", ctx->path, ctx->lineno,
             len, p);
}

/* inih's line reader, counting lines so every message can name one, and
 * refusing lines longer than inih's buffer instead of splitting them. */
static char *read_line(char *buf, int num, void *stream)
{
    load_ctx_t *ctx = stream;
    int n = 0;
    int ch = EOF;
    bool too_long = false;
    while ((ch = fgetc(ctx->f)) != EOF) {
        if (n < num - 1) {
            buf[n++] = (char)ch;
        } else {
            too_long = true;
        }
        if (ch == '\n') {
            break;
        }
    }
    if (n == 0 && ch == EOF) {
        return NULL;
    }
    buf[n] = '\0';
    ctx->lineno++;
    ctx->indented = (buf[0] == ' ' || buf[0] == '\t');
    header_check(ctx, buf);
    if (too_long && ctx->err[0] == '\0') {
        snprintf(ctx->err, sizeof ctx->err, "%s:%d: line longer than %d characters (continue a profile on an indented line)",
                 ctx->path, ctx->lineno, num - 2);
        buf[0] = '\0';
    }
    return buf;
}

static int on_key(void *user, const char *section, const char *name, const char *value)
{
    load_ctx_t *ctx = user;
    char where[SCENARIO_ORIGIN_LEN];
    snprintf(where, sizeof where, "%s:%d", ctx->path, ctx->lineno);
    int known = 0;
    int i = find_key(section, name, &known);
    bool append = false;
    if (i >= 0 && ctx->seen[i]) {
        if (KEYS[i].kind != K_PROFILE && KEYS[i].kind != K_RPROFILE) {
            if (ctx->err[0] == '\0') {
                snprintf(ctx->err, sizeof ctx->err, "%s: [%s] %s: given twice (first at %s:%d)",
                         where, section, name, ctx->path, ctx->first_line[i]);
            }
            return 0;
        }
        append = true;   /* continuation line, or the key again: extends the profile */
    }
    char err[SCENARIO_ERR_LEN];
    if (apply(ctx->sc, where, section, name, value, append, err, sizeof err) != 0) {
        if (ctx->err[0] != '\0') {
            return 0;
        }
        if (append && !ctx->indented) {
            /* the key again: say so before what its value lacks as more of the profile */
            char prefix[SCENARIO_ERR_LEN];
            const int n = snprintf(prefix, sizeof prefix, "%s: [%s] %s: ", where, section, name);
            const char *why = (n > 0 && strncmp(err, prefix, (size_t)n) == 0) ? err + n : err;
            err_mark_cut(snprintf(ctx->err, sizeof ctx->err,
                                  "%s: [%s] %s: given twice (first at %s:%d; a repeated profile key adds t:value "
                                  "points to it): %s",
                                  where, section, name, ctx->path, ctx->first_line[i], why),
                         ctx->err, sizeof ctx->err);
        } else {
            snprintf(ctx->err, sizeof ctx->err, "%s", err);
        }
        return 0;
    }
    if (append) {
        snprintf(ctx->sc->origin[i], SCENARIO_ORIGIN_LEN, "%s", ctx->path);
    } else {
        ctx->first_line[i] = ctx->lineno;
    }
    ctx->seen[i] = true;
    return 1;
}

int scenario_load(scenario_t *sc, const char *path, char *err, size_t errlen)
{
    load_ctx_t ctx;
    memset(&ctx, 0, sizeof ctx);
    ctx.sc = sc;
    ctx.path = path;
    ctx.f = fopen(path, "r");
    if (ctx.f == NULL) {
        snprintf(err, errlen, "%s: cannot open: %s", path, strerror(errno));
        return -1;
    }
    int rc = ini_parse_stream(read_line, &ctx, on_key, &ctx);
    fclose(ctx.f);
    if (ctx.err[0] != '\0') {
        snprintf(err, errlen, "%s", ctx.err);
        return -1;
    }
    if (rc != 0) {
        snprintf(err, errlen, "%s:%d: syntax error (expected [section] or key = value)", path, rc);
        return -1;
    }
    return 0;
}

int scenario_set(scenario_t *sc, const char *assignment, char *err, size_t errlen)
{
    char buf[SCENARIO_ERR_LEN];
    char where[SCENARIO_ORIGIN_LEN];
    snprintf(where, sizeof where, "--set %s", assignment);
    if (strlen(assignment) >= sizeof buf) {
        snprintf(err, errlen, "%s: too long", where);
        return -1;
    }
    strcpy(buf, assignment);
    char *eq = strchr(buf, '=');
    char *dot = strchr(buf, '.');
    if (eq == NULL || dot == NULL || dot > eq) {
        snprintf(err, errlen, "%s: expected section.key=value", where);
        return -1;
    }
    *eq = '\0';
    *dot = '\0';
    return apply(sc, where, buf, dot + 1, eq + 1, false, err, errlen);
}

/* ---- cross-key checks ------------------------------------------------------ */

/* Controller value from absolute key abs_i or factor key fac_i (not both) times the plant value. */
static int resolve(scenario_t *sc, const char *abs_name, const char *fac_name, double plant_value,
                   double *abs_v, double fac_v, char *err, size_t errlen)
{
    int known = 0;
    int ia = find_key("controller", abs_name, &known);
    int iff = find_key("controller", fac_name, &known);
    if (!isnan(*abs_v) && !isnan(fac_v)) {
        snprintf(err, errlen, "%s: [controller] %s: conflicts with %s set at %s (give one of them)",
                 sc->origin[ia], abs_name, fac_name, sc->origin[iff]);
        return -1;
    }
    if (isnan(*abs_v)) {
        *abs_v = (isnan(fac_v) ? 1.0 : fac_v) * plant_value;
    }
    return 0;
}

/* method = proposed with step 1 off would run the conventional method
 * unannounced (ctrl.h): refused, naming the fix. */
static int check_identify(const scenario_t *sc, char *err, size_t errlen)
{
    int known = 0;
    const int i_mode = find_key("identify", "mode", &known);
    const int i_method = find_key("controller", "method", &known);
    if (sc->controller.method != SC_METHOD_PROPOSED || sc->identify.mode != SC_RSID_OFF) {
        return 0;
    }
    /* where mode was set to off, else where the method was asked for */
    const char *where = (sc->origin[i_mode][0] != '\0') ? sc->origin[i_mode] : sc->origin[i_method];
    snprintf(err, errlen,
             "%s: [identify] mode: off with [controller] method = proposed: the proposed method needs step 1; "
             "set [identify] mode = windows | speeds (identify R), or trusted (the controller's R_ohm is right), "
             "or method = conventional",
             where);
    return -1;
}

/* [faults] encoder_jump_counts: a count is whole, and within a 32-bit jump. */
static int check_faults(const scenario_t *sc, char *err, size_t errlen)
{
    int known = 0;
    const int i = find_key("faults", "encoder_jump_counts", &known);
    const double n = sc->faults.encoder_jump_counts;
    if (n == floor(n) && fabs(n) <= 2147483647.0) {
        return 0;
    }
    snprintf(err, errlen, "%s: [faults] encoder_jump_counts: %g is not a whole number of counts (|n| < 2^31)",
             sc->origin[i], n);
    return -1;
}

/* [controller] i_limit_A: the targets' current limit must stay below the
 * overcurrent trip, or the drive would trip where it should limit. Set by
 * the user: named; derived: the rating and the ADC range named. */
static int check_limits(const scenario_t *sc, char *err, size_t errlen)
{
    int known = 0;
    const int i = find_key("controller", "i_limit_A", &known);
    const int i_pk = find_key("motor", "i_peak_A", &known);
    const int i_ir = find_key("motor", "i_rated_A", &known);
    if (sc->controller.i_limit_A < sc->controller.i_max_A) {
        return 0;
    }
    if (sc->origin[i][0] != '\0') {
        snprintf(err, errlen, "%s: [controller] i_limit_A: %g A is not below the overcurrent trip i_max_A (%g A)",
                 sc->origin[i], sc->controller.i_limit_A, sc->controller.i_max_A);
        return -1;
    }
    const char *where = (sc->origin[i_pk][0] != '\0') ? sc->origin[i_pk] : sc->origin[i_ir];
    snprintf(err, errlen,
             "%s: [motor] i_peak_A: the current limit it asks for (i_limit_A %g A) reaches the overcurrent trip "
             "(i_max_A %g A: 1.26 x i_peak_A, at most 14/15 of [plant] adc_full_scale_A = %g A): a rated "
             "current beyond the ADC's range; a wider ADC range or a lower i_peak_A",
             (where[0] != '\0') ? where : "[motor]", sc->controller.i_limit_A, sc->controller.i_max_A,
             sc->plant.adc_full_scale_A);
    return -1;
}

/* The keys where a finished scenario's value of a derived key came from. */
typedef struct {
    const char *section, *name;
    size_t p_offset;           /* of the float in drive_params_t */
    double scale;              /* key unit per parameter unit */
} sc_derived_t;
#define D(s, k, f, scale, from) { s, k, offsetof(drive_params_t, f), scale },
static const sc_derived_t DERIVED_KEYS[] = { DRIVE_DERIVED_KEYS(D) };
#undef D

/* A key's value into the parameter set: NaN (left to derive) as DRIVE_PARAM_DERIVED. */
static float told_or_derived(double v, double scale)
{
    return isnan(v) ? DRIVE_PARAM_DERIVED : (float)(v / scale);
}

void scenario_params(const scenario_t *sc, drive_params_t *p)
{
    hal_sim_cfg_t hs;
    hal_sim_default_cfg(&hs);
    drive_params_board(p);
    p->motor.R_Ohm = (float)sc->controller.R_ohm;
    p->motor.L_H = (float)sc->controller.L_H;
    p->motor.psi_f_Wb = (float)sc->controller.psif_Wb;
    p->motor.pole_pairs = (uint16_t)sc->controller.pole_pairs;   /* what the controller is told */
    p->motor.J_kgm2 = (float)sc->controller.J_kgm2;
    p->motor.B_Nms = (float)sc->controller.B_Nms;
    p->rating.i_rated_A = (float)sc->motor.i_rated_A;
    p->rating.i_peak_A = (float)(isnan(sc->motor.i_peak_A) ? 2.0 * sc->motor.i_rated_A : sc->motor.i_peak_A);
    p->rating.t_peak_s = (float)sc->motor.t_peak_s;
    p->rating.n_rated_rad_s = (float)(sc->motor.n_rated_rpm / SIM_RPM_PER_RAD_S);
    p->rating.n_max_rad_s = (float)((isnan(sc->motor.n_max_rpm) ? sc->motor.n_rated_rpm : sc->motor.n_max_rpm) /
                                    SIM_RPM_PER_RAD_S);
    p->board.Ts_s = (float)hs.inv.Ts_s;
    /* the dead time as if measured, unless the scenario gives the controller another */
    p->board.deadtime_s = (float)(isnan(sc->controller.deadtime_s) ? sc->plant.deadtime_s : sc->controller.deadtime_s);
    /* the board's bus limits relative to its nominal bus, at the scenario's bus */
    const float bus_scale = (float)sc->plant.vdc_V / p->board.vdc_nominal_V;
    p->limits.vdc_max_V = p->limits.vdc_max_V * bus_scale;
    p->limits.vdc_min_V = p->limits.vdc_min_V * bus_scale;
    p->board.vdc_nominal_V = (float)sc->plant.vdc_V;
    p->board.i_full_scale_A = (float)sc->plant.adc_full_scale_A;
    p->board.enc_lines = sc->plant.encoder_lines;
    /* align off: told [controller] encoder_offset_el_rad, else the plant's as if measured;
     * on: the alignment's measurement replaces it */
    const double enc_told = isnan(sc->controller.encoder_offset_el_rad) ? sc->plant.encoder_offset_el_rad
                                                                        : sc->controller.encoder_offset_el_rad;
    p->board.enc_offset_el_rad = (sc->run.align == SC_ON) ? 0.0f : (float)enc_told;
    p->tuning.speed_bw_rad_s = (float)sc->controller.speed_bw_rad_s;
    p->tuning.pll_bw_rad_s = (float)sc->controller.pll_bw_rad_s;
    p->tuning.R_min_Ohm = isnan(sc->controller.R_min_ohm) ? p->tuning.R_min_Ohm : (float)sc->controller.R_min_ohm;
    p->tuning.R_max_Ohm = isnan(sc->controller.R_max_ohm) ? p->tuning.R_max_Ohm : (float)sc->controller.R_max_ohm;
    for (size_t j = 0; j < sizeof DERIVED_KEYS / sizeof DERIVED_KEYS[0]; j++) {
        int known = 0;
        const sc_derived_t *d = &DERIVED_KEYS[j];
        const int i = find_key(d->section, d->name, &known);
        const double v = real_value(sc, &KEYS[i]);
        *(float *)(void *)((char *)p + d->p_offset) = told_or_derived(v, d->scale);
    }
}

int scenario_key_set(const scenario_t *sc, const char *section, const char *name)
{
    int known = 0;
    const int i = find_key(section, name, &known);
    return (i >= 0 && sc->origin[i][0] != '\0') ? 1 : 0;
}

void scenario_warnings(const scenario_t *sc, char *buf, size_t len)
{
    buf[0] = '\0';
    if ((sc->derive_status & DRIVE_DERIVE_WARN_BEMF) != 0u) {
        const double n_max = isnan(sc->motor.n_max_rpm) ? sc->motor.n_rated_rpm : sc->motor.n_max_rpm;
        const double e_V = n_max / SIM_RPM_PER_RAD_S * (double)sc->controller.pole_pairs * sc->controller.psif_Wb;
        snprintf(buf, len,
                 "BEMF_ABOVE_BUS: the back-EMF at [motor] n_max_rpm = %g r/min is %.4g V, beyond the bus's "
                 "phase-voltage limit [plant] vdc_V / sqrt(3) = %.4g V (a trip there generates into the bus)",
                 n_max, e_V, sc->plant.vdc_V / sqrt(3.0));
    }
}

/* The derived keys left unset: derived from the motor's data (drive_params_derive);
 * a motor the drive cannot run refused, naming the keys. */
static int derive_keys(scenario_t *sc, char *err, size_t errlen)
{
    drive_params_t p;
    int known = 0;
    const int i_ir = find_key("motor", "i_rated_A", &known);
    scenario_params(sc, &p);
    const drive_derive_t st = drive_params_derive(&p);
    sc->derive_status = st;
    if ((st & DRIVE_DERIVE_RATINGS) != 0u) {
        snprintf(err, errlen,
                 "%s: [motor]: ratings do not fit: i_rated_A %g A, i_peak_A %g A (>= i_rated_A), t_peak_s %g s, "
                 "n_rated_rpm %g, n_max_rpm %g (>= n_rated_rpm)",
                 (sc->origin[i_ir][0] != '\0') ? sc->origin[i_ir] : "[motor]", (double)p.rating.i_rated_A,
                 (double)p.rating.i_peak_A, (double)p.rating.t_peak_s, (double)p.rating.n_rated_rad_s * SIM_RPM_PER_RAD_S,
                 (double)p.rating.n_max_rad_s * SIM_RPM_PER_RAD_S);
        return -1;
    }
    if ((st & DRIVE_DERIVE_OBSERVER) != 0u && sc->controller.method == SC_METHOD_PROPOSED) {
        ctrl_obs_gains_t g;
        float G_max;
        (void)drive_params_obs_gains(&p, &g, &G_max);
        snprintf(err, errlen,
                 "[controller] L_H, R_ohm: no observer gain for this motor: the discrete stability bound with "
                 "L^'s floor at half the told L (%g H) allows G = Ks/phi <= %.4g V/A at Ts = %g s, and eq. (36) "
                 "then accepts R^ only up to %.4g ohm, below the told R_ohm %g ohm (a shorter PWM period or "
                 "method = conventional)",
                 sc->controller.L_H, (double)G_max, (double)p.board.Ts_s, 0.45 * (double)G_max, sc->controller.R_ohm);
        return -1;
    }
    for (size_t j = 0; j < sizeof DERIVED_KEYS / sizeof DERIVED_KEYS[0]; j++) {
        const sc_derived_t *d = &DERIVED_KEYS[j];
        const int i = find_key(d->section, d->name, &known);
        double *v = (double *)field(sc, &KEYS[i]);
        if (isnan(*v)) {
            *v = (double)*(const float *)(const void *)((const char *)&p + d->p_offset) * d->scale;
        }
    }
    return 0;
}

/* Level 4's current limit: below the limit of the full drive. */
static int check_level(const scenario_t *sc, char *err, size_t errlen)
{
    int known = 0;
    const int i = find_key("run", "level4_i_limit_A", &known);
    if (sc->run.level4_i_limit_A <= sc->controller.i_limit_A) {
        return 0;
    }
    snprintf(err, errlen, "%s: [run] level4_i_limit_A: %g A is above [controller] i_limit_A (%g A)",
             sc->origin[i], sc->run.level4_i_limit_A, sc->controller.i_limit_A);
    return -1;
}

/* Where bound b's value came from, for its message: the key's line, else
 * (a controller value from its factor) the factor's, else the plant's. */
static const char *bound_origin(const scenario_t *sc, const sc_bound_t *b, char *how, size_t howlen)
{
    int known = 0;
    const int i = find_key(b->section, b->name, &known);
    how[0] = '\0';
    if (sc->origin[i][0] != '\0' || b->factor == NULL) {
        return (sc->origin[i][0] != '\0') ? sc->origin[i] : "the defaults";
    }
    const int f = find_key("controller", b->factor, &known);
    const int p = find_key("plant", b->name, &known);
    const double fac = *(const double *)(const void *)((const char *)sc + KEYS[f].offset);
    snprintf(how, howlen, " (%s %g x [plant] %s)", b->factor, isnan(fac) ? 1.0 : fac, b->name);
    if (sc->origin[f][0] != '\0') {
        return sc->origin[f];
    }
    return (sc->origin[p][0] != '\0') ? sc->origin[p] : "the defaults";
}

/* The first value of bound b outside it (*v; for a profile of several
 * points, its time *t_s, else NaN); false if none. */
static bool bound_broken(const scenario_t *sc, const sc_bound_t *b, double *v, double *t_s)
{
    const char *at = (const char *)sc + b->offset;
    *t_s = NAN;
    if (b->kind == B_PROFILE) {
        const profile_t *pr = (const profile_t *)(const void *)at;
        for (uint32_t n = 0; n < pr->n; n++) {
            *v = pr->pt[n].value;
            if (!(*v >= b->lo && *v <= b->hi)) {
                *t_s = (pr->n > 1u) ? pr->pt[n].t_s : NAN;
                return true;
            }
        }
        return false;
    }
    *v = (b->kind == B_UINT) ? (double)*(const uint32_t *)(const void *)at : *(const double *)(const void *)at;
    /* NaN: a derived key not yet derived (derive_keys runs after) */
    return !isnan(*v) && !(*v >= b->lo && *v <= b->hi);
}

/* Every BOUNDS value within its bound; else err names key, value and bound. */
static int check_bounds(const scenario_t *sc, char *err, size_t errlen)
{
    for (int j = 0; j < N_BOUNDS; j++) {
        const sc_bound_t *b = &BOUNDS[j];
        double v = 0.0;
        double t_s = NAN;
        if (!bound_broken(sc, b, &v, &t_s)) {
            continue;
        }
        char how[SCENARIO_ORIGIN_LEN];
        const char *where = bound_origin(sc, b, how, sizeof how);
        if (!isnan(t_s)) {
            snprintf(how, sizeof how, " (at t = %g s)", t_s);
        }
        const char *sp = (b->unit[0] != '\0') ? " " : "";
        err_mark_cut(snprintf(err, errlen, "%s: [%s] %s: %g%s%s%s is not plausible: the bound is %g .. %g%s%s", where,
                              b->section, b->name, v, sp, b->unit, how, b->lo, b->hi, sp, b->unit),
                     err, errlen);
        return -1;
    }
    return 0;
}

int scenario_finish(scenario_t *sc, char *err, size_t errlen)
{
    if (sc->controller.pole_pairs == 0u) {
        sc->controller.pole_pairs = sc->plant.pole_pairs;
    }
    if (resolve(sc, "R_ohm", "R_factor", sc->plant.R_ohm, &sc->controller.R_ohm,
                sc->controller.R_factor, err, errlen) != 0 ||
        resolve(sc, "L_H", "L_factor", sc->plant.L_H, &sc->controller.L_H,
                sc->controller.L_factor, err, errlen) != 0 ||
        resolve(sc, "psif_Wb", "psif_factor", sc->plant.psif_Wb, &sc->controller.psif_Wb,
                sc->controller.psif_factor, err, errlen) != 0) {
        return -1;
    }
    if (isnan(sc->controller.J_kgm2)) {
        sc->controller.J_kgm2 = sc->plant.J_kgm2;
    }
    if (isnan(sc->controller.B_Nms)) {
        sc->controller.B_Nms = sc->plant.B_Nms;
    }
    if (check_bounds(sc, err, errlen) != 0 || derive_keys(sc, err, errlen) != 0) {
        return -1;
    }
    /* level 4's limit from the current limit, derived or set */
    if (isnan(sc->run.level4_i_limit_A)) {
        sc->run.level4_i_limit_A = SC_LEVEL4_I_LIMIT_PER_LIMIT * sc->controller.i_limit_A;
    }
    if (check_level(sc, err, errlen) != 0 || check_faults(sc, err, errlen) != 0 ||
        check_limits(sc, err, errlen) != 0) {
        return -1;
    }
    return check_identify(sc, err, errlen);
}

void scenario_print_keys(FILE *f)
{
    const char *section = "";
    for (int i = 0; i < N_KEYS; i++) {
        const sc_key_t *k = &KEYS[i];
        if (strcmp(k->section, section) != 0) {
            section = k->section;
            fprintf(f, "  [%s]\n", section);
        }
        char buf[32];
        const char *text = default_text(k, buf, sizeof buf);
        const char *def = (k->def == DERIVED) ? "derived" : ((text == NULL) ? "-" : ((k->kind == K_PROFILE) ? "0" : text));
        fprintf(f, "    %-22s %-13s %s\n", k->name, def, k->help);
    }
}

void scenario_print_bounds(FILE *f)
{
    fprintf(f, "Plausibility bounds (a value outside is refused, exit 2; the controller's after its factor):\n");
    for (int j = 0; j < N_BOUNDS; j++) {
        const sc_bound_t *b = &BOUNDS[j];
        char key[SCENARIO_ORIGIN_LEN];
        snprintf(key, sizeof key, "[%s] %s", b->section, b->name);
        fprintf(f, "    %-26s %g .. %g%s%s\n", key, b->lo, b->hi, (b->unit[0] != '\0') ? " " : "", b->unit);
    }
}
