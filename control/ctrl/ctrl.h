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

/* What ctrl_t.db.par holds (ctrl_t.model_src). */
#define CTRL_MODEL_EST      0u      /* the estimation's model */
#define CTRL_MODEL_NOMINAL  1u      /* the configured parameters */

typedef enum { CTRL_MODE_OPEN_LOOP = 0, CTRL_MODE_TORQUE = 1, CTRL_MODE_SPEED = 2 } ctrl_mode_t;

/* The oscillation watch on the estimated model (discrete_model_design.md
 * sec. 7). The deadbeat's innovation eps(k) = i(k) - (the state at k it
 * started from a period before) obeys eps(k+2) = (1 - lambda) eps(k) for
 * a model L^ = lambda L: its lag-2 regression num/den is 1 - lambda, near
 * 0 on a right model, -1 where the error stops shrinking (lambda = 2),
 * below it growing (at 2.2 by 1.2x per 2 periods, a hundredfold in 50).
 * Averaged over CTRL_OSC_PERIODS, while the innovation's rms is above
 * ctrl_cfg_t.osc_i_min_A (the ADC's noise): at lambda >= CTRL_OSC_LAMBDA_HOLD
 * L^ is cut by 1/lambda, the L the oscillation measures, and held
 * (est_hold_oscillation). */
#define CTRL_OSC_PERIODS     128.0f /* the regression's averaging (a pair every 4 periods) [periods] */
#define CTRL_OSC_LAMBDA_HOLD 2.0f  /* L^/L at which the error stops shrinking: cut [-] */

typedef struct {
    dq_t pred_A;                /* the state at k+1 the model started from this period [A] */
    dq_t eps_A;                 /* the innovation i - pred of the pair's first period [A] */
    float num_A2;               /* <eps(k), eps(k-2)>, <eps(k-2), eps(k-2)>, averaged [A^2] */
    float den_A2;
    uint16_t phase;             /* 0..3: a lag-2 pair every 4 periods (0: its first, 2: its second) */
} ctrl_osc_t;

/* One period of the watch: every 4 periods a pair of innovations
 * i_A - o->pred_A two periods apart into the regression (the lag-2
 * regression needs no more); x_next_A the next prediction. Returns
 * lambda = 1 - num/den when it reached CTRL_OSC_LAMBDA_HOLD with den above
 * den_min_A2 [A^2] (the watch then starts anew), else 0. ISR (inline). */
static inline float ctrl_osc_step(ctrl_osc_t *o, dq_t i_A, dq_t x_next_A, float den_min_A2)
{
    float lambda = 0.0f;
    if (o->phase == 0u) {
        o->eps_A.d = i_A.d - o->pred_A.d;
        o->eps_A.q = i_A.q - o->pred_A.q;
    } else if (o->phase == 2u) {
        const float ed = i_A.d - o->pred_A.d;
        const float eq = i_A.q - o->pred_A.q;
        o->num_A2 += (4.0f / CTRL_OSC_PERIODS) * ((ed * o->eps_A.d + eq * o->eps_A.q) - o->num_A2);
        o->den_A2 += (4.0f / CTRL_OSC_PERIODS) * ((o->eps_A.d * o->eps_A.d + o->eps_A.q * o->eps_A.q) - o->den_A2);
        if ((o->den_A2 > den_min_A2) && (o->num_A2 < (1.0f - CTRL_OSC_LAMBDA_HOLD) * o->den_A2)) {
            lambda = 1.0f - o->num_A2 / o->den_A2;
            o->num_A2 = 0.0f;
            o->den_A2 = 0.0f;
        }
    } else {
        /* between the pairs */
    }
    o->phase = (uint16_t)((o->phase + 1u) & 3u);
    o->pred_A = x_next_A;
    return lambda;
}
typedef enum { CTRL_METHOD_CONVENTIONAL = 0, CTRL_METHOD_PROPOSED = 1 } ctrl_method_t;

/* Flags in ctrl_out_t.flags; the estimation's bits (est.h EST_FLAG_*,
 * 0x0100-0x0800) are or-ed in. */
