/*
 * app.h - the ISR glue and the drive state machine.
 *
 *   INIT --start--> CALIBRATE --offsets in band--> ALIGN --settled-->
 *        IDENTIFY_R --R^ accepted--> RUN
 *   IDLE --start--> (the same sequence)
 *   CALIBRATE, ALIGN, IDENTIFY_R, RUN --stop--> IDLE
 *   INIT, IDLE, CALIBRATE, ALIGN, IDENTIFY_R, RUN --protection--> FAULT
 *   IDENTIFY_R --R^ refused--> FAULT (the reason in the code)
 *   FAULT --fault reset, cause gone--> IDLE
 *
 * INIT is the power-on state (nothing measured yet, bus may still be
 * charging); IDLE the stopped state after a run or a fault. A start runs
 * the sequence; a step that is off (cfg.calibrate, cfg.align) or already
 * done (alignment, once per power-up) is skipped within the same ISR call,
 * so with both off the start request's ISR call is already a RUN period.
 *   CALIBRATE  PWM off: wait cal_settle_s, average cal_samples periods of
 *              ia, ib; these means are the offsets subtracted from then on.
 *              An offset beyond offset_max_A faults (CURRENT_OFFSET).
 *              Runs at every start: sensor offsets drift with temperature.
 *   ALIGN      PWM on: stationary voltage vectors through svpwm_duty, in
 *              two steps, so that no start position is a dead point:
 *                1. the vector at align_prepos_el_rad (90 deg: u_beta, the
 *                   b-c line), ramped from 0 to align_u_V over
 *                   align_ramp_s, held align_prepos_s;
 *                2. turned onto phase a over align_ramp_s (cross-fade:
 *                   (1 - f) x the pre-position vector + f x align_u_V on
 *                   alpha, f = 0..1), held align_settle_s;
 *              the rotor's d axis is then on phase a and encoder_align()
 *              makes that count read 0 rad.
 *              Dead point: the vector at angle phi drives the current
 *              there, and a rotor whose d axis is at theta gets
 *              Te = 1.5 p psi_f I sin(phi - theta): zero at theta = phi
 *              (stable) and at theta = phi + pi (unstable, but a rotor
 *              resting exactly there stays: with the phase-a vector alone
 *              the offset came out pi off). After step 1 the rotor is at
 *              +90 deg, or still at -90 deg, step 1's own dead point. The
 *              turn's vector angle psi goes from 90 to 0 deg: a rotor at
 *              -90 deg gets sin(psi + 90 deg) = cos(psi) > 0 from the turn's
 *              first period, one at +90 deg follows the vector, and the
 *              phase-a vector gives either one full torque (sin(+/-90 deg)),
 *              so no start angle leaves both steps without torque. Any phi
 *              with sin(phi) != 0 would do; 90 deg gives the most torque.
 *              Open-loop voltage, not a current loop: only the direction
 *              matters, and with u_beta = 0 in the final hold it is exact
 *              whatever the current sensors' offset and gain and the dead
 *              time (its error vector is collinear with u_alpha); the
 *              magnitude follows R, which the overcurrent check bounds.
 *              Once per power-up (the incremental count stays valid while
 *              powered), again after an ENCODER fault.
 *   IDENTIFY_R step 1 of the proposed method (paper sec. V-B): ctrl_step
 *              every period (conventional control, observer running) and
 *              a timed sequence: rsid_settle_1_s, window 1 (rsid_window_s),
 *              rsid_settle_2_s, window 2, then ctrl_rsid_finish(): R^ into
 *              the observer, step 2 (L^, psi_f^) starts, RUN. The two
 *              operating points (cfg.rsid_mode):
 *                WINDOWS  set from outside (the load a dyno or the SIL
 *                         scenario applies, the speed reference): the
 *                         app only times the windows;
 *                SPEEDS   the app commands rsid_speed_1/2 (speed mode;
 *                         ramped at rsid_accel) at the load present,
 *                         which must not be ~0 (equal loads need
 *                         different speeds and a load: else DEGENERATE);
 *                         in RUN it then ramps from rsid_speed_2 to the
 *                         outside reference at rsid_accel (the handover:
 *                         a step there asked the torque limit against the
 *                         load) and follows the outside reference once
 *                         it is reached;
 *                TRUSTED  no step 1: step 2 with the controller's R, for
 *                         an R known at this winding temperature;
 *                OFF      no step 1, no step 2 (the proposed method then
 *                         controls as the conventional one, ctrl.h).
 *              The speed the app commands goes into its own ctrl_step
 *              only: ctrl.ref keeps the outside reference throughout.
 *              A refused R^ is a fault naming the reason (RSID_*). Runs
 *              at every start: R follows the winding temperature. A
 *              controller whose proposed-method settings ctrl_init
 *              refused cannot identify: a start then faults CONFIG.
 *   RUN        ctrl_step every period.
 *
 * Background requests (start, stop, fault reset) only set a flag; the ISR
 * carries them out at the start of its next call, so the controller state
 * is only ever touched from the ISR. A fault turns the PWM off in the same
 * ISR call that detected it and keeps a snapshot (app_snapshot_t).
 *
 * Protection, in every state but FAULT (first match is the reason):
 *   HW_TRIP           hal_trip_active() (trip-zone input latched)
 *   NONFINITE_SAMPLE  ia, ib or vdc not finite
 *   OVERCURRENT       |ia|, |ib| or |ic| (offset-corrected) > i_max_A
 *   OVERVOLTAGE       vdc > vdc_max_V
 *   UNDERVOLTAGE      vdc < vdc_min_V, armed once a start sequence has
 *                     passed calibration (done or skipped) and kept armed:
 *                     the bus may charge while in INIT; the motor is never
 *                     energised on a low bus; a bus lost later is a fault
 *   ENCODER           |count change| in one period > the change at
 *                     speed_max_rad_s times APP_ENC_JUMP_MARGIN, plus one
 *                     count: a jump no shaft can make (lost counts, noise)
 *   OVERSPEED         |speed estimate (encoder PLL)| > speed_max_rad_s
 *   OVERRUN           entry-to-entry interval > 1.5 periods (a period was
 *                     missed), or app_isr's run time > isr_budget_cycles
 *                     (checked at its exit, before the ack), hal_cycles()
 * and from the state's own step: NONFINITE_OUTPUT (controller output, or
 * the alignment's SVPWM refusing its input), CURRENT_OFFSET (CALIBRATE).
 */
