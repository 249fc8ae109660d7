/* app.c - the ISR context: the state machine, protection, the requests
 * taken and the start sequence that chains the start-up steps; see app.h.
 * The background context (init, requests) is app_bg.c. */
#include "app.h"

#include <stddef.h>

/* Duty that gives zero line-to-line voltage: written whenever PWM goes off. */
#define DUTY_ZERO_VOLTAGE 0.5f

/* ---- outputs and faults ------------------------------------------------- */

/* PWM off first, then the bookkeeping: the outputs go off in this ISR call. */
RAMFUNC static void app_latch_fault(app_t *app, const app_step_t *f, const hal_sample_t *s)
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
RAMFUNC static inline app_step_t app_output(app_t *app, app_step_t r, const hal_sample_t *s)
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
RAMFUNC static ctrl_in_t ctrl_input(const app_t *app, const hal_sample_t *s)
{
    const ctrl_in_t in = { s->ia_A - app->offset_ia_A, s->ib_A - app->offset_ib_A, s->vdc_V, s->enc_count };
    return in;
}

RAMFUNC static void stop_to_idle(app_t *app)
{
    const float d[3] = { DUTY_ZERO_VOLTAGE, DUTY_ZERO_VOLTAGE, DUTY_ZERO_VOLTAGE };

    hal_pwm_disable();
    app->pwm_on = false;
    hal_pwm_write(d);
    app->state = APP_STATE_IDLE;
}

/* Levels 1-2 (level.h): the bus within their extra-low limit, else
 * BUS_CHARGED (a NaN bus refused too). Flash: a build level's check. */
FLASHFUNC static app_step_t level12_bus(const app_t *app, const hal_sample_t *s)
{
    if (!(s->vdc_V <= app->cfg.lvl.vdc_max_12_V)) {
        return app_step_fault(APP_FAULT_BUS_CHARGED, s->vdc_V, app->cfg.lvl.vdc_max_12_V);
    }
    return app_step_running();
}

/* ---- the start sequence, from flash (FLASHFUNC): the transitions a start
 * or a commissioning takes, once per start, and the CALIBRATE and ALIGN
 * steps, before the drive takes the user's reference ------------------- */

FLASHFUNC static void enter_run(app_t *app)
{
    ctrl_reset(&app->ctrl);
    app->state = APP_STATE_RUN;
    app->rsid.handover = false;
}

/* The proposed method's blocks were accepted by ctrl_init. */
FLASHFUNC static bool proposed_available(const app_t *app)
{
    return (ctrl_status(&app->ctrl) & CTRL_CFG_NEEDED_PROPOSED) == 0u;
}

/* After ALIGN, done or skipped: step 1 of the proposed method, or RUN
 * (level 4: RUN, no step 1 or 2; the conventional method asked for on a
 * motor the proposed method's blocks refused: RUN, nothing to identify). */
FLASHFUNC static void leave_align(app_t *app)
{
    if ((app->cfg.rsid.mode == APP_RSID_OFF) || (app->level == LEVEL_TORQUE) || !proposed_available(app)) {
        enter_run(app);
    } else if (app->cfg.rsid.mode == APP_RSID_TRUSTED) {
        enter_run(app);
        (void)est_start_trusted(ctrl_est_rw(&app->ctrl), app->cfg.ctrl.R_Ohm); /* nominal R is in its own band */
    } else {
        ctrl_reset(&app->ctrl);
        (void)est_rsid_begin(ctrl_est_rw(&app->ctrl)); /* status checked by leave_calibrate */
        app->state = APP_STATE_IDENTIFY_R;
        rsid_seq_start(&app->rsid, ctrl_speed_m_rad_s(&app->ctrl));
    }
}

/* The controller's blocks this start needs (ctrl.h CTRL_CFG_NEEDED_*):
 * the proposed method's only for the proposed method asked for (the
 * operator's request: ctrl_set_method refuses it on such a motor) at the
 * full level with step 1 or a trusted R; the conventional method never
 * reads them, whatever [identify] says. */
FLASHFUNC static ctrl_status_t config_needed(const app_t *app)
{
    const bool proposed = (app->op_taken.method == CTRL_METHOD_PROPOSED);
    return (!proposed || (app->cfg.rsid.mode == APP_RSID_OFF) || (app->level < LEVEL_FULL))
               ? CTRL_CFG_NEEDED_ALWAYS
               : (ctrl_status_t)(CTRL_CFG_NEEDED_ALWAYS | CTRL_CFG_NEEDED_PROPOSED);
}

