/*
 * est.h - the proposed method's estimation under one owner: the observer
 * (smo.h), step 1 (rs_ident.h), step 2's transfer laws (param_est.h) and
 * when they may learn (est_gate.h), the inverter error and R tracking by
 * d-current injection (r_track.h), and the model's psi_f through a dead
 * band with its speed floor (psi_band.h). Design: the notes README.md lists.
 *
 * One est_step() per period, one output (est_out_t): the motor model - R,
 * L, psi_f and the inverter voltage error to compensate - that the
 * deadbeat law, MTPA and the limits use, how to use it (src), and what
 * is held and why (hold). Nothing outside est.c and est_cfg.c (the
 * settings and start-up) touches est_t's members (`make check`,
 * tools/check/est_owner.sh): the controller reads est_output() and calls
 * the functions below.
 *
 * Order inside est_step (the phase's part of it):
 *   observer: i^(k+1), f^ from i(k), w(k), u(k)            (smo_step)
 *   injection: inverter error after step 1, R^ in step 2   (r_track)
 *   step 1: the window sums                                (rs_ident)
 *   step 2: gate (pause, restore), transfer laws at the speed floor
 *           input, the model's psi_f and the floor         (est_gate,
 *           param_est, psi_band)
 *   output: the model and its status
 */
#ifndef EST_H
#define EST_H

#include <stdbool.h>
#include <stdint.h>

#include "clarke_park.h"
#include "est_gate.h"
#include "param_est.h"
#include "psi_band.h"
#include "r_track.h"
#include "rs_ident.h"
#include "smo.h"

typedef enum {
    EST_OFF = 0,          /* observer stopped: the told model */
    EST_STEP1 = 1,        /* observer runs, R^ being identified: the told model */
    EST_STEP2 = 2         /* observer, transfer laws, injection: the estimated model */
} est_phase_t;

/* Why the model's values are held (est_out_t.hold; 0: step 2 learning,
 * the estimates are measurements). The first five are est_gate.h's. */
#define EST_HOLD_ACCEL       0x0001u /* speed changing faster than its estimate follows */
#define EST_HOLD_CURRENT     0x0002u /* current transient */
#define EST_HOLD_TORQUE      0x0004u /* torque-command transient */
#define EST_HOLD_VOLTAGE     0x0008u /* voltage limit: the applied voltage is not the model's */
#define EST_HOLD_SETTLE      0x0010u /* one of those cleared, the hold time running */
#define EST_HOLD_SPEED_FLOOR 0x0020u /* below the speed floor (psi_band.h): the last trusted or the told model;
                                       * with EST_FLAG_INV_UNIDENTIFIED at every speed */
#define EST_HOLD_NO_STEP2    0x0040u /* step 2 not running: the told model */
#define EST_HOLD_ANGLE       0x0080u /* L^ held: step 1's windows suggest an angle error (EST_FLAG_ANGLE_SUSPECT) */
#define EST_HOLD_STEP1_REFUSED 0x0100u /* with EST_HOLD_NO_STEP2: step 1 was refused (the told model until the next) */
#define EST_HOLD_INVERTER_UNKNOWN 0x0200u /* with EST_HOLD_SPEED_FLOOR: the inverter error could not be
                                            * measured (EST_FLAG_INV_UNIDENTIFIED), so every speed is below the floor */
#define EST_HOLD_OSCILLATION 0x0400u /* the model's L^ made the current oscillate (ctrl.h's watch): L^ cut to the
                                       * L the oscillation measures and held there until the next start (a warning) */
/* The named bits (est_hold_name()). */
#define EST_HOLD_NAMES_N 11u

/* est_out_t.flags: bits of the controller's output flags. */
#define EST_FLAG_INV_UNIDENTIFIED 0x0100u /* the inverter error could not be identified: not compensated */
#define EST_FLAG_R_HELD           0x0200u /* track_R: the last cycle was held (no current, transient, band, or the
                                            * inverter's compensation leaves R unresolved) */
#define EST_FLAG_PSI_HELD         0x0400u /* step 2: the model's psi_f did not move this period */
#define EST_FLAG_ANGLE_SUSPECT    0x0800u /* step 1's windows found an encoder angle error: the offset corrected,
                                            * or L^ held where the inverter could fake it (a warning) */

