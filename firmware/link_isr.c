/* link_isr.c - the link's control-ISR part: the capture and the stream's
 * sampling (link.h, link_protocol.md "Capture", "Stream"). Compiled into
 * RAM with the ISR path; the rest of the link (link.c) runs from flash. */
#include "link.h"

#include "mathx.h"

#define COUNT16_MAX 0xFFFFu
#define INT16_FULL_SCALE 32767.0f
#define ROUND_HALF 0.5f

static void count16(uint16_t *c)
{
    if (*c < COUNT16_MAX) {
        (*c)++;
    }
}

static int16_t to_count(float v, float per_lsb)
{
    const float x = v * per_lsb;
    if (!mathx_isfinitef(x)) {
        return 0;
    }
    const float r = (x >= 0.0f) ? x + ROUND_HALF : x - ROUND_HALF;
    return (int16_t)mathx_clampf(r, -INT16_FULL_SCALE, INT16_FULL_SCALE);
}

/* Whether the trigger fires on this sample (trig_ready kept for the next). */
static bool triggered(link_capture_t *c, const link_target_t *t, bool enough_pre)
{
    const uint16_t st = (uint16_t)t->app->state;
    bool fire = false;
    switch (c->trig) {
    case LINK_TRIG_ABOVE: {
        const float v = link_var_get(t, c->trig_id).f;
        if (v > c->level) {
            fire = c->trig_ready && enough_pre;
            c->trig_ready = false;
        } else if (v <= c->level - c->hyst) {
            c->trig_ready = true;
        }
        break;
    }
    case LINK_TRIG_BELOW: {
        const float v = link_var_get(t, c->trig_id).f;
        if (v < c->level) {
            fire = c->trig_ready && enough_pre;
            c->trig_ready = false;
        } else if (v >= c->level + c->hyst) {
            c->trig_ready = true;
        }
        break;
    }
    case LINK_TRIG_FAULT:
        fire = enough_pre && st == (uint16_t)APP_STATE_FAULT && c->last_app_state != (uint16_t)APP_STATE_FAULT;
        break;
    case LINK_TRIG_STATE:
        fire = enough_pre && st != c->last_app_state;
        break;
    default:
        fire = enough_pre;
        break;
    }
    c->last_app_state = st;
    return fire;
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
    const uint32_t index = t->app->ticks - 1u;   /* ticks counts this period's call already */
    int16_t *row = &c->buf[c->head * LINK_CAP_CHANNELS];
    for (uint16_t k = 0u; k < c->nch; k++) {
        row[k] = to_count(link_var_get(t, c->ids[k]).f, c->per_lsb[k]);
    }
    c->head = (uint16_t)(c->head + 1u);
    c->head = (c->head >= c->samples) ? 0u : c->head;
    c->filled = (c->filled < c->samples) ? (uint16_t)(c->filled + 1u) : c->filled;
    if (state == LINK_CAP_POST) {
        c->post_left--;
        if (c->post_left == 0u) {
            c->first_index = c->trig_index - (uint32_t)c->pre * c->decimate;
            c->state = LINK_CAP_DONE;
        }
        return;
    }
    if (triggered(c, t, c->filled > c->pre)) {
        c->trig_index = index;
        c->post_left = (uint16_t)(c->samples - c->pre - 1u);
        if (c->post_left == 0u) {
            c->first_index = c->trig_index - (uint32_t)c->pre * c->decimate;
            c->state = LINK_CAP_DONE;
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
    for (uint16_t k = 0u; k < n; k++) {
        s->val[w][k] = link_var_get(&l->t, s->ids[k]);
    }
    s->wr = next;
}

void link_isr(link_t *l)
{
    capture_isr(&l->cap, &l->t);
    stream_isr(l);
}
