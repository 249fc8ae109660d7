/* The simulated board with the gates off, through sil_run(): the diode
 * bridge brakes a shaft the load drives past the bus-limited speed
 * (hal/sim/plant_design.md sec. 9), the passive load's Coulomb friction
 * holds a shaft at rest and stops a turning one (sec. 10), and the
 * drive's readings follow the shaft in every state (firmware/app/app.h): in
 * FAULT after a gate trip, during a commissioning and build level 3. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>

#include "app.h"
#include "board_cfg.h"
#include "sil.h"
#include "sil_scenario.h"
#include "table1.h"

#define PI_D          3.141592653589793
#define RPM_PER_RAD_S (30.0 / PI_D)
#define MAX_ROWS      200000
#define BUS_V         311.0

typedef struct {
    double t_s, state, speed, speed_est, id, iq, id_meas, iq_meas, te;
} row_t;

static row_t g_rows[MAX_ROWS];
static size_t g_n;

static int on_row(const sil_row_t *r, void *user)
{
    (void)user;
    if (g_n < MAX_ROWS) {
        const row_t x = { r->t_s, r->state, r->speed_rpm, r->speed_est_rpm, r->id_A, r->iq_A, r->id_meas_A,
                          r->iq_meas_A, r->te_Nm };
        g_rows[g_n++] = x;
    }
    return 0;
}

/* The paper motor (drive_sil's defaults), the overrides, a row every period; commission: the
 * app's commissioning instead of the run. */
static void run(const char *const *sets, int commission, sil_result_t *res)
{
    scenario_t sc;
    static const char *const base[] = { "run.log_every=1", NULL };
    scenario_defaults(&sc);
    sil_scenario_set(&sc, base);
    sil_scenario_set(&sc, sets);
    sil_scenario_finish(&sc);
    g_n = 0u;
    const sil_ctl_t ctl = { NULL, NULL, NULL, 0u, NULL, commission };
    assert_int_equal(sil_run_ctl(&sc, on_row, NULL, &ctl, res), 0);
}

/* What the speed estimate may lag the shaft by [r/min]: the encoder's PLL (bandwidth w_b,
 * critically damped) lags a speed ramping at a by about 2 a / w_b while it settles (3 here, a
 * margin), a the rows' largest acceleration; and a few counts' quantisation (SPEED_COUNTS_RPM). */
#define SPEED_COUNTS_RPM 2.0
#define PLL_LAG_PER_ACCEL 3.0
static double speed_follow_rpm(void)
{
    const double Ts = 1e-4;
    double a = 0.0;
    for (size_t k = 1; k < g_n; k++) {
        a = fmax(a, fabs(g_rows[k].speed - g_rows[k - 1u].speed) / RPM_PER_RAD_S / Ts);
    }
    return PLL_LAG_PER_ACCEL * a / (double)TUNE_ENC_PLL_BW_RAD_S * RPM_PER_RAD_S + SPEED_COUNTS_RPM;
}

/* Across the rows in `state`: the largest |speed_est - speed| [r/min] and |i_meas - i| [A];
 * the count of such rows. */
static size_t follow(double state, double *speed_err, double *i_err)
{
    size_t n = 0u;
    *speed_err = 0.0;
    *i_err = 0.0;
    for (size_t k = 0; k < g_n; k++) {
        const row_t *r = &g_rows[k];
        if (!(r->state == state)) {
            continue;
        }
        n++;
        *speed_err = fmax(*speed_err, fabs(r->speed_est - r->speed));
        *i_err = fmax(*i_err, fmax(fabs(r->id_meas - r->id), fabs(r->iq_meas - r->iq)));
    }
    return n;
}

