/* app.c - the ISR context: the state machine, protection and the
 * requests taken; see app.h. The start sequence that chains the start-up
 * steps is app_start.c (from flash), the background context (init,
 * requests) app_bg.c. */
#include "app.h"
#include "app_start.h"

#include <stddef.h>

/* Duty that gives zero line-to-line voltage: written whenever PWM goes off. */
#define DUTY_ZERO_VOLTAGE 0.5f

/* ---- outputs and faults ------------------------------------------------- */

/* PWM off first, then the bookkeeping: the outputs go off in this ISR call. */
void app_latch_fault(app_t *app, const app_step_t *f, const hal_sample_t *s)
{
    hal_pwm_disable();
    app->pwm_on = false;
    protect_snapshot(&app->snapshot, app->state, s, f);
    protect_watch_reset(&app->prot);
    app->state = APP_STATE_FAULT;
    app->fault = f->fault;
    if (f->fault == APP_FAULT_ENCODER) {
        app->aligned = false; /* counts were lost: the aligned offset no longer holds */
    }
}

/* A step's period written out: the duties unless the output is not
 * finite (the outputs go on after the first ones are written), then the
 * step's fault if it has one. */
app_step_t app_output(app_t *app, app_step_t r, const hal_sample_t *s)
{
    if ((app->out.flags & CTRL_FLAG_NONFINITE) == 0u) {
        hal_pwm_write(app->out.duty);
        if (!app->pwm_on) {
            hal_pwm_enable();
            app->pwm_on = true;
        }
    }
    if (r.status == APP_STEP_FAULT) {
        app_latch_fault(app, &r, s);
    }
    return r;
}

/* The controller's inputs: this period's samples, offsets subtracted. */
static ctrl_in_t ctrl_input(const app_t *app, const hal_sample_t *s)
{
    const ctrl_in_t in = { s->ia_A - app->offset_ia_A, s->ib_A - app->offset_ib_A, s->vdc_V, s->enc_count };
    return in;
}

static void stop_to_idle(app_t *app)
{
    const float d[3] = { DUTY_ZERO_VOLTAGE, DUTY_ZERO_VOLTAGE, DUTY_ZERO_VOLTAGE };

    hal_pwm_disable();
    app->pwm_on = false;
    hal_pwm_write(d);
    app->state = APP_STATE_IDLE;
}

/* ---- state steps, one per ISR call -------------------------------------- */

/* COMMISSION: the sequence's vector through ctrl's output path; done:
 * gates off, IDLE, the results valid, the measured offset taken. */
static void commission_state(app_t *app, const hal_sample_t *s)
{
    ab_t u;
    app_step_t r;

    { /* the inputs' scope ends here: 8 B less of app_isr's frame (the stack's RAM gate) */
        const ctrl_in_t in = ctrl_input(app, s);
        r = comm_step(app->comm, &in, ctrl_speed_m_rad_s(&app->ctrl), &u);
    }
    ctrl_step_ab(&app->ctrl, u, s->vdc_V, &app->out);
    if ((r.status != APP_STEP_FAULT) && ((app->out.flags & CTRL_FLAG_NONFINITE) != 0u)) {
        r = app_step_fault(APP_FAULT_NONFINITE_OUTPUT, u.a, 0.0f);
    }
    if (r.status == APP_STEP_DONE) {
        stop_to_idle(app);
        app->comm_valid = true;
        /* the ENCODER stage refuses unless the counts agree with the told pole pairs */
        encoder_set_offset(&app->ctrl.enc, app->comm->res.enc_offset_el_rad);
        app->aligned = true;
    } else {
        (void)app_output(app, r, s);
    }
}

/* In RAM with the ISR path: the link's capture reads it. */
uint16_t app_comm_result(const app_t *app)
{
    comm_outcome_t r = COMM_NONE;

    if (app->comm == NULL) {
        r = COMM_NONE;
    } else if (app->comm_valid) {
        r = COMM_DONE;
    } else if (app->state == APP_STATE_COMMISSION) {
        r = COMM_RUNNING;
    } else if ((app->state == APP_STATE_FAULT) && (app->snapshot.state == APP_STATE_COMMISSION)) {
        r = COMM_REFUSED;
    }
    return (uint16_t)r;
}

/* A refusal of R^ itself (not the controller's output, not its settings). */
static bool is_rsid_refusal(app_fault_t f)
{
    return (f == APP_FAULT_RSID_TOO_FEW) || (f == APP_FAULT_RSID_NOT_STEADY) || (f == APP_FAULT_RSID_DEGENERATE) ||
           (f == APP_FAULT_RSID_NON_FINITE) || (f == APP_FAULT_RSID_OUT_OF_BAND) || (f == APP_FAULT_RSID_D_AXIS);
}

