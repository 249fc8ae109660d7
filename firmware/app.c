/* app.c - ISR glue, start-up sequence and protection; see app.h. */
#include "app.h"

#include "board_cfg.h"
#include "mathx.h"
#include "svpwm.h"

/* Duty that gives zero line-to-line voltage: written whenever PWM goes off. */
#define DUTY_ZERO_VOLTAGE 0.5f
#define RAD_S_PER_RPM (MATHX_TWO_PI_F / 60.0f)
#define RAD_PER_DEG (MATHX_PI_F / 180.0f)
#define S_PER_NS 1.0e-9f
#define ENC_COUNTS_PER_LINE 4u      /* x4 quadrature decoding */
/* Longest time converted to periods: keeps the float-to-integer cast defined (28 h at 10 kHz). */
#define PERIODS_MAX 1.0e9f

/* ---- configuration ------------------------------------------------------ */

void app_cfg_default(app_cfg_t *cfg)
{
    static const app_cfg_t zero; /* a field added later reads 0, not garbage */
    ctrl_cfg_t *c = &cfg->ctrl;

    *cfg = zero;
    c->Ts_s = 1.0f / (float)BOARD_PWM_FREQ_HZ;
    c->Rs_Ohm = MOTOR_R_OHM;
    c->Ls_H = MOTOR_L_H;
    c->psi_f_Wb = MOTOR_PSI_F_WB;
    c->pole_pairs = (uint16_t)MOTOR_POLE_PAIRS;
    c->enc_lines = (uint32_t)BOARD_ENC_LINES;
    c->enc_offset_el_rad = BOARD_ENC_OFFSET_EL_RAD;
    c->enc_pll_bw_rad_s = TUNE_ENC_PLL_BW_RAD_S;
    c->speed_kp_Nms_rad = TUNE_SPEED_KP_NMS_RAD;
    c->speed_ki_Nm_rad = TUNE_SPEED_KI_NM_RAD;
    c->te_max_Nm = TUNE_TE_MAX_PER_RATED * MOTOR_RATED_TORQUE_NM;
    c->i_max_A = MODEL_I_BOUND_PER_TRIP * BOARD_OVERCURRENT_A;
    c->u_max_V = BOARD_VDC_MAX_V;
    c->omega_max_el_rad_s = MODEL_SPEED_BOUND_RPM * RAD_S_PER_RPM * (float)MOTOR_POLE_PAIRS;
    c->psi_max_Wb = MODEL_PSI_BOUND_PER_PSIF * MOTOR_PSI_F_WB;
    c->deadtime_s = (float)BOARD_DEADTIME_NS * S_PER_NS;

    cfg->i_max_A = BOARD_OVERCURRENT_A;
    cfg->vdc_max_V = BOARD_VDC_MAX_V;
    cfg->vdc_min_V = BOARD_VDC_MIN_V;
    cfg->speed_max_rad_s = BOARD_OVERSPEED_RPM * RAD_S_PER_RPM;
    cfg->isr_period_cycles = (uint32_t)BOARD_ISR_PERIOD_CYCLES;
    cfg->isr_budget_cycles = (uint32_t)BOARD_ISR_BUDGET_CYCLES;

    cfg->calibrate = true;
    cfg->cal_settle_s = BOARD_CAL_SETTLE_S;
    cfg->cal_samples = (uint32_t)BOARD_CAL_SAMPLES;
    cfg->offset_max_A = BOARD_I_OFFSET_MAX_A;
    cfg->align = (BOARD_ENC_OFFSET_KNOWN == 0U);
    cfg->align_u_V = BOARD_ALIGN_CURRENT_A * MOTOR_R_OHM;
    cfg->align_prepos_el_rad = BOARD_ALIGN_PREPOS_EL_DEG * RAD_PER_DEG;
    cfg->align_ramp_s = BOARD_ALIGN_RAMP_S;
    cfg->align_prepos_s = BOARD_ALIGN_PREPOS_S;
    cfg->align_settle_s = BOARD_ALIGN_SETTLE_S;

    ctrl_cfg_proposed_defaults(c, BOARD_RSID_R_MIN_PER_R * MOTOR_R_OHM, BOARD_RSID_R_MAX_PER_R * MOTOR_R_OHM);
    c->track_R = BOARD_TRACK_R;
    cfg->rsid_mode = (app_rsid_mode_t)BOARD_RSID_MODE;
    cfg->rsid_settle_1_s = BOARD_RSID_SETTLE_1_S;
    cfg->rsid_window_s = BOARD_RSID_WINDOW_S;
    cfg->rsid_settle_2_s = BOARD_RSID_SETTLE_2_S;
    cfg->rsid_speed_1_rad_s = BOARD_RSID_SPEED_1_RPM * RAD_S_PER_RPM;
    cfg->rsid_speed_2_rad_s = BOARD_RSID_SPEED_2_RPM * RAD_S_PER_RPM;
    cfg->rsid_accel_rad_s2 = BOARD_RSID_ACCEL_RPM_S * RAD_S_PER_RPM;
}

