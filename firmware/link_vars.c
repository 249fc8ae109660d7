/* link_vars.c - the link's variable table; see link_vars.h. */
#include "link_vars.h"

#include <stddef.h>

#include "link_codec.h"
#include "mathx.h"

#define U16_MAX_F 65535.0f
#define U32_MAX_F 4294967295.0f
/* Ranges of quantities with no configured limit, from the nominal value they scale with. */
#define FLUX_RANGE_PER_PSIF 2.0f      /* |psi_s|, psi_f^ up to twice the PM flux */
#define L_RANGE_PER_L 2.0f            /* L^ up to twice the nominal inductance */
#define FNV_OFFSET 2166136261ul
#define FNV_PRIME 16777619ul
#define FLOAT_BYTES 4u

#define R LINK_ACC_READ
#define W LINK_ACC_WRITE
#define WS LINK_ACC_WRITE_STOPPED
static const link_var_t VARS[LV_COUNT] = {
    [LV_STATE] = { "state", "", LINK_T_U16, R, LINK_CAP_I16 },
    [LV_FAULT] = { "fault", "", LINK_T_U16, R, LINK_CAP_I16 },
    [LV_FLAGS] = { "flags", "", LINK_T_U16, R, LINK_CAP_I16 },
    [LV_SPEED_EST_RPM] = { "speed_est_rpm", "r/min", LINK_T_F32, R, LINK_CAP_I16 },
    [LV_SPEED_REF_RPM] = { "speed_ref_rpm", "r/min", LINK_T_F32, W, LINK_CAP_I16 },
    [LV_TE_CMD_NM] = { "te_cmd_Nm", "N m", LINK_T_F32, W, LINK_CAP_I16 },
    [LV_TE_REF_NM] = { "te_ref_Nm", "N m", LINK_T_F32, R, LINK_CAP_I16 },
    [LV_TE_EST_NM] = { "te_est_Nm", "N m", LINK_T_F32, R, LINK_CAP_I16 },
    [LV_PSI_REF_WB] = { "psi_ref_Wb", "Wb", LINK_T_F32, R, LINK_CAP_I16 },
    [LV_PSI_EST_WB] = { "psi_est_Wb", "Wb", LINK_T_F32, R, LINK_CAP_I16 },
    [LV_ID_MEAS_A] = { "id_meas_A", "A", LINK_T_F32, R, LINK_CAP_I16 },
    [LV_IQ_MEAS_A] = { "iq_meas_A", "A", LINK_T_F32, R, LINK_CAP_I16 },
    [LV_UD_CMD_V] = { "ud_cmd_V", "V", LINK_T_F32, R, LINK_CAP_I16 },
    [LV_UQ_CMD_V] = { "uq_cmd_V", "V", LINK_T_F32, R, LINK_CAP_I16 },
    [LV_UD_REF_V] = { "ud_ref_V", "V", LINK_T_F32, W, LINK_CAP_I16 },
    [LV_UQ_REF_V] = { "uq_ref_V", "V", LINK_T_F32, W, LINK_CAP_I16 },
    [LV_R_EST_OHM] = { "R_est_ohm", "Ohm", LINK_T_F32, R, LINK_CAP_F32 },
    [LV_L_EST_H] = { "L_est_H", "H", LINK_T_F32, R, LINK_CAP_F32 },
    [LV_PSIF_EST_WB] = { "psif_est_Wb", "Wb", LINK_T_F32, R, LINK_CAP_F32 },
    [LV_EST] = { "est", "", LINK_T_U16, R, LINK_CAP_I16 },
    [LV_EST_HOLD] = { "est_hold", "", LINK_T_U16, R, LINK_CAP_I16 },
    [LV_METHOD] = { "method", "", LINK_T_U16, WS, LINK_CAP_I16 },
    [LV_MODE] = { "mode", "", LINK_T_U16, WS, LINK_CAP_I16 },
    [LV_CMD_ERROR] = { "cmd_error", "", LINK_T_U16, R, LINK_CAP_I16 },
    [LV_TICKS] = { "ticks", "", LINK_T_U32, R, LINK_CAP_I16 },
    [LV_LINK_WRITES] = { "link_writes", "", LINK_T_U32, R, LINK_CAP_I16 },
    [LV_LINK_ERR_CRC] = { "link_err_crc", "", LINK_T_U16, R, LINK_CAP_I16 },
    [LV_LINK_ERR_FRAMING] = { "link_err_framing", "", LINK_T_U16, R, LINK_CAP_I16 },
    [LV_LINK_ERR_OVERRUN] = { "link_err_overrun", "", LINK_T_U16, R, LINK_CAP_I16 },
    [LV_LINK_STREAM_DROPPED] = { "link_stream_dropped", "", LINK_T_U16, R, LINK_CAP_I16 },
    [LV_LINK_ERR_LINE] = { "link_err_line", "", LINK_T_U16, R, LINK_CAP_I16 },
    [LV_RESET_BY_WATCHDOG] = { "reset_by_watchdog", "", LINK_T_U16, R, LINK_CAP_I16 },
    [LV_COMM_RESULT] = { "comm_result", "", LINK_T_U16, R, LINK_CAP_I16 },
    [LV_COMM_STAGE] = { "comm_stage", "", LINK_T_U16, R, LINK_CAP_I16 },
    [LV_COMM_R_OHM] = { "comm_R_ohm", "Ohm", LINK_T_F32, R, LINK_CAP_F32 },
    [LV_COMM_L_H] = { "comm_L_H", "H", LINK_T_F32, R, LINK_CAP_F32 },
    [LV_COMM_PSIF_WB] = { "comm_psif_Wb", "Wb", LINK_T_F32, R, LINK_CAP_F32 },
    [LV_COMM_POLE_PAIRS] = { "comm_pole_pairs", "", LINK_T_U16, R, LINK_CAP_I16 },
    [LV_COMM_J_KGM2] = { "comm_J_kgm2", "kg m^2", LINK_T_F32, R, LINK_CAP_F32 },
    [LV_COMM_B_NMS] = { "comm_B_Nms", "N m s", LINK_T_F32, R, LINK_CAP_F32 },
    [LV_COMM_ENC_OFFSET] = { "comm_encoder_offset_el_rad", "rad", LINK_T_F32, R, LINK_CAP_F32 },
    [LV_COMM_SPEED_KP] = { "comm_speed_kp_Nms_rad", "N m s/rad", LINK_T_F32, R, LINK_CAP_F32 },
    [LV_COMM_SPEED_KI] = { "comm_speed_ki_Nm_rad", "N m/rad", LINK_T_F32, R, LINK_CAP_F32 },
    [LV_LEVEL] = { "level", "", LINK_T_U16, R, LINK_CAP_I16 },
    [LV_LEVEL_NEXT] = { "level_next", "", LINK_T_U16, R, LINK_CAP_I16 },
};
#undef R
#undef W
#undef WS

