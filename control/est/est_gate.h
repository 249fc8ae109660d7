/*
 * est_gate.h - when step 2 may learn: pauses the L^ / psi_f^ transfer laws
 * (param_est.h) while their steady-state assumptions are broken, and holds
 * a value from before the transient (step2_design.md sec. 4-7).
 *
 * The transfer laws read parameter errors out of the observer's f^ under
 * two assumptions: di/dt ~ 0 (else fd, fq carry -dL di/dt) and a speed
 * estimate that matches the rotor (else fq carries w_err psi_f0, which the
 * psi law takes as -w_err/w of psi_f^). Per period the gate checks:
 *   acceleration   |d omega_el/dt| (low-passed)  > max(accel_per_speed |w|, accel_floor)
 *                  (a type-2 PLL lags a ramp by ~a/bw: fq^ then carries
 *                  a psi_f0/bw, i.e. a relative psi^ error a/(bw w))
 *   current        |i_dq - i_dq_lp| (d + q)       > di_max_A
 *   torque command |Te* - Te*_lp|                 > dte_max_Nm
 *   voltage        the last period was voltage-limited (the applied
 *                  voltage is not the one the model was solved for)
 * Any of them pauses the laws for hold_s after it clears (the observer's
 * f^ and the speed estimate settle). At the onset the estimates go back
 * to a delayed copy taken snap_s .. 2 snap_s earlier: the checks see a
 * transient a few periods after it began, and what it drove the
 * estimates to in those periods is not kept. The restore goes through the
 * observer's setters, which keep its prediction unchanged (bumpless).
 * The gate acts only once the estimates have settled (the two copies
 * within `settled` of each other), and from then on until the next reset:
 * while step 2 is still converging from a large error, the convergence
 * itself moves torque and speed, and a gate that paused and restored on
 * it would never let it finish; L^'s noise later must not switch it off.
 * The low |w| and |w iq| freezes stay in param_est (conditioning).
 */
#ifndef EST_GATE_H
#define EST_GATE_H

#include <stdbool.h>
#include <stdint.h>

#include "clarke_park.h"
#include "mathx.h"
#include "smo.h"

/* Design defaults (step2_design.md sec. 4). */
#define EST_GATE_ACCEL_PER_SPEED_DEFAULT_1_S 1.0f   /* |a| > |w| / 1 s: the lag moved psi^ 1.8 % at 2500 r/min/s with 5 */
#define EST_GATE_ACCEL_FLOOR_DEFAULT_RAD_S2  100.0f /* electrical, the least floor; 320 r/min/s at p = 3 */
/* The floor per acceleration the speed estimate reports for one count of
 * position error, bw^2 2 pi p / cpr: the quantisation reads as at most
 * (1 + 2 e^-2)/2 = 0.64 of it before the low-pass (step2_design.md sec. 5). */
#define EST_GATE_ACCEL_FLOOR_PER_COUNT       0.64f
#define EST_GATE_SETTLED_DEFAULT             0.01f  /* copies this close: the estimates had settled */
#define EST_GATE_DI_MAX_DEFAULT_A         0.5f
#define EST_GATE_DTE_MAX_DEFAULT_NM       0.3f
#define EST_GATE_TAU_DEFAULT_S            5.0e-3f /* low-pass of i, Te* */
#define EST_GATE_TAU_ACCEL_DEFAULT_S      2.0e-3f /* low-pass of the acceleration */
#define EST_GATE_HOLD_DEFAULT_S           20.0e-3f
#define EST_GATE_SNAP_DEFAULT_S           5.0e-3f
#define EST_GATE_F_HOLD_DEFAULT_S         30.0e-3f /* f^ after a current transient (step2_design.md sec. 7) */

/* Why the laws are paused (est_gate_t.reasons, bit set). */
#define EST_GATE_ACCEL   0x0001u
#define EST_GATE_CURRENT 0x0002u
#define EST_GATE_TORQUE  0x0004u
#define EST_GATE_VOLTAGE 0x0008u
#define EST_GATE_HOLD    0x0010u /* conditions clear, hold time running */

