/*
 * r_track.h - d-axis square-wave current injection with synchronous
 * demodulation of the observer's f^_d (beyond the paper; derivation and
 * inverter_error_design.md, r_tracking_design.md; figures: observer_log.md).
 *
 * For an SPMSM (Ld = Lq) an i_d makes no torque (Te = 1.5 p psi_f iq, eq. 3),
 * so a small i_d square wave +-I can run in service. In steady state the
 * observer's d disturbance is (inverter_error_design.md sec. 2)
 *   fd = -dR id + Ve id/|i| + dL w iq - dL did/dt
 * dR = R^ - R0, Ve the inverter voltage error the controller does not model
 * (dead time, device drop: a vector of magnitude Ve against the current).
 * With z = fd^ - w L^ iq (invariant under param_est's L^ law) and, while
 * identifying, L_c the L^ of the cycle's first summed sample (0 while
 * tracking), z + L_c w iq = fd^ - w (L^ - L_c) iq is invariant too and
 * carries w (L_c - L0) iq instead of -w L0 iq (inverter_error_design.md sec. 6: an iq that
 * differs between the segments, the + segments at the voltage limit, no
 * longer leaks in at the gain w L0). Demodulated against the reference's sign s (pattern
 * + - - + per cycle, so a linear drift cancels; the first blank_periods of
 * every segment skipped, so the current's and observer's transients and
 * dL did/dt stay out):
 *   rho = -sum((z + L_c w iq) s) / sum(id s) = dR - Ve/|i|      [Ohm]
 * Two uses, one per phase:
 *   R_TRACK_IDENT  just after step 1 (R^ = R0, dR = 0), once step 2's L^
 *                  and psi^ have settled (ident_delay_periods: their
 *                  transient moves id and would leak into the
 *                  demodulation), at amplitude i_ident_A for
 *                  ident_cycles: Ve = -rho |i|, |i| =
 *                  sqrt(I^2 + iq^2); the caller compensates it;
 *   R_TRACK_TRACK  step 2, at amplitude i_track_A: with Ve compensated
 *                  rho = dR; per cycle the caller moves R^ by dR_step_Ohm =
 *                  -k_R rho + rate, rate -= k_I rho (type 2: a winding
 *                  warming at a steady rate is followed without lag).
 * A cycle is held (no result) when the mean iq of the + and - segments
 * differ by more than iq_step_max_A (a load transient), and while
 * tracking when |mean iq| < iq_min_A (dR's tilt needs a load current);
 * identifying takes any load: the square wave +-I is then the current's
 * direction itself, and Ve = -rho |i| holds with |i| = I.
 *
 * Timing: r_track_step() once per period after smo_step(), with that
 * period's measurements; r_track_id_ref() then gives the reference for the
 * voltage computed in the same period (it reaches the current 2 periods
 * later, inside the blanking).
 */
#ifndef R_TRACK_H
#define R_TRACK_H

#include <stdbool.h>
#include <stdint.h>

/* Design defaults (inverter_error_design.md, r_tracking_design.md). */
#define R_TRACK_I_IDENT_DEFAULT_A    1.0f   /* identification: 4.5 W for 0.12 s at 3 ohm */
#define R_TRACK_I_TRACK_DEFAULT_A    0.5f   /* in service: 1.5 R I^2 = 1.1 W at 3 ohm */
#define R_TRACK_SEG_DEFAULT          100u   /* periods per segment: 10 ms, cycle 40 ms */
#define R_TRACK_BLANK_DEFAULT        30u    /* periods skipped after a segment starts */
#define R_TRACK_SYNC_MAX_DEFAULT     200u   /* IDENT: summed periods per segment at most, so the
                                             * sums span whole 6 w ripple periods down to 6 w Ts = 2 pi/200 */
#define R_TRACK_IDENT_CYCLES_DEFAULT 3u     /* 0.12 s */
#define R_TRACK_IDENT_DELAY_DEFAULT  1000u  /* 0.1 s: L^, psi^ settle first (psi^: 6 time constants) */
#define R_TRACK_AUTO_DELAY_DEFAULT   10000u /* 1 s: tracking's start in track_R auto */
#define R_TRACK_IQ_MIN_DEFAULT_A     1.0f
#define R_TRACK_IQ_STEP_DEFAULT_A    0.2f
#define R_TRACK_K_R_DEFAULT          0.5f   /* per cycle */
#define R_TRACK_K_I_DEFAULT          0.1f   /* per cycle: poles 0.7 +- 0.1j, |z| 0.71, time constant 115 ms */
#define R_TRACK_VE_MAX_DEFAULT_V     20.0f  /* |Ve| beyond this is no inverter error: refused */
/* What the identification may leave, as a bound (SIL: within 2.9 % of the
 * hand value, inverter_error_design.md sec. 5), and the psi^ error it may cause: psi^ holds where
 * |w| psi_f < (unc_frac |Ve| + unc_abs) / psi_tol. */