/* Whole periods of Ts_s in t_s, rounded; 0 for a non-positive time. */
static uint32_t periods_of(float t_s, float Ts_s)
{
    float n = t_s / Ts_s;
    if (!(n > 0.0f)) {
        return 0u;
    }
    if (!(n < PERIODS_MAX)) {
        n = PERIODS_MAX;
    }
    return (uint32_t)(n + 0.5f);
}

void app_init(app_t *app, const app_cfg_t *cfg)
{
    const float Ts = cfg->ctrl.Ts_s;
    const uint32_t cpr = ENC_COUNTS_PER_LINE * cfg->ctrl.enc_lines;

    hal_pwm_disable();
    app->cfg = *cfg;
    app->state = APP_STATE_INIT;
    app->fault = APP_FAULT_NONE;
    app->snapshot.sample.ia_A = 0.0f;
    app->snapshot.sample.ib_A = 0.0f;
    app->snapshot.sample.vdc_V = 0.0f;
    app->snapshot.sample.enc_count = 0u;
    app->snapshot.state = APP_STATE_INIT;
    app->snapshot.value = 0.0f;
    app->snapshot.limit = 0.0f;
    (void)ctrl_init(&app->ctrl, &cfg->ctrl); /* status kept in ctrl.status; a start checks it when needed */
    app->out.duty[0] = DUTY_ZERO_VOLTAGE;
    app->out.duty[1] = DUTY_ZERO_VOLTAGE;
    app->out.duty[2] = DUTY_ZERO_VOLTAGE;
    app->out.flags = 0u;
    app->ticks = 0u;
    app->state_ticks = 0u;
    app->offset_ia_A = 0.0f;
    app->offset_ib_A = 0.0f;
    app->cal_sum_ia_A = 0.0f;
    app->cal_sum_ib_A = 0.0f;
    app->uv_armed = false;
    app->aligned = false;
    app->pwm_on = false;
    app->enc_prev = 0u;
    app->enc_delta = 0;
    app->seeded = false;
    app->isr_entry = 0u;
    app->isr_interval_cycles = 0u;
    app->isr_run_cycles = 0u;

    app->enc_cpr = (cpr > 0u) ? cpr : 1u;
    app->enc_jump_max = APP_ENC_JUMP_MARGIN * cfg->speed_max_rad_s * Ts * (float)app->enc_cpr / MATHX_TWO_PI_F
                        + 1.0f; /* + one count of quantisation */
    /* 1.5 periods: the entry jitter is a few cycles, a missed period adds a whole one */
    app->isr_late_cycles = cfg->isr_period_cycles + cfg->isr_period_cycles / 2u;
    app->cal_settle_ticks = periods_of(cfg->cal_settle_s, Ts);
    app->align_ramp_ticks = periods_of(cfg->align_ramp_s, Ts);
    app->align_prepos_ticks = periods_of(cfg->align_prepos_s, Ts);
    app->align_settle_ticks = periods_of(cfg->align_settle_s, Ts);
    mathx_sincosf(cfg->align_prepos_el_rad, &app->align_prepos_sin, &app->align_prepos_cos);
    app->rsid_window_ticks = periods_of(cfg->rsid_window_s, Ts);
    app->rsid_win1_tick = periods_of(cfg->rsid_settle_1_s, Ts);
    app->rsid_win2_tick = app->rsid_win1_tick + app->rsid_window_ticks + periods_of(cfg->rsid_settle_2_s, Ts);
    app->rsid_end_tick = app->rsid_win2_tick + app->rsid_window_ticks;
    app->rsid_speed_ref_rad_s = 0.0f;
    app->rsid_speed_step_rad_s = cfg->rsid_accel_rad_s2 * Ts;
    app->speed_handover = false;
    app->rsid_result = RS_IDENT_OK;

    app->req_start = 0u;
    app->req_stop = 0u;
    app->req_fault_reset = 0u;
}

