/*
 * app.h - the ISR glue and the drive state machine.
 *
 *   INIT --start--> CALIBRATE --offsets in band--> ALIGN --settled-->
 *        IDENTIFY_R --R^ accepted--> RUN
 *   IDLE --start--> (the same sequence)
 *   CALIBRATE, ALIGN, IDENTIFY_R, RUN --stop--> IDLE
 *   INIT, IDLE, CALIBRATE, ALIGN, IDENTIFY_R, RUN --protection--> FAULT
 *   INIT, IDLE --commission--> CALIBRATE (if on) --> COMMISSION
 *              --measured--> IDLE (results in comm.res, comm_valid)
 *   COMMISSION --stop--> IDLE; --refused (COMM_*)--> FAULT
 *   INIT --start-up fault (app_latch_startup_fault)--> FAULT
 *   IDENTIFY_R --R^ refused--> FAULT (the reason in the code), or with
 *              rsid.on_refusal = TOLD --> RUN, step 2 from the told R (the
 *              inverter error identified, R^ learned by injection), or
 *              CONVENTIONAL --> RUN, conventional method; both with the
 *              warning APP_WARN_STEP1_REFUSED (the reason in rsid_refusal)
 *   FAULT --fault reset, cause gone--> IDLE (never from FLASH_CRC)
 *
 * INIT is the power-on state (nothing measured yet, bus may still be
 * charging); IDLE the stopped state after a run or a fault. A start runs
 * the sequence; a step that is off (cfg.calibrate, cfg.align) or already
 * done (alignment, once per power-up) is skipped within the same ISR call,
 * so with both off the start request's ISR call is already a RUN period.
 * Each step is its own state machine (app_step.h):
 *   CALIBRATE  calib.h: PWM off, the current offsets, at every start.
 *   ALIGN      align.h: the rotor's d axis onto phase a by two stationary
 *              voltage vectors through ctrl_step_ab() (ctrl's SVPWM and
 *              finiteness check), then encoder_align(). Once per power-up,
 *              again after an ENCODER fault.
 *   IDENTIFY_R rsid_seq.h: step 1 of the proposed method, at every start
 *              (R follows the winding temperature). A controller whose
 *              proposed-method settings ctrl_init refused cannot identify:
 *              a start then faults CONFIG before anything is energised.
 *   RUN        ctrl_step every period.
 *   COMMISSION commission.h: checks the phase order, the encoder's
 *              direction and the told pole pairs (enc_check.h, as level
 *              3), measures R, L, the encoder offset, psi_f, J and B on
 *              a free shaft
 *              without the controller's told R, L, psi_f (its voltage
 *              through ctrl_step_ab, as ALIGN's); needs only the encoder
 *              block of ctrl_init and app_attach_comm(). The measured
 *              offset replaces the controller's (as an alignment).
 * Why the sequence is built this way (dead points of the alignment,
 * open-loop voltage, the handover): firmware/app/startup_design.md.
 *
 * Background requests (start, stop, fault reset, the operator's
 * references, mode and method) only set a flag; the ISR carries them out
 * at the start of its next call, so the controller state is only ever
 * touched from the ISR. ctrl_track() runs first in every call, in every
 * state: the controller owns the encoder. The monitor's readings (speed,
 * measured currents) and the bus reading are this period's in every
 * state (ctrl_monitor_readings where ctrl_step does not run). A fault turns the PWM off in the same
 * ISR call that detected it and keeps a snapshot (protect.h).
 *
 * Protection (protect.h) in every state but FAULT, and from the state's
 * own step: NONFINITE_OUTPUT (controller or alignment output),
 * CURRENT_OFFSET (CALIBRATE), RSID_* and CONFIG (IDENTIFY_R),
 * ENCODER_DIRECTION, POLE_PAIRS, PHASE_ORDER (ENC_CHECK).
 *
 * Build levels (level.h), taken at a start (app_request_level before it):
 *   level 1  INIT/IDLE --start--> PWM_CHECK (until stopped)
 *   level 2  --start--> CALIBRATE --> ADC_CHECK (until stopped)
 *   level 3  --start--> (CALIBRATE) --> ENC_CHECK --checked--> IDLE
 *            (or FAULT: ENCODER_DIRECTION, POLE_PAIRS, PHASE_ORDER)
 *   level 4  the sequence above, torque mode, conventional, no step 1,
 *            current limit lvl.i_lim_4_A
 *   level 5  the sequence above as configured
 * PWM_CHECK, ADC_CHECK, ENC_CHECK --stop--> IDLE. Undervoltage is not
 * checked at levels 1-2 (no DC bus); a bus above lvl.vdc_max_12_V at their
 * start, or in PWM_CHECK or ADC_CHECK, latches BUS_CHARGED (level.h);
 * CALIBRATE runs at level 2 whatever cfg.calibrate says (the offsets are
 * what it reports).
 */
