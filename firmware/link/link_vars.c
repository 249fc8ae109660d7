/* link_vars.c - the link's variable table; see link_vars.h. Its values
 * (link_var_get) are the ISR's too: in RAM (RAMFUNC); the rest runs from
 * flash. */
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
static const link_var_t VARS[LV_PARAM_FIRST] = {
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
    [LV_COMM_DEADTIME_S] = { "comm_deadtime_s", "s", LINK_T_F32, R, LINK_CAP_F32 },
    [LV_COMM_DEVICE_DROP_V] = { "comm_device_drop_V", "V", LINK_T_F32, R, LINK_CAP_F32 },
    [LV_COMM_UNTOLD_DEADTIME_S] = { "comm_untold_deadtime_s", "s", LINK_T_F32, R, LINK_CAP_F32 },
    [LV_VDC_V] = { "vdc_V", "V", LINK_T_F32, R, LINK_CAP_I16 },
    [LV_METHOD_RAN] = { "method_ran", "", LINK_T_U16, R, LINK_CAP_I16 },
    [LV_HOLD_REASON] = { "hold_reason", "", LINK_T_U16, R, LINK_CAP_I16 },
    [LV_FAULT_PRESENT] = { "fault_present", "", LINK_T_U16, R, LINK_CAP_I16 },
    [LV_HOST_TIMEOUT_S] = { "host_timeout_s", "s", LINK_T_F32, W, LINK_CAP_I16 },
    [LV_NV_STATUS] = { "nv_status", "", LINK_T_U16, R, LINK_CAP_I16 },
};
/* the parameters' descriptors: written when stopped, captured as float32 (integers as they are) */
#define LINK_PARAM_VAR(id, key, unit, type, field, lo, hi, lo_open) \
    { key, unit, ((type) == LINK_PARAM_U16) ? (uint16_t)LINK_T_U16 : (uint16_t)LINK_T_F32, WS, \
      ((type) == LINK_PARAM_U16) ? (uint16_t)LINK_CAP_I16 : (uint16_t)LINK_CAP_F32 },
static const link_var_t PARAM_VARS[LINK_PARAM_COUNT] = { LINK_PARAMS(LINK_PARAM_VAR) };
#undef LINK_PARAM_VAR
#undef R
#undef W
#undef WS

const link_var_t *link_var(uint16_t id)
{
    if ((id >= (uint16_t)LV_PARAM_FIRST) && (id < (uint16_t)LV_COUNT)) {
        return &PARAM_VARS[id - (uint16_t)LV_PARAM_FIRST];
    }
    return &VARS[(id < (uint16_t)LV_PARAM_FIRST) ? id : 0u];
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
    if ((id >= (uint16_t)LV_PARAM_FIRST) && (id < (uint16_t)LV_COUNT)) {
        const link_param_t *d = link_param((uint16_t)(id - (uint16_t)LV_PARAM_FIRST));
        *lo = d->lo;
        *hi = d->hi;
        return;
    }
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
    case LV_STATE: *hi = (float)APP_STATE_LAST; break;
    case LV_FAULT: case LV_FAULT_PRESENT: *hi = (float)APP_FAULT_LAST; break;
    case LV_CMD_ERROR: *hi = (float)CMD_ERR_LAST; break;
    case LV_EST: *hi = (float)EST_STEP2; break;
    case LV_METHOD: case LV_METHOD_RAN: *hi = (float)CTRL_METHOD_PROPOSED; break;
    case LV_VDC_V: *hi = c->prot.vdc_max_V; break;
    case LV_HOST_TIMEOUT_S: *hi = LINK_HOST_TIMEOUT_MAX_S; break;
    case LV_NV_STATUS: *hi = (float)LINK_NV_STATUS_LAST; break;
    /* the commissioning's values: what a plausible measurement can reach on this drive */
    case LV_COMM_RESULT: *hi = (float)COMM_REFUSED; break;
    case LV_COMM_STAGE: *hi = (float)COMM_STAGE_LAST; break;
    case LV_COMM_R_OHM: *hi = c->ctrl.est_cfg.R_max_Ohm; break;
    case LV_COMM_L_H: *hi = L_RANGE_PER_L * c->ctrl.L_H; break;
    case LV_COMM_PSIF_WB: *hi = flux_max_Wb; break;
    case LV_COMM_ENC_OFFSET: *hi = MATHX_TWO_PI_F; break;
    case LV_MODE: *hi = (float)CTRL_MODE_SPEED; break;
    case LV_LEVEL: case LV_LEVEL_NEXT: *hi = (float)LEVEL_MAX; break;
    default: *hi = (link_var(id)->type == LINK_T_U32) ? U32_MAX_F : U16_MAX_F; break;
    }
}

