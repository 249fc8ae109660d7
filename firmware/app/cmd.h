/*
 * cmd.h - the operator's command block on the target.
 *
 * As in TI's C2000 motor-control examples, the user drives the board from
 * Code Composer Studio's expressions window: main.c owns one `volatile
 * cmd_t`, the user edits its fields there (or a telemetry link writes
 * them), and the background loop hands it to cmd_apply(). Every field is
 * checked there; a bad value is refused, keeps the previous command and is
 * named in `error`, so nothing unchecked reaches the ISR.
 */
#ifndef CMD_H
#define CMD_H

#include <stdint.h>

#include "app.h"

typedef enum {
    CMD_OK = 0,
    CMD_ERR_METHOD,      /* method is neither conventional nor proposed */
    CMD_ERR_METHOD_CFG,  /* proposed method refused: its observer configuration failed at init */
    CMD_ERR_MODE,        /* mode is not open loop, torque or speed */
    CMD_ERR_SPEED,       /* speed reference not finite or beyond cmd_limits_t */
    CMD_ERR_TORQUE,      /* torque reference not finite or beyond cmd_limits_t */
    CMD_ERR_VOLTAGE,     /* open-loop voltage not finite or beyond cmd_limits_t */
    CMD_ERR_METHOD_NO_STEP1, /* proposed method refused: step 1 is off (BOARD_RSID_MODE 0), or refused R^
                              * at this start (APP_WARN_STEP1_REFUSED); it would run as the conventional
                              * one. Set the mode to windows, speeds or trusted; restart */
    CMD_ERR_LEVEL,       /* level is not 0 (keep) or 1 .. 5 (level.h) */
    CMD_ERR_FAULTED,     /* start or commission refused: a fault is latched (reset it first); nothing done */
    CMD_ERR_NOT_STOPPED, /* commission refused: the drive is not stopped (INIT or IDLE); nothing done */
    CMD_ERR_RANGE        /* a link setting (host_timeout_s, a parameter) not finite or outside its limits */
} cmd_error_t;
#define CMD_ERR_LAST CMD_ERR_RANGE   /* the highest code */

/* The commissioning's request and report (cmd_comm_apply): a separate
 * object from cmd_t, which cmd_apply() copies whole on the stack. The
 * values are not written to flash: the user copies them into the board's
 * configuration. */
typedef struct {
    uint16_t start;        /* write 1 while stopped (cmd_t.run 0): measure the motor (commission.h);
                            * cmd_comm_apply() sets it back to 0. The rest is read only: */
    uint16_t state;        /* 0 none, 1 running (stage says which), 2 done (values valid), 3 refused (fault says why) */
    uint16_t stage;        /* comm_stage_t reached (the refusing one) */
    uint16_t fault;        /* app_fault_t of a refusal (COMM_*, or a protection's) */
    float fault_value;     /* its measured value and limit (the fault snapshot) */
    float fault_limit;
    float R_Ohm, L_H, psi_f_Wb;
    uint16_t pole_pairs;
    float J_kgm2, B_Nms;
    float enc_offset_el_rad;
    float speed_kp_Nms_rad, speed_ki_Nm_rad;
} cmd_comm_t;

typedef struct {
    uint16_t run;          /* 1: start (calibration, alignment, identification, run); 0: stop */
    uint16_t fault_reset;  /* write 1 to clear a latched fault (ignored when none is); cmd_apply() sets it back to 0 */
    uint16_t method;       /* ctrl_method_t: 0 conventional, 1 proposed */
    uint16_t mode;         /* ctrl_mode_t: 0 open loop, 1 torque, 2 speed */
    float speed_ref_rpm;   /* mechanical speed reference (speed mode) [r/min] */
    float te_ref_Nm;       /* torque reference (torque mode) [N m] */
    float ud_ref_V;        /* rotor-frame voltage (open-loop mode) [V] */
    float uq_ref_V;
    uint16_t error;        /* cmd_error_t of the last refused field, CMD_OK when all were taken */
    uint16_t run_taken;    /* last run value acted on: a start or stop is sent on a change only */
    uint16_t level;        /* build level the next start runs (level.h): 1 PWM, 2 ADC, 3 encoder check,
                            * 4 torque control, 5 the drive; 0 keeps the app's (BOARD_LEVEL at power-on) */
    /* Reports, written by cmd_apply() from the drive (watch them; writes are overwritten). */
    uint16_t level_now;    /* the level of the last start */
    float ia_adc_A;        /* level 2: the current ADC's readings, offsets not removed [A] */
    float ib_adc_A;
    float vdc_adc_V;       /* level 2: the bus reading [V] */
    float ia_offset_A;     /* the current offsets the drive subtracts (0 until calibrated) [A] */
    float ib_offset_A;
    int32_t enc_counts;    /* level 3: the count's travel over the check (sign: against the commanded turn if < 0) */
    float pole_pairs_est;  /* level 3: the pole pairs the counts gave (whole and equal to the motor's: right) */
} cmd_t;

typedef struct {
    float speed_max_rpm;   /* |speed_ref_rpm| accepted */
    float te_max_Nm;       /* |te_ref_Nm| accepted */
    float u_max_V;         /* |ud_ref_V|, |uq_ref_V| accepted */
} cmd_limits_t;

/* Power-on command: stopped, conventional method, speed mode, references 0. Start-up. */
void cmd_init(volatile cmd_t *cmd);

/* Check the command and pass it to the drive. Background loop only. */
void cmd_apply(volatile cmd_t *cmd, const cmd_limits_t *lim, app_t *app);

/* Power-on: no request, nothing commissioned. Start-up. */
void cmd_comm_init(volatile cmd_comm_t *cc);

/* A start request passed to the app while the command block is stopped
 * (cmd->run 0; the app acts only in INIT or IDLE), then the stage,
 * outcome and values from the app into *cc. Background loop only (the ISR
 * writes comm.res before comm_valid). */
void cmd_comm_apply(volatile cmd_comm_t *cc, const volatile cmd_t *cmd, app_t *app);

#endif /* CMD_H */
