/* protect.c - protection checks and the fault snapshot; see protect.h. */
#include "protect.h"

#include <stddef.h>

#include "mathx.h"

#define N_PHASES 3u
#define N_READINGS 2u                /* ia, ib */
#define ONE_THIRD (1.0f / 3.0f)
#define OP_WHOLE_PARTS (PROTECT_OP_SUBWINDOWS - 1u) /* the window's parts before the part so far */
#define SIN_120 0.866025404f                    /* the phase axes: 0, 120, 240 deg el */
#define COS_120 (-0.5f)
#define INV_SQRT3 0.577350269f
/* the cone rule: x carried nothing in more than this share, 1/OP_CONE_SHARE_INV, of its cone periods */
#define OP_CONE_SHARE_INV 2u
#define OP_CONE_SHARE (1.0f / (float)OP_CONE_SHARE_INV)

FLASHFUNC void protect_arm_uv(protect_t *p)
{
    p->uv_armed = true;
}

FLASHFUNC void protect_disarm_uv(protect_t *p)
{
    p->uv_armed = false;
}

/* ---- checks on the periods' history (protect_watch) --------------------- */

RAMFUNC void protect_op_sums_clear(protect_op_sums_t *a)
{
    uint32_t x;

    a->n = 0u;
    a->turn_counts = 0;
    for (x = 0u; x < N_PHASES; x++) {
        a->ix_A[x] = 0.0f;
        a->cone_n[x] = 0u;
        a->none_n[x] = 0u;
        a->ux_V[x] = 0.0f;
    }
}

/* The window restarts: no whole part, the part so far empty. */
RAMFUNC static void op_clear(protect_t *p)
{
    protect_op_sums_clear(&p->op_part);
    p->op_parts_n = 0u;
    p->op_parts_next = 0u;
}

RAMFUNC void protect_watch_reset(protect_t *p)
{
    op_clear(p);
    p->st_seeded = false;
    p->enc_missed_counts = 0.0f;
    p->stall_ticks = 0u;
}

RAMFUNC static int32_t abs_i32(int32_t v)
{
    return (v < 0) ? -v : v;
}

RAMFUNC static int32_t max_i32(int32_t a, int32_t b)
{
    return (a > b) ? a : b;
}

/* OPEN_PHASE's preparation: the ring's parts added into op_prev (|u_x|
 * per part, the parts' largest |net count change|), a piece of a part per
 * period in the part's first OP_PREP_STEPS periods: step s adds piece
 * s mod OP_PREP_PIECES of part s / OP_PREP_PIECES (the parts in the ring's
 * order, each sum's rounding as one step a part gave it), op_prev emptied
 * first by step 0; op_prev is used only once the ring is full. */
#define OP_PREP_PIECES 3u
#define OP_PREP_STEPS (OP_PREP_PIECES * OP_WHOLE_PARTS)

/* Step s (< OP_PREP_STEPS), in the part's (s + 1)-th period. The phases
 * written out, as in open_phase_check. */
RAMFUNC static void op_prep_step(protect_t *p, uint32_t s)
{
    protect_op_sums_t *b = &p->op_prev;
    uint32_t k = 0u;
    uint32_t piece = s;

    while (piece >= OP_PREP_PIECES) { /* no division: at most OP_WHOLE_PARTS - 1 turns */
        piece -= OP_PREP_PIECES;
        k++;
    }
    const protect_op_sums_t *q = &p->op_parts[k];
    if (s == 0u) {
        protect_op_sums_clear(b);
    }
    if (piece == 0u) {
        b->n = (uint16_t)(b->n + q->n);
        b->turn_counts = max_i32(b->turn_counts, abs_i32(q->turn_counts));
        b->cone_n[0] = (uint16_t)(b->cone_n[0] + q->cone_n[0]);
        b->cone_n[1] = (uint16_t)(b->cone_n[1] + q->cone_n[1]);
        b->cone_n[2] = (uint16_t)(b->cone_n[2] + q->cone_n[2]);
    } else if (piece == 1u) {
        b->none_n[0] = (uint16_t)(b->none_n[0] + q->none_n[0]);
        b->none_n[1] = (uint16_t)(b->none_n[1] + q->none_n[1]);
        b->none_n[2] = (uint16_t)(b->none_n[2] + q->none_n[2]);
        b->ix_A[0] += q->ix_A[0];
        b->ix_A[1] += q->ix_A[1];
        b->ix_A[2] += q->ix_A[2];
    } else {
        b->ux_V[0] += mathx_fabsf(q->ux_V[0]);
        b->ux_V[1] += mathx_fabsf(q->ux_V[1]);
        b->ux_V[2] += mathx_fabsf(q->ux_V[2]);
    }
}

