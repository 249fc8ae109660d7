/* The proposed method on a real inverter: inverter
 * voltage error not learned as flux, resistance tracked in service
 * (control/inverter_error_design.md, r_tracking_design.md), on the simulated board with the
 * switching inverter and the paper's timeline (tools/scenarios/prop_paper.ini,
 * conv_paper.ini: step 1 at 500 r/min, 2 and 4 N m; step 2 from 0.54 s,
 * the inverter error identified 0.1 s later).
 *
 *  - exact controller parameters with an inverter error the controller
 *    does not know: dead time 1 us told 0, told 2 us, a 1.5 V device drop;
 *    after step 1 the speed and load step through 1000, 500, 200 and
 *    100 r/min at 3 and 6 N m (0.35 s each, measured over the last
 *    0.15 s): the proposed method's mean |Te - Te*| at most the
 *    conventional one's + 0.005 N m at every point, psi_f^ within 2 % at
 *    >= 200 r/min, and the identified error the hand value (4/pi) dV;
 *  - a device drop the controller is told (as a commissioning writes it)
 *    is compensated by both methods: the small motor's torque error
 *    within 1 % of T_rated, a tenth of the untold one;
 *  - the winding warms 3.0 -> 3.9 ohm over 5 s at 500 r/min, 4 N m: with
 *    track_R R^ within 3 % of the plant's R from 1 s after step 2 on,
 *    psi_f^ within 1 %, mean |Te - Te*| <= 0.01 N m; without it psi_f^
 *    takes the warm-up (the case the tracking exists for);
 *  - the same warm-up (3.0 -> 3.6 ohm over 2-6 s) at 1500 r/min, 4 N m,
 *    track_R left at its default: each injection edge meets the voltage
 *    limit there for a period, and R^ must still follow, within 5 % (it
 *    stood at step 1's value, 17 % low at the end, while an edge's clamp
 *    held every cycle; the encoder's count error scatters the cycles by
 *    up to w psi_f dtheta / I = 7 % of R here, r_tracking_design.md sec. 5);
 *  - the same warm-up at 300 r/min: R^ within 3 % (the speed estimate's
 *    answer to each count arriving must not read as an acceleration that
 *    holds the tracking; with the gate's floor at 100 rad/s^2 every
 *    cycle was held and R^ stood at 3.0 ohm until 4.6 s, 11 % low);
 *  - the realistic scenarios of make sil (tools/scenarios/real_*.ini: ADC
 *    noise 0.02 A, dead time 1 us compensated as 0.9 us, device drop
 *    1.2 V, 1000-line encoder, winding 3.0 -> 3.9 ohm over the run): the
 *    proposed method's mean |Te - Te*| in the paper's window at most half
 *    the conventional one's in every mismatch case of the paper. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "app.h"
#include "sil.h"
#include "sil_scenario.h"

#define PSI0       0.24
#define PI_D       3.14159265358979323846
#define VDC        311.0
#define TS         1e-4
/* the staircase after the paper's step 1 */
#define N_POINTS   8
#define T_FIRST    0.8      /* first point's start [s] */
#define T_POINT    0.35     /* each point [s]: ramp 0.1 s, settle, measure */
#define T_MEASURE  0.2      /* from the point's start to its window */
#define RAMP_S     0.1
/* acceptance */
#define TE_MARGIN_NM    0.005
#define PSI_TOL         0.02
#define PSI_TOL_MIN_RPM 200.0
#define VE_TOL          0.05   /* identified error against (4/pi) dV */
#define R_TOL           0.03
#define R_TOL_1500      0.05    /* at 1500 r/min: the encoder's scatter (header) */
#define PSI_TOL_WARM    0.01
#define TE_MAX_WARM_NM  0.01
#define T_AFTER_STEP2   1.0
#define REAL_RATIO_MAX  0.5
#define WIN_T0          0.80     /* the paper's steady window */
#define WIN_T1          0.95

static const double POINT_RPM[N_POINTS] = { 1000, 1000, 500, 500, 200, 200, 100, 100 };
static const double POINT_NM[N_POINTS] = { 3, 6, 3, 6, 3, 6, 3, 6 };

typedef struct {
    double te_abs[N_POINTS], psi[N_POINTS];
    long n[N_POINTS];
    double inv_err, t2;
    /* warming winding */
    double R_dev, psi_dev, te_sum;
    long n_warm;
    int state, fault;
} fig_t;

