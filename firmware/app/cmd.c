/* cmd.c - the operator's command block; see cmd.h. */
#include "cmd.h"

#include "mathx.h"


void cmd_init(volatile cmd_t *cmd)
{
    cmd->run = 0u;
    cmd->fault_reset = 0u;
    cmd->method = (uint16_t)CTRL_METHOD_CONVENTIONAL;
    cmd->mode = (uint16_t)CTRL_MODE_SPEED;
    cmd->speed_ref_rpm = 0.0f;
    cmd->te_ref_Nm = 0.0f;
    cmd->ud_ref_V = 0.0f;
    cmd->uq_ref_V = 0.0f;
    cmd->error = (uint16_t)CMD_OK;
    cmd->run_taken = 0u;
    cmd->level = 0u;
    cmd->level_now = 0u;
    cmd->ia_adc_A = 0.0f;
    cmd->ib_adc_A = 0.0f;
    cmd->vdc_adc_V = 0.0f;
    cmd->ia_offset_A = 0.0f;
    cmd->ib_offset_A = 0.0f;
    cmd->enc_counts = 0;
    cmd->pole_pairs_est = 0.0f;
}

/* The drive's reports into the block (level.h: levels 2 and 3). */
static void report(volatile cmd_t *cmd, const app_t *app)
{
    cmd->level_now = app->level;
    cmd->ia_adc_A = app->adc.ia_A;
    cmd->ib_adc_A = app->adc.ib_A;
    cmd->vdc_adc_V = app->adc.vdc_V;
    cmd->ia_offset_A = app->offset_ia_A;
    cmd->ib_offset_A = app->offset_ib_A;
    cmd->enc_counts = app->rot.out.counts;
    cmd->pole_pairs_est = app->rot.out.pole_pairs_est;
}

void cmd_comm_init(volatile cmd_comm_t *rep)
{
    rep->start = 0u;
    rep->state = 0u;
    rep->stage = 0u;
    rep->fault = 0u;
    rep->fault_value = 0.0f;
    rep->fault_limit = 0.0f;
    rep->R_Ohm = 0.0f;
    rep->L_H = 0.0f;
    rep->psi_f_Wb = 0.0f;
    rep->pole_pairs = 0u;
    rep->J_kgm2 = 0.0f;
    rep->B_Nms = 0.0f;
    rep->enc_offset_el_rad = 0.0f;
    rep->speed_kp_Nms_rad = 0.0f;
    rep->speed_ki_Nm_rad = 0.0f;
}

void cmd_comm_apply(volatile cmd_comm_t *rep, const volatile cmd_t *cmd, app_t *app)
{
    const comm_result_t *r;
    uint16_t state = 0u;

    if (app->comm == NULL) {
        rep->start = 0u; /* no commissioning attached (app_attach_comm) */
        return;
    }
    r = &app->comm->res;
    if (rep->start != 0u) {
        if (cmd->run == 0u) {
            app_request_commission(app); /* acted on only while stopped (INIT, IDLE) */
        }
        rep->start = 0u;
    }
    if (app->comm_valid) {
        state = 2u;
    } else if (app->state == APP_STATE_COMMISSION) {
        state = 1u;
    } else if ((app->state == APP_STATE_FAULT) && (app->snapshot.state == APP_STATE_COMMISSION)) {
        state = 3u;
    } else {
        state = rep->state; /* kept until the next commissioning */
    }
    rep->state = state;
    rep->stage = (uint16_t)app->comm->stage;
    if (state == 3u) {
        rep->fault = (uint16_t)app->fault;
        rep->fault_value = app->snapshot.value;
        rep->fault_limit = app->snapshot.limit;
    }
    if (state == 2u) {
        rep->R_Ohm = r->R_Ohm;
        rep->L_H = r->L_H;
        rep->psi_f_Wb = r->psi_f_Wb;
        rep->pole_pairs = r->pole_pairs;
        rep->J_kgm2 = r->J_kgm2;
        rep->B_Nms = r->B_Nms;
        rep->enc_offset_el_rad = r->enc_offset_el_rad;
        rep->speed_kp_Nms_rad = r->speed_kp_Nms_rad;
        rep->speed_ki_Nm_rad = r->speed_ki_Nm_rad;
    }
}

