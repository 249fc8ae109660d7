/* bench_isr_link.c SCENARIO STATES_OUT [KEY=VALUE ...] - the SIL run of
 * tools/bench/bench_isr.sh with the link busy in every period, for callgrind
 * (`make bench`): the control ISR is app_isr then link_isr, as on the
 * board (firmware/f28335/main.c). From the first period a capture is armed on 4
 * channels and, each time it is done, armed again cycling through the
 * triggers iq_meas_A>I, iq_meas_A<I (I: its value when armed, which the
 * current's ripple crosses) and forced (short captures, so it triggers
 * often; one that waits longer than 3 captures' length is armed anew); a stream of 8 variables runs every period (the line's
 * budget lifted: the ISR's worst is what is measured) and the background
 * drains it after each period. Writes the app state each period ended
 * in, one a line, to STATES_OUT. Host only. */
#include <stdio.h>
#include <string.h>

#include "bench_link_request.h"
#include "link.h"
#include "scenario.h"
#include "sil.h"

#define BENCH_BAUD 100000000u        /* a budget that takes an 8-variable stream every period */
#define CAP_PRE 10u
#define CAP_SAMPLES 60u
#define TRIGGERS 3u
#define REARM_PERIODS (3u * CAP_SAMPLES)  /* a trigger not seen by then is given up: armed anew */

static link_t lk;
static volatile cmd_t cmd;
static cmd_limits_t lim;
static FILE *states;
static uint16_t arms;
static uint32_t done;                /* captures that triggered and completed */
static uint32_t waited;              /* periods since the last arming */

static void arm(void)
{
    static const uint16_t trig[TRIGGERS] = { LINK_TRIG_ABOVE, LINK_TRIG_BELOW, LINK_TRIG_FORCED };
    const float iq_now_A = link_var_get(&lk.t, LV_IQ_MEAS_A).f;   /* the current ripples across it */
    bench_link_arm(&lk, CAP_PRE, CAP_SAMPLES, trig[arms % TRIGGERS], LV_IQ_MEAS_A, iq_now_A);
    arms++;
}

static void on_start(void *user, app_t *app)
{
    (void)user;
    const link_cfg_t lc = { app->cfg.ctrl.Ts_s, BENCH_BAUD, "bench", 0.0f, { NULL, NULL, NULL, NULL } };
    lim.speed_max_rpm = app->cfg.prot.speed_max_rad_s / MATHX_RAD_S_PER_RPM_F;
    lim.te_max_Nm = app->cfg.ctrl.te_max_Nm;
    lim.u_max_V = app->cfg.ctrl.u_max_V;
    cmd_init(&cmd);
    link_init(&lk, &lc, app, &cmd, &lim);
    uint16_t p[2u + 2u * LINK_STREAM_VARS];
    uint16_t i = link_put_u16(p, 0u, 1u);
    for (uint16_t k = 0; k < LINK_STREAM_VARS; k++) {
        i = link_put_u16(p, i, (uint16_t)(LV_SPEED_EST_RPM + k));
    }
    bench_link_request(&lk, LINK_STREAM_SET, p, i);
    arm();
}

static void on_isr_end(void *user)
{
    (void)user;
    link_isr(&lk);
}

static int on_period_end(void *user)
{
    (void)user;
    uint16_t b;
    link_poll(&lk);
    while (link_tx_get(&lk, &b)) {
    }
    waited++;
    if (lk.cap.state == LINK_CAP_DONE || waited > REARM_PERIODS) {
        done += (lk.cap.state == LINK_CAP_DONE) ? 1u : 0u;
        waited = 0u;
        arm();
    }
    return 0;
}

static int on_row(const sil_row_t *row, void *user)
{
    (void)user;
    fprintf(states, "%d\n", (int)row->state);
    return 0;
}

int main(int argc, char **argv)
{
    static scenario_t sc;
    char err[SCENARIO_ERR_LEN];
    if (argc < 3) {
        fprintf(stderr, "usage: bench_isr_link SCENARIO STATES_OUT [KEY=VALUE ...]\n");
        return 2;
    }
    scenario_defaults(&sc);
    if (scenario_load(&sc, argv[1], err, sizeof err) != 0) {
        fprintf(stderr, "bench_isr_link: %s\n", err);
        return 2;
    }
    for (int a = 3; a < argc; a++) {
        if (scenario_set(&sc, argv[a], err, sizeof err) != 0) {
            fprintf(stderr, "bench_isr_link: %s\n", err);
            return 2;
        }
    }
    if (scenario_set(&sc, "run.log_every=1", err, sizeof err) != 0 || scenario_finish(&sc, err, sizeof err) != 0) {
        fprintf(stderr, "bench_isr_link: %s\n", err);
        return 2;
    }
    states = fopen(argv[2], "w");
    if (states == NULL) {
        perror(argv[2]);
        return 2;
    }
    const sil_hooks_t hooks = { on_start, on_isr_end, NULL, on_period_end, NULL };
    sil_ctl_t ctl;
    memset(&ctl, 0, sizeof ctl);
    ctl.hooks = &hooks;
    sil_result_t res;
    (void)sil_run_ctl(&sc, on_row, NULL, &ctl, &res);
    fclose(states);
    printf("bench_isr_link: %u periods, %u captures armed, %u triggered and done, stream dropped %u\n",
           (unsigned)res.periods, (unsigned)arms, (unsigned)done, (unsigned)lk.stats.stream_dropped);
    return 0;
}