static void identify_state(app_t *app, const hal_sample_t *s)
{
    const ctrl_in_t in = ctrl_input(app, s);
    app_step_t r = rsid_seq_step(&app->rsid, &app->ctrl, &in, &app->out);

    if ((r.status == APP_STEP_FAULT) && is_rsid_refusal(r.fault) &&
        (app->cfg.rsid.on_refusal != APP_RSID_REFUSAL_FAULT)) {
        /* no silent fallback: the warning names why; the observer was
         * stopped (est_rsid_finish_with): step 2 from the told R (TOLD), or
         * the conventional method, which also takes a refused start */
        app->rsid_refusal = r;
        app->warnings |= APP_WARN_STEP1_REFUSED;
        if ((app->cfg.rsid.on_refusal != APP_RSID_REFUSAL_TOLD) || !est_start_told(ctrl_est_rw(&app->ctrl))) {
            (void)ctrl_set_method(&app->ctrl, CTRL_METHOD_CONVENTIONAL);
        }
        r = app_step_done();
    }
    if (app_output(app, r, s).status == APP_STEP_DONE) {
        app->state = APP_STATE_RUN; /* step 2 runs from the next period; no reset */
    }
}

/* PWM_CHECK (level 1): the fixed duties, outputs on. */
static void pwm_check_state(app_t *app, const hal_sample_t *s)
{
    int16_t k;

    for (k = 0; k < 3; k++) {
        app->out.duty[k] = app->cfg.lvl.pwm_duty[k];
    }
    app->out.flags = 0u;
    (void)app_output(app, app_step_running(), s);
}

/* ADC_CHECK (level 2): outputs off, the readings into the report. */
static void adc_check_state(app_t *app, const hal_sample_t *s)
{
    app->adc.ia_A = s->ia_A;
    app->adc.ib_A = s->ib_A;
    app->adc.vdc_V = s->vdc_V;
}

/* ENC_CHECK (level 3): the turning vector through ctrl's output path; the
 * check's verdict ends it (IDLE) or latches its fault. */
static void enc_check_state(app_t *app, const hal_sample_t *s)
{
    const ab_t i = clarke_2ph(s->ia_A - app->offset_ia_A, s->ib_A - app->offset_ib_A);
    ab_t u;
    app_step_t r = level_rot_step(&app->rot, i.a, i.b, s->enc_count, &u);

    ctrl_step_ab(&app->ctrl, u, s->vdc_V, &app->out);
    if ((app->out.flags & CTRL_FLAG_NONFINITE) != 0u) {
        r = app_step_fault(APP_FAULT_NONFINITE_OUTPUT, u.a, 0.0f);
    }
    if (app_output(app, r, s).status == APP_STEP_DONE) {
        stop_to_idle(app);
    }
}

/* RUN: ctrl_step every period; after SPEEDS, at the handover ramp until
 * the outside reference is reached. */
static void run_state(app_t *app, const hal_sample_t *s)
{
    const ctrl_in_t in = ctrl_input(app, s);
    app_step_t r = app_step_running();

    if (app->rsid.handover) {
        rsid_seq_handover_step(&app->rsid, &app->ctrl, &in, &app->out);
    } else {
        ctrl_step(&app->ctrl, &in, &app->out);
    }
    if ((app->out.flags & CTRL_FLAG_NONFINITE) != 0u) {
        r = app_step_fault(APP_FAULT_NONFINITE_OUTPUT, 0.0f, 0.0f);
    }
    if ((est_output(ctrl_est(&app->ctrl))->hold & EST_HOLD_OSCILLATION) != 0u) {
        app->warnings |= APP_WARN_OSCILLATION; /* no silent fallback: the told model since */
    }
    (void)app_output(app, r, s);
}

/* The operator's request (app_request_op), whole, at the start of a
 * period: the references every time, a mode or method when the operator
 * changed it (the app's own choice, e.g. the conventional method after a
 * refused step 1, stands until then). */
static void take_operator(app_t *app)
{
    if (app->req_op != 0u) {
        const app_op_t op = app->op_req;
        app->req_op = 0u;
        ctrl_set_ref(&app->ctrl, &op.ref);
        /* level 4 holds its own mode and method (level_control) */
        if ((op.mode != app->op_taken.mode) && (app->level != LEVEL_TORQUE)) {
            ctrl_set_mode(&app->ctrl, op.mode);
        }
        if ((op.method != app->op_taken.method) && (app->level != LEVEL_TORQUE)) {
            (void)ctrl_set_method(&app->ctrl, op.method); /* refused: unchanged (cmd checks it first) */
        }
        app->op_taken = op;
    }
}

/* Background requests; stop wins over start. A fault reset is FAULT's
 * only: one found here is dropped, never kept for the next fault. */
