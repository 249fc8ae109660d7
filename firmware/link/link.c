/* link.c - dispatcher, reply cache, capture and stream of the link; see link.h and link_protocol.md. */
#include "link.h"

#include <stddef.h>

#include "board_cfg.h"
#include "mathx.h"

#define COUNT16_MAX 0xFFFFu
#define INT16_FULL_SCALE 32767.0f
#define NS_PER_S 1.0e9f
#define ROUND_HALF 0.5f
/* frame bytes on the line around a payload: type, seq, CRC (4), a COBS code and the delimiter (2),
 * and one more COBS code per 254 bytes (none for a stream row) */
#define FRAME_OVERHEAD 6u
#define STREAM_ROW_HEADER 4u     /* the row's period index */
#define EVENT_BYTES 6u           /* state, fault, period count */
#define VALUE_BYTES 4u
#define REPLY_ROOM LINK_ENCODED_MAX
#define CAP_READ_HEADER 5u       /* status, first row, rows */
#define STR_MAX 255u
#define VAR_DESC_FIXED 16u       /* LIST_VARS per variable: type, access, scale, min, max, two string lengths */
#define CAP_ARM_FIXED 18u        /* CAPTURE_ARM before the channel ids (link_protocol.md) */

static void count16(uint16_t *c)
{
    if (*c < COUNT16_MAX) {
        (*c)++;
    }
}

void link_cfg_default(link_cfg_t *cfg)
{
    cfg->Ts_s = 0.0f;
    cfg->baud = 0u;
    cfg->firmware_id = NULL;
    cfg->host_timeout_s = BOARD_HOST_TIMEOUT_S;
    cfg->params.set = NULL;
    cfg->params.apply = NULL;
    cfg->params.user = NULL;
    cfg->params.store = NULL;
}

void link_init(link_t *l, const link_cfg_t *cfg, app_t *app, volatile cmd_t *cmd, const cmd_limits_t *lim)
{
    l->cfg = *cfg;
    l->t.app = app;
    l->t.cmd = cmd;
    l->t.lim = lim;
    l->t.stats = &l->stats;
    l->t.host = &l->host;
    l->t.params = &l->cfg.params;
    l->host.timeout_s = cfg->host_timeout_s;
    l->host.phase = LINK_HOST_IDLE;
    l->host.seen_ticks = app->ticks;
    l->host.step_ticks = 0u;
    l->stats.writes = 0u;
    l->stats.err_crc = 0u;
    l->stats.err_framing = 0u;
    l->stats.err_overrun = 0u;
    l->stats.stream_dropped = 0u;
    l->stats.err_line = 0u;
    l->stats.reset_by_watchdog = 0u;
    link_rx_init(&l->rx);
    l->rx_head = 0u;
    l->rx_tail = 0u;
    l->tx_head = 0u;
    l->tx_tail = 0u;
    l->cache_valid = false;
    l->cache_len = 0u;
    l->ev_state = (uint16_t)app->state;
    l->ev_fault = (uint16_t)app->fault;
    l->quit = false;
    l->written = 0u;
    l->cap.state = LINK_CAP_IDLE;
    l->cap.nch = 0u;
    l->stream.n = 0u;
    l->stream.wr = 0u;
    l->stream.rd = 0u;
}

bool link_rx_put(link_t *l, uint16_t byte)
{
    const uint16_t next = (uint16_t)((l->rx_head + 1u) & (LINK_RX_LEN - 1u));
    if (next == l->rx_tail) {
        count16(&l->stats.err_overrun);
        return false;
    }
    l->rx_ring[l->rx_head] = (uint16_t)(byte & LINK_BYTE_MASK);
    l->rx_head = next;
    return true;
}

uint16_t link_tx_pending(const link_t *l)
{
    return (uint16_t)((l->tx_head - l->tx_tail) & (LINK_TX_LEN - 1u));
}

static uint16_t tx_room(const link_t *l)
{
    return (uint16_t)(LINK_TX_LEN - 1u - link_tx_pending(l));
}

bool link_tx_get(link_t *l, uint16_t *byte)
{
    if (l->tx_tail == l->tx_head) {
        return false;
    }
    *byte = l->tx_ring[l->tx_tail];
    l->tx_tail = (uint16_t)((l->tx_tail + 1u) & (LINK_TX_LEN - 1u));
    return true;
}

void link_drop(link_t *l)
{
    l->rx_tail = l->rx_head;
    l->tx_tail = l->tx_head;
    link_rx_resync(&l->rx);
}

