/* Operating limits in the SIL (switching inverter, Table I motor): limits that hold
 * whatever the estimates do, estimation that pauses through transients,
 * flux weakening at the voltage limit. Every case runs both methods on the
 * same scenario (tools/scenarios/prop_lim_*, prop_fw_*; the method
 * switched by an override) and compares with the plant's true values or
 * with values derived here from the machine equations. Figures are
 * printed for the closing note. */
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

#define PI_D      3.14159265358979323846
#define RPM       (2.0 * PI_D / 60.0)
#define R0        3.0
#define L0        0.011
#define PSI0      0.24
#define PP        3.0
#define KT0       (1.5 * PP * PSI0)
#define VDC       311.0
#define I_LIMIT_A (2.0 * 6.0 / KT0) /* the derived current limit: i_peak = 2 i_rated, 11.1 A */

#define NO_FAULT_STATE APP_STATE_RUN

/* ---- one run: figures over windows ------------------------------------- */

typedef struct {
    double w0, w1;              /* window A: mean |Te - Te*|, speed band, estimates */
    double te_abs;  long n;
    double te_mean;
    double spd_min, spd_max;
    double id_max;              /* largest true id in the window */
    double te_peak;             /* largest |true Te| over the whole run */
    double est_dev;             /* largest |L^/L0 - 1|, |psi^/psi0 - 1| in step 2 from t_est on */
    double t_est;
    double L_ratio, psi_ratio;  /* true / controller's factor: the estimates' truth is L0, psi0 */
    double psi_last;            /* psi^ at the end */
} fig_t;

static fig_t fig;

static int on_row(const sil_row_t *r, void *user)
{
    (void)user;
    fig.te_peak = fmax(fig.te_peak, fabs(r->te_Nm));
    if (r->t_s >= fig.w0 && r->t_s < fig.w1) {
        fig.te_abs += fabs(r->te_Nm - r->te_ref_Nm);
        fig.te_mean += r->te_Nm;
        fig.n++;
        fig.spd_min = fmin(fig.spd_min, r->speed_rpm);
        fig.spd_max = fmax(fig.spd_max, r->speed_rpm);
        fig.id_max = fmax(fig.id_max, r->id_A);
    }
    if ((int)r->est == EST_STEP2 && r->t_s >= fig.t_est) {
        fig.est_dev = fmax(fig.est_dev, fabs(r->L_est_H / L0 - 1.0));
        fig.est_dev = fmax(fig.est_dev, fabs(r->psif_est_Wb / PSI0 - 1.0));
    }
    fig.psi_last = r->psif_est_Wb;
    return 0;
}

/* Runs tools/scenarios/<name>.ini with method m and the overrides (NULL-terminated). */
static void run(const char *name, const char *method, const char *const *sets, double w0, double w1,
                double t_est, sil_result_t *res)
{
    scenario_t sc;
    char m[64];
    const char *const method_sets[] = { m, "run.log_every=1", NULL };
    static const char *const no_step1[] = { "identify.mode=off", NULL };

    memset(&fig, 0, sizeof fig);
    fig.w0 = w0;
    fig.w1 = w1;
    fig.t_est = t_est;
    fig.spd_min = 1e9;
    fig.spd_max = -1e9;
    fig.id_max = -1e9;
    snprintf(m, sizeof m, "controller.method=%s", method);
    sil_scenario_open(&sc, name);
    sil_scenario_set(&sc, method_sets);
    if (strcmp(method, "conventional") == 0) {
        sil_scenario_set(&sc, no_step1);
    }
    sil_scenario_set(&sc, sets);
    sil_scenario_finish(&sc);
    assert_int_equal(sil_run(&sc, on_row, NULL, res), 0);
}

static const char *const METHODS[2] = { "conventional", "proposed" };

/* ---- speed steps +1000 -> -1000 / 0 r/min at 0.8 s, 2 N m ---------------- */

#define REV_T_STEP     0.8
#define REV_I_TOL      1.05    /* peak |i| within 5 % of i_limit_A */
#define REV_EST_TOL    0.02    /* estimates within 2 % ... */
#define REV_EST_AFTER  0.05    /* ... 50 ms after the speed settles */
#define REV_SETTLE_S   0.15    /* the speed settles (both methods) within 150 ms of the step: from the trace */
#define REV_TE_PEAK    6.3     /* te_max 6: peak true torque */

