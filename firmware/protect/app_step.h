/*
 * app_step.h - what the application's pieces share: the drive states, the
 * fault codes, and the outcome of one step of a start-up state machine
 * (calib, align, rsid_seq) or of the protection checks (protect).
 *
 * Every start-up step is a small state machine with its own state struct,
 * a _start() and a _step() called once per ISR period that returns
 * running, done, or a fault with the quantity and the limit it crossed;
 * the start sequence in app.c chains them (app.h).
 */
#ifndef APP_STEP_H
#define APP_STEP_H

#include <stdint.h>

/* Values are logged (SIL CSV, telemetry). */
typedef enum {
    APP_STATE_INIT = 0,
    APP_STATE_IDLE = 1,
    APP_STATE_CALIBRATE = 2,
    APP_STATE_ALIGN = 3,
    APP_STATE_IDENTIFY_R = 4,
    APP_STATE_RUN = 5,
    APP_STATE_FAULT = 6,
    APP_STATE_PWM_CHECK = 7,    /* level 1: fixed duties, a pattern for the scope */
    APP_STATE_ADC_CHECK = 8,    /* level 2: PWM off, the ADC's readings and offsets reported */
    APP_STATE_ENC_CHECK = 9,    /* level 3: open-loop rotation, the encoder and wiring checked */
    APP_STATE_COMMISSION = 10   /* measuring the motor (commission.h) */
} app_state_t;
#define APP_STATE_LAST APP_STATE_COMMISSION   /* the highest state's value */

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
    APP_FAULT_CONFIG = 11,           /* a block the start needs refused by ctrl_init, or the ratings or ADC range by drive_params_derive */
    APP_FAULT_RSID_TOO_FEW = 12,     /* IDENTIFY_R: a window shorter than rs_ident's n_min */
    APP_FAULT_RSID_NOT_STEADY = 13,  /* R^ too uncertain: noise or a transient (snapshot: se of R^, its limit) */
    APP_FAULT_RSID_DEGENERATE = 14,  /* the two operating points too alike for (41) */
    APP_FAULT_RSID_NON_FINITE = 15,  /* NaN/Inf in the windows or the result */
    APP_FAULT_RSID_OUT_OF_BAND = 16, /* R^ outside [R_min, R_max] (snapshot: R^, the bound crossed) */
    APP_FAULT_OPEN_PHASE = 17,       /* a phase carries no current under voltage (protect.h) */
    APP_FAULT_CURRENT_SENSOR = 18,   /* a current reading frozen while the rotor turns (protect.h) */
    APP_FAULT_ENCODER_LOST = 19,     /* the count stopped while moving, or no count at the torque limit (protect.h) */
    APP_FAULT_WATCHDOG_RESET = 20,   /* start-up: the last reset was the watchdog's (app_latch_startup_fault) */
    APP_FAULT_FLASH_CRC = 21,        /* start-up: the program image fails its linker CRC (flash_crc.h); no reset clears it */
    APP_FAULT_ENCODER_DIRECTION = 22, /* level 3: the count ran against the commanded rotation (enc_check.h) */
    APP_FAULT_POLE_PAIRS = 23,       /* level 3: the counts per commanded turn give other pole pairs (enc_check.h) */
    APP_FAULT_PHASE_ORDER = 24,      /* level 3: the current vector turned against the commanded one (enc_check.h) */
    APP_FAULT_RSID_D_AXIS = 25,      /* R^ hangs on the d-axis term (field weakening) (snapshot: that uncertainty of R^, the limit) */
    /* commissioning (commission.h; the stage in comm_t.stage): */
    APP_FAULT_COMM_TIMEOUT = 26,     /* a stage outlasted its timeout (value: its time [s], limit: the timeout) */
    APP_FAULT_COMM_NO_ROTATION = 27, /* the swept vector moved the count by less than half an electrical turn at the most pole pairs */
    APP_FAULT_COMM_IMPLAUSIBLE = 28, /* a stage's measurement or the voltage it needed outside its plausible range */
    APP_FAULT_BUS_CHARGED = 29,      /* levels 1-2: the bus above their extra-low limit (level.h; value: the bus, limit: it) */
    APP_FAULT_RSID_INVERTER = 30     /* R^ could hang on what the inverter's compensation leaves (snapshot: that
                                      * uncertainty of R^, the limit) */
} app_fault_t;
#define APP_FAULT_LAST APP_FAULT_RSID_INVERTER   /* the highest fault's value */

typedef enum {
    APP_STEP_RUNNING = 0,       /* call again next period */
    APP_STEP_DONE = 1,          /* finished in this period: the sequence moves on */
    APP_STEP_FAULT = 2          /* refused: fault, value and limit say why */
} app_step_status_t;

typedef struct {
    app_step_status_t status;
    app_fault_t fault;          /* APP_FAULT_NONE unless status is APP_STEP_FAULT */
    float value;                /* the quantity that tripped, in its unit (A, V, rad/s, counts, cycles, Ohm) */
    float limit;                /* the threshold it crossed (0 where none applies) */
} app_step_t;

/* Outcomes, for the steps' returns. */
static inline app_step_t app_step_running(void)
{
    const app_step_t r = { APP_STEP_RUNNING, APP_FAULT_NONE, 0.0f, 0.0f };
    return r;
}

static inline app_step_t app_step_done(void)
{
    const app_step_t r = { APP_STEP_DONE, APP_FAULT_NONE, 0.0f, 0.0f };
    return r;
}

static inline app_step_t app_step_fault(app_fault_t fault, float value, float limit)
{
    const app_step_t r = { APP_STEP_FAULT, fault, value, limit };
    return r;
}

/* Encoder counts per line: x4 quadrature decoding (eQEP, hal_sim). */
#define APP_ENC_COUNTS_PER_LINE 4u

/* Whole periods of Ts_s in t_s, rounded; 0 for a non-positive time, at
 * most 1e9 (28 h at 10 kHz: the float-to-integer cast stays defined).
 * Start-up, or ISR in commissioning (from flash). */
uint32_t app_periods_of(float t_s, float Ts_s);

#endif /* APP_STEP_H */