/* Bytes into the transmit queue (the caller checked the room). */
static void tx_put(link_t *l, const uint16_t *b, uint16_t n)
{
    for (uint16_t i = 0u; i < n; i++) {
        l->tx_ring[l->tx_head] = b[i];
        l->tx_head = (uint16_t)((l->tx_head + 1u) & (LINK_TX_LEN - 1u));
    }
}

/* A frame straight into the transmit queue (the caller checked the room). */
static void tx_frame(link_t *l, const link_frame_t *f)
{
    const uint16_t n = link_frame_encode_ring(f, l->tx_ring, l->tx_head, (uint16_t)(LINK_TX_LEN - 1u));
    l->tx_head = (uint16_t)((l->tx_head + n) & (LINK_TX_LEN - 1u));
}

/* ---- requests ---------------------------------------------------------------- */

static uint16_t str_len(const char *s)
{
    uint16_t n = 0u;
    while (n < STR_MAX && s[n] != '\0') {
        n++;
    }
    return n;
}

/* A string as its length byte and its characters, one per word. */
static uint16_t put_str(uint16_t *b, uint16_t i, const char *s)
{
    const uint16_t n = str_len(s);
    b[i++] = n;
    for (uint16_t k = 0u; k < n; k++) {
        b[i++] = (uint16_t)((uint16_t)s[k] & LINK_BYTE_MASK);
    }
    return i;
}

static uint16_t do_hello(link_t *l, uint16_t *p)
{
    uint16_t i = 1u;
    p[i++] = LINK_PROTOCOL_VERSION;
    i = link_put_u16(p, i, (uint16_t)LV_COUNT);
    i = link_put_u32(p, i, link_vars_hash(&l->t));
    i = link_put_u32(p, i, (uint32_t)(l->cfg.Ts_s * NS_PER_S + ROUND_HALF));
    i = link_put_u32(p, i, l->cfg.baud);
    i = link_put_u16(p, i, LINK_CAP_ROWS);
    p[i++] = LINK_CAP_CHANNELS;
    p[i++] = LINK_STREAM_VARS;
    return put_str(p, i, l->cfg.firmware_id);
}

/* A variable's capture scale [counts per unit]: its limits' larger magnitude is full scale
 * (32767 counts); an integer is captured as it is. */
static float counts_per_unit(const link_t *l, uint16_t id)
{
    float lo;
    float hi;
    link_var_limits(&l->t, id, &lo, &hi);
    const float amax = (mathx_fabsf(lo) > mathx_fabsf(hi)) ? mathx_fabsf(lo) : mathx_fabsf(hi);
    return ((link_var(id)->type == (uint16_t)LINK_T_F32) && amax > 0.0f) ? INT16_FULL_SCALE / amax : 1.0f;
}

/* LIST_VARS first_id: as many descriptors from first_id as fit. */
static uint16_t do_list(link_t *l, const link_frame_t *q, uint16_t *p)
{
    if (q->len != 2u) {
        p[0] = LINK_ST_BAD_REQUEST;
        return 1u;
    }
    uint16_t id = link_get_u16(q->payload, 0u);
    uint16_t i = link_put_u16(p, 1u, id);
    const uint16_t count_at = i++;
    uint16_t count = 0u;
    while (id < (uint16_t)LV_COUNT) {
        const link_var_t *d = link_var(id);
        /* the descriptor, and its capture format byte after all of them */
        const uint16_t need = (uint16_t)(VAR_DESC_FIXED + str_len(d->name) + str_len(d->unit) + 1u);
        if ((uint16_t)(i + need + count) > LINK_PAYLOAD_MAX) {
            break;
        }
        float lo;
        float hi;
        link_var_limits(&l->t, id, &lo, &hi);
        p[i++] = d->type;
        p[i++] = d->access;
        i = link_put_f32(p, i, 1.0f / counts_per_unit(l, id));
        i = link_put_f32(p, i, lo);
        i = link_put_f32(p, i, hi);
        i = put_str(p, i, d->name);
        i = put_str(p, i, d->unit);
        id++;
        count++;
    }
    p[count_at] = count;
    for (uint16_t k = 0u; k < count; k++) {   /* after version 1's fields: a host may stop before them */
        const uint16_t vid = (uint16_t)(id - count + k);
        p[i++] = (uint16_t)(link_var(vid)->capture | ((vid >= (uint16_t)LV_PARAM_FIRST) ? LINK_LIST_PARAM : 0u));
    }
    return i;
}

static uint16_t value_size(uint16_t id)
{
    return (link_var(id)->type == (uint16_t)LINK_T_U16) ? 2u : 4u;
}