const link_var_t *link_var(uint16_t id)
{
    return &VARS[(id < (uint16_t)LV_COUNT) ? id : 0u];
}

static void sym(float x, float *lo, float *hi)
{
    *lo = -x;
    *hi = x;
}

void link_var_limits(const link_target_t *t, uint16_t id, float *lo, float *hi)
{
    const app_cfg_t *c = &t->app->cfg;
    const float speed_max_rpm = c->prot.speed_max_rad_s / MATHX_RAD_S_PER_RPM_F;
    const float flux_max_Wb = FLUX_RANGE_PER_PSIF * c->ctrl.psi_f_Wb;
    *lo = 0.0f;
    switch (id) {
    case LV_SPEED_EST_RPM: sym(speed_max_rpm, lo, hi); break;
    case LV_SPEED_REF_RPM: sym(t->lim->speed_max_rpm, lo, hi); break;
    case LV_TE_CMD_NM: sym(t->lim->te_max_Nm, lo, hi); break;
    case LV_TE_REF_NM: case LV_TE_EST_NM: sym(c->ctrl.te_max_Nm, lo, hi); break;
    case LV_PSI_REF_WB: case LV_PSI_EST_WB: case LV_PSIF_EST_WB: sym(flux_max_Wb, lo, hi); break;
    case LV_ID_MEAS_A: case LV_IQ_MEAS_A: sym(c->prot.i_max_A, lo, hi); break;
    case LV_UD_CMD_V: case LV_UQ_CMD_V: sym(c->ctrl.u_max_V, lo, hi); break;
    case LV_UD_REF_V: case LV_UQ_REF_V: sym(t->lim->u_max_V, lo, hi); break;
    case LV_R_EST_OHM: *hi = c->ctrl.est_cfg.R_max_Ohm; break;
    case LV_L_EST_H: *hi = L_RANGE_PER_L * c->ctrl.L_H; break;
    case LV_STATE: *hi = (float)APP_STATE_FAULT; break;
    case LV_METHOD: *hi = (float)CTRL_METHOD_PROPOSED; break;
    /* the commissioning's values: what a plausible measurement can reach on this drive */
    case LV_COMM_RESULT: *hi = (float)COMM_REFUSED; break;
    case LV_COMM_STAGE: *hi = (float)COMM_STAGE_WIRING; break;
    case LV_COMM_R_OHM: *hi = c->ctrl.est_cfg.R_max_Ohm; break;
    case LV_COMM_L_H: *hi = L_RANGE_PER_L * c->ctrl.L_H; break;
    case LV_COMM_PSIF_WB: *hi = flux_max_Wb; break;
    case LV_COMM_ENC_OFFSET: *hi = MATHX_TWO_PI_F; break;
    case LV_MODE: *hi = (float)CTRL_MODE_SPEED; break;
    case LV_LEVEL: case LV_LEVEL_NEXT: *hi = (float)LEVEL_MAX; break;
    default: *hi = (link_var(id)->type == LINK_T_U32) ? U32_MAX_F : U16_MAX_F; break;
    }
}

