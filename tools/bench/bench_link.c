/* bench_link.c CALLS [idle|capture|worst] - drives link_isr() (firmware/link/link.h) for
 * tools/bench/bench_link.sh (callgrind): the link's cost in the control ISR.
 *   idle     nothing armed: the call only finds capture and stream off
 *   capture  a capture armed on 4 channels with a NAME>VALUE trigger that
 *            never fires: every period samples 4 channels and compares the
 *            trigger variable (the typical case while waiting for a trigger)
 *   worst    a capture of 4 channels armed again whenever it is done, with
 *            a trigger that fires (forced, 60 rows), plus a stream of 8
 *            variables every period whose queue the background drains
 *            (link_poll between calls): every kind of period, the trigger's
 *            among them
 * The app is configured (app_cfg_default) but not run; its monitor holds
 * fixed values. Host only. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app.h"
#include "cmd.h"
#include "bench_link_request.h"
#include "link.h"

static app_t app;
static volatile cmd_t cmd;
static link_t lk;
static const cmd_limits_t LIM = { 2000.0f, 12.0f, 300.0f };

int main(int argc, char **argv)
{
    const long n = (argc > 1) ? atol(argv[1]) : 10000;
    const char *mode = (argc > 2) ? argv[2] : "capture";
    const link_cfg_t lc = { 1e-4f, 937500u, "bench", 0.0f, { NULL, NULL, NULL, NULL } };
    app_cfg_default(&app.cfg);
    app.state = APP_STATE_RUN;
    app.ctrl.mon.speed_mech_rad_s = 52.0f;
    app.ctrl.mon.iq_A = 3.7f;
    cmd_init(&cmd);
    link_init(&lk, &lc, &app, &cmd, &LIM);
    const int worst = strcmp(mode, "worst") == 0;
    /* pre 10, 60 rows, forced (worst); or pre 100, 1000 rows, ABOVE speed_est_rpm > 1e6 (never) */
    const uint16_t pre = worst ? 10u : 100u;
    const uint16_t rows = worst ? 60u : 1000u;
    const uint16_t trig = worst ? LINK_TRIG_FORCED : LINK_TRIG_ABOVE;
    if (strcmp(mode, "idle") != 0) {
        bench_link_arm(&lk, pre, rows, trig, LV_SPEED_EST_RPM, 1.0e6f);
    }
    if (worst) {
        uint16_t p[18];
        uint16_t i = link_put_u16(p, 0u, 1u);
        for (uint16_t k = 0; k < LINK_STREAM_VARS; k++) {
            i = link_put_u16(p, i, (uint16_t)(LV_SPEED_EST_RPM + k));
        }
        lk.cfg.baud = 100000000u;   /* a budget that takes it: the ISR's cost is what is measured */
        bench_link_request(&lk, LINK_STREAM_SET, p, i);
    }
    uint16_t b;
    long captures = 0;
    for (long k = 0; k < n; k++) {
        app.ticks++;
        link_isr(&lk);
        link_poll(&lk);
        while (link_tx_get(&lk, &b)) {
        }
        if (worst && lk.cap.state == LINK_CAP_DONE) {
            captures++;
            bench_link_arm(&lk, pre, rows, trig, LV_SPEED_EST_RPM, 1.0e6f);
        }
    }
    printf("bench_link: %ld calls, %s, capture state %u, %ld captures done, stream dropped %u\n", n, mode,
           (unsigned)lk.cap.state, captures, (unsigned)lk.stats.stream_dropped);
    return 0;
}