#define CTRL_FLAG_VOLTAGE_LIMIT    0x0001u /* vector clamped to the hexagon */
#define CTRL_FLAG_FLUX_UNREACHABLE 0x0002u /* negative discriminant: flux target not reachable in one period */
#define CTRL_FLAG_NONFINITE        0x0004u /* a non-finite value appeared; duties are 0.5 and the app must fault */

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
    uint16_t te_max_follows_kt; /* 1: te_max_Nm is the told model's kt times a current (the derived
                                 * default: kt i_peak), so the limit follows the kt of the model in use
                                 * (the learned psi_f); 0: a fixed cap */
    float i_max_A;              /* bound on the currents the model uses */
    float u_max_V;              /* bound on |ud|, |uq| before the hexagon */
    float omega_max_el_rad_s;   /* bound on |omega_el| the model uses */
    float osc_i_min_A;          /* the oscillation watch judges an innovation above this rms (the ADC's
                                 * noise: drive_trip_margin_A); <= 0: no watch [A] */
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
    est_cfg_t est_cfg;          /* the proposed method's estimation: est_cfg_defaults() for
                                 * ctrl_cfg_told() of the fields above builds it */
} ctrl_cfg_t;

/* What ctrl_init refused, a set of bits (0: nothing). A refused block
 * must not run: the app refuses a start that needs one (CONFIG fault). */
typedef uint16_t ctrl_status_t;
#define CTRL_CFG_OK         ((ctrl_status_t)0x0000u)
#define CTRL_CFG_ENCODER    ((ctrl_status_t)0x0008u) /* encoder_init refused (e.g. PLL bandwidth x Ts above its bound) */
#define CTRL_CFG_SPEED_PI   ((ctrl_status_t)0x0010u) /* pi_init refused the speed PI's gains or limits */
#define CTRL_CFG_DBDTC      ((ctrl_status_t)0x0020u) /* dbdtc_init refused the model's parameters or bounds */
#define CTRL_CFG_DEADTIME   ((ctrl_status_t)0x0040u) /* dead time not finite, negative or above 0.1 Ts;
                                                      * or device drop so, or above 0.1 u_max_V */
/* The estimation's refusals (est.h EST_CFG_*: 0x0001, 0x0002, 0x0004,
 * 0x0080, 0x0100) are or-ed in. Needed by every method (encoder, speed
 * loop, model, output path)... */
#define CTRL_CFG_NEEDED_ALWAYS   ((ctrl_status_t)(CTRL_CFG_ENCODER | CTRL_CFG_SPEED_PI | CTRL_CFG_DBDTC | CTRL_CFG_DEADTIME))
/* ...and by the proposed method's steps 1 and 2: every refusal of the estimation. */
#define CTRL_CFG_NEEDED_PROPOSED ((ctrl_status_t)EST_CFG_ANY)

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
} ctrl_mon_t;                           /* the estimation's model and status: ctrl_est(); written,
                                         * never read back by ctrl_step */

typedef struct {                /* what ctrl_t keeps of ctrl_cfg_t (the blocks keep their own) */
    float Ts_s;                 /* control period [s] */
    float i_max_A;              /* bound on the currents the model uses [A] */
    float i_lim_A;              /* the configured current limit (ctrl_cfg_t.i_lim_A as given) [A] */
    float u_max_V;              /* bound on |ud|, |uq| [V] */
    float omega_max_el_rad_s;   /* bound on |omega_el| [rad/s el] */
    float te_max_Nm;            /* |Te*| limit as configured [N m] */
    uint16_t te_max_follows_kt; /* ctrl_cfg_t's */
} ctrl_kept_t;