static uint16_t put_value(uint16_t *p, uint16_t i, uint16_t id, link_val_t v)
{
    switch (link_var(id)->type) {
    case LINK_T_U16: return link_put_u16(p, i, (uint16_t)v.u);
    case LINK_T_U32: return link_put_u32(p, i, v.u);
    default: return link_put_f32(p, i, v.f);
    }
}

/* A streamed raw value (a float's bits, in the raw unit of its source, or an integer) in its
 * variable's type and unit, as READ gives it. */
static uint16_t put_raw(uint16_t *p, uint16_t i, const link_target_t *t, uint16_t id, uint32_t raw)
{
    link_val_t v;
    v.u = raw;
    v.f = (float)raw;
    if (link_var(id)->type == (uint16_t)LINK_T_F32) {
        v.u = 0u;
        v.f = link_f32_of_bits(raw) / link_var_source(t, id).raw_per_unit;
    }
    return put_value(p, i, id, v);
}

/* READ id...: each value in its type's size. */
static uint16_t do_read(link_t *l, const link_frame_t *q, uint16_t *p)
{
    if (q->len == 0u || (q->len & 1u) != 0u) {
        p[0] = LINK_ST_BAD_REQUEST;
        return 1u;
    }
    uint16_t i = 1u;
    for (uint16_t k = 0u; k < q->len; k = (uint16_t)(k + 2u)) {
        const uint16_t id = link_get_u16(q->payload, k);
        if (id >= (uint16_t)LV_COUNT) {
            p[0] = LINK_ST_UNKNOWN_ID;
            return link_put_u16(p, 1u, id);
        }
        if ((uint16_t)(i + value_size(id)) > LINK_PAYLOAD_MAX) {
            p[0] = LINK_ST_BAD_REQUEST;
            return 1u;
        }
        i = put_value(p, i, id, link_var_get(&l->t, id));
    }
    return i;
}

/* The references a host commands the drive with (the host timeout's). */
static bool is_reference(uint16_t id)
{
    return (id == (uint16_t)LV_SPEED_REF_RPM) || (id == (uint16_t)LV_TE_CMD_NM) || (id == (uint16_t)LV_UD_REF_V) ||
           (id == (uint16_t)LV_UQ_REF_V);
}

/* WRITE id value(4 bytes: u32 for integers, f32 bits for floats): status, cmd_error. */
static uint16_t do_write(link_t *l, const link_frame_t *q, uint16_t *p)
{
    if (q->len != 6u) {
        p[0] = LINK_ST_BAD_REQUEST;
        return 1u;
    }
    const uint16_t id = link_get_u16(q->payload, 0u);
    if (id >= (uint16_t)LV_COUNT) {
        p[0] = LINK_ST_UNKNOWN_ID;
        return link_put_u16(p, 1u, id);
    }
    link_val_t v;
    v.u = link_get_u32(q->payload, 2u);
    v.f = link_get_f32(q->payload, 2u);
    bool refused_access = false;
    const uint16_t err = link_var_write(&l->t, id, v, &refused_access);
    if (!refused_access) {
        l->stats.writes++;
        l->written |= (id < LINK_WRITTEN_BITS) ? ((uint32_t)1u << id) : 0u;
    }
    if (!refused_access && (err == (uint16_t)CMD_OK) && is_reference(id)) {
        l->host.phase = LINK_HOST_ARMED;  /* the host commands the drive: its silence counts from now */
    }
    p[0] = refused_access ? LINK_ST_ACCESS : ((err != (uint16_t)CMD_OK) ? LINK_ST_REFUSED : LINK_ST_OK);
    return link_put_u16(p, 1u, err);
}

/* ACTION LEVEL n: status (REFUSED for a level outside 1..5), cmd_error. */
static uint16_t do_level(link_t *l, const link_frame_t *q, uint16_t *p)
{
    if (q->len != 2u) {
        p[0] = LINK_ST_BAD_REQUEST;
        return 1u;
    }
    const uint16_t err = link_level(&l->t, q->payload[1]);
    if (err == (uint16_t)CMD_ERR_LEVEL) {
        p[0] = LINK_ST_REFUSED;
    } else {
        l->stats.writes++;
    }
    return link_put_u16(p, 1u, err);
}