/* The values: read by the ISR (capture, stream), so in RAM. */
RAMFUNC static link_val_t of_u(uint32_t u)
{
    link_val_t v;
    v.u = u;
    v.f = (float)u;
    return v;
}

RAMFUNC static link_val_t of_f(float f)
{
    link_val_t v;
    v.u = 0u;
    v.f = f;
    return v;
}

RAMFUNC link_val_t link_var_get(const link_target_t *t, uint16_t id)
{
    const app_t *a = t->app;
    const ctrl_mon_t *m = app_monitor(a);
    const est_out_t *e = app_estimate(a);
    if (id >= (uint16_t)LV_PARAM_FIRST) {              /* a parameter: from the parameter set */
        const uint16_t k = (uint16_t)(id - (uint16_t)LV_PARAM_FIRST);
        const float x = (t->params->set != NULL) ? link_param_get(t->params->set, k) : 0.0f;
        return (link_param(k)->type == (uint16_t)LINK_PARAM_U16) ? of_u((uint32_t)x) : of_f(x);
    }
    switch (id) {
    case LV_STATE: return of_u((uint32_t)a->state);
    case LV_FAULT: return of_u((uint32_t)a->fault);
    case LV_FLAGS: return of_u((uint32_t)(a->out.flags | a->warnings)); /* as the CSV's flags */
    case LV_SPEED_EST_RPM: return of_f(m->speed_mech_rad_s / MATHX_RAD_S_PER_RPM_F);
    case LV_SPEED_REF_RPM: return of_f(a->op_taken.ref.speed_ref_rad_s / MATHX_RAD_S_PER_RPM_F);
    case LV_TE_CMD_NM: return of_f(a->op_taken.ref.te_ref_Nm);
    case LV_TE_REF_NM: return of_f(m->te_ref_Nm);
    case LV_TE_EST_NM: return of_f(m->te_est_Nm);
    case LV_PSI_REF_WB: return of_f(m->psi_ref_Wb);
    case LV_PSI_EST_WB: return of_f(m->psi_est_Wb);
    case LV_ID_MEAS_A: return of_f(m->id_A);
    case LV_IQ_MEAS_A: return of_f(m->iq_A);
    case LV_UD_CMD_V: return of_f(m->ud_V);
    case LV_UQ_CMD_V: return of_f(m->uq_V);
    case LV_UD_REF_V: return of_f(a->op_taken.ref.ud_ref_V);
    case LV_UQ_REF_V: return of_f(a->op_taken.ref.uq_ref_V);
    case LV_R_EST_OHM: return of_f(e->R_Ohm);
    case LV_L_EST_H: return of_f(e->L_H);
    case LV_PSIF_EST_WB: return of_f(e->psi_f_Wb);
    case LV_EST: return of_u((uint32_t)e->phase);
    case LV_EST_HOLD: return of_u((uint32_t)e->hold);
    case LV_METHOD: return of_u((uint32_t)a->op_taken.method);
    case LV_MODE: return of_u((uint32_t)a->op_taken.mode);
    case LV_CMD_ERROR: return of_u((uint32_t)t->cmd->error);
    case LV_TICKS: return of_u(a->ticks);
    case LV_LINK_WRITES: return of_u(t->stats->writes);
    case LV_LINK_ERR_CRC: return of_u((uint32_t)t->stats->err_crc);
    case LV_LINK_ERR_FRAMING: return of_u((uint32_t)t->stats->err_framing);
    case LV_LINK_ERR_OVERRUN: return of_u((uint32_t)t->stats->err_overrun);
    case LV_LINK_STREAM_DROPPED: return of_u((uint32_t)t->stats->stream_dropped);
    case LV_LINK_ERR_LINE: return of_u((uint32_t)t->stats->err_line);
    case LV_RESET_BY_WATCHDOG: return of_u((uint32_t)t->stats->reset_by_watchdog);
    case LV_COMM_RESULT: return of_u((uint32_t)app_comm_result(a));
    case LV_COMM_STAGE: return of_u((a->comm != NULL) ? (uint32_t)a->comm->stage : 0u);
    /* the commissioning's, 0 without one attached (app_attach_comm) */
    case LV_COMM_R_OHM: return of_f((a->comm != NULL) ? a->comm->res.R_Ohm : 0.0f);
    case LV_COMM_L_H: return of_f((a->comm != NULL) ? a->comm->res.L_H : 0.0f);
    case LV_COMM_PSIF_WB: return of_f((a->comm != NULL) ? a->comm->res.psi_f_Wb : 0.0f);
    case LV_COMM_POLE_PAIRS: return of_u((a->comm != NULL) ? (uint32_t)a->comm->res.pole_pairs : 0u);
    case LV_COMM_J_KGM2: return of_f((a->comm != NULL) ? a->comm->res.J_kgm2 : 0.0f);
    case LV_COMM_B_NMS: return of_f((a->comm != NULL) ? a->comm->res.B_Nms : 0.0f);
    case LV_COMM_ENC_OFFSET: return of_f((a->comm != NULL) ? a->comm->res.enc_offset_el_rad : 0.0f);
    case LV_COMM_SPEED_KP: return of_f((a->comm != NULL) ? a->comm->res.speed_kp_Nms_rad : 0.0f);
    case LV_COMM_SPEED_KI: return of_f((a->comm != NULL) ? a->comm->res.speed_ki_Nm_rad : 0.0f);
    case LV_LEVEL: return of_u((uint32_t)a->level);
    case LV_LEVEL_NEXT: return of_u((uint32_t)a->req_level);
    case LV_COMM_DEADTIME_S: return of_f((a->comm != NULL) ? a->comm->res.deadtime_s : 0.0f);
    case LV_COMM_DEVICE_DROP_V: return of_f((a->comm != NULL) ? a->comm->res.device_drop_V : 0.0f);
    case LV_COMM_UNTOLD_DEADTIME_S: return of_f((a->comm != NULL) ? a->comm->res.untold_deadtime_s : 0.0f);
    case LV_VDC_V: return of_f(a->vdc_V);
    case LV_METHOD_RAN: return of_u((uint32_t)app_method_ran(a));
    case LV_HOLD_REASON: return of_u((uint32_t)e->hold);
    case LV_FAULT_PRESENT: return of_u((uint32_t)a->fault_present);
    case LV_HOST_TIMEOUT_S: return of_f(t->host->timeout_s);
    case LV_NV_STATUS: return of_u((t->params->store != NULL) ? (uint32_t)t->params->store->status : 0u);
    default: return of_u(0u);
    }
}