static const char *const REV_PARAMS[3][3] = {
    { NULL, NULL, NULL },
    { "controller.L_factor=1.5", NULL, NULL },
    { "controller.L_factor=1.3", "controller.psif_factor=0.8", NULL },
};

static void reversal(const char *target, const char *te_max)
{
    char ref[96];
    snprintf(ref, sizeof ref, "reference.speed_rpm=0:0, 0.2:1000~, 0.8:%s", target);
    for (int p = 0; p < 3; p++) {
        for (int m = 0; m < 2; m++) {
            const char *sets[6] = { ref, te_max, NULL, NULL, NULL, NULL };
            sil_result_t res;
            int k = 2;
            for (int j = 0; j < 2 && REV_PARAMS[p][j] != NULL; j++) {
                sets[k++] = REV_PARAMS[p][j];
            }
            run("prop_lim_reversal", METHODS[m], sets, 0.0, 0.0, REV_T_STEP + REV_SETTLE_S + REV_EST_AFTER,
                &res);
            print_message("step to %s r/min, %s, %s %s: state %d fault %d, peak |i| %.2f A, peak |Te| %.2f N m, "
                          "estimates after settling within %.3f %%\n",
                          target, te_max, METHODS[m], p == 0 ? "exact" : (p == 1 ? "L = 1.5 L0" : "L = 1.3 L0, psi = 0.8 psi0"),
                          res.final_state, res.final_fault, res.max_abs_i_A, fig.te_peak, 100.0 * fig.est_dev);
            assert_int_equal(res.final_fault, APP_FAULT_NONE);
            assert_int_equal(res.final_state, NO_FAULT_STATE);
            assert_true(res.max_abs_i_A <= REV_I_TOL * I_LIMIT_A);
            /* the true-torque bound: the proposed method whatever its start
             * parameters; the conventional one has only its nominal
             * parameters (L = 1.5 L0: 7.5 N m, printed) and is held to it
             * with exact ones */
            if (strcmp(te_max, "controller.te_max_Nm=6") == 0 && (m == 1 || p == 0)) {
                assert_true(fig.te_peak <= REV_TE_PEAK);
            }
            if (m == 1) {
                assert_true(fig.est_dev <= REV_EST_TOL);
            }
        }
    }
}

static void reversal_to_minus_1000(void **state) { (void)state; reversal("-1000", "controller.te_max_Nm=12"); }
static void reversal_to_0(void **state) { (void)state; reversal("0", "controller.te_max_Nm=12"); }
static void reversal_te_max_6(void **state)
{
    (void)state;
    reversal("-1000", "controller.te_max_Nm=6");
    reversal("0", "controller.te_max_Nm=6");
}

/* ---- decelerate 500 -> 50 r/min in 50 ms at 3 N m ------------------------- */

#define DEC_PSI_TOL   0.01
#define DEC_TE_ERR    0.01     /* mean |Te - Te*| at 50 r/min [N m] */

static void decel_holds_estimates(void **state)
{
    (void)state;
    for (int m = 0; m < 2; m++) {
        sil_result_t res;
        run("prop_lim_decel", METHODS[m], NULL, 0.95, 1.2, 0.6, &res);
        const double te = fig.te_abs / (double)fig.n;
        print_message("decel 500 -> 50 r/min, %s: mean |Te - Te*| at 50 r/min %.4f N m, psi^ %+.3f %%\n",
                      METHODS[m], te, 100.0 * (fig.psi_last / PSI0 - 1.0));
        assert_int_equal(res.final_fault, APP_FAULT_NONE);
        assert_true(te <= DEC_TE_ERR);
        if (m == 1) {
            assert_true(fabs(fig.psi_last / PSI0 - 1.0) <= DEC_PSI_TOL);
            assert_true(fig.est_dev <= DEC_PSI_TOL * 5.0); /* L^ too, the 5 % bound of the ramps */
        }
    }
}

/* ---- ramped reversals 2500 and 10000 r/min/s -------------------------------- */

#define RAMP_EST_TOL 0.05