/* ---- outputs and faults ------------------------------------------------- */

/* Duties for the next period; the outputs go on after the first ones are written. */
static void write_duties(app_t *app, const float duty[3])
{
    hal_pwm_write(duty);
    if (!app->pwm_on) {
        hal_pwm_enable();
        app->pwm_on = true;
    }
}

/* PWM off first, then the bookkeeping: the outputs go off in this ISR call. */
static void latch_fault(app_t *app, app_fault_t fault, const hal_sample_t *s, float value, float limit)
{
    hal_pwm_disable();
    app->pwm_on = false;
    app->snapshot.sample = *s;
    app->snapshot.state = app->state;
    app->snapshot.value = value;
    app->snapshot.limit = limit;
    app->state = APP_STATE_FAULT;
    app->fault = fault;
    if (fault == APP_FAULT_ENCODER) {
        app->aligned = false; /* counts were lost: the aligned offset no longer holds */
    }
}

/* Count change from prev to now (both < cpr), the shortest way round. */
static int32_t count_delta(uint32_t now, uint32_t prev, uint32_t cpr)
{
    const uint32_t d = (now + cpr - prev) % cpr;
    return (d > (cpr / 2u)) ? ((int32_t)d - (int32_t)cpr) : (int32_t)d;
}

/* Every call: count change and entry-to-entry time since the last call;
 * the encoder's speed estimate outside RUN (ctrl_step steps it in RUN). */
static void track(app_t *app, const hal_sample_t *s, uint32_t t_entry)
{
    const uint32_t count = s->enc_count % app->enc_cpr;

    if (app->seeded) {
        app->enc_delta = count_delta(count, app->enc_prev, app->enc_cpr);
        app->isr_interval_cycles = t_entry - app->isr_entry; /* modulo 2^32, wrap-safe */
    }
    app->enc_prev = count;
    app->isr_entry = t_entry;
    app->seeded = true;
    if ((app->state != APP_STATE_RUN) && (app->state != APP_STATE_IDENTIFY_R)) {
        encoder_step(&app->ctrl.enc, s->enc_count);
    }
}

/* The checks of app.h on this call's samples, in order; the first that
 * fails is returned with the quantity and its limit. */
