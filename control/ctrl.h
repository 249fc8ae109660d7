/*
 * ctrl.h - the drive controller: one ctrl_step() per 10 kHz PWM period.
 *
 * The ISR's order is ctrl_step()'s body (ctrl.c): its named stages -
 * mode, sample, estimate, model, references, limits, deadbeat, modulate
 * (with the voltage the inverter realises), monitor, output - each one
 * call (why this order: ctrl_step_design.md sec. 1). The estimation of the
 * proposed method (observer, step 1, step 2, inverter error, speed floor)
 * has one owner, est.h; ctrl_step takes its output model and status.
 *
 * Methods: the conventional method uses the told model and eq. (10)-(12);
 * the proposed method the estimation's model (paper sec. V; design:
 * corrected_model_design.md and the notes README.md lists), which is the
 * told one until step 2 runs and below the speed floor. Method switching
 * (bumpless both ways): once step 2 has started, the estimation keeps
 * running whatever the method, so CONVENTIONAL -> PROPOSED takes a
 * converged observer and PROPOSED -> CONVENTIONAL only swaps the model
 * back to the told parameters and eq. (10). PROPOSED before step 2 has
 * started (no R^ identified or trusted) controls exactly as CONVENTIONAL:
 * the observer's psi^ would otherwise absorb the resistance error
 * (step1_design.md sec. 2).
 *
 * Non-finite inputs or results give 50 % duties and CTRL_FLAG_NONFINITE.
 */
#ifndef CTRL_H
#define CTRL_H

#include <stdbool.h>
#include <stdint.h>

#include "clarke_park.h"
#include "dbdtc.h"
#include "encoder.h"
#include "est.h"
#include "oplim.h"
#include "pi.h"

typedef enum { CTRL_MODE_OPEN_LOOP = 0, CTRL_MODE_TORQUE = 1, CTRL_MODE_SPEED = 2 } ctrl_mode_t;
typedef enum { CTRL_METHOD_CONVENTIONAL = 0, CTRL_METHOD_PROPOSED = 1 } ctrl_method_t;

/* Flags in ctrl_out_t.flags */
#define CTRL_FLAG_VOLTAGE_LIMIT    0x0001u /* vector clamped to the hexagon */
#define CTRL_FLAG_FLUX_UNREACHABLE 0x0002u /* negative discriminant: flux target not reachable in one period */
#define CTRL_FLAG_NONFINITE        0x0004u /* a non-finite value appeared; duties are 0.5 and the app must fault */
/* Inverter error and R tracking (inverter_error_design.md, r_tracking_design.md); high bits, set while it lasts: */
#define CTRL_FLAG_INV_UNIDENTIFIED EST_FLAG_INV_UNIDENTIFIED /* 0x0100: the inverter error could not be identified: not compensated */
#define CTRL_FLAG_R_HELD           EST_FLAG_R_HELD /* 0x0200: track_R: the last cycle was held (no current, transient, band) */
#define CTRL_FLAG_PSI_HELD         EST_FLAG_PSI_HELD /* 0x0400: step 2: the model's psi_f holds (holds_design.md sec. 2) */
#define CTRL_FLAG_ANGLE_SUSPECT    EST_FLAG_ANGLE_SUSPECT /* 0x0800: step 1 suggests an encoder angle error: L^ held */

/* Why the estimates are held: ctrl_mon_t.est_hold, the CSV's est_hold (0:
 * step 2 learning; psi_f^ is then a magnet-temperature indicator). While
 * any bit is set, the estimate columns show the values the model holds.
 * The first five are est_gate.h's (step 2 paused, estimates from before
 * the transient). */
#define CTRL_EST_HOLD_ACCEL       EST_HOLD_ACCEL       /* 0x0001 speed changing faster than its estimate follows */
#define CTRL_EST_HOLD_CURRENT     EST_HOLD_CURRENT     /* 0x0002 current transient */
#define CTRL_EST_HOLD_TORQUE      EST_HOLD_TORQUE      /* 0x0004 torque-command transient */
#define CTRL_EST_HOLD_VOLTAGE     EST_HOLD_VOLTAGE     /* 0x0008 voltage limit: the applied voltage is not the model's */
#define CTRL_EST_HOLD_SETTLE      EST_HOLD_SETTLE      /* 0x0010 one of those cleared, the hold time running */
#define CTRL_EST_HOLD_SPEED_FLOOR EST_HOLD_SPEED_FLOOR /* 0x0020 below the speed where w psi_f dominates the voltage
                                                        * the drive cannot explain (psi_band.h): the last trusted
                                                        * or the told model, the conventional torque path
                                                        * (with flag 0x0100, the inverter error unmeasured:
                                                        * at every speed) */