#ifndef APP_H
#define APP_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "align.h"
#include "app_step.h"
#include "calib.h"
#include "commission.h"
#include "ctrl.h"
#include "drive_params.h"
#include "hal.h"
#include "level.h"
#include "protect.h"
#include "rsid_seq.h"

/* Warnings (app_t.warnings): the drive runs on, but not as configured.
 * Bits above ctrl_out_t.flags' (CTRL_FLAG_*): the SIL's CSV column
 * `flags` carries both. Cleared at the next start. */
#define APP_WARN_STEP1_REFUSED 0x1000u /* step 1 refused R^ (rsid_refusal says why): conventional method */
#define APP_WARN_HOST_TIMEOUT  0x2000u /* the link's host went quiet: the drive ramped to zero and stopped (link.h) */
#define APP_WARN_OSCILLATION   0x4000u /* the current oscillated on step 2's model: the told model since
                                        * (est.h EST_HOLD_OSCILLATION) */

/* CONFIG's snapshot value: ctrl_init's refusals (ctrl_status_t, bits up to
 * 0x0100) | app_cfg_t.params_refused shifted this far. */
#define APP_PARAMS_REFUSED_SHIFT 12u

/* The app's configuration: the controller's, and each piece's own (the
 * step's init takes it as it is: one home per value). */
typedef struct {
    ctrl_cfg_t ctrl;
    protect_cfg_t prot;         /* protection limits and the watch checks (protect.h); Ts, counts, te_max and pole pairs from ctrl */
    bool calibrate;             /* measure the current offsets at every start */
    calib_cfg_t cal;            /* CALIBRATE (calib.h) */
    bool align;                 /* encoder offset unknown: align the rotor once per power-up */
    align_cfg_t aln;            /* ALIGN (align.h) */
    rsid_seq_cfg_t rsid;        /* IDENTIFY_R: step 1 of the proposed method and its refusal policy (rsid_seq.h) */
    comm_cfg_t comm;            /* COMMISSION (commission.h) */
    /* The I^2t budget (app_background): above i2t_rated_A the budget
     * (i_peak^2 - i_rated^2) t_peak drains by (i^2 - i_rated^2) dt; spent,
     * the targets' current limit is i2t_rated_A until half of it is back. */
    float i2t_rated_A;          /* continuous current [A]; <= 0: no budget */
    float i2t_budget_A2s;       /* [A^2 s] */
    uint16_t params_refused;    /* drive_params_derive's refusals of the ratings and the ADC range
                                 * (DRIVE_DERIVE_RATINGS, _ADC_RANGE; 0: none): a start faults CONFIG */
    level_cfg_t lvl;            /* the build levels (level.h) */
} app_cfg_t;

/* Level 2's report: the ADC's readings of the last ADC_CHECK period. */
typedef struct {
    float ia_A, ib_A;           /* as read, offsets not removed [A] */
    float vdc_V;                /* [V] */
} app_adc_t;

/* The operator's input: references, mode, method (app_request_op). */
typedef struct {
    ctrl_ref_t ref;             /* [rad/s mech, N m, V] */
    ctrl_mode_t mode;
    ctrl_method_t method;
} app_op_t;

