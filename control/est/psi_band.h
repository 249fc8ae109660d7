/*
 * psi_band.h - the PM flux the proposed method's deadbeat model takes in
 * step 2: the observer's equilibrium flux seen through a dead band of the
 * q-axis voltage nobody can explain (holds_design.md sec. 1-3).
 *
 * The observer's q axis explains w psi^ + fq^, so its equilibrium flux is
 * psi_eq = psi^ + fq^/w, and any q voltage Vu the model does not know (the
 * inverter error left after compensation, noise, encoder) sits in it as
 * Vu/w. P low-passes psi_eq (a = Ts/tau, while learning and |w| > w_min)
 * with 1/w taken once per decision (every PSI_BAND_DECIDE_PERIODS periods,
 * 1 ms: the step-2 gate pauses learning while w moves by more than
 * 0.1 % in that time):
 *
 *   P += a (psi^ + fq^/w - P)
 *
 * With |Vu| <= Vb, the model's psi_f holds its value h until
 * |P - h| > 2 Vb/|w|: then h is wrong by more than Vb/|w|, more than P can
 * be, and the model tracks P until P settles (moves by less than
 * settle_frac Vb/|w| in settle_s), then holds again. Every change thus
 * brings the model closer to the motor's psi_f: never worse than where it
 * was, so never worse than the nominal value it starts from; where it
 * cannot tell (low speed, little evidence) it holds what it knows.
 * Vb = frac x Ve_told + found_frac x |Ve_found| + |dfq_R| + abs_V (the fundamentals
 * of the inverter error the controller is told, Ve_told = ve_told_per_vdc
 * x Vdc + ve_told_drop_V, and of the error r_track identified on top;
 * dfq_R the q voltage of R^'s last tracking move) takes the coarse frac
 * until the inverter error is identified, the fine one after
 * (psi_band_rebase); with the inverter measured by commissioning (R
 * trusted) the fine one and the prior of what the measurement leaves
 * (psi_band_bound_measured, holds_design.md sec. 6).
 *
 * Speed floor: where Vb/|w| exceeds unexplained_max x |P| (the estimate),
 * or |w| <= w_min, the voltage the drive cannot explain may fake more of
 * psi_f than the model may carry: `low` says so, decided at every decision
 * (hysteresis PSI_BAND_LOW_HYST), and at once when |w| <= w_min. Until
 * the bound is final (psi_band_rebase, psi_band_bound_measured) the floor's
 * Vb is the prior ve_prior_per_vdc x Vdc + abs_V: the least inverter error
 * nobody told, which the coarse guess from the told dead time does not
 * cover when the told dead time is 0. The caller then keeps the told model and the
 * conventional torque path (holds_design.md sec. 5).
 *
 * Calling context: ISR (psi_band_step, psi_band_rebase, psi_band_start),
 * background (psi_band_init).
 */
#ifndef PSI_BAND_H
#define PSI_BAND_H

#include <stdbool.h>
#include <stdint.h>

#include "mathx.h"

/* Design defaults (holds_design.md sec. 2, 3, 5). */
#define PSI_BAND_TAU_DEFAULT_S         0.02f /* low-pass of psi_eq: 0.14 V rms of fq^ noise -> 0.006 V */
#define PSI_BAND_UNC_TOLD_FRAC_DEFAULT 0.5f  /* before identification: of the told dead time's fundamental (an untold device drop too) */
#define PSI_BAND_UNC_IDENT_FRAC_DEFAULT 0.05f /* after: of the told dead time's fundamental ... */
#define PSI_BAND_UNC_FOUND_FRAC_DEFAULT 0.3f  /* ... + this of the identified one (segments not synchronous
                                              * with its 6 w ripple: below the sync speed) */
#define PSI_BAND_UNC_FOUND_SYNC_FRAC_DEFAULT 0.1f /* ... or this (synchronous segments: 5.3 % left at most) */
#define PSI_BAND_UNC_ABS_DEFAULT_V     0.05f /* noise and encoder left in the low-passed fq^ */
#define PSI_BAND_SETTLE_DEFAULT_S      0.02f /* P settled: moved by less than ... */
#define PSI_BAND_SETTLE_FRAC_DEFAULT   0.05f /* ... this x Vb/|w| in that time: within 0.08 Vb/|w| of its end */
#define PSI_BAND_DECIDE_PERIODS        10u   /* learning periods per decision (1 division) */
#define PSI_BAND_UNEXPLAINED_MAX_DEFAULT 0.05f /* Vb/|w| above this x psi_f: below the speed floor */
#define PSI_BAND_LOW_HYST              1.2f  /* leave the floor at 1/1.2 of that: no chatter at the floor */
#define PSI_BAND_LOW_W    0x0001u /* |w| <= w_min (set at once; cleared at the next decision or pause above) */
#define PSI_BAND_LOW_BAND 0x0002u /* Vb/|w| > unexplained_max |P| (every decision; the prior's Vb before the bound is
                                   * final; always once the bound is unknown) */
