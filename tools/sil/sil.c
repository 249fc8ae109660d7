/* sil.c - the SIL runner core: scenario -> board + app, period loop, rows; see sil.h. */
#include "sil.h"
#include "sim_units.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

#include "app.h"
#include "drive_params.h"
#include "csv_num.h"
#include "board_cfg.h"
#include "hal_sim.h"
#include "json_out.h"
#include "sil_board.h"

/* Bounds the controller's model clamps to (ctrl_cfg_t): generous, never the active limit.
 * The current, speed and flux bounds are the board's (board_cfg.h MODEL_*). */
#define MODEL_U_BOUND_PER_VDC 1.0        /* |ud|, |uq| bound / bus (the hexagon clamps at 2/3) */
#define COMM_RUN_MARGIN_S 1.0            /* a commissioning run's length beyond its stages' timeouts: calibration [s] */

static app_t g_app;
static comm_t g_comm;              /* the commissioning's state (app_attach_comm) */
static const sil_hooks_t *g_hooks;   /* of the run under way, or NULL */

static void sil_isr(void)
{
    app_isr(&g_app);
    if (g_hooks != NULL && g_hooks->isr_end != NULL) {
        g_hooks->isr_end(g_hooks->user);
    }
}

static void faults_from(const scenario_t *sc, hal_sim_faults_t *f)
{
    hal_sim_faults_none(f);
    scenario_map(sc, SC_TO_FAULTS, f, 0.0);
}

/* The scenario's controller and board values as the drive's parameter set
 * (defaults: the board's, tools/sil/scenario_keys.h), mapped by the target's
 * own drive_params_to_app_cfg(); then the start-up sequence's keys. */
void sil_drive_params(const scenario_t *sc, drive_params_t *p)
{
    hal_sim_cfg_t hc;
    sil_board_from(sc, &hc);
    scenario_params(sc, p);
    p->board.Ts_s = (float)hc.inv.Ts_s;
    p->board.u_bound_V = (float)(MODEL_U_BOUND_PER_VDC * sc->plant.vdc_V);
}

void sil_app_cfg(const scenario_t *sc, const drive_params_t *p, app_cfg_t *ac)
{
    app_cfg_default(ac);   /* the board's start-up sequence, watch and ISR timing */
    drive_params_to_app_cfg(p, ac);
    /* the keys whose target is the app's configuration: [run], [identify] */
    scenario_map(sc, SC_TO_APP, ac, (double)p->board.Ts_s);
}

static void app_cfg_from(const scenario_t *sc, app_cfg_t *ac)
{
    drive_params_t p;
    sil_drive_params(sc, &p);
    sil_app_cfg(sc, &p, ac);
}

void sil_drive_config(const scenario_t *sc, drive_params_t *p, app_cfg_t *ac)
{
    sil_drive_params(sc, p);
    sil_app_cfg(sc, p, ac);
    (void)drive_params_derive(p);
}

static ctrl_mode_t ctrl_mode_of(uint32_t mode)
{
    if (mode == SC_MODE_OPEN_LOOP) {
        return CTRL_MODE_OPEN_LOOP;
    }
    return (mode == SC_MODE_TORQUE) ? CTRL_MODE_TORQUE : CTRL_MODE_SPEED;
}

/* One row: the truth, the monitor, and the references of the firmware's command block (the
 * operator's request the ISR took this period: the scenario's profile or a link's write). */