#define CTRL_EST_HOLD_NO_STEP2    EST_HOLD_NO_STEP2    /* 0x0040 step 2 not running (observer off, step 1, step 1
                                                        * refused): the told values */
#define CTRL_EST_HOLD_ANGLE       EST_HOLD_ANGLE       /* 0x0080 L^ held: step 1 suggests an angle error */

/* ctrl_cfg_t.track_R: off; on from step 2's start; auto from
 * rtrack.auto_delay_periods after it (step 1's R^ holds that long: a
 * winding's thermal time constant is minutes; r_tracking_design.md sec. 3). */
#define CTRL_TRACK_R_OFF  0u
#define CTRL_TRACK_R_ON   1u
#define CTRL_TRACK_R_AUTO 2u

typedef struct {
    float Ts_s;                 /* control period [s], 1e-4 */
    float R_Ohm;               /* controller's stator resistance (may differ from the motor's) */
    float L_H;                 /* controller's inductance, Ld = Lq */
    float psi_f_Wb;             /* controller's PM flux linkage */
    uint16_t pole_pairs;
    uint32_t enc_lines;         /* encoder lines; counts per revolution = 4 * lines */
    float enc_offset_el_rad;    /* electrical angle at encoder count 0 */
    float enc_pll_bw_rad_s;     /* speed-estimator bandwidth [rad/s] */
    float speed_kp_Nms_rad;     /* speed PI: N m per (rad/s) of mechanical speed error */
    float speed_ki_Nm_rad;      /* speed PI: N m per rad of integrated speed error */
    float te_max_Nm;            /* |Te*| limit, 2x rated = 12 N m */
    float i_max_A;              /* bound on the currents the model uses */
    float u_max_V;              /* bound on |ud|, |uq| before the hexagon */
    float omega_max_el_rad_s;   /* bound on |omega_el| the model uses */
    float psi_max_Wb;           /* bound on psi_s* */
    float deadtime_s;           /* inverter dead time [s]: its voltage error is fed forward and
                                 * counted in the realised voltage; 0: none */
    float device_drop_V;        /* on-state drop of a leg's conducting device [V], fed forward and
                                 * counted as the dead time's error is (against the current's
                                 * sign, on top of it); 0: none */
    /* Operating limits (limits_design.md); i_lim_A outside (0, i_max_A]: i_max_A;
     * u_margin outside (0, 1]: 0.92 (ctrl.c CTRL_U_MARGIN_DEFAULT) */
    float i_lim_A;              /* stator-current limit |i| [A] the deadbeat target respects */
    float u_margin;             /* share of the inscribed circle Vdc/sqrt(3) the flux
                                 * reference leaves for steady state (flux weakening) [-] */
    /* Proposed method; ctrl_cfg_proposed_defaults() fills all of it. The
     * fields of smo/pe/rsid that repeat the ones above (Ts, nominal R, L,
     * psi_f, the bounds, the R band) are taken from here by ctrl_init(). */
    float R_min_Ohm;            /* accepted R^ band [Ohm], absolute: rs_ident's */
    float R_max_Ohm;            /*   plausibility check and smo's setter range */
    smo_cfg_t smo;              /* observer gains and ranges */
    param_est_cfg_t pe;         /* step-2 rates, thresholds, clamps */
    rs_ident_cfg_t rsid;        /* step-1 checks */
    r_track_cfg_t rtrack;       /* d-axis injection: inverter error after step 1, R in service */
    uint16_t track_R;           /* CTRL_TRACK_R_*: R^ tracked in step 2 by the injection (r_tracking_design.md) */
    float untold_deadtime_s;    /* the speed floor's prior until the inverter error is identified: the
                                 * least error nobody told, as a dead time [s] (holds_design.md sec. 6) */
    est_gate_cfg_t gate;        /* when step 2 may learn (est_gate.h) */
} ctrl_cfg_t;