/* The drive at 500 r/min against an active 4 N m; the gate driver trips at 2 s: the load drives
 * the shaft backwards until the diodes, conducting once the line back-EMF passes the bus
 * (sqrt(3) p w psi_f > vdc, 2382 r/min for the paper motor), brake it with the load's 4 N m.
 * Before the diode model the shaft ran away to -117,911 r/min in 4 s. The readings follow the
 * shaft and the freewheeling currents in FAULT: the speed estimate within what the encoder's
 * PLL lags on the load's acceleration, the currents within the ADC's quantisation. */
static void gate_trip_with_an_active_load_brakes_through_the_diodes(void **state)
{
    (void)state;
    static const char *const sets[] = { "reference.speed_rpm=0:0, 0.1:500~", "load.torque_Nm=0:0, 0.5:4",
                                        "faults.gate_trip_s=2", "run.duration_s=6", NULL };
    const double speed_max_rpm = 3500.0;        /* the bound */
    const double i_follow_A = 0.02;             /* 2.5 ADC steps of 15 A / 2048 */
    const plant_cfg_t pc = table1_plant();
    const double w_on_rpm = BUS_V / (sqrt(3.0) * (double)pc.pole_pairs * pc.psi_f_Wb) * RPM_PER_RAD_S;
    sil_result_t res;
    run(sets, 0, &res);
    assert_int_equal(res.final_state, APP_STATE_FAULT);
    double top = 0.0;
    for (size_t k = 0; k < g_n; k++) {
        top = fmax(top, fabs(g_rows[k].speed));
    }
    const row_t *last = &g_rows[g_n - 1u];
    double se;
    double ie;
    const size_t n = follow((double)APP_STATE_FAULT, &se, &ie);
    const double bound = speed_follow_rpm();
    printf("  gate trip at 2 s, 4 N m: |speed| at most %.0f r/min, %.0f r/min at the end (bus-limited %.0f), "
           "torque %.3g N m; in FAULT (%zu rows) speed_est within %.3g r/min (the PLL's bound %.3g), i_meas "
           "within %.3g A; at the end within %.3g r/min\n",
           top, last->speed, w_on_rpm, last->te, n, se, bound, ie, fabs(last->speed_est - last->speed));
    assert_true(top < speed_max_rpm);
    assert_true(last->speed < -w_on_rpm);           /* driven past the bus-limited speed, then held there */
    assert_true(fabs(last->te - 4.0) < 0.5);        /* the diodes' torque balances the load (with its ripple) */
    assert_true(n > 1000u);
    assert_true(se < bound);
    assert_true(fabs(last->speed_est - last->speed) < SPEED_COUNTS_RPM);
    assert_true(ie < i_follow_A);
}

/* The gates off from t = 0 (a trip), the shaft at 300 r/min and a passive load of 0.1 N m
 * Coulomb friction: it decelerates at F / J to rest in w0 J / F = 0.405 s, and stays there. */
static void coulomb_friction_stops_a_turning_shaft(void **state)
{
    (void)state;
    static const char *const sets[] = { "faults.gate_trip_s=0", "plant.speed0_rpm=300", "load.friction_Nm=0.1",
                                        "run.duration_s=0.8", NULL };
    const plant_cfg_t pc = table1_plant();
    const double w0 = 300.0 / RPM_PER_RAD_S;
    const double t_stop = w0 * pc.J_kgm2 / 0.1;
    sil_result_t res;
    run(sets, 0, &res);
    size_t k_stop = g_n;
    for (size_t k = 0; k < g_n && k_stop == g_n; k++) {
        if (!(g_rows[k].speed != 0.0)) {
            k_stop = k;
        }
    }
    assert_true(k_stop < g_n);
    printf("  300 r/min, 0.1 N m Coulomb: at rest at %.4f s (w0 J / F = %.4f s)\n", g_rows[k_stop].t_s, t_stop);
    assert_true(fabs(g_rows[k_stop].t_s - t_stop) <= 2.0 * 1e-4);
    for (size_t k = k_stop; k < g_n; k++) {
        assert_float_equal(g_rows[k].speed, 0.0, 0.0);
    }
}