static uint16_t do_action(link_t *l, const link_frame_t *q, uint16_t *p)
{
    if (q->len >= 1u && q->payload[0] == (uint16_t)LINK_ACTION_LEVEL) {
        return do_level(l, q, p);
    }
    if (q->len != 1u) {
        p[0] = LINK_ST_BAD_REQUEST;
        return 1u;
    }
    const uint16_t err = link_action(&l->t, q->payload[0]);
    if (err == LINK_ACTION_UNKNOWN) {
        p[0] = LINK_ST_BAD_REQUEST;
        return 1u;
    }
    if ((err == (uint16_t)CMD_ERR_FAULTED) || (err == (uint16_t)CMD_ERR_NOT_STOPPED)) {
        p[0] = LINK_ST_REFUSED;          /* nothing done: the state says why */
        return link_put_u16(p, 1u, err);
    }
    l->stats.writes++;
    if (q->payload[0] == (uint16_t)LINK_ACTION_QUIT) {
        l->quit = true;
    }
    if (q->payload[0] == (uint16_t)LINK_ACTION_START) {
        l->host.phase = LINK_HOST_ARMED;
    } else if ((q->payload[0] == (uint16_t)LINK_ACTION_STOP) || (q->payload[0] == (uint16_t)LINK_ACTION_QUIT)) {
        l->host.phase = LINK_HOST_IDLE;  /* stopped by the host itself: nothing to watch */
    }
    return link_put_u16(p, 1u, err);
}

uint32_t link_stream_need_Bps(const link_t *l, uint16_t n, uint16_t decimate)
{
    const float frame = (float)(FRAME_OVERHEAD + STREAM_ROW_HEADER + VALUE_BYTES * (uint32_t)n);
    const float rows_per_s = 1.0f / (l->cfg.Ts_s * (float)((decimate > 0u) ? decimate : 1u));
    return (uint32_t)(frame * rows_per_s + ROUND_HALF);
}

uint32_t link_stream_budget_Bps(const link_t *l)
{
    return l->cfg.baud / LINK_BITS_PER_BYTE_ON_LINE * LINK_LINE_BUDGET_PCT / 100u;
}

/* STREAM_SET decimate id...: status, need, budget [B/s]. Refused above the budget. */
static uint16_t do_stream_set(link_t *l, const link_frame_t *q, uint16_t *p)
{
    if (q->len < 2u || (q->len & 1u) != 0u || q->len > (uint16_t)(2u + 2u * LINK_STREAM_VARS)) {
        p[0] = LINK_ST_BAD_REQUEST;
        return 1u;
    }
    const uint16_t dec = link_get_u16(q->payload, 0u);
    const uint16_t n = (uint16_t)((q->len - 2u) / 2u);
    for (uint16_t k = 0u; k < n; k++) {
        const uint16_t id = link_get_u16(q->payload, (uint16_t)(2u + 2u * k));
        if (id >= (uint16_t)LV_COUNT) {
            p[0] = LINK_ST_UNKNOWN_ID;
            return link_put_u16(p, 1u, id);
        }
    }
    if (dec == 0u) {
        p[0] = LINK_ST_BAD_REQUEST;
        return 1u;
    }
    const uint32_t need = (n > 0u) ? link_stream_need_Bps(l, n, dec) : 0u;
    const uint32_t budget = link_stream_budget_Bps(l);
    uint16_t i = link_put_u32(p, 1u, need);
    i = link_put_u32(p, i, budget);
    if (need > budget) {
        p[0] = LINK_ST_REFUSED;
        return i;
    }
    link_stream_t *s = &l->stream;
    s->n = 0u;                           /* the ISR stops sampling before the set changes */
    s->f32_mask = 0u;
    s->in_place = (n > 0u);
    for (uint16_t k = 0u; k < n; k++) {
        s->ids[k] = link_get_u16(q->payload, (uint16_t)(2u + 2u * k));
        s->fp[k] = link_var_source(&l->t, s->ids[k]).p;
        s->f32_mask |= (link_var(s->ids[k])->type == (uint16_t)LINK_T_F32) ? (uint16_t)(1u << k) : 0u;
        s->in_place = s->in_place && (s->fp[k] != NULL);
    }
    for (uint16_t k = n; k < LINK_STREAM_VARS; k++) {
        s->fp[k] = (n > 0u) ? s->fp[0] : NULL;  /* read by the in-place copy, never sent */
    }
    s->decimate = dec;
    s->dec_left = 0u;
    s->rd = s->wr;
    s->n = n;
    return i;
}

/* CAPTURE_ARM's fields before the channel ids (link_protocol.md). */
typedef struct {
    uint16_t dec, pre, samples, trig, trig_id, nch;
    float level, hyst;
} cap_arm_t;

/* CAPTURE_ARM's fields of q into *r; false when the frame's length or a
 * field is out of range (BAD_REQUEST). */
