/* rsid_seq.c - step 1 of the proposed method as a timed sequence; see rsid_seq.h. */
#include "rsid_seq.h"

#include "mathx.h"

void rsid_seq_init(rsid_seq_t *q, const rsid_seq_cfg_t *cfg, float Ts_s)
{
    q->cfg = *cfg;
    q->window_ticks = app_periods_of(cfg->window_s, Ts_s);
    q->win1_tick = app_periods_of(cfg->settle_1_s, Ts_s);
    q->settle_2_ticks = app_periods_of(cfg->settle_2_s, Ts_s);
    q->win2_tick = q->win1_tick + q->window_ticks + q->settle_2_ticks;
    q->end_tick = q->win2_tick + q->window_ticks;
    q->win2_max_ticks = app_periods_of(cfg->window_max_s, Ts_s);
    q->check_ticks = 1u; /* set from the controller's batch at the first check */
    q->speed_step_rad_s = cfg->accel_rad_s2 * Ts_s;
    q->ticks = 0u;
    q->repeats = 0u;
    q->speed_ref_rad_s = 0.0f;
    q->handover = false;
    q->result = RS_IDENT_OK;
    q->check = RSID_CHECK_NONE;
    q->check_tick = 0u;
}

FLASHFUNC void rsid_seq_start(rsid_seq_t *q, float speed_now_rad_s)
{
    q->ticks = 0u;
    q->repeats = 0u;
    q->speed_ref_rad_s = speed_now_rad_s; /* SPEEDS ramps from here */
    q->handover = false;
    q->check = RSID_CHECK_NONE;
}

/* The commanded speed one period on towards target at accel (a step when
 * that is 0); true while target is not yet reached. */
RAMFUNC static bool ramp_speed(rsid_seq_t *q, float target)
{
    const float dmax = q->speed_step_rad_s;
    const float err = target - q->speed_ref_rad_s;

    q->speed_ref_rad_s += (dmax > 0.0f) ? mathx_clampf(err, -dmax, dmax) : err;
    return (dmax > 0.0f) && (mathx_fabsf(err) > dmax);
}

/* ctrl_step at the sequence's speed reference; the outside's (ctrl.ref's)
 * is put back after it. Only the speed is kept aside: the ISR's deepest
 * chain runs through here (ram_budget's stack). */
RAMFUNC static void step_at_speed(const rsid_seq_t *q, ctrl_t *c, const ctrl_in_t *in, ctrl_out_t *out)
{
    const float outside_rad_s = ctrl_ref(c)->speed_ref_rad_s;

    ctrl_set_speed_ref(c, q->speed_ref_rad_s);
    ctrl_step(c, in, out);
    ctrl_set_speed_ref(c, outside_rad_s);
}

/* The fault naming why step 1 refused R^, with the quantity and its limit. */
RAMFUNC static app_step_t refusal(const ctrl_t *c, rs_ident_result_t r)
{
    const rs_ident_out_t *o = est_rsid_out(ctrl_est(c));
    const rs_ident_cfg_t *rc = est_rsid_cfg(ctrl_est(c));

    switch (r) {
    case RS_IDENT_NOT_STEADY:
        return app_step_fault(APP_FAULT_RSID_NOT_STEADY,
                              o->R_se_Ohm, o->R_se_max_Ohm); /* standard error of R^, its limit */
    case RS_IDENT_DEGENERATE:
        return app_step_fault(APP_FAULT_RSID_DEGENERATE, o->R_est_Ohm, 0.0f);
    case RS_IDENT_NON_FINITE:
        return app_step_fault(APP_FAULT_RSID_NON_FINITE, o->R_est_Ohm, 0.0f);
    case RS_IDENT_OUT_OF_BAND: {
        const float R_hat = o->R_raw_Ohm; /* R_est_Ohm stays R_nom when refused */
        return app_step_fault(APP_FAULT_RSID_OUT_OF_BAND, R_hat,
                              (R_hat > rc->R_max_Ohm) ? rc->R_max_Ohm : rc->R_min_Ohm);
    }
    case RS_IDENT_D_AXIS:
        return app_step_fault(APP_FAULT_RSID_D_AXIS, o->R_d_axis_Ohm, o->R_se_max_Ohm); /* R^'s d-axis share, the limit */
    case RS_IDENT_INVERTER:
        return app_step_fault(APP_FAULT_RSID_INVERTER, o->R_inverter_Ohm, o->R_inverter_max_Ohm);
    case RS_IDENT_INVALID_CFG:
        return app_step_fault(APP_FAULT_CONFIG, o->R_est_Ohm, 0.0f);
    case RS_IDENT_TOO_FEW:
    case RS_IDENT_OK: /* not called with OK */
    default:
        return app_step_fault(APP_FAULT_RSID_TOO_FEW, o->R_est_Ohm, 0.0f);
    }
}