/* A per-leg square wave of amplitude dv (dead time, device drop) has the
 * rotor-frame fundamental (4/pi) dv against the current (inverter_error_design.md sec. 2). */
#define EST_FUNDAMENTAL_OF_SQUARE 1.27323954f

/* est_out_t.src: how the model is used. */
#define EST_SRC_TOLD     0u /* the told values, eq. (10), the told dead time: the conventional path */
#define EST_SRC_OBSERVER 1u /* step 2's estimates, the state at k+1 from i^(k+1) (eq. 11, 12) */
#define EST_SRC_HELD     2u /* held estimates, eq. (10) with them (after a current transient, or
                             * the last trusted ones below the speed floor) */

/* est_out_t.moved */
#define EST_MOVED_LPSI 0x0001u /* L or psi_f may have moved: worth taking when far enough */
#define EST_MOVED_ALL  0x0002u /* R changed or the model was re-based: take it */

/* est_cfg_t.track_R: off; on from step 2's start; auto from
 * rtrack.auto_delay_periods after it (step 1's R^ holds that long: a
 * winding's thermal time constant is minutes; r_tracking_design.md sec. 3). */
#define EST_TRACK_R_OFF  0u
#define EST_TRACK_R_ON   1u
#define EST_TRACK_R_AUTO 2u

/* Until the inverter error is identified, the speed floor assumes at
 * least this dead-time error nobody told [s] (holds_design.md sec. 6). */
#define EST_UNTOLD_DEADTIME_DEFAULT_S 0.15e-6f

/* What est_init refused (bits; ctrl_init's status carries them). */
typedef uint16_t est_status_t;
#define EST_CFG_OK        ((est_status_t)0x0000u)
#define EST_CFG_OBSERVER  ((est_status_t)0x0001u) /* smo_init refused (stability, (36)) */
#define EST_CFG_ESTIMATOR ((est_status_t)0x0002u) /* param_est_init or psi_band_init refused */
#define EST_CFG_RSID      ((est_status_t)0x0004u) /* rs_ident_init refused */
#define EST_CFG_GATE      ((est_status_t)0x0080u) /* est_gate_init refused */
#define EST_CFG_RTRACK    ((est_status_t)0x0100u) /* r_track_init refused */
/* Every bit est_init may return: any of them makes the estimation unavailable. */
#define EST_CFG_ANY ((est_status_t)(EST_CFG_OBSERVER | EST_CFG_ESTIMATOR | EST_CFG_RSID | EST_CFG_GATE | EST_CFG_RTRACK))

/* What the drive is told of the motor and the board, as the estimation
 * takes it (the controller's configuration: ctrl_cfg_told()). */
typedef struct {
    float Ts_s;                 /* control period [s] */
    float R_Ohm, L_H, psi_f_Wb; /* the told model [Ohm, H, Wb] */
    uint16_t pole_pairs;        /* [-] */
    float i_max_A;              /* bounds the observer's inputs take [A] */
    float u_max_V;              /* [V] */
    float omega_max_el_rad_s;   /* [rad/s el] */
    float deadtime_s;           /* the told dead time as compensated (its fundamental bounds psi_band's Vb) [s] */
    float device_drop_V;        /* the told device drop as compensated [V] */
    uint32_t enc_counts_per_rev; /* encoder counts a turn (the gate's acceleration floor) [-] */
    float enc_pll_bw_rad_s;     /* the speed estimate's bandwidth [rad/s] */
} est_told_t;

/* The estimation's settings: est_cfg_defaults() builds them from the told
 * values; a caller may then change a field (the scenario keys, the
 * parameter set's scaling rules). The told model and bounds are not
 * repeated here: est_init takes them (est_told_t). */