static link_src_t src_of(const volatile float *p, float raw_per_unit)
{
    link_src_t s;
    s.p = p;
    s.raw_per_unit = raw_per_unit;
    return s;
}

/* As link_var_get (link_isr.c) reads each one: the same field, the same conversion. */
link_src_t link_var_source(const link_target_t *t, uint16_t id)
{
    const app_t *a = t->app;
    const ctrl_mon_t *m = &a->ctrl.mon;
    const est_out_t *e = est_output(ctrl_est(&a->ctrl));
    switch (id) {
    case LV_SPEED_EST_RPM: return src_of(&m->speed_mech_rad_s, MATHX_RAD_S_PER_RPM_F);
    case LV_SPEED_REF_RPM: return src_of(&a->op_taken.ref.speed_ref_rad_s, MATHX_RAD_S_PER_RPM_F);
    case LV_TE_CMD_NM: return src_of(&a->op_taken.ref.te_ref_Nm, 1.0f);
    case LV_TE_REF_NM: return src_of(&m->te_ref_Nm, 1.0f);
    case LV_TE_EST_NM: return src_of(&m->te_est_Nm, 1.0f);
    case LV_PSI_REF_WB: return src_of(&m->psi_ref_Wb, 1.0f);
    case LV_PSI_EST_WB: return src_of(&m->psi_est_Wb, 1.0f);
    case LV_ID_MEAS_A: return src_of(&m->id_A, 1.0f);
    case LV_IQ_MEAS_A: return src_of(&m->iq_A, 1.0f);
    case LV_UD_CMD_V: return src_of(&m->ud_V, 1.0f);
    case LV_UQ_CMD_V: return src_of(&m->uq_V, 1.0f);
    case LV_UD_REF_V: return src_of(&a->op_taken.ref.ud_ref_V, 1.0f);
    case LV_UQ_REF_V: return src_of(&a->op_taken.ref.uq_ref_V, 1.0f);
    case LV_R_EST_OHM: return src_of(&e->R_Ohm, 1.0f);
    case LV_L_EST_H: return src_of(&e->L_H, 1.0f);
    case LV_PSIF_EST_WB: return src_of(&e->psi_f_Wb, 1.0f);
    default: return src_of(NULL, 1.0f);  /* integers and codes */
    }
}

/* The command block set to what the drive runs with (app.op_req), run and fault reset untouched. */
static void cmd_sync(const link_target_t *t)
{
    const app_t *a = t->app;
    volatile cmd_t *c = t->cmd;
    c->method = (uint16_t)a->op_req.method;
    c->mode = (uint16_t)a->op_req.mode;
    c->speed_ref_rpm = a->op_req.ref.speed_ref_rad_s / MATHX_RAD_S_PER_RPM_F;
    c->te_ref_Nm = a->op_req.ref.te_ref_Nm;
    c->ud_ref_V = a->op_req.ref.ud_ref_V;
    c->uq_ref_V = a->op_req.ref.uq_ref_V;
}