static bool cap_arm_read(const link_frame_t *q, cap_arm_t *r)
{
    if (q->len < CAP_ARM_FIXED) {
        return false;
    }
    r->dec = link_get_u16(q->payload, 0u);
    r->pre = link_get_u16(q->payload, 2u);
    r->samples = link_get_u16(q->payload, 4u);
    r->trig = q->payload[6];
    r->trig_id = link_get_u16(q->payload, 7u);
    r->level = link_get_f32(q->payload, 9u);
    r->hyst = link_get_f32(q->payload, 13u);
    r->nch = q->payload[17];
    return !(r->nch == 0u || r->nch > LINK_CAP_CHANNELS || q->len != (uint16_t)(CAP_ARM_FIXED + 2u * r->nch) ||
             r->dec == 0u || r->samples == 0u || r->samples > LINK_CAP_ROWS || r->pre >= r->samples ||
             r->trig > (uint16_t)LINK_TRIG_STATE || !mathx_isfinitef(r->level) || !mathx_isfinitef(r->hyst) ||
             r->hyst < 0.0f);
}

/* Channel k's variable id in CAPTURE_ARM q. */
static uint16_t cap_arm_id(const link_frame_t *q, uint16_t k)
{
    return link_get_u16(q->payload, (uint16_t)(CAP_ARM_FIXED + 2u * k));
}

/* True when the trigger's id and every channel's name a variable; else
 * false with the first that does not (the trigger's first) in *unknown. */
static bool cap_arm_ids_known(const link_frame_t *q, const cap_arm_t *r, uint16_t *unknown)
{
    if (r->trig_id >= (uint16_t)LV_COUNT) {
        *unknown = r->trig_id;
        return false;
    }
    for (uint16_t k = 0u; k < r->nch; k++) {
        const uint16_t id = cap_arm_id(q, k);
        if (id >= (uint16_t)LV_COUNT) {
            *unknown = id;
            return false;
        }
    }
    return true;
}

/* A row's slots for q's nch channels: one a channel, a float32 one more. */
static uint16_t cap_arm_stride(const link_frame_t *q, uint16_t nch)
{
    uint16_t stride = nch;
    for (uint16_t k = 0u; k < nch; k++) {
        const uint16_t id = cap_arm_id(q, k);
        stride = (uint16_t)(stride + ((link_var(id)->capture == (uint16_t)LINK_CAP_F32) ? LINK_CAP_F32_SLOTS - 1u : 0u));
    }
    return stride;
}

/* The capture's channels from q (the capture IDLE): ids, sources, formats
 * and scales, and whether every one is an int16 copied in place. */
static void cap_arm_channels(link_t *l, const link_frame_t *q)
{
    link_capture_t *c = &l->cap;
    for (uint16_t k = 0u; k < c->nch; k++) {
        const uint16_t id = cap_arm_id(q, k);
        const bool f32 = link_var(id)->capture == (uint16_t)LINK_CAP_F32;
        c->ids[k] = id;
        const link_src_t src = link_var_source(&l->t, id);
        c->fp[k] = src.p;
        c->fmt[k] = f32 ? (uint16_t)LINK_CAP_F32 : (uint16_t)LINK_CAP_I16;
        c->per_lsb[k] = f32 ? 1.0f : counts_per_unit(l, id);
        c->per_raw[k] = c->per_lsb[k] / src.raw_per_unit;
    }
    c->i16_in_place = true;
    for (uint16_t k = 0u; k < c->nch; k++) {
        c->i16_in_place = c->i16_in_place && (c->fp[k] != NULL) && (c->fmt[k] == (uint16_t)LINK_CAP_I16);
    }
}

/* The capture's trigger, depth and decimation from r, its counters from
 * the start (the capture IDLE). */
static void cap_arm_run(link_t *l, const cap_arm_t *r)
{
    link_capture_t *c = &l->cap;
    c->trig_src = link_var_source(&l->t, r->trig_id);
    c->samples = r->samples;
    c->pre = r->pre;
    c->decimate = r->dec;
    c->trig = r->trig;
    c->trig_id = r->trig_id;
    c->level = r->level;
    c->hyst = r->hyst;
    c->dec_left = 0u;
    c->head = 0u;
    c->filled = 0u;
    c->post_left = 0u;
    c->trig_ready = false;
    c->last_app_state = (uint16_t)l->t.app->state;
    c->trig_index = 0u;
    c->first_index = 0u;
}