static fig_t fig;

static int on_row_points(const sil_row_t *r, void *user)
{
    (void)user;
    fig.state = (int)r->state;
    fig.fault = (int)r->fault;
    fig.inv_err = r->inv_err_est_V;
    for (int i = 0; i < N_POINTS; i++) {
        const double t0 = T_FIRST + T_POINT * i + T_MEASURE;
        if (r->t_s >= t0 && r->t_s < T_FIRST + T_POINT * (i + 1)) {
            fig.te_abs[i] += fabs(r->te_Nm - r->te_ref_Nm);
            fig.psi[i] += r->psif_est_Wb;
            fig.n[i]++;
        }
    }
    return 0;
}

/* The judged window [win_t0, win_t1) [s]: the paper's unless run_window sets another. */
static double win_t0 = WIN_T0;
static double win_t1 = WIN_T1;

static int on_row_window(const sil_row_t *r, void *user)
{
    (void)user;
    fig.state = (int)r->state;
    fig.fault = (int)r->fault;
    if (r->t_s >= win_t0 && r->t_s < win_t1) {
        fig.te_sum += fabs(r->te_Nm - r->te_ref_Nm);
        fig.n_warm++;
    }
    return 0;
}

static int on_row_warm(const sil_row_t *r, void *user)
{
    (void)user;
    fig.state = (int)r->state;
    fig.fault = (int)r->fault;
    if (isnan(fig.t2) && (int)r->est == EST_STEP2) {
        fig.t2 = r->t_s;
    }
    if (!isnan(fig.t2) && r->t_s >= fig.t2 + T_AFTER_STEP2) {
        fig.R_dev = fmax(fig.R_dev, fabs(r->R_est_ohm / r->R_ohm - 1.0));
        fig.psi_dev = fmax(fig.psi_dev, fabs(r->psif_est_Wb / PSI0 - 1.0));
        fig.te_sum += fabs(r->te_Nm - r->te_ref_Nm);
        fig.n_warm++;
    }
    return 0;
}

static void run(const char *stem, const char *const *sets, sil_row_fn fn)
{
    scenario_t sc;
    sil_result_t res;
    memset(&fig, 0, sizeof fig);
    fig.t2 = NAN;
    sil_scenario_open(&sc, stem);
    sil_scenario_set(&sc, sets);
    sil_scenario_finish(&sc);
    assert_int_equal(sil_run(&sc, fn, NULL, &res), 0);
    assert_int_equal(fig.state, APP_STATE_RUN);
    assert_int_equal(fig.fault, APP_FAULT_NONE);
}

/* A run's mean |Te - Te*| over [t0_s, t1_s) into fig.te_sum / fig.n_warm. */
static void run_window(const char *stem, const char *const *sets, double t0_s, double t1_s)
{
    win_t0 = t0_s;
    win_t1 = t1_s;
    run(stem, sets, on_row_window);
    win_t0 = WIN_T0;
    win_t1 = WIN_T1;
    assert_true(fig.n_warm > 0);
}

/* The staircase's speed and load profiles as scenario overrides. */
static void staircase(char *speed, size_t ns, char *load, size_t nl, char *dur, size_t nd)
{
    int a = snprintf(speed, ns, "reference.speed_rpm=0:0, 0.2:500~");
    int b = snprintf(load, nl, "load.torque_Nm=0:2, 0.35:4");
    double prev = 500.0;
    for (int i = 0; i < N_POINTS; i++) {
        const double t = T_FIRST + T_POINT * i;
        if (fabs(POINT_RPM[i] - prev) > 0.5) {
            a += snprintf(speed + a, ns - (size_t)a, ", %.3f:%g, %.3f:%g~", t, prev, t + RAMP_S, POINT_RPM[i]);
            prev = POINT_RPM[i];
        }
        b += snprintf(load + b, nl - (size_t)b, ", %.3f:%g", t, POINT_NM[i]);
    }
    snprintf(dur, nd, "run.duration_s=%.3f", T_FIRST + T_POINT * N_POINTS);
}

/* One inverter condition: both methods on the staircase; Ve_expect the
 * rotor-frame error the proposed method must identify [V]. */