/* OPEN_PHASE, phase x of the window of op_prev and *a, the cone rule of
 * protect.h: enough periods in x's cone, x carrying nothing in more than
 * half of them; on the counts (none > cone / 2 as 2 none > cone: exact,
 * no conversion to float in the part's last period). */
RAMFUNC static inline bool op_cone_open(const protect_t *p, const protect_op_sums_t *b, const protect_op_sums_t *a, uint32_t x)
{
    const uint32_t cone = (uint32_t)b->cone_n[x] + a->cone_n[x];
    const uint32_t none = (uint32_t)b->none_n[x] + a->none_n[x];
    return (cone >= p->op_cone_min) && ((OP_CONE_SHARE_INV * none) > cone);
}

/* ... the voltage rule, in sums over the window (ix_limit: op_ratio x the
 * sum of |i|; op_u_min_sum_V: op_u_min_V x the periods). */
RAMFUNC static inline bool op_slow_open(const protect_t *p, const protect_op_sums_t *b, const protect_op_sums_t *a, uint32_t x,
                                float ix_limit)
{
    return (b->ix_A[x] + a->ix_A[x] < ix_limit) && (b->ux_V[x] + mathx_fabsf(a->ux_V[x]) >= p->op_u_min_sum_V);
}

/* OPEN_PHASE: the test of protect.h on the window of the whole parts before
 * (op_prev) and the part *a just ended, compared as sums and counts over
 * the window's periods (limits derived by protect_init); the shares
 * computed for a fault's value only. */
RAMFUNC static app_step_t open_phase_judge(protect_t *p, const protect_op_sums_t *a)
{
    const protect_op_sums_t *b = &p->op_prev;
    const bool slow = ((float)max_i32(b->turn_counts, abs_i32(a->turn_counts)) <= p->op_slow_counts);
    uint32_t x;

    /* the usual verdict, nothing open, at a glance when the voltage rule does not judge: a
     * phase the cone rule opens has 2 none > cone >= op_cone_min, so with 2 x the phases'
     * none together at most op_cone_min none is open (no cone tested, no sum of |i| taken, in
     * the part's last period); the tests below judge otherwise */
    const uint32_t none_all = (uint32_t)b->none_n[0] + b->none_n[1] + b->none_n[2] + a->none_n[0] + a->none_n[1] +
                              a->none_n[2];
    if (!slow && ((OP_CONE_SHARE_INV * none_all) <= p->op_cone_min)) {
        return app_step_running();
    }
    /* sum of |i|: the phases' sums of |i_x| over sqrt(3) (exact with one phase carrying nothing,
     * up to 2 / sqrt(3) high otherwise; no square root every period) */
    const float i_sum = (b->ix_A[0] + a->ix_A[0] + b->ix_A[1] + a->ix_A[1] + b->ix_A[2] + a->ix_A[2]) * INV_SQRT3;
    const float ix_limit = p->cfg.watch.op_ratio * i_sum;

    if (!(i_sum >= p->op_i_min_sum_A)) {
        return app_step_running();
    }
    /* the first open phase is the reason (a loop: once a part, RAM counts more than cycles) */
    for (x = 0u; x < N_PHASES; x++) {
        if (op_cone_open(p, b, a, x)) {
            /* the share of x's cone periods it carried current in, below one half */
            const float cone = (float)(b->cone_n[x] + a->cone_n[x]);
            p->op_phase = (uint16_t)x;
            return app_step_fault(APP_FAULT_OPEN_PHASE, 1.0f - (float)(b->none_n[x] + a->none_n[x]) / cone,
                                  OP_CONE_SHARE);
        }
        if (slow && op_slow_open(p, b, a, x, ix_limit)) {
            /* mean |i_x| / mean |i|, below op_ratio */
            p->op_phase = (uint16_t)x;
            return app_step_fault(APP_FAULT_OPEN_PHASE, (b->ix_A[x] + a->ix_A[x]) / i_sum, p->cfg.watch.op_ratio);
        }
    }
    return app_step_running();
}