/* What ctrl_init refused, a set of bits (0: nothing). A refused block
 * must not run: the app refuses a start that needs one (CONFIG fault). */
typedef uint16_t ctrl_status_t;
#define CTRL_CFG_OK         ((ctrl_status_t)0x0000u)
#define CTRL_CFG_OBSERVER   EST_CFG_OBSERVER         /* 0x0001 smo_init refused (stability, (36)) */
#define CTRL_CFG_ESTIMATOR  EST_CFG_ESTIMATOR        /* 0x0002 param_est_init or psi_band_init refused */
#define CTRL_CFG_RSID       EST_CFG_RSID             /* 0x0004 rs_ident_init refused */
#define CTRL_CFG_ENCODER    ((ctrl_status_t)0x0008u) /* encoder_init refused (e.g. PLL bandwidth x Ts above its bound) */
#define CTRL_CFG_SPEED_PI   ((ctrl_status_t)0x0010u) /* pi_init refused the speed PI's gains or limits */
#define CTRL_CFG_DBDTC      ((ctrl_status_t)0x0020u) /* dbdtc_init refused the model's parameters or bounds */
#define CTRL_CFG_DEADTIME   ((ctrl_status_t)0x0040u) /* dead time not finite, negative or above 0.1 Ts;
                                                      * or device drop so, or above 0.1 u_max_V */
#define CTRL_CFG_GATE       EST_CFG_GATE             /* 0x0080 est_gate_init refused (step 2's pause and hold) */
#define CTRL_CFG_RTRACK     EST_CFG_RTRACK           /* 0x0100 r_track_init refused (d-current injection, inverter_error_design.md) */
/* Needed by every method (encoder, speed loop, model, output path)... */
#define CTRL_CFG_NEEDED_ALWAYS   ((ctrl_status_t)(CTRL_CFG_ENCODER | CTRL_CFG_SPEED_PI | CTRL_CFG_DBDTC | CTRL_CFG_DEADTIME))
/* ...and by the proposed method's steps 1 and 2. */
#define CTRL_CFG_NEEDED_PROPOSED ((ctrl_status_t)(CTRL_CFG_OBSERVER | CTRL_CFG_ESTIMATOR | CTRL_CFG_RSID | CTRL_CFG_GATE | CTRL_CFG_RTRACK))

/* Where the proposed method's steps stand (ctrl_t.ident, monitor). */
typedef enum {
    CTRL_IDENT_OFF = 0,           /* observer stopped */
    CTRL_IDENT_STEP1 = 1,         /* observer runs, R^ (then the inverter error) being identified,
                                 * conventional control */
    CTRL_IDENT_STEP2 = 2          /* observer and L^, psi^ estimator run */
} ctrl_ident_t;

typedef struct { float ia_A; float ib_A; float vdc_V; uint32_t enc_count; } ctrl_in_t; /* one period's samples */

typedef struct {
    float speed_ref_rad_s;      /* mechanical speed reference (speed mode) */
    float te_ref_Nm;            /* torque reference (torque mode) */
    float ud_ref_V, uq_ref_V;   /* rotor-frame voltage (open-loop mode) */
} ctrl_ref_t;

typedef struct { float duty[3]; uint16_t flags; } ctrl_out_t;

typedef struct {                /* monitor: written by every ctrl_step (ctrl_monitor_readings in the other
                                 * states), for logging/telemetry */
    float theta_el_rad, omega_el_rad_s, speed_mech_rad_s;   /* as the controller sees them */
    float id_A, iq_A;                     /* measured this period */
    float i_aim_alpha_A, i_aim_beta_A;    /* the current the step aimed at (its Te*, psi_s* through the model
                                           * in use), stator frame; 0 in open loop and the other states */
    float ud_V, uq_V;                     /* rotor-frame voltage commanded for the next period, after the hexagon clamp */
    float te_ref_Nm, te_est_Nm;           /* torque reference and the controller's torque estimate (at k+1) */
    float psi_ref_Wb, psi_est_Wb;         /* stator-flux reference and estimate (at k+1) */
    uint16_t model_from_observer;         /* 1: this step's model was the estimation's (proposed, step 2) */
} ctrl_mon_t;                           /* the estimation's model and status: ctrl_est() */