typedef enum { AFTER_GO_ON = 0, AFTER_REPEAT = 1, AFTER_FINISH = 2 } after_t;

/* A check of the windows as at q->check_tick came back with r, *o
 * (rsid_seq.h): go on filling window 2 (R^ refused only for its standard
 * error with window 1's share below the limit and room for another
 * batch), repeat both windows (SPEEDS: window 1's share too large,
 * repeats left), or finish. */
RAMFUNC static after_t after_check(const rsid_seq_t *q, rs_ident_result_t r, const rs_ident_out_t *o)
{
    if (r != RS_IDENT_NOT_STEADY) {
        return AFTER_FINISH;
    }
    if (o->R_se_part_Ohm[0] <= o->R_se_max_Ohm) {
        /* a longer window 2 can help */
        return (q->check_tick - q->win2_tick + q->check_ticks > q->win2_max_ticks) ? AFTER_FINISH : AFTER_GO_ON;
    }
    return ((q->cfg.mode == APP_RSID_SPEEDS) && (q->repeats < q->cfg.repeats_max)) ? AFTER_REPEAT : AFTER_FINISH;
}

/* From window 2's nominal end, at each of its batch boundaries while no
 * check is under way: a copy of window 2's sample sums as they are now,
 * and the staged solve of it with window 1 (complete, unchanged until the
 * check ends) started (one stage per period from the next, the result
 * acted on in the period after the last: the ISR's worst period stays
 * near its typical one; window 2 goes on filling meanwhile, its batch
 * sums unchanged until the check ends: n_batch > RS_IDENT_SOLVE_STAGES). */
RAMFUNC static void check_begin(rsid_seq_t *q, ctrl_t *c)
{
    const uint32_t batch = est_rsid_cfg(ctrl_est(c))->n_batch;

    q->check_ticks = (batch > 0u) ? batch : 1u;
    if (!est_rsid_stage_begin(ctrl_est_rw(c), &q->solver, &q->win2)) {
        return; /* inside a batch of window 2: at its end */
    }
    q->check_tick = q->ticks;
    q->check = RSID_CHECK_SOLVING;
}

/* The window period k fills: window 1 over its ticks, window 2 from its
 * start while the sequence does not finish in this period (next). */
RAMFUNC static rs_ident_window_t window_at(const rsid_seq_t *q, uint32_t k, after_t next)
{
    if ((k >= q->win1_tick) && (k < q->win1_tick + q->window_ticks)) {
        return RS_IDENT_WINDOW_1;
    }
    if ((k >= q->win2_tick) && (next != AFTER_FINISH)) {
        /* up to end_tick, and on while lengthened or checked; not in the
         * period that finishes (the windows are emptied in it) */
        return RS_IDENT_WINDOW_2;
    }
    return RS_IDENT_WINDOW_NONE;
}

/* Period k's ctrl_step: SPEEDS at the sequence's speed (point 1 until
 * window 1 ends, then point 2) in place of the outside reference, else at
 * the outside one; true while SPEEDS ramps outside a window (the period
 * is not counted). */