/* OPEN_PHASE's cone rule, this period: the aimed current i* (stator frame) at least op_i_min_A,
 * projected on each phase's axis (0, 120, 240 deg): the largest |projection| is the phase whose
 * cone it is in (the axes and their negatives are 60 deg apart: i* is within 30 deg of that
 * phase's, either way), counted, and whether it carried nothing (i_x^2 < op_ratio^2 |i*|^2).
 * Field-oriented only (RUN, IDENTIFY_R; the aim is 0 in open loop). */
RAMFUNC static void op_cones(protect_t *p, const protect_watch_in_t *in, float ic)
{
    protect_op_sums_t *a = &p->op_part;
    const float al = in->i_aim_alpha_A;
    const float be = in->i_aim_beta_A;
    const float n2 = al * al + be * be;

    const float i_min = p->cfg.watch.op_i_min_A;
    if (in->ctrl_running && (n2 >= i_min * i_min)) {
        const float proj_b = COS_120 * al + SIN_120 * be;
        const float pa = mathx_fabsf(al);
        const float pb = mathx_fabsf(proj_b);
        const float pc = mathx_fabsf(al + proj_b); /* -(a's + b's) */
        uint32_t x;
        float ix;
        if ((pa >= pb) && (pa >= pc)) {
            x = 0u;
            ix = in->ia_corr_A;
        } else if (pb >= pc) {
            x = 1u;
            ix = in->ib_corr_A;
        } else {
            x = 2u;
            ix = ic;
        }
        a->cone_n[x]++;
        const float ratio = p->cfg.watch.op_ratio;
        if (ix * ix < ratio * ratio * n2) {
            a->none_n[x]++;
        }
    }
}

/* OPEN_PHASE: this period into the part so far, and one preparation step;
 * at a part's end the steps left, then the window of the last
 * PROTECT_OP_SUBWINDOWS parts is judged and the part goes into the ring. */
RAMFUNC static app_step_t open_phase_check(protect_t *p, const protect_watch_in_t *in)
{
    const float ic = -in->ia_corr_A - in->ib_corr_A;
    protect_op_sums_t *a = &p->op_part;
    app_step_t r = app_step_running();
    protect_op_sums_t *q;
    float d_mean;
    uint32_t k;

    if ((in->duty == NULL) || (p->op_part_ticks == 0u)) {
        op_clear(p); /* outputs off: nothing to compare */
        return r;
    }
    d_mean = (in->duty[0] + in->duty[1] + in->duty[2]) * ONE_THIRD;
    op_cones(p, in, ic);
    /* the phases written out: the every-period part without a loop's bookkeeping */
    a->ix_A[0] += mathx_fabsf(in->ia_corr_A);
    a->ix_A[1] += mathx_fabsf(in->ib_corr_A);
    a->ix_A[2] += mathx_fabsf(ic);
    a->ux_V[0] += (in->duty[0] - d_mean) * in->vdc_V;
    a->ux_V[1] += (in->duty[1] - d_mean) * in->vdc_V;
    a->ux_V[2] += (in->duty[2] - d_mean) * in->vdc_V;
    a->turn_counts += p->enc_delta;
    a->n++;
    if (a->n < p->op_part_ticks) {
        if (a->n <= OP_PREP_STEPS) {
            op_prep_step(p, a->n - 1u);  /* the part's n-th period: step n - 1 */
        }
        return r;
    }
    for (k = a->n - 1u; k < OP_PREP_STEPS; k++) { /* a part shorter than the steps: the rest */
        op_prep_step(p, k);
    }
    q = &p->op_parts[p->op_parts_next];   /* the part into the ring (over the oldest), judged there */
    *q = *a;
    p->op_parts_next = (p->op_parts_next + 1u < OP_WHOLE_PARTS) ? (p->op_parts_next + 1u) : 0u;
    if (p->op_parts_n == OP_WHOLE_PARTS) {
        r = open_phase_judge(p, q);
    } else {
        p->op_parts_n++;
    }
    protect_op_sums_clear(a);
    return r;
}

/* CURRENT_SENSOR, reading c (other: the other reading): the turn and the
 * other reading's span since it last changed. */