static void take_requests(app_t *app, const hal_sample_t *s)
{
    app->req_fault_reset = 0u;
    if (app->req_stop != 0u) {
        app->req_stop = 0u;
        app->req_start = 0u;
        app->req_commission = 0u;
        if ((app->state != APP_STATE_INIT) && (app->state != APP_STATE_IDLE)) { /* FAULT is not here */
            stop_to_idle(app);
        }
    } else if ((app->req_start != 0u) || (app->req_commission != 0u)) {
        const bool commission = (app->req_commission != 0u); /* wins over a start asked for with it */
        app->req_start = 0u; /* ignored unless stopped */
        app->req_commission = 0u;
        if ((app->state == APP_STATE_INIT) || (app->state == APP_STATE_IDLE)) {
            app_start_sequence(app, s, commission);
        }
    }
}

static app_step_t protection(const app_t *app, const hal_sample_t *s)
{
    return protect_check(&app->prot, s, app->offset_ia_A, app->offset_ib_A, ctrl_speed_m_rad_s(&app->ctrl));
}

/* The checks on the periods' history; the duties written last call are the ones just applied. */
static app_step_t watch(app_t *app, const hal_sample_t *s)
{
    protect_watch_in_t in;

    in.ia_A = s->ia_A;
    in.ib_A = s->ib_A;
    in.ia_corr_A = s->ia_A - app->offset_ia_A;
    in.ib_corr_A = s->ib_A - app->offset_ib_A;
    in.vdc_V = s->vdc_V;
    in.duty = app->pwm_on ? app->out.duty : NULL;
    in.ctrl_running = (app->state == APP_STATE_RUN) || (app->state == APP_STATE_IDENTIFY_R);
    in.speed_m_rad_s = ctrl_speed_m_rad_s(&app->ctrl);
    in.te_ref_Nm = ctrl_monitor(&app->ctrl)->te_ref_Nm;
    return protect_watch(&app->prot, &in);
}

/* FAULT: outputs stay off; a reset is taken only if no check fails now,
 * and never from FLASH_CRC (the image itself is bad). */
static void fault_state(app_t *app, const hal_sample_t *s)
{
    app->req_start = 0u; /* a start asked for while faulted is not kept */
    app->req_commission = 0u;
    app->req_stop = 0u;
    if (app->req_fault_reset != 0u) {
        app->req_fault_reset = 0u;
        if ((app->fault != APP_FAULT_FLASH_CRC) && (protection(app, s).status != APP_STEP_FAULT)) {
            app->state = APP_STATE_IDLE;
            app->fault = APP_FAULT_NONE;
        }
    }
}

/* The states but RUN and FAULT: their step for this period. */
static void other_state(app_t *app, const hal_sample_t *s)
{
    switch (app->state) {
    case APP_STATE_CALIBRATE:
        app_calibrate_state(app, s);
        break;
    case APP_STATE_ALIGN:
        app_align_state(app, s);
        break;
    case APP_STATE_IDENTIFY_R:
        identify_state(app, s);
        break;
    case APP_STATE_PWM_CHECK:
        pwm_check_state(app, s);
        break;
    case APP_STATE_ADC_CHECK:
        adc_check_state(app, s);
        break;
    case APP_STATE_ENC_CHECK:
        enc_check_state(app, s);
        break;
    case APP_STATE_COMMISSION:
        commission_state(app, s);
        break;
    default: /* INIT, IDLE: outputs off, nothing to do */
        break;
    }
}

void app_isr(app_t *app)
{
    hal_sample_t s;
    uint32_t t_entry;
    app_step_t f;

    hal_sample_read(&s); /* first HAL call of the ISR (hal.h) */
    t_entry = hal_cycles();
    app->ticks++;
    protect_track(&app->prot, s.enc_count, t_entry);
    ctrl_track(&app->ctrl, s.enc_count); /* every state: the speed estimate protection checks */
    take_operator(app);

    if (app->state == APP_STATE_FAULT) {
        fault_state(app, &s);
    } else {
        f = protection(app, &s);
        if (f.status != APP_STEP_FAULT) {
            f = watch(app, &s);
        }
        if (f.status == APP_STEP_FAULT) {
            app_latch_fault(app, &f, &s);
        } else {
            take_requests(app, &s);
            if (app->state == APP_STATE_RUN) {
                run_state(app, &s); /* the common period first: no dispatch */
            } else {
                other_state(app, &s);
            }
        }
    }

    f = protect_run_time(&app->prot, t_entry, hal_cycles());
    if ((app->state != APP_STATE_FAULT) && (f.status == APP_STEP_FAULT)) {
        app_latch_fault(app, &f, &s);
    }
    hal_isr_ack();
}
