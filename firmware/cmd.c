/* cmd.c - the operator's command block; see cmd.h. */
#include "cmd.h"

#include "mathx.h"

#define RPM_TO_RAD_S (MATHX_TWO_PI_F / 60.0f)

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
}

/* True when x is finite and |x| <= lim (a NaN fails both). */
static bool within(float x, float lim)
{
    return mathx_isfinitef(x) && (mathx_fabsf(x) <= lim);
}

void cmd_apply(volatile cmd_t *cmd, const cmd_limits_t *lim, app_t *app)
{
    /* One snapshot: the debugger may write while this runs. */
    const cmd_t c = *cmd;
    cmd_error_t err = CMD_OK;
    ctrl_ref_t ref = app->ctrl.ref;

    if (c.method > (uint16_t)CTRL_METHOD_PROPOSED) {
        err = CMD_ERR_METHOD;
    } else if ((c.method == (uint16_t)CTRL_METHOD_PROPOSED) &&
               ((app->cfg.rsid_mode == APP_RSID_OFF) || ((app->warnings & APP_WARN_STEP1_REFUSED) != 0u))) {
        err = CMD_ERR_METHOD_NO_STEP1; /* no silent fallback to the conventional method */
    } else if ((ctrl_method_t)c.method != app->ctrl.method) {
        if (!ctrl_set_method(&app->ctrl, (ctrl_method_t)c.method)) {
            err = CMD_ERR_METHOD_CFG;
        }
    }

    if (c.mode > (uint16_t)CTRL_MODE_SPEED) {
        err = CMD_ERR_MODE;
    } else {
        ctrl_set_mode(&app->ctrl, (ctrl_mode_t)c.mode);
    }

    /* Each reference is taken only when valid; a refused one keeps its old value. */
    if (within(c.speed_ref_rpm, lim->speed_max_rpm)) {
        ref.speed_ref_rad_s = c.speed_ref_rpm * RPM_TO_RAD_S;
    } else {
        err = CMD_ERR_SPEED;
    }
    if (within(c.te_ref_Nm, lim->te_max_Nm)) {
        ref.te_ref_Nm = c.te_ref_Nm;
    } else {
        err = CMD_ERR_TORQUE;
    }
    if (within(c.ud_ref_V, lim->u_max_V) && within(c.uq_ref_V, lim->u_max_V)) {
        ref.ud_ref_V = c.ud_ref_V;
        ref.uq_ref_V = c.uq_ref_V;
    } else {
        err = CMD_ERR_VOLTAGE;
    }
    ctrl_set_ref(&app->ctrl, &ref);

    if (c.fault_reset != 0u) {
        app_fault_reset(app);
        cmd->fault_reset = 0u;
    }
    if (c.run != c.run_taken) {
        if (c.run != 0u) {
            app_request_start(app);
        } else {
            app_request_stop(app);
        }
        cmd->run_taken = c.run;
    }
    cmd->error = (uint16_t)err;
}