#define PSI_BAND_LOW_HELD 0x0004u /* the caller holds the model at every speed (psi_band_hold) */

typedef struct {
    float Ts_s;            /* control period [s] */
    float tau_s;           /* low-pass of the equilibrium flux [s] */
    float w_min_rad_s;     /* no update at or below this |w| [rad/s electrical] */
    float psi_min_Wb;      /* clamps of the model's psi_f [Wb] */
    float psi_max_Wb;
    float unc_told_frac;   /* Vb before identification, x the compensated fundamental [1] */
    float unc_ident_frac;  /* Vb after identification, x the told fundamental [1] */
    float unc_found_frac;  /* Vb, x the identified fundamental [1] */
    float unc_found_sync_frac; /* ... when it was identified in ripple-synchronous segments [1] */
    float unc_abs_V;       /* Vb's absolute part [V] */
    float ve_told_per_vdc; /* the told dead time's fundamental per bus volt, (4/pi) td/Ts [1] */
    float ve_told_drop_V;  /* the told device drop's fundamental, (4/pi) drop [V] */
    float ve_prior_per_vdc; /* before identification, the speed floor's Vb: an untold error's
                             * fundamental per bus volt, (4/pi) td_untold/Ts [1] */
    float settle_s;        /* P settled: moved by less than settle_frac Vb/|w| in this time [s] */
    float settle_frac;     /* [1] */
    float unexplained_max; /* speed floor: Vb/|w| above this x |P| [1] */
} psi_band_cfg_t;

typedef struct {
    psi_band_cfg_t cfg;
    float a;               /* Ts/tau [1] */
    uint16_t settle_n;     /* settle_s in decisions */
    uint16_t n;            /* decisions since P_snap */
    uint16_t k;            /* learning periods since the last decision */
    bool track;            /* the model follows P (else it holds h) */
    bool taken;            /* h was taken from P since the last start or rebase (else the anchor) */
    uint16_t low;          /* below the speed floor (0: above): PSI_BAND_LOW_* bits */
    bool final;            /* the bound is final (inverter error identified or refused): the floor decides */
    bool unknown;          /* the identification was refused: no bound, below the floor at every speed */
    bool trust;            /* the last decision was under the final bound and above the floor */
    float k_per_vdc;       /* Vb's part per bus volt in use (coarse or fine x the told fundamental) [1] */
    float k_V;             /* Vb's part of the told drop in use (coarse or fine x its fundamental) [V] */
    float found_frac;      /* Vb's share of the identified fundamental in use [1] */
    float r_unc_V;         /* Vb's part for R^ tracking: its last move's q voltage |dR iq| [V] */
    float anchor_Wb;       /* the model's psi_f when step 2 started */
    float h_Wb;            /* the value held */
    float inv_w_s_rad;     /* 1/w of this decision's periods [s/rad] */
    float P_Wb;            /* low-passed equilibrium flux [Wb] */
    float P_snap_Wb;       /* P settle_s ago (while tracking) */
    float psi_Wb;          /* the model's psi_f [Wb] */
} psi_band_t;

/* Design defaults into cfg for Ts_s [s], the freeze speed w_min [rad/s]
 * and the clamps [Wb]; ve_told_per_vdc, ve_told_drop_V and ve_prior_per_vdc
 * 0 (the caller's, from its dead times and drop). Background. */
void psi_band_cfg_defaults(psi_band_cfg_t *cfg, float Ts_s, float w_min_rad_s, float psi_min_Wb, float psi_max_Wb);

/* Copies cfg; false (and a = 0: nothing moves) unless 0 < Ts < tau,
 * Ts <= settle_s <= 1 s, w_min > 0, 0 < psi_min <= psi_max, fractions and
 * abs_V >= 0, 0 < unexplained_max, all finite. Background. */
