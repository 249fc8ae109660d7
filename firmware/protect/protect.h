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
 * and, from the history of the periods (protect_watch, after the checks
 * above pass; thresholds in protect_watch_cfg_t, values in board_cfg.h):
 *   OPEN_PHASE        over a window of op_window_s with the outputs on
 *                     (sliding: judged at the end of each of its
 *                     PROTECT_OP_SUBWINDOWS parts, over the last whole
 *                     window), mean |i| >= op_i_min_A (|i| as the sum of
 *                     the three |i_x| / sqrt(3): exact with one phase
 *                     carrying nothing, up to 15 % high otherwise), for
 *                     one phase x
 *                     (firmware/protect/protect_design.md):
 *                       - the cone rule (RUN and IDENTIFY_R, field-
 *                         oriented): of the periods the controller's
 *                         step aimed the current i* (|i*| >=
 *                         op_i_min_A) nearest x's axis (within 30 deg of
 *                         it, either way: the axes and their negatives
 *                         are 60 deg apart), at least PROTECT_OP_CONE_MIN
 *                         of the window's, x carried nothing (|i_x| <
 *                         op_ratio |i*|) in more than half. A healthy
 *                         phase there carries cos(30 deg + the current's
 *                         lag behind its aim), above op_ratio for a lag
 *                         under 48 deg: whatever else the window holds (a
 *                         speed step's burst across the phase, a
 *                         current-limited deceleration, the zero
 *                         crossings, field weakening) it does not trip;
 *                         or, slow (the parts' net turns kept the
 *                         back-EMF's peak below PROTECT_OP_EMF_SHARE x
 *                         op_u_min_V),
 *                       - mean |i_x| < op_ratio x mean |i| while the voltage
 *                         phase x was given, averaged (signed) over each
 *                         part, then |.| over the window, is >= op_u_min_V
 *                         (u_x: the phase voltage of the duties, zero
 *                         sequence removed). Slow, a healthy i_x follows
 *                         u_x / R, so a small i_x comes with a small u_x
 *                         (a current vector across the phase, as in the
 *                         alignment's first step); averaging over a part
 *                         first keeps the deadbeat's answer to ADC noise
 *                         (L / Ts x noise, 16 V for 0.15 A) out of it.
 *                     Not observable with no current asked for, nor at
 *                     speed with the aim kept away from x's axis.
 *   CURRENT_SENSOR    in RUN and IDENTIFY_R: one current reading unchanged
 *                     (by less than stuck_delta_A, half an ADC step) and
 *                     beyond +- stuck_zero_A while the rotor turned (net)
 *                     stuck_angle_el_rad and the other reading moved over
 *                     stuck_span_A, for at least stuck_min_periods (a
 *                     fast motor turns 15 deg el in 4 periods, where ADC
 *                     noise of 2 codes rms keeps a code by chance one
 *                     period in a thousand): a field-oriented current turns with
 *                     the rotor, so both readings move. A reading stuck
 *                     near 0 A looks like an open phase and is judged by
 *                     OPEN_PHASE. Not observable at standstill on a
 *                     noise-free ADC.
 *   ENCODER_LOST      the count unchanged while the speed estimate,
 *                     integrated since the last change, says it should
 *                     have moved enc_lost_counts (the PLL runs on past a
 *                     count that stops); or, at low speed where the PLL
 *                     stops first, in RUN and IDENTIFY_R no count change
 *                     for enc_stall_s with |te_ref| >= enc_stall_te_frac x
 *                     te_max (no motion at the torque limit: the encoder
 *                     lost, or a stalled rotor).
 * A latched fault keeps a snapshot: the period's raw samples, the state it
 * was detected in, the quantity and the limit it crossed.
 */
#ifndef PROTECT_H
#define PROTECT_H

#include <stdbool.h>
#include <stdint.h>

#include "app_step.h"
#include "hal.h"
#include "mathx.h"

/* Count change per period beyond the overspeed limit's that still counts
 * as motion: the PLL-based overspeed check trips long before a real shaft
 * gets there (12 N m / J adds 9 r/min per period). */
#define PROTECT_ENC_JUMP_MARGIN 1.5f
#define APP_ENC_JUMP_MARGIN PROTECT_ENC_JUMP_MARGIN /* old name */

/* OPEN_PHASE's voltage rule holds while the back-EMF's peak w_el psi_f stays below this share
 * of op_u_min_V (25 V given leaves 25 - 12.5 - 3 V of dead-time residue across R: 3.2 A at the
 * reference's 3 ohm, above op_ratio x its 12 A limit; protect_design.md). */
#define PROTECT_OP_EMF_SHARE 0.5f
/* OPEN_PHASE's cone rule judges a phase from this share of the window's periods in its cone on
 * (each phase has 1/3 with the aim turning, all at standstill; protect_design.md). */
#define PROTECT_OP_CONE_MIN 0.125f

/* Thresholds of the checks on the periods' history (protect_watch). */
typedef struct {
    float op_window_s;          /* OPEN_PHASE window [s] */
    float op_i_min_A;           /* mean |i| in the window at least; a period's |i| in a cone [A] */
    float op_ratio;             /* a phase's |i_x| below this x |i| carries nothing [-] ... */
    float op_u_min_V;           /* ... while its mean |u_x| (per part) is at least this, slow [V] */
    float stuck_delta_A;        /* a reading changing by less is unchanged [A] */
    float stuck_angle_el_rad;   /* net rotor turn with one reading unchanged [rad el] ... */
    float stuck_span_A;         /* ... while the other one moved over this [A] */
    float stuck_zero_A;         /* ... and it is beyond +- this (near 0: OPEN_PHASE's) [A] */
    uint32_t stuck_min_periods; /* ... for at least this many periods (noise keeps one ADC code that long only by chance) */
    float enc_lost_counts;      /* counts the speed estimate says were missed [counts] */
    float enc_stall_s;          /* no count change this long ... [s] */
    float enc_stall_te_frac;    /* ... at |te_ref| >= this x the controller's torque limit [-] */
} protect_watch_cfg_t;

/* One period's inputs to protect_watch. */
typedef struct {
    float ia_A, ib_A;           /* raw samples [A] */
    float ia_corr_A, ib_corr_A; /* offsets subtracted [A] */
    float vdc_V;                /* [V] */
    const float *duty;          /* the three duties applied in the period just sampled; NULL: outputs off */
    bool ctrl_running;          /* RUN or IDENTIFY_R: the current is field-oriented */
    float speed_m_rad_s;        /* speed estimate (encoder PLL), mechanical [rad/s] */
    float te_ref_Nm;            /* the controller's torque reference [N m] (NaN: none) */
    float i_aim_alpha_A, i_aim_beta_A; /* the current the controller's last step aimed at, stator frame [A] */
} protect_watch_in_t;

typedef struct {
    float i_max_A;              /* software overcurrent on |ia|, |ib|, |ic| [A] */
    float vdc_max_V;            /* overvoltage trip [V] */
    float vdc_min_V;            /* undervoltage trip, once armed [V] */
    float speed_max_rad_s;      /* overspeed trip, mechanical [rad/s]; also sets the encoder jump limit */
    uint32_t isr_period_cycles; /* control period in hal_cycles() counts [cycles] */
    uint32_t isr_budget_cycles; /* longest allowed ISR run [cycles] */
    protect_watch_cfg_t watch;  /* the checks on the periods' history */
} protect_cfg_t;

/* The drive's values the checks need, from the controller's configuration
 * (app_init): not set twice. */
typedef struct {
    float Ts_s;                 /* control period [s] */
    uint32_t enc_cpr;           /* encoder counts per revolution [counts] */
    float te_max_Nm;            /* the controller's torque limit [N m] */
    uint16_t pole_pairs;        /* [-] */
    float psi_f_Wb;             /* the controller's PM flux: the back-EMF of OPEN_PHASE's voltage rule [Wb] */
} protect_drive_t;

/* What was known in the period a fault was detected. */
typedef struct {
    hal_sample_t sample;        /* raw samples of that period */
    app_state_t state;          /* state the fault was detected in */
    float value;                /* the quantity that tripped, in its unit (A, V, rad/s, counts, cycles); 0 for a trip or NaN */
    float limit;                /* the threshold it crossed */
} app_snapshot_t;

/* OPEN_PHASE's window slides in this many parts: it is judged every
 * op_window_s / PROTECT_OP_SUBWINDOWS (25 ms with the board's 0.1 s), at
 * the end of each part, in that part's last period. So that this period
 * costs about what any other does, the window's whole parts before it are
 * summed during the part, a third of a part per period in its first
 * periods (a part shorter than that sums the rest at its end): the end
 * adds its own part, judges (the usual verdict, nothing open, from one
 * sum of counts), and moves it into the ring (figures: protect_log.md). */
#define PROTECT_OP_SUBWINDOWS 4u

/* OPEN_PHASE's sums over a part of the window. */
typedef struct {               /* the counts 16-bit (RAM): a window of at most 65535 periods */
    uint16_t n;                 /* periods [-] */
    uint16_t cone_n[3];         /* periods with the aim in phase x's cone and |i*| >= op_i_min_A [-] */
    uint16_t none_n[3];         /* ... of them, x carrying nothing (|i_x| < op_ratio |i*|) [-] */
    float ix_A[3];              /* sums of |i_a|, |i_b|, |i_c| [A] */
    float ux_V[3];              /* sums of u_a, u_b, u_c (signed) [V] */
    int32_t turn_counts;        /* net count change [counts]; op_prev: the parts' largest |net change| */
} protect_op_sums_t;

typedef struct {
    protect_cfg_t cfg;
    protect_drive_t drv;
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
    /* protect_watch: derived */
    uint32_t op_part_ticks;        /* OPEN_PHASE window part [periods] */
    float op_i_min_sum_A;          /* op_i_min_A x a whole window's periods [A] */
    float op_u_min_sum_V;          /* op_u_min_V x a whole window's periods [V] */
    float op_slow_counts;          /* the voltage rule's top speed: net count change per part [counts] */
    uint32_t stall_ticks_max;      /* enc_stall_s [periods] */
    float el_rad_per_count;        /* electrical angle of one count [rad] */
    float counts_per_rad;          /* counts per mechanical radian [counts/rad] */
    /* protect_watch: OPEN_PHASE window */
    protect_op_sums_t op_part;     /* the part so far */
    protect_op_sums_t op_parts[PROTECT_OP_SUBWINDOWS - 1u];  /* the last whole parts, a ring */
    uint32_t op_parts_n;           /* whole parts in the ring (at most PROTECT_OP_SUBWINDOWS - 1) */
    uint32_t op_parts_next;        /* ring index the next whole part goes to */
    protect_op_sums_t op_prev;     /* the ring's sums, built during the part: ux_V the sum of each part's
                                    * |sum of u_x|, turn_counts the parts' largest |net change| */
    uint16_t op_phase;             /* the phase found open (0 a, 1 b, 2 c), for the operator */
    uint16_t op_cone_min;          /* PROTECT_OP_CONE_MIN of a whole window's periods [-] */
    /* protect_watch: CURRENT_SENSOR, per reading (0 ia, 1 ib) since it last changed */
    float st_last_A[2];
    float st_angle_el_rad[2];      /* net turn, signed [rad el] */
    uint32_t st_periods[2];        /* periods unchanged */
    float st_other_min_A[2], st_other_max_A[2];
    bool st_seeded;
    /* protect_watch: ENCODER_LOST */
    float enc_missed_counts;       /* counts the speed estimate expected since the count last changed */
    uint32_t stall_ticks;          /* periods at the torque limit with no count change */
} protect_t;

/* Start-up: copy *cfg and *drv, derive the limits; nothing tracked,
 * undervoltage off. */
void protect_init(protect_t *p, const protect_cfg_t *cfg, const protect_drive_t *drv);

/* Count change from prev to now (both < cpr), the shortest way round; no
 * 32-bit % (an RTS call from flash on the C28x). Any context. */
static inline int32_t protect_count_delta(uint32_t now, uint32_t prev, uint32_t cpr)
{
    const uint32_t d = (now >= prev) ? (now - prev) : (now + cpr - prev);
    return (d > (cpr / 2u)) ? ((int32_t)d - (int32_t)cpr) : (int32_t)d;
}

/* ISR, every call first: the count change and the entry-to-entry time.
 * Inline: one call less in every period. */
static inline void protect_track(protect_t *p, uint32_t enc_count, uint32_t t_entry_cycles)
{
    const uint32_t count = mathx_umod_u32(enc_count, p->enc_cpr);

    if (p->seeded) {
        p->enc_delta = protect_count_delta(count, p->enc_prev, p->enc_cpr);
        p->isr_interval_cycles = t_entry_cycles - p->isr_entry; /* modulo 2^32, wrap-safe */
    }
    p->enc_prev = count;
    p->isr_entry = t_entry_cycles;
    p->seeded = true;
}

/* ISR (the start sequence's transitions; from flash): from now on an
 * undervoltage is a fault (kept armed). */
void protect_arm_uv(protect_t *p);

/* ISR (the start sequence; from flash): no undervoltage check until the
 * next protect_arm_uv (build levels 1-2 run without the DC bus, level.h). */
void protect_disarm_uv(protect_t *p);

/* ISR: the checks above on this call's samples *s, the current offsets
 * [A] and the speed estimate [rad/s, mechanical]: RUNNING when all pass,
 * else FAULT with the first failing check, its quantity and limit.
 * Inline: its result stays in registers in every period. */
static inline app_step_t protect_check(const protect_t *p, const hal_sample_t *s, float offset_ia_A,
                                       float offset_ib_A, float speed_m_rad_s)
{
    const protect_cfg_t *cfg = &p->cfg;
    const float ia = s->ia_A - offset_ia_A;
    const float ib = s->ib_A - offset_ib_A;
    const float ic = -ia - ib;
    float i_peak;

    if (hal_trip_active()) {
        return app_step_fault(APP_FAULT_HW_TRIP, 0.0f, 0.0f);
    }
    if (!mathx_isfinitef(s->ia_A) || !mathx_isfinitef(s->ib_A) || !mathx_isfinitef(s->vdc_V)) {
        return app_step_fault(APP_FAULT_NONFINITE_SAMPLE, 0.0f, 0.0f);
    }
    i_peak = mathx_fabsf(ia);
    i_peak = (mathx_fabsf(ib) > i_peak) ? mathx_fabsf(ib) : i_peak;
    i_peak = (mathx_fabsf(ic) > i_peak) ? mathx_fabsf(ic) : i_peak;
    if (!(i_peak <= cfg->i_max_A)) { /* !(x <= max): a NaN limit trips too */
        return app_step_fault(APP_FAULT_OVERCURRENT, i_peak, cfg->i_max_A);
    }
    if (!(s->vdc_V <= cfg->vdc_max_V)) {
        return app_step_fault(APP_FAULT_OVERVOLTAGE, s->vdc_V, cfg->vdc_max_V);
    }
    if (p->uv_armed && (s->vdc_V < cfg->vdc_min_V)) {
        return app_step_fault(APP_FAULT_UNDERVOLTAGE, s->vdc_V, cfg->vdc_min_V);
    }
    if (mathx_fabsf((float)p->enc_delta) > p->enc_jump_max) {
        return app_step_fault(APP_FAULT_ENCODER, mathx_fabsf((float)p->enc_delta), p->enc_jump_max);
    }
    if (!(mathx_fabsf(speed_m_rad_s) <= cfg->speed_max_rad_s)) {
        return app_step_fault(APP_FAULT_OVERSPEED, mathx_fabsf(speed_m_rad_s), cfg->speed_max_rad_s);
    }
    if (p->isr_interval_cycles > p->isr_late_cycles) {
        return app_step_fault(APP_FAULT_OVERRUN, (float)p->isr_interval_cycles, (float)p->isr_late_cycles);
    }
    if (p->isr_run_cycles > cfg->isr_budget_cycles) { /* the last call's: for a fault reset's check */
        return app_step_fault(APP_FAULT_OVERRUN, (float)p->isr_run_cycles, (float)cfg->isr_budget_cycles);
    }
    return app_step_running();
}

/* ISR, at the exit: the run time from t_entry_cycles to now_cycles;
 * FAULT (OVERRUN) when over the budget. Inline: one call less in every
 * period. */
static inline app_step_t protect_run_time(protect_t *p, uint32_t t_entry_cycles, uint32_t now_cycles)
{
    p->isr_run_cycles = now_cycles - t_entry_cycles;
    if (p->isr_run_cycles > p->cfg.isr_budget_cycles) {
        return app_step_fault(APP_FAULT_OVERRUN, (float)p->isr_run_cycles, (float)p->cfg.isr_budget_cycles);
    }
    return app_step_running();
}

/* OPEN_PHASE: a part's sums emptied (protect_init.c and protect.c). Any context. */
void protect_op_sums_clear(protect_op_sums_t *a);

/* ISR, after protect_check passed: the checks on the periods' history
 * (see above); RUNNING, or FAULT with the quantity and its limit:
 * OPEN_PHASE the share phase x carried and its limit [-] (the cone rule:
 * of its cone periods, those it carried current in, and 1/2; the voltage
 * rule: mean |i_x| / mean |i| and op_ratio), CURRENT_SENSOR the
 * turn [rad el] and stuck_angle_el_rad, ENCODER_LOST the missed counts and
 * enc_lost_counts, or the time without a count [s] and enc_stall_s. */
app_step_t protect_watch(protect_t *p, const protect_watch_in_t *in);

/* ISR or start-up: forget the history protect_watch keeps (after a fault). */
void protect_watch_reset(protect_t *p);

/* ISR: the snapshot of a fault detected in state on *s. */
void protect_snapshot(app_snapshot_t *snap, app_state_t state, const hal_sample_t *s, const app_step_t *f);

#endif /* PROTECT_H */