static void fill_row(sil_row_t *r)
{
    hal_sim_truth_t tr;
    hal_sim_truth(&tr);
    const ctrl_mon_t *m = ctrl_monitor(&g_app.ctrl);
    const app_op_t *op = &g_app.op_taken;
    const bool closed = (op->mode != CTRL_MODE_OPEN_LOOP);
    r->t_s = tr.t_s;
    r->state = (double)g_app.state;
    r->fault = (double)g_app.fault;
    r->flags = (double)(g_app.out.flags | g_app.warnings); /* app.h: APP_WARN_* above CTRL_FLAG_* */
    r->speed_ref_rpm = (op->mode == CTRL_MODE_SPEED) ? (double)op->ref.speed_ref_rad_s * SIM_RPM_PER_RAD_S : NAN;
    r->speed_rpm = tr.speed_m_rad_s * SIM_RPM_PER_RAD_S;
    r->speed_est_rpm = (double)m->speed_mech_rad_s * SIM_RPM_PER_RAD_S;
    r->te_ref_Nm = closed ? (double)m->te_ref_Nm : NAN;
    r->te_Nm = tr.te_Nm;
    r->te_est_Nm = (double)m->te_est_Nm;
    r->psi_ref_Wb = closed ? (double)m->psi_ref_Wb : NAN;
    r->psi_Wb = tr.psi_s_Wb;
    r->psi_est_Wb = (double)m->psi_est_Wb;
    r->id_A = tr.id_A;
    r->iq_A = tr.iq_A;
    r->ud_V = tr.ud_mean_V;
    r->uq_V = tr.uq_mean_V;
    r->ud_cmd_V = (double)m->ud_V;
    r->uq_cmd_V = (double)m->uq_V;
    r->load_Nm = tr.load_Nm;
    const est_t *es = ctrl_est(&g_app.ctrl);
    const est_out_t *eo = est_output(es);
    const dq_t f = est_f_V(es);
    r->R_est_ohm = (double)eo->R_Ohm;
    r->L_est_H = (double)eo->L_H;
    r->psif_est_Wb = (double)eo->psi_f_Wb;
    r->fd_est = (double)f.d;
    r->fq_est = (double)f.q;
    r->est = (double)eo->phase;
    r->est_hold = (double)eo->hold;
    r->est_src = (double)eo->src;
    r->R_ohm = tr.R_Ohm;
    r->inv_err_est_V = (double)eo->inv_err_V;
    r->psif_model_Wb = r->psif_est_Wb; /* the older name */
    r->id_meas_A = (double)m->id_A;
    r->iq_meas_A = (double)m->iq_A;
    r->psif_obs_Wb = (double)((eo->phase == EST_OFF) ? eo->psi_f_Wb : est_psi_f_obs_Wb(es));
    r->pwm = tr.pwm_enabled ? 1.0 : 0.0;
    r->inj = (double)tr.faults_active;
    const bool faulted = (g_app.state == APP_STATE_FAULT);
    r->fault_value = faulted ? (double)g_app.snapshot.value : 0.0;
    r->fault_limit = faulted ? (double)g_app.snapshot.limit : 0.0;
    r->ia_adc_A = (double)g_app.adc.ia_A;
    r->ib_adc_A = (double)g_app.adc.ib_A;
    r->vdc_adc_V = (double)g_app.adc.vdc_V;
    r->ia_offset_A = (double)g_app.offset_ia_A;
    r->ib_offset_A = (double)g_app.offset_ib_A;
}

/* The scenario's profiles of a run, read by cursors at its periods' times. */
typedef struct {
    profile_cursor_t speed_rpm, te_Nm, ud_V, uq_V, load_Nm, R_Ohm;
    bool R_varies;           /* the plant's R has a profile: set every change */
    double until_s;          /* every value read last holds for t < until_s */
} sil_refs_t;

static void refs_init(sil_refs_t *r, const scenario_t *sc)
{
    profile_cursor_init(&r->speed_rpm, &sc->reference.speed_rpm);
    profile_cursor_init(&r->te_Nm, &sc->reference.torque_Nm);
    profile_cursor_init(&r->ud_V, &sc->reference.ud_V);
    profile_cursor_init(&r->uq_V, &sc->reference.uq_V);
    profile_cursor_init(&r->load_Nm, &sc->load.torque_Nm);
    profile_cursor_init(&r->R_Ohm, &sc->plant.R_ohm_profile);
    r->R_varies = (sc->plant.R_ohm_profile.n > 1u);
    r->until_s = -INFINITY;
}

static double min_until(double until_s, const profile_cursor_t *c)
{
    const double u = profile_cursor_until_s(c);
    return (u < until_s) ? u : until_s;
}

/* The references into *op and the plant's load and R at t_s (a period's
 * start, never earlier than the last): read only when one may change;
 * true when read (*op may have changed). */