typedef struct {
    app_cfg_t cfg;
    app_state_t state;
    app_fault_t fault;
    app_snapshot_t snapshot;       /* of the latched fault */
    ctrl_t ctrl;
    ctrl_out_t out;
    uint32_t ticks;                /* ISR calls since app_init */
    uint32_t i2t_ticks;            /* app_background: ticks at its last call */
    float i2t_used_A2s;            /* I^2t budget spent [A^2 s] */
    bool i2t_limited;              /* the current limit is i2t_rated_A */
    float offset_ia_A, offset_ib_A;  /* subtracted from ia, ib: 0 until a calibration is accepted [A] */
    bool aligned;                  /* encoder offset set by an alignment since power-up */
    bool pwm_on;                   /* outputs enabled by the app */
    /* the pieces, each with its own state */
    protect_t prot;                /* checks, encoder and ISR-time tracking */
    calib_t cal;                   /* CALIBRATE */
    align_t aln;                   /* ALIGN */
    rsid_seq_t rsid;               /* IDENTIFY_R, and the handover in RUN */
    comm_t *comm;                  /* COMMISSION: the state app_attach_comm() gave (its stage stays at a
                                    * refusal's); NULL: no commissioning */
    bool commissioning;            /* this start is a commissioning (CALIBRATE leads to COMMISSION) */
    bool comm_valid;               /* comm.res holds a completed commissioning's results */
    uint16_t warnings;             /* APP_WARN_* since the last start */
    uint16_t fault_present;        /* app_fault_t: the check the last fault reset found still failing
                                    * (its cause present, or FLASH_CRC); APP_FAULT_NONE when it cleared */
    float vdc_V;                   /* this period's bus reading [V] (every state) */
    app_step_t rsid_refusal;       /* APP_WARN_STEP1_REFUSED: the fault step 1 would have latched */
    uint16_t level;                /* the build level of the last start (level.h) */
    level_rot_t rot;               /* ENC_CHECK: level 3's rotation and its figures (rot.out) */
    app_adc_t adc;                 /* ADC_CHECK: level 2's report */
    /* Requests: one word each, so that setting (background) and clearing
     * (ISR) are single stores and cannot lose one another. */
    volatile uint16_t req_start;
    volatile uint16_t req_commission;
    volatile uint16_t req_stop;
    volatile uint16_t req_fault_reset;
    /* The operator's request: written whole by the background between
     * req_op = 0 and req_op = 1, taken by the ISR at its next start. */
    volatile app_op_t op_req;
    volatile uint16_t req_op;
    volatile uint16_t req_level;   /* the build level the next start takes */
    volatile uint16_t req_warning; /* APP_WARN_* bits the background raises (app_request_warning) */
    uint16_t req_reconfigure;          /* APP_RECONF_* | APP_RECONF_ASKED: a new configuration asked for
                                        * (the background's own: app_reconfigure_now takes it) */
    app_op_t op_taken;             /* the last request the ISR took */
} app_t;

/* Start-up: the board's configuration (firmware/params/board_cfg.h) into *cfg. */
void app_cfg_default(app_cfg_t *cfg);

/* Start-up or host: the parameter set *p (drive_params.h; its values left
 * to derive derived) into *cfg: the controller's configuration
 * (drive_params_to_ctrl_cfg), the protection limits, step 1's timing and
 * speeds, the commissioning's bounds, the alignment's voltage and the
 * open-phase thresholds; the rest of *cfg (start-up sequence, watch) is
 * left. */
void drive_params_to_app_cfg(const drive_params_t *p, app_cfg_t *cfg);

/* Start-up or background (the drive stopped: app_request_reconfigure): the board's whole
 * configuration from the parameter set *p: drive_params_to_app_cfg(), then the start-up
 * sequence's, the watch checks' and the levels' settings of firmware/params/board_cfg.h
 * (app_cfg_default() is this for drive_params_board()'s set). */
void app_cfg_from_params(app_cfg_t *cfg, const drive_params_t *p);

/* Start-up: copy *cfg (or use it in place when cfg is &app->cfg), init the
 * controller, PWM off, state INIT. */
void app_init(app_t *app, const app_cfg_t *cfg);

/* Start-up, after app_init: the commissioning's state, an object of its
 * own (on the F28335 in M0, main.c: .ebss has no room for it), initialised
 * here from app->cfg. Without it app_request_commission() is ignored. */
void app_attach_comm(app_t *app, comm_t *comm);

/* ISR context, once per period: hal_sample_read -> protection -> requests
 * -> state step (ctrl_step in RUN) -> hal_pwm_write / enable / disable ->
 * run-time check -> hal_isr_ack. */
void app_isr(app_t *app);

/* Background loop: services the watchdog; the I^2t budget from the
 * monitor's current (app_cfg_t i2t_*), limiting the targets' current to
 * the continuous one while it is spent (ctrl_set_i_limit). */
void app_background(app_t *app);

/* Background: INIT or IDLE -> the start sequence at the next ISR. */
void app_request_start(app_t *app);

/* Background: INIT or IDLE -> CALIBRATE (if on) -> COMMISSION at the next
 * ISR; the results in app->comm->res once app->comm_valid. Ignored without
 * app_attach_comm(). */
void app_request_commission(app_t *app);

/* The commissioning's outcome now (comm_outcome_t; COMM_NONE without
 * app_attach_comm()). Any context. */
uint16_t app_comm_result(const app_t *app);