#ifndef APP_H
#define APP_H

#include <stdbool.h>
#include <stdint.h>

#include "ctrl.h"
#include "hal.h"

/* Values are logged (SIL CSV, telemetry). */
typedef enum {
    APP_STATE_INIT = 0,
    APP_STATE_IDLE = 1,
    APP_STATE_CALIBRATE = 2,
    APP_STATE_ALIGN = 3,
    APP_STATE_IDENTIFY_R = 4,
    APP_STATE_RUN = 5,
    APP_STATE_FAULT = 6
} app_state_t;

typedef enum {
    APP_FAULT_NONE = 0,
    APP_FAULT_HW_TRIP = 1,
    APP_FAULT_OVERCURRENT = 2,
    APP_FAULT_NONFINITE_OUTPUT = 3,
    APP_FAULT_NONFINITE_SAMPLE = 4,
    APP_FAULT_OVERVOLTAGE = 5,
    APP_FAULT_UNDERVOLTAGE = 6,
    APP_FAULT_OVERSPEED = 7,
    APP_FAULT_ENCODER = 8,
    APP_FAULT_OVERRUN = 9,
    APP_FAULT_CURRENT_OFFSET = 10,
    APP_FAULT_CONFIG = 11,           /* identification asked for, ctrl_init refused the observer's settings */
    APP_FAULT_RSID_TOO_FEW = 12,     /* IDENTIFY_R: a window shorter than rs_ident's n_min */
    APP_FAULT_RSID_NOT_STEADY = 13,  /* R^ too uncertain: noise or a transient (snapshot: se of R^, its limit) */
    APP_FAULT_RSID_DEGENERATE = 14,  /* the two operating points too alike for (41) */
    APP_FAULT_RSID_NON_FINITE = 15,  /* NaN/Inf in the windows or the result */
    APP_FAULT_RSID_OUT_OF_BAND = 16  /* R^ outside [R_min, R_max] (snapshot: R^, the bound crossed) */
} app_fault_t;

/* Step 1 of the proposed method in IDENTIFY_R (see above). */
typedef enum {
    APP_RSID_OFF = 0,
    APP_RSID_WINDOWS = 1,
    APP_RSID_SPEEDS = 2,
    APP_RSID_TRUSTED = 3
} app_rsid_mode_t;

/* Count change per period beyond the overspeed limit's that still counts
 * as motion: the PLL-based overspeed check trips long before a real shaft
 * gets there (12 N m / J adds 9 r/min per period). */
#define APP_ENC_JUMP_MARGIN 1.5f

typedef struct {
    ctrl_cfg_t ctrl;
    /* protection */
    float i_max_A;              /* software overcurrent on |ia|, |ib|, |ic| [A] */
    float vdc_max_V;            /* overvoltage trip [V] */
    float vdc_min_V;            /* undervoltage trip, armed after calibration [V] */
    float speed_max_rad_s;      /* overspeed trip, mechanical [rad/s]; also sets the encoder jump limit */
    uint32_t isr_period_cycles; /* control period in hal_cycles() counts [cycles] */
    uint32_t isr_budget_cycles; /* longest allowed app_isr run [cycles] */
    /* start-up sequence */
    bool calibrate;             /* measure the current offsets at every start */
    float cal_settle_s;         /* PWM off this long before averaging [s] */
    uint32_t cal_samples;       /* periods averaged [-] */
    float offset_max_A;         /* accepted |offset| of ia and ib [A] */
    bool align;                 /* encoder offset unknown: align the rotor once per power-up */
    float align_u_V;            /* magnitude of the alignment's voltage vectors [V] */
    float align_prepos_el_rad;  /* step 1's vector, from phase a: sin != 0 (see ALIGN) [rad el] */
    float align_ramp_s;         /* ramp from 0 at the pre-position, and the turn onto phase a [s] */
    float align_prepos_s;       /* hold at the pre-position after its ramp [s] */
    float align_settle_s;       /* hold on phase a after the turn [s] */
    app_rsid_mode_t rsid_mode;  /* step 1 of the proposed method (IDENTIFY_R) */
    float rsid_settle_1_s;      /* IDENTIFY_R entry to window 1 [s] */
    float rsid_window_s;        /* each averaging window [s] */
    float rsid_settle_2_s;      /* window 1's end to window 2: the operating point changes in it [s] */
    float rsid_speed_1_rad_s;   /* SPEEDS: mechanical speed of point 1 [rad/s] */
    float rsid_speed_2_rad_s;   /*   and of point 2 [rad/s] */
    float rsid_accel_rad_s2;    /* SPEEDS: ramp rate of the commanded speed, handover included [rad/s^2] */
} app_cfg_t;