static bool refs_at(sil_refs_t *r, double t_s, app_op_t *op)
{
    if (t_s < r->until_s) {
        return false;   /* op, load and R hold what they were set to */
    }
    op->ref.speed_ref_rad_s = (float)(profile_cursor_eval(&r->speed_rpm, t_s) / SIM_RPM_PER_RAD_S);
    op->ref.te_ref_Nm = (float)profile_cursor_eval(&r->te_Nm, t_s);
    op->ref.ud_ref_V = (float)profile_cursor_eval(&r->ud_V, t_s);
    op->ref.uq_ref_V = (float)profile_cursor_eval(&r->uq_V, t_s);
    hal_sim_set_load(profile_cursor_eval(&r->load_Nm, t_s));
    double until_s = profile_cursor_until_s(&r->speed_rpm);
    until_s = min_until(until_s, &r->te_Nm);
    until_s = min_until(until_s, &r->ud_V);
    until_s = min_until(until_s, &r->uq_V);
    until_s = min_until(until_s, &r->load_Nm);
    if (r->R_varies) {
        hal_sim_set_R_Ohm(profile_cursor_eval(&r->R_Ohm, t_s));   /* the winding warms */
        until_s = min_until(until_s, &r->R_Ohm);
    }
    r->until_s = until_s;
    return true;
}

/* fmax(a, b) without the library call: the larger; NaN only if both are. */
static double max_or_nonnan(double a, double b)
{
    return ((a >= b) || isnan(b)) ? a : b;
}

/* The fault bookkeeping of sil_result_t after one period. */
static void track_faults(const hal_sim_truth_t *tr, bool was_faulted, sil_result_t *res)
{
    const bool faulted = (g_app.state == APP_STATE_FAULT);
    if (isnan(res->t_inject_s) && tr->faults_active != 0u) {
        res->t_inject_s = tr->t_s;
    }
    if (faulted && isnan(res->t_fault_s)) {
        res->t_fault_s = tr->t_s;
        res->fault_state = (int)g_app.snapshot.state;
        res->fault_value = (double)g_app.snapshot.value;
        res->fault_limit = (double)g_app.snapshot.limit;
        res->fault_ia_A = (double)g_app.snapshot.sample.ia_A;
        res->fault_ib_A = (double)g_app.snapshot.sample.ib_A;
        res->fault_vdc_V = (double)g_app.snapshot.sample.vdc_V;
        res->fault_enc_count = g_app.snapshot.sample.enc_count;
    }
    if (faulted && tr->pwm_enabled) {
        res->gates_on_in_fault++;
    }
    if (was_faulted && !faulted) {
        res->fault_exits++;
    }
}

int sil_run(const scenario_t *sc, sil_row_fn on_row, void *user, sil_result_t *res)
{
    return sil_run_ctl(sc, on_row, user, NULL, res);
}

/* The result before the run: zero, and NaN for the times and the fault's
 * values not yet seen. */
static void result_begin(sil_result_t *res)
{
    memset(res, 0, sizeof *res);
    res->t_run_s = NAN;
    res->t_inject_s = NAN;
    res->t_fault_s = NAN;
    res->fault_value = NAN;
    res->fault_limit = NAN;
}

/* The board and the app set up for the scenario, the ISR attached, the
 * start (or the commissioning) requested; the operator's mode and method
 * into *op, with each period's references taken later (a proposed method
 * ctrl_init refused stays conventional: the app faults CONFIG at the start
 * if [identify] asks for step 1). */
static void run_begin(const scenario_t *sc, const hal_sim_cfg_t *hc, const sil_hooks_t *hooks, bool commission,
                      app_op_t *op)
{
    app_cfg_t ac;
    hal_sim_faults_t hf;
    app_cfg_from(sc, &ac);
    faults_from(sc, &hf);
    hal_sim_configure(hc);
    hal_sim_set_faults(&hf);
    hal_init();
    app_init(&g_app, &ac);
    app_attach_comm(&g_app, &g_comm);
    op->mode = ctrl_mode_of(sc->controller.mode);
    op->method = (sc->controller.method == SC_METHOD_PROPOSED) ? CTRL_METHOD_PROPOSED : CTRL_METHOD_CONVENTIONAL;
    g_hooks = hooks;
    if (hooks != NULL && hooks->start != NULL) {
        hooks->start(hooks->user, &g_app);
    }
    hal_isr_attach(sil_isr);
    if (commission) {
        app_request_commission(&g_app);
    } else {
        app_request_start(&g_app);
    }
}

/* A commissioning's run is over once the app left COMMISSION (done: IDLE;
 * refused: FAULT), or faulted before it began (calibration, bus). */