static app_fault_t protection(const app_t *app, const hal_sample_t *s, float *value, float *limit)
{
    const app_cfg_t *cfg = &app->cfg;
    const float ia = s->ia_A - app->offset_ia_A;
    const float ib = s->ib_A - app->offset_ib_A;
    const float ic = -ia - ib;

    *value = 0.0f;
    *limit = 0.0f;
    if (hal_trip_active()) {
        return APP_FAULT_HW_TRIP;
    }
    if (!mathx_isfinitef(s->ia_A) || !mathx_isfinitef(s->ib_A) || !mathx_isfinitef(s->vdc_V)) {
        return APP_FAULT_NONFINITE_SAMPLE;
    }
    *value = mathx_fabsf(ia);
    *value = (mathx_fabsf(ib) > *value) ? mathx_fabsf(ib) : *value;
    *value = (mathx_fabsf(ic) > *value) ? mathx_fabsf(ic) : *value;
    *limit = cfg->i_max_A;
    if (!(*value <= *limit)) { /* !(x <= max): a NaN limit trips too */
        return APP_FAULT_OVERCURRENT;
    }
    *value = s->vdc_V;
    *limit = cfg->vdc_max_V;
    if (!(*value <= *limit)) {
        return APP_FAULT_OVERVOLTAGE;
    }
    *limit = cfg->vdc_min_V;
    if (app->uv_armed && (*value < *limit)) {
        return APP_FAULT_UNDERVOLTAGE;
    }
    *value = mathx_fabsf((float)app->enc_delta);
    *limit = app->enc_jump_max;
    if (*value > *limit) {
        return APP_FAULT_ENCODER;
    }
    *value = mathx_fabsf(app->ctrl.enc.omega_m_rad_s);
    *limit = cfg->speed_max_rad_s;
    if (!(*value <= *limit)) {
        return APP_FAULT_OVERSPEED;
    }
    *value = (float)app->isr_interval_cycles;
    *limit = (float)app->isr_late_cycles;
    if (app->isr_interval_cycles > app->isr_late_cycles) {
        return APP_FAULT_OVERRUN;
    }
    *value = (float)app->isr_run_cycles; /* the last call's: for a fault reset's check */
    *limit = (float)cfg->isr_budget_cycles;
    if (app->isr_run_cycles > cfg->isr_budget_cycles) {
        return APP_FAULT_OVERRUN;
    }
    *value = 0.0f;
    *limit = 0.0f;
    return APP_FAULT_NONE;
}

/* ---- the start sequence ------------------------------------------------- */

static void enter_run(app_t *app)
{
    ctrl_reset(&app->ctrl);
    app->state = APP_STATE_RUN;
    app->speed_handover = false;
}

static void enter_identify(app_t *app)
{
    ctrl_reset(&app->ctrl);
    (void)ctrl_rsid_begin(&app->ctrl); /* status checked by leave_align */
    app->state = APP_STATE_IDENTIFY_R;
    app->state_ticks = 0u;
    app->rsid_speed_ref_rad_s = app->ctrl.enc.omega_m_rad_s; /* SPEEDS ramps from here */
    app->speed_handover = false;
}

/* After ALIGN, done or skipped: step 1 of the proposed method, or RUN. */
static void leave_align(app_t *app)
{
    if (app->cfg.rsid_mode == APP_RSID_OFF) {
        enter_run(app);
    } else if (app->cfg.rsid_mode == APP_RSID_TRUSTED) {
        enter_run(app);
        (void)ctrl_est_start(&app->ctrl, app->cfg.ctrl.Rs_Ohm); /* nominal R is in its own band */
    } else {
        enter_identify(app);
    }
}

static void enter_align(app_t *app)
{
    app->state = APP_STATE_ALIGN;
    app->state_ticks = 0u;
}

/* After CALIBRATE, done or skipped: the bus must be up from here on, and
 * the observer's settings valid when step 1 or 2 will need them; both are
 * checked on this call's samples before anything is energised. */
static void leave_calibrate(app_t *app, const hal_sample_t *s)
{
    app->uv_armed = true;
    if (s->vdc_V < app->cfg.vdc_min_V) {
        latch_fault(app, APP_FAULT_UNDERVOLTAGE, s, s->vdc_V, app->cfg.vdc_min_V);
    } else if ((app->cfg.rsid_mode != APP_RSID_OFF) && (app->ctrl.status != CTRL_CFG_OK)) {
        latch_fault(app, APP_FAULT_CONFIG, s, (float)app->ctrl.status, 0.0f);
    } else if (app->cfg.align && !app->aligned) {
        enter_align(app);
    } else {
        leave_align(app);
    }
}

static void enter_calibrate(app_t *app)
{
    app->state = APP_STATE_CALIBRATE;
    app->state_ticks = 0u;
    app->cal_sum_ia_A = 0.0f;
    app->cal_sum_ib_A = 0.0f;
}

