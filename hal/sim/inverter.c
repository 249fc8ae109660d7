/* inverter.c - averaged and switching inverter models; see inverter.h. */
#include "inverter.h"

#include <math.h>

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

/* A leg's switching instants in one period (0 < duty < 1), or a leg held at one rail. */
typedef struct {
    leg_state_t held;          /* LEG_LOW / LEG_HIGH for duty <= 0 / >= 1, else LEG_DEAD (switching) */
    double on_s, off_s;        /* upper gate on / off command */
    double deadtime_s;
} leg_times_t;

static void leg_times(const inv_cfg_t *cfg, double duty, leg_times_t *lt)
{
    double d = clamp01(duty);
    lt->held = (d <= 0.0) ? LEG_LOW : ((d >= 1.0) ? LEG_HIGH : LEG_DEAD);
    lt->on_s = 0.5 * (1.0 - d) * cfg->Ts_s;
    lt->off_s = 0.5 * (1.0 + d) * cfg->Ts_s;
    lt->deadtime_s = cfg->deadtime_s;
}

static leg_state_t leg_state_at(const leg_times_t *lt, double t_s)
{
    if (lt->held != LEG_DEAD) {
        return lt->held;
    }
    if (t_s >= lt->on_s + lt->deadtime_s && t_s < lt->off_s) {
        return LEG_HIGH;
    }
    if (t_s >= lt->on_s && t_s < lt->off_s + lt->deadtime_s) {
        return LEG_DEAD;
    }
    return LEG_LOW;
}