typedef struct {
    float Ts_s;               /* period [s] */
    float accel_per_speed_1_s; /* |d omega_el/dt| threshold per |omega_el| [1/s] */
    float accel_floor_rad_s2; /* ... but not below this [rad/s^2, electrical] */
    float settled;            /* relative difference of the two copies below which the
                               * estimates count as settled and the gate acts [-] */
    float di_max_A;           /* |id - id_lp| + |iq - iq_lp| threshold [A] */
    float dte_max_Nm;         /* |Te* - Te*_lp| threshold [N m] */
    float tau_s;              /* low-pass time constant of i and Te* [s] */
    float tau_accel_s;        /* low-pass time constant of the acceleration [s] */
    float hold_s;             /* pause kept this long after the last trip [s] */
    float snap_s;             /* age step of the delayed copy [s] */
    float f_hold_s;           /* the prediction by eq. (10), not i^(k+1), this long
                               * after a current or torque-command transient [s] */
} est_gate_cfg_t;

typedef struct {
    est_gate_cfg_t cfg;
    bool valid;
    bool seeded;
    float k_lp;               /* Ts/tau */
    float k_acc;              /* Ts/tau_accel */
    float k_dw;               /* accel_per_speed Ts: threshold of |dw| per |w| [1] */
    float dw_floor;           /* accel_floor Ts [rad/s per period] */
    float w_floor;            /* |w| below which the floor applies [rad/s] */
    uint16_t hold_n;          /* hold_s in periods */
    uint16_t snap_n;          /* snap_s in periods */
    uint16_t f_hold_n;        /* f_hold_s in periods */
    uint16_t hold_cnt;        /* periods left of the pause */
    uint16_t snap_cnt;        /* periods since the last copy */
    uint16_t reasons;         /* EST_GATE_* of the last step; 0: the laws may run */
    uint16_t di_cnt;          /* periods left in which f^ still carries a current transient */
    float w_prev;             /* omega_el(k-1) */
    float dw_lp;              /* low-passed change of omega_el per period [rad/s] */
    dq_t i_lp;                /* low-passed i_dq [A] */
    float te_lp;              /* low-passed Te* [N m] */
    float L_old, psi_old;     /* delayed copy, snap_n .. 2 snap_n periods old */
    float L_new, psi_new;     /* copy of the last snap boundary */
    bool settled;             /* the two copies agree within cfg.settled */
} est_gate_t;

/* Design defaults for period Ts_s [s]. Background. */
void est_gate_cfg_defaults(est_gate_cfg_t *cfg, float Ts_s);

/* The acceleration floor [rad/s^2, electrical] above the quantisation of a
 * speed estimate from counts_per_rev counts a turn through a type-2 PLL of
 * bandwidth pll_bw_rad_s [rad/s] at pole_pairs: EST_GATE_ACCEL_FLOOR_PER_COUNT
 * x bw^2 2 pi p / cpr, not below EST_GATE_ACCEL_FLOOR_DEFAULT_RAD_S2 (nor
 * when the encoder is not described: cpr or bw 0). Background. */
float est_gate_accel_floor_rad_s2(uint32_t counts_per_rev, uint16_t pole_pairs, float pll_bw_rad_s);

/* Copies cfg (finite, positive, hold and snap of 1..65535 periods) and
 * resets; false when refused (then est_gate_step never lets the laws run). Background. */
bool est_gate_init(est_gate_t *g, const est_gate_cfg_t *cfg);

/* Filters re-seeded at the next step, both copies from *smo, no pause.
 * Background or ISR (when step 2 starts). */
void est_gate_reset(est_gate_t *g, const smo_t *smo);

/* The two copies within cfg.settled of each other (NaN: not). */
static inline bool est_gate_copies_agree(const est_gate_t *g)
{
    return (mathx_fabsf(g->L_new - g->L_old) <= g->cfg.settled * g->L_new) &&
           (mathx_fabsf(g->psi_new - g->psi_old) <= g->cfg.settled * g->psi_new);
}

/* The period's transients (EST_GATE_ACCEL, _CURRENT, _TORQUE, _VOLTAGE):
 * the deviations from the low-passed values, then the filters. */