RAMFUNC static void stuck_follow(protect_t *p, uint32_t c, float reading, float other, float turn)
{
    if (!p->st_seeded || (mathx_fabsf(reading - p->st_last_A[c]) > p->cfg.watch.stuck_delta_A)) {
        p->st_last_A[c] = reading;
        p->st_angle_el_rad[c] = 0.0f;
        p->st_periods[c] = 0u;
        p->st_other_min_A[c] = other;
        p->st_other_max_A[c] = other;
    } else {
        p->st_angle_el_rad[c] += turn;
        p->st_periods[c]++;
        p->st_other_min_A[c] = (other < p->st_other_min_A[c]) ? other : p->st_other_min_A[c];
        p->st_other_max_A[c] = (other > p->st_other_max_A[c]) ? other : p->st_other_max_A[c];
    }
}

/* CURRENT_SENSOR: reading c stuck by the tests of protect.h. */
RAMFUNC static bool stuck_judged(const protect_t *p, uint32_t c)
{
    const protect_watch_cfg_t *w = &p->cfg.watch;
    return (mathx_fabsf(p->st_angle_el_rad[c]) >= w->stuck_angle_el_rad) && (p->st_periods[c] >= w->stuck_min_periods) &&
           (mathx_fabsf(p->st_last_A[c]) > w->stuck_zero_A) &&
           (p->st_other_max_A[c] - p->st_other_min_A[c] >= w->stuck_span_A);
}

/* CURRENT_SENSOR: per reading, the turn and the other reading's span since
 * it last changed (the two readings written out: no loop's bookkeeping
 * every period). */
RAMFUNC static app_step_t stuck_check(protect_t *p, const protect_watch_in_t *in)
{
    const float turn = (float)p->enc_delta * p->el_rad_per_count; /* signed: a count jittering back and forth is no turn */
    uint32_t c;

    if (!in->ctrl_running) {
        p->st_seeded = false;
        return app_step_running();
    }
    stuck_follow(p, 0u, in->ia_A, in->ib_A, turn);
    stuck_follow(p, 1u, in->ib_A, in->ia_A, turn);
    p->st_seeded = true;
    c = stuck_judged(p, 0u) ? 0u : (stuck_judged(p, 1u) ? 1u : N_READINGS);
    if (c < N_READINGS) {
        return app_step_fault(APP_FAULT_CURRENT_SENSOR, mathx_fabsf(p->st_angle_el_rad[c]), p->cfg.watch.stuck_angle_el_rad);
    }
    return app_step_running();
}

/* ENCODER_LOST: the counts the speed estimate expected since the count last
 * changed; the periods at the torque limit without a count. */
RAMFUNC static app_step_t encoder_lost_check(protect_t *p, const protect_watch_in_t *in)
{
    const protect_watch_cfg_t *w = &p->cfg.watch;
    const bool moved = (p->enc_delta != 0);

    p->enc_missed_counts = moved ? 0.0f
                                 : p->enc_missed_counts + mathx_fabsf(in->speed_m_rad_s) * p->drv.Ts_s * p->counts_per_rad;
    if (!(p->enc_missed_counts < w->enc_lost_counts)) { /* a NaN speed trips too */
        return app_step_fault(APP_FAULT_ENCODER_LOST, p->enc_missed_counts, w->enc_lost_counts);
    }
    if (moved || !in->ctrl_running || !(mathx_fabsf(in->te_ref_Nm) >= w->enc_stall_te_frac * p->drv.te_max_Nm)) {
        p->stall_ticks = 0u;
    } else {
        p->stall_ticks++;
    }
    if ((p->stall_ticks_max > 0u) && (p->stall_ticks >= p->stall_ticks_max)) {
        return app_step_fault(APP_FAULT_ENCODER_LOST, (float)p->stall_ticks * p->drv.Ts_s, w->enc_stall_s);
    }
    return app_step_running();
}

RAMFUNC app_step_t protect_watch(protect_t *p, const protect_watch_in_t *in)
{
    app_step_t r = encoder_lost_check(p, in);
    if (r.status != APP_STEP_FAULT) {
        r = stuck_check(p, in);
    }
    if (r.status != APP_STEP_FAULT) {
        r = open_phase_check(p, in);
    }
    return r;
}

RAMFUNC void protect_snapshot(app_snapshot_t *snap, app_state_t state, const hal_sample_t *s, const app_step_t *f)
{
    snap->sample = *s;
    snap->state = state;
    snap->value = f->value;
    snap->limit = f->limit;
}
