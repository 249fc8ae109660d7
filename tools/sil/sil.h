/*
 * sil.h - software-in-the-loop run of the firmware application
 * (firmware/app/app.h) on the simulated board (hal_sim.h) for one scenario,
 * without a process: drive_sil and the C tests both call sil_run().
 * Link order: firmware sim control.
 *
 * One row per logged period k (every run.log_every periods, k = 0 first):
 * true plant values at the sample instant t_k, the controller's monitor
 * after its ISR at t_k, and the applied voltage averaged over
 * [t_k, t_k + Ts]. Columns without a value in the mode are NaN
 * (tools/sil/CSV_COLUMNS.md describes every column).
 */
#ifndef SIL_H
#define SIL_H

#include <signal.h>
#include <stdint.h>
#include <stdio.h>

#include "app.h"
#include "csv_num.h"
#include "scenario.h"

typedef struct {
    double t_s;
    double state, fault, flags;             /* app_state_t, app_fault_t, ctrl_out_t.flags */
    double speed_ref_rpm, speed_rpm, speed_est_rpm;
    double te_ref_Nm, te_Nm, te_est_Nm;
    double psi_ref_Wb, psi_Wb, psi_est_Wb;
    double id_A, iq_A;                      /* true, at t_k */
    double ud_V, uq_V;                      /* true applied, mean over the period */
    double ud_cmd_V, uq_cmd_V;              /* commanded for the next period (monitor) */
    double load_Nm;
    double R_est_ohm, L_est_H, psif_est_Wb, fd_est, fq_est;
    double est;                             /* est_phase_t: 0 observer off, 1 step 1, 2 step 2 */
    double R_ohm;                           /* true stator resistance at t_k (warms with [plant] R_ohm's profile) */
    double est_hold;                        /* EST_HOLD_* bits: why the estimates are held (0: learning) */
    double pwm;                             /* 1: gates on during [t_k, t_k + Ts] */
    double inj;                             /* hal_sim_fault_bit_t of the injected faults active ([faults]) */
    double fault_value, fault_limit;        /* the fault snapshot's quantity and limit; 0 unless in FAULT */
    double inv_err_est_V;                   /* inverter voltage error the controller identified (est_output()->inv_err_V) */
    double psif_model_Wb;                   /* = psif_est_Wb (older name) */
    double id_meas_A, iq_meas_A;            /* the controller's measured dq currents this period (ctrl_mon_t.id_A, iq_A) */
    double ia_adc_A, ib_adc_A, vdc_adc_V;   /* level 2's report (app_t.adc): the last ADC_CHECK period's readings (offsets in), 0 before one */
    double ia_offset_A, ib_offset_A;        /* the current offsets the app subtracts (0 until calibrated) */
    double psif_obs_Wb;                     /* the observer's internal psi^ (est_psi_f_obs_Wb) */
    double est_src;                         /* EST_SRC_*: 0 the told model, 1 the observer's, 2 held estimates */
} sil_row_t;

typedef struct {
    uint32_t periods;          /* simulated */
    uint32_t rows;             /* passed to the callback */
    int final_state;           /* app_state_t at the end */
    int final_fault;           /* app_fault_t at the end */
    unsigned warnings;         /* app.h APP_WARN_* raised during the run (a later start clears the app's, not these) */
    int rsid_refusal;          /* APP_WARN_STEP1_REFUSED: the RSID_* fault step 1 would have latched */
    double max_abs_i_A;        /* largest true phase current seen at a sample */
    double max_abs_speed_rpm;  /* largest true |speed| at a sample, mechanical [r/min] */
    double t_run_s;            /* first period that ended in RUN (its t_k); NaN if none */
    double enc_offset_el_rad;  /* the controller's encoder offset at the end: told or found by alignment, [0, 2 pi) */
    double i_offset_a_A, i_offset_b_A;   /* current offsets the app subtracts at the end (0 unless calibrated) */
    /* faults ([faults] injection and the app's protection) */
    double t_inject_s;         /* first period with an injected fault active (its t_k); NaN if none */
    double t_fault_s;          /* the ISR call that latched the first fault (its t_k); NaN if none */
    int fault_state;           /* app_state_t that first fault was latched in */
    double fault_value, fault_limit;     /* its snapshot: the quantity and limit ... */
    double fault_ia_A, fault_ib_A, fault_vdc_V;   /* ... and the raw samples of that period */
    uint32_t fault_enc_count;
    uint32_t gates_on_in_fault;          /* periods with the gates on while the app was in FAULT (latching call included): 0 */
    uint32_t fault_exits;                /* times the app left FAULT (no reset is requested in SIL: 0) */
    uint32_t pwm_periods;      /* periods with the gates on (0: the motor was never energised) */
    int level;                 /* the build level run ([run] level) */
    /* level 3's check at the end (enc_check_out_t; zeros until a check ends) */
    double enc_counts;         /* the count's travel over the check [counts] */
    double enc_angle_el_rad;   /* the commanded angle's travel [rad el] */
    double enc_pole_pairs;     /* the pole pairs the counts give */
    double enc_i_pos_A, enc_i_neg_A;   /* the current's positive and negative sequence [A] */
    /* commissioning (sil_ctl_t.commission) */
    int comm_valid;            /* 1: the commissioning completed, the values below are its results */
    int comm_stage;            /* comm_stage_t reached (a refusal's stage) */
    double comm_R_ohm, comm_L_H, comm_psif_Wb, comm_J_kgm2, comm_B_Nms, comm_enc_offset_el_rad;
    double comm_speed_kp_Nms_rad, comm_speed_ki_Nm_rad, comm_u_err_V;
    double comm_inv_dv_V, comm_deadtime_s, comm_device_drop_V, comm_untold_deadtime_s; /* the inverter's error */
    uint32_t comm_pole_pairs;
} sil_result_t;

