/* inverter.c - averaged and switching inverter models; see inverter.h. */
#include "inverter.h"

#include <math.h>
#include <stdlib.h>

#define SQRT3 1.7320508075688772
#define N_LEGS 3
#define EDGES_PER_LEG 4
#define MAX_BREAKS (N_LEGS * EDGES_PER_LEG + 2)

static double clamp01(double d)
{
    if (d > 1.0) {
        return 1.0;
    }
    return (d >= 0.0) ? d : 0.0;   /* NaN maps to 0 */
}

leg_state_t inv_leg_state(const inv_cfg_t *cfg, double duty, double t_s)
{
    double d = clamp01(duty);
    if (d <= 0.0) {
        return LEG_LOW;
    }
    if (d >= 1.0) {
        return LEG_HIGH;
    }
    double t_on = 0.5 * (1.0 - d) * cfg->Ts_s;
    double t_off = 0.5 * (1.0 + d) * cfg->Ts_s;
    if (t_s >= t_on + cfg->deadtime_s && t_s < t_off) {
        return LEG_HIGH;
    }
    if (t_s >= t_on && t_s < t_off + cfg->deadtime_s) {
        return LEG_DEAD;
    }
    return LEG_LOW;
}

int inv_leg_edges(const inv_cfg_t *cfg, double duty, double t_s[4])
{
    double d = clamp01(duty);
    if (d <= 0.0 || d >= 1.0) {
        return 0;
    }
    double t_on = 0.5 * (1.0 - d) * cfg->Ts_s;
    double t_off = 0.5 * (1.0 + d) * cfg->Ts_s;
    double cand[EDGES_PER_LEG] = { t_on, t_on + cfg->deadtime_s, t_off, t_off + cfg->deadtime_s };
    int n = 0;
    for (int k = 0; k < EDGES_PER_LEG; k++) {
        /* Without dead time the delayed edges coincide; a dead band past Ts is cut at the period end. */
        if (cand[k] > 0.0 && cand[k] < cfg->Ts_s && (n == 0 || cand[k] > t_s[n - 1])) {
            t_s[n++] = cand[k];
        }
    }
    return n;
}

/* Sign of the current, 0 at exactly 0. */
static double sign_of(double i_A)
{
    return (i_A > 0.0) ? 1.0 : ((i_A < 0.0) ? -1.0 : 0.0);
}

/* Leg voltage [V] against the negative rail, before the device drop; a
 * dead leg follows its current's sign. */
static double leg_voltage(const inv_cfg_t *cfg, leg_state_t st, double i_A)
{
    if (st == LEG_HIGH || (st == LEG_DEAD && i_A < 0.0)) {
        return cfg->vdc_V;
    }
    return 0.0;
}

/* The leg currents are needed for the dead band's diode and the device drop. */
static bool needs_current(const inv_cfg_t *cfg)
{
    return cfg->deadtime_s > 0.0 || cfg->device_drop_V > 0.0;
}

/* Alpha-beta of three leg voltages; the common mode drops out. */
static void legs_to_ab(const double v_V[N_LEGS], double *ua_V, double *ub_V)
{
    *ua_V = (2.0 * v_V[0] - v_V[1] - v_V[2]) / 3.0;
    *ub_V = (v_V[1] - v_V[2]) / SQRT3;
}

/* Integrate over [0, span_s] in equal RK4 steps no longer than substep_max_s. */
static void integrate_piece(const inv_cfg_t *cfg, plant_t *plant, double ua_V, double ub_V,
                            double TL_Nm, double span_s)
{
    double n_steps = ceil(span_s / cfg->substep_max_s);
    if (n_steps < 1.0) {
        n_steps = 1.0;
    }
    double h = span_s / n_steps;
    for (int k = 0; k < (int)n_steps; k++) {
        plant_step(plant, ua_V, ub_V, TL_Nm, h);
    }
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a;
    double y = *(const double *)b;
    return (x > y) - (x < y);
}

/* High time of one leg [s] over the period, the dead band counted for i < 0. */
static double leg_high_time(const inv_cfg_t *cfg, double duty, double i_A)
{
    double edges[EDGES_PER_LEG];
    int n = inv_leg_edges(cfg, duty, edges);
    double high_s = 0.0;
    double t0 = 0.0;
    for (int k = 0; k <= n; k++) {
        double t1 = (k < n) ? edges[k] : cfg->Ts_s;
        leg_state_t st = inv_leg_state(cfg, duty, 0.5 * (t0 + t1));
        if (leg_voltage(cfg, st, i_A) > 0.0) {
            high_s += t1 - t0;
        }
        t0 = t1;
    }
    return high_s;
}

static void period_averaged(const inv_cfg_t *cfg, const double duty[3], double TL_Nm, plant_t *plant)
{
    double i_abc[N_LEGS] = { 0.0, 0.0, 0.0 };
    if (needs_current(cfg)) {
        plant_iabc_A(plant, i_abc);
    }
    double v[N_LEGS];
    for (int k = 0; k < N_LEGS; k++) {
        v[k] = cfg->vdc_V * leg_high_time(cfg, duty[k], i_abc[k]) / cfg->Ts_s -
               cfg->device_drop_V * sign_of(i_abc[k]);
    }
    double ua;
    double ub;
    legs_to_ab(v, &ua, &ub);
    integrate_piece(cfg, plant, ua, ub, TL_Nm, cfg->Ts_s);
}

static void period_switching(const inv_cfg_t *cfg, const double duty[3], double TL_Nm, plant_t *plant)
{
    double br[MAX_BREAKS];
    int n = 0;
    for (int k = 0; k < N_LEGS; k++) {
        n += inv_leg_edges(cfg, duty[k], &br[n]);
    }
    qsort(br, (size_t)n, sizeof br[0], cmp_double);
    br[n++] = cfg->Ts_s;

    double t0 = 0.0;
    for (int j = 0; j < n; j++) {
        double t1 = br[j];
        if (t1 <= t0) {
            continue;   /* coinciding edges of different legs */
        }
        double i_abc[N_LEGS] = { 0.0, 0.0, 0.0 };
        if (needs_current(cfg)) {
            plant_iabc_A(plant, i_abc);
        }
        double v[N_LEGS];
        for (int k = 0; k < N_LEGS; k++) {
            v[k] = leg_voltage(cfg, inv_leg_state(cfg, duty[k], 0.5 * (t0 + t1)), i_abc[k]) -
                   cfg->device_drop_V * sign_of(i_abc[k]);
        }
        double ua;
        double ub;
        legs_to_ab(v, &ua, &ub);
        integrate_piece(cfg, plant, ua, ub, TL_Nm, t1 - t0);
        t0 = t1;
    }
}

void inv_period(const inv_cfg_t *cfg, const double duty[3], double TL_Nm, plant_t *plant)
{
    if (cfg->model == INV_SWITCHING) {
        period_switching(cfg, duty, TL_Nm, plant);
    } else {
        period_averaged(cfg, duty, TL_Nm, plant);
    }
}