static bool commission_over(bool *seen)
{
    *seen = *seen || (g_app.state == APP_STATE_COMMISSION);
    return (*seen && g_app.state != APP_STATE_COMMISSION) || (g_app.state == APP_STATE_FAULT);
}

/* The operator's request when the scenario's references change at t_s,
 * taken at the start of this period's ISR (an unchanged request would only
 * set the controller's reference to what it is); the hooks may amend it. */
static void take_refs(sil_refs_t *refs, double t_s, const sil_hooks_t *hooks, app_op_t *op)
{
    if (refs_at(refs, t_s, op)) {
        app_op_t req = *op;
        if (hooks != NULL && hooks->refs != NULL) {
            hooks->refs(hooks->user, &req);
        }
        app_request_op(&g_app, &req);
    }
}

/* Period k's figures into the result: faults, the time RUN began, the peak
 * current and speed, the periods with the gates on, the warnings raised. */
static void account_period(const hal_sim_truth_t *tr, bool was_faulted, uint32_t k, sil_result_t *res)
{
    track_faults(tr, was_faulted, res);
    if (isnan(res->t_run_s) && g_app.state == APP_STATE_RUN) {
        res->t_run_s = tr->t_s;
    }
    const double i_max = max_or_nonnan(fabs(tr->ia_A), max_or_nonnan(fabs(tr->ib_A), fabs(tr->ic_A)));
    res->max_abs_i_A = max_or_nonnan(res->max_abs_i_A, i_max);
    res->max_abs_speed_rpm = max_or_nonnan(res->max_abs_speed_rpm, fabs(tr->speed_m_rad_s) * SIM_RPM_PER_RAD_S);
    res->pwm_periods += tr->pwm_enabled ? 1u : 0u;
    res->warnings |= g_app.warnings;   /* every warning of the run, a later start's clearing aside */
    res->periods = k + 1u;
}

/* After the run: the app's outcome, level 3's figures and the
 * commissioning's results into the result. */
static void result_finish(sil_result_t *res)
{
    res->final_state = (int)g_app.state;
    res->final_fault = (int)g_app.fault;
    res->warnings |= g_app.warnings;
    res->rsid_refusal = (int)g_app.rsid_refusal.fault;
    res->enc_offset_el_rad = (double)ctrl_enc_offset_el_rad(&g_app.ctrl);
    res->i_offset_a_A = (double)g_app.offset_ia_A;
    res->i_offset_b_A = (double)g_app.offset_ib_A;
    res->level = (int)g_app.level;
    res->enc_counts = (double)g_app.rot.out.counts;
    res->enc_angle_el_rad = (double)g_app.rot.out.angle_el_rad;
    res->enc_pole_pairs = (double)g_app.rot.out.pole_pairs_est;
    res->enc_i_pos_A = (double)g_app.rot.out.i_pos_A;
    res->enc_i_neg_A = (double)g_app.rot.out.i_neg_A;
    const comm_result_t *cr = &g_comm.res;
    res->comm_valid = g_app.comm_valid ? 1 : 0;
    res->comm_stage = (int)g_comm.stage;
    res->comm_R_ohm = (double)cr->R_Ohm;
    res->comm_L_H = (double)cr->L_H;
    res->comm_psif_Wb = (double)cr->psi_f_Wb;
    res->comm_J_kgm2 = (double)cr->J_kgm2;
    res->comm_B_Nms = (double)cr->B_Nms;
    res->comm_enc_offset_el_rad = (double)cr->enc_offset_el_rad;
    res->comm_speed_kp_Nms_rad = (double)cr->speed_kp_Nms_rad;
    res->comm_speed_ki_Nm_rad = (double)cr->speed_ki_Nm_rad;
    res->comm_u_err_V = (double)cr->u_err_V;
    res->comm_inv_dv_V = (double)cr->inv_dv_V;
    res->comm_deadtime_s = (double)cr->deadtime_s;
    res->comm_device_drop_V = (double)cr->device_drop_V;
    res->comm_untold_deadtime_s = (double)cr->untold_deadtime_s;
    res->comm_pole_pairs = cr->pole_pairs;
}