leg_state_t inv_leg_state(const inv_cfg_t *cfg, double duty, double t_s)
{
    leg_times_t lt;
    leg_times(cfg, duty, &lt);
    return leg_state_at(&lt, t_s);
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

/* Integrate over [0, span_s] in equal RK4 steps no longer than substep_max_s
 * (inlined: it runs 7 times a period). */
#if defined(__GNUC__)
__attribute__((always_inline))
#endif
static inline void integrate_piece(const inv_cfg_t *cfg, plant_t *plant, double ua_V, double ub_V,
                            double TL_Nm, double span_s)
{
    if (span_s <= cfg->substep_max_s) {
        plant_piece(plant, ua_V, ub_V, TL_Nm, span_s);   /* the default: one step per piece */
        return;
    }
    double n_steps = ceil(span_s / cfg->substep_max_s);
    if (n_steps < 1.0) {
        n_steps = 1.0;
    }
    double h = span_s / n_steps;
    for (int k = 0; k < (int)n_steps; k++) {
        plant_piece(plant, ua_V, ub_V, TL_Nm, h);
    }
}

/* Sort the period's few edges in place (insertion sort: at most MAX_BREAKS values). */
static void sort_edges(double *t_s, int n)
{
    for (int i = 1; i < n; i++) {
        double x = t_s[i];
        int j = i - 1;
        while (j >= 0 && t_s[j] > x) {
            t_s[j + 1] = t_s[j];
            j--;
        }
        t_s[j + 1] = x;
    }
}

/* High time of one leg [s] over the period: [on + dead time, off) high, the
 * dead bands [on, on + dead time) and [off, off + dead time) (cut at the
 * period's end) high for i < 0, the diode carrying the current; the same
 * time inv_leg_state() says over the period. */
static double leg_high_time(const inv_cfg_t *cfg, double duty, double i_A)
{
    leg_times_t lt;
    leg_times(cfg, duty, &lt);
    if (lt.held != LEG_DEAD) {
        return (lt.held == LEG_HIGH) ? cfg->Ts_s : 0.0;
    }
    if (i_A < 0.0) {
        return fmin(lt.off_s + lt.deadtime_s, cfg->Ts_s) - lt.on_s;
    }
    return fmax(lt.off_s - (lt.on_s + lt.deadtime_s), 0.0);
}

static void period_averaged(const inv_cfg_t *cfg, const double duty[3], double TL_Nm, plant_t *plant)
{
    double i_abc[N_LEGS] = { 0.0, 0.0, 0.0 };
    if (needs_current(cfg)) {
        plant_piece_iabc_A(plant, i_abc);
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

/* The stator voltage of each of the 8 leg patterns (bit k: leg k high) at
 * the bus vdc_V, from legs_to_ab() itself so the pieces get the same bits
 * as the general path; rebuilt when the bus changes (a sag or surge). */
typedef struct {
    double vdc_V;
    double ua_V[1 << N_LEGS];
    double ub_V[1 << N_LEGS];
} pattern_table_t;

static const pattern_table_t *pattern_table(double vdc_V)
{
    static pattern_table_t tab = { -1.0, { 0.0 }, { 0.0 } };
    if (tab.vdc_V != vdc_V) {
        for (unsigned m = 0u; m < (1u << N_LEGS); m++) {
            double v[N_LEGS];
            for (int k = 0; k < N_LEGS; k++) {
                v[k] = ((m >> k) & 1u) ? vdc_V : 0.0;
            }
            legs_to_ab(v, &tab.ua_V[m], &tab.ub_V[m]);
        }
        tab.vdc_V = vdc_V;
    }
    return &tab;
}

/* Ideal switches (no dead time, no device drop): the legs' states need no
 * current. A switching leg goes high at on_s and low at off_s, both
 * monotone in its duty, and every on_s <= Ts/2 <= every off_s: with the
 * legs sorted by duty, widest first, the edges in time order are the
 * ons in that order, then the offs in the reverse order. Each edge
 * toggles one bit of the legs' pattern; zero-length pieces (equal edges)
 * are skipped. Same pieces, same voltages as the general path. */
static void period_switching_ideal(const inv_cfg_t *cfg, const double duty[3], double TL_Nm, plant_t *plant)
{
    leg_times_t lt[N_LEGS];
    double d_sw[N_LEGS];
    int order[N_LEGS];
    int n = 0;
    unsigned mask = 0u;
    for (int k = 0; k < N_LEGS; k++) {
        leg_times(cfg, duty[k], &lt[k]);
        if (lt[k].held == LEG_HIGH) {
            mask |= 1u << k;
        } else if (lt[k].held == LEG_DEAD) {
            const double d = clamp01(duty[k]);
            int j = n - 1;
            while (j >= 0 && d_sw[j] < d) {
                d_sw[j + 1] = d_sw[j];
                order[j + 1] = order[j];
                j--;
            }
            d_sw[j + 1] = d;
            order[j + 1] = k;
            n++;
        }
    }
    const pattern_table_t *tab = pattern_table(cfg->vdc_V);
    double t0 = 0.0;
    for (int e = 0; e <= 2 * n; e++) {
        double t1 = cfg->Ts_s;
        int leg = -1;
        if (e < n) {
            leg = order[e];
            t1 = lt[leg].on_s;
        } else if (e < 2 * n) {
            leg = order[2 * n - 1 - e];
            t1 = lt[leg].off_s;
        }
        if (t1 > t0) {
            integrate_piece(cfg, plant, tab->ua_V[mask], tab->ub_V[mask], TL_Nm, t1 - t0);
            t0 = t1;
        }
        if (leg >= 0) {
            mask ^= 1u << leg;
        }
    }
}

static void period_switching(const inv_cfg_t *cfg, const double duty[3], double TL_Nm, plant_t *plant)
{
    if (!needs_current(cfg)) {
        period_switching_ideal(cfg, duty, TL_Nm, plant);
        return;
    }
    double br[MAX_BREAKS];
    int n = 0;
    for (int k = 0; k < N_LEGS; k++) {
        n += inv_leg_edges(cfg, duty[k], &br[n]);
    }
    sort_edges(br, n);
    br[n++] = cfg->Ts_s;
    leg_times_t lt[N_LEGS];
    for (int k = 0; k < N_LEGS; k++) {
        leg_times(cfg, duty[k], &lt[k]);
    }

    double t0 = 0.0;
    for (int j = 0; j < n; j++) {
        double t1 = br[j];
        if (t1 <= t0) {
            continue;   /* coinciding edges of different legs */
        }
        double i_abc[N_LEGS] = { 0.0, 0.0, 0.0 };
        const bool with_current = needs_current(cfg);
        if (with_current) {
            plant_piece_iabc_A(plant, i_abc);
        }
        double v[N_LEGS];
        for (int k = 0; k < N_LEGS; k++) {
            v[k] = leg_voltage(cfg, leg_state_at(&lt[k], 0.5 * (t0 + t1)), i_abc[k]);
            if (with_current) {
                v[k] -= cfg->device_drop_V * sign_of(i_abc[k]);
            }
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
    plant_pieces_begin(plant);
    if (cfg->model == INV_SWITCHING) {
        period_switching(cfg, duty, TL_Nm, plant);
    } else {
        period_averaged(cfg, duty, TL_Nm, plant);
    }
    plant_pieces_end(plant);
}