/* CONFIG when a controller block in needed or the parameter set (the
 * ratings, the ADC range: they bound a commissioning's currents too) was
 * refused; the value: ctrl_init's refusals, the parameter set's above them. */
FLASHFUNC static app_step_t config_refusal(const app_t *app, ctrl_status_t needed)
{
    if (((ctrl_status(&app->ctrl) & needed) != 0u) || (app->cfg.params_refused != 0u)) {
        const uint16_t why =
            (uint16_t)(ctrl_status(&app->ctrl) | (uint16_t)(app->cfg.params_refused << APP_PARAMS_REFUSED_SHIFT));
        return app_step_fault(APP_FAULT_CONFIG, (float)why, 0.0f);
    }
    return app_step_running();
}

/* After CALIBRATE, done or skipped: the bus must be up from here on, and
 * every controller block this start needs accepted by ctrl_init (CONFIG,
 * the refusals in the snapshot's value); both are checked on this call's
 * samples before anything is energised. */
FLASHFUNC static void leave_calibrate(app_t *app, const hal_sample_t *s)
{
    const bool bus = (app->level > LEVEL_ADC); /* levels 1-2 run without the DC bus */
    /* the told R, L, psi_f play no part in a commissioning: it needs only the encoder's speed estimate */
    const app_step_t cfg = config_refusal(app, app->commissioning ? CTRL_CFG_ENCODER : config_needed(app));

    if (bus) {
        protect_arm_uv(&app->prot);
    }
    if (bus && (s->vdc_V < app->cfg.prot.vdc_min_V)) {
        const app_step_t f = app_step_fault(APP_FAULT_UNDERVOLTAGE, s->vdc_V, app->cfg.prot.vdc_min_V);
        app_latch_fault(app, &f, s);
    } else if (cfg.status == APP_STEP_FAULT) {
        app_latch_fault(app, &cfg, s);
    } else if (app->commissioning) {
        ctrl_reset(&app->ctrl);
        app->state = APP_STATE_COMMISSION;
        comm_start(app->comm);
    } else if (app->level == LEVEL_ADC) {
        app->state = APP_STATE_ADC_CHECK;
    } else if (app->level == LEVEL_ROTATE) {
        app->state = APP_STATE_ENC_CHECK;
        level_rot_start(&app->rot);
    } else if (app->cfg.align && !app->aligned) {
        app->state = APP_STATE_ALIGN;
        align_start(&app->aln);
    } else {
        leave_align(app);
    }
}

/* Level 4's own current limit, mode and method; the operator's mode and
 * method (and the configured limit) back at the first start at another
 * level. */
FLASHFUNC static void level_control(app_t *app, uint16_t was)
{
    if (app->level == LEVEL_TORQUE) {
        ctrl_set_i_lim(&app->ctrl, app->cfg.lvl.i_lim_4_A);
        ctrl_set_mode(&app->ctrl, CTRL_MODE_TORQUE);
        (void)ctrl_set_method(&app->ctrl, CTRL_METHOD_CONVENTIONAL);
    } else if (was == LEVEL_TORQUE) {
        ctrl_set_i_lim(&app->ctrl, app->cfg.ctrl.i_lim_A);
        ctrl_set_mode(&app->ctrl, app->op_taken.mode);
        (void)ctrl_set_method(&app->ctrl, app->op_taken.method);
    }
}

/* A start, or (commission) a commissioning: that runs as at the full
 * level (the bus armed, no level's check), whatever level is asked for. */
FLASHFUNC static void start_sequence(app_t *app, const hal_sample_t *s, bool commission)
{
    const uint16_t was = app->level;

    app->level = commission ? LEVEL_FULL : app->req_level;
    app->commissioning = commission;
    if (commission) {
        app->comm_valid = false;
    }
    app->warnings = 0u;
    app->rsid_refusal = app_step_running();
    level_control(app, was);
    if (app->level <= LEVEL_ADC) {
        const app_step_t bus = level12_bus(app, s);
        protect_disarm_uv(&app->prot);
        if (bus.status == APP_STEP_FAULT) {
            app_latch_fault(app, &bus, s); /* before any gate switches */
            return;
        }
    }
    if (app->level == LEVEL_PWM) {
        app->state = APP_STATE_PWM_CHECK;
    } else if (app->cfg.calibrate || (app->level == LEVEL_ADC)) {
        app->state = APP_STATE_CALIBRATE;
        calib_start(&app->cal);
    } else {
        leave_calibrate(app, s);
    }
}

