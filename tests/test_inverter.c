/* Unit tests for hal/sim/inverter.c: centre-aligned edge timing, the
 * period-average voltage of both models against the duty formula, the
 * ideal-switch path against the general one, the dead-time error, and
 * switching vs averaged currents at 500 r/min, 4 N m under the analytic
 * steady-state voltage, through the HAL of the board. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>

#include "hal_sim.h"
#include "inverter.h"
#include "table1.h"

#define TS_S 1.0e-4
#define VDC_V 311.0
#define SQRT3 1.7320508075688772
#define TWO_PI 6.283185307179586
#define TIME_TOL_S 1.0e-12

static inv_cfg_t inv_cfg(inv_model_t model, double deadtime_s)
{
    inv_cfg_t c;
    c.model = model;
    c.vdc_V = VDC_V;
    c.Ts_s = TS_S;
    c.deadtime_s = deadtime_s;
    c.device_drop_V = 0.0;
    c.substep_max_s = 1.0e-6;
    return c;
}

/* Duty 0.25: high from 37.5 us to 62.5 us; dead time adds the delayed edges. */
static void centre_aligned_edges(void **state)
{
    (void)state;
    inv_cfg_t c = inv_cfg(INV_SWITCHING, 0.0);
    double t[4];
    assert_int_equal(inv_leg_edges(&c, 0.25, t), 2);
    assert_float_equal(t[0], 37.5e-6, TIME_TOL_S);
    assert_float_equal(t[1], 62.5e-6, TIME_TOL_S);
    assert_int_equal(inv_leg_state(&c, 0.25, 10e-6), LEG_LOW);
    assert_int_equal(inv_leg_state(&c, 0.25, 50e-6), LEG_HIGH);
    assert_int_equal(inv_leg_state(&c, 0.25, 90e-6), LEG_LOW);
    assert_int_equal(inv_leg_edges(&c, 0.0, t), 0);
    assert_int_equal(inv_leg_edges(&c, 1.0, t), 0);
    assert_int_equal(inv_leg_state(&c, 1.0, 1e-6), LEG_HIGH);

    c.deadtime_s = 2.0e-6;
    assert_int_equal(inv_leg_edges(&c, 0.25, t), 4);
    assert_float_equal(t[1], 39.5e-6, TIME_TOL_S);
    assert_float_equal(t[3], 64.5e-6, TIME_TOL_S);
    assert_int_equal(inv_leg_state(&c, 0.25, 38e-6), LEG_DEAD);
    assert_int_equal(inv_leg_state(&c, 0.25, 63e-6), LEG_DEAD);
    assert_int_equal(inv_leg_state(&c, 0.25, 50e-6), LEG_HIGH);
}

/* Mean rotor-frame voltage over one period at theta_el = 0 (rotor frame = stator frame). */
static void period_mean_u_drop(inv_model_t model, double deadtime_s, double drop_V, const double duty[3],
                               double id0_A, double *ua, double *ub)
{
    plant_cfg_t pc = table1_plant();
    pc.speed_held = true;
    plant_t p;
    plant_init(&p, &pc, 0.0);
    p.x.id_A = id0_A;
    inv_cfg_t c = inv_cfg(model, deadtime_s);
    c.device_drop_V = drop_V;
    plant_acc_clear(&p);
    inv_period(&c, duty, 0.0, &p);
    *ua = p.acc.ud_Vs / p.acc.time_s;
    *ub = p.acc.uq_Vs / p.acc.time_s;
}

static void period_mean_u(inv_model_t model, double deadtime_s, const double duty[3], double id0_A,
                          double *ua, double *ub)
{
    period_mean_u_drop(model, deadtime_s, 0.0, duty, id0_A, ua, ub);
}

/* The ideal-switch path (no dead time, no drop) against the general path,
 * forced by a dead time too short to move an edge (t + 1e-300 s rounds to
 * t): both must give the same pieces and voltages, so the same state to
 * the bit, over every order of the legs, ties, rails and a duty whose two
 * edges coincide. */