/* Put v into the command field of id (a writable id). */
static void cmd_field_set(volatile cmd_t *c, uint16_t id, link_val_t v)
{
    switch (id) {
    case LV_SPEED_REF_RPM: c->speed_ref_rpm = v.f; break;
    case LV_TE_CMD_NM: c->te_ref_Nm = v.f; break;
    case LV_UD_REF_V: c->ud_ref_V = v.f; break;
    case LV_UQ_REF_V: c->uq_ref_V = v.f; break;
    /* a value beyond 16 bits must not wrap into a valid one */
    case LV_METHOD: c->method = (v.u > 0xFFFFul) ? 0xFFFFu : (uint16_t)v.u; break;
    case LV_MODE: c->mode = (v.u > 0xFFFFul) ? 0xFFFFu : (uint16_t)v.u; break;
    default: break;
    }
}

static bool stopped(const app_t *a)
{
    return (a->state == APP_STATE_INIT) || (a->state == APP_STATE_IDLE) || (a->state == APP_STATE_FAULT);
}

uint16_t link_var_write(const link_target_t *t, uint16_t id, link_val_t v, bool *access_refused)
{
    const link_var_t *d = link_var(id);
    *access_refused = (id >= (uint16_t)LV_COUNT) || (d->access == (uint16_t)LINK_ACC_READ) ||
                      ((d->access == (uint16_t)LINK_ACC_WRITE_STOPPED) && !stopped(t->app));
    if (*access_refused) {
        return (uint16_t)CMD_OK;
    }
    cmd_sync(t);
    cmd_field_set(t->cmd, id, v);
    cmd_apply(t->cmd, t->lim, t->app);
    const uint16_t err = t->cmd->error;
    if (err != (uint16_t)CMD_OK) {
        cmd_sync(t);                     /* the refused value out of the block: it would be refused again */
        cmd_apply(t->cmd, t->lim, t->app);
        t->cmd->error = err;             /* still named for the expressions window */
    }
    return err;
}

bool link_action(const link_target_t *t, uint16_t action)
{
    volatile cmd_t *c = t->cmd;
    switch (action) {
    case LINK_ACTION_START:
        c->run = 1u;
        c->run_taken = 0u;               /* an edge: cmd_apply acts on a change only */
        break;
    case LINK_ACTION_STOP:
    case LINK_ACTION_QUIT:
        c->run = 0u;
        c->run_taken = 1u;
        break;
    case LINK_ACTION_FAULT_RESET:
        c->fault_reset = 1u;
        break;
    case LINK_ACTION_COMMISSION:
        if (c->run == 0u) {
            app_request_commission(t->app); /* as cmd_comm_apply: acted on only while stopped */
        }
        break;
    default:
        return false;
    }
    cmd_sync(t);
    cmd_apply(c, t->lim, t->app);
    return true;
}

uint16_t link_level(const link_target_t *t, uint16_t level)
{
    if ((level < LEVEL_MIN) || (level > LEVEL_MAX)) {
        return (uint16_t)CMD_ERR_LEVEL;  /* 0 would mean "keep" to cmd_apply: not a level to ask for */
    }
    cmd_sync(t);
    t->cmd->level = level;
    cmd_apply(t->cmd, t->lim, t->app);
    return t->cmd->error;
}

static uint32_t fnv(uint32_t h, uint16_t byte)
{
    return (h ^ (uint32_t)(byte & 0x00FFu)) * FNV_PRIME;
}

static uint32_t fnv_str(uint32_t h, const char *s)
{
    for (uint16_t i = 0u; s[i] != '\0'; i++) {
        h = fnv(h, (uint16_t)s[i]);
    }
    return fnv(h, 0u);
}

uint32_t link_vars_hash(const link_target_t *t)
{
    uint32_t h = FNV_OFFSET;
    for (uint16_t i = 0u; i < (uint16_t)LV_COUNT; i++) {
        float lo;
        float hi;
        uint16_t b[FLOAT_BYTES * 2u];
        link_var_limits(t, i, &lo, &hi);
        (void)link_put_f32(b, link_put_f32(b, 0u, lo), hi);
        h = fnv_str(h, VARS[i].name);
        h = fnv_str(h, VARS[i].unit);
        h = fnv(h, VARS[i].type);
        h = fnv(h, VARS[i].access);
        h = fnv(h, VARS[i].capture);
        for (uint16_t k = 0u; k < FLOAT_BYTES * 2u; k++) {
            h = fnv(h, b[k]);
        }
    }
    return h;
}