static inline uint16_t est_gate_transients(est_gate_t *g, float omega_el_rad_s, dq_t i_dq_A, float te_ref_Nm,
                                           bool v_limited)
{
    const est_gate_cfg_t *c = &g->cfg;
    uint16_t why = 0u;
    if (!g->seeded) {
        g->w_prev = omega_el_rad_s;
        g->i_lp = i_dq_A;
        g->te_lp = te_ref_Nm;
        g->seeded = true;
    }
    /* deviations from the low-passed values, then the filters; the
     * acceleration as the low-passed change of the speed per period. The
     * states are bounded by their inputs (a NaN input is caught by
     * ctrl_step's finiteness check, which stops the drive). */
    const float dw = omega_el_rad_s - g->w_prev;
    const float dev_d = i_dq_A.d - g->i_lp.d;
    const float dev_q = i_dq_A.q - g->i_lp.q;
    const float dev_te = te_ref_Nm - g->te_lp;
    const float w_abs = mathx_fabsf(omega_el_rad_s);
    g->w_prev = omega_el_rad_s;
    g->dw_lp += g->k_acc * (dw - g->dw_lp);
    g->i_lp.d += g->k_lp * dev_d;
    g->i_lp.q += g->k_lp * dev_q;
    g->te_lp += g->k_lp * dev_te;

    const float dw_max = (w_abs > g->w_floor) ? (g->k_dw * w_abs) : g->dw_floor;
    if (!(mathx_fabsf(g->dw_lp) <= dw_max)) {
        why = EST_GATE_ACCEL;
    }
    if (!(mathx_fabsf(dev_d) + mathx_fabsf(dev_q) <= c->di_max_A)) {
        why |= EST_GATE_CURRENT;
    }
    if (!(mathx_fabsf(dev_te) <= c->dte_max_Nm)) {
        why |= EST_GATE_TORQUE;
    }
    if (v_limited) {
        why |= EST_GATE_VOLTAGE;
    }
    return why;
}

/* The holds after the transients why: the copies restored at an onset
 * (true), the hold time, the snapshots while clear. */
static inline bool est_gate_hold_and_snap(est_gate_t *g, smo_t *smo, uint16_t why_now, float omega_el_rad_s,
                                          dq_t i_dq_A)
{
    uint16_t why = why_now;
    bool restored = false;

    if ((why & (EST_GATE_CURRENT | EST_GATE_TORQUE)) != 0u) {
        g->di_cnt = g->f_hold_n;
    } else if (g->di_cnt > 0u) {
        g->di_cnt--;
    }
    if (!g->settled) {
        why = 0u; /* still converging: learn on (header) */
        g->di_cnt = 0u;
    }

    if (why != 0u) {
        if (g->hold_cnt == 0u) {
            /* onset: back to the delayed copy, which the transient's first
             * periods have not touched */
            (void)smo_set_L_deferred(smo, g->L_old, omega_el_rad_s, i_dq_A.q);
            (void)smo_set_psi(smo, g->psi_old, omega_el_rad_s);
            g->L_new = g->L_old;
            g->psi_new = g->psi_old;
            g->settled = true;
            restored = true;
        }
        g->hold_cnt = g->hold_n;
        g->snap_cnt = 0u;
    } else if (g->hold_cnt > 0u) {
        g->hold_cnt--;
        why = EST_GATE_HOLD;
    } else {
        g->snap_cnt++;
        if (g->snap_cnt >= g->snap_n) {
            g->snap_cnt = 0u;
            g->L_old = g->L_new;
            g->psi_old = g->psi_new;
            g->L_new = smo->L_H;
            g->psi_new = smo->psi_f_Wb;
            /* settled once, settled until the next reset: on a real board L^'s
             * noise moves it by up to 10 % in 5 ms, which must not switch the
             * gate off (step2_design.md sec. 6) */
            g->settled = g->settled || est_gate_copies_agree(g);
        }
    }
    g->reasons = why;
    return restored;
}

/* One period, before param_est_step(): omega_el_rad_s and i_dq_A of this
 * sample, te_ref_Nm and v_limited of the last step. On a new pause sets
 * L^, psi^ of *smo back to the delayed copy (bumpless setters) and
 * returns true when it did (the model's parameters moved); the laws may
 * run when g->reasons == 0. ISR, no division (inline: once a period). */
static inline bool est_gate_step(est_gate_t *g, smo_t *smo, float omega_el_rad_s, dq_t i_dq_A, float te_ref_Nm,
                                 bool v_limited)
{
    if (!g->valid) {
        g->reasons = EST_GATE_HOLD;
        return false;
    }
    const uint16_t why = est_gate_transients(g, omega_el_rad_s, i_dq_A, te_ref_Nm, v_limited);
    return est_gate_hold_and_snap(g, smo, why, omega_el_rad_s, i_dq_A);
}

/* L_H [H] set from outside the laws (est_hold_oscillation): both copies
 * take it, so a transient's restore keeps it. ISR. */
void est_gate_take_L(est_gate_t *g, float L_H);

/* True while the observer's prediction i^(k+1) (through f^) may replace
 * eq. (10): no current or torque-command transient within f_hold_s (f^
 * integrates its tracking lag during one, step2_design.md sec. 7) and the gate
 * acting (settled estimates). ISR. */
static inline bool est_gate_f_usable(const est_gate_t *g)
{
    return g->di_cnt == 0u;
}

#endif /* EST_GATE_H */
