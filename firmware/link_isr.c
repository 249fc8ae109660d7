/* link_isr.c - the link's control-ISR part: the capture and the stream's
 * sampling (link.h, link_protocol.md "Capture", "Stream") and the
 * variables' values they read (link_var_get, link_vars.h). Compiled into
 * RAM with the ISR path; the rest of the link (link.c, link_vars.c,
 * link_codec.c) runs from flash. */
#include "link.h"

#include <stddef.h>

#include "mathx.h"

#define COUNT16_MAX 0xFFFFu
#define COUNT_OFFSET_ROUND 32768.5f /* 2^15 offset and the half that rounds */
#define OFFSET_COUNT_MIN 1.0f       /* -32767 in offset binary */
#define OFFSET_COUNT_MAX 65535.0f   /* +32767 in offset binary */
#define SIGN16 0x8000u
#define LOW16 0xFFFFul
#define HALF_BITS 16u

typedef union {
    float f;
    uint32_t u;
} f32_bits_t;

/* ---- the variables' values (link_vars.h): read by the ISR, so they live here, in RAM ---- */

static link_val_t of_u(uint32_t u)
{
    link_val_t v;
    v.u = u;
    v.f = (float)u;
    return v;
}

static link_val_t of_f(float f)
{
    link_val_t v;
    v.u = 0u;
    v.f = f;
    return v;
}

link_val_t link_var_get(const link_target_t *t, uint16_t id)
{
    const app_t *a = t->app;
    const ctrl_mon_t *m = &a->ctrl.mon;
    const est_out_t *e = est_output(ctrl_est(&a->ctrl)); /* the estimation's model and status */
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
    case LV_VDC_V: return of_f(a->vdc_V);
    /* the torque path that ran: proposed only while the estimation's model drove it */
    case LV_METHOD_RAN:
        return of_u(((ctrl_method(&a->ctrl) == CTRL_METHOD_PROPOSED) && (m->model_from_observer != 0u))
                        ? (uint32_t)CTRL_METHOD_PROPOSED : (uint32_t)CTRL_METHOD_CONVENTIONAL);
    case LV_HOLD_REASON: return of_u((uint32_t)e->hold);
    case LV_FAULT_PRESENT: return of_u((uint32_t)a->fault_present);
    case LV_HOST_TIMEOUT_S: return of_f(t->host->timeout_s);
    default: return of_u(0u);
    }
}

/* ---- capture and stream ---- */

/* the stream's in-place copy writes its LINK_STREAM_VARS slots out */
typedef char link_stream_eight_vars[(LINK_STREAM_VARS == 8u) ? 1 : -1];

/* A float's raw 32 bits. */
static inline uint32_t f32_bits(const volatile float *fp)
{
    f32_bits_t x;
    x.f = *fp;
    return x.u;
}

static void count16(uint16_t *c)
{
    if (*c < COUNT16_MAX) {
        (*c)++;
    }
}

/* x [counts] rounded (half up) and saturated to +-32767, as the int16's bits: offset binary
 * (x + 2^15 + 1/2) truncated when in [1, 65535), else the end on its side, then the sign bit
 * flipped. A NaN gives -32767. The range is tested after the offset (the same counts as
 * clamping x first, for every float): the common case is one add and two compares. */
static uint16_t to_count(float x)
{
    const float v = x + COUNT_OFFSET_ROUND;
    uint16_t u;
    if (v >= OFFSET_COUNT_MIN && v < OFFSET_COUNT_MAX) {
        u = (uint16_t)v;
    } else {
        u = (v >= OFFSET_COUNT_MAX) ? (uint16_t)OFFSET_COUNT_MAX : (uint16_t)OFFSET_COUNT_MIN;
    }
    return (uint16_t)(u ^ SIGN16);
}

/* A variable's value as a float: the one in place in the raw unit (the common case), else by id. */
static inline float raw_float(const link_target_t *t, const volatile float *fp, uint16_t id)
{
    return (fp != NULL) ? *fp : link_var_get(t, id).f;
}

/* Whether the trigger fires on this sample (trig_ready kept for the next). The trigger
 * variable is compared in its unit, as READ and the CSV give it. The app's state is read,
 * and kept for the next sample, by the state triggers only. */
static bool triggered(link_capture_t *c, const link_target_t *t, bool enough_pre)
{
    bool fire = false;
    switch (c->trig) {
    case LINK_TRIG_ABOVE: {
        const float v = raw_float(t, c->trig_src.p, c->trig_id) / c->trig_src.raw_per_unit;
        if (v > c->level) {
            fire = c->trig_ready && enough_pre;
            c->trig_ready = false;
        } else if (v <= c->level - c->hyst) {
            c->trig_ready = true;
        }
        break;
    }
    case LINK_TRIG_BELOW: {
        const float v = raw_float(t, c->trig_src.p, c->trig_id) / c->trig_src.raw_per_unit;
        if (v < c->level) {
            fire = c->trig_ready && enough_pre;
            c->trig_ready = false;
        } else if (v >= c->level + c->hyst) {
            c->trig_ready = true;
        }
        break;
    }
    case LINK_TRIG_FAULT: {
        const uint16_t st = (uint16_t)t->app->state;
        fire = enough_pre && st == (uint16_t)APP_STATE_FAULT && c->last_app_state != (uint16_t)APP_STATE_FAULT;
        c->last_app_state = st;
        break;
    }
    case LINK_TRIG_STATE: {
        const uint16_t st = (uint16_t)t->app->state;
        fire = enough_pre && st != c->last_app_state;
        c->last_app_state = st;
        break;
    }
    default:
        fire = enough_pre;
        break;
    }
    return fire;
}

