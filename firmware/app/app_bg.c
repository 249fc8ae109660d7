/* app_bg.c - the application's start-up and background context: app_init
 * and the requests the ISR takes at the start of its next call (app.c);
 * see app.h. */
#include "app.h"

/* Duty that gives zero line-to-line voltage: the outputs' state while off. */
#define DUTY_ZERO_VOLTAGE 0.5f

/* The start-up steps and protection from app->cfg (app_init, app_reconfigure). */
static void app_init_steps(app_t *app)
{
    const app_cfg_t *cfg = &app->cfg;
    const float Ts = cfg->ctrl.Ts_s;
    const protect_drive_t drv = { Ts, APP_ENC_COUNTS_PER_LINE * cfg->ctrl.enc_lines, cfg->ctrl.te_max_Nm,
                                  cfg->ctrl.pole_pairs, cfg->ctrl.psi_f_Wb };

    protect_init(&app->prot, &cfg->prot, &drv);
    calib_init(&app->cal, &cfg->cal, Ts);
    align_init(&app->aln, &cfg->aln, Ts);
    rsid_seq_init(&app->rsid, &cfg->rsid, Ts);
    level_rot_init(&app->rot, &cfg->lvl, &cfg->ctrl, Ts);
}

void app_init(app_t *app, const app_cfg_t *cfg)
{
    const app_snapshot_t no_snapshot = { { 0.0f, 0.0f, 0.0f, 0u }, APP_STATE_INIT, 0.0f, 0.0f };
    const ctrl_out_t zero_voltage = { { DUTY_ZERO_VOLTAGE, DUTY_ZERO_VOLTAGE, DUTY_ZERO_VOLTAGE }, 0u };

    hal_pwm_disable();
    if (cfg != &app->cfg) {
        app->cfg = *cfg; /* main.c builds it in place */
    }
    app->state = APP_STATE_INIT;
    app->fault = APP_FAULT_NONE;
    app->snapshot = no_snapshot;
    (void)ctrl_init(&app->ctrl, &cfg->ctrl); /* status kept in ctrl.status; a start checks it when needed */
    app->out = zero_voltage;
    app->ticks = 0u;
    app->i2t_ticks = 0u;
    app->i2t_used_A2s = 0.0f;
    app->i2t_limited = false;
    app->offset_ia_A = 0.0f;
    app->offset_ib_A = 0.0f;
    app->aligned = false;
    app->pwm_on = false;
    app_init_steps(app);
    app->comm = NULL;
    app->commissioning = false;
    app->comm_valid = false;
    app->req_commission = 0u;
    app->level = cfg->lvl.level;
    app->req_level = cfg->lvl.level;
    app->adc.ia_A = 0.0f;
    app->adc.ib_A = 0.0f;
    app->adc.vdc_V = 0.0f;
    app->warnings = 0u;
    app->vdc_V = 0.0f;
    app->fault_present = (uint16_t)APP_FAULT_NONE;
    app->rsid_refusal = app_step_running();
    app->req_start = 0u;
    app->req_stop = 0u;
    app->req_fault_reset = 0u;
    app->req_warning = 0u;
    app->req_reconfigure = 0u;
    app->op_taken.ref = *ctrl_ref(&app->ctrl);
    app->op_taken.mode = ctrl_mode(&app->ctrl);
    app->op_taken.method = ctrl_method(&app->ctrl);
    app_request_op(app, &app->op_taken);
    app->req_op = 0u;
}

void app_latch_startup_fault(app_t *app, app_fault_t fault, float value, float limit)
{
    const hal_sample_t none = { 0.0f, 0.0f, 0.0f, 0u };
    const app_step_t f = app_step_fault(fault, value, limit);

    hal_pwm_disable();
    app->pwm_on = false;
    protect_snapshot(&app->snapshot, app->state, &none, &f);
    app->state = APP_STATE_FAULT;
    app->fault = fault;
}

/* The budget is given back down to this share before the peak current is again allowed. */
#define I2T_RESTORE_SHARE 0.5f

/* The I^2t budget over the ISR periods since the last call. */
static void i2t_step(app_t *app)
{
    const app_cfg_t *c = &app->cfg;
    const uint32_t now = app->ticks;
    const ctrl_mon_t *m = ctrl_monitor(&app->ctrl);
    const float dt_s = (float)(now - app->i2t_ticks) * c->ctrl.Ts_s;
    const float i2 = (app->state == APP_STATE_RUN || app->state == APP_STATE_IDENTIFY_R)
                         ? (m->id_A * m->id_A + m->iq_A * m->iq_A) : 0.0f;
    float used = app->i2t_used_A2s + (i2 - c->i2t_rated_A * c->i2t_rated_A) * dt_s;

    app->i2t_ticks = now;
    used = (used > 0.0f) ? used : 0.0f;
    used = (used < c->i2t_budget_A2s) ? used : c->i2t_budget_A2s;
    app->i2t_used_A2s = used;
    if (!app->i2t_limited && (used >= c->i2t_budget_A2s)) {
        app->i2t_limited = true;
        ctrl_set_i_limit(&app->ctrl, c->i2t_rated_A);
    } else if (app->i2t_limited && (used <= I2T_RESTORE_SHARE * c->i2t_budget_A2s)) {
        app->i2t_limited = false;
        ctrl_set_i_limit(&app->ctrl, 0.0f); /* the configured limit again */
    } else {
        /* unchanged */
    }
}

