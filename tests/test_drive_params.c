/* Unit tests for firmware/drive_params: the values derived from the
 * motor's data (firmware/params/params_design.md). The paper motor on the board
 * gets the constants the drive had before they were derived, to the bit;
 * other motors get them in proportion, by hand-computed figures; a motor
 * the drive cannot run is refused by name; a value the user set stays;
 * every value of the parameter set's lists reaches the field it names. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "app.h"
#include "board_cfg.h"
#include "drive_params.h"
#include "mathx.h"

#define RPM (0.104719755)   /* rad/s per r/min */

/* The paper motor's parameter set, mapped: every derived value is the
 * constant it replaced (hand values of board_cfg.h, smo.h, est_gate.h,
 * r_track.h, param_est.h before the derivation). */
static void paper_motor_gets_the_old_constants_to_the_bit(void **state)
{
    (void)state;
    static app_cfg_t cfg;
    app_cfg_default(&cfg);
    const ctrl_cfg_t *c = &cfg.ctrl;
    assert_float_equal(c->speed_kp_Nms_rad, 0.5f, 0.0);
    assert_float_equal(c->speed_ki_Nm_rad, 20.0f, 0.0);
    assert_float_equal(c->te_max_Nm, 12.0f, 0.0);
    assert_float_equal(c->i_lim_A, REF_I_PEAK_A, 0.0); /* never above the peak rating (params_design.md sec. 3) */
    assert_float_equal(cfg.prot.i_max_A, 14.0f, 0.0);
    assert_float_equal(cfg.cal.offset_max_A, 0.75f, 0.0);
    /* the observer's gains on the exact discrete model (discrete_model_design.md sec. 5):
     * a = Ts R/L, rho = e^-a, g = (1 - rho)/R, the double pole 0.8: G g = rho - 0.6,
     * mu Ts G g = 0.04, Ks = 2 ef_max, phi = Ks/G */
    const double a = 1e-4 * 3.0 / 0.011;
    const double rho = exp(-a);
    const double g = (1.0 - rho) / 3.0;
    const double G = (rho - 0.6) / g;
    assert_float_equal(c->est_cfg.smo.phi_A, 100.0 / G, 1e-5);
    assert_float_equal(c->est_cfg.smo.Ks_V, 100.0f, 0.0);
    assert_float_equal(c->est_cfg.smo.mu_d_1_s, 0.04 / (1e-4 * (rho - 0.6)), 1e-3);
    assert_float_equal(c->est_cfg.smo.ef_max_V, 50.0f, 0.0);
    assert_float_equal(c->est_cfg.R_max_Ohm, 18.0f, 0.0);
    assert_float_equal(c->est_cfg.gate.di_max_A, 0.5f, 0.0);
    assert_float_equal(c->est_cfg.gate.dte_max_Nm, 0.3f, 0.0);
    assert_float_equal(c->est_cfg.rtrack.i_ident_A, 1.0f, 0.0);
    assert_float_equal(c->est_cfg.rtrack.i_track_A, 0.5f, 0.0);
    assert_float_equal(c->est_cfg.rtrack.iq_min_A, 1.0f, 0.0);
    assert_float_equal(c->est_cfg.rtrack.iq_step_max_A, 0.2f, 0.0);
    assert_float_equal(c->est_cfg.rtrack.ve_max_V, 20.0f, 0.0);
    assert_float_equal(c->est_cfg.pe.w_min_rad_s, 30.0f, 0.0);
    assert_float_equal(c->est_cfg.pe.wiq_min_A_rad_s, 30.0f, 0.0);
    assert_float_equal(cfg.aln.u_V, 9.0f, 0.0);
    assert_float_equal(cfg.prot.watch.op_u_min_V, 25.0f, 0.0);
    assert_float_equal(cfg.prot.watch.op_i_min_A, 1.0f, 0.0);
    assert_float_equal(cfg.rsid.settle_1_s, 0.28f, 0.0);
    assert_float_equal(cfg.rsid.settle_2_s, 0.14f, 0.0);
    assert_float_equal(cfg.rsid.speed_1_rad_s, 500.0 * RPM, 1e-4);
    assert_float_equal(cfg.rsid.speed_2_rad_s, 1000.0 * RPM, 1e-4);
    assert_float_equal(cfg.rsid.accel_rad_s2, 2500.0 * RPM, 1e-3);
    assert_float_equal(cfg.prot.speed_max_rad_s, 2400.0 * RPM, 1e-3);
}