static void ramp_reversal(const char *profile, double t0, double t1)
{
    double te[2];
    for (int m = 0; m < 2; m++) {
        const char *const sets[] = { profile, NULL };
        sil_result_t res;
        run("prop_lim_ramp_reversal", METHODS[m], sets, t0, t1, 0.6, &res);
        te[m] = fig.te_abs / (double)fig.n;
        print_message("ramped reversal %s, %s: mean |Te - Te*| during the ramp %.4f N m, estimates within %.3f %%\n",
                      profile + strlen("reference.speed_rpm="), METHODS[m], te[m], 100.0 * fig.est_dev);
        assert_int_equal(res.final_fault, APP_FAULT_NONE);
        if (m == 1) {
            assert_true(fig.est_dev <= RAMP_EST_TOL);
        }
    }
    assert_true(te[1] <= te[0]);
}

static void ramped_reversals(void **state)
{
    (void)state;
    ramp_reversal("reference.speed_rpm=0:0, 0.2:1000~, 0.8:1000, 1.6:-1000~", 0.8, 1.6);
    ramp_reversal("reference.speed_rpm=0:0, 0.2:1000~, 0.8:1000, 1.0:-1000~", 0.8, 1.0);
}

/* ---- voltage limit ----------------------------------------------------------- */

/* Ramp to 2050 r/min in 0.2 s under 6 N m: speed within 1 % after 0.3 s, torque within 2 %. */
#define FW_SPEED_TOL 0.01
#define FW_TE_TOL    0.02

static void ramp_2050_rated_torque(void **state)
{
    (void)state;
    for (int m = 0; m < 2; m++) {
        sil_result_t res;
        run("prop_fw_2050", METHODS[m], NULL, 0.3, 0.6, 0.0, &res);
        const double te_mean = fig.te_mean / (double)fig.n;
        print_message("2050 r/min at 6 N m, %s: speed %.1f .. %.1f r/min, mean Te %.4f N m, mean |Te - Te*| %.4f N m, "
                      "peak |i| %.2f A\n", METHODS[m], fig.spd_min, fig.spd_max, te_mean,
                      fig.te_abs / (double)fig.n, res.max_abs_i_A);
        assert_int_equal(res.final_fault, APP_FAULT_NONE);
        assert_true(fig.spd_min >= 2050.0 * (1.0 - FW_SPEED_TOL) && fig.spd_max <= 2050.0 * (1.0 + FW_SPEED_TOL));
        assert_true(fabs(te_mean - 6.0) <= FW_TE_TOL * 6.0);
        assert_true(fig.te_abs / (double)fig.n <= FW_TE_TOL * 6.0);
    }
}

/* Speed mode to 2800 r/min at 1 N m, overspeed 3200 r/min: reached, id < 0, |i| within the limit. */
static void speed_2800_weakens_field(void **state)
{
    (void)state;
    for (int m = 0; m < 2; m++) {
        sil_result_t res;
        run("prop_fw_2800", METHODS[m], NULL, 0.6, 0.8, 0.0, &res);
        print_message("2800 r/min at 1 N m, %s: speed %.1f .. %.1f r/min, largest id %.2f A, peak |i| %.2f A\n",
                      METHODS[m], fig.spd_min, fig.spd_max, fig.id_max, res.max_abs_i_A);
        assert_int_equal(res.final_fault, APP_FAULT_NONE);
        assert_true(fig.spd_min >= 2800.0 * (1.0 - FW_SPEED_TOL) && fig.spd_max <= 2800.0 * (1.0 + FW_SPEED_TOL));
        assert_true(fig.id_max < 0.0);
        assert_true(res.max_abs_i_A <= I_LIMIT_A);
    }
}

/* Largest torque at electrical speed w within |i| <= I and |u| <= Vdc/sqrt(3)
 * (steady state of the true machine, u = R i + j w psi): scan id, for each
 * the largest iq by bisection. Independent of the controller's code. */
static double te_max_at(double w, double I)
{
    const double vmax = VDC / sqrt(3.0);
    double best = 0.0;
    for (int k = 0; k <= 2400; k++) {
        const double id = -I * (double)k / 2400.0;
        double lo = 0.0;
        double hi = sqrt(fmax(I * I - id * id, 0.0));
        for (int it = 0; it < 60; it++) {
            const double iq = 0.5 * (lo + hi);
            const double ud = R0 * id - w * L0 * iq;
            const double uq = R0 * iq + w * (PSI0 + L0 * id);
            if (ud * ud + uq * uq <= vmax * vmax) {
                lo = iq;
            } else {
                hi = iq;
            }
        }
        best = fmax(best, KT0 * lo);
    }
    return best;
}

