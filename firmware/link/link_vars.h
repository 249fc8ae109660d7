/*
 * link_vars.h - the one variable table of the link (link_protocol.md,
 * "Variables"): what the firmware computes and what the operator sets
 * through cmd_t, each with id (its index), name, type, unit, limits and
 * access. Where drive_sil's CSV shows the same quantity the name is the
 * CSV's. Writes go through cmd_apply() only; the table has no pointer
 * into the drive, values are fetched by id.
 */
#ifndef LINK_VARS_H
#define LINK_VARS_H

#include <stdint.h>

#include "app.h"
#include "cmd.h"
#include "link_nv.h"
#include "link_params.h"

typedef enum { LINK_T_U16 = 0, LINK_T_U32 = 1, LINK_T_F32 = 2 } link_type_t;
typedef enum {
    LINK_ACC_READ = 0,          /* read only */
    LINK_ACC_WRITE = 1,         /* read and write in any state */
    LINK_ACC_WRITE_STOPPED = 2  /* write only in INIT, IDLE or FAULT */
} link_access_t;

typedef enum {
    LV_STATE = 0, LV_FAULT, LV_FLAGS, LV_SPEED_EST_RPM, LV_SPEED_REF_RPM, LV_TE_CMD_NM, LV_TE_REF_NM,
    LV_TE_EST_NM, LV_PSI_REF_WB, LV_PSI_EST_WB, LV_ID_MEAS_A, LV_IQ_MEAS_A, LV_UD_CMD_V, LV_UQ_CMD_V,
    LV_UD_REF_V, LV_UQ_REF_V, LV_R_EST_OHM, LV_L_EST_H, LV_PSIF_EST_WB, LV_EST, LV_EST_HOLD,
    LV_METHOD, LV_MODE, LV_CMD_ERROR, LV_TICKS, LV_LINK_WRITES, LV_LINK_ERR_CRC, LV_LINK_ERR_FRAMING,
    LV_LINK_ERR_OVERRUN, LV_LINK_STREAM_DROPPED, LV_LINK_ERR_LINE, LV_RESET_BY_WATCHDOG,
    /* the commissioning (commission.h): names of drive_sil's OUT.ini keys with comm_ before them */
    LV_COMM_RESULT, LV_COMM_STAGE, LV_COMM_R_OHM, LV_COMM_L_H, LV_COMM_PSIF_WB, LV_COMM_POLE_PAIRS,
    LV_COMM_J_KGM2, LV_COMM_B_NMS, LV_COMM_ENC_OFFSET, LV_COMM_SPEED_KP, LV_COMM_SPEED_KI,
    LV_LEVEL, LV_LEVEL_NEXT,
    /* the commissioning's inverter error (the ids above kept) */
    LV_COMM_DEADTIME_S, LV_COMM_DEVICE_DROP_V, LV_COMM_UNTOLD_DEADTIME_S,
    /* readings and the fallbacks named (every state) */
    LV_VDC_V, LV_METHOD_RAN, LV_HOLD_REASON, LV_FAULT_PRESENT,
    LV_HOST_TIMEOUT_S,          /* the link's own setting (link_host_t) */
    LV_NV_STATUS,               /* the parameter store's state (link_nv_status_t, link_nv.h) */
    LV_PARAM_FIRST,             /* the drive's parameters (link_params.h), LINK_PARAM_COUNT of them */
    LV_COUNT = LV_PARAM_FIRST + LINK_PARAM_COUNT
} link_var_id_t;

/* How a capture keeps a variable: int16 counts scaled by its limits (the default), or its float32
 * value where int16's resolution would hide what the variable is for (the model estimates). */
typedef enum { LINK_CAP_I16 = 0, LINK_CAP_F32 = 1 } link_cap_fmt_t;

typedef struct {
    const char *name;
    const char *unit;           /* "" for a count or a code */
    uint16_t type;              /* link_type_t */
    uint16_t access;            /* link_access_t */
    uint16_t capture;           /* link_cap_fmt_t */
} link_var_t;

/* The link's own counts (link.c), shown as variables. Saturating. */
typedef struct {
    uint32_t writes;            /* WRITE and ACTION requests executed (a repeat answered from the cache is not) */
    uint16_t err_crc, err_framing, err_overrun, stream_dropped;
    uint16_t err_line;          /* the port's own receive errors (garbled characters, FIFO overflows): set by the glue */
    uint16_t reset_by_watchdog; /* 1: the last reset was the watchdog's (set by the glue at start-up) */
} link_stats_t;

#define LINK_HOST_TIMEOUT_MAX_S 600.0f   /* host_timeout_s's top [s]: a host quiet longer is gone */

/* The link's watch of its host (link.c; link_protocol.md, "Host timeout"). Background. */
typedef struct {
    float timeout_s;            /* host_timeout_s: no valid frame this long, once armed, ramps the drive to
                                 * zero and stops it; 0: off */
    uint16_t phase;             /* LINK_HOST_*: what the watch is doing */
    uint32_t seen_ticks;        /* the app's ticks at the last valid frame */
    uint32_t step_ticks;        /* ... at the ramp's last step; at zero: when its references reached it */
} link_host_t;

