/* test_app_init_pattern.c - app_init and cmd_init must not rely on zeroed
 * memory. On the target the image is built with TI's COFF ABI, whose C
 * run-time zeroes nothing (f28335_codestart.asm zeroes .ebss, but the
 * application does not count on it); the host tests always start from
 * zeroed statics, where a field app_init misses would never show.
 *
 * Here the drive's state (app_t, cmd_t) is filled with a byte pattern
 * before app_init / cmd_init, then main.c's sequence runs on the simulated
 * board (hal_sim, the default board): the operator's command block asks
 * for a start in speed mode, the background loop applies it, and the ISR
 * runs calibration, alignment, step 1 of the proposed method and RUN.
 * Every period's outputs (state, fault, warnings, duties, flags, the
 * command block's error and the plant's currents and speed) must be
 * bit-identical for every pattern: a field the ISR or the background read
 * before anything wrote it would make a pattern's run differ. Patterns:
 * 0x00 (the host's own start), 0xFF (floats NaN, integers all ones),
 * 0x7F (floats 3.4e38), 0xA5 (floats -2.9e-16, booleans neither 0 nor
 * 1). Run 0x00 twice first: the board simulation must repeat itself, or
 * a difference would prove nothing.
 *
 * The same for the commissioning's state (comm_t, its own object: in M0
 * on the F28335, not zeroed by anyone): filled with the pattern before
 * app_attach_comm, then a commissioning through the command block's
 * request on a free shaft to its end (IDLE, values valid). */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app.h"
#include "board_cfg.h"
#include "cmd.h"
#include "hal_sim.h"
#include "sil_board.h"

#define RUN_S        3.0          /* calibration 0.11 s, alignment 1.2 s, step 1 about 1.2 s, then RUN [s] */
#define SPEED_RPM    600.0f       /* the operator's reference: step 1's second speed hands over to it */
#define LOAD_NM      1.0          /* step 1 in speeds mode needs a load (rsid_seq.h) */
#define COMM_RUN_S   6.0          /* calibration, then the commissioning's stages, about 5.2 s [s] */

typedef struct {
    uint16_t state, fault, warnings, cmd_error;
    float duty[3];
    uint16_t flags;
    double ia_A, ib_A, speed_m_rad_s;
} trace_t;

static app_t app;
static comm_t comm;
static volatile cmd_t cmd;
static volatile cmd_comm_t cmd_comm;
static trace_t *trace[2];

static void isr(void)
{
    app_isr(&app);
}

/* main.c's start-up and loop, with the drive's state filled with fill
 * first: a start in speed mode, or (commission) a commissioning. */
static uint32_t run(uint8_t fill, trace_t *out, uint32_t n, uint16_t *max_state, bool commission)
{
    hal_sim_cfg_t hc;
    app_cfg_t cfg;
    cmd_limits_t lim;

    sil_board_default(&hc);
    hal_sim_configure(&hc);
    hal_sim_set_load(commission ? 0.0 : LOAD_NM);
    hal_init();
    memset(&app, fill, sizeof app);
    memset(&comm, fill, sizeof comm);
    memset((void *)&cmd, fill, sizeof cmd);
    memset((void *)&cmd_comm, fill, sizeof cmd_comm);
    app_cfg_default(&cfg);
    cfg.rsid.mode = APP_RSID_SPEEDS;
    cfg.lvl.level = LEVEL_FULL; /* the whole start to RUN (the board's own start is level 1's, no bus) */
    app_init(&app, &cfg);
    app_attach_comm(&app, &comm);
    cmd_init(&cmd);
    cmd_comm_init(&cmd_comm);
    lim.speed_max_rpm = MOTOR_RATED_SPEED_RPM;
    lim.te_max_Nm = cfg.ctrl.te_max_Nm;
    lim.u_max_V = cfg.ctrl.u_max_V;
    hal_isr_attach(isr);
    /* the operator: proposed method, speed mode, the reference, run */
    cmd.method = (uint16_t)CTRL_METHOD_PROPOSED;
    cmd.mode = (uint16_t)CTRL_MODE_SPEED;
    cmd.speed_ref_rpm = SPEED_RPM;
    cmd.run = commission ? 0u : 1u;
    cmd_comm.start = commission ? 1u : 0u;
    *max_state = 0u;
    for (uint32_t k = 0; k < n; k++) {
        cmd_apply(&cmd, &lim, &app);
        cmd_comm_apply(&cmd_comm, &cmd, &app);
        app_background(&app);
        hal_sim_period();
        const hal_sim_truth_t *tr = hal_sim_truth_view();
        trace_t t;
        memset(&t, 0, sizeof t); /* padding too: compared with memcmp */
        t.state = (uint16_t)app.state;
        t.fault = (uint16_t)app.fault;
        t.warnings = app.warnings;
        t.cmd_error = cmd.error;
        memcpy(t.duty, app.out.duty, sizeof t.duty);
        t.flags = app.out.flags;
        t.ia_A = tr->ia_A;
        t.ib_A = tr->ib_A;
        t.speed_m_rad_s = tr->speed_m_rad_s;
        out[k] = t;
        if (t.state > *max_state && t.state != APP_STATE_FAULT) {
            *max_state = t.state;
        }
    }
    return n;
}