/* CAPTURE_ARM decimate pre samples trig trig_id level hyst nch id...: status. */
static uint16_t do_capture_arm(link_t *l, const link_frame_t *q, uint16_t *p)
{
    link_capture_t *c = &l->cap;
    cap_arm_t r;
    uint16_t unknown;
    p[0] = LINK_ST_BAD_REQUEST;
    if (!cap_arm_read(q, &r)) {
        return 1u;
    }
    if (!cap_arm_ids_known(q, &r, &unknown)) {
        p[0] = LINK_ST_UNKNOWN_ID;
        return link_put_u16(p, 1u, unknown);
    }
    const uint16_t stride = cap_arm_stride(q, r.nch);
    const uint16_t rows_fit = (uint16_t)(LINK_CAP_SLOTS / ((stride > 0u) ? stride : 1u));
    if (r.samples > rows_fit) {
        return link_put_u16(p, 1u, rows_fit);   /* BAD_REQUEST naming the rows that fit */
    }
    c->state = LINK_CAP_IDLE;            /* the ISR leaves it alone from here */
    c->nch = r.nch;
    c->stride = stride;
    cap_arm_channels(l, q);
    cap_arm_run(l, &r);
    c->state = LINK_CAP_PRE;             /* last: the ISR starts sampling */
    p[0] = LINK_ST_OK;
    return 1u;
}

/* CAPTURE_STATUS: status, state, samples, pre, decimate, trigger and first row's period index,
 * channels, then per channel id and unit per count. */
static uint16_t do_capture_status(link_t *l, uint16_t *p)
{
    const link_capture_t *c = &l->cap;
    uint16_t i = 1u;
    p[i++] = c->state;
    i = link_put_u16(p, i, c->samples);
    i = link_put_u16(p, i, c->pre);
    i = link_put_u16(p, i, c->decimate);
    i = link_put_u32(p, i, c->trig_index);
    i = link_put_u32(p, i, c->first_index);
    p[i++] = c->nch;
    for (uint16_t k = 0u; k < c->nch; k++) {
        i = link_put_u16(p, i, c->ids[k]);
        i = link_put_f32(p, i, 1.0f / c->per_lsb[k]);
    }
    for (uint16_t k = 0u; k < c->nch; k++) {
        p[i++] = c->fmt[k];              /* after the fields of version 1: older hosts ignore it */
    }
    return i;
}

/* CAPTURE_READ first rows: status, first, rows, then rows x channels int16, oldest row first. */
static uint16_t do_capture_read(link_t *l, const link_frame_t *q, uint16_t *p)
{
    const link_capture_t *c = &l->cap;
    if (q->len != 4u) {
        p[0] = LINK_ST_BAD_REQUEST;
        return 1u;
    }
    if (c->state != LINK_CAP_DONE) {
        p[0] = LINK_ST_BUSY;
        return 1u;
    }
    const uint16_t first = link_get_u16(q->payload, 0u);
    uint16_t rows = link_get_u16(q->payload, 2u);
    const uint16_t fit = (uint16_t)((LINK_PAYLOAD_MAX - CAP_READ_HEADER) / (2u * c->stride));
    if (first >= c->samples) {
        p[0] = LINK_ST_BAD_REQUEST;
        return 1u;
    }
    rows = (rows < fit) ? rows : fit;
    rows = (rows < (uint16_t)(c->samples - first)) ? rows : (uint16_t)(c->samples - first);
    uint16_t i = link_put_u16(p, 1u, first);
    i = link_put_u16(p, i, rows);
    for (uint16_t r = 0u; r < rows; r++) {
        uint16_t at = (uint16_t)(c->head + first + r);    /* head: the oldest row once the ring is full */
        at = (at >= c->samples) ? (uint16_t)(at - c->samples) : at;
        const uint16_t *row = &c->buf[at * c->stride];
        for (uint16_t k = 0u; k < c->stride; k++) {
            i = link_put_u16(p, i, row[k]);   /* a float32: its low half, then its high half */
        }
    }
    return i;
}

static uint16_t do_ping(link_t *l, uint16_t *p)
{
    uint16_t i = link_put_u16(p, 1u, l->stats.err_crc);
    i = link_put_u16(p, i, l->stats.err_framing);
    i = link_put_u16(p, i, l->stats.err_overrun);
    return link_put_u32(p, i, l->t.app->ticks);
}