/* The small motor of the any-motor campaign: R 0.1 ohm, L 0.2 mH,
 * psi_f 0.008 Wb, p 4, J 2e-5, 24 V bus, rated 6.25 A (0.3 N m), 3000 r/min. */
static void small_motor(drive_params_t *p)
{
    drive_params_board(p);
    p->motor.R_Ohm = 0.1f;
    p->motor.L_H = 0.0002f;
    p->motor.psi_f_Wb = 0.008f;
    p->motor.pole_pairs = 4u;
    p->motor.J_kgm2 = 2.0e-5f;
    p->board.vdc_nominal_V = 24.0f;
    p->rating.i_rated_A = 6.25f;
    p->rating.i_peak_A = 12.5f;
    p->rating.n_rated_rad_s = (float)(3000.0 * RPM);
    p->rating.n_max_rad_s = (float)(3000.0 * RPM);
}

/* Hand values: kt = 1.5 x 4 x 0.008 = 0.048 N m/A; te_max 0.048 x 12.5 = 0.6;
 * i_limit = i_peak = 12.5 A; trip min(14 x 12.5/11.11 = 15.75, 15 - 0.75 = 14.25) = 14.25 A,
 * above 12.5 A + 6 x 2 x 15/2048 = 0.088 A (6 sigma of 2 codes of ADC noise);
 * kp = 0.5 x 2e-5/0.00129 = 0.00775; ki = 20 x 2e-5/0.00129 = 0.310;
 * speeds 750, 1500 r/min; overspeed 3600 r/min. */
static void small_motor_limits_and_speed_loop(void **state)
{
    (void)state;
    drive_params_t p;
    small_motor(&p);
    const drive_derive_t st = drive_params_derive(&p);
    assert_int_equal(st & DRIVE_DERIVE_REFUSED, 0);
    assert_float_equal(p.limits.te_max_Nm, 0.6, 1e-5);
    assert_float_equal(p.limits.i_limit_A, 12.5, 0.0);
    assert_float_equal(p.limits.i_trip_A, 14.25, 1e-5);
    assert_float_equal(drive_trip_margin_A(&p), 12.0 * 15.0 / 2048.0, 1e-6);
    assert_float_equal(p.tuning.speed_kp_Nms_rad, 0.5 * 2e-5 / 0.00129, 1e-7);
    assert_float_equal(p.tuning.speed_ki_Nm_rad, 20.0 * 2e-5 / 0.00129, 1e-5);
    assert_float_equal(p.step1.speed_1_rad_s, 750.0 * RPM, 1e-3);
    assert_float_equal(p.step1.speed_2_rad_s, 1500.0 * RPM, 1e-3);
    assert_float_equal(p.limits.speed_max_rad_s, 3600.0 * RPM, 1e-2);
    /* ramp: 750 r/min in 0.2 s = 3750 r/min/s, below 0.25 T_rated / J = 3750 rad/s^2 */
    assert_float_equal(p.step1.accel_rad_s2, 3750.0 * RPM, 1e-2);
}

/* The observer's gains for the small motor (discrete_model_design.md
 * sec. 5): ef_max = 50 x 24/311 = 3.859 V, Ks = 7.717 V; a = Ts R/L =
 * 0.05, rho = e^-0.05, g = (1 - rho)/R = 0.4877 A/V, G = (rho - 0.6)/g =
 * 0.7202 V/A, phi = Ks/G = 10.72 A; ctrl_init then accepts the proposed
 * method, its L^ floor below half the told L. */
static void small_motor_observer_gain_designed_and_accepted(void **state)
{
    (void)state;
    drive_params_t p;
    smo_gains_t g;
    small_motor(&p);
    assert_true(drive_params_obs_gains(&p, &g));
    const double ef = 50.0 * 24.0 / 311.0;
    const double rho = exp(-0.05);
    const double gam = (1.0 - rho) / 0.1;
    const double G = (rho - 0.6) / gam;
    assert_float_equal(g.ef_max_V, ef, 1e-5);
    assert_float_equal(g.Ks_V, 2.0 * ef, 1e-5);
    assert_float_equal(g.phi_A, 2.0 * ef / G, 1e-4);
    assert_float_equal(g.phi_A, 10.72, 0.01);

    static app_cfg_t cfg;
    static ctrl_t ctrl;
    app_cfg_default(&cfg);
    drive_params_to_app_cfg(&p, &cfg);
    cfg.ctrl.u_max_V = 24.0f;
    assert_int_equal(ctrl_init(&ctrl, &cfg.ctrl) & CTRL_CFG_NEEDED_PROPOSED, 0);
    assert_true(cfg.ctrl.est_cfg.smo.L_min_H <= 0.5f * cfg.ctrl.L_H);
}

