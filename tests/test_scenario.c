/* Unit tests for tools/sil/scenario.c and profile.c: defaults from Table I,
 * parsing of every key kind, profiles (steps, ramps, continuation lines),
 * and every bad-input case, whose message must name file, line and key. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "drive_params.h"
#include "hal_sim.h"
#include "link_params.h"
#include "scenario.h"

#define TOL 1e-12

static char g_path[64];

/* Write text to a fresh temporary file; its name in g_path. */
static const char *write_ini(const char *text)
{
    snprintf(g_path, sizeof g_path, "/tmp/test_scenario_XXXXXX");
    int fd = mkstemp(g_path);
    assert_true(fd >= 0);
    FILE *f = fdopen(fd, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
    return g_path;
}

static int load_text(scenario_t *sc, const char *text, char *err)
{
    scenario_defaults(sc);
    const char *p = write_ini(text);
    int rc = scenario_load(sc, p, err, SCENARIO_ERR_LEN);
    if (rc == 0) {
        rc = scenario_finish(sc, err, SCENARIO_ERR_LEN);
    }
    unlink(p);
    return rc;
}

/* The error must be rejected and name "<file>:<line>" and the key. */
static void expect_error(const char *text, int line, const char *key)
{
    scenario_t sc;
    char err[SCENARIO_ERR_LEN] = "";
    int rc = load_text(&sc, text, err);
    char where[96];
    snprintf(where, sizeof where, "%s:%d:", g_path, line);
    print_message("  -> %s\n", err);
    assert_int_equal(rc, -1);
    assert_non_null(strstr(err, where));
    assert_non_null(strstr(err, key));
}

static void defaults_are_table1(void **state)
{
    (void)state;
    scenario_t sc;
    char err[SCENARIO_ERR_LEN];
    scenario_defaults(&sc);
    assert_int_equal(scenario_finish(&sc, err, sizeof err), 0);
    assert_float_equal(sc.plant.R_ohm, 3.0, TOL);
    assert_float_equal(sc.plant.L_H, 0.011, TOL);
    assert_float_equal(sc.plant.psif_Wb, 0.24, TOL);
    assert_int_equal(sc.plant.pole_pairs, 3);
    assert_float_equal(sc.plant.J_kgm2, 0.00129, TOL);
    assert_float_equal(sc.plant.vdc_V, 311.0, TOL);
    assert_int_equal(sc.plant.encoder_lines, 2500);
    assert_int_equal(sc.plant.model, SC_MODEL_AVERAGED);
    assert_float_equal(sc.controller.R_ohm, 3.0, TOL);
    assert_float_equal(sc.controller.L_H, 0.011, TOL);
    assert_float_equal(sc.controller.psif_Wb, 0.24, TOL);
    assert_int_equal(sc.run.log_every, 10);
    assert_float_equal(profile_eval(&sc.reference.speed_rpm, 0.5), 0.0, TOL);
}

/* The defaults marked "params" are the drive's parameter set (the board's,
 * firmware/params/drive_params.h) as the decimals board_cfg.h spells: 0.011f
 * reads exactly 0.011 in the double plant, not 0.0109999999. */
static void defaults_come_from_the_parameter_set(void **state)
{
    (void)state;
    scenario_t sc;
    drive_params_t p;
    scenario_defaults(&sc);
    drive_params_board(&p);
    assert_true(sc.plant.L_H == 0.011);
    assert_true(sc.plant.psif_Wb == 0.24);
    assert_float_equal(sc.plant.L_H, p.motor.L_H, 1e-9);
    assert_float_equal(sc.plant.J_kgm2, p.motor.J_kgm2, 1e-12);
    assert_int_equal(sc.plant.encoder_lines, p.board.enc_lines);
    assert_float_equal(sc.controller.pll_bw_rad_s, p.tuning.pll_bw_rad_s, 0.0);
    /* the ratings: the paper motor's (5.56 A = 6 N m / (1.5 x 3 x 0.24)), every digit of the float */
    assert_true((float)sc.motor.i_rated_A == p.rating.i_rated_A);
    assert_true(isnan(sc.motor.i_peak_A));   /* 2 x i_rated */
    assert_float_equal(sc.motor.n_rated_rpm, 2000.0, 1e-3);
    /* derived keys: unset until scenario_finish derives them from the motor's data */
    assert_true(isnan(sc.controller.te_max_Nm));
    assert_true(isnan(sc.identify.settle_1_s));
    char err[SCENARIO_ERR_LEN];
    assert_int_equal(scenario_finish(&sc, err, sizeof err), 0);
    static app_cfg_t app_cfg;
    app_cfg_default(&app_cfg);
    assert_float_equal(sc.controller.i_max_A, app_cfg.prot.i_max_A, 0.0);
    assert_float_equal(sc.controller.te_max_Nm, app_cfg.ctrl.te_max_Nm, 0.0);
    assert_float_equal(sc.controller.speed_kp_Nms_rad, 0.5, 0.0);
    assert_float_equal(sc.controller.speed_ki_Nm_rad, 20.0, 0.0);
    /* 1.2 x 2000 r/min, from rad/s back to the key's unit */
    assert_float_equal(sc.controller.overspeed_rpm, 2400.0, 1e-3);
    /* step 1's timing: derived as the app's start-up settings (app_cfg_default) */
    assert_float_equal(sc.identify.settle_1_s, app_cfg.rsid.settle_1_s, 0.0);
    assert_float_equal(sc.identify.settle_1_s, 0.28, 1e-7);
    assert_float_equal(sc.identify.window_s, app_cfg.rsid.window_s, 1e-9);
    assert_float_equal(sc.identify.speed_2_rpm, 1000.0, 0.0);
    assert_int_equal(sc.identify.repeats_max, app_cfg.rsid.repeats_max);
    /* step 1's checks and policies: the app's too (board_cfg.h, rs_ident.h) */
    assert_true(sc.identify.R_se_max_rel == 0.015);
    assert_float_equal(sc.identify.R_se_max_rel, app_cfg.ctrl.est_cfg.rsid.R_se_max_rel, 1e-9);
    assert_true(sc.identify.batch_s == 0.005);  /* 50 periods of 0.1 ms */
    assert_int_equal(llround(sc.identify.batch_s / app_cfg.ctrl.Ts_s), app_cfg.ctrl.est_cfg.rsid.n_batch);
    assert_int_equal(sc.identify.mode, app_cfg.rsid.mode);
    assert_int_equal(sc.identify.on_refusal, app_cfg.rsid.on_refusal);
    assert_int_equal(sc.identify.track_R, app_cfg.ctrl.est_cfg.track_R);
    assert_float_equal(sc.plant.encoder_offset_el_rad, p.board.enc_offset_el_rad, 0.0);
    /* the simulated board's own settings: hal_sim_default_cfg()'s (hal_sim.h) */
    assert_true(sc.plant.substep_s == 1e-4);
    assert_true(sc.plant.trip_A == 15.0);
    assert_true(sc.plant.adc_full_scale_A == 15.0);
    assert_int_equal(sc.plant.seed, 1u);
    assert_int_equal(sc.plant.model, SC_MODEL_AVERAGED);
    assert_true(sc.plant.deadtime_s == 0.0);
    assert_true(sc.plant.adc_noise_A == 0.0);
}

static void parses_every_kind(void **state)
{
    (void)state;
    scenario_t sc;
    char err[SCENARIO_ERR_LEN] = "";
    int rc = load_text(&sc,
                       "; a comment\n"
                       "[plant]\n"
                       "R_ohm = 3.3\n"
                       "model = switching\n"
                       "encoder_lines = 1024\n"
                       "deadtime_s = 2e-6\n"
                       "[controller]\n"
                       "L_factor = 1.5\n"
                       "psif_Wb = 0.2\n"
                       "method = proposed\n"
                       "mode = torque\n"
                       "[identify]\n"
                       "mode = windows\n"
                       "R_se_max_rel = 0.02\n"
                       "[reference]\n"
                       "torque_Nm = 0:0, 0.1:4, 0.3:6~\n"
                       "  0.5:0\n"
                       "[load]\n"
                       "torque_Nm = 2\n"
                       "[run]\n"
                       "duration_s = 0.6\n"
                       "log_every = 1\n",
                       err);
    assert_int_equal(rc, 0);
    assert_float_equal(sc.plant.R_ohm, 3.3, TOL);
    assert_int_equal(sc.plant.model, SC_MODEL_SWITCHING);
    assert_int_equal(sc.plant.encoder_lines, 1024);
    assert_float_equal(sc.plant.deadtime_s, 2e-6, TOL);
    assert_float_equal(sc.controller.R_ohm, 3.3, TOL);         /* default factor 1 x plant */
    assert_float_equal(sc.controller.L_H, 1.5 * 0.011, TOL);
    assert_float_equal(sc.controller.psif_Wb, 0.2, TOL);
    assert_int_equal(sc.controller.method, SC_METHOD_PROPOSED);
    assert_int_equal(sc.controller.mode, SC_MODE_TORQUE);
    assert_int_equal(sc.identify.mode, SC_RSID_WINDOWS);
    assert_float_equal(sc.identify.R_se_max_rel, 0.02, TOL);
    const profile_t *p = &sc.reference.torque_Nm;
    assert_int_equal(p->n, 4);
    assert_float_equal(profile_eval(p, 0.05), 0.0, TOL);
    assert_float_equal(profile_eval(p, 0.1), 4.0, TOL);
    assert_float_equal(profile_eval(p, 0.2), 5.0, TOL);      /* halfway up the ramp */
    assert_float_equal(profile_eval(p, 0.4), 6.0, TOL);
    assert_float_equal(profile_eval(p, 0.5), 0.0, TOL);      /* continuation line */
    assert_float_equal(profile_eval(&sc.load.torque_Nm, 0.0), 2.0, TOL);
    assert_float_equal(sc.run.duration_s, 0.6, TOL);
    assert_int_equal(sc.run.log_every, 1);
}

/* Bits of a double, so NaN compares to NaN. */
static int same_bits(double a, double b)
{
    return memcmp(&a, &b, sizeof a) == 0;
}

/* The cursor answers profile_eval's value bit for bit, forwards on a
 * period's grid, backwards, at the points' own times and for NaN. */
static void profile_cursor_equals_eval(void **state)
{
    (void)state;
    profile_t p = { 0 };
    char err[SCENARIO_ERR_LEN];
    assert_int_equal(profile_parse_append(&p, "0.1:2, 0.3:5~, 0.5:5, 0.6:-1~, 0.8:3", err, sizeof err), 0);
    profile_cursor_t c;
    profile_cursor_init(&c, &p);
    assert_float_equal(profile_cursor_eval(&c, 0.05), 0.0, TOL);   /* hand values */
    assert_float_equal(profile_cursor_eval(&c, 0.2), 3.5, TOL);    /* halfway up 2 -> 5 */
    assert_float_equal(profile_cursor_eval(&c, 0.55), 2.0, TOL);   /* halfway down 5 -> -1 */
    assert_float_equal(profile_cursor_eval(&c, 0.9), 3.0, TOL);
    assert_float_equal(profile_cursor_eval(&c, 0.15), 2.75, TOL);  /* backwards */
    const double Ts = 1e-4;
    for (int k = -100; k < 10000; k++) {
        const double t = (double)k * Ts;
        assert_true(same_bits(profile_cursor_eval(&c, t), profile_eval(&p, t)));
    }
    for (int k = 10000; k > -100; k -= 7) {
        const double t = (double)k * Ts;
        assert_true(same_bits(profile_cursor_eval(&c, t), profile_eval(&p, t)));
    }
    for (uint32_t k = 0; k < p.n; k++) {
        assert_true(same_bits(profile_cursor_eval(&c, p.pt[k].t_s), profile_eval(&p, p.pt[k].t_s)));
    }
    assert_true(same_bits(profile_cursor_eval(&c, NAN), profile_eval(&p, NAN)));
    assert_true(same_bits(profile_cursor_eval(&c, 0.2), profile_eval(&p, 0.2)));
    profile_t empty = { 0 };
    profile_cursor_init(&c, &empty);
    assert_true(same_bits(profile_cursor_eval(&c, 0.3), 0.0));
}

static void profile_rules(void **state)
{
    (void)state;
    profile_t p = { 0 };
    char err[SCENARIO_ERR_LEN];
    assert_int_equal(profile_parse_append(&p, "0.2:10", err, sizeof err), 0);
    assert_float_equal(profile_eval(&p, 0.1), 0.0, TOL);     /* 0 before the first point */
    assert_float_equal(profile_eval(&p, 0.2), 10.0, TOL);
    p.n = 0;
    assert_int_equal(profile_parse_append(&p, "0.2:10~", err, sizeof err), 0);
    assert_float_equal(profile_eval(&p, 0.1), 5.0, TOL);     /* ramp from 0 at t = 0 */
    p.n = 0;
    assert_int_equal(profile_parse_append(&p, "-7.5", err, sizeof err), 0);
    assert_float_equal(profile_eval(&p, 3.0), -7.5, TOL);
    p.n = 0;
    assert_int_equal(profile_parse_append(&p, "0:1, 0.1:2", err, sizeof err), 0);
    assert_int_equal(profile_parse_append(&p, "0.1:3", err, sizeof err), -1);   /* time not increasing */
    assert_int_equal(p.n, 2);                                                     /* unchanged */
    assert_int_equal(profile_parse_append(&p, "0.2:x", err, sizeof err), -1);
    assert_int_equal(profile_parse_append(&p, "0.2 3", err, sizeof err), -1);
    assert_int_equal(profile_parse_append(&p, "0.2:3,", err, sizeof err), -1);
    assert_int_equal(profile_parse_append(&p, "0.2:3 0.3:4", err, sizeof err), -1);
}

static void set_overrides_and_replaces_profiles(void **state)
{
    (void)state;
    scenario_t sc;
    char err[SCENARIO_ERR_LEN] = "";
    scenario_defaults(&sc);
    assert_int_equal(scenario_set(&sc, "reference.speed_rpm=0:0, 0.1:500", err, sizeof err), 0);
    assert_int_equal(scenario_set(&sc, "reference.speed_rpm=0:100", err, sizeof err), 0);
    assert_int_equal(sc.reference.speed_rpm.n, 1);
    assert_int_equal(scenario_set(&sc, "plant.J_kgm2=0.01", err, sizeof err), 0);
    assert_float_equal(sc.plant.J_kgm2, 0.01, TOL);
    assert_int_equal(scenario_set(&sc, "plant.J_kgm2", err, sizeof err), -1);
    assert_non_null(strstr(err, "--set plant.J_kgm2"));
    assert_int_equal(scenario_set(&sc, "plantJ=1", err, sizeof err), -1);
    assert_int_equal(scenario_set(&sc, "plant.nokey=1", err, sizeof err), -1);
    assert_non_null(strstr(err, "nokey"));
    assert_int_equal(scenario_set(&sc, "controller.mode=fast", err, sizeof err), -1);
    assert_non_null(strstr(err, "mode"));
}

/* [plant] R_ohm: a number or a positive profile from t = 0; R_ohm holds
 * its value at t = 0, which the controller's factor multiplies. */
static void plant_resistance_profile(void **state)
{
    (void)state;
    scenario_t sc;
    char err[SCENARIO_ERR_LEN] = "";
    int rc = load_text(&sc,
                       "[plant]\n"
                       "R_ohm = 0:3.0, 2:3.9~\n"
                       "device_drop_V = 1.2\n"
                       "[controller]\n"
                       "R_factor = 2\n",
                       err);
    assert_int_equal(rc, 0);
    assert_float_equal(sc.plant.R_ohm, 3.0, TOL);
    assert_float_equal(profile_eval(&sc.plant.R_ohm_profile, 1.0), 3.45, TOL);
    assert_float_equal(profile_eval(&sc.plant.R_ohm_profile, 5.0), 3.9, TOL);
    assert_float_equal(sc.plant.device_drop_V, 1.2, TOL);
    assert_float_equal(sc.controller.R_ohm, 6.0, TOL);
    scenario_defaults(&sc);
    assert_int_equal(sc.plant.R_ohm_profile.n, 1);
    assert_float_equal(profile_eval(&sc.plant.R_ohm_profile, 3.0), 3.0, TOL);
    expect_error("[plant]\nR_ohm = 1:3.0, 2:3.9~\n", 2, "start at t = 0");
    expect_error("[plant]\nR_ohm = 0:3.0, 2:0~\n", 2, "R_ohm");
    expect_error("[plant]\ndevice_drop_V = -1\n", 2, "device_drop_V");
}

/* The small motor of the any-motor campaign with only its data: the
 * derived keys follow it (hand values: kt = 0.048 N m/A, i_peak 12.5 A,
 * te_max 0.6 N m, kp = 0.5 x 2e-5/0.00129, speeds 750/1500 r/min). */
static const char SMALL[] = "[plant]\nR_ohm = 0.1\nL_H = 0.0002\npsif_Wb = 0.008\npole_pairs = 4\n"
                            "J_kgm2 = 2e-5\nvdc_V = 24\n[motor]\ni_rated_A = 6.25\nn_rated_rpm = 3000\n"
                            "[controller]\nmethod = proposed\n[identify]\nmode = speeds\n";

static void motor_section_derives_the_keys(void **state)
{
    (void)state;
    scenario_t sc;
    char err[SCENARIO_ERR_LEN] = "";
    assert_int_equal(load_text(&sc, SMALL, err), 0);
    assert_float_equal(sc.controller.te_max_Nm, 0.6, 1e-5);
    assert_float_equal(sc.controller.speed_kp_Nms_rad, 0.5 * 2e-5 / 0.00129, 1e-7);
    assert_float_equal(sc.identify.speed_1_rpm, 750.0, 1e-3);
    assert_float_equal(sc.identify.speed_2_rpm, 1500.0, 1e-3);
    assert_float_equal(sc.controller.overspeed_rpm, 3600.0, 1e-2);
    assert_float_equal(sc.controller.J_kgm2, 2e-5, 1e-12);   /* told: the plant's */
    assert_int_equal(scenario_key_set(&sc, "controller", "te_max_Nm"), 0);
    /* a key an override sets stays and is marked set */
    scenario_defaults(&sc);
    const char *path = write_ini(SMALL);
    assert_int_equal(scenario_load(&sc, path, err, sizeof err), 0);
    unlink(path);
    assert_int_equal(scenario_set(&sc, "controller.te_max_Nm=0.5", err, sizeof err), 0);
    assert_int_equal(scenario_finish(&sc, err, sizeof err), 0);
    assert_float_equal(sc.controller.te_max_Nm, 0.5, 0.0);
    assert_int_equal(scenario_key_set(&sc, "controller", "te_max_Nm"), 1);
}

/* A [campaign] section is skipped whatever it holds (drive-campaign's
 * distributions), the sections around it are read as without it; a key
 * unknown to drive_sil outside it is still refused. */
static void campaign_section_is_skipped(void **state)
{
    (void)state;
    scenario_t with;
    scenario_t without;
    char err[SCENARIO_ERR_LEN] = "";
    assert_int_equal(load_text(&without, SMALL, err), 0);
    static char text[sizeof SMALL + 256];
    snprintf(text, sizeof text,
             "[campaign]\nR_factor = loguniform 0.7 1.3\nno_such_key = ???\n  indented more\n%s"
             "[campaign]\nspeed_frac = uniform 0.1 0.9\n", SMALL);
    assert_int_equal(load_text(&with, text, err), 0);
    assert_float_equal(with.plant.R_ohm, without.plant.R_ohm, 0.0);
    assert_float_equal(with.controller.R_ohm, without.controller.R_ohm, 0.0);
    assert_float_equal(with.controller.te_max_Nm, without.controller.te_max_Nm, 0.0);
    assert_int_equal(with.identify.mode, without.identify.mode);
    expect_error("[campaign]\nR_factor = 2\n[plant]\nR_factor = 2\n", 4, "R_factor");
}

/* A motor the drive cannot run: refused naming the keys. */
static void motor_the_drive_cannot_run_refused(void **state)
{
    (void)state;
    scenario_t sc;
    char err[SCENARIO_ERR_LEN] = "";
    /* L 15 uH with 0.1 ohm at 10 kHz: L/R 1.5 periods, no observer gain (proposed only) */
    assert_int_equal(load_text(&sc, "[plant]\nR_ohm = 0.1\nL_H = 15e-6\n[controller]\nmethod = proposed\n"
                                    "[identify]\nmode = speeds\n", err), -1);
    print_message("  -> %s\n", err);
    assert_non_null(strstr(err, "[controller] L_H, R_ohm: no observer gain"));
    assert_non_null(strstr(err, "L/R = 0.00015 s is 1.5 PWM periods (Ts = 0.0001 s)"));
    assert_int_equal(load_text(&sc, "[plant]\nR_ohm = 0.1\nL_H = 15e-6\n", err), 0);   /* conventional runs */
    /* the D5065's 39 mOhm, 15.7 uH: 4 periods, accepted */
    assert_int_equal(load_text(&sc, "[plant]\nR_ohm = 0.039\nL_H = 15.7e-6\n[controller]\nmethod = proposed\n"
                                    "[identify]\nmode = speeds\n", err), 0);
    /* a rated current beyond the 15 A ADC */
    expect_error("[motor]\ni_rated_A = 10\n", 2, "i_peak_A");
    expect_error("[motor]\ni_rated_A = 5\ni_peak_A = 4\n", 2, "ratings do not fit");
    /* back-EMF at n_max beyond the bus: a warning naming the keys, no refusal */
    assert_int_equal(load_text(&sc, "[motor]\nn_max_rpm = 2500\n", err), 0);
    char w[SCENARIO_ERR_LEN];
    scenario_warnings(&sc, w, sizeof w);
    assert_non_null(strstr(w, "BEMF_ABOVE_BUS"));
    assert_non_null(strstr(w, "n_max_rpm"));
    assert_int_equal(load_text(&sc, "", err), 0);
    scenario_warnings(&sc, w, sizeof w);
    assert_string_equal(w, "");
}

/* Inputs whose first message used to name a symptom: an empty value, a
 * key given again, a section line without its ']', a key before any
 * section - each named as what it is, at its own line. */
static void messages_name_the_real_problem(void **state)
{
    (void)state;
    expect_error("[plant]\nR_ohm =\n", 2, "[plant] R_ohm: no value");
    expect_error("[plant]\nL_H =\n", 2, "[plant] L_H: no value");
    expect_error("[reference]\nspeed_rpm =\n", 2, "[reference] speed_rpm: no value");
    expect_error("[plant]\nL_H = 0.01\n\nL_H = 0.02\n", 4, "[plant] L_H: given twice (first at");
    expect_error("[plant]\nR_ohm = 3\nR_ohm = 4\n", 3, "[plant] R_ohm: given twice (first at");
    expect_error("[plant\nL_H = 0.01\n", 1, "section line \"[plant\" has no closing ']'");
    expect_error("[plant]\nL_H = 0.01\n [controller\n", 3, "no closing ']'");
    expect_error("L_H = 0.01\n", 1, "L_H: a key before any [section] line");
    /* a profile continued on an indented line, or by the key again with t:value points, still extends it */
    scenario_t sc;
    char err[SCENARIO_ERR_LEN] = "";
    assert_int_equal(load_text(&sc, "[reference]\nspeed_rpm = 0:0, 0.1:500\n  0.2:100\nspeed_rpm = 0.3:50\n", err), 0);
    assert_int_equal(sc.reference.speed_rpm.n, 4);
    assert_float_equal(profile_eval(&sc.reference.speed_rpm, 0.25), 100.0, TOL);
    assert_float_equal(profile_eval(&sc.reference.speed_rpm, 0.35), 50.0, TOL);
}

/* Plausibility bounds (scenario.c BOUNDS): the absurd is refused naming
 * key, value and bound, the controller's values after their factors; the
 * bounds themselves and the merely beyond-limit are accepted. */
static void plausibility_bounds(void **state)
{
    (void)state;
    expect_error("[plant]\nJ_kgm2 = 1e9\n", 2, "[plant] J_kgm2: 1e+09 kg m^2 is not plausible: the bound is 1e-08 .. 100");
    expect_error("[plant]\nL_H = 1e6\n", 2, "[plant] L_H: 1e+06 H is not plausible");
    expect_error("[plant]\nvdc_V = 1\n", 2, "[plant] vdc_V: 1 V is not plausible: the bound is 5 .. 1500 V");
    expect_error("[plant]\nvdc_V = 1500.1\n", 2, "vdc_V");
    expect_error("[plant]\nR_ohm = 0:3, 1:2000~\n", 2, "[plant] R_ohm: 2000 ohm (at t = 1 s)");
    expect_error("[plant]\npsif_Wb = 11\n", 2, "psif_Wb");
    expect_error("[plant]\npole_pairs = 65\n", 2, "[plant] pole_pairs: 65 is not plausible: the bound is 1 .. 64");
    expect_error("[controller]\nL_factor = 1000\n", 2, "[controller] L_H: 11 H (L_factor 1000 x [plant] L_H)");
    expect_error("[controller]\nR_ohm = 1e-4\n", 2, "[controller] R_ohm: 0.0001 ohm");
    expect_error("[reference]\nspeed_rpm = 0:0, 1:1.5e5~\n", 2, "[reference] speed_rpm: 150000 r/min (at t = 1 s)");
    scenario_t sc;
    char err[SCENARIO_ERR_LEN] = "";
    assert_int_equal(load_text(&sc,
                               "[plant]\nvdc_V = 1500\nJ_kgm2 = 100\nL_H = 10\npole_pairs = 64\n"
                               "[controller]\nR_ohm = 0.001\n[reference]\nspeed_rpm = 0:0, 1:-1e5~\n",
                               err),
                     0);
    /* above the overspeed trip (a result: it may fault), not absurd */
    assert_int_equal(load_text(&sc, "[reference]\nspeed_rpm = 5000\n", err), 0);
}

static void bad_inputs_name_file_line_key(void **state)
{
    (void)state;
    expect_error("[plant]\nR_ohm = 3\n[motor]\nR_ohm = 3\n", 4, "[motor]");
    expect_error("[plant]\nR_ohm = 3\nRs = 3\n", 3, "Rs");
    expect_error("[plant]\n\nL_H = 11mH\n", 3, "L_H");
    expect_error("[plant]\nR_ohm = -1\n", 2, "R_ohm");
    expect_error("[plant]\npole_pairs = 2.5\n", 2, "pole_pairs");
    expect_error("[plant]\nmodel = pwm\n", 2, "model");
    expect_error("[controller]\nmethod = better\n", 2, "method");
    expect_error("[controller]\nmode = position\n", 2, "mode");
    expect_error("[controller]\ni_limit_A = 14\n", 2, "i_limit_A"); /* above the 11.1 A peak rating */
    expect_error("[motor]\ni_peak_A = 14.2\n", 2, "i_peak_A"); /* its limit 14.2 A + 0.09 A: above the 14.25 A the ADC reads */
    expect_error("[controller]\ni_limit_A = 11\ni_max_A = 11.01\n", 2, "i_limit_A"); /* a margin of 0.01 A */
    expect_error("[reference]\nspeed_rpm = 0:0, 0.1 500\n", 2, "speed_rpm");
    expect_error("[reference]\nspeed_rpm = 0:0, 0.1:500, 0.05:0\n", 2, "speed_rpm");
    expect_error("[load]\ntorque_Nm = 0:abc\n", 2, "torque_Nm");
    expect_error("[run]\nduration_s = 0\n", 2, "duration_s");
    expect_error("[run]\nduration_s = -1\n", 2, "duration_s");
    expect_error("[run]\nlog_every = 0\n", 2, "log_every");
    expect_error("[plant]\nR_ohm = 3\nR_ohm = 4\n", 3, "R_ohm");
    expect_error("[controller]\nL_H = 0.01\nL_factor = 1.5\n", 2, "L_H");
    expect_error("[plant]\nR_ohm 3\n", 2, "syntax");
    /* no silent fallback: the proposed method without step 1, at the line that asked for it */
    expect_error("[controller]\nmethod = proposed\n", 2, "[identify] mode: off with [controller] method = proposed");
    expect_error("[controller]\nmethod = proposed\n[identify]\nmode = off\n", 4, "mode = windows | speeds");
    expect_error("[identify]\nR_se_max_rel = 0\n", 2, "R_se_max_rel");
    char long_line[400];
    int n = snprintf(long_line, sizeof long_line, "[reference]\nspeed_rpm = 0:0");
    while (n < 300) {
        n += snprintf(long_line + n, sizeof long_line - (size_t)n, ", %d:1", n);
    }
    snprintf(long_line + n, sizeof long_line - (size_t)n, "\n");
    expect_error(long_line, 2, "longer than");

    scenario_t sc;
    char err[SCENARIO_ERR_LEN];
    scenario_defaults(&sc);
    assert_int_equal(scenario_load(&sc, "/nonexistent/x.ini", err, sizeof err), -1);
    assert_non_null(strstr(err, "/nonexistent/x.ini"));
}

/* [faults]: every time unset (never) by default, the parts' defaults, a
 * full section parsed, and bad values named. */
/* The build level and the wrong boards' keys: defaults, resolution, refusals. */
static void level_and_wrong_board_keys(void **state)
{
    (void)state;
    scenario_t sc;
    char err[SCENARIO_ERR_LEN] = "";
    assert_int_equal(load_text(&sc, "[plant]\npole_pairs = 4\n", err), 0);
    assert_int_equal(sc.run.level, 5u);
    assert_int_equal(sc.controller.pole_pairs, 4u);                          /* the plant's */
    assert_float_equal(sc.run.level4_i_limit_A, 0.3 * sc.controller.i_limit_A, 1e-12);
    assert_int_equal(sc.plant.encoder_direction, SC_DIRECTION_FORWARD);
    assert_int_equal(sc.plant.phase_order, SC_PHASES_ABC);
    assert_int_equal(load_text(&sc, "[plant]\nencoder_direction = -1\nphase_order = acb\n"
                                    "[controller]\npole_pairs = 2\n[run]\nlevel = 3\nlevel4_i_limit_A = 2\n", err), 0);
    assert_int_equal(sc.plant.encoder_direction, SC_DIRECTION_REVERSED);
    assert_int_equal(sc.plant.phase_order, SC_PHASES_ACB);
    assert_int_equal(sc.controller.pole_pairs, 2u);
    assert_int_equal(sc.run.level, 3u);
    assert_float_equal(sc.run.level4_i_limit_A, 2.0, 0.0);
    expect_error("[run]\nlevel = 0\n", 2, "level");
    expect_error("[run]\nlevel = 6\n", 2, "level");
    expect_error("[run]\nlevel4_i_limit_A = 13\n", 2, "level4_i_limit_A"); /* above the 11.1 A limit */
    expect_error("[plant]\nencoder_direction = 2\n", 2, "encoder_direction");
    expect_error("[plant]\nphase_order = bac\n", 2, "phase_order");
    expect_error("[controller]\npole_pairs = 65\n", 2, "pole_pairs");
}

static void faults_section(void **state)
{
    (void)state;
    scenario_t sc;
    char err[SCENARIO_ERR_LEN];
    scenario_defaults(&sc);
    assert_true(isnan(sc.faults.open_phase_s) && isnan(sc.faults.short_s) && isnan(sc.faults.adc_stuck_s) &&
                isnan(sc.faults.encoder_lost_s) && isnan(sc.faults.encoder_jump_s) && isnan(sc.faults.vdc_sag_s) &&
                isnan(sc.faults.vdc_surge_s) && isnan(sc.faults.gate_trip_s) && isnan(sc.faults.isr_overrun_s));
    assert_int_equal(sc.faults.short_phases, 1); /* bc */
    assert_float_equal(sc.faults.vdc_sag_V, 150.0, TOL);
    assert_int_equal(load_text(&sc,
                               "[faults]\nopen_phase_s = 0\nopen_phase = c\nshort_s = 0.2\nshort_phases = ca\n"
                               "adc_stuck_s = 0.3\nadc_stuck = b\nencoder_jump_s = 0.4\nencoder_jump_counts = -7\n"
                               "vdc_surge_V = 500\nisr_overrun_run_s = 2e-4\n",
                               err),
                     0);
    assert_float_equal(sc.faults.open_phase_s, 0.0, TOL);
    assert_int_equal(sc.faults.open_phase, 2);
    assert_int_equal(sc.faults.short_phases, 2);
    assert_int_equal(sc.faults.adc_stuck, 1);
    assert_float_equal(sc.faults.encoder_jump_counts, -7.0, TOL);
    assert_float_equal(sc.faults.vdc_surge_V, 500.0, TOL);
    assert_float_equal(sc.faults.isr_overrun_run_s, 2e-4, TOL);
    expect_error("[faults]\nopen_phase = d\n", 2, "open_phase");
    expect_error("[faults]\nshort_s = -0.1\n", 2, "short_s");
    expect_error("[faults]\nadc_stuck = c\n", 2, "adc_stuck");
    expect_error("[faults]\nshort_ohm = 0\n", 2, "short_ohm");
    expect_error("[faults]\nencoder_jump_s = 0.1\nencoder_jump_counts = 2.5\n", 3, "encoder_jump_counts");
}

/* ---- the one key table (scenario_keys.h) ---------------------------------- */

/* The struct a target names, at its starting configuration. */
typedef union {
    drive_params_t p;
    app_cfg_t a;
    hal_sim_cfg_t s;
    hal_sim_faults_t f;
} target_cfg_t;

static void target_start(sc_target_t t, target_cfg_t *c)
{
    memset(c, 0, sizeof *c);
    if (t == SC_TO_PARAMS) {
        drive_params_board(&c->p);
    } else if (t == SC_TO_APP) {
        app_cfg_default(&c->a);
    } else if (t == SC_TO_SIM) {
        hal_sim_default_cfg(&c->s);
    } else {
        hal_sim_faults_none(&c->f);
    }
}

static size_t conv_size(sc_conv_t c)
{
    switch (c) {
    case SC_CONV_U16:
        return sizeof(uint16_t);
    case SC_CONV_F64:
    case SC_CONV_U64:
        return 8u;
    case SC_CONV_ENUM:
        return sizeof(unsigned int);
    case SC_CONV_BOOL:
        return sizeof(bool);
    case SC_CONV_F32:
    case SC_CONV_U32:
    case SC_CONV_I32:
    case SC_CONV_PERIODS:
    case SC_CONV_NONE:
        break;
    }
    return 4u;
}

/* Another value of key k than v, in its range, as "section.key=text"; its number in *x. */
static void other_value(const scenario_key_info_t *k, double v, char *buf, size_t len, double *x)
{
    if (k->type == SC_KEY_ENUM) {
        size_t n = 0;
        while (k->names[n] != NULL) {
            n++;
        }
        *x = (double)(((size_t)v + 1u) % n);
        snprintf(buf, len, "%s.%s=%s", k->section, k->name, k->names[(size_t)*x]);
        return;
    }
    if (k->type == SC_KEY_UINT) {
        *x = (v + 1.0 <= k->hi) ? v + 1.0 : v - 1.0;
    } else if (k->lo < 0.0) {
        *x = isnan(v) ? 1.0 : v + 1.0;   /* any finite value: a whole step */
    } else {
        *x = (isnan(v) || !(v > 0.0)) ? 0.5 : 1.5 * v;
        if (*x > k->hi) {   /* a bounded key: between its value (or lo) and hi */
            *x = 0.5 * ((isnan(v) ? k->lo : v) + k->hi);
        }
    }
    snprintf(buf, len, "%s.%s=%.17g", k->section, k->name, *x);
}

/* Every key with a target moves exactly its own field there, to its
 * value: the table's line is the whole mapping (no second table). */
static void every_key_maps_to_its_own_field(void **state)
{
    (void)state;
    static scenario_t sc0;
    static scenario_t sc;
    static target_cfg_t a;
    static target_cfg_t b;
    char err[SCENARIO_ERR_LEN];
    const double Ts_s = 1e-4;
    int mapped = 0;
    scenario_defaults(&sc0);
    for (int i = 0; i < scenario_key_count(); i++) {
        scenario_key_info_t k;
        scenario_key_info(i, &k);
        assert_non_null(k.help);
        assert_true(scenario_key_known(k.section, k.name));
        if (k.to.target == SC_TO_NONE || k.type == SC_KEY_PROFILE) {
            continue;
        }
        /* the key's value now, read through its own JSON (a number or a name) */
        char *json = NULL;
        size_t json_len = 0;
        FILE *f = open_memstream(&json, &json_len);
        scenario_key_json(f, &sc0, i);
        fclose(f);
        double v = NAN;
        if (k.type == SC_KEY_ENUM) {
            for (size_t n = 0; k.names[n] != NULL; n++) {
                char q[40];
                snprintf(q, sizeof q, "\"%s\"", k.names[n]);
                v = (strcmp(q, json) == 0) ? (double)n : v;
            }
        } else if (strcmp(json, "null") != 0) {
            v = strtod(json, NULL);
        }
        free(json);
        char set[160];
        double x;
        other_value(&k, v, set, sizeof set, &x);
        sc = sc0;
        if (scenario_set(&sc, set, err, sizeof err) != 0) {
            fail_msg("%s: %s", set, err);
        }
        target_start(k.to.target, &a);
        target_start(k.to.target, &b);
        scenario_map(&sc0, k.to.target, &a, Ts_s);
        scenario_map(&sc, k.to.target, &b, Ts_s);
        const double got = scenario_loc_read(&k.to, &b, Ts_s);
        const double tol = (k.to.conv == SC_CONV_PERIODS) ? Ts_s / 2.0 : 1e-6 * fabs(x);
        if (!(fabs(got - ((k.to.conv == SC_CONV_BOOL) ? (double)(x != 0.0) : x)) <= tol)) {
            fail_msg("%s: the target reads %.9g", set, got);
        }
        const size_t lo = k.to.offset;
        const size_t hi = lo + conv_size(k.to.conv);
        for (int j = 0; j < i; j++) {   /* no other key writes this field */
            scenario_key_info_t o;
            scenario_key_info(j, &o);
            if (o.to.target == k.to.target && o.to.offset == lo) {
                fail_msg("%s.%s and %s.%s write the same field", o.section, o.name, k.section, k.name);
            }
        }
        for (size_t n = 0; n < sizeof a; n++) {
            const unsigned char *pa = (const unsigned char *)&a;
            const unsigned char *pb = (const unsigned char *)&b;
            if (pa[n] != pb[n] && (n < lo || n >= hi)) {
                fail_msg("%s: byte %zu of the target changed, outside its field %zu..%zu", set, n, lo, hi);
            }
        }
        mapped++;
    }
    /* all but the profiles and the keys read by name (method, mode, the factors, [run]'s duration) */
    if (!(mapped >= scenario_key_count() - 20)) {
        fail_msg("only %d of %d keys mapped", mapped, scenario_key_count());
    }
}

/* One table of bounds: every link parameter's [controller] key is refused by scenario_set /
 * scenario_finish exactly outside the link's range (link_params.h) and taken inside: its top
 * and twice it (infinity for an unbounded one), its bottom (refused when open) and a step below
 * it, an integer's fraction. */
static void controller_keys_have_the_links_ranges(void **state)
{
    (void)state;
    for (uint16_t k = 0u; k < (uint16_t)LINK_PARAM_COUNT; k++) {
        const link_param_t *d = link_param(k);
        const bool whole = (d->type == (uint16_t)LINK_PARAM_U16);
        const float below = (d->lo > 0.0f) ? 0.5f * d->lo : d->lo - 1.0f;
        const struct { float v; bool ok; } cases[] = {
            /* an unbounded top: no value to try but a plain one inside (the cross-checks, e.g.
             * i_limit_A below the trip, are the scenario's own) */
            { (d->hi < 1e38f) ? d->hi : d->lo + 1.0f, true }, { (d->hi < 1e38f) ? 2.0f * d->hi : INFINITY, false },
            { d->lo, !d->lo_open }, { below, false },
            { whole ? d->lo + 0.5f : 0.5f * (d->lo + (d->hi < 1e38f ? d->hi : d->lo + 2.0f)), !whole },
        };
        for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
            scenario_t sc;
            char err[SCENARIO_ERR_LEN];
            char set[96];
            scenario_defaults(&sc);
            snprintf(set, sizeof set, "controller.%s=%.9g", d->key, (double)cases[c].v);
            const int rc = (scenario_set(&sc, set, err, sizeof err) == 0) ? scenario_finish(&sc, err, sizeof err) : -1;
            if ((rc == 0) != cases[c].ok) {
                fail_msg("%s: %s, not %s (%s)", set, (rc == 0) ? "taken" : "refused", cases[c].ok ? "taken" : "refused",
                         err);
            }
            assert_true(link_param_ok(k, cases[c].v) == cases[c].ok);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(defaults_are_table1),
        cmocka_unit_test(defaults_come_from_the_parameter_set),
        cmocka_unit_test(parses_every_kind),
        cmocka_unit_test(profile_rules),
        cmocka_unit_test(profile_cursor_equals_eval),
        cmocka_unit_test(set_overrides_and_replaces_profiles),
        cmocka_unit_test(plant_resistance_profile),
        cmocka_unit_test(bad_inputs_name_file_line_key),
        cmocka_unit_test(motor_section_derives_the_keys),
        cmocka_unit_test(motor_the_drive_cannot_run_refused),
        cmocka_unit_test(campaign_section_is_skipped),
        cmocka_unit_test(messages_name_the_real_problem),
        cmocka_unit_test(plausibility_bounds),
        cmocka_unit_test(level_and_wrong_board_keys),
        cmocka_unit_test(faults_section),
        cmocka_unit_test(every_key_maps_to_its_own_field),
        cmocka_unit_test(controller_keys_have_the_links_ranges),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
