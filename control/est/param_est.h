/*
 * param_est.h - step 2 of the proposed method: online L^ and psi_f^
 * (paper sec. V-C, V-D), by transfer laws operating on the observer's
 * state (smo.h), which replace the paper's (43)-(50) and (53)-(55).
 *
 * After smo_step(), when running, the laws taking turns (every
 * Tu = PARAM_EST_LAW_PERIODS Ts each):
 *   |w iq| > wiq_min:  delta = gamma_L Tu fd^;   L^ -= delta/(w iq); fd^ -= delta
 *   |w|    > w_min:    delta = gamma_psi Tu fq^; psi^ += delta/w;   fq^ -= delta
 * (step2_design.md sec. 1, 2); gamma_L drops to gamma_L_slow after L_fast_s of
 * the L law's running (converged: from then on it averages the encoder's
 * count error, step2_design.md sec. 8). w L^ iq - fd^ and w psi^ + fq^ are unchanged, so the
 * fast observer never sees an update; f^ drains into the parameters at the
 * slow rates gamma until f^ = 0. Signed w iq and w keep braking and reversal
 * right. Below the thresholds the division is ill-conditioned and the law
 * freezes (the estimate holds).
 *
 * No low-pass on the estimates: the observer is the filter (with 0.02 A rms
 * current noise the estimates stay within 0.13 %, build/sil/report.md), and a
 * filter inside the loop would add phase to the transfer law for nothing.
 */
#ifndef PARAM_EST_H
#define PARAM_EST_H

#include <stdbool.h>
#include <stdint.h>

#include "mathx.h"
#include "smo.h"

/* Design defaults (step2_design.md sec. 3). */
#define PARAM_EST_GAMMA_L_DEFAULT_1_S   150.0f /* tau 6.7 ms, 13x slower than the observer */
#define PARAM_EST_GAMMA_PSI_DEFAULT_1_S 60.0f  /* tau 17 ms */
/* L^'s law after its first PARAM_EST_L_FAST_DEFAULT_S of running: the
 * averaging rate (step2_design.md sec. 1, 8: the encoder's count error). */
#define PARAM_EST_GAMMA_L_SLOW_DEFAULT_1_S 15.0f /* tau 67 ms */
#define PARAM_EST_L_FAST_DEFAULT_S      1.0f   /* [s] of L-law running at gamma_L */
#define PARAM_EST_L_FAST_MAX_S          3600.0f /* its counter's range */
/* L^'s law after its first PARAM_EST_L_FAST_DEFAULT_S of running: the
 * averaging rate (step2_design.md sec. 1, 8: the encoder's count error). */
#define PARAM_EST_GAMMA_L_SLOW_DEFAULT_1_S 15.0f /* tau 67 ms */
#define PARAM_EST_L_FAST_DEFAULT_S      1.0f   /* [s] of L-law running at gamma_L */
#define PARAM_EST_L_FAST_MAX_S          3600.0f /* its counter's range */
#define PARAM_EST_WIQ_MIN_DEFAULT_A_RAD_S       30.0f  /* [A rad/s] */
#define PARAM_EST_W_MIN_DEFAULT_RAD_S   30.0f  /* electrical, ~95 r/min at p = 3 */
/* Rate limits of L^ and psi^, x nominal per second (step2_design.md sec. 3): a
 * 50 % error still goes in 50 ms, a transient the gate misses moves an
 * estimate by at most 1 % per ms. */
#define PARAM_EST_RATE_MAX_FACTOR_1_S   20.0f

/* Each law runs every this many periods (they take turns, L^ first), with
 * its gain per update scaled by it: the same continuous rates (tau 6.7
 * and 17 ms, 67 and 170 periods) at half the cost per period. */
#define PARAM_EST_LAW_PERIODS 2.0f

/* Bits returned by param_est_step(). */
#define PARAM_EST_L_MOVED     0x0001u /* L^ law acted this period */
#define PARAM_EST_PSI_MOVED   0x0002u /* psi^ law acted this period */
#define PARAM_EST_L_CLAMPED   0x0004u /* L^ held at a clamp (at its last update) */
#define PARAM_EST_PSI_CLAMPED 0x0008u /* psi^ held at a clamp (at its last update) */

typedef struct {
    float Ts_s;               /* sampling period [s] */
    float gamma_L_1_s;        /* slow rate of L^ while it converges [1/s] */
    float gamma_L_slow_1_s;   /* its rate from then on (averaging) [1/s], <= gamma_L_1_s */
    float L_fast_s;           /* running time of the L law at gamma_L_1_s after param_est_run [s] */
    float gamma_psi_1_s;      /* slow rate of psi^ [1/s] */
    float wiq_min_A_rad_s;    /* freeze L^ when |w iq| <= this [A rad/s] */
    float w_min_rad_s;        /* freeze psi^ when |w| <= this [rad/s electrical] (the default speed floor) */
    float L_min_H;            /* clamps */
    float L_max_H;
    float psi_min_Wb;
    float psi_max_Wb;
    float L_rate_max_H_s;     /* |dL^/dt| limit [H/s] */
    float psi_rate_max_Wb_s;  /* |dpsi^/dt| limit [Wb/s] */
} param_est_cfg_t;

typedef struct {
    param_est_cfg_t cfg;
    bool valid;
    bool running;             /* run/freeze switch; false after init and reset */
    float gamma_L_Tu;         /* the L law's gain per law step [1], Tu = PARAM_EST_LAW_PERIODS Ts (0: L^ held) */
    bool L_held;              /* param_est_hold_L */
    uint32_t L_fast_left;     /* L-law updates left at gamma_L (then gamma_L_slow) */
    float kpsi;               /* gamma_psi Tu [1] */
    float dL_max_H;           /* L_rate_max Tu: largest step of L^ per update [H] */
    float dpsi_max_Wb;        /* psi_rate_max Tu [Wb] */
    bool phase_psi;           /* this period's law: psi^ (true) or L^ */
    uint16_t flags_last;      /* bits of the last step (the resting law's clamp bits) */
} param_est_t;

