/*
 * rsid_seq.h - step 1 of the proposed method as a timed sequence (the
 * IDENTIFY_R state, app.h; paper sec. V-B): ctrl_step every period
 * (conventional control, observer running) and, from IDENTIFY_R's first
 * period, settle_1_s, window 1 (window_s), settle_2_s, window 2, then
 * the check below, then est_rsid_finish_with(): R^ into the observer,
 * step 2 (L^, psi_f^) starts.
 * The operating points (mode):
 *   WINDOWS  set from outside (a dyno's load, the speed reference): the
 *            sequence only times the windows;
 *   SPEEDS   the sequence commands speed_1 then speed_2 (speed mode,
 *            ramped at accel; the settle times count from the ramp's
 *            end) at the load present; in RUN it then ramps from speed_2
 *            to the outside reference at accel (the handover) and follows
 *            the outside reference once it is reached;
 *   TRUSTED, OFF: no step 1 (app.c: step 2 from the controller's R, or
 *            no step 2); the sequence is not started.
 * The speed it commands goes into its own ctrl_step only: ctrl.ref keeps
 * the outside reference throughout. A refused R^ is a fault naming the
 * reason (RSID_*) with the quantity and its limit.
 * The windows are checked at window 2's nominal end (at its batch
 * boundary), and every batch after it while window 2 is lengthened:
 * window 1 (complete) with window 2 (its batch sums, which hold still
 * for a batch, and a copy of its sample sums, rs_ident_copy_head) is
 * solved in RS_IDENT_SOLVE_STAGES
 * stages, one per period
 * (rs_ident_solve_step: no ISR period carries a whole solve), while
 * window 2 goes on filling; the sequence acts on the result in the period
 * after the last stage (est_rsid_finish_with: R^ as at the check),
 * RSID_CHECK_PERIODS periods after the check's.
 * Window 2 is lengthened (control/step1_design.md sec. 7): while R^ is refused
 * only for its standard error (NOT_STEADY), window 1's share of it is below the limit (so more of
 * window 2 can help) and window 2 is shorter than window_max_s, window 2
 * goes on. Window 2's operating point must hold that long (WINDOWS: the
 * outside's load and speed). In SPEEDS mode, when window 1's share alone
 * is too large, both windows are repeated (back to speed 1, settle_2_s,
 * window 1, speed 2, settle_2_s, window 2; the sums accumulate) up to
 * repeats_max times; in WINDOWS mode the points are the outside's and
 * cannot be repeated.
 */
#ifndef RSID_SEQ_H
#define RSID_SEQ_H

#include <stdbool.h>
#include <stdint.h>

#include "app_step.h"
#include "ctrl.h"

/* Step 1 of the proposed method in IDENTIFY_R (see above). */
typedef enum {
    APP_RSID_OFF = 0,
    APP_RSID_WINDOWS = 1,
    APP_RSID_SPEEDS = 2,
    APP_RSID_TRUSTED = 3
} app_rsid_mode_t;

/* What a refused step 1 does: latch the RSID_* fault (PWM
 * off); run on with the conventional method; or run on with step 2 from
 * the told R, the inverter error identified first and R^ learned by the
 * injection (est_start_told; track_R as configured). Both run-ons warn
 * APP_WARN_STEP1_REFUSED (app.h). */
typedef enum {
    APP_RSID_REFUSAL_FAULT = 0,
    APP_RSID_REFUSAL_CONVENTIONAL = 1,
    APP_RSID_REFUSAL_TOLD = 2
} app_rsid_refusal_t;

typedef struct {
    app_rsid_mode_t mode;
    float settle_1_s;           /* IDENTIFY_R entry to window 1 [s] */
    float window_s;             /* each averaging window [s] */
    float settle_2_s;           /* window 1's end to window 2: the operating point changes in it [s] */
    float speed_1_rad_s;        /* SPEEDS: mechanical speed of point 1 [rad/s] */
    float speed_2_rad_s;        /*   and of point 2 [rad/s] */
    float accel_rad_s2;         /* SPEEDS: ramp rate of the commanded speed, handover included [rad/s^2] */
    float window_max_s;         /* window 2 lengthened up to this while se(R^) is too large [s] (<= window_s: never) */
    uint16_t repeats_max;       /* SPEEDS: both windows repeated at most this often while window 1's share is too large */
    app_rsid_refusal_t on_refusal; /* a refused step 1: fault, or conventional with a warning (app.c) */
} rsid_seq_cfg_t;

/* The check of the windows (see above). */
typedef enum {
    RSID_CHECK_NONE = 0,        /* none under way: one starts at the next check tick */
    RSID_CHECK_SOLVING = 1,     /* a stage per period */
    RSID_CHECK_SOLVED = 2       /* the sequence acts on the result in the next period */
} rsid_check_t;

/* Periods from a check's to the one that acts on it: the stages and one. */
#define RSID_CHECK_PERIODS (RS_IDENT_SOLVE_STAGES + 1u)

typedef struct {
    rsid_seq_cfg_t cfg;
    uint32_t win1_tick, win2_tick, end_tick;  /* window starts and the end, periods from the start */
    uint32_t window_ticks;
    uint32_t win2_max_ticks;    /* window 2's longest */
    uint32_t settle_2_ticks;    /* settle_2_s in periods */
    uint16_t repeats;           /* SPEEDS: repeats of both windows so far */
    uint32_t check_ticks;       /* periods between checks while lengthening (one batch) */
    float speed_step_rad_s;     /* SPEEDS: ramp step per period [rad/s] */
    uint32_t ticks;             /* periods counted since rsid_seq_start (not while ramping) */
    float speed_ref_rad_s;      /* SPEEDS: the ramped reference (IDENTIFY_R, then the handover) [rad/s] */
    bool handover;              /* RUN after SPEEDS: still ramping to the outside reference */
    rs_ident_result_t result;   /* the last step 1's (R^ etc. in the controller's step-1 result) */
    /* the check of the windows, solved in stages over the periods after it */
    rsid_check_t check;         /* where the check is */
    uint32_t check_tick;        /* the tick it was started at */
    rs_ident_head_t win2;       /* window 2's sample sums then (rs_ident_copy_head) */
    rs_ident_solver_t solver;   /* the solve, into the controller's step-1 result (est_rsid_out) */
} rsid_seq_t;

/* Start-up: copy *cfg, derive the periods at Ts_s [s]. */
void rsid_seq_init(rsid_seq_t *q, const rsid_seq_cfg_t *cfg, float Ts_s);

/* ISR, on entering IDENTIFY_R after est_rsid_begin() (the start
 * sequence's transition; from flash): SPEEDS ramps from speed_now_rad_s
 * [rad/s, mechanical]. */
void rsid_seq_start(rsid_seq_t *q, float speed_now_rad_s);

/* ISR, once per IDENTIFY_R period: the window, the commanded speed and
 * one ctrl_step on *in into *out. DONE in the period step 1 succeeded
 * (step 2 runs from the next), NONFINITE_OUTPUT when ctrl_step flagged
 * it, RSID_* or CONFIG when est_rsid_finish_with refused R^. */
app_step_t rsid_seq_step(rsid_seq_t *q, ctrl_t *c, const ctrl_in_t *in, ctrl_out_t *out);

/* ISR, RUN while q->handover: one ctrl_step at the handover ramp's speed;
 * the handover ends once the outside reference is reached. */
void rsid_seq_handover_step(rsid_seq_t *q, ctrl_t *c, const ctrl_in_t *in, ctrl_out_t *out);

#endif /* RSID_SEQ_H */