#define R_TRACK_VE_UNC_FRAC_DEFAULT  0.05f
#define R_TRACK_VE_UNC_ABS_DEFAULT_V 0.05f
#define R_TRACK_PSI_TOL_DEFAULT      0.01f
/* What a tracking cycle may read from the inverter's compensation as R
 * (r_tracking_design.md sec. 6): (inv_unc_frac + ripple_unc r/|i|)
 * Ve_comp/|i|, Ve_comp the compensated error's fundamental, r the current's
 * ripple at the legs' edges (inverr.h); R^ moves only where that is at
 * most R_res_max R^. The two shares twice the worst measured on the zoo's
 * motors (observer_log.md, 2026-12-02, the current's ripple). */
#define R_TRACK_INV_UNC_FRAC_DEFAULT 0.02f
#define R_TRACK_RIPPLE_UNC_DEFAULT   0.2f
#define R_TRACK_R_RES_MAX_DEFAULT    0.05f
/* After a cycle discarded for that, no injection for this long: the
 * operating point keeps it unresolvable for a while, and each cycle's
 * edges only disturb step 2 (its gate's holds) [periods] */
#define R_TRACK_UNRESOLVED_WAIT_DEFAULT 10000u

/* Periods from a d-current reference to the sampled current (deadbeat: the
 * voltage computed at k acts over [k+1, k+2]). */
#define R_TRACK_RESPONSE_PERIODS 2u

typedef enum { R_TRACK_OFF = 0, R_TRACK_IDENT = 1, R_TRACK_TRACK = 2 } r_track_phase_t;

/* Results of r_track_step(). */
typedef enum {
    R_TRACK_NONE = 0,         /* cycle under way */
    R_TRACK_CYCLE = 1,        /* TRACK: a cycle's rho_Ohm is ready */
    R_TRACK_HELD = 2,         /* a cycle was discarded (no current, transient) */
    R_TRACK_IDENT_DONE = 3,   /* IDENT: Ve_V is ready (phase now OFF) */
    R_TRACK_IDENT_REFUSED = 4 /* IDENT: no valid cycle or |Ve| too large; Ve_V = 0 (phase now OFF) */
} r_track_event_t;

typedef struct {
    float Ts_s;               /* control period [s]; 0: IDENT's segments never synchronous (defaults) */
    float i_ident_A;          /* injection amplitude while identifying Ve [A] */
    float i_track_A;          /* injection amplitude while tracking R [A] */
    uint16_t seg_periods;     /* periods per segment (4 per cycle) */
    uint16_t blank_periods;   /* periods skipped at each segment's start, < seg_periods */
    uint16_t sync_max_periods; /* IDENT: a segment sums whole periods of the inverter error's 6 w
                                * ripple, at most this many (else seg_periods, not synchronous) */
    uint16_t ident_cycles;    /* cycles averaged for Ve (fewer of longer synchronous segments:
                               * the identification's time stays ident_cycles x 4 seg_periods) */
    uint16_t ident_delay_periods; /* IDENT waits this long, without injection, before its first cycle
                                   * (whose synchronous length is decided as the wait ends: >= 1) */
    uint16_t auto_delay_periods;  /* ctrl's track_R auto: TRACK waits this long after step 2's start */
    float iq_min_A;           /* TRACK: |mean iq| below: cycle held */
    float iq_step_max_A;      /* |mean iq(+) - mean iq(-)| above: cycle held */
    float k_R;                /* fraction of rho corrected per cycle, (0, 1] */
    float k_I;                /* fraction of rho added to the rate per cycle, 0 <= k_I < k_R
                               * (error poles: z^2 - (2 - k_R - k_I) z + 1 - k_R, r_tracking_design.md sec. 1) */
    float ve_max_V;           /* |Ve| above: identification refused */
    float ve_unc_frac;        /* bound on what identification leaves: frac |Ve| + abs [1, V] */
    float ve_unc_abs_V;
    float psi_tol;            /* psi^ error that bound may cause where psi^ learns [1] */
    float inv_unc_frac;       /* TRACK: share of the compensated inverter error a cycle may read as R [1] */
    float ripple_unc;         /* ... and its growth with the ripple's share of the current [1] */
    float R_res_max;          /* TRACK: R^ moves only where that R error is at most this x R^ [1] */
    uint16_t unresolved_wait_periods; /* TRACK: no injection this long after a discarded cycle */
} r_track_cfg_t;