typedef struct {
    float R_min_Ohm;            /* accepted R^ band [Ohm] */
    float R_max_Ohm;
    float untold_deadtime_s;    /* until the inverter error is identified, the least error nobody
                                 * told, as a dead time (the speed floor's prior; >= 0) [s] */
    smo_cfg_t smo;              /* observer gains and ranges (est_init writes the told values and bounds) */
    param_est_cfg_t pe;         /* step-2 rates, thresholds, clamps */
    rs_ident_cfg_t rsid;        /* step-1 checks */
    r_track_cfg_t rtrack;       /* d-axis injection */
    uint16_t track_R;           /* EST_TRACK_R_*: R^ tracked in step 2 by the injection */
    est_gate_cfg_t gate;        /* when step 2 may learn */
} est_cfg_t;

typedef struct {                /* what est_t keeps of its configuration (the blocks keep their own) */
    float R_Ohm, L_H, psi_f_Wb; /* the told model [Ohm, H, Wb] */
    float R_min_Ohm;            /* accepted R^ band [Ohm] */
    float R_max_Ohm;
    float w_min_rad_s;          /* pe.w_min_rad_s: the psi^ law's own speed floor [rad/s el] */
    float wiq_min_A_rad_s;      /* pe.wiq_min_A_rad_s: the L^ law's |w iq| floor [A rad/s] */
    uint16_t track_R;           /* EST_TRACK_R_* */
    uint16_t auto_delay_periods; /* rtrack.auto_delay_periods */
    float deadtime_frac;        /* the told dead time over Ts, as compensated [1] */
    float device_drop_V;        /* the told device drop, as compensated [V] */
    float untold_frac;          /* untold_deadtime_s over Ts: the prior of what nobody told [1] */
} est_kept_t;

typedef struct {                /* one period's inputs */
    dq_t i_dq_A;                /* i(k), rotor frame [A] */
    float omega_el_rad_s;       /* w(k) within +-omega_max [rad/s electrical] */
    const zoh_turn_t *turn;     /* the rotor's turn over the period at w(k) within +-omega_max (zoh.h) */
    float sin_el, cos_el;       /* of theta_el(k) */
    dq_t u_V;                   /* u(k): the voltage realised over [k, k+1] [V] */
    float vdc_V;                /* bus [V] */
    float te_ref_Nm;            /* the last period's torque reference [N m] */
    bool voltage_limited;       /* the last period's voltage was clamped */
    float dpsi_weak_Wb;         /* the flux reference's weakening (oplim's dpsi; > 0: weakened) [Wb] */
    float ripple_A;             /* the largest current ripple at a leg's edge over [k, k+1] (inverr.h) [A] */
} est_in_t;

typedef struct {                /* the output: written by est_step and the phase changes */
    float R_Ohm, L_H, psi_f_Wb; /* the motor model [Ohm, H, Wb] */
    float inv_dv_V;             /* per-leg inverter error to compensate beyond the told dead time [V] */
    float inv_err_V;            /* the identified inverter error, rotor-frame fundamental [V] (monitor) */
    uint16_t src;               /* EST_SRC_* */
    uint16_t moved;             /* EST_MOVED_* this period */
    uint16_t hold;              /* EST_HOLD_* */
    uint16_t flags;             /* EST_FLAG_* */
    est_phase_t phase;
} est_out_t;

typedef struct {
    est_kept_t cfg;
    est_status_t status;
    est_phase_t phase;
    smo_t smo;
    param_est_t pe;
    rs_ident_t ri;
    rs_ident_window_t win;      /* window the coming periods go into */
    rs_ident_out_t rsid_out;    /* last est_rsid_finish() result */
    r_track_t rt;
    psi_band_t pb;
    est_gate_t gate;
    float inv_dv_V;             /* per-leg error identified on top of the told dead time [V] */
    float w_psi_min_rad_s;      /* the transfer laws' speed floor for psi^ (param_est_step's input) */
    float step1_ripple_A;       /* step 1: the largest current ripple at a leg's edge seen [A] */
    float step1_vdc_V;          /* step 1: the bus of its last period [V] */
    float angle_fix_el_rad;     /* the encoder angle error step 1 found where it may be corrected, else 0 [rad el] */
    uint16_t rt_flags;          /* EST_FLAG_INV_UNIDENTIFIED, EST_FLAG_R_HELD while they last */
    uint16_t force;             /* EST_MOVED_ALL due at the next output */
    uint16_t hold_fixed;        /* EST_HOLD_ANGLE while an angle error is suspected, EST_HOLD_OSCILLATION
                                 * once the current oscillated on the estimates (else 0) */
    bool refused;               /* the last step 1 was refused (EST_HOLD_STEP1_REFUSED) */
    bool trusted;               /* the model was taken above the speed floor as psi_band decided it under
                                 * the final bound (the last trusted model, kept below the floor) */
    est_out_t out;
} est_t;

