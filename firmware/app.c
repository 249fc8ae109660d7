/* app.c - ISR glue and drive state machine; see app.h. */
#include "app.h"

#include "mathx.h"

/* Duty that gives zero line-to-line voltage: written whenever PWM goes off. */
#define DUTY_ZERO_VOLTAGE 0.5f

static void write_zero_voltage(void)
{
    const float d[3] = { DUTY_ZERO_VOLTAGE, DUTY_ZERO_VOLTAGE, DUTY_ZERO_VOLTAGE };
    hal_pwm_write(d);
}

/* PWM off first, then the bookkeeping: the outputs go off in this ISR call. */
static void latch_fault(app_t *app, app_fault_t fault, const hal_sample_t *s)
{
    hal_pwm_disable();
    app->state = APP_STATE_FAULT;
    app->fault = fault;
    app->fault_snapshot = *s;
}

/* Protection on this period's samples; APP_FAULT_NONE when all is well. */
static app_fault_t check_samples(const app_t *app, const hal_sample_t *s)
{
    const float i_max = app->cfg.i_max_A;
    const float ic = -s->ia_A - s->ib_A;

    if (hal_trip_active()) {
        return APP_FAULT_HW_TRIP;
    }
    if (!mathx_isfinitef(s->ia_A + s->ib_A + s->vdc_V)) {
        return APP_FAULT_NONFINITE;
    }
    /* ! (x <= max): a NaN would also trip, though it is caught above */
    if (!(mathx_fabsf(s->ia_A) <= i_max) || !(mathx_fabsf(s->ib_A) <= i_max) ||
        !(mathx_fabsf(ic) <= i_max)) {
        return APP_FAULT_OVERCURRENT;
    }
    return APP_FAULT_NONE;
}

void app_init(app_t *app, const app_cfg_t *cfg)
{
    hal_pwm_disable();
    app->cfg = *cfg;
    app->state = APP_STATE_IDLE;
    app->fault = APP_FAULT_NONE;
    app->fault_snapshot.ia_A = 0.0f;
    app->fault_snapshot.ib_A = 0.0f;
    app->fault_snapshot.vdc_V = 0.0f;
    app->fault_snapshot.enc_count = 0u;
    ctrl_init(&app->ctrl, &cfg->ctrl);
    app->out.duty[0] = DUTY_ZERO_VOLTAGE;
    app->out.duty[1] = DUTY_ZERO_VOLTAGE;
    app->out.duty[2] = DUTY_ZERO_VOLTAGE;
    app->out.flags = 0u;
    app->ticks = 0u;
    app->req_start = 0u;
    app->req_stop = 0u;
    app->req_fault_reset = 0u;
}

void app_isr(app_t *app)
{
    hal_sample_t s;
    ctrl_in_t in;
    app_fault_t f;
    bool entering = false;

    hal_sample_read(&s);
    app->ticks++;

    if (app->state == APP_STATE_FAULT) {
        if (app->req_fault_reset != 0u) {
            app->req_fault_reset = 0u;
            if (check_samples(app, &s) == APP_FAULT_NONE) {
                app->state = APP_STATE_IDLE;
                app->fault = APP_FAULT_NONE;
            }
        }
        app->req_start = 0u; /* a start asked for while faulted is not kept */
        hal_isr_ack();
        return;
    }

    f = check_samples(app, &s);
    if (f != APP_FAULT_NONE) {
        latch_fault(app, f, &s);
        hal_isr_ack();
        return;
    }

    if (app->req_stop != 0u) {
        app->req_stop = 0u;
        app->req_start = 0u;
        if (app->state == APP_STATE_RUN) {
            hal_pwm_disable();
            write_zero_voltage();
            app->state = APP_STATE_IDLE;
        }
        hal_isr_ack();
        return;
    }

    if ((app->state == APP_STATE_IDLE) && (app->req_start != 0u)) {
        app->req_start = 0u;
        ctrl_reset(&app->ctrl);
        app->state = APP_STATE_RUN;
        entering = true;
    }

    if (app->state == APP_STATE_RUN) {
        in.ia_A = s.ia_A;
        in.ib_A = s.ib_A;
        in.vdc_V = s.vdc_V;
        in.enc_count = s.enc_count;
        ctrl_step(&app->ctrl, &in, &app->out);
        if ((app->out.flags & CTRL_FLAG_NONFINITE) != 0u) {
            latch_fault(app, APP_FAULT_NONFINITE, &s);
        } else {
            hal_pwm_write(app->out.duty);
            if (entering) {
                hal_pwm_enable(); /* after the first duties are written */
            }
        }
    }
    hal_isr_ack();
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

void app_request_stop(app_t *app)
{
    app->req_stop = 1u;
}

void app_fault_reset(app_t *app)
{
    hal_trip_clear();
    app->req_fault_reset = 1u;
}