static void inverter_condition(const char *name, const char *s1, const char *s2, double Ve_expect)
{
    char speed[512];
    char load[512];
    char dur[64];
    double conv[N_POINTS];
    staircase(speed, sizeof speed, load, sizeof load, dur, sizeof dur);
    const char *const sets[] = { speed, load, dur, s1, s2, NULL };

    run("conv_paper", sets, on_row_points);
    for (int i = 0; i < N_POINTS; i++) {
        assert_true(fig.n[i] > 0);
        conv[i] = fig.te_abs[i] / (double)fig.n[i];
    }
    run("prop_paper", sets, on_row_points);
    print_message("%s: inverter error identified %.3f V (hand value %.3f V)\n", name, fig.inv_err, Ve_expect);
    assert_true(fabs(fig.inv_err - Ve_expect) <= VE_TOL * fabs(Ve_expect));
    for (int i = 0; i < N_POINTS; i++) {
        const double te = fig.te_abs[i] / (double)fig.n[i];
        const double psi = fig.psi[i] / (double)fig.n[i] / PSI0 - 1.0;
        print_message("  %4.0f r/min %.0f N m: |Te-Te*| proposed %.4f, conventional %.4f N m; psi_f^ %+.2f %%\n",
                      POINT_RPM[i], POINT_NM[i], te, conv[i], 100.0 * psi);
        assert_true(te <= conv[i] + TE_MARGIN_NM);
        if (POINT_RPM[i] >= PSI_TOL_MIN_RPM) {
            assert_true(fabs(psi) <= PSI_TOL);
        }
    }
}

/* (4/pi) dV: fundamental of a per-leg square wave of amplitude dV. */
static double fundamental(double dV)
{
    return 4.0 / PI_D * dV;
}

static void deadtime_told_zero(void **state)
{
    (void)state;
    inverter_condition("dead time 1 us, told 0", "plant.deadtime_s=1e-6", "controller.deadtime_s=0",
                       fundamental(1e-6 / TS * VDC));
}

static void deadtime_told_double(void **state)
{
    (void)state;
    inverter_condition("dead time 1 us, told 2 us", "plant.deadtime_s=1e-6", "controller.deadtime_s=2e-6",
                       fundamental(-1e-6 / TS * VDC));
}

static void device_drop_uncompensated(void **state)
{
    (void)state;
    inverter_condition("device drop 1.5 V", "plant.device_drop_V=1.5", "controller.deadtime_s=0",
                       fundamental(1.5));
}

/* The small motor (24 V, L 0.2 mH: the deadbeat's gain L/Ts = 2 V/A),
 * conventional scenario at 1500 r/min, a 1.2 V device drop on the
 * switching board. Untold, each leg loses 1.2 V against its current: a
 * q voltage (4/pi) 1.2 = 1.53 V short, Ts/L of it = 0.76 A of i_q, kt
 * 0.048 N m/A: about 0.04 N m of torque missing (the SIL: 0.07). Told
 * ([controller] device_drop_V, as a commissioning writes it), both
 * methods feed it forward in the deadbeat's voltage: within 1 % of T_rated
 * (0.3 N m) and below a tenth of the untold error. */
static void device_drop_told_is_compensated_by_both_methods(void **state)
{
    const char *const untold[] = { "plant.device_drop_V=1.2", "identify.mode=trusted", NULL };
    const char *const told_conv[] = { "plant.device_drop_V=1.2", "controller.device_drop_V=1.2",
                                      "identify.mode=trusted", NULL };
    const char *const told_prop[] = { "plant.device_drop_V=1.2", "controller.device_drop_V=1.2",
                                      "identify.mode=trusted", "controller.method=proposed", NULL };
    const double t_rated = 1.5 * 4.0 * 0.008 * 6.25;
    (void)state;
    run_window("conv_motor_small", untold, 2.5, 3.0);
    const double te_untold = fig.te_sum / (double)fig.n_warm;
    run_window("conv_motor_small", told_conv, 2.5, 3.0);
    const double te_conv = fig.te_sum / (double)fig.n_warm;
    run_window("conv_motor_small", told_prop, 2.5, 3.0);
    const double te_prop = fig.te_sum / (double)fig.n_warm;
    print_message("device drop 1.2 V: mean |Te-Te*| untold %.4f, told conventional %.4f, proposed %.4f N m\n",
                  te_untold, te_conv, te_prop);
    assert_true(te_untold > 0.03);
    assert_true(te_conv <= 0.01 * t_rated && te_conv <= 0.1 * te_untold);
    assert_true(te_prop <= 0.01 * t_rated && te_prop <= 0.1 * te_untold);
}