static void ideal_switch_path_equals_general_path(void **state)
{
    (void)state;
    static const double duties[][3] = {
        { 0.8, 0.35, 0.1 }, { 0.1, 0.35, 0.8 }, { 0.35, 0.8, 0.1 }, { 0.5, 0.5, 0.5 },
        { 0.7, 0.7, 0.2 }, { 0.2, 0.7, 0.2 }, { 1.0, 0.4, 0.0 }, { 0.0, 0.0, 1.0 },
        { 0.6, 1.0, 0.3 }, { 1.0e-17, 0.5, 0.999999 },
    };
    const size_t n_duties = sizeof duties / sizeof duties[0];
    plant_cfg_t pc = table1_plant();
    plant_t a;
    plant_t b;
    plant_init(&a, &pc, 0.3);
    plant_init(&b, &pc, 0.3);
    inv_cfg_t ideal = inv_cfg(INV_SWITCHING, 0.0);
    ideal.substep_max_s = TS_S;
    inv_cfg_t general = ideal;
    general.deadtime_s = 1.0e-300;
    for (int rep = 0; rep < 30; rep++) {
        for (size_t k = 0; k < n_duties; k++) {
            inv_period(&ideal, duties[k], 1.0, &a);
            inv_period(&general, duties[k], 1.0, &b);
        }
    }
    assert_true(fabs(a.x.iq_A) > 0.1);   /* the duties drove a current */
    assert_memory_equal(&a.x, &b.x, sizeof a.x);
    assert_memory_equal(&a.acc, &b.acc, sizeof a.acc);
}

/* Both models: mean alpha-beta voltage = Clarke of duty x Vdc (common mode removed). */
static void period_mean_voltage_is_duty_times_vdc(void **state)
{
    (void)state;
    const double duty[3] = { 0.8, 0.35, 0.1 };
    double va = duty[0] * VDC_V;
    double vb = duty[1] * VDC_V;
    double vc = duty[2] * VDC_V;
    double ea = (2.0 * va - vb - vc) / 3.0;
    double eb = (vb - vc) / SQRT3;
    for (int m = 0; m < 2; m++) {
        double ua;
        double ub;
        period_mean_u(m == 0 ? INV_AVERAGED : INV_SWITCHING, 0.0, duty, 0.0, &ua, &ub);
        assert_float_equal(ua, ea, 1e-9 * VDC_V);
        assert_float_equal(ub, eb, 1e-9 * VDC_V);
    }
}

/* Dead time td, ia > 0 and ib, ic < 0 (id > 0 at theta 0): leg a loses td,
 * legs b and c gain td, so u_alpha drops by (2/3)(2 td/Ts) Vdc. */
static void deadtime_error_follows_current_sign(void **state)
{
    (void)state;
    const double td_s = 2.0e-6;
    const double duty[3] = { 0.5, 0.5, 0.5 };
    const double expect_ua = -(2.0 / 3.0) * (2.0 * td_s / TS_S) * VDC_V;
    for (int m = 0; m < 2; m++) {
        double ua;
        double ub;
        period_mean_u(m == 0 ? INV_AVERAGED : INV_SWITCHING, td_s, duty, 5.0, &ua, &ub);
        assert_float_equal(ua, expect_ua, 1e-9 * VDC_V);
        assert_float_equal(ub, 0.0, 1e-9 * VDC_V);
        period_mean_u(m == 0 ? INV_AVERAGED : INV_SWITCHING, td_s, duty, -5.0, &ua, &ub);
        assert_float_equal(ua, -expect_ua, 1e-9 * VDC_V);
    }
}

/* Device drop D, ia > 0 and ib, ic < 0 (id > 0 at theta 0): leg a is D
 * lower, legs b and c D higher, so u_alpha drops by (4/3) D; with dead time
 * as well the two errors add (same shape); at zero current no drop. */