static link_src_t src_of(const volatile float *p, float raw_per_unit)
{
    link_src_t s;
    s.p = p;
    s.raw_per_unit = raw_per_unit;
    return s;
}

/* As link_var_get reads each one: the same field, the same conversion. */
link_src_t link_var_source(const link_target_t *t, uint16_t id)
{
    const app_t *a = t->app;
    const ctrl_mon_t *m = app_monitor(a);
    const est_out_t *e = app_estimate(a);
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
    case LV_VDC_V: return src_of(&a->vdc_V, 1.0f);
    case LV_R_EST_OHM: return src_of(&e->R_Ohm, 1.0f);
    case LV_L_EST_H: return src_of(&e->L_H, 1.0f);
    case LV_PSIF_EST_WB: return src_of(&e->psi_f_Wb, 1.0f);
    default: return src_of(NULL, 1.0f);  /* integers and codes */
    }
}

void link_cmd_sync(const link_target_t *t)
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

/* A link setting (not a command field): v within its limits, or CMD_ERR_RANGE (kept as it was). */
static uint16_t link_setting_write(const link_target_t *t, uint16_t id, float v)
{
    float lo;
    float hi;
    link_var_limits(t, id, &lo, &hi);
    if (!(mathx_isfinitef(v) && (v >= lo) && (v <= hi))) {
        return (uint16_t)CMD_ERR_RANGE;
    }
    t->host->timeout_s = v;              /* LV_HOST_TIMEOUT_S: the one setting for now */
    return (uint16_t)CMD_OK;
}

/* Parameter k (stopped): into the parameter set within its range, then the glue rebuilds the
 * configuration; CMD_ERR_RANGE (nothing changed) outside it. No parameter set: not writable. */