/* At rest with the gates off: an active 0.05 N m against 0.1 N m of Coulomb friction moves
 * nothing; 0.2 N m turns the shaft at (0.2 - 0.1) / J. */
static void coulomb_friction_holds_a_shaft_at_rest(void **state)
{
    (void)state;
    static const char *const held[] = { "faults.gate_trip_s=0", "load.friction_Nm=0.1", "load.torque_Nm=0.05",
                                        "run.duration_s=0.5", NULL };
    static const char *const moved[] = { "faults.gate_trip_s=0", "load.friction_Nm=0.1", "load.torque_Nm=0.2",
                                         "run.duration_s=0.5", NULL };
    const plant_cfg_t pc = table1_plant();
    sil_result_t res;
    run(held, 0, &res);
    for (size_t k = 0; k < g_n; k++) {
        assert_float_equal(g_rows[k].speed, 0.0, 0.0);
    }
    run(moved, 0, &res);
    const row_t *last = &g_rows[g_n - 1u];
    const double expect_rpm = -(0.2 - 0.1) / pc.J_kgm2 * (last->t_s + 1e-4) * RPM_PER_RAD_S;
    printf("  0.2 N m against 0.1 N m Coulomb: %.2f r/min at %.4f s (expected %.2f)\n", last->speed, last->t_s,
           expect_rpm);
    assert_true(fabs(last->speed - expect_rpm) < 0.01 * fabs(expect_rpm));
}

/* The readings in COMMISSION: the commissioning turns the shaft (SPIN: to 0.4 n_rated) and the
 * speed estimate follows it (it read 0 before: the monitor was written by ctrl_step only). */
static void readings_follow_the_shaft_while_commissioning(void **state)
{
    (void)state;
    const double i_follow_A = 0.02;
    sil_result_t res;
    run(NULL, 1, &res);
    assert_true(res.comm_valid);
    double se;
    double ie;
    const size_t n = follow((double)APP_STATE_COMMISSION, &se, &ie);
    const double bound = speed_follow_rpm();
    double top = 0.0;
    for (size_t k = 0; k < g_n; k++) {
        top = fmax(top, (g_rows[k].state == (double)APP_STATE_COMMISSION) ? fabs(g_rows[k].speed_est) : 0.0);
    }
    printf("  commissioning (%zu rows): speed_est up to %.0f r/min, within %.3g r/min (the PLL's bound %.3g); "
           "i_meas within %.3g A\n", n, top, se, bound, ie);
    assert_true(top > 500.0);              /* SPIN's 0.4 x 2000 r/min */
    assert_true(se < bound);
    assert_true(ie < i_follow_A);
}

/* Level 3 (ENC_CHECK: an open-loop vector turns the rotor a turn at 60 r/min): the readings. */
static void readings_follow_the_shaft_at_level_3(void **state)
{
    (void)state;
    static const char *const sets[] = { "run.level=3", "run.duration_s=2", NULL };
    const double i_follow_A = 0.02;
    sil_result_t res;
    run(sets, 0, &res);
    double se;
    double ie;
    const size_t n = follow((double)APP_STATE_ENC_CHECK, &se, &ie);
    const double bound = speed_follow_rpm();
    printf("  level 3 (%zu rows): speed_est within %.3g r/min (the PLL's bound %.3g), i_meas within %.3g A\n", n, se,
           bound, ie);
    assert_true(n > 1000u);
    assert_true(se < bound);
    assert_true(ie < i_follow_A);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(gate_trip_with_an_active_load_brakes_through_the_diodes),
        cmocka_unit_test(coulomb_friction_stops_a_turning_shaft),
        cmocka_unit_test(coulomb_friction_holds_a_shaft_at_rest),
        cmocka_unit_test(readings_follow_the_shaft_while_commissioning),
        cmocka_unit_test(readings_follow_the_shaft_at_level_3),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
