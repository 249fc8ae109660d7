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

/* Stator voltage of leg k alone at v_V, the others at 0. */
static void leg_ab(int k, double v_V, double *ua_V, double *ub_V)
{
    double v[N_LEGS] = { 0.0, 0.0, 0.0 };
    v[k] = v_V;
    legs_to_ab(v, ua_V, ub_V);
}

/* A constant voltage over [t1_s, t2_s) of a period of 2 tau_s (nothing if empty). */
static void pulse_between(plant_t *plant, double ua_V, double ub_V, double t1_s, double t2_s, double tau_s)
{
    if (t2_s > t1_s) {
        (void)plant_period_pulse(plant, ua_V, ub_V, 0.5 * (t1_s + t2_s) - tau_s, 0.5 * (t2_s - t1_s));
    }
}

/* The leg voltage [V] of state st whose current has the sign s_i (-1, 0, 1),
 * device drop included. */
static double leg_voltage_sign(const inv_cfg_t *cfg, leg_state_t st, double s_i)
{
    return leg_voltage(cfg, st, s_i) - cfg->device_drop_V * s_i;
}

/* The period's edges in (0, Ts), sorted, then Ts: returns the count. */
static int period_breaks(const inv_cfg_t *cfg, const double duty[3], double br[MAX_BREAKS])
{
    int n = 0;
    for (int k = 0; k < N_LEGS; k++) {
        n += inv_leg_edges(cfg, duty[k], &br[n]);
    }
    sort_edges(br, n);
    br[n++] = cfg->Ts_s;
    return n;
}

/* The averaged model's stator voltage over the period: the legs' mean, dead
 * time and drop by the current's sign at the period's start. */
static void averaged_voltage(const inv_cfg_t *cfg, const double duty[3], const plant_t *plant, double *ua_V,
                             double *ub_V)
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
    legs_to_ab(v, ua_V, ub_V);
}

/* Ideal switches: each leg's pulse is centred in the period, high over
 * |t - Ts/2| < d Ts/2 (a held-high leg over the whole period); the plant
 * superposes the three (linear in the voltage). */
static void legs_ideal(const inv_cfg_t *cfg, const double duty[3], plant_t *plant)
{
    const double tau = 0.5 * cfg->Ts_s;
    const double half_s[N_LEGS] = { clamp01(duty[0]) * tau, clamp01(duty[1]) * tau, clamp01(duty[2]) * tau };
    plant_period_legs(plant, cfg->vdc_V, half_s);
}

/* A piece of the period and its stator voltage. */
typedef struct {
    double t0_s, t1_s, ua_V, ub_V;
} piece_t;

/* The legs with each one's current sign held from the period's start (s0):
 * its centred pulse, the dead band's pulse the sign gives, the device drop
 * over the whole period; each leg's switching times into lt. */
static void legs_held_sign(const inv_cfg_t *cfg, const double duty[3], plant_t *plant, leg_times_t lt[N_LEGS],
                           double s0[N_LEGS])
{
    const double Ts = cfg->Ts_s;
    const double tau = 0.5 * Ts;
    const double td = cfg->deadtime_s;
    double i0[N_LEGS];
    plant_walk_iabc_A(plant, i0);
    legs_ideal(cfg, duty, plant);
    for (int k = 0; k < N_LEGS; k++) {
        leg_times(cfg, duty[k], &lt[k]);
        s0[k] = sign_of(i0[k]);
        double ua;
        double ub;
        if (lt[k].held == LEG_DEAD) {
            leg_ab(k, cfg->vdc_V, &ua, &ub);
            if (i0[k] < 0.0) {
                pulse_between(plant, ua, ub, lt[k].off_s, fmin(lt[k].off_s + td, Ts), tau);
            } else {
                pulse_between(plant, -ua, -ub, lt[k].on_s, fmin(lt[k].on_s + td, lt[k].off_s), tau);
            }
        }
        if (cfg->device_drop_V > 0.0 && s0[k] != 0.0) {
            leg_ab(k, -cfg->device_drop_V * s0[k], &ua, &ub);
            (void)plant_period_pulse(plant, ua, ub, 0.0, tau);
        }
    }
}

/* Dead time or device drop: with each leg's current sign held from the
 * period's start, a leg is its centred pulse, minus the turn-on dead band
 * (i >= 0: the lower diode) or plus the turn-off one (i < 0, cut at Ts),
 * minus the drop over the whole period. The walker then checks that held
 * sign against the current at every piece's start; where it would change
 * a piece's voltage, the period is given piece by piece instead. */