/* The observer's gains for the told R, L at Ts with the disturbance error
 * ef_max_V [V] it must dominate (smo_gains_design: designed on the exact
 * discrete model, discrete_model_design.md sec. 5). False (g filled for
 * the diagnosis) when the told L/R is below SMO_LR_MIN_PERIODS x Ts: the
 * proposed method is then refused. Background. */
bool est_obs_gains(const est_told_t *told, float ef_max_V, smo_gains_t *g);

/* The default R^ band [Ohm] for the told R (told->R_Ohm): rs_ident.h's
 * RS_IDENT_BAND_*_FACTOR x R_Ohm (step1_design.md sec. 8; the
 * observer's reaching condition and stability hold for any R^ on the
 * exact model, discrete_model_design.md sec. 5). Background, before
 * est_cfg_defaults. */
void est_rsid_band(const est_told_t *told, float *R_min_Ohm, float *R_max_Ohm);

/* The estimation's settings for the told values *told with the observer's
 * gains *g and the R^ band [R_min_Ohm, R_max_Ohm] (absolute: the told R
 * may be far from the motor's): the modules' design defaults, L^ kept
 * above the observer's reaching condition at R_min (smo_L_floor_H), the
 * gate's acceleration floor above the encoder's quantisation. Background. */
void est_cfg_defaults(est_cfg_t *cfg, const est_told_t *told, const smo_gains_t *g, float R_min_Ohm,
                      float R_max_Ohm);

/* Builds everything from the settings *cfg and the told values *told
 * (written into each block's settings as it is built). Returns the
 * refusals (EST_CFG_*); a refused estimation must not be started.
 * Background. */
est_status_t est_init(est_t *e, const est_cfg_t *cfg, const est_told_t *told);

/* Observer stopped, estimates back to the told values, windows emptied.
 * Background, or ISR before PWM is enabled (ctrl_reset; from flash). */
void est_reset(est_t *e);

/* Step 1 begins: observer restarted from the told values, step 2 and the
 * injection stopped, windows emptied. False when init refused. ISR (the
 * start sequence's transition into step 1; from flash) or background. */
bool est_rsid_begin(est_t *e);

/* Window the following periods are averaged into. ISR or background. */
void est_rsid_window(est_t *e, rs_ident_window_t win);

/* Step 1 ends: solves; on RS_IDENT_OK R^ into the observer (bumpless) and
 * step 2 starts with the inverter-error identification; otherwise the
 * observer stops. Background (from flash; the ISR's step 1 solves in
 * stages: est_rsid_stage_step, then est_rsid_finish_with). */
rs_ident_result_t est_rsid_finish(est_t *e);

/* A staged check of step 1's windows so far (rs_ident_solve_begin/_step, for an
 * ISR with a budget): begun only when window 2 has no incomplete batch
 * (false, nothing begun, else: its batch sums hold still through the
 * stages), window 2's sample sums copied into *win2_copy (window 1 is
 * complete), the solve into est_rsid_out(); est_rsid_stage_step runs one
 * stage per call and returns true when s->result and the output are
 * final, the d-axis and angle checks included. ISR. */
bool est_rsid_stage_begin(est_t *e, rs_ident_solver_t *s, rs_ident_head_t *win2_copy);
bool est_rsid_stage_step(est_t *e, rs_ident_solver_t *s);

/* Step 1 ends on a staged solve's result r_solved: as est_rsid_finish
 * without solving again. ISR once. */
rs_ident_result_t est_rsid_finish_with(est_t *e, rs_ident_result_t r_solved);