/* The tracking injection (params_design.md sec. 6): R I = 1.5 V x bus /
 * 311 V, at most 0.2 i_rated. Small motor: 0.5 A x (24/0.1) / (311/3) =
 * 1.158 A, below 0.2 x 6.25 = 1.25 A; the large one (0.5 ohm, 540 V,
 * 9.52 A): 5.21 A by the bus, capped at 1.905 A. */
static void tracking_injection_by_bus_then_capped(void **state)
{
    (void)state;
    drive_params_t p;
    static app_cfg_t cfg;
    small_motor(&p);
    app_cfg_default(&cfg);
    drive_params_to_app_cfg(&p, &cfg);
    assert_float_equal(cfg.ctrl.est_cfg.rtrack.i_track_A, 0.5 * (24.0 / 0.1) / (311.0 / 3.0), 1e-5);
    p.motor.R_Ohm = 0.5f;
    p.board.vdc_nominal_V = 540.0f;
    p.rating.i_rated_A = 9.5238f;
    p.rating.i_peak_A = 2.0f * 9.5238f;
    drive_params_to_app_cfg(&p, &cfg);
    assert_float_equal(cfg.ctrl.est_cfg.rtrack.i_track_A, 0.2 * 9.5238, 1e-5);
}

/* L/R below 2 periods: L 19 uH with R 0.1 ohm at 10 kHz (1.9 periods)
 * is refused (OBSERVER), the rest derived; 21 uH (2.1 periods) and the
 * D5065 (39 mOhm, 15.7 uH: 4 periods) are accepted. */
static void observer_refused_below_two_periods(void **state)
{
    (void)state;
    drive_params_t p;
    small_motor(&p);
    p.motor.L_H = 19.0e-6f;
    assert_int_equal(drive_params_derive(&p) & DRIVE_DERIVE_REFUSED, DRIVE_DERIVE_OBSERVER);
    small_motor(&p);
    p.motor.L_H = 21.0e-6f;
    assert_int_equal(drive_params_derive(&p) & DRIVE_DERIVE_REFUSED, 0);
    small_motor(&p);
    p.motor.R_Ohm = 0.039f;
    p.motor.L_H = 15.7e-6f;
    assert_int_equal(drive_params_derive(&p) & DRIVE_DERIVE_REFUSED, 0);
}

/* i_peak 20 A on the board's 15 A ADC: i_limit 20 A against a trip of at
 * most 14.25 A: refused (ADC_RANGE). The paper motor (i_peak 11.11 A) on an
 * ADC range of 1.1 i_peak = 12.22 A: it reads up to 0.95 x 12.22 = 11.61 A,
 * the trip, above 11.11 A + 12 x 12.22/2048 = 0.072 A (6 sigma of 2 codes of
 * noise): accepted; the least range accepted is i_peak / (0.95 - 12/2048) =
 * 1.0592 i_peak: 1.06 i_peak accepted, 1.058 refused. A set limit above
 * i_peak: I_LIMIT. Ratings that contradict: RATINGS. */
static void ratings_beyond_the_adc_or_inconsistent_refused(void **state)
{
    (void)state;
    drive_params_t p;
    drive_params_board(&p);
    p.rating.i_rated_A = 10.0f;
    p.rating.i_peak_A = 20.0f;
    assert_true((drive_params_derive(&p) & DRIVE_DERIVE_ADC_RANGE) != 0u);
    drive_params_board(&p);
    p.board.i_full_scale_A = 1.1f * p.rating.i_peak_A;
    assert_int_equal(drive_params_derive(&p) & DRIVE_DERIVE_REFUSED, 0);
    assert_float_equal(p.limits.i_limit_A, p.rating.i_peak_A, 0.0);
    assert_float_equal(p.limits.i_trip_A, 0.95 * 1.1 * 11.1111, 1e-4);
    assert_float_equal(drive_trip_margin_A(&p), 12.0 * 1.1 * 11.1111 / 2048.0, 1e-5);
    drive_params_board(&p);
    p.board.i_full_scale_A = 1.06f * p.rating.i_peak_A;
    assert_int_equal(drive_params_derive(&p) & DRIVE_DERIVE_REFUSED, 0);
    drive_params_board(&p);
    p.board.i_full_scale_A = 1.058f * p.rating.i_peak_A;
    assert_int_equal(drive_params_derive(&p) & DRIVE_DERIVE_REFUSED, DRIVE_DERIVE_ADC_RANGE);
    drive_params_board(&p);
    p.limits.i_limit_A = 1.01f * p.rating.i_peak_A;
    assert_int_equal(drive_params_derive(&p) & DRIVE_DERIVE_REFUSED, DRIVE_DERIVE_I_LIMIT);
    drive_params_board(&p);
    p.rating.i_peak_A = 0.5f * p.rating.i_rated_A;
    assert_true((drive_params_derive(&p) & DRIVE_DERIVE_RATINGS) != 0u);
}

