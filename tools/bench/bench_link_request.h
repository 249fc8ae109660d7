/* bench_link_request.h - a request straight into a link, handled at once,
 * its reply and whatever else was queued dropped: the link benches'
 * (tools/bench/bench_link.c, tools/bench/bench_isr_link.c) way to arm a capture or set
 * a stream. Each call is a new request (its own sequence number). Host only. */
#ifndef BENCH_LINK_REQUEST_H
#define BENCH_LINK_REQUEST_H

#include <string.h>

#include "link.h"

#define BENCH_LINK_POLLS 8   /* link_poll calls: the request's bytes are in after the first */

static void bench_link_request(link_t *lk, uint16_t type, const uint16_t *p, uint16_t len)
{
    static link_frame_t f;
    static uint16_t w[LINK_ENCODED_MAX];
    uint16_t b;
    f.type = type;
    f.seq = (uint16_t)(f.seq % 255u + 1u);
    f.len = len;
    if (len > 0u) {
        memcpy(f.payload, p, len * sizeof p[0]);
    }
    const uint16_t n = link_frame_encode(&f, w);
    for (uint16_t i = 0; i < n; i++) {
        (void)link_rx_put(lk, w[i]);
    }
    for (int k = 0; k < BENCH_LINK_POLLS; k++) {
        link_poll(lk);
    }
    while (link_tx_get(lk, &b)) {
    }
}

/* CAPTURE_ARM (decimate 1) of the benches' 4 channels: iq_meas_A, id_meas_A, speed_est_rpm,
 * te_est_Nm. */
static void bench_link_arm(link_t *lk, uint16_t pre, uint16_t samples, uint16_t trig, uint16_t trig_id, float level)
{
    static const uint16_t ch[4] = { LV_IQ_MEAS_A, LV_ID_MEAS_A, LV_SPEED_EST_RPM, LV_TE_EST_NM };
    uint16_t p[26];
    uint16_t i = link_put_u16(p, 0u, 1u);
    i = link_put_u16(p, i, pre);
    i = link_put_u16(p, i, samples);
    p[i++] = trig;
    i = link_put_u16(p, i, trig_id);
    i = link_put_f32(p, i, level);
    i = link_put_f32(p, i, 0.0f);
    p[i++] = 4u;
    for (uint16_t k = 0u; k < 4u; k++) {
        i = link_put_u16(p, i, ch[k]);
    }
    bench_link_request(lk, LINK_CAPTURE_ARM, p, i);
}

#endif /* BENCH_LINK_REQUEST_H */