/* CALIBRATE's period: the offsets; done: the next state of the sequence. */
FLASHFUNC static void calibrate_state(app_t *app, const hal_sample_t *s)
{
    const app_step_t r = calib_step(&app->cal, s->ia_A, s->ib_A);

    if (r.status == APP_STEP_FAULT) {
        app_latch_fault(app, &r, s);
    } else if (r.status == APP_STEP_DONE) {
        app->offset_ia_A = app->cal.offset_ia_A;
        app->offset_ib_A = app->cal.offset_ib_A;
        leave_calibrate(app, s);
    }
}

/* ALIGN's period: the alignment's vector through ctrl's output path;
 * done: the count reads 0 rad, the next state of the sequence. */
FLASHFUNC static void align_state(app_t *app, const hal_sample_t *s)
{
    ab_t u;
    app_step_t r = align_step(&app->aln, &u);

    ctrl_step_ab(&app->ctrl, u, s->vdc_V, &app->out);
    if ((app->out.flags & CTRL_FLAG_NONFINITE) != 0u) {
        r = app_step_fault(APP_FAULT_NONFINITE_OUTPUT, u.a, 0.0f);
    }
    if ((app_output(app, r, s).status == APP_STEP_DONE)) {
        ctrl_encoder_align(&app->ctrl, s->enc_count);
        app->aligned = true;
        leave_align(app);
    }
}

/* ---- state steps, one per ISR call -------------------------------------- */

/* COMMISSION: the sequence's vector through ctrl's output path; done:
 * gates off, IDLE, the results valid, the measured offset taken. */
RAMFUNC static void commission_state(app_t *app, const hal_sample_t *s)
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
RAMFUNC uint16_t app_comm_result(const app_t *app)
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
RAMFUNC static bool is_rsid_refusal(app_fault_t f)
{
    return (f == APP_FAULT_RSID_TOO_FEW) || (f == APP_FAULT_RSID_NOT_STEADY) || (f == APP_FAULT_RSID_DEGENERATE) ||
           (f == APP_FAULT_RSID_NON_FINITE) || (f == APP_FAULT_RSID_OUT_OF_BAND) || (f == APP_FAULT_RSID_D_AXIS) ||
           (f == APP_FAULT_RSID_INVERTER);
}

RAMFUNC static void identify_state(app_t *app, const hal_sample_t *s)
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

/* ---- the build levels 1-3 (level.h), from flash (FLASHFUNC): bring-up
 * states, the motor not under the user's control ------------------------ */

/* PWM_CHECK (level 1): the fixed duties, outputs on; a bus charged
 * meanwhile latches BUS_CHARGED before the duties are written. */
FLASHFUNC static void pwm_check_state(app_t *app, const hal_sample_t *s)
{
    const app_step_t bus = level12_bus(app, s);
    int16_t k;

    if (bus.status == APP_STEP_FAULT) {
        app_latch_fault(app, &bus, s);
        return;
    }
    for (k = 0; k < 3; k++) {
        app->out.duty[k] = app->cfg.lvl.pwm_duty[k];
    }
    app->out.flags = 0u;
    (void)app_output(app, app_step_running(), s);
}

/* ADC_CHECK (level 2): outputs off, the readings into the report; a bus
 * charged meanwhile latches BUS_CHARGED. */
FLASHFUNC static void adc_check_state(app_t *app, const hal_sample_t *s)
{
    const app_step_t bus = level12_bus(app, s);

    app->adc.ia_A = s->ia_A;
    app->adc.ib_A = s->ib_A;
    app->adc.vdc_V = s->vdc_V;
    if (bus.status == APP_STEP_FAULT) {
        app_latch_fault(app, &bus, s);
    }
}

/* ENC_CHECK (level 3): the turning vector through ctrl's output path; the
 * check's verdict ends it (IDLE) or latches its fault. */