/* The board of a run: the scenario's, with a commissioning's free shaft. */
static void run_board(const scenario_t *sc, bool commission, hal_sim_cfg_t *hc)
{
    sil_board_from(sc, hc);
    if (commission) {
        hc->load_coulomb_Nm = 0.0;   /* a commissioning's free shaft: [load] plays no part */
        hc->load_B_Nms = 0.0;
    }
}

/* The periods a run simulates (after run_begin): run.duration_s, or a
 * commissioning's stages' timeouts and a margin, or no end (UINT32_MAX)
 * for duration_s <= 0 when a period_end hook ends the run. */
static uint32_t run_periods(const scenario_t *sc, const sil_hooks_t *hooks, bool commission, double Ts_s)
{
    const double comm_s = (double)comm_max_s(&g_comm) + COMM_RUN_MARGIN_S;
    const bool endless = !commission && (sc->run.duration_s <= 0.0) && hooks != NULL && hooks->period_end != NULL;
    return endless ? UINT32_MAX : (uint32_t)llround((commission ? comm_s : sc->run.duration_s) / Ts_s);
}

/* Period k of a run: the board's period (its ISR runs the app's), the
 * background, a new configuration between periods, the period's figures. */
static void run_period(const hal_sim_truth_t *tr, uint32_t k, sil_result_t *res)
{
    const bool was_faulted = (g_app.state == APP_STATE_FAULT);
    hal_sim_period();
    app_background(&g_app);
    app_reconfigure_now(&g_app);   /* a new configuration (the link's parameters): between periods */
    account_period(tr, was_faulted, k, res);
}

/* After each period: a row when one is due (every log_every periods from
 * k = 0; *to_row counts down to it) to on_row, counted in res; on_row's
 * return (0 without a row). */
static int row_if_due(uint32_t *to_row, uint32_t log_every, sil_row_fn on_row, void *user, sil_result_t *res)
{
    int rc = 0;
    if (*to_row == 0u) {
        *to_row = log_every;
        if (on_row != NULL) {
            sil_row_t row;
            fill_row(&row);
            rc = on_row(&row, user);
            res->rows++;
        }
    }
    (*to_row)--;
    return rc;
}

/* After a whole period (every row so far complete): SIL_STOPPED when
 * *stop is set, else the period_end hook's return; 0 goes on. */
static int run_goes_on(const volatile sig_atomic_t *stop, const sil_hooks_t *hooks)
{
    if (stop != NULL && *stop != 0) {
        return SIL_STOPPED;
    }
    return (hooks != NULL && hooks->period_end != NULL) ? hooks->period_end(hooks->user) : 0;
}

int sil_run_ctl(const scenario_t *sc, sil_row_fn on_row, void *user, const sil_ctl_t *ctl, sil_result_t *res)
{
    hal_sim_cfg_t hc;
    app_op_t op;
    sil_refs_t refs;
    const sil_hooks_t *hooks = (ctl != NULL) ? ctl->hooks : NULL;
    const bool commission = (ctl != NULL) && (ctl->commission != 0);
    run_board(sc, commission, &hc);
    result_begin(res);
    run_begin(sc, &hc, hooks, commission, &op);

    const double Ts = hc.inv.Ts_s;
    const uint32_t n = run_periods(sc, hooks, commission, Ts);
    refs_init(&refs, sc);
    const hal_sim_truth_t *tr = hal_sim_truth_view();   /* what is checked every period */
    uint32_t periods_to_row = 0u;                       /* a row every log_every periods, from k = 0 */
    const volatile sig_atomic_t *stop = (ctl != NULL) ? ctl->stop : NULL;
    const sil_tick_fn on_tick = (ctl != NULL && ctl->tick_periods > 0u) ? ctl->on_tick : NULL;
    uint32_t periods_to_tick = (on_tick != NULL) ? ctl->tick_periods : 0u;
    int rc = 0;
    bool comm_seen = false;   /* the app has been in COMMISSION */
    for (uint32_t k = 0; k < n && rc == 0; k++) {
        if (commission) {
            if (commission_over(&comm_seen)) {
                break;
            }
        } else {
            take_refs(&refs, (double)k * Ts, hooks, &op);
        }
        run_period(tr, k, res);
        rc = row_if_due(&periods_to_row, sc->run.log_every, on_row, user, res);
        if (on_tick != NULL && --periods_to_tick == 0u) {
            periods_to_tick = ctl->tick_periods;
            on_tick(tr->t_s, ctl->tick_user);
        }
        if (rc == 0) {
            rc = run_goes_on(stop, hooks);
        }
    }
    g_hooks = NULL;
    result_finish(res);
    return rc;
}

