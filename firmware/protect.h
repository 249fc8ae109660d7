/*
 * protect.h - the drive's protection checks and the fault snapshot.
 * Checked in every state but FAULT, on each period's samples, in this
 * order (the first that fails is the reason):
 *   HW_TRIP           hal_trip_active() (trip-zone input latched)
 *   NONFINITE_SAMPLE  ia, ib or vdc not finite
 *   OVERCURRENT       |ia|, |ib| or |ic| (offset-corrected) > i_max_A
 *   OVERVOLTAGE       vdc > vdc_max_V
 *   UNDERVOLTAGE      vdc < vdc_min_V, once armed (protect_arm_uv: after a
 *                     start passed calibration; the bus may charge in INIT)
 *   ENCODER           |count change| in one period > the change at
 *                     speed_max_rad_s times PROTECT_ENC_JUMP_MARGIN, plus
 *                     one count: a jump no shaft can make
 *   OVERSPEED         |speed estimate (encoder PLL)| > speed_max_rad_s
 *   OVERRUN           entry-to-entry interval > 1.5 periods (a period was
 *                     missed), or the last ISR run > isr_budget_cycles
 * A latched fault keeps a snapshot: the period's raw samples, the state it
 * was detected in, the quantity and the limit it crossed.
 */
#ifndef PROTECT_H
#define PROTECT_H

#include <stdbool.h>
#include <stdint.h>

#include "app_step.h"
#include "hal.h"

/* Count change per period beyond the overspeed limit's that still counts
 * as motion: the PLL-based overspeed check trips long before a real shaft
 * gets there (12 N m / J adds 9 r/min per period). */
#define PROTECT_ENC_JUMP_MARGIN 1.5f
#define APP_ENC_JUMP_MARGIN PROTECT_ENC_JUMP_MARGIN /* old name */

typedef struct {
    float i_max_A;              /* software overcurrent on |ia|, |ib|, |ic| [A] */
    float vdc_max_V;            /* overvoltage trip [V] */
    float vdc_min_V;            /* undervoltage trip, once armed [V] */
    float speed_max_rad_s;      /* overspeed trip, mechanical [rad/s]; also sets the encoder jump limit */
    uint32_t isr_period_cycles; /* control period in hal_cycles() counts [cycles] */
    uint32_t isr_budget_cycles; /* longest allowed ISR run [cycles] */
    uint32_t enc_cpr;           /* encoder counts per revolution [counts] */
    float Ts_s;                 /* control period [s] */
} protect_cfg_t;

/* What was known in the period a fault was detected. */
typedef struct {
    hal_sample_t sample;        /* raw samples of that period */
    app_state_t state;          /* state the fault was detected in */
    float value;                /* the quantity that tripped, in its unit (A, V, rad/s, counts, cycles); 0 for a trip or NaN */
    float limit;                /* the threshold it crossed */
} app_snapshot_t;

typedef struct {
    protect_cfg_t cfg;
    /* derived by protect_init */
    uint32_t enc_cpr;              /* counts per revolution, at least 1 */
    float enc_jump_max;            /* largest plausible |enc_delta| [counts] */
    uint32_t isr_late_cycles;      /* entry-to-entry interval that means a missed period [cycles] */
    /* tracked every call */
    uint32_t enc_prev;             /* count of the previous call */
    int32_t enc_delta;             /* count change since the previous call, shortest way [counts] */
    bool seeded;                   /* enc_prev and isr_entry valid */
    uint32_t isr_entry;            /* hal_cycles() at the previous entry */
    uint32_t isr_interval_cycles;  /* entry to entry, this call [cycles] */
    uint32_t isr_run_cycles;       /* entry to exit, last call [cycles] */
    bool uv_armed;                 /* undervoltage check active */
} protect_t;

/* Start-up: copy *cfg, derive the limits; nothing tracked, undervoltage off. */
void protect_init(protect_t *p, const protect_cfg_t *cfg);

/* ISR, every call first: the count change and the entry-to-entry time. */
void protect_track(protect_t *p, uint32_t enc_count, uint32_t t_entry_cycles);

/* ISR: from now on an undervoltage is a fault (kept armed). */
void protect_arm_uv(protect_t *p);

/* ISR: the checks above on this call's samples *s, the current offsets
 * [A] and the speed estimate [rad/s, mechanical]: RUNNING when all pass,
 * else FAULT with the first failing check, its quantity and limit. */
app_step_t protect_check(const protect_t *p, const hal_sample_t *s, float offset_ia_A, float offset_ib_A,
                         float speed_m_rad_s);

/* ISR, at the exit: the run time from t_entry_cycles to now_cycles;
 * FAULT (OVERRUN) when over the budget. */
app_step_t protect_run_time(protect_t *p, uint32_t t_entry_cycles, uint32_t now_cycles);

/* ISR: the snapshot of a fault detected in state on *s. */
void protect_snapshot(app_snapshot_t *snap, app_state_t state, const hal_sample_t *s, const app_step_t *f);

#endif /* PROTECT_H */