static void capture_done_after(link_capture_t *c)
{
    c->first_index = c->trig_index - (uint32_t)c->pre * c->decimate;
    c->state = LINK_CAP_DONE;
}

/* One row of any channels: integers and codes by id, float32 channels in two slots. */
static void capture_row(const link_capture_t *c, const link_target_t *t, uint16_t *row)
{
    for (uint16_t k = 0u; k < c->nch; k++) {
        const float v = raw_float(t, c->fp[k], c->ids[k]) * c->per_raw[k];
        if (c->fmt[k] == (uint16_t)LINK_CAP_F32) {
            f32_bits_t x;                /* two slots, low half first */
            x.f = v;
            row[0] = (uint16_t)(x.u & LOW16);
            row[1] = (uint16_t)(x.u >> HALF_BITS);
            row += LINK_CAP_F32_SLOTS;
        } else {
            *row++ = to_count(v);
        }
    }
}

static void capture_isr(link_capture_t *c, const link_target_t *t)
{
    const uint16_t state = c->state;
    if (state != LINK_CAP_PRE && state != LINK_CAP_POST) {
        return;
    }
    if (c->dec_left > 0u) {
        c->dec_left--;
        return;
    }
    c->dec_left = (uint16_t)(c->decimate - 1u);
    uint16_t *row = &c->buf[c->head * c->stride];
    if (c->i16_in_place) {               /* the common case: int16 counts of floats in place */
        const volatile float *const *fp = c->fp;
        const float *per_raw = c->per_raw;
        const uint16_t *const end = row + c->nch;
        while (row != end) {                 /* walking pointers: no index to scale per channel */
            *row++ = to_count(**fp++ * *per_raw++);
        }
    } else {
        capture_row(c, t, row);
    }
    c->head = (uint16_t)(c->head + 1u);
    c->head = (c->head >= c->samples) ? 0u : c->head;
    c->filled = (c->filled < c->samples) ? (uint16_t)(c->filled + 1u) : c->filled;
    if (state == LINK_CAP_POST) {
        c->post_left--;
        if (c->post_left == 0u) {
            capture_done_after(c);
        }
        return;
    }
    if (triggered(c, t, c->filled > c->pre)) {
        c->trig_index = t->app->ticks - 1u;   /* ticks counts this period's call already */
        c->post_left = (uint16_t)(c->samples - c->pre - 1u);
        if (c->post_left == 0u) {
            capture_done_after(c);
        } else {
            c->state = LINK_CAP_POST;
        }
    }
}

static void stream_isr(link_t *l)
{
    link_stream_t *s = &l->stream;
    const uint16_t n = s->n;
    if (n == 0u) {
        return;
    }
    if (s->dec_left > 0u) {
        s->dec_left--;
        return;
    }
    s->dec_left = (uint16_t)(s->decimate - 1u);
    const uint16_t w = s->wr;
    const uint16_t next = (uint16_t)((w + 1u) & (LINK_STREAM_ROWS - 1u));
    if (next == s->rd) {
        count16(&l->stats.stream_dropped);
        return;
    }
    s->index[w] = l->t.app->ticks - 1u;
    uint32_t *raw = s->raw[w];
    if (s->in_place) {                   /* the common case: every slot's float bits, written out (no
                                          * loop's bookkeeping); slots from n on are never sent */
        raw[0] = f32_bits(s->fp[0]);
        raw[1] = f32_bits(s->fp[1]);
        raw[2] = f32_bits(s->fp[2]);
        raw[3] = f32_bits(s->fp[3]);
        raw[4] = f32_bits(s->fp[4]);
        raw[5] = f32_bits(s->fp[5]);
        raw[6] = f32_bits(s->fp[6]);
        raw[7] = f32_bits(s->fp[7]);
    } else {
        for (uint16_t k = 0u; k < n; k++) {
            const volatile float *fp = s->fp[k];
            f32_bits_t x;
            if (fp != NULL) {
                x.f = *fp;               /* its bits, converted by the background */
            } else {
                const link_val_t v = link_var_get(&l->t, s->ids[k]);
                if (((s->f32_mask >> k) & 1u) != 0u) {
                    x.f = v.f;
                } else {
                    x.u = v.u;
                }
            }
            raw[k] = x.u;
        }
    }
    s->wr = next;
}

void link_isr(link_t *l)
{
    capture_isr(&l->cap, &l->t);
    stream_isr(l);
}