/* Called for every logged row; a nonzero return stops the run. */
typedef int (*sil_row_fn)(const sil_row_t *row, void *user);

/* What a run's driver adds (drive_sil --link, tools/sil/link_sil.h); any member may be NULL. */
typedef struct {
    void (*start)(void *user, app_t *app);        /* after app_init, before the first period */
    void (*isr_end)(void *user);                  /* after every app_isr call, in its context */
    void (*refs)(void *user, app_op_t *op);       /* the scenario's operator request about to be made: may change it */
    int (*period_end)(void *user);                /* the background after each period; nonzero ends the run */
    void *user;
} sil_hooks_t;

/* Called every sil_ctl_t.tick_periods periods with the simulated time reached [s]. */
typedef void (*sil_tick_fn)(double t_s, void *user);

/* Optional controls of a run (sil_run_ctl); all NULL/0: none. */
typedef struct {
    const volatile sig_atomic_t *stop;   /* checked after every period: nonzero ends the run there */
    sil_tick_fn on_tick;                 /* progress, or NULL */
    void *tick_user;
    uint32_t tick_periods;               /* periods between on_tick calls (> 0 with on_tick) */
    const sil_hooks_t *hooks;            /* a driver's additions (drive_sil --link), or NULL; with
                                          * period_end, run.duration_s = 0 runs until it ends the run */
    int commission;                      /* 1: commission the motor instead of the scenario's run (sil_run_ctl) */
} sil_ctl_t;

/* sil_run_ctl()'s return when *ctl->stop ended the run early. */
#define SIL_STOPPED (-1)

/* Run scenario *sc (after scenario_finish()) from power-on: configure the board, init the app,
 * start it, simulate run.duration_s. on_row may be NULL. Returns 0, or the callback's nonzero value. */
int sil_run(const scenario_t *sc, sil_row_fn on_row, void *user, sil_result_t *res);

/* sil_run() with controls (ctl may be NULL): also returns SIL_STOPPED when *ctl->stop
 * became nonzero (res then covers the periods run, every row of them delivered).
 * With ctl->commission the app is asked to commission the motor (firmware/commission/commission.h)
 * instead of starting: [reference] and [load] play no part (no load), run.duration_s
 * neither; the run ends in the period the app leaves COMMISSION (IDLE: res->comm_valid,
 * or FAULT), or after the stages' timeouts and a second. */
int sil_run_ctl(const scenario_t *sc, sil_row_fn on_row, void *user, const sil_ctl_t *ctl, sil_result_t *res);

/* The drive's parameter set a run of finished scenario *sc configures the app from: the
 * scenario's values on the board's (scenario_params), the simulated board's period and the
 * model's voltage bound. */
void sil_drive_params(const scenario_t *sc, drive_params_t *p);

/* The app's configuration of a run from parameter set *p (sil_drive_params, or one the link
 * changed): the board's start-up sequence, drive_params_to_app_cfg(), then the scenario's keys
 * whose target is the app's configuration. */
void sil_app_cfg(const scenario_t *sc, const drive_params_t *p, app_cfg_t *ac);

/* The drive's parameter set (its derived values derived) and the app's
 * configuration a run of *sc (finished) starts with: drive_sil
 * --board-config writes them as the board image's (board_config.h). */
void sil_drive_config(const scenario_t *sc, drive_params_t *p, app_cfg_t *ac);

/* Longest CSV line of a row, with its newline: every column is one of sil_row_t's doubles,
 * at most CSV_NUM_MAX characters with its separator. */
#define SIL_CSV_LINE_MAX (sizeof(sil_row_t) / sizeof(double) * CSV_NUM_MAX)

/* The CSV header line (with newline) to f. */
void sil_csv_header(FILE *f);

/* One row as a CSV line (with newline, no NUL) into line[SIL_CSV_LINE_MAX]; returns its length.
 * Numbers as "%.9g", NaN as "nan" (csv_num.h). */
size_t sil_csv_format(char *line, const sil_row_t *row);

/* One row as a CSV line to f (sil_csv_format). */
void sil_csv_row(FILE *f, const sil_row_t *row);

/* What a run was asked for: the scenario file, the --set overrides on top
 * of it in the order given, and whether it measured the motor (--commission). */
typedef struct {
    const char *scenario_path;
    const char *const *sets;
    int n_sets;
    bool commission;
} sil_origin_t;

/* The resolved truth and controller values of the last sil_run(), as one
 * JSON object (drive_sil writes it beside the CSV as OUT.resolved.json):
 * what was asked for (scenario, overrides, commission), the plant's
 * parameters (R at t = 0) from the scenario, and the values the controller
 * was configured with (the app's configuration after the parameter set's
 * mapping); "warnings": the scenario's, then run_warnings (the run's by
 * name, summary_warning_text; "" without). Keys as the scenario's. */
void sil_write_resolved(FILE *f, const scenario_t *sc, const sil_origin_t *origin, const char *run_warnings);

#endif /* SIL_H */