/* The first period where two traces differ, or n when none does. */
static uint32_t first_difference(const trace_t *a, const trace_t *b, uint32_t n)
{
    for (uint32_t k = 0; k < n; k++) {
        if (memcmp(&a[k], &b[k], sizeof a[k]) != 0) {
            return k;
        }
    }
    return n;
}

static void init_does_not_rely_on_zeroed_memory(void **state)
{
    (void)state;
    const uint32_t n = (uint32_t)(RUN_S / 1e-4 + 0.5);
    const uint8_t fills[] = { 0x00u, 0xFFu, 0x7Fu, 0xA5u };
    uint16_t reached;

    trace[0] = calloc(n, sizeof *trace[0]);
    trace[1] = calloc(n, sizeof *trace[1]);
    assert_non_null(trace[0]);
    assert_non_null(trace[1]);

    /* the reference run: it must get through the whole start to RUN, without a fault */
    run(0x00u, trace[0], n, &reached, false);
    assert_int_equal(reached, APP_STATE_RUN);
    assert_int_equal(trace[0][n - 1].state, APP_STATE_RUN);
    assert_int_equal(trace[0][n - 1].fault, APP_FAULT_NONE);
    /* step 1 on this board (no load through the alignment, 1 N m) solved
     * R^ = 8.1 Ohm for the 3 Ohm motor; the d-axis check refuses it
     * (RSID_D_AXIS, step1_design.md sec. 6) and the drive runs on
     * conventionally with the warning: only that one is allowed */
    assert_int_equal(trace[0][n - 1].warnings & (uint16_t)~APP_WARN_STEP1_REFUSED, 0u);
    for (size_t j = 0; j < sizeof fills; j++) {
        run(fills[j], trace[1], n, &reached, false);
        const uint32_t k = first_difference(trace[0], trace[1], n);
        if (k < n) {
            print_error("fill 0x%02X: period %u differs (state %u/%u, fault %u/%u, duty a %.9g/%.9g)\n",
                        fills[j], k, trace[0][k].state, trace[1][k].state, trace[0][k].fault,
                        trace[1][k].fault, (double)trace[0][k].duty[0], (double)trace[1][k].duty[0]);
        }
        assert_int_equal(k, n);
    }
    free(trace[0]);
    free(trace[1]);
}

static void commissioning_does_not_rely_on_zeroed_memory(void **state)
{
    (void)state;
    const uint32_t n = (uint32_t)(COMM_RUN_S / 1e-4 + 0.5);
    const uint8_t fills[] = { 0xFFu, 0x7Fu, 0xA5u };
    uint16_t reached;

    trace[0] = calloc(n, sizeof *trace[0]);
    trace[1] = calloc(n, sizeof *trace[1]);
    assert_non_null(trace[0]);
    assert_non_null(trace[1]);
    run(0x00u, trace[0], n, &reached, true);
    run(0x00u, trace[1], n, &reached, true);
    assert_int_equal(first_difference(trace[0], trace[1], n), n);   /* the board repeats itself */
    assert_int_equal(reached, APP_STATE_COMMISSION);
    assert_int_equal(trace[0][n - 1].state, APP_STATE_IDLE);
    assert_int_equal(trace[0][n - 1].fault, APP_FAULT_NONE);
    assert_int_equal(cmd_comm.state, 2u);                              /* done, the values valid */
    for (size_t j = 0; j < sizeof fills; j++) {
        run(fills[j], trace[1], n, &reached, true);
        const uint32_t k = first_difference(trace[0], trace[1], n);
        if (k < n) {
            print_error("commissioning, fill 0x%02X: period %u differs (state %u/%u, fault %u/%u)\n", fills[j], k,
                        trace[0][k].state, trace[1][k].state, trace[0][k].fault, trace[1][k].fault);
        }
        assert_int_equal(k, n);
    }
    free(trace[0]);
    free(trace[1]);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(init_does_not_rely_on_zeroed_memory),
        cmocka_unit_test(commissioning_does_not_rely_on_zeroed_memory),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