void app_background(app_t *app)
{
    if ((app->cfg.i2t_rated_A > 0.0f) && (app->cfg.i2t_budget_A2s > 0.0f)) {
        i2t_step(app);
    }
    hal_watchdog_kick();
}

void app_request_start(app_t *app)
{
    app->req_start = 1u;
}

void app_attach_comm(app_t *app, comm_t *comm)
{
    const app_cfg_t *cfg = &app->cfg;

    comm_init(comm, &cfg->comm, cfg->ctrl.Ts_s, APP_ENC_COUNTS_PER_LINE * cfg->ctrl.enc_lines, cfg->ctrl.pole_pairs);
    app->comm = comm;
}

void app_request_commission(app_t *app)
{
    if (app->comm != NULL) {
        app->req_commission = 1u;
    }
}

void app_request_op(app_t *app, const app_op_t *op)
{
    app->req_op = 0u; /* the ISR cannot take a half-written request */
    app->op_req.ref = op->ref;
    app->op_req.mode = op->mode;
    app->op_req.method = op->method;
    app->req_op = 1u;
}

void app_request_level(app_t *app, uint16_t level)
{
    if ((level >= LEVEL_MIN) && (level <= LEVEL_MAX)) {
        app->req_level = level;
    }
}

void app_request_warning(app_t *app, uint16_t bits)
{
    app->req_warning = bits; /* one store: the ISR takes it whole */
}

void app_request_reconfigure(app_t *app, uint16_t flags)
{
    app->req_reconfigure = (uint16_t)(app->req_reconfigure | flags | APP_RECONF_ASKED);
}

/* ---- a new configuration, the drive stopped ----------------------------- */

/* The encoder's geometry and PLL in *e are those *c asks for: its tracking can go on. */
static bool same_encoder(const encoder_t *e, const ctrl_cfg_t *c)
{
    const encoder_cfg_t *ec = &e->cfg;
    return (ec->counts_per_rev == ENCODER_COUNTS_PER_LINE * c->enc_lines) && (ec->pole_pairs == c->pole_pairs) &&
           !(ec->pll_bw_rad_s < c->enc_pll_bw_rad_s) && !(ec->pll_bw_rad_s > c->enc_pll_bw_rad_s) &&
           !(ec->Ts_s < c->Ts_s) && !(ec->Ts_s > c->Ts_s);
}

/* The ISR held off (app_reconfigure_now): the controller and the start-up steps from app->cfg
 * again (app_request_reconfigure's flags). */
static void app_reconfigure(app_t *app, uint16_t flags)
{
    const app_cfg_t *cfg = &app->cfg;
    const bool same = same_encoder(&app->ctrl.enc, &cfg->ctrl);
    const float offset_in_use = app->ctrl.enc.offset_el_rad; /* aligned or told: cfg's is the told one */

    /* status kept in ctrl.status (a start checks it); the encoder from cfg, its tracking from the
     * next count (the periods held off were not tracked) */
    (void)ctrl_init(&app->ctrl, &cfg->ctrl);
    if (!same) {
        app->aligned = false; /* another geometry: an aligned offset no longer holds */
    } else if ((flags & APP_RECONF_ENC_OFFSET) == 0u) {
        encoder_set_offset(&app->ctrl.enc, offset_in_use);
    } else {
        /* the configuration's offset, as ctrl_init set it */
    }
    if ((flags & APP_RECONF_ENC_OFFSET) != 0u) {
        app->aligned = true; /* told as measured: no alignment at the next start */
    }
    ctrl_set_ref(&app->ctrl, &app->op_taken.ref);
    ctrl_set_mode(&app->ctrl, app->op_taken.mode);
    (void)ctrl_set_method(&app->ctrl, app->op_taken.method);
    app_init_steps(app);
    if (app->comm != NULL) {
        const comm_result_t res = app->comm->res; /* the measured values stay readable */
        comm_init(app->comm, &cfg->comm, cfg->ctrl.Ts_s, APP_ENC_COUNTS_PER_LINE * cfg->ctrl.enc_lines,
                  cfg->ctrl.pole_pairs);
        app->comm->res = res;
    }
}

bool app_stopped(const app_t *app)
{
    return (app->state == APP_STATE_INIT) || (app->state == APP_STATE_IDLE) || (app->state == APP_STATE_FAULT);
}

bool app_reconfigure_due(const app_t *app)
{
    return (app->req_reconfigure != 0u) && app_stopped(app);
}

void app_reconfigure_now(app_t *app)
{
    if (!app_reconfigure_due(app)) {
        return;   /* read again with the ISR held off: a start taken meanwhile waits for the next */
    }
    app_reconfigure(app, app->req_reconfigure);
    app->req_reconfigure = 0u;
}

void app_request_stop(app_t *app)
{
    app->req_stop = 1u;
}

void app_fault_reset(app_t *app)
{
    /* Only the ISR leaves FAULT, and only on this request: a FAULT read here
     * still holds when the ISR takes it. Outside FAULT hal_trip_clear() would
     * force the outputs off under the running drive, and a kept request
     * would clear the next fault with no operator action. */
    if (app->state == APP_STATE_FAULT) {
        hal_trip_clear();
        app->req_fault_reset = 1u;
    }
}