FLASHFUNC static void enc_check_state(app_t *app, const hal_sample_t *s)
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
RAMFUNC static void run_state(app_t *app, const hal_sample_t *s)
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

/* The background's warnings (app_request_warning), at the start of a period. */
RAMFUNC static void take_warnings(app_t *app)
{
    app->warnings |= app->req_warning;
    app->req_warning = 0u;
}

/* The operator's request (app_request_op),
 * whole, at the start of a period: the references every time, a mode or method when the operator
 * changed it (the app's own choice, e.g. the conventional method after a
 * refused step 1, stands until then). */
RAMFUNC static void take_operator(app_t *app)
{
    if (app->req_warning != 0u) {
        take_warnings(app);
    }
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
RAMFUNC static void take_requests(app_t *app, const hal_sample_t *s)
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
            start_sequence(app, s, commission);
        }
    }
}

RAMFUNC static app_step_t protection(const app_t *app, const hal_sample_t *s)
{
    return protect_check(&app->prot, s, app->offset_ia_A, app->offset_ib_A, ctrl_speed_m_rad_s(&app->ctrl));
}

/* The checks on the periods' history; the duties written last call are the ones just applied. */
RAMFUNC static app_step_t watch(app_t *app, const hal_sample_t *s)
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
    in.i_aim_alpha_A = ctrl_monitor(&app->ctrl)->i_aim_alpha_A; /* where the last step aimed the current */
    in.i_aim_beta_A = ctrl_monitor(&app->ctrl)->i_aim_beta_A;
    return protect_watch(&app->prot, &in);
}

/* The monitor's readings of a period ctrl_step did not run in. */
RAMFUNC static void readings(app_t *app, const hal_sample_t *s)
{
    const ctrl_in_t in = ctrl_input(app, s);
    ctrl_monitor_readings(&app->ctrl, &in, app->pwm_on);
}

/* A fault reset asked for: taken only if no check fails now, and never
 * from FLASH_CRC (the image itself is bad). Flash: once per reset, and its
 * copy of the inline checks stays out of RAM. */
FLASHFUNC static void fault_reset(app_t *app, const hal_sample_t *s)
{
    if (app->fault == APP_FAULT_FLASH_CRC) {
        app->fault_present = (uint16_t)APP_FAULT_FLASH_CRC; /* the image itself: no check clears it */
        return;
    }
    const app_step_t now = protection(app, s);
    if (now.status == APP_STEP_FAULT) {
        app->fault_present = (uint16_t)now.fault; /* the cause is still there: said, not cleared */
    } else {
        app->fault_present = (uint16_t)APP_FAULT_NONE;
        app->state = APP_STATE_IDLE;
        app->fault = APP_FAULT_NONE;
    }
}

/* FAULT: outputs stay off; a reset asked for is tried (fault_reset). */
RAMFUNC static void fault_state(app_t *app, const hal_sample_t *s)
{
    app->req_start = 0u; /* a start asked for while faulted is not kept */
    app->req_commission = 0u;
    app->req_stop = 0u;
    if (app->req_fault_reset != 0u) {
        app->req_fault_reset = 0u;
        fault_reset(app, s);
    }
}

/* The states but RUN and FAULT: their step for this period. */
RAMFUNC static void other_state(app_t *app, const hal_sample_t *s)
{
    switch (app->state) {
    case APP_STATE_CALIBRATE:
        calibrate_state(app, s);
        break;
    case APP_STATE_ALIGN:
        align_state(app, s);
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

RAMFUNC void app_isr(app_t *app)
{
    hal_sample_t s;
    uint32_t t_entry;
    app_step_t f;

    hal_sample_read(&s); /* first HAL call of the ISR (hal.h) */
    t_entry = hal_cycles();
    app->ticks++;
    app->vdc_V = s.vdc_V;
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
    if ((app->state != APP_STATE_RUN) && (app->state != APP_STATE_IDENTIFY_R)) {
        readings(app, &s); /* a state ctrl_step did not run in: the monitor's readings all the same */
    }
    f = protect_run_time(&app->prot, t_entry, hal_cycles());
    if ((app->state != APP_STATE_FAULT) && (f.status == APP_STEP_FAULT)) {
        app_latch_fault(app, &f, &s);
    }
    hal_isr_ack();
}