static void start_sequence(app_t *app, const hal_sample_t *s)
{
    if (app->cfg.calibrate) {
        enter_calibrate(app);
    } else {
        leave_calibrate(app, s);
    }
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

/* PWM off: settle, then average; the means become the offsets if in band. */
static void calibrate_step(app_t *app, const hal_sample_t *s)
{
    const uint32_t n = (app->cfg.cal_samples > 0u) ? app->cfg.cal_samples : 1u;
    float oa;
    float ob;

    app->state_ticks++;
    if (app->state_ticks <= app->cal_settle_ticks) {
        return;
    }
    app->cal_sum_ia_A += s->ia_A;
    app->cal_sum_ib_A += s->ib_A;
    if (app->state_ticks < app->cal_settle_ticks + n) {
        return;
    }
    oa = app->cal_sum_ia_A / (float)n;
    ob = app->cal_sum_ib_A / (float)n;
    if (!(mathx_fabsf(oa) <= app->cfg.offset_max_A)) {
        latch_fault(app, APP_FAULT_CURRENT_OFFSET, s, oa, app->cfg.offset_max_A);
    } else if (!(mathx_fabsf(ob) <= app->cfg.offset_max_A)) {
        latch_fault(app, APP_FAULT_CURRENT_OFFSET, s, ob, app->cfg.offset_max_A);
    } else {
        app->offset_ia_A = oa;
        app->offset_ib_A = ob;
        leave_calibrate(app, s);
    }
}

/* ALIGN's voltage vector in its period k (app.h): the pre-position vector
 * ramped from 0 and held, then cross-faded onto phase a and held there. */
static ab_t align_vector(const app_t *app, uint32_t k)
{
    const uint32_t turn = app->align_ramp_ticks + app->align_prepos_ticks; /* first period of the turn */
    float w_pre = 0.0f; /* weights of the pre-position vector and of the one on phase a */
    float w_a = 1.0f;
    ab_t u;

    if (k < app->align_ramp_ticks) {
        w_pre = (float)k / (float)app->align_ramp_ticks;
        w_a = 0.0f;
    } else if (k < turn) {
        w_pre = 1.0f;
        w_a = 0.0f;
    } else if (k < turn + app->align_ramp_ticks) {
        w_a = (float)(k - turn) / (float)app->align_ramp_ticks;
        w_pre = 1.0f - w_a;
    }
    /* in the final hold w_pre = 0: u_beta is exactly 0 (app.h: dead time, sensors) */
    u.a = app->cfg.align_u_V * (w_pre * app->align_prepos_cos + w_a);
    u.b = app->cfg.align_u_V * w_pre * app->align_prepos_sin;
    return u;
}

/* Both alignment steps, then the count reads 0 rad. */
static void align_step(app_t *app, const hal_sample_t *s)
{
    const uint32_t k = app->state_ticks;
    const uint32_t end = 2u * app->align_ramp_ticks + app->align_prepos_ticks + app->align_settle_ticks;
    const ab_t u = align_vector(app, k);
    ab_t u_real;
    svpwm_duty_t d;
    float duty[3];

    /* invalid = non-finite or no bus; the undervoltage check, armed by now, leaves only the former */
    if ((svpwm_duty(u, s->vdc_V, &d, &u_real) & SVPWM_INVALID_INPUT) != 0u) {
        latch_fault(app, APP_FAULT_NONFINITE_OUTPUT, s, u.a, 0.0f);
        return;
    }
    duty[0] = d.a;
    duty[1] = d.b;
    duty[2] = d.c;
    write_duties(app, duty);
    app->state_ticks++;
    if (k >= end) {
        encoder_align(&app->ctrl.enc, s->enc_count);
        app->aligned = true;
        leave_align(app);
    }
}

/* One ctrl_step on this period's samples; duties out, or a fault. */
static void run_step(app_t *app, const hal_sample_t *s)
{
    ctrl_in_t in;

    in.ia_A = s->ia_A - app->offset_ia_A;
    in.ib_A = s->ib_A - app->offset_ib_A;
    in.vdc_V = s->vdc_V;
    in.enc_count = s->enc_count;
    ctrl_step(&app->ctrl, &in, &app->out);
    if ((app->out.flags & CTRL_FLAG_NONFINITE) != 0u) {
        latch_fault(app, APP_FAULT_NONFINITE_OUTPUT, s, 0.0f, 0.0f);
    } else {
        write_duties(app, app->out.duty);
    }
}

/* run_step at the app's speed reference (rsid_speed_ref_rad_s); ctrl.ref,
 * the outside's, is put back after it. */
static void run_step_app_speed(app_t *app, const hal_sample_t *s)
{
    const ctrl_ref_t outside = app->ctrl.ref;
    ctrl_ref_t ref = outside;

    ref.speed_ref_rad_s = app->rsid_speed_ref_rad_s;
    ctrl_set_ref(&app->ctrl, &ref);
    run_step(app, s);
    ctrl_set_ref(&app->ctrl, &outside);
}

/* The app's speed reference one period on towards target at rsid_accel
 * (a step when that is 0); true while target is not yet reached. */
static bool ramp_speed(app_t *app, float target)
{
    const float dmax = app->rsid_speed_step_rad_s;
    const float err = target - app->rsid_speed_ref_rad_s;

    app->rsid_speed_ref_rad_s += (dmax > 0.0f) ? mathx_clampf(err, -dmax, dmax) : err;
    return (dmax > 0.0f) && (mathx_fabsf(err) > dmax);
}

/* RUN: ctrl_step every period; after SPEEDS, at the handover ramp until
 * the outside reference is reached. */
static void run_state_step(app_t *app, const hal_sample_t *s)
{
    if (app->speed_handover) {
        app->speed_handover = ramp_speed(app, app->ctrl.ref.speed_ref_rad_s);
        run_step_app_speed(app, s);
    } else {
        run_step(app, s);
    }
}

/* The fault naming why step 1 refused R^; the snapshot gets the quantity. */
static app_fault_t rsid_fault(const app_t *app, rs_ident_result_t r, float *value, float *limit)
{
    const rs_ident_out_t *o = &app->ctrl.rsid_out;
    const rs_ident_cfg_t *rc = &app->ctrl.ri.cfg;

    *value = o->R_est_Ohm;
    *limit = 0.0f;
    switch (r) {
    case RS_IDENT_NOT_STEADY:
        *value = (o->iq_std_A[0] > o->iq_std_A[1]) ? o->iq_std_A[0] : o->iq_std_A[1];
        *limit = rc->iq_std_max_A;
        return APP_FAULT_RSID_NOT_STEADY;
    case RS_IDENT_DEGENERATE:
        return APP_FAULT_RSID_DEGENERATE;
    case RS_IDENT_NON_FINITE:
        return APP_FAULT_RSID_NON_FINITE;
    case RS_IDENT_OUT_OF_BAND:
        *value = rc->R_nom_Ohm - o->dR_Ohm; /* R^: rs_ident leaves R_est_Ohm at R_nom when refused */
        *limit = (*value > rc->R_max_Ohm) ? rc->R_max_Ohm : rc->R_min_Ohm;
        return APP_FAULT_RSID_OUT_OF_BAND;
    case RS_IDENT_INVALID_CFG:
        return APP_FAULT_CONFIG;
    case RS_IDENT_TOO_FEW:
    case RS_IDENT_OK: /* not called with OK */
    default:
        return APP_FAULT_RSID_TOO_FEW;
    }
}

/* Step 1: the controller runs every period; the app times the windows and,
 * in SPEEDS mode, commands the two speeds. */
static void identify_step(app_t *app, const hal_sample_t *s)
{
    const uint32_t k = app->state_ticks;
    rs_ident_window_t win = RS_IDENT_WINDOW_NONE;
    bool moving = false;
    float value = 0.0f;
    float limit = 0.0f;

    if ((k >= app->rsid_win1_tick) && (k < app->rsid_win1_tick + app->rsid_window_ticks)) {
        win = RS_IDENT_WINDOW_1;
    } else if ((k >= app->rsid_win2_tick) && (k < app->rsid_end_tick)) {
        win = RS_IDENT_WINDOW_2;
    }
    ctrl_rsid_window(&app->ctrl, win);
    if (app->cfg.rsid_mode == APP_RSID_SPEEDS) {
        /* point 1 until window 1 ends, then point 2, in place of the outside reference */
        const float target = (k < app->rsid_win1_tick + app->rsid_window_ticks) ? app->cfg.rsid_speed_1_rad_s
                                                                                  : app->cfg.rsid_speed_2_rad_s;
        /* the settle times count from the end of the ramp: a window in a
         * ramp sees the speed estimate's lag as back-EMF in fq (biases R^) */
        moving = ramp_speed(app, target) && (win == RS_IDENT_WINDOW_NONE);
        run_step_app_speed(app, s);
    } else {
        run_step(app, s);
    }
    if (app->state != APP_STATE_IDENTIFY_R) {
        return; /* run_step faulted */
    }
    if (moving) {
        return;
    }
    app->state_ticks++;
    if (app->state_ticks >= app->rsid_end_tick) {
        app->rsid_result = ctrl_rsid_finish(&app->ctrl);
        if (app->rsid_result == RS_IDENT_OK) {
            app->state = APP_STATE_RUN; /* step 2 runs from the next period; no reset */
            app->speed_handover = (app->cfg.rsid_mode == APP_RSID_SPEEDS);
        } else {
            /* the fault first: value and limit are its outputs (argument order is unspecified) */
            const app_fault_t f = rsid_fault(app, app->rsid_result, &value, &limit);
            latch_fault(app, f, s, value, limit);
        }
    }
}

/* Background requests; stop wins over start. */
static void take_requests(app_t *app, const hal_sample_t *s)
{
    if (app->req_stop != 0u) {
        app->req_stop = 0u;
        app->req_start = 0u;
        if ((app->state == APP_STATE_CALIBRATE) || (app->state == APP_STATE_ALIGN) ||
            (app->state == APP_STATE_IDENTIFY_R) || (app->state == APP_STATE_RUN)) {
            stop_to_idle(app);
        }
    } else if (app->req_start != 0u) {
        app->req_start = 0u; /* ignored unless stopped */
        if ((app->state == APP_STATE_INIT) || (app->state == APP_STATE_IDLE)) {
            start_sequence(app, s);
        }
    }
}

/* FAULT: outputs stay off; a reset is taken only if no check fails now. */
static void fault_step(app_t *app, const hal_sample_t *s)
{
    float value;
    float limit;

    app->req_start = 0u; /* a start asked for while faulted is not kept */
    app->req_stop = 0u;
    if (app->req_fault_reset != 0u) {
        app->req_fault_reset = 0u;
        if (protection(app, s, &value, &limit) == APP_FAULT_NONE) {
            app->state = APP_STATE_IDLE;
            app->fault = APP_FAULT_NONE;
        }
    }
}

void app_isr(app_t *app)
{
    hal_sample_t s;
    uint32_t t_entry;
    float value;
    float limit;
    app_fault_t f;

    hal_sample_read(&s); /* first HAL call of the ISR (hal.h) */
    t_entry = hal_cycles();
    app->ticks++;
    track(app, &s, t_entry);

    if (app->state == APP_STATE_FAULT) {
        fault_step(app, &s);
    } else {
        f = protection(app, &s, &value, &limit);
        if (f != APP_FAULT_NONE) {
            latch_fault(app, f, &s, value, limit);
        } else {
            take_requests(app, &s);
            switch (app->state) {
            case APP_STATE_CALIBRATE:
                calibrate_step(app, &s);
                break;
            case APP_STATE_ALIGN:
                align_step(app, &s);
                break;
            case APP_STATE_IDENTIFY_R:
                identify_step(app, &s);
                break;
            case APP_STATE_RUN:
                run_state_step(app, &s);
                break;
            default: /* INIT, IDLE: outputs off, nothing to do */
                break;
            }
        }
    }

    app->isr_run_cycles = hal_cycles() - t_entry;
    if ((app->state != APP_STATE_FAULT) && (app->isr_run_cycles > app->cfg.isr_budget_cycles)) {
        latch_fault(app, APP_FAULT_OVERRUN, &s, (float)app->isr_run_cycles, (float)app->cfg.isr_budget_cycles);
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