/* link_host_t.phase */
enum {
    LINK_HOST_IDLE = 0,         /* no host command to watch (none yet, or stopped by the host) */
    LINK_HOST_ARMED = 1,        /* a host wrote a reference or started the drive: its silence counts */
    LINK_HOST_RAMPING = 2,      /* the timeout fired: the references ramp to zero */
    LINK_HOST_AT_ZERO = 3       /* ... reached zero: waiting for standstill */
};

/* The drive's parameter set on the link (link_params.h), the glue's hook and the store. */
typedef struct {
    drive_params_t *set;        /* the set, or NULL: no parameters on the link */
    void (*apply)(void *user, uint16_t k); /* after parameter k's write (stopped): the glue asks for
                                 * the app's configuration from *set (app_request_reconfigure). Background */
    void *user;
    link_nv_t *store;           /* the parameter store the action save asks (link_nv.h; the glue saves
                                 * *set when link_nv_due), or NULL: none, nv_status NONE */
} link_params_glue_t;

/* What the table reads and writes. */
typedef struct {
    app_t *app;
    volatile cmd_t *cmd;        /* the operator's block: writes land here, then cmd_apply() */
    const cmd_limits_t *lim;
    const link_stats_t *stats;
    link_host_t *host;          /* the link's own setting host_timeout_s */
    const link_params_glue_t *params; /* the parameters (link_cfg_t.params) */
} link_target_t;

/* A value: integers in u (and f as float), floats in f. */
typedef struct {
    uint32_t u;
    float f;
} link_val_t;

/* The descriptor of id (< LV_COUNT). Any context. */
const link_var_t *link_var(uint16_t id);

/* Its value now. ISR (capture, stream) or background. */
link_val_t link_var_get(const link_target_t *t, uint16_t id);

/* Its limits [lo, hi] in its unit: the range the command accepts or the value can reach on
 * this drive, from the configuration (capture scaling, LIST_VARS). Background or ISR. */
void link_var_limits(const link_target_t *t, uint16_t id, float *lo, float *hi);

/* Write v (integers in u, floats in f) through cmd_apply(): the other fields of the command
 * are first set to what the drive runs with (app.op_req), a refused value is put back. Returns
 * CMD_OK or the cmd_error_t cmd_apply() named; *access_refused true when the table's access
 * refused it before cmd_apply() (read-only, or write-when-stopped while running). The link's own
 * settings and the drive's parameters (link_params.h) are checked against their limits instead
 * (CMD_ERR_RANGE, nothing changed); a parameter written goes into the parameter set, then
 * params_apply. Background. */
uint16_t link_var_write(const link_target_t *t, uint16_t id, link_val_t v, bool *access_refused);

/* Where the ISR finds a float variable in place: its value in its unit is *p / raw_per_unit.
 * p is NULL for the integers and codes (enumerations, the flags' union): link_var_get. */
typedef struct {
    const volatile float *p;
    float raw_per_unit;         /* 1: as it is */
} link_src_t;

/* The source of id (< LV_COUNT) on this drive: resolved once when a capture or stream is set,
 * so the ISR follows a pointer instead of searching by id. Background. */
link_src_t link_var_source(const link_target_t *t, uint16_t id);

/* 32-bit FNV-1a over every descriptor (name, unit, type, access) and its limits on this drive
 * (the scale follows from them): HELLO's table hash, the host's cache key. Background. */
uint32_t link_vars_hash(const link_target_t *t);


typedef enum {
    LINK_ACTION_START = 1,      /* the start sequence (cmd run 0 -> 1) */
    LINK_ACTION_STOP = 2,       /* to IDLE, PWM off */
    LINK_ACTION_FAULT_RESET = 3,/* clear a latched fault */
    LINK_ACTION_QUIT = 4,       /* the SIL: stop, then end the run (the firmware only stops) */
    LINK_ACTION_COMMISSION = 5, /* measure the motor (commission.h): acted on while stopped (INIT, IDLE) */
    LINK_ACTION_LEVEL = 6,      /* the build level the next start runs (level.h), with its argument */
    LINK_ACTION_SAVE = 7        /* the parameters saved in the store (link_nv.h): acted on while stopped */
} link_action_t;

/* The command block set to what the drive runs with (app.op_req), run and fault reset untouched
 * (before a field of it is set and cmd_apply() called). Background. */
void link_cmd_sync(const link_target_t *t);

/* link_action's return for an action it does not know. */
#define LINK_ACTION_UNKNOWN 0xFFFFu

/* Carry out an action through cmd_apply() (start and stop as an edge of cmd.run, so a start after a
 * fault reset starts again); save asks the store (link_nv_ask: the glue writes the flash after,
 * nv_status says how it went). Returns CMD_OK (or the command's field error cmd_apply() named), a
 * refusal that did nothing (CMD_ERR_FAULTED: start or commission with a fault latched;
 * CMD_ERR_NOT_STOPPED: commission while the drive runs, save while it is not stopped: INIT, IDLE or
 * FAULT), or LINK_ACTION_UNKNOWN (save without a store included). Background. */
uint16_t link_action(const link_target_t *t, uint16_t action);

/* The build level (LEVEL_MIN .. LEVEL_MAX, level.h) the next start runs, through cmd_t.level and
 * cmd_apply() as the debugger sets it. Returns CMD_OK, or CMD_ERR_LEVEL for a level outside
 * 1 .. 5 (nothing changed). Background. */
uint16_t link_level(const link_target_t *t, uint16_t level);
#endif /* LINK_VARS_H */