typedef struct {
    ctrl_cfg_t cfg;
    ctrl_mode_t mode;           /* active mode */
    ctrl_mode_t mode_req;       /* set in background, taken at the next step */
    ctrl_method_t method;
    ctrl_ref_t ref;
    encoder_t enc;
    dbdtc_t db;                 /* parameters in use live in db.par */
    pi_t speed_pi;
    dq_t u_applied_V;           /* realised rotor-frame voltage being applied this period, u(k) */
    float deadtime_frac;        /* td/Ts from cfg (0: no compensation) */
    float device_drop_V;        /* the drop from cfg (0: none or refused) [V] */
    float i_lim_A;              /* current limit in use (cfg.i_lim_A or i_max_A) [A] */
    float u_lim_per_vdc;        /* steady-state voltage limit / Vdc: u_margin / sqrt(3) [-] */
    oplim_t lim;                /* current limit and flux weakening (oplim.h) */
    ctrl_status_t status;       /* from ctrl_init; not OK: the proposed method is unavailable */
    est_t est;                  /* the proposed method's estimation (est.h): only through its calls */
    est_in_t est_in;            /* the estimation's inputs of this period (ctrl.c stage_estimate) */
    uint16_t flags_last;        /* CTRL_FLAG_* of the last step (the estimation's voltage check) */
    uint16_t model_src;         /* what db.par holds: the told model or the estimation's (ctrl.c MODEL_*) */
    bool tracked;               /* ctrl_track ran this period: ctrl_step leaves the encoder alone */
    ctrl_mon_t mon;
} ctrl_t;

/* The observer's switching gain, boundary layer and the disturbance
 * error condition (36) must dominate (smo_cfg_t Ks_V, phi_A, ef_max_V). */
typedef struct {
    float Ks_V;                 /* switching gain [V] */
    float phi_A;                /* boundary layer [A]; G = Ks/phi [V/A] */
    float ef_max_V;             /* |f^ - f| (36) must dominate [V] */
} ctrl_obs_gains_t;

/* Background: smo.h's design defaults (Table I: 100 V, 2.5 A, 50 V). */
void ctrl_obs_gains_default(ctrl_obs_gains_t *g);

/* Background: the gains for a motor (smo_design.md sec. 4): Ks =
 * 2 ef_max_V ((36) with R^ up to 0.45 G and a 10 % margin), phi = phi_A
 * unless G = Ks/phi would pass the discrete stability bound with L^'s
 * floor at half the told L_H and the margin OBS_L_MIN_STABILITY_MARGIN
 * (*G_max_V_A), then phi = Ks / G_max. Returns false (g filled all the
 * same) when the band's top 0.45 G leaves out R_Ohm, or G_max <= 0: no
 * gain satisfies both bounds. */
bool ctrl_obs_gains_design(float Ts_s, float R_Ohm, float L_H, float ef_max_V, float phi_A,
                           ctrl_obs_gains_t *g, float *G_max_V_A);

/* Fills the proposed method's settings of *cfg from its other fields
 * (set those first) with the modules' design defaults, the R^ band
 * [R_min_Ohm, R_max_Ohm] (absolute: the nominal R may be far from the
 * motor's) and L^ kept above the observer's stability bound at R_max.
 * Background, before ctrl_init. */
void ctrl_cfg_proposed_defaults(ctrl_cfg_t *cfg, float R_min_Ohm, float R_max_Ohm);

/* As ctrl_cfg_proposed_defaults with the observer's gains *g. Background. */
void ctrl_cfg_proposed_with(ctrl_cfg_t *cfg, float R_min_Ohm, float R_max_Ohm, const ctrl_obs_gains_t *g);

/* The default R^ band for cfg->R_Ohm (set it first): rs_ident.h's
 * RS_IDENT_BAND_*_FACTOR x R_Ohm, the top kept below the largest R^ the
 * observer's default gains take under condition (36) (step1_design.md
 * sec. 8), and not below R_Ohm. Background, before ctrl_cfg_proposed_defaults. */
void ctrl_rsid_band_default(const ctrl_cfg_t *cfg, float *R_min_Ohm, float *R_max_Ohm);

/* As ctrl_rsid_band_default under condition (36) with the gains *g. Background. */
void ctrl_rsid_band_with(const ctrl_cfg_t *cfg, const ctrl_obs_gains_t *g, float *R_min_Ohm, float *R_max_Ohm);