typedef struct {
    r_track_cfg_t cfg;
    bool valid;
    r_track_phase_t phase;
    float i_inj_A;            /* amplitude of the phase */
    uint16_t seg;             /* segment of the cycle, 0..3 (signs + - - +) */
    uint16_t j;               /* period within the segment */
    uint16_t seg_len;         /* periods per segment of this cycle */
    uint16_t blank_len;       /* periods of a segment not summed (IDENT: all but its last whole ripple periods) */
    bool sync;                /* this cycle's segments sum whole 6 w ripple periods */
    bool ident_sync;          /* IDENT: every valid cycle was synchronous (the fine bound applies) */
    uint16_t ident_need;      /* IDENT: valid cycles wanted, ident_cycles of seg_periods' time at most */
    float s_now;              /* sign of the segment */
    uint16_t wait;            /* periods left before the first cycle (IDENT) */
    float ref_q[R_TRACK_RESPONSE_PERIODS]; /* references of the last periods, oldest first [A] */
    float id_expect_A;        /* injected current the last sample carries (the reference
                               * R_TRACK_RESPONSE_PERIODS earlier) [A] */
    uint16_t cycles;          /* valid cycles summed (IDENT) */
    uint16_t tried;           /* cycles ended (IDENT) */
    uint16_t n;               /* samples used this cycle (half of them per sign) */
    float L_c_H;              /* L^ at the cycle's first summed sample while identifying, 0 while tracking [H] */
    float s_zs;               /* sum (z + L_c w iq) s */
    float s_is;               /* sum id s */
    float s_iq;               /* sum iq */
    float s_iqs;              /* sum iq s: the + and - segments' difference */
    float id_zs, id_is, id_iq;  /* IDENT: sums over the valid cycles */
    float rho_Ohm;            /* last cycle's dR - Ve/|i| */
    float rate_Ohm;           /* TRACK: R's change per cycle, learned [Ohm] */
    float dR_step_Ohm;        /* TRACK: R^ change the last valid cycle asks for [Ohm] */
    float Ve_V;               /* identified inverter error (IDENT) [V, dq magnitude] */
} r_track_t;

/* Design defaults (Ts_s 0: the caller's). Background. */
void r_track_cfg_defaults(r_track_cfg_t *cfg);

/* Copies cfg (finite, amplitudes > 0, 0 < blank < seg, blank + sync_max fits 4 segments in
 * 16 bits, ident_cycles >= 1,
 * iq limits > 0, 0 < k_R <= 1, 0 <= k_I < k_R, ve_max > 0) and resets. Background. */
bool r_track_init(r_track_t *rt, const r_track_cfg_t *cfg);

/* Phase OFF, Ve = 0. Background or ISR. */
void r_track_reset(r_track_t *rt);

/* Starts phase (sums cleared, cycle from its start); nothing when invalid. ISR or background. */
void r_track_start(r_track_t *rt, r_track_phase_t phase);

/* TRACK: no injection for the next periods [-] (at least; ISR). */
void r_track_delay(r_track_t *rt, uint16_t periods);

/* TRACK: the cycle under way dropped, no injection until a segment
 * after the last call (the field weakened or the voltage at its limit:
 * the cycle would read the weakening loop or the clamp, not R;
 * r_tracking_design.md sec. 3); nothing in other phases. ISR. */
void r_track_hold(r_track_t *rt);

/* IDENT: the cycle under way dropped and started again, its length for
 * omega_el_rad_s [rad/s el] (the speed changing: the speed estimate's lag
 * and the 6 w ripple's changing period would read as Ve; inverter_error_design.md sec. 4);
 * nothing in other phases or during the delay. ISR. */
void r_track_restart_cycle(r_track_t *rt, float omega_el_rad_s);


/* TRACK: true when the R error the inverter's compensation may put into
 * a cycle's rho, (inv_unc_frac + ripple_unc r/|i|) Ve_comp/|i|, is at most
 * R_res_max R_Ohm (r_tracking_design.md sec. 6): the current |i| i_abs_A
 * [A], the compensated error's fundamental ve_comp_V [V], the ripple at
 * the legs' edges ripple_A [A], R^ R_Ohm [Ohm]; false at no current. ISR
 * (once a cycle). */