typedef struct {
    ctrl_kept_t cfg;
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
    float ripple_A;             /* the largest current ripple at a leg's edge in the last period (inverr.h) [A] */
    zoh_turn_t turn;            /* the rotor's turn over a period, taken at w within turn_tol of w(k) (zoh.h) */
    float turn_tol_rad_s;       /* ZOH_THETA_TOL_RAD / Ts [rad/s el] */
    float omega_lo_rad_s;       /* -cfg.omega_max_el_rad_s: w(k)'s lower bound, negated once [rad/s el] */
    float i_lim_A;              /* current limit in use (cfg.i_lim_A or i_max_A) [A] */
    float te_lim_Nm;            /* |Te*| limit in use: te_max_Nm, times kt(model)/kt(told) when it follows kt [N m] */
    float te_per_psi_Nm_Wb;     /* te_max_Nm / told psi_f when the limit follows kt, else 0 [N m/Wb] */
    ctrl_osc_t osc;             /* the oscillation watch (CTRL_OSC_*) */
    float osc_den_min_A2;       /* osc_i_min_A^2 (0: no watch) [A^2] */
    float u_lim_per_vdc;        /* steady-state voltage limit / Vdc: u_margin / sqrt(3) [-] */
    oplim_t lim;                /* current limit and flux weakening (oplim.h) */
    ctrl_status_t status;       /* from ctrl_init; not OK: the proposed method is unavailable */
    est_t est;                  /* the proposed method's estimation (est.h): only through its calls */
    est_in_t est_in;            /* the estimation's inputs of this period (ctrl.c stage_estimate) */
    uint16_t flags_last;        /* CTRL_FLAG_* of the last step (the estimation's voltage check) */
    float te_ref_last_Nm;       /* Te* of the last step (the estimation's transient check) [N m] */
    float te_est_last_Nm;       /* the model's Te(k+1) of the last step (bumpless into speed mode) [N m] */
    uint16_t model_src;         /* what db.par holds: the told model or the estimation's (ctrl.c MODEL_*) */
    bool tracked;               /* ctrl_track ran this period: ctrl_step leaves the encoder alone */
    ctrl_mon_t mon;
} ctrl_t;

/* The told model and bounds of *cfg as the estimation takes them (for
 * est_cfg_defaults(&cfg->est_cfg, ...); ctrl_init passes the same, with
 * the dead time as taken, to est_init). Background. */
void ctrl_cfg_told(const ctrl_cfg_t *cfg, est_told_t *told);

/* The torque limit (ctrl_t.te_lim_Nm) and the speed PI's output limits
 * for the model now in use (ctrl.c; ctrl_init, ctrl_reset and the model's
 * changes call it). ISR or background. */
void ctrl_take_te_limit(ctrl_t *c);

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

/* References [rad/s mech, N m, V]. As ctrl_set_mode: a multi-word copy
 * the ISR must not be interrupted in by another writer. */
void ctrl_set_ref(ctrl_t *c, const ctrl_ref_t *ref);

/* The speed reference alone [rad/s mech], the others kept: one 32-bit
 * store. ISR (step 1's speeds), or background. */
void ctrl_set_speed_ref(ctrl_t *c, float speed_ref_rad_s);

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

/* Step 1 ends on a staged solve's result r_solved (est_rsid_finish_with);
 * where its windows found an encoder angle error (est.h
 * est_angle_error_el_rad), the encoder's offset corrected by it and step 2
 * started again on the corrected angle (holds_design.md sec. 8). ISR once. */
rs_ident_result_t ctrl_rsid_finish(ctrl_t *c, rs_ident_result_t r_solved);

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

/* The current limit the targets respect now [A] (ctrl_set_i_lim,
 * ctrl_set_i_limit). */
static inline float ctrl_i_lim_A(const ctrl_t *c)
{
    return c->i_lim_A;
}

/* The references in use [rad/s mech, N m, V]. */
static inline const ctrl_ref_t *ctrl_ref(const ctrl_t *c)
{
    return &c->ref;
}

/* The estimation (est.h: its readers est_output() - the model, its
 * status and phase - est_psi_f_obs_Wb(), est_f_V(), est_rsid_out()). */
static inline const est_t *ctrl_est(const ctrl_t *c)
{
    return &c->est;
}

/* The estimation for its calls (est.h: step 1's begin, windows, staged
 * solve and finish, est_start_trusted); the proposed method's steps are
 * asked for there. ISR (the app's state machine) or background while
 * stopped. */
static inline est_t *ctrl_est_rw(ctrl_t *c)
{
    return &c->est;
}

#endif /* CTRL_H */