#define HELD_TOL 0.05
#define HELD_SHARE_MIN 0.85   /* steady torque at the limits / their maximum: u_margin 0.92 of the voltage */

static void torque_mode_2200_more_is_more(void **state)
{
    (void)state;
    const double t_max = te_max_at(2200.0 * RPM * PP, I_LIMIT_A);
    for (int m = 0; m < 2; m++) {
        sil_result_t res;
        double te3;
        double te6;
        run("prop_fw_torque_2200", METHODS[m], NULL, 0.1, 0.2, 0.0, &res);
        te3 = fig.te_mean / (double)fig.n;
        run("prop_fw_torque_2200", METHODS[m], NULL, 0.3, 0.4, 0.0, &res);
        te6 = fig.te_mean / (double)fig.n;
        print_message("held at 2200 r/min, %s: Te* 3 -> %.3f N m, Te* 6 -> %.3f N m (limits allow %.3f N m)\n",
                      METHODS[m], te3, te6, t_max);
        assert_int_equal(res.final_fault, APP_FAULT_NONE);
        assert_true(te6 >= te3);
        assert_true(te6 >= (1.0 - HELD_TOL) * fmin(6.0, t_max));
        /* Te* = 12 N m, beyond the limits: the flux-first voltage limit
         * keeps i_d negative through the step (the torque-first clamp ran
         * it to +7.8 A and the torque down to 1.4 N m), and the torque
         * settles at the weakening loop's u_margin of the voltage */
        const char *const sets12[] = { "reference.torque_Nm=0:3, 0.2:12", NULL };
        run("prop_fw_torque_2200", METHODS[m], sets12, 0.2, 0.4, 0.0, &res);
        const double id_max = fig.id_max;
        run("prop_fw_torque_2200", METHODS[m], sets12, 0.3, 0.4, 0.0, &res);
        const double te12 = fig.te_mean / (double)fig.n;
        print_message("held at 2200 r/min, %s: Te* 12 -> %.3f N m (%.1f %% of %.3f), largest id after the step %.2f A\n",
                      METHODS[m], te12, 100.0 * te12 / t_max, t_max, id_max);
        assert_int_equal(res.final_fault, APP_FAULT_NONE);
        assert_true(id_max < 0.0);
        assert_true(te12 >= HELD_SHARE_MIN * t_max);
    }
}

/* ---- paper load step 4 -> 6 -> 4 N m, exact parameters --------------------- */

static void paper_load_step_as_clean(void **state)
{
    double te[2];
    double back[2];
    static const char *const names[2] = { "conv_paper", "prop_paper" };
    (void)state;
    for (int m = 0; m < 2; m++) {
        sil_result_t res;
        run(names[m], METHODS[m], NULL, 1.05, 1.15, 0.0, &res);
        back[m] = fig.te_abs / (double)fig.n;
        run(names[m], METHODS[m], NULL, 0.95, 1.05, 0.0, &res);
        te[m] = fig.te_abs / (double)fig.n;
        assert_int_equal(res.final_fault, APP_FAULT_NONE);
    }
    print_message("paper load step, mean |Te - Te*| over 0.95-1.05 s: conventional %.5f, proposed %.5f N m "
                  "(6 -> 4 N m over 1.05-1.15 s: %.5f, %.5f)\n", te[0], te[1], back[0], back[1]);
    assert_true(te[1] <= te[0]);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(reversal_to_minus_1000),
        cmocka_unit_test(reversal_to_0),
        cmocka_unit_test(reversal_te_max_6),
        cmocka_unit_test(decel_holds_estimates),
        cmocka_unit_test(ramped_reversals),
        cmocka_unit_test(ramp_2050_rated_torque),
        cmocka_unit_test(speed_2800_weakens_field),
        cmocka_unit_test(torque_mode_2200_more_is_more),
        cmocka_unit_test(paper_load_step_as_clean),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