/* ---- CSV ------------------------------------------------------------------- */

typedef struct {
    const char *name;
    size_t offset;
} sil_col_t;

#define COL(f) { #f, offsetof(sil_row_t, f) }
static const sil_col_t COLS[] = {
    COL(t_s), COL(state), COL(fault), COL(flags),
    COL(speed_ref_rpm), COL(speed_rpm), COL(speed_est_rpm),
    COL(te_ref_Nm), COL(te_Nm), COL(te_est_Nm),
    COL(psi_ref_Wb), COL(psi_Wb), COL(psi_est_Wb),
    COL(id_A), COL(iq_A), COL(ud_V), COL(uq_V), COL(ud_cmd_V), COL(uq_cmd_V),
    COL(load_Nm), COL(R_est_ohm), COL(L_est_H), COL(psif_est_Wb), COL(fd_est), COL(fq_est), COL(est),
    COL(R_ohm), COL(est_hold), COL(pwm), COL(inj), COL(fault_value), COL(fault_limit), COL(inv_err_est_V),
    COL(psif_model_Wb), COL(id_meas_A), COL(iq_meas_A), COL(ia_adc_A), COL(ib_adc_A), COL(vdc_adc_V), COL(ia_offset_A),
    COL(ib_offset_A), COL(psif_obs_Wb), COL(est_src),
};
#define N_COLS (sizeof COLS / sizeof COLS[0])
/* SIL_CSV_LINE_MAX counts one column per double of sil_row_t */
typedef char sil_csv_cols_fit[(N_COLS <= sizeof(sil_row_t) / sizeof(double)) ? 1 : -1];

void sil_csv_header(FILE *f)
{
    for (size_t i = 0; i < N_COLS; i++) {
        fprintf(f, "%s%s", COLS[i].name, (i + 1u < N_COLS) ? "," : "\n");
    }
}

size_t sil_csv_format(char *line, const sil_row_t *row)
{
    size_t n = 0;
    for (size_t i = 0; i < N_COLS; i++) {
        double v = *(const double *)((const char *)row + COLS[i].offset);
        n += (size_t)csv_num_g9(line + n, v);   /* "%.9g"; one spelling "nan" for any NaN */
        line[n++] = (i + 1u < N_COLS) ? ',' : '\n';
    }
    return n;
}

void sil_csv_row(FILE *f, const sil_row_t *row)
{
    char line[SIL_CSV_LINE_MAX];
    fwrite(line, 1, sil_csv_format(line, row), f);
}

/* ---- resolved values (OUT.json) --------------------------------------------- */

/* One derived value: {"value": v, "source": "derived"|"set", "from": "keys"}. */
static void json_derived(FILE *f, const char *key, double v, int set, const char *from, const char *sep)
{
    fprintf(f, "  \"%s\": {", key);
    json_flt(f, "value", (float)v, ", ");   /* a float of the drive's parameter set */
    fprintf(f, "\"source\": \"%s\", \"from\": \"%s\"}%s", set ? "set" : "derived", from, sep);
}

/* The derived keys' values (scenario_keys.h), each set or derived, from
 * the finished scenario's parameter set; resolved_derived's first part. */
static void derived_keys(FILE *f, const scenario_t *sc)
{
    drive_params_t p;
    char name[64];
    scenario_params(sc, &p);   /* finished: the derived keys' values */
    for (int i = 0; i < scenario_key_count(); i++) {
        scenario_key_info_t k;
        scenario_key_info(i, &k);
        if (k.from_keys != NULL) {
            snprintf(name, sizeof name, "%s.%s", k.section, k.name);
            json_derived(f, name, scenario_loc_read(&k.to, &p, 0.0), scenario_key_set(sc, k.section, k.name),
                         k.from_keys, ",\n");
        }
    }
}

/* The settings without a key (always derived, R_max_ohm aside: a key), as
 * the run's configuration *ac holds them; resolved_derived's second part. */