bool r_track_resolves(const r_track_t *rt, float ve_comp_V, float ripple_A, float i_abs_A, float R_Ohm);

/* TRACK: the last cycle's rho discarded (the R^ error it may carry
 * exceeds what R^ may take): the rate as before it, no R^ step, no
 * injection for unresolved_wait_periods. ISR. */
void r_track_discard(r_track_t *rt);

/* d-current reference for the voltage computed this period [A] (0 when
 * OFF). ISR (inline: every period while the injection runs). */
static inline float r_track_id_ref(const r_track_t *rt)
{
    return ((rt->phase == R_TRACK_OFF) || (rt->wait > 0u)) ? 0.0f : rt->s_now * rt->i_inj_A;
}

/* The wait ended this period (r_track_step): IDENT takes its first
 * cycle's length for omega_el_rad_s [rad/s el]. ISR. */
void r_track_wait_over(r_track_t *rt, float omega_el_rad_s);

/* A segment ended this period (r_track_step): the next one, and at the
 * cycle's end its result (the event) and IDENT's next length. ISR. */
r_track_event_t r_track_segment_end(r_track_t *rt, float omega_el_rad_s);

/* One period: z_V = fd^ - w L^ iq [V], measured id_A, iq_A [A], the
 * observer's omega_el_rad_s [rad/s] and L_H = L^ [H]. ISR (inline: the
 * sums every period; the segment's and the wait's ends a call). */
static inline r_track_event_t r_track_step(r_track_t *rt, float z_V, float id_A, float iq_A, float omega_el_rad_s,
                                           float L_H)
{
    r_track_event_t ev = R_TRACK_NONE;
    if (rt->phase == R_TRACK_OFF) {
        return R_TRACK_NONE;
    }
    if (rt->wait > 0u) {
        rt->wait--;
        if (rt->wait == 0u) {
            r_track_wait_over(rt, omega_el_rad_s);
        }
        return R_TRACK_NONE;
    }
    /* the reference two periods back is in this sample (delay line, no modulo) */
    rt->id_expect_A = rt->ref_q[0];
    rt->ref_q[0] = rt->ref_q[1];
    if (rt->j >= rt->blank_len) {
        if (rt->n == 0u) {
            /* constant over the cycle: the L^ law's invariant stays one; IDENT only (inverter_error_design.md sec. 6) */
            rt->L_c_H = (rt->phase == R_TRACK_IDENT) ? L_H : 0.0f;
        }
        /* inverter_error_design.md sec. 6: -w L0 iq out of z, so iq(+) != iq(-) does not leak */
        rt->s_zs += rt->s_now * (z_V + rt->L_c_H * omega_el_rad_s * iq_A);
        rt->s_is += rt->s_now * id_A;
        rt->s_iq += iq_A;
        rt->s_iqs += rt->s_now * iq_A;
        rt->n++;
    }
    rt->j++;
    if (rt->j >= rt->seg_len) {
        ev = r_track_segment_end(rt, omega_el_rad_s);
    }
    rt->ref_q[1] = r_track_id_ref(rt); /* for the voltage computed this period */
    return ev;
}

/* True in a segment's blanked periods (its edge: not summed), where the
 * edge's own voltage step may meet the limit without harm. ISR. */
static inline bool r_track_at_edge(const r_track_t *rt)
{
    return rt->j < rt->cfg.blank_periods;
}

/* Lowest |w| [rad/s el] at which psi^ may learn once the inverter error
 * Ve_V was identified (0 when refused), for the nominal psi_f_Wb:
 * (unc_frac |Ve| + unc_abs) / (psi_tol psi_f). Background or ISR once. */
float r_track_w_psi_min(const r_track_t *rt, float psi_f_Wb);

/* Flux reference with the injection: psi_s* + L id*, first order in
 * L id* of psi_d* = psi_f + L id* at the torque's psi_q* (the injected
 * amplitude is psi_f/psi_s* of id*: 3 % less at 6 N m; the demodulation
 * uses the measured id). psi_s_Wb unchanged when OFF or the result is not
 * positive. ISR. */
static inline float r_track_psi_ref(const r_track_t *rt, float psi_s_Wb, float L_H)
{
    const float psi = psi_s_Wb + L_H * r_track_id_ref(rt);
    return (psi > 0.0f) ? psi : psi_s_Wb;
}

#endif /* R_TRACK_H */