/* What was known in the period a fault was detected. */
typedef struct {
    hal_sample_t sample;        /* raw samples of that period */
    app_state_t state;          /* state the fault was detected in */
    float value;                /* the quantity that tripped, in its unit (A, V, rad/s, counts, cycles); 0 for a trip or NaN */
    float limit;                /* the threshold it crossed */
} app_snapshot_t;

typedef struct {
    app_cfg_t cfg;
    app_state_t state;
    app_fault_t fault;
    app_snapshot_t snapshot;
    ctrl_t ctrl;
    ctrl_out_t out;
    uint32_t ticks;                /* ISR calls since app_init */
    uint32_t state_ticks;          /* ISR calls in CALIBRATE / ALIGN / IDENTIFY_R so far */
    float offset_ia_A, offset_ib_A;  /* subtracted from ia, ib: 0 until a calibration is accepted [A] */
    float cal_sum_ia_A, cal_sum_ib_A;  /* CALIBRATE: sums so far [A] */
    bool uv_armed;                 /* undervoltage check active */
    bool aligned;                  /* encoder offset set by an alignment since power-up */
    bool pwm_on;                   /* outputs enabled by the app */
    /* encoder and ISR timing, every call */
    uint32_t enc_prev;             /* count of the previous call */
    int32_t enc_delta;             /* count change since the previous call, shortest way */
    bool seeded;                   /* enc_prev and isr_entry valid */
    uint32_t isr_entry;            /* hal_cycles() at the previous entry */
    uint32_t isr_interval_cycles;  /* entry to entry, this call */
    uint32_t isr_run_cycles;       /* entry to exit, last call */
    /* derived from cfg by app_init */
    uint32_t enc_cpr;              /* counts per revolution */
    float enc_jump_max;            /* largest plausible |enc_delta| [counts] */
    uint32_t isr_late_cycles;      /* entry-to-entry interval that means a missed period */
    uint32_t cal_settle_ticks, align_ramp_ticks, align_prepos_ticks, align_settle_ticks;
    float align_prepos_cos, align_prepos_sin;  /* of align_prepos_el_rad */
    uint32_t rsid_win1_tick, rsid_win2_tick, rsid_end_tick;  /* IDENTIFY_R: window starts, end */
    uint32_t rsid_window_ticks;
    float rsid_speed_ref_rad_s;    /* SPEEDS: the ramped reference (IDENTIFY_R, then the handover) */
    bool speed_handover;           /* RUN after SPEEDS: still ramping to the outside reference */
    float rsid_speed_step_rad_s;   /* SPEEDS: ramp step per period */
    rs_ident_result_t rsid_result; /* last step 1 (R^ etc. in ctrl.rsid_out) */
    /* Requests: one word each, so that setting (background) and clearing
     * (ISR) are single stores and cannot lose one another. */
    volatile uint16_t req_start;
    volatile uint16_t req_stop;
    volatile uint16_t req_fault_reset;
} app_t;

/* Start-up: the board's configuration (firmware/board_cfg.h) into *cfg. */
void app_cfg_default(app_cfg_t *cfg);

/* Start-up: copy *cfg, init the controller, PWM off, state INIT. */
void app_init(app_t *app, const app_cfg_t *cfg);

/* ISR context, once per period: hal_sample_read -> protection -> requests
 * -> state step (ctrl_step in RUN) -> hal_pwm_write / enable / disable ->
 * run-time check -> hal_isr_ack. */
void app_isr(app_t *app);

/* Background loop: services the watchdog. */
void app_background(app_t *app);

/* Background: INIT or IDLE -> the start sequence at the next ISR. */
void app_request_start(app_t *app);

/* Background: CALIBRATE, ALIGN, IDENTIFY_R, RUN -> IDLE at the next ISR, PWM off. */
void app_request_stop(app_t *app);

/* Background: clears a latched hardware trip; FAULT -> IDLE at the next
 * ISR if no protection check fails on that ISR's samples. */
void app_fault_reset(app_t *app);

#endif /* APP_H */