static void derived_settings(FILE *f, const scenario_t *sc, const app_cfg_t *ac)
{
    const ctrl_cfg_t *c = &ac->ctrl;
    static const char I[] = "motor.i_rated_A";
    static const char V[] = "plant.vdc_V";
    json_derived(f, "observer.Ks_V", (double)c->est_cfg.smo.Ks_V, 0, "plant.vdc_V (2 ef_max)", ",\n");
    json_derived(f, "observer.phi_A", (double)c->est_cfg.smo.phi_A, 0,
                 "observer.Ks_V / G, G from controller.R_ohm controller.L_H and Ts", ",\n");
    json_derived(f, "observer.mu_1_s", (double)c->est_cfg.smo.mu_d_1_s, 0, "controller.R_ohm controller.L_H and Ts",
                 ",\n");
    json_derived(f, "observer.ef_max_V", (double)c->est_cfg.smo.ef_max_V, 0, V, ",\n");
    json_derived(f, "observer.L_min_H", (double)c->est_cfg.smo.L_min_H, 0, "controller.L_H observer gains", ",\n");
    json_derived(f, "controller.R_max_ohm", (double)c->est_cfg.R_max_Ohm, scenario_key_set(sc, "controller", "R_max_ohm"),
                 "controller.R_ohm", ",\n");
    json_derived(f, "estimator.w_min_rad_s", (double)c->est_cfg.pe.w_min_rad_s, 0, "plant.vdc_V controller.psif_Wb", ",\n");
    json_derived(f, "estimator.wiq_min_A_rad_s", (double)c->est_cfg.pe.wiq_min_A_rad_s, 0,
                 "estimator.w_min_rad_s motor.i_rated_A", ",\n");
    json_derived(f, "gate.di_max_A", (double)c->est_cfg.gate.di_max_A, 0, I, ",\n");
    json_derived(f, "gate.dte_max_Nm", (double)c->est_cfg.gate.dte_max_Nm, 0, "motor.i_rated_A controller.psif_Wb plant.pole_pairs", ",\n");
    json_derived(f, "r_track.i_ident_A", (double)c->est_cfg.rtrack.i_ident_A, 0, I, ",\n");
    json_derived(f, "r_track.i_track_A", (double)c->est_cfg.rtrack.i_track_A, 0, I, ",\n");
    json_derived(f, "r_track.iq_min_A", (double)c->est_cfg.rtrack.iq_min_A, 0, I, ",\n");
    json_derived(f, "r_track.iq_step_max_A", (double)c->est_cfg.rtrack.iq_step_max_A, 0, I, ",\n");
    json_derived(f, "r_track.ve_max_V", (double)c->est_cfg.rtrack.ve_max_V, 0, V, ",\n");
    json_derived(f, "align.u_V", (double)ac->aln.u_V, 0, "motor.i_rated_A controller.R_ohm", ",\n");
    json_derived(f, "open_phase.u_min_V", (double)ac->prot.watch.op_u_min_V, 0, V, ",\n");
    json_derived(f, "open_phase.i_min_A", (double)ac->prot.watch.op_i_min_A, 0, I, "\n");
}

/* OUT.json's "derived": the values derived from the motor's data
 * (firmware/params/params_design.md), the derived keys' and the settings
 * without a key, as the run used them. */
static void resolved_derived(FILE *f, const scenario_t *sc, const app_cfg_t *ac)
{
    fputs(" \"derived\": {\n", f);
    derived_keys(f, sc);
    derived_settings(f, sc, ac);
    fputs(" },\n", f);
}

/* OUT.json's "warnings": the scenario's, then the run's (HOST_TIMEOUT,
 * STEP1_REFUSED), each one string. */
static void resolved_warnings(FILE *f, const scenario_t *sc, const char *run_warnings)
{
    char w[SCENARIO_ERR_LEN];
    scenario_warnings(sc, w, sizeof w);
    fputs(" \"warnings\": [", f);
    if (w[0] != '\0') {
        json_string(f, w);
    }
    if (run_warnings[0] != '\0') {
        fputs((w[0] != '\0') ? ", " : "", f);
        json_string(f, run_warnings);
    }
    fputs("],\n", f);
}

/* OUT.json's "keys", the last: every key as resolved, and whether it was
 * set, left at its default or derived. */