/* The reply to l->req into l->rep. */
static void dispatch(link_t *l)
{
    const link_frame_t *q = &l->req;
    uint16_t *p = l->rep.payload;
    uint16_t n;
    p[0] = LINK_ST_OK;
    switch (q->type) {
    case LINK_HELLO: n = do_hello(l, p); break;
    case LINK_LIST_VARS: n = do_list(l, q, p); break;
    case LINK_READ: n = do_read(l, q, p); break;
    case LINK_WRITE: n = do_write(l, q, p); break;
    case LINK_ACTION: n = do_action(l, q, p); break;
    case LINK_STREAM_SET: n = do_stream_set(l, q, p); break;
    case LINK_CAPTURE_ARM: n = do_capture_arm(l, q, p); break;
    case LINK_CAPTURE_STATUS: n = do_capture_status(l, p); break;
    case LINK_CAPTURE_READ: n = do_capture_read(l, q, p); break;
    case LINK_PING: n = do_ping(l, p); break;
    default:
        p[0] = LINK_ST_UNKNOWN_TYPE;
        n = 1u;
        break;
    }
    l->rep.type = (uint16_t)(q->type | LINK_REPLY);
    l->rep.seq = q->seq;
    l->rep.len = n;
}

/* A request: answered from the cache when it repeats the last one, else executed and cached. */
static void on_request(link_t *l)
{
    const link_frame_t *q = &l->req;
    const uint16_t crc = link_crc16(q->payload, q->len);
    if ((q->type & LINK_REPLY) != 0u || q->type == (uint16_t)LINK_EVENT || q->type == (uint16_t)LINK_STREAM) {
        count16(&l->rx.err_framing);     /* not a request: the host's own frames echoed, or noise */
        return;
    }
    l->host.seen_ticks = l->t.app->ticks; /* a valid frame: the host is there */
    if (l->cache_valid && q->type == l->cache_type && q->seq == l->cache_seq && crc == l->cache_crc) {
        tx_put(l, l->cache, l->cache_len);
        return;
    }
    dispatch(l);
    l->cache_len = link_frame_encode(&l->rep, l->cache);
    l->cache_type = q->type;
    l->cache_seq = q->seq;
    l->cache_crc = crc;
    l->cache_valid = true;
    tx_put(l, l->cache, l->cache_len);
}

/* Unsolicited frames: one stream row, or a state or fault change. */
static void send_unsolicited(link_t *l)
{
    link_frame_t *f = &l->rep;
    const uint16_t st = (uint16_t)l->t.app->state;
    const uint16_t ft = (uint16_t)l->t.app->fault;
    if ((st != l->ev_state || ft != l->ev_fault) && tx_room(l) >= LINK_ENCODED_SIZE(EVENT_BYTES)) {
        f->type = LINK_EVENT;
        f->seq = 0u;
        f->payload[0] = st;
        f->payload[1] = ft;
        f->len = link_put_u32(f->payload, 2u, l->t.app->ticks);
        tx_frame(l, f);
        l->ev_state = st;
        l->ev_fault = ft;
    }
    link_stream_t *s = &l->stream;
    while (s->rd != s->wr && tx_room(l) >= LINK_ENCODED_SIZE(STREAM_ROW_HEADER + VALUE_BYTES * (uint16_t)s->n)) {
        const uint16_t r = s->rd;
        const uint16_t n = s->n;
        f->type = LINK_STREAM;
        f->seq = 0u;
        uint16_t i = link_put_u32(f->payload, 0u, s->index[r]);
        for (uint16_t k = 0u; k < n; k++) {
            i = put_raw(f->payload, i, &l->t, s->ids[k], s->raw[r][k]);
        }
        f->len = i;
        tx_frame(l, f);
        s->rd = (uint16_t)((r + 1u) & (LINK_STREAM_ROWS - 1u));
    }
}

/* ---- the host timeout ------------------------------------------------------ */

/* The app runs something a stop ends (not INIT, IDLE or FAULT). */
static bool running(const app_t *a)
{
    return (a->state != APP_STATE_INIT) && (a->state != APP_STATE_IDLE) && (a->state != APP_STATE_FAULT);
}

/* x moved toward 0 by step (>= 0), not past it. */
static float toward_zero(float x, float step)
{
    const float m = mathx_fabsf(x) - step;
    if (!(m > 0.0f)) {
        return 0.0f;
    }
    return (x > 0.0f) ? m : -m;
}

/* The ramp's step over dt_s from the references in force, into the command block through
 * cmd_apply(): the speed at the drive's ramp rate, torque and voltages from their limits in the
 * time the rated speed takes at it. True when all are zero. */