/* The controller, read-only, for ctrl.h's readers (ctrl_status,
 * ctrl_method, ctrl_mode, ctrl_ref, ...). Any context; inline. */
static inline const ctrl_t *app_ctrl(const app_t *app)
{
    return &app->ctrl;
}

/* What the link and the logs read of the controller: the monitor of its
 * last period (ctrl.h) and the estimation's model and status (est.h).
 * Any context; inline, as cheap as the field itself. */
static inline const ctrl_mon_t *app_monitor(const app_t *app)
{
    return ctrl_monitor(&app->ctrl);
}

static inline const est_out_t *app_estimate(const app_t *app)
{
    return est_output(ctrl_est(&app->ctrl));
}

/* The torque path that ran in the last period: the proposed method only
 * while the estimation's model drove it, else the conventional one. Any
 * context; inline. */
static inline ctrl_method_t app_method_ran(const app_t *app)
{
    return ((ctrl_method(&app->ctrl) == CTRL_METHOD_PROPOSED) && (ctrl_monitor(&app->ctrl)->model_from_observer != 0u))
               ? CTRL_METHOD_PROPOSED
               : CTRL_METHOD_CONVENTIONAL;
}

/* Background: the operator's references, mode and method; the ISR takes
 * them together at the start of its next call (ctrl_set_ref, _mode,
 * _method there: the background never writes the controller). */
void app_request_op(app_t *app, const app_op_t *op);

/* Background: the build level (LEVEL_MIN .. LEVEL_MAX, level.h) the next
 * start runs; another value is ignored. */
void app_request_level(app_t *app, uint16_t level);

/* Background: raise the warnings `bits` (APP_WARN_*) at the next ISR, as the ISR's own
 * (cleared at the next start). */
void app_request_warning(app_t *app, uint16_t bits);

/* app_request_reconfigure's flags */
#define APP_RECONF_ASKED      0x0001u /* set by every request */
#define APP_RECONF_ENC_OFFSET 0x0002u /* the configuration's encoder offset replaces the one in use (aligned
                                       * or commissioned included) */

/* Background, the drive stopped (INIT, IDLE, FAULT): a new configuration (the drive's parameters
 * changed: link_params.h), taken by app_reconfigure_now from app->cfg, which the caller writes
 * where the ISR cannot read it half-written: with the ISR held off just before
 * app_reconfigure_now (main.c), or between periods (the SIL). flags: APP_RECONF_*; requests
 * before it is taken add up. */
void app_request_reconfigure(app_t *app, uint16_t flags);

/* The drive stopped: INIT, IDLE or FAULT (PWM off, no start step running). Background, or with the
 * ISR held off to act on it. */
bool app_stopped(const app_t *app);

/* Background: a new configuration asked for and the drive stopped (INIT, IDLE, FAULT). */
bool app_reconfigure_due(const app_t *app);

/* Background, with the control ISR held off (hal_isr_pause; the SIL's background runs between
 * periods): when due, the controller and the start-up steps from app->cfg again, as app_init (flash code, divisions, a deep stack: start-up work, not the ISR's).
 * Kept: the operator's request, the alignment, the commissioning's results, the calibration, a
 * latched fault and the encoder's offset; the encoder's and protection's tracking start again
 * (the periods held off were not tracked: the next count seeds them). */
void app_reconfigure_now(app_t *app);

/* Background: CALIBRATE, ALIGN, IDENTIFY_R, RUN, COMMISSION and the levels' states -> IDLE at the next ISR, PWM off. */
void app_request_stop(app_t *app);

/* Start-up, after app_init and before the ISR is attached: a fault found
 * before the drive could run (WATCHDOG_RESET: the last reset was the
 * watchdog's; FLASH_CRC: the image fails its CRC) latched as any other:
 * FAULT, PWM off, value and limit in the snapshot (state INIT, samples 0),
 * until the operator clears it (app_fault_reset). FLASH_CRC is never
 * cleared: the image must be programmed again. */
void app_latch_startup_fault(app_t *app, app_fault_t fault, float value, float limit);

/* Background, acts only in FAULT: clears a latched hardware trip; FAULT ->
 * IDLE at the next ISR if no protection check fails on that ISR's samples
 * (else the failing check's fault in fault_present, the FAULT kept).
 * Outside FAULT it does nothing (no hal_trip_clear under a running drive,
 * no request kept for a later fault); the ISR also drops a reset request
 * it finds outside FAULT. */
void app_fault_reset(app_t *app);

#endif /* APP_H */