/* The encoder angle error step 1's windows found [rad el] (the rotor's
 * angle minus the angle read: the SIL against the plant decided the
 * sign, holds_design.md sec. 8), 0 unless it exceeded EST_ANGLE_SUSPECT_RAD,
 * L^ is held for it (EST_HOLD_ANGLE) and its voltage w psi_f d exceeds
 * what the inverter may leave unexplained (an untold dead time at low
 * speed reads as an angle too). Any context. */
float est_angle_error_el_rad(const est_t *e);

/* The caller corrected the encoder's angle by est_angle_error_el_rad():
 * step 2 again from the observer's told state at R^ on the corrected
 * angle, L^ learning, the inverter error identified first;
 * EST_FLAG_ANGLE_SUSPECT stays (the warning: the offset was wrong).
 * Nothing unless the angle hold is set. ISR once. */
void est_angle_corrected(est_t *e);

/* Step 2 without step 1 for a trusted R_Ohm in the band: false otherwise
 * or when init refused. ISR (the start sequence's transition; from
 * flash) or background. */
bool est_start_trusted(est_t *e, float R_Ohm);

/* Step 2 from the told R when step 1 could not measure it: the inverter
 * error identified first (R_TRACK_IDENT at the told R), then R^ learned by
 * the injection as track_R says. False when init refused. ISR or
 * background. */
bool est_start_told(est_t *e);

/* An injection event of the period (r_track_step's; est_step calls it,
 * nothing else): the inverter error into the compensation, R^ tracked,
 * the holds. ISR. */
void est_r_track_event(est_t *e, r_track_event_t ev, const est_in_t *in);

/* The controller saw the current oscillate on step 2's model (ctrl.h's
 * watch, which measured L^ at 1/L_scale of the motor's L): L^ times
 * L_scale (0 < L_scale < 1; keeping the transfer law's invariant at
 * omega_el_rad_s, iq_A), taken by the model at once and held there (the L
 * law stopped, the gate's copies with it): EST_HOLD_OSCILLATION until the
 * next step 1 or start. Nothing outside step 2. ISR (rare). */
void est_hold_oscillation(est_t *e, float L_scale, float omega_el_rad_s, float iq_A);

/* est_hold while psi_band's `low` holds the model: the gate's reasons,
 * the speed floor when it is the speed, the angle hold. ISR. */
static inline uint16_t est_hold_low(const est_t *e)
{
    const uint16_t floor = ((e->pb.low & (PSI_BAND_LOW_W | PSI_BAND_LOW_BAND)) == 0u)
                               ? 0u
                               : (e->pb.unknown ? (EST_HOLD_SPEED_FLOOR | EST_HOLD_INVERTER_UNKNOWN) : EST_HOLD_SPEED_FLOOR);
    return (uint16_t)(e->gate.reasons | e->hold_fixed | floor);
}

/* Step 2's part of est_step after the observer: the gate (pause,
 * restore), the transfer laws at the speed floor, the model's psi_f and
 * the floor; then the model and its status. ISR. */
