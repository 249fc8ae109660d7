/* app_start.c - the app's start sequence (app.h): the transitions a
 * start or a commissioning takes, once per start, and the CALIBRATE and
 * ALIGN steps. ISR context, called by app.c; a file of its own because it
 * runs from flash (firmware/target.mk FLASH_ISR_SRCS): each function runs
 * once per start, or in CALIBRATE or ALIGN, before the drive takes the
 * user's reference. */
#include "app_start.h"

static void enter_run(app_t *app)
{
    ctrl_reset(&app->ctrl);
    app->state = APP_STATE_RUN;
    app->rsid.handover = false;
}

/* After ALIGN, done or skipped: step 1 of the proposed method, or RUN
 * (level 4: RUN, no step 1 or 2). */
static void leave_align(app_t *app)
{
    if ((app->cfg.rsid.mode == APP_RSID_OFF) || (app->level == LEVEL_TORQUE)) {
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

/* The controller's blocks this start needs (ctrl.h CTRL_CFG_NEEDED_*). */
static ctrl_status_t config_needed(const app_t *app)
{
    return ((app->cfg.rsid.mode == APP_RSID_OFF) || (app->level < LEVEL_FULL)) ? CTRL_CFG_NEEDED_ALWAYS
                                                : (ctrl_status_t)(CTRL_CFG_NEEDED_ALWAYS | CTRL_CFG_NEEDED_PROPOSED);
}

/* CONFIG when a controller block in needed or the parameter set (the
 * ratings, the ADC range: they bound a commissioning's currents too) was
 * refused; the value: ctrl_init's refusals, the parameter set's above them. */
static app_step_t config_refusal(const app_t *app, ctrl_status_t needed)
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
static void leave_calibrate(app_t *app, const hal_sample_t *s)
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
static void level_control(app_t *app, uint16_t was)
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
void app_start_sequence(app_t *app, const hal_sample_t *s, bool commission)
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
        protect_disarm_uv(&app->prot);
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

/* ---- its steps, one per ISR call --------------------------------------- */

void app_calibrate_state(app_t *app, const hal_sample_t *s)
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

/* The alignment's vector through ctrl's output path; then the count reads 0 rad. */
void app_align_state(app_t *app, const hal_sample_t *s)
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