static void resolved_keys(FILE *f, const scenario_t *sc)
{
    fputs(" \"keys\": {\n", f);
    const int n = scenario_key_count();
    for (int i = 0; i < n; i++) {
        scenario_key_info_t k;
        scenario_key_info(i, &k);
        const bool set = scenario_key_set(sc, k.section, k.name) != 0;
        fprintf(f, "  \"%s.%s\": {\"value\": ", k.section, k.name);
        scenario_key_json(f, sc, i);
        fprintf(f, ", \"source\": \"%s\"}%s", set ? "set" : ((k.from_keys != NULL) ? "derived" : "default"),
                (i + 1 < n) ? ",\n" : "\n");
    }
    fputs(" }}\n", f);
}

void sil_write_resolved(FILE *f, const scenario_t *sc, const sil_origin_t *origin, const char *run_warnings)
{
    const app_cfg_t *ac = &g_app.cfg;
    const ctrl_cfg_t *c = &ac->ctrl;
    static const char *const METHOD[] = { "conventional", "proposed" };
    static const char *const MODE[] = { "speed", "torque", "open_loop" };

    fputs("{\"scenario\": ", f);
    json_string(f, origin->scenario_path);
    fputs(",\n \"overrides\": [", f);
    for (int i = 0; i < origin->n_sets; i++) {
        json_string(f, origin->sets[i]);
        fputs((i + 1 < origin->n_sets) ? ", " : "", f);
    }
    fprintf(f, "], \"commission\": %s,\n \"plant\": {", origin->commission ? "true" : "false");
    json_num(f, "R_ohm", sc->plant.R_ohm, ", ");
    json_num(f, "L_H", sc->plant.L_H, ", ");
    json_num(f, "psif_Wb", sc->plant.psif_Wb, ", ");
    json_num(f, "pole_pairs", (double)sc->plant.pole_pairs, ", ");
    json_num(f, "J_kgm2", sc->plant.J_kgm2, ", ");
    json_num(f, "vdc_V", sc->plant.vdc_V, ", ");
    json_num(f, "deadtime_s", sc->plant.deadtime_s, ", ");
    json_num(f, "encoder_lines", (double)sc->plant.encoder_lines, ", ");
    json_num(f, "encoder_direction", (sc->plant.encoder_direction == SC_DIRECTION_REVERSED) ? -1.0 : 1.0, ", ");
    fprintf(f, "\"phase_order\": \"%s\"},\n", (sc->plant.phase_order == SC_PHASES_ACB) ? "acb" : "abc");
    fprintf(f, " \"controller\": {\"method\": \"%s\", \"mode\": \"%s\", ",
            METHOD[(sc->controller.method == SC_METHOD_PROPOSED) ? 1 : 0],
            MODE[(sc->controller.mode <= SC_MODE_OPEN_LOOP) ? sc->controller.mode : 0u]);
    json_flt(f, "R_ohm", c->R_Ohm, ", ");
    json_flt(f, "L_H", c->L_H, ", ");
    json_flt(f, "psif_Wb", c->psi_f_Wb, ", ");
    json_num(f, "pole_pairs", (double)c->pole_pairs, ", ");
    json_flt(f, "R_min_ohm", c->est_cfg.R_min_Ohm, ", ");
    json_flt(f, "R_max_ohm", c->est_cfg.R_max_Ohm, ", ");
    json_flt(f, "deadtime_s", c->deadtime_s, ", ");
    json_flt(f, "pll_bw_rad_s", c->enc_pll_bw_rad_s, ", ");
    json_flt(f, "speed_kp_Nms_rad", c->speed_kp_Nms_rad, ", ");
    json_flt(f, "speed_ki_Nm_rad", c->speed_ki_Nm_rad, ", ");
    json_flt(f, "te_max_Nm", c->te_max_Nm, ", ");
    json_flt(f, "i_max_A", ac->prot.i_max_A, ", ");
    json_flt(f, "i_limit_A", c->i_lim_A, ", ");
    json_flt(f, "overspeed_rpm", (float)((double)ac->prot.speed_max_rad_s * SIM_RPM_PER_RAD_S), ", ");
    json_num(f, "config_status", (double)ctrl_status(&g_app.ctrl), "},\n");
    resolved_derived(f, sc, ac);
    resolved_warnings(f, sc, run_warnings);
    resolved_keys(f, sc);
}