static inline void est_step2(est_t *e, const est_in_t *in)
{
    est_out_t *o = &e->out;
    const float w = in->omega_el_rad_s;
    /* the injected d current is no transient (step2_design.md sec. 4) */
    dq_t i_gate = in->i_dq_A;
    i_gate.d -= e->rt.id_expect_A;
    uint16_t moved = est_gate_step(&e->gate, &e->smo, w, i_gate, in->te_ref_Nm, in->voltage_limited)
                         ? EST_MOVED_LPSI : 0u;
    uint16_t psi_held = EST_FLAG_PSI_HELD;

    if (e->gate.reasons == 0u) {
        if (param_est_step(&e->pe, &e->smo, w, in->i_dq_A.q, e->w_psi_min_rad_s) != 0u) {
            moved = EST_MOVED_LPSI;
        }
        /* the model's psi_f: only what the voltage it cannot explain (the
         * inverter error compensated, noise) cannot fake (holds_design.md sec. 2) */
        if (psi_band_step(&e->pb, e->smo.psi_f_Wb, e->smo.fq_V, w, in->vdc_V, o->inv_err_V)) {
            moved = EST_MOVED_LPSI;
            psi_held = 0u;
        }
    } else {
        psi_band_pause(&e->pb, w);
    }
    if (e->pb.low == 0u) {
        o->R_Ohm = e->smo.R_Ohm;
        o->L_H = e->smo.L_H;
        o->psi_f_Wb = e->pb.psi_Wb;
        o->inv_dv_V = e->inv_dv_V;
        /* f^ carries a current transient: eq. (10) with the held estimates (step2_design.md sec. 7) */
        o->src = est_gate_f_usable(&e->gate) ? EST_SRC_OBSERVER : EST_SRC_HELD;
        /* the gate's reasons and the oscillation's cut L^ (an angle hold keeps pb.low set: the branches below) */
        o->hold = (uint16_t)(e->gate.reasons | e->hold_fixed);
        e->trusted = e->pb.trust; /* taken above the floor as decided under the final bound */
    } else if (e->trusted) {
        /* below the floor: the last trusted model (as it is in *o), eq. (10) */
        o->src = EST_SRC_HELD;
        o->hold = est_hold_low(e);
        moved = 0u;
    } else {
        /* below the floor, nothing trusted: the told model, the conventional path */
        o->R_Ohm = e->cfg.R_Ohm;
        o->L_H = e->cfg.L_H;
        o->psi_f_Wb = e->cfg.psi_f_Wb;
        o->inv_dv_V = 0.0f;
        o->src = EST_SRC_TOLD;
        o->hold = est_hold_low(e);
    }
    o->moved = (uint16_t)(moved | e->force);
    e->force = 0u;
    o->flags = (uint16_t)(e->rt_flags | psi_held);
}

/* One period, every period (nothing while off): observer, injection,
 * step 1's window sums or step 2; the output model and status. Inline:
 * the ISR's cost (the rare work is in est.c). ISR. */
static inline void est_step(est_t *e, const est_in_t *in)
{
    if (e->phase == EST_OFF) {
        return;
    }
    /* u(k) is the clamped voltage the last step realised, as the observer needs */
    (void)smo_step_turn(&e->smo, in->i_dq_A, in->u_V, in->omega_el_rad_s, in->turn); /* i^(k+1): (51b), (55) */
    if (e->rt.phase != R_TRACK_OFF) {
        const bool edge = r_track_at_edge(&e->rt);
        /* identifying, the controller holds the weakening instead (est_identifying) */
        const bool weak = (in->dpsi_weak_Wb > 0.0f) && (e->rt.phase == R_TRACK_TRACK);
        if ((!edge && (weak || ((e->gate.reasons & EST_GATE_VOLTAGE) != 0u))) ||
            ((e->gate.reasons & EST_GATE_ACCEL) != 0u)) {
            /* tracking only: the injection would read the weakening loop, the clamp (the gate's
             * voltage reason) or the speed estimate's lag in a ramp (its acceleration reason),
             * not R; the first two not in an edge's blanked periods (not summed), where the
             * edge's own voltage step may meet the limit and nudge the weakening
             * (r_tracking_design.md sec. 3) */
            r_track_hold(&e->rt);
            if ((e->gate.reasons & EST_GATE_ACCEL) != 0u) {
                r_track_restart_cycle(&e->rt, in->omega_el_rad_s); /* identifying: no cycle across a
                                                                    * speed change */
            }
        }
        /* z: the L^ law's invariant */
        const float z = e->smo.fd_V - in->omega_el_rad_s * e->smo.L_H * in->i_dq_A.q;
        const r_track_event_t ev = r_track_step(&e->rt, z, in->i_dq_A.d, in->i_dq_A.q, in->omega_el_rad_s, e->smo.L_H);
        if (ev != R_TRACK_NONE) {
            est_r_track_event(e, ev, in);
        }
    }
    if (e->phase == EST_STEP1) {
        /* what the inverter's compensation may put into R^ (est.c rsid_checks) */
        e->step1_ripple_A = (in->ripple_A > e->step1_ripple_A) ? in->ripple_A : e->step1_ripple_A;
        e->step1_vdc_V = in->vdc_V;
        /* the angle for the fit of the electrical-frequency ripple (step1_design.md sec. 4) */
        rs_ident_step_el(&e->ri, e->win, e->smo.fd_V, e->smo.fq_V, in->i_dq_A.d, in->i_dq_A.q, in->omega_el_rad_s,
                         in->cos_el, in->sin_el);
    } else {
        est_step2(e, in);
    }
}