static void period_switching_general(const inv_cfg_t *cfg, const double duty[3], plant_t *plant)
{
    const double tau = 0.5 * cfg->Ts_s;
    leg_times_t lt[N_LEGS];
    double s0[N_LEGS];
    legs_held_sign(cfg, duty, plant, lt, s0);

    double br[MAX_BREAKS];
    const int n = period_breaks(cfg, duty, br);
    piece_t pc[MAX_BREAKS];
    int n_pc = 0;
    bool held_ok = true;
    double t0 = 0.0;
    for (int j = 0; j < n; j++) {
        const double t1 = br[j];
        if (t1 <= t0) {
            continue;   /* coinciding edges of different legs */
        }
        double i_abc[N_LEGS];
        plant_walk_iabc_A(plant, i_abc);
        double v[N_LEGS];
        for (int k = 0; k < N_LEGS; k++) {
            const leg_state_t st = leg_state_at(&lt[k], 0.5 * (t0 + t1));
            const double s = sign_of(i_abc[k]);
            v[k] = leg_voltage_sign(cfg, st, s);
            if ((cfg->device_drop_V > 0.0 && s != s0[k]) || (st == LEG_DEAD && (s < 0.0) != (s0[k] < 0.0))) {
                held_ok = false;
            }
        }
        piece_t *q = &pc[n_pc++];
        q->t0_s = t0;
        q->t1_s = t1;
        legs_to_ab(v, &q->ua_V, &q->ub_V);
        plant_walk_advance(plant, q->ua_V, q->ub_V, t1);
        t0 = t1;
    }
    if (!held_ok) {
        plant_period_clear(plant);
        for (int j = 0; j < n_pc; j++) {
            pulse_between(plant, pc[j].ua_V, pc[j].ub_V, pc[j].t0_s, pc[j].t1_s, tau);
        }
    }
}

/* plant.substep_s below Ts, switching model: the period in n_sub equal
 * sub-periods, each solved at once; a piece's voltage from the current at its start holds
 * across the sub-periods it spans. */
static void period_substeps(const inv_cfg_t *cfg, const double duty[3], double TL_Nm, plant_t *plant, int n_sub)
{
    const double Ts = cfg->Ts_s;
    const double h = Ts / (double)n_sub;
    leg_times_t lt[N_LEGS];
    for (int k = 0; k < N_LEGS; k++) {
        leg_times(cfg, duty[k], &lt[k]);
    }
    double br[MAX_BREAKS];
    const int n = period_breaks(cfg, duty, br);
    double ua = 0.0;
    double ub = 0.0;
    bool piece_open = false;
    int j = 0;
    for (int m = 0; m < n_sub; m++) {
        const double lo = h * (double)m;
        const double hi = (m == n_sub - 1) ? Ts : h * (double)(m + 1);
        const double tau = 0.5 * (hi - lo);
        plant_period_begin(plant, hi - lo, TL_Nm);
        double t0 = lo;
        while (t0 < hi) {
            while (j < n && br[j] <= t0) {
                j++;
            }
            const double t1 = (j < n && br[j] < hi) ? br[j] : hi;
            if (!piece_open) {   /* a piece's voltage from the current at its start */
                double i_abc[N_LEGS] = { 0.0, 0.0, 0.0 };
                if (needs_current(cfg)) {
                    plant_walk_iabc_A(plant, i_abc);
                }
                double v[N_LEGS];
                for (int k = 0; k < N_LEGS; k++) {
                    v[k] = leg_voltage_sign(cfg, leg_state_at(&lt[k], 0.5 * (t0 + t1)), sign_of(i_abc[k]));
                }
                legs_to_ab(v, &ua, &ub);
                piece_open = true;
            }
            pulse_between(plant, ua, ub, t0 - lo, t1 - lo, tau);
            plant_walk_advance(plant, ua, ub, t1 - lo);
            if (j < n && br[j] <= t1) {
                piece_open = false;   /* the piece ends at an edge; else it runs on into the next sub-period */
            }
            t0 = t1;
        }
        plant_period_end(plant);
    }
}

void inv_period(const inv_cfg_t *cfg, const double duty[3], double TL_Nm, plant_t *plant)
{
    const bool split = cfg->substep_max_s > 0.0 && cfg->substep_max_s < cfg->Ts_s;
    if (cfg->model != INV_SWITCHING) {   /* one voltage over the period: one RK4 step is cheapest */
        double ua;
        double ub;
        averaged_voltage(cfg, duty, plant, &ua, &ub);
        plant_step_rk4(plant, ua, ub, TL_Nm, cfg->Ts_s, split ? (int)ceil(cfg->Ts_s / cfg->substep_max_s) : 1);
        return;
    }
    if (split) {
        period_substeps(cfg, duty, TL_Nm, plant, (int)ceil(cfg->Ts_s / cfg->substep_max_s));
        return;
    }
    plant_period_begin(plant, cfg->Ts_s, TL_Nm);
    if (needs_current(cfg)) {
        period_switching_general(cfg, duty, plant);
    } else {
        legs_ideal(cfg, duty, plant);
    }
    plant_period_end(plant);
}