RAMFUNC static bool step_ctrl(rsid_seq_t *q, ctrl_t *c, const ctrl_in_t *in, ctrl_out_t *out, uint32_t k,
                              rs_ident_window_t win)
{
    bool moving = false;
    if (q->cfg.mode == APP_RSID_SPEEDS) {
        const float target = (k < q->win1_tick + q->window_ticks) ? q->cfg.speed_1_rad_s : q->cfg.speed_2_rad_s;
        /* the settle times count from the end of the ramp: a window in a
         * ramp sees the speed estimate's lag as back-EMF in fq (biases R^) */
        moving = ramp_speed(q, target) && (win == RS_IDENT_WINDOW_NONE);
        step_at_speed(q, c, in, out);
    } else {
        ctrl_step(c, in, out);
    }
    return moving;
}

/* A solved check's result acted on (next): go on filling window 2, both
 * windows once more, or finish: done (SPEEDS: the handover next), or
 * refused with the fault naming why. */
RAMFUNC static app_step_t act_on_check(rsid_seq_t *q, ctrl_t *c, after_t next)
{
    q->check = RSID_CHECK_NONE;
    if (next == AFTER_REPEAT) {
        /* back to point 1 (the target follows ticks), settle_2 after the
         * ramp, both windows once more: their sums go on accumulating */
        q->repeats++;
        q->ticks = (q->win1_tick > q->settle_2_ticks) ? (q->win1_tick - q->settle_2_ticks) : 0u;
    }
    if (next != AFTER_FINISH) {
        return app_step_running();
    }
    q->result = ctrl_rsid_finish(c, q->solver.result);
    if (q->result != RS_IDENT_OK) {
        return refusal(c, q->result);
    }
    q->handover = (q->cfg.mode == APP_RSID_SPEEDS);
    return app_step_done();
}

/* From the windows' nominal end on, a period: a check begun (at a batch
 * boundary), its solve staged one period at a time, then acted on. */
RAMFUNC static app_step_t after_windows(rsid_seq_t *q, ctrl_t *c, after_t next)
{
    if (q->check == RSID_CHECK_NONE) {
        check_begin(q, c);
        return app_step_running();
    }
    if (q->check == RSID_CHECK_SOLVING) {
        /* the sequence acts on the result from the next period: the last
         * stage and the start of step 2 do not share one */
        if (est_rsid_stage_step(ctrl_est_rw(c), &q->solver)) {
            q->check = RSID_CHECK_SOLVED;
        }
        return app_step_running();
    }
    return act_on_check(q, c, next);
}

RAMFUNC app_step_t rsid_seq_step(rsid_seq_t *q, ctrl_t *c, const ctrl_in_t *in, ctrl_out_t *out)
{
    const uint32_t k = q->ticks;
    /* a solved check is acted on in this period: known before the sample */
    const after_t next = (q->check == RSID_CHECK_SOLVED) ? after_check(q, q->solver.result, est_rsid_out(ctrl_est(c)))
                                                         : AFTER_GO_ON;
    const rs_ident_window_t win = window_at(q, k, next);

    est_rsid_window(ctrl_est_rw(c), win);
    const bool moving = step_ctrl(q, c, in, out, k, win);
    if ((out->flags & CTRL_FLAG_NONFINITE) != 0u) {
        return app_step_fault(APP_FAULT_NONFINITE_OUTPUT, 0.0f, 0.0f);
    }
    if (moving) {
        return app_step_running();
    }
    q->ticks++;
    if (q->ticks < q->end_tick) {
        return app_step_running();
    }
    return after_windows(q, c, next);
}

RAMFUNC void rsid_seq_handover_step(rsid_seq_t *q, ctrl_t *c, const ctrl_in_t *in, ctrl_out_t *out)
{
    q->handover = ramp_speed(q, ctrl_ref(c)->speed_ref_rad_s);
    step_at_speed(q, c, in, out);
}