static void winding_warms(void **state)
{
    (void)state;
    const char *const on[] = { "plant.R_ohm=0:3.0, 5:3.9~", "run.duration_s=6", "identify.track_R=on", NULL };
    const char *const off[] = { "plant.R_ohm=0:3.0, 5:3.9~", "run.duration_s=6", "identify.track_R=off", NULL };
    run("prop_paper", on, on_row_warm);
    const double te = fig.te_sum / (double)fig.n_warm;
    print_message("warming winding, track_R on:  max |R^/R - 1| %.2f %%, max |psi_f^/psi_f - 1| %.2f %%, "
                  "mean |Te-Te*| %.4f N m (from %.2f s)\n",
                  100.0 * fig.R_dev, 100.0 * fig.psi_dev, te, fig.t2 + T_AFTER_STEP2);
    assert_true(fig.n_warm > 0);
    assert_true(fig.R_dev <= R_TOL);
    assert_true(fig.psi_dev <= PSI_TOL_WARM);
    assert_true(te <= TE_MAX_WARM_NM);

    run("prop_paper", off, on_row_warm);
    print_message("warming winding, track_R off: max |R^/R - 1| %.2f %%, max |psi_f^/psi_f - 1| %.2f %%, "
                  "mean |Te-Te*| %.4f N m\n",
                  100.0 * fig.R_dev, 100.0 * fig.psi_dev, fig.te_sum / (double)fig.n_warm);
    assert_true(fig.psi_dev > PSI_TOL_WARM);   /* the warm-up learned as flux */
}

static void winding_warms_at_the_edges_limit(void **state)
{
    (void)state;
    const char *const sets[] = { "plant.R_ohm=0:3.0, 2:3.0, 6:3.6~", "run.duration_s=6",
                                 "reference.speed_rpm=0:0, 0.2:500~, 0.7:500, 1.2:1500~", "load.torque_Nm=0:2, 0.35:4",
                                 NULL };
    run("prop_paper", sets, on_row_warm);
    print_message("warming winding at 1500 r/min, track_R default: max |R^/R - 1| %.2f %% (from %.2f s)\n",
                  100.0 * fig.R_dev, fig.t2 + T_AFTER_STEP2);
    assert_int_equal(fig.fault, APP_FAULT_NONE);
    assert_true(fig.n_warm > 0);
    assert_true(fig.R_dev <= R_TOL_1500);
}

static void winding_warms_at_low_speed(void **state)
{
    (void)state;
    const char *const sets[] = { "plant.R_ohm=0:3.0, 2:3.0, 6:3.6~", "run.duration_s=6",
                                 "reference.speed_rpm=0:0, 0.2:500~, 0.7:500, 1.2:300~", "load.torque_Nm=0:2, 0.35:4",
                                 NULL };
    run("prop_paper", sets, on_row_warm);
    print_message("warming winding at 300 r/min, track_R default: max |R^/R - 1| %.2f %% (from %.2f s)\n",
                  100.0 * fig.R_dev, fig.t2 + T_AFTER_STEP2);
    assert_true(fig.n_warm > 0);
    assert_true(fig.R_dev <= R_TOL);
}

static void realistic_board(void **state)
{
    (void)state;
    static const char *const cases[] = { "R430", "L150", "L066", "psif200", "psif050", "L066_psif150" };
    const char *const none[] = { NULL };
    char stem[64];
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        snprintf(stem, sizeof stem, "real_conv_%s", cases[k]);
        run(stem, none, on_row_window);
        const double conv = fig.te_sum / (double)fig.n_warm;
        snprintf(stem, sizeof stem, "real_prop_%s", cases[k]);
        run(stem, none, on_row_window);
        const double prop = fig.te_sum / (double)fig.n_warm;
        print_message("realistic %-13s |Te-Te*| proposed %.4f, conventional %.4f N m (%.2f x)\n", cases[k], prop, conv,
                      prop / conv);
        assert_true(prop <= REAL_RATIO_MAX * conv);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(deadtime_told_zero),
        cmocka_unit_test(deadtime_told_double),
        cmocka_unit_test(device_drop_uncompensated),
        cmocka_unit_test(device_drop_told_is_compensated_by_both_methods),
        cmocka_unit_test(winding_warms),
        cmocka_unit_test(winding_warms_at_the_edges_limit),
        cmocka_unit_test(winding_warms_at_low_speed),
        cmocka_unit_test(realistic_board),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