static uint16_t param_write(const link_target_t *t, uint16_t k, link_val_t v, bool *access_refused)
{
    const float x = (link_param(k)->type == (uint16_t)LINK_PARAM_U16) ? (float)v.u : v.f;
    if (t->params->set == NULL) {
        *access_refused = true;
        return (uint16_t)CMD_OK;
    }
    if (!link_param_set(t->params->set, k, x)) {
        return (uint16_t)CMD_ERR_RANGE;
    }
    if (t->params->apply != NULL) {
        t->params->apply(t->params->user, k);
    }
    return (uint16_t)CMD_OK;
}

uint16_t link_var_write(const link_target_t *t, uint16_t id, link_val_t v, bool *access_refused)
{
    const link_var_t *d = link_var(id);
    *access_refused = (id >= (uint16_t)LV_COUNT) || (d->access == (uint16_t)LINK_ACC_READ) ||
                      ((d->access == (uint16_t)LINK_ACC_WRITE_STOPPED) && !app_stopped(t->app));
    if (*access_refused) {
        return (uint16_t)CMD_OK;
    }
    if (id == (uint16_t)LV_HOST_TIMEOUT_S) {
        return link_setting_write(t, id, v.f);
    }
    if (id >= (uint16_t)LV_PARAM_FIRST) {
        return param_write(t, (uint16_t)(id - (uint16_t)LV_PARAM_FIRST), v, access_refused);
    }
    link_cmd_sync(t);
    cmd_field_set(t->cmd, id, v);
    cmd_apply(t->cmd, t->lim, t->app);
    const uint16_t err = t->cmd->error;
    if (err != (uint16_t)CMD_OK) {
        link_cmd_sync(t);                     /* the refused value out of the block: it would be refused again */
        cmd_apply(t->cmd, t->lim, t->app);
        t->cmd->error = err;             /* still named for the expressions window */
    }
    return err;
}

/* An action the drive's state makes do nothing: the refusal that says why, else CMD_OK. */
static uint16_t action_refusal(const app_t *a, uint16_t action)
{
    const bool start = (action == (uint16_t)LINK_ACTION_START);
    const bool commission = (action == (uint16_t)LINK_ACTION_COMMISSION);
    if ((start || commission) && (a->state == APP_STATE_FAULT)) {
        return (uint16_t)CMD_ERR_FAULTED;    /* the app drops a start asked for in FAULT */
    }
    if (commission && (a->state != APP_STATE_INIT) && (a->state != APP_STATE_IDLE)) {
        return (uint16_t)CMD_ERR_NOT_STOPPED;
    }
    if ((action == (uint16_t)LINK_ACTION_SAVE) && !app_stopped(a)) {
        return (uint16_t)CMD_ERR_NOT_STOPPED;    /* a flash erase holds the CPU: never while running */
    }
    return (uint16_t)CMD_OK;
}

uint16_t link_action(const link_target_t *t, uint16_t action)
{
    volatile cmd_t *c = t->cmd;
    if ((action == (uint16_t)LINK_ACTION_SAVE) && (t->params->store == NULL)) {
        return LINK_ACTION_UNKNOWN;              /* no store on this drive */
    }
    const uint16_t refused = action_refusal(t->app, action);
    if (refused != (uint16_t)CMD_OK) {
        c->error = refused;              /* named for the expressions window too */
        return refused;
    }
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
        c->run = 0u;                     /* no edge (a start left run at 1): the stopped command block */
        c->run_taken = 0u;
        app_request_commission(t->app);
        break;
    case LINK_ACTION_SAVE:
        link_nv_ask(t->params->store);   /* the command block untouched */
        return (uint16_t)CMD_OK;
    default:
        return LINK_ACTION_UNKNOWN;
    }
    link_cmd_sync(t);
    cmd_apply(c, t->lim, t->app);
    return c->error;
}

uint16_t link_level(const link_target_t *t, uint16_t level)
{
    if ((level < LEVEL_MIN) || (level > LEVEL_MAX)) {
        return (uint16_t)CMD_ERR_LEVEL;  /* 0 would mean "keep" to cmd_apply: not a level to ask for */
    }
    link_cmd_sync(t);
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
        const link_var_t *d = link_var(i);
        h = fnv_str(h, d->name);
        h = fnv_str(h, d->unit);
        h = fnv(h, d->type);
        h = fnv(h, d->access);
        h = fnv(h, d->capture);
        for (uint16_t k = 0u; k < FLOAT_BYTES * 2u; k++) {
            h = fnv(h, b[k]);
        }
    }
    return h;
}