/* A value the user set stays; the speed PI scales with w_c (kp x2, ki x4,
 * settle / 2). */
static void set_values_stay_and_bandwidth_scales(void **state)
{
    (void)state;
    drive_params_t p;
    drive_params_board(&p);
    p.limits.te_max_Nm = 5.0f;
    p.step1.settle_1_s = 0.0f;
    p.tuning.speed_bw_rad_s = 2.0f * TUNE_SPEED_BW_RAD_S;
    (void)drive_params_derive(&p);
    assert_float_equal(p.limits.te_max_Nm, 5.0, 0.0);
    assert_float_equal(p.step1.settle_1_s, 0.0, 0.0);
    assert_float_equal(p.tuning.speed_kp_Nms_rad, 1.0, 1e-6);
    assert_float_equal(p.tuning.speed_ki_Nm_rad, 80.0, 1e-4);
    assert_float_equal(p.step1.settle_2_s, 0.07, 1e-7);
}

/* Each value of the parameter set's lists, set to its own number (1, 2,
 * 3, ... in the lists' order: all the user's, none derived), reaches the
 * field its DRIVE_TO names unchanged: no formula overwrites a copy. */
#define SET_OWN_NUMBER(group, field, type, dflt, to) \
    p.group.field = (type)n;                         \
    n += 1.0f;
#define COPY_ERROR_DRIVE_TO(path) (double)cfg.path - (double)
#define COPY_ERROR_DRIVE_TO_NONE(value) 0.0
#define CHECK_COPY(group, field, type, dflt, to) assert_float_equal(COPY_ERROR_##to(p.group.field), 0.0, 0.0);
static void every_listed_value_reaches_its_field(void **state)
{
    (void)state;
    drive_params_t p;
    static app_cfg_t cfg;
    float n = 1.0f;
    app_cfg_default(&cfg);
    drive_params_board(&p);
    DRIVE_PARAMS(SET_OWN_NUMBER)
    drive_params_to_app_cfg(&p, &cfg);
    DRIVE_PARAMS(CHECK_COPY)
    assert_float_equal(cfg.ctrl.R_Ohm, 1.0, 0.0);
    assert_int_equal(cfg.prot.isr_budget_cycles, 21);
    assert_float_equal(cfg.rsid.accel_rad_s2, 39.0, 0.0);
    assert_float_equal(cfg.ctrl.device_drop_V, 14.0, 0.0);
    assert_float_equal(cfg.comm.deadtime_s, 13.0, 0.0); /* the told dead time the commissioning splits on */
}

/* Back-EMF at n_max: 3 x 0.24 x 2000 r/min = 150.8 V, below 311/sqrt(3) =
 * 179.6 V; at 2500 r/min 188.5 V: the warning, no refusal. */
static void back_emf_beyond_the_bus_warns(void **state)
{
    (void)state;
    drive_params_t p;
    drive_params_board(&p);
    assert_int_equal(drive_params_derive(&p), DRIVE_DERIVE_OK);
    drive_params_board(&p);
    p.rating.n_max_rad_s = (float)(2500.0 * RPM);
    assert_int_equal(drive_params_derive(&p), DRIVE_DERIVE_WARN_BEMF);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(paper_motor_gets_the_old_constants_to_the_bit),
        cmocka_unit_test(small_motor_limits_and_speed_loop),
        cmocka_unit_test(small_motor_observer_gain_designed_and_accepted),
        cmocka_unit_test(tracking_injection_by_bus_then_capped),
        cmocka_unit_test(observer_refused_below_two_periods),
        cmocka_unit_test(ratings_beyond_the_adc_or_inconsistent_refused),
        cmocka_unit_test(set_values_stay_and_bandwidth_scales),
        cmocka_unit_test(back_emf_beyond_the_bus_warns),
        cmocka_unit_test(every_listed_value_reaches_its_field),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