bool psi_band_init(psi_band_t *pb, const psi_band_cfg_t *cfg);

/* Step 2 starts from psi_Wb [Wb] (the model's value then): anchor, P and
 * the model's psi_f; the coarse bound. ISR or background. */
void psi_band_start(psi_band_t *pb, float psi_Wb);

/* The inverter error was identified (sync: in ripple-synchronous
 * segments, the smaller share of it in Vb) and compensated: f^_q moved by dfq_V
 * [V] (bumpless in the observer), so psi_eq by dfq/w; the model holds the
 * anchor again unless P is far from it under the fine bound (what it took
 * under the coarse bound may have been the error). It changes at the next
 * psi_band_step (and `low` at its next decision). ISR. */
void psi_band_rebase(psi_band_t *pb, float dfq_V, bool sync);

/* R^ moved (R tracking): f^_q moved by dfq_V [V] (bumpless in the
 * observer), so psi_eq and P by dfq/w; |dfq| joins Vb until the next move
 * (R^'s error is of the order of its last correction). A model taken from P carries the
 * R^ error P had then as dR iq/w: held, it takes P again at once and
 * holds that (from the next psi_band_step's decision); tracking, it goes
 * on tracking; a model holding the anchor is left alone. ISR (an R-tracking cycle's end). */
void psi_band_r_moved(psi_band_t *pb, float dfq_V);

/* R is trusted without step 1 (commissioning measured it and the
 * inverter, no identification due): the fine bound on the told
 * fundamental and the prior of what nobody told on top (what the
 * measurement leaves, ve_prior_per_vdc x Vdc), final: the speed floor
 * decides from now on (holds_design.md sec. 6). ISR (the start
 * sequence's transition: est_start_trusted; from flash). */
void psi_band_bound_measured(psi_band_t *pb);

/* The inverter error's identification was refused: no bound on what the
 * drive cannot explain, so every speed is below the floor (`low` keeps
 * PSI_BAND_LOW_BAND until psi_band_start; holds_design.md sec. 6). ISR. */
void psi_band_bound_unknown(psi_band_t *pb);

/* The caller holds the model at every speed (hold = true: `low` keeps
 * PSI_BAND_LOW_HELD until psi_band_start or hold = false). ISR. */
void psi_band_hold(psi_band_t *pb, bool hold);

/* Learning paused (the step-2 gate) at w [rad/s electrical]: the next
 * psi_band_step takes 1/w afresh; PSI_BAND_LOW_W follows w. ISR. */
void psi_band_pause(psi_band_t *pb, float omega_el_rad_s);

/* psi_band_step's decision, every PSI_BAND_DECIDE_PERIODS learning
 * periods (psi_band_step's vdc_V, ve_found_V): the count restarted, the
 * band at the 1/w taken, `low`, the tracking and the model's psi_f. True
 * when it moved. ISR. */
bool psi_band_decide(psi_band_t *pb, float vdc_V, float ve_found_V);

/* One learning period (not during the step-2 gate's pauses): the
 * observer's psi^ [Wb] and fq^ [V], w [rad/s electrical], the bus vdc_V
 * [V] (the told and prior fundamentals are per bus volt) and the
 * fundamental [V] of the error identified on top of the told dead time
 * (ve_found_V). True when the model's psi_f moved. 1 division every
 * PSI_BAND_DECIDE_PERIODS. ISR (inline: the filter every period, the
 * decision a call). */
static inline bool psi_band_step(psi_band_t *pb, float psi_obs_Wb, float fq_V, float omega_el_rad_s, float vdc_V,
                                 float ve_found_V)
{
    if (!(mathx_fabsf(omega_el_rad_s) > pb->cfg.w_min_rad_s)) {
        pb->k = 0u;
        pb->inv_w_s_rad = 0.0f;
        pb->low = (uint16_t)(pb->low | PSI_BAND_LOW_W);
        return false; /* psi_eq ill-conditioned: hold */
    }
    if (pb->k == 0u) {
        pb->inv_w_s_rad = 1.0f / omega_el_rad_s;
    }
    pb->P_Wb += pb->a * (psi_obs_Wb + fq_V * pb->inv_w_s_rad - pb->P_Wb);
    pb->k++;
    if (pb->k < PSI_BAND_DECIDE_PERIODS) {
        return false;
    }
    return psi_band_decide(pb, vdc_V, ve_found_V);
}

#endif /* PSI_BAND_H */