/* True while the inverter error's identification sums a cycle at a
 * steady speed: the controller then holds the field weakening's flux, so
 * the cycle reads the inverter, not the weakening loop
 * (inverter_error_design.md sec. 9). ISR. */
static inline bool est_identifying(const est_t *e)
{
    return (e->rt.phase == R_TRACK_IDENT) && (e->rt.wait == 0u) && ((e->gate.reasons & EST_GATE_ACCEL) == 0u);
}

/* The flux reference psi_ref_Wb [Wb] with the injection's L id* added
 * for the model's L_H [H] (none while the injection is off). ISR. */
static inline float est_psi_ref(const est_t *e, float psi_ref_Wb, float L_H)
{
    return (e->rt.phase == R_TRACK_OFF) ? psi_ref_Wb : r_track_psi_ref(&e->rt, psi_ref_Wb, L_H);
}

/* The name of one est_hold bit (EST_HOLD_*: "ACCEL", "CURRENT", "TORQUE",
 * "VOLTAGE", "SETTLE", "SPEED_FLOOR", "NO_STEP2", "ANGLE_SUSPECT",
 * "STEP1_REFUSED", "INVERTER_UNKNOWN"), "" for anything else. Any context. */
const char *est_hold_name(uint16_t bit);

/* The bit of est_hold that explains what the model holds best
 * (STEP1_REFUSED, NO_STEP2, ANGLE_SUSPECT, INVERTER_UNKNOWN, SPEED_FLOOR,
 * then the step-2 gate's VOLTAGE, CURRENT, TORQUE, ACCEL, SETTLE); 0 for
 * none. Any context. */
uint16_t est_hold_reason_bit(uint16_t hold);

/* est_hold_name(est_hold_reason_bit(hold)): the reason's name, "" for 0. Any context. */
const char *est_hold_reason(uint16_t hold);

/* ---- readers (any context) ---- */

static inline const est_out_t *est_output(const est_t *e)
{
    return &e->out;
}

/* The observer's i^(k+1) of the last est_step [A] (src OBSERVER). */
static inline dq_t est_i_hat_A(const est_t *e)
{
    return e->smo.i_hat_A;
}

/* The observer's gain g_c of a rotor-frame voltage in the last est_step's
 * turn (zoh.h) [A/V]: the model's when src is EST_SRC_OBSERVER (its R^, L^). */
static inline dq_t est_zoh_g_c(const est_t *e)
{
    return e->smo.z.g_c;
}

/* The observer's decay over a period at its R^, L^ (zoh.h). ISR. */
static inline const zoh_model_t *est_zoh_model(const est_t *e)
{
    return &e->smo.zm;
}

/* The observer's Phi, g_u, g_c were taken in the turn *t for its decay
 * as it is now. ISR. */
static inline bool est_zoh_taken_in(const est_t *e, const zoh_turn_t *t)
{
    return e->smo.z_turn == t->seq;
}

/* The number of the observer's g_c (smo_t.z_rev: changes when it is taken again). ISR. */
static inline uint32_t est_zoh_rev(const est_t *e)
{
    return e->smo.z_rev;
}

/* The observer's internal psi^ [Wb]: it carries the voltage the model
 * cannot explain as Vu/w, no measurement (the told psi_f while off). */
static inline float est_psi_f_obs_Wb(const est_t *e)
{
    return e->smo.psi_f_Wb;
}

/* The observer's disturbances f^_d, f^_q [V] (0 while off). */
static inline dq_t est_f_V(const est_t *e)
{
    dq_t f = { 0.0f, 0.0f };
    if (e->phase != EST_OFF) {
        f.d = e->smo.fd_V;
        f.q = e->smo.fq_V;
    }
    return f;
}

static inline const rs_ident_out_t *est_rsid_out(const est_t *e)
{
    return &e->rsid_out;
}

static inline const rs_ident_cfg_t *est_rsid_cfg(const est_t *e)
{
    return &e->ri.cfg;
}

#endif /* EST_H */