/* Design defaults for Ts_s [s] and nominal L_H [H], psi_f_Wb [Wb]. Background. */
void param_est_cfg_defaults(param_est_cfg_t *cfg, float Ts_s, float L_H, float psi_f_Wb);

/* Copies cfg and resets (frozen). Needs finite values, Ts > 0, 0 < gamma Ts < 1,
 * thresholds and rate limits > 0, 0 < min <= max and the clamps inside the observer's
 * accepted ranges (*smo initialised OK). Returns false otherwise; then
 * param_est_step() never moves anything. Background. */
bool param_est_init(param_est_t *pe, const param_est_cfg_t *cfg, const smo_t *smo);

/* Frozen. Background, or ISR before PWM is enabled (est_reset; from flash). */
void param_est_reset(param_est_t *pe);

/* Run/freeze switch: run = true starts step 2 (after smo_set_R()). Background or ISR. */
void param_est_run(param_est_t *pe, bool run);

/* L^ held (hold = true) while psi^ goes on: an angle error would be
 * learned as L (est.h). Cleared by param_est_reset. Background or ISR. */
void param_est_hold_L(param_est_t *pe, bool hold);

/* The L law's gain per update for the held flag and the phase: zero
 * holds L^ without a test in the ISR's path. ISR (rare: a phase change). */
void param_est_set_gain_L(param_est_t *pe);

/* One period, after smo_step() of the same period: the transfer laws on
 * *smo with the measured iq_A(k) [A] and omega_el_rad_s(k) [rad/s]; psi^
 * freezes at |w| <= w_min_rad_s (the caller's speed floor, at least
 * cfg.w_min_rad_s). Returns PARAM_EST_* bits. ISR (2 guarded divisions
 * + 1 in smo_take_L). Inline: once a period. */
static inline uint16_t param_est_step(param_est_t *pe, smo_t *smo, float omega_el_rad_s, float iq_A,
                                      float w_min_rad_s)
{
    const param_est_cfg_t *c = &pe->cfg;
    uint16_t flags = 0u;

    if (!pe->running || (smo->status != SMO_CFG_OK)) {
        return 0u;
    }
    /* the observer's own input bounds, so the invariant smo_take_L/psi keep is this one (and
     * running: the clamps inside the observer's ranges, param_est_init) */
    const float w = mathx_clampf(omega_el_rad_s, smo->omega_lo_rad_s, smo->cfg.omega_max_rad_s);
    const float iq = mathx_clampf(iq_A, smo->i_lo_A, smo->cfg.i_max_A);
    const float wiq = w * iq;

    /* The laws take turns, each every second period at twice the gain
     * (PARAM_EST_LAW_PERIODS): the same slow rates at half the cost. The
     * clamp bits of the law that rests keep their last value. */
    pe->phase_psi = !pe->phase_psi;
    flags = pe->flags_last & (pe->phase_psi ? PARAM_EST_L_CLAMPED : PARAM_EST_PSI_CLAMPED);

    /* Replaces (53)-(55): corrected steady state fd = dL w iq
     * (corrected_model_design.md sec. 2, step2_design.md sec. 1),
     * applied as a slow transfer of fd^ into L^ instead of L + fd/(w iq). */
    if (!pe->phase_psi && (mathx_fabsf(wiq) > c->wiq_min_A_rad_s)) {
        const float delta_V = pe->gamma_L_Tu * smo->fd_V;
        const float L_tgt = smo->L_H - mathx_clampf(delta_V / wiq, -pe->dL_max_H, pe->dL_max_H);
        const float L_new = mathx_clampf(L_tgt, c->L_min_H, c->L_max_H);
        smo_take_L(smo, L_new, w, iq); /* fd^ -= delta (less when clamped) */
        flags |= PARAM_EST_L_MOVED;
        if (pe->L_fast_left != 0u) {
            pe->L_fast_left--;
            if (pe->L_fast_left == 0u) {
                param_est_set_gain_L(pe); /* converged: the averaging rate from here */
            }
        }
        if (!((L_tgt >= c->L_min_H) && (L_tgt <= c->L_max_H))) {
            flags |= PARAM_EST_L_CLAMPED;
        }
    }
    /* Replaces (43)-(50): fq = -dpsi w at equilibrium (step2_design.md sec. 2); psi^
     * takes fq^ at the speed-independent rate gamma_psi. */
    if (pe->phase_psi && (mathx_fabsf(w) > w_min_rad_s)) {
        const float delta_V = pe->kpsi * smo->fq_V;
        const float psi_tgt = smo->psi_f_Wb + mathx_clampf(delta_V / w, -pe->dpsi_max_Wb, pe->dpsi_max_Wb);
        const float psi_new = mathx_clampf(psi_tgt, c->psi_min_Wb, c->psi_max_Wb);
        smo_take_psi(smo, psi_new, w); /* fq^ -= delta (less when clamped) */
        flags |= PARAM_EST_PSI_MOVED;
        if (!((psi_tgt >= c->psi_min_Wb) && (psi_tgt <= c->psi_max_Wb))) {
            flags |= PARAM_EST_PSI_CLAMPED;
        }
    }
    pe->flags_last = flags;
    return flags;
}

#endif /* PARAM_EST_H */