static void device_drop_follows_current_sign(void **state)
{
    (void)state;
    const double drop_V = 1.5;
    const double td_s = 1.0e-6;
    const double duty[3] = { 0.6, 0.45, 0.3 };
    double ua0;
    double ub0;
    period_mean_u(INV_AVERAGED, 0.0, duty, 0.0, &ua0, &ub0);
    for (int m = 0; m < 2; m++) {
        const inv_model_t model = (m == 0) ? INV_AVERAGED : INV_SWITCHING;
        double ua;
        double ub;
        period_mean_u_drop(model, 0.0, drop_V, duty, 5.0, &ua, &ub);
        assert_true(fabs(ua - ua0 - (-(4.0 / 3.0) * drop_V)) < 1e-9 * VDC_V);
        assert_true(fabs(ub - ub0) < 1e-9 * VDC_V);
        period_mean_u_drop(model, 0.0, drop_V, duty, -5.0, &ua, &ub);
        assert_true(fabs(ua - ua0 - ((4.0 / 3.0) * drop_V)) < 1e-9 * VDC_V);
        period_mean_u_drop(model, td_s, drop_V, duty, 5.0, &ua, &ub);
        assert_true(fabs(ua - ua0 - (-(4.0 / 3.0) * (drop_V + td_s / TS_S * VDC_V))) < 1e-9 * VDC_V);
        if (model == INV_AVERAGED) {   /* switching: the current leaves 0 after the first piece */
            period_mean_u_drop(model, 0.0, drop_V, duty, 0.0, &ua, &ub);
            assert_true(fabs(ua - ua0) < 1e-9 * VDC_V);
        }
    }
}

/* ---- open loop through the HAL at 500 r/min, 4 N m ------------------------ */

#define SPEED_RPM 500.0
#define TE_NM 4.0
#define SETTLE_S 0.05
#define MEAN_PERIODS 200
#define ENC_COUNTS_PER_REV (4.0 * 2500.0)   /* the board's default encoder, x4 */
#define VDC_LSB_V 0.125                      /* bus ADC LSB that reads 311 V exactly */

static double g_ud_V;
static double g_uq_V;
static double g_w_el;
static double g_pole_pairs;

/* Sine PWM of the rotor-frame voltage at the mid angle of the period it is applied in. */
static void open_loop_isr(void)
{
    hal_sample_t s;
    hal_sample_read(&s);
    double th = g_pole_pairs * TWO_PI * (double)s.enc_count / ENC_COUNTS_PER_REV + 1.5 * g_w_el * TS_S;
    double ua = g_ud_V * cos(th) - g_uq_V * sin(th);
    double ub = g_ud_V * sin(th) + g_uq_V * cos(th);
    double v[3] = { ua, -0.5 * ua + 0.5 * SQRT3 * ub, -0.5 * ua - 0.5 * SQRT3 * ub };
    float d[3];
    for (int k = 0; k < 3; k++) {
        d[k] = (float)(0.5 + v[k] / (double)s.vdc_V);
    }
    hal_pwm_write(d);
    hal_pwm_enable();
    hal_isr_ack();
}

static void run_open_loop(inv_model_t model, double substep_s, double speed_rpm, double *id_A, double *iq_A)
{
    hal_sim_cfg_t c;
    sil_board_default(&c);
    c.inv.model = model;
    if (substep_s > 0.0) {
        c.inv.substep_max_s = substep_s;
    }
    c.plant.speed_held = true;
    c.plant.omega0_m_rad_s = speed_rpm * TWO_PI / 60.0;
    c.sens.vdc_full_scale_V = ldexp(VDC_LSB_V, (int)c.sens.adc_bits);
    hal_sim_configure(&c);
    hal_init();
    hal_isr_attach(open_loop_isr);
    int settle = (int)lround(SETTLE_S / TS_S);
    double sd = 0.0;
    double sq = 0.0;
    for (int k = 0; k < settle + MEAN_PERIODS; k++) {
        hal_sim_period();
        if (k >= settle) {
            hal_sim_truth_t tr;
            hal_sim_truth(&tr);
            sd += tr.id_mean_A;
            sq += tr.iq_mean_A;
        }
    }
    *id_A = sd / MEAN_PERIODS;
    *iq_A = sq / MEAN_PERIODS;
}