/* Start-up: copy *cfg, build the blocks, reset; mode torque, method
 * conventional. Returns the set of refusals of every block (CTRL_CFG_*):
 * encoder, speed PI, model, dead time, and the proposed method's settings
 * (observer stability bound and condition (36) in smo_init, estimator and
 * step-1 limits). A refusal in CTRL_CFG_NEEDED_PROPOSED makes the proposed
 * method unavailable; the app refuses a start needing any refused block. */
ctrl_status_t ctrl_init(ctrl_t *c, const ctrl_cfg_t *cfg);

/* Clear states (integrator, applied voltage); observer stopped, estimates
 * back to nominal (step 1 is to be repeated). The encoder keeps tracking
 * (ctrl_track). Background, or ISR before PWM is enabled. */
void ctrl_reset(ctrl_t *c);

/* ISR at the start of a period (the app takes the operator's request
 * there), or a harness between periods; takes effect at the next step
 * (bumpless into speed mode). */
void ctrl_set_mode(ctrl_t *c, ctrl_mode_t mode);

/* The current limit the targets respect [A], as cfg.i_lim_A at init
 * (outside (0, i_max_A]: i_max_A); from the next step. ISR (the app's
 * state machine) or background while stopped. */
void ctrl_set_i_lim(ctrl_t *c, float i_lim_A);

/* As ctrl_set_mode; switchable at run time, bumpless (policy in the
 * header comment). Returns false (method unchanged) for PROPOSED when
 * ctrl_init did not return CTRL_CFG_OK. */
bool ctrl_set_method(ctrl_t *c, ctrl_method_t method);

/* Step 1 begins: observer (re)started from the nominal parameters, step 2
 * stopped, windows emptied; control conventional until ctrl_rsid_finish().
 * Returns false when the proposed method is unavailable. ISR (the app's
 * state machine) or background while stopped. */
bool ctrl_rsid_begin(ctrl_t *c);

/* Window the following periods are averaged into (RS_IDENT_WINDOW_NONE
 * while settling). ISR or background. */
void ctrl_rsid_window(ctrl_t *c, rs_ident_window_t win);

/* Step 1 ends: solves (step1_design.md sec. 1) into c->rsid_out; on RS_IDENT_OK
 * sets R^ bumplessly and starts step 2 - its first 0.12 s at the same
 * operating point identify the inverter error (inverter_error_design.md sec. 5) -
 * otherwise stops the
 * observer and returns the reason. ISR once (about 20 divisions) or background. */
rs_ident_result_t ctrl_rsid_finish(ctrl_t *c);

/* A staged check of step 1's windows so far (est.h
 * est_rsid_stage_begin/_step): begun (true) only at a batch boundary of
 * window 2, its sample sums copied into *win2_copy, *s the caller's
 * solver; one stage per call of ctrl_rsid_stage_step, true when
 * s->result and ctrl_rsid_out() are final (the d-axis and angle checks
 * included). ISR (a bounded stage each). */
bool ctrl_rsid_stage_begin(ctrl_t *c, rs_ident_solver_t *s, rs_ident_head_t *win2_copy);
bool ctrl_rsid_stage_step(ctrl_t *c, rs_ident_solver_t *s);

/* Step 1 ends on a staged solve's result r (in ctrl_rsid_out()); the rest
 * as ctrl_rsid_finish. No division. ISR once. */
rs_ident_result_t ctrl_rsid_finish_with(ctrl_t *c, rs_ident_result_t r);

/* Step 2 without step 1, for an R the caller trusts (a recent
 * identification at the same winding temperature): R^ = R_Ohm, observer
 * started (seeded) if stopped, estimator running. False when R_Ohm is
 * outside [R_min_Ohm, R_max_Ohm] or the method is unavailable. ISR or background. */
bool ctrl_est_start(ctrl_t *c, float R_Ohm);

/* References [rad/s mech, N m, V]. As ctrl_set_mode: a multi-word copy
 * the ISR must not be interrupted in by another writer. */
void ctrl_set_ref(ctrl_t *c, const ctrl_ref_t *ref);

/* The targets' current limit [A] from now on, i_lim_A in (0, cfg.i_lim_A]
 * (else cfg's). Background: one 32-bit store, the ISR reads the old
 * value or the new one. */
void ctrl_set_i_limit(ctrl_t *c, float i_lim_A);

