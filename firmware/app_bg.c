/* app_bg.c - the application's start-up and background context: app_init
 * and the requests the ISR takes at the start of its next call (app.c);
 * see app.h. */
#include "app.h"

/* Duty that gives zero line-to-line voltage: the outputs' state while off. */
#define DUTY_ZERO_VOLTAGE 0.5f
#define ENC_COUNTS_PER_LINE 4u      /* x4 quadrature decoding */

void app_init(app_t *app, const app_cfg_t *cfg)
{
    const float Ts = cfg->ctrl.Ts_s;
    const app_snapshot_t no_snapshot = { { 0.0f, 0.0f, 0.0f, 0u }, APP_STATE_INIT, 0.0f, 0.0f };
    const ctrl_out_t zero_voltage = { { DUTY_ZERO_VOLTAGE, DUTY_ZERO_VOLTAGE, DUTY_ZERO_VOLTAGE }, 0u };
    protect_cfg_t pc = { cfg->i_max_A, cfg->vdc_max_V, cfg->vdc_min_V, cfg->speed_max_rad_s,
                         cfg->isr_period_cycles, cfg->isr_budget_cycles,
                         ENC_COUNTS_PER_LINE * cfg->ctrl.enc_lines, Ts, cfg->watch };
    const calib_cfg_t cc = { cfg->cal_settle_s, cfg->cal_samples, cfg->offset_max_A };
    const align_cfg_t ac = { cfg->align_u_V, cfg->align_prepos_el_rad, cfg->align_ramp_s, cfg->align_prepos_s,
                             cfg->align_settle_s };
    const rsid_seq_cfg_t rc = { cfg->rsid_mode, cfg->rsid_settle_1_s, cfg->rsid_window_s, cfg->rsid_settle_2_s,
                                cfg->rsid_speed_1_rad_s, cfg->rsid_speed_2_rad_s, cfg->rsid_accel_rad_s2,
                                cfg->rsid_window_max_s, cfg->rsid_repeats_max };

    pc.watch.te_max_Nm = cfg->ctrl.te_max_Nm;
    pc.watch.pole_pairs = cfg->ctrl.pole_pairs;
    hal_pwm_disable();
    app->cfg = *cfg;
    app->state = APP_STATE_INIT;
    app->fault = APP_FAULT_NONE;
    app->snapshot = no_snapshot;
    (void)ctrl_init(&app->ctrl, &cfg->ctrl); /* status kept in ctrl.status; a start checks it when needed */
    app->out = zero_voltage;
    app->ticks = 0u;
    app->offset_ia_A = 0.0f;
    app->offset_ib_A = 0.0f;
    app->aligned = false;
    app->pwm_on = false;
    protect_init(&app->prot, &pc);
    calib_init(&app->cal, &cc, Ts);
    align_init(&app->aln, &ac, Ts);
    rsid_seq_init(&app->rsid, &rc, Ts);
    app->warnings = 0u;
    app->rsid_refusal = app_step_running();
    app->req_start = 0u;
    app->req_stop = 0u;
    app->req_fault_reset = 0u;
    app->op_taken.ref = *ctrl_ref(&app->ctrl);
    app->op_taken.mode = ctrl_mode(&app->ctrl);
    app->op_taken.method = ctrl_method(&app->ctrl);
    app_request_op(app, &app->op_taken);
    app->req_op = 0u;
}

void app_background(app_t *app)
{
    (void)app;
    hal_watchdog_kick();
}

void app_request_start(app_t *app)
{
    app->req_start = 1u;
}

void app_request_op(app_t *app, const app_op_t *op)
{
    app->req_op = 0u; /* the ISR cannot take a half-written request */
    app->op_req.ref = op->ref;
    app->op_req.mode = op->mode;
    app->op_req.method = op->method;
    app->req_op = 1u;
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