/* Analytic point: id = 0, iq = Te/(1.5 p psi_f), ud = -w L iq, uq = R iq + w psi_f. */
static void switching_matches_averaged_at_500rpm_4Nm(void **state)
{
    (void)state;
    plant_cfg_t pc = table1_plant();
    g_pole_pairs = (double)pc.pole_pairs;
    g_w_el = g_pole_pairs * SPEED_RPM * TWO_PI / 60.0;
    double iq = TE_NM / (1.5 * (double)pc.pole_pairs * pc.psi_f_Wb);
    g_ud_V = -g_w_el * pc.L_H * iq;
    g_uq_V = pc.R_Ohm * iq + g_w_el * pc.psi_f_Wb;

    double id_av;
    double iq_av;
    double id_sw;
    double iq_sw;
    run_open_loop(INV_AVERAGED, 0.0, SPEED_RPM, &id_av, &iq_av);
    run_open_loop(INV_SWITCHING, 0.0, SPEED_RPM, &id_sw, &iq_sw);
    print_message("averaged id %.4f iq %.4f, switching id %.4f iq %.4f, analytic id 0 iq %.4f\n",
                  id_av, iq_av, id_sw, iq_sw, iq);
    print_message("switching vs averaged: |d id|/iq %.3g, |d iq|/iq %.3g\n",
                  fabs(id_sw - id_av) / iq, fabs(iq_sw - iq_av) / iq);
    const double rel_tol = 0.02;
    assert_true(fabs(iq_sw - iq_av) < rel_tol * fabs(iq_av));
    assert_true(fabs(id_sw - id_av) < rel_tol * fabs(iq_av));
    assert_true(fabs(iq_av - iq) < rel_tol * iq);
    assert_true(fabs(id_av) < rel_tol * iq);
}

/* The default (the period solved at once) against 1 us sub-periods,
 * switching model. At n/m counts per period the angle lands exactly on an
 * encoder edge every m periods, where rounding alone would flip the count:
 * 500 r/min is 25/3 counts, 511.3 r/min 5113/600 (an edge at period 600);
 * 511.37 r/min is 51137/6000, no edge in the 700 periods run. */
static void default_substep_agrees_with_1us(void **state)
{
    (void)state;
    const double speed_rpm = 511.37;
    const double fine_s = 1.0e-6;
    const double rel_tol = 1.0e-6;
    double id_def;
    double iq_def;
    double id_fine;
    double iq_fine;
    run_open_loop(INV_SWITCHING, 0.0, speed_rpm, &id_def, &iq_def);
    run_open_loop(INV_SWITCHING, fine_s, speed_rpm, &id_fine, &iq_fine);
    print_message("default vs 1 us substeps: |d id| %.3g A, |d iq| %.3g A\n",
                  fabs(id_def - id_fine), fabs(iq_def - iq_fine));
    assert_true(fabs(iq_def - iq_fine) < rel_tol * fabs(iq_fine));
    assert_true(fabs(id_def - id_fine) < rel_tol * fabs(iq_fine));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(centre_aligned_edges),
        cmocka_unit_test(period_mean_voltage_is_duty_times_vdc),
        cmocka_unit_test(ideal_switch_path_equals_general_path),
        cmocka_unit_test(deadtime_error_follows_current_sign),
        cmocka_unit_test(device_drop_follows_current_sign),
        cmocka_unit_test(switching_matches_averaged_at_500rpm_4Nm),
        cmocka_unit_test(default_substep_agrees_with_1us),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