/* Every period, in every state, first: the encoder count [counts] into
 * the angle and speed estimate. ctrl owns the encoder: ctrl_step uses what
 * this call left (and tracks in->enc_count itself only when the caller
 * did not call ctrl_track this period, as a bare controller does). ISR.
 * Inline: one call less in every period. */
static inline void ctrl_track(ctrl_t *c, uint32_t enc_count)
{
    encoder_step(&c->enc, enc_count);
    c->tracked = true;
}

/* The rotor's d axis is on phase a: the count enc_count now reads 0 rad
 * el (the app's alignment). ISR. */
void ctrl_encoder_align(ctrl_t *c, uint32_t enc_count);

/* One control period from the samples *in; duties and flags to *out. ISR, 10 kHz. */
void ctrl_step(ctrl_t *c, const ctrl_in_t *in, ctrl_out_t *out);

/* One period of a stationary-frame voltage u_ab_V [V] at the bus vdc_V
 * [V] (the app's rotor alignment): the same output path as ctrl_step -
 * SVPWM, the realised voltage kept as u(k) (at the encoder's angle), the
 * finiteness check (50 % duties and CTRL_FLAG_NONFINITE for a non-finite
 * input or no bus) - without the dead-time feedforward. ISR, 10 kHz,
 * instead of ctrl_step. */
void ctrl_step_ab(ctrl_t *c, ab_t u_ab_V, float vdc_V, ctrl_out_t *out);

/* The monitor's readings of a period without ctrl_step (the drive stopped
 * or faulted, a start-up step, a commissioning, a build level): angle and
 * speed of this period's ctrl_track, the measured currents in the rotor
 * frame (in: offsets subtracted), the torque (3) and the flux the model in
 * use gives for them, the voltage applied (ctrl_step_ab's u(k) when
 * outputs_on, else 0), the references 0. ISR, after the state's step. */
void ctrl_monitor_readings(ctrl_t *c, const ctrl_in_t *in, bool outputs_on);

/* ---- readers: what the app, the command block and the SIL see -------
 * Any context: single words, or the monitor written once per ctrl_step. */

/* The monitor of the last ctrl_step (logging, telemetry). */
static inline const ctrl_mon_t *ctrl_monitor(const ctrl_t *c)
{
    return &c->mon;
}

/* Mechanical speed estimate of the last ctrl_track [rad/s]. */
static inline float ctrl_speed_m_rad_s(const ctrl_t *c)
{
    return c->enc.omega_m_rad_s;
}

/* Electrical angle at encoder count 0 [rad el], told or aligned, in [0, 2 pi). */
static inline float ctrl_enc_offset_el_rad(const ctrl_t *c)
{
    return c->enc.offset_el_rad;
}

/* ctrl_init's refusals (CTRL_CFG_*). */
static inline ctrl_status_t ctrl_status(const ctrl_t *c)
{
    return c->status;
}

/* The method in use. */
static inline ctrl_method_t ctrl_method(const ctrl_t *c)
{
    return c->method;
}

/* The mode asked for (in use from the next step). */
static inline ctrl_mode_t ctrl_mode(const ctrl_t *c)
{
    return c->mode_req;
}

/* The references in use [rad/s mech, N m, V]. */
static inline const ctrl_ref_t *ctrl_ref(const ctrl_t *c)
{
    return &c->ref;
}

/* The last ctrl_rsid_finish(): R^ (raw, accepted or not), window means,
 * standard errors. */
static inline const rs_ident_out_t *ctrl_rsid_out(const ctrl_t *c)
{
    return est_rsid_out(&c->est);
}

/* The step-1 settings ctrl_init gave rs_ident (R band, limits, batch). */
static inline const rs_ident_cfg_t *ctrl_rsid_cfg(const ctrl_t *c)
{
    return est_rsid_cfg(&c->est);
}

/* The estimation (est.h readers: est_output() - the model, its status
 * and phase - est_psi_f_obs_Wb(), est_f_V()). */
static inline const est_t *ctrl_est(const ctrl_t *c)
{
    return &c->est;
}

/* Where the proposed method's steps stand now. */
static inline ctrl_ident_t ctrl_ident(const ctrl_t *c)
{
    return (ctrl_ident_t)est_output(&c->est)->phase;
}

#endif /* CTRL_H */