/* True when x is finite and |x| <= lim (a NaN fails both). */
static bool within(float x, float lim)
{
    return mathx_isfinitef(x) && (mathx_fabsf(x) <= lim);
}

/* Request c's method into *op when the drive can run it; else *err says
 * why not (no silent fallback) and op keeps its method. */
static void take_method(const cmd_t *c, const app_t *app, app_op_t *op, cmd_error_t *err)
{
    if (c->method > (uint16_t)CTRL_METHOD_PROPOSED) {
        *err = CMD_ERR_METHOD;
    } else if ((c->method == (uint16_t)CTRL_METHOD_PROPOSED) &&
               ((app->cfg.rsid.mode == APP_RSID_OFF) || (((app->warnings & APP_WARN_STEP1_REFUSED) != 0u) &&
                                                         (app->cfg.rsid.on_refusal != APP_RSID_REFUSAL_TOLD)))) {
        *err = CMD_ERR_METHOD_NO_STEP1; /* no silent fallback to the conventional method (told: step 2 runs) */
    } else if ((c->method == (uint16_t)CTRL_METHOD_PROPOSED) &&
               ((ctrl_status(&app->ctrl) & CTRL_CFG_NEEDED_PROPOSED) != 0u)) {
        *err = CMD_ERR_METHOD_CFG;
    } else {
        op->method = (ctrl_method_t)c->method;
    }
}

/* Request c's mode and references into *op, each taken only when valid; a
 * refused one keeps its old value and sets *err (the last refusal wins). */
static void take_mode_and_refs(const cmd_t *c, const cmd_limits_t *lim, app_op_t *op, cmd_error_t *err)
{
    if (c->mode > (uint16_t)CTRL_MODE_SPEED) {
        *err = CMD_ERR_MODE;
    } else {
        op->mode = (ctrl_mode_t)c->mode;
    }
    if (within(c->speed_ref_rpm, lim->speed_max_rpm)) {
        op->ref.speed_ref_rad_s = c->speed_ref_rpm * MATHX_RAD_S_PER_RPM_F;
    } else {
        *err = CMD_ERR_SPEED;
    }
    if (within(c->te_ref_Nm, lim->te_max_Nm)) {
        op->ref.te_ref_Nm = c->te_ref_Nm;
    } else {
        *err = CMD_ERR_TORQUE;
    }
    if (within(c->ud_ref_V, lim->u_max_V) && within(c->uq_ref_V, lim->u_max_V)) {
        op->ref.ud_ref_V = c->ud_ref_V;
        op->ref.uq_ref_V = c->uq_ref_V;
    } else {
        *err = CMD_ERR_VOLTAGE;
    }
}

/* Request c's fault reset and run edge (start, stop) to the app, each
 * acknowledged in *cmd: fault_reset back to 0, run_taken = run. */
static void take_actions(volatile cmd_t *cmd, const cmd_t *c, app_t *app)
{
    if (c->fault_reset != 0u) {
        app_fault_reset(app);
        cmd->fault_reset = 0u;
    }
    if (c->run != c->run_taken) {
        if (c->run != 0u) {
            app_request_start(app);
        } else {
            app_request_stop(app);
        }
        cmd->run_taken = c->run;
    }
}

void cmd_apply(volatile cmd_t *cmd, const cmd_limits_t *lim, app_t *app)
{
    /* One snapshot: the debugger may write while this runs. */
    const cmd_t c = *cmd;
    cmd_error_t err = CMD_OK;
    /* the last request (the background's own): a refused field keeps its value */
    app_op_t op = app->op_req;

    take_method(&c, app, &op, &err);
    take_mode_and_refs(&c, lim, &op, &err);
    app_request_op(app, &op); /* the ISR takes it at the start of its next period */

    if (c.level > LEVEL_MAX) {
        err = CMD_ERR_LEVEL;
    } else if (c.level != 0u) {
        app_request_level(app, c.level); /* taken at the next start */
    }
    take_actions(cmd, &c, app);
    cmd->error = (uint16_t)err;
    report(cmd, app);
}