static bool host_ramp_step(link_t *l, float dt_s)
{
    const app_t *a = l->t.app;
    volatile cmd_t *c = l->t.cmd;
    const float decel = a->cfg.rsid.accel_rad_s2;
    const float stop_s = a->cfg.comm.speed_max_rad_s / decel;   /* the rated speed to zero */
    const float w = toward_zero(a->op_req.ref.speed_ref_rad_s, decel * dt_s);  /* the request in force */
    const float te = toward_zero(a->op_req.ref.te_ref_Nm, l->t.lim->te_max_Nm * dt_s / stop_s);
    const float ud = toward_zero(a->op_req.ref.ud_ref_V, l->t.lim->u_max_V * dt_s / stop_s);
    const float uq = toward_zero(a->op_req.ref.uq_ref_V, l->t.lim->u_max_V * dt_s / stop_s);
    link_cmd_sync(&l->t);
    c->speed_ref_rpm = w / MATHX_RAD_S_PER_RPM_F;
    c->te_ref_Nm = te;
    c->ud_ref_V = ud;
    c->uq_ref_V = uq;
    cmd_apply(c, l->t.lim, l->t.app);
    /* the SIL's profile must not take them back (link_sil.c on_refs) */
    l->written |= ((uint32_t)1u << LV_SPEED_REF_RPM) | ((uint32_t)1u << LV_TE_CMD_NM) |
                  ((uint32_t)1u << LV_UD_REF_V) | ((uint32_t)1u << LV_UQ_REF_V);
    return (w == 0.0f) && (te == 0.0f) && (ud == 0.0f) && (uq == 0.0f);
}

/* The host timeout (link_poll): armed and quiet too long, a running drive ramps to zero and stops
 * at standstill (speed mode; at once in another mode once its references are zero; a drive in a
 * start-up step stops at once); the warning raised. */
static void host_watch(link_t *l)
{
    link_host_t *h = &l->host;
    app_t *a = l->t.app;
    const uint32_t now = a->ticks;
    const float Ts = l->cfg.Ts_s;
    if (h->phase == LINK_HOST_IDLE) {
        return;
    }
    if (h->phase == LINK_HOST_ARMED) {
        if (!(h->timeout_s > 0.0f) || !((float)(now - h->seen_ticks) * Ts > h->timeout_s)) {
            return;
        }
        h->phase = LINK_HOST_IDLE;
        if (!running(a)) {
            return;                      /* stopped already: nothing to do */
        }
        app_request_warning(a, APP_WARN_HOST_TIMEOUT);
        if (a->state != APP_STATE_RUN) {
            (void)link_action(&l->t, LINK_ACTION_STOP);
            return;
        }
        h->phase = LINK_HOST_RAMPING;
        h->step_ticks = now;
        return;
    }
    if (!running(a)) {
        h->phase = LINK_HOST_IDLE;       /* stopped or faulted meanwhile */
        return;
    }
    if (h->phase == LINK_HOST_RAMPING) {
        const bool zero = host_ramp_step(l, (float)(now - h->step_ticks) * Ts);
        h->step_ticks = now;             /* at zero: from now on, when it got there */
        if (!zero) {
            return;
        }
        h->phase = LINK_HOST_AT_ZERO;
    }
    const float stop_s = a->cfg.comm.speed_max_rad_s / a->cfg.rsid.accel_rad_s2;
    const bool still = mathx_fabsf(ctrl_speed_m_rad_s(&a->ctrl)) <=
                       LINK_STOP_STANDSTILL_PER_RATED * a->cfg.comm.speed_max_rad_s;
    if ((a->op_taken.mode != CTRL_MODE_SPEED) || still || ((float)(now - h->step_ticks) * Ts > stop_s)) {
        (void)link_action(&l->t, LINK_ACTION_STOP);
        h->phase = LINK_HOST_IDLE;
    }
}

void link_poll(link_t *l)
{
    for (uint16_t k = 0u; k < LINK_RX_BUDGET; k++) {
        if (l->rx_tail == l->rx_head || tx_room(l) < REPLY_ROOM) {
            break;                       /* nothing more, or no room for a reply: the rest waits */
        }
        const uint16_t b = l->rx_ring[l->rx_tail];
        l->rx_tail = (uint16_t)((l->rx_tail + 1u) & (LINK_RX_LEN - 1u));
        if (link_rx_byte(&l->rx, b, &l->req)) {
            on_request(l);
        }
    }
    l->stats.err_crc = l->rx.err_crc;
    l->stats.err_framing = l->rx.err_framing;
    if (l->rx_tail == l->rx_head) {
        send_unsolicited(l);             /* received bytes waiting for room come first: the queue drains */
    }
    host_watch(l);
}
