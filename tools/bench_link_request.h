/* bench_link_request.h - a request straight into a link, handled at once,
 * its reply and whatever else was queued dropped: the link benches'
 * (tools/bench_link.c, tools/bench_isr_link.c) way to arm a capture or set
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

#endif /* BENCH_LINK_REQUEST_H */
