/* Unit tests for firmware/link (link_protocol.md) on a real app_t against
 * the HAL mock: every request type, WRITE through cmd_apply() (a refused
 * value named and not applied, access checked), the reply cache (a repeat
 * is answered, not executed again), the stream's budget, the capture's
 * trigger, pre-trigger rows and period indices, actions refused naming
 * the state, the host timeout's ramp and stop, the parameters (written
 * stopped, within their range), and a lossy link (bytes
 * dropped, flipped, duplicated, garbage at 10 % each way) on which every
 * write is applied exactly once. Expected values are derived in the
 * comments. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "app.h"
#include "app_probe.h"
#include "cmd.h"
#include "drive_params.h"
#include "link.h"
#include "link_nv.h"
#include "link_params.h"
#include "mathx.h"
#include "mock_hal.h"
#include "nv_ram_sector.h"

#define TS_S 1.0e-4f
#define BAUD 115200u
#define POLLS_MAX 64

static const cmd_limits_t LIM = { 2000.0f, 12.0f, 300.0f };
static app_t app;
static volatile cmd_t cmd;
static link_t lk;
static link_rx_t host_rx;           /* the host's receiver */
static link_frame_t rep;

static int setup(void **state)
{
    app_cfg_t cfg;
    link_cfg_t lc = { TS_S, BAUD, "test", 0.0f, { NULL, NULL, NULL, NULL } };
    (void)state;
    app_cfg_default(&cfg);
    expect_function_call(hal_pwm_disable);
    app_init(&app, &cfg);
    cmd_init(&cmd);
    link_init(&lk, &lc, &app, &cmd, &LIM);
    link_rx_init(&host_rx);
    return 0;
}

/* Everything the link has sent, through the host's receiver: the last reply of type want into rep;
 * the number of such replies. */
static int drain(uint16_t want)
{
    uint16_t b;
    int n = 0;
    static link_frame_t f;
    while (link_tx_get(&lk, &b)) {
        if (link_rx_byte(&host_rx, b, &f) && f.type == want) {
            rep = f;
            n++;
        }
    }
    return n;
}

static void send_bytes(const uint16_t *w, uint16_t n)
{
    for (uint16_t i = 0; i < n; i++) {
        assert_true(link_rx_put(&lk, w[i]));
    }
}

/* One request, polled until handled; returns the reply count (1 expected). */
static int request(uint16_t type, uint16_t seq, const uint16_t *p, uint16_t len)
{
    static link_frame_t f;
    uint16_t w[LINK_ENCODED_MAX];
    f.type = type;
    f.seq = seq;
    f.len = len;
    if (len > 0u) {
        memcpy(f.payload, p, len * sizeof p[0]);
    }
    send_bytes(w, link_frame_encode(&f, w));
    for (int k = 0; k < POLLS_MAX; k++) {
        link_poll(&lk);
    }
    return drain((uint16_t)(type | LINK_REPLY));
}

static uint16_t seq_next(void)
{
    static uint16_t s;
    s = (uint16_t)(s % 255u + 1u);
    return s;
}

static int write_f(uint16_t id, float v, uint16_t seq)
{
    uint16_t p[6];
    (void)link_put_u16(p, 0u, id);
    (void)link_put_f32(p, 2u, v);
    return request(LINK_WRITE, seq, p, 6u);
}

static void hello_names_version_table_and_period(void **state)
{
    (void)state;
    assert_int_equal(request(LINK_HELLO, 1u, NULL, 0u), 1);
    assert_int_equal(rep.seq, 1);
    assert_int_equal(rep.payload[0], LINK_ST_OK);
    assert_int_equal(rep.payload[1], LINK_PROTOCOL_VERSION);
    assert_int_equal(link_get_u16(rep.payload, 2u), LV_COUNT);
    assert_int_equal(link_get_u32(rep.payload, 4u), link_vars_hash(&lk.t));
    assert_int_equal(link_get_u32(rep.payload, 8u), 100000u);      /* 1e-4 s in ns */
    assert_int_equal(link_get_u32(rep.payload, 12u), BAUD);
    assert_int_equal(link_get_u16(rep.payload, 16u), 1024);
    assert_int_equal(rep.payload[20], 4);                           /* "test" */
}

static void list_vars_pages_through_the_table_with_csv_names(void **state)
{
    (void)state;
    uint16_t id = 0u;
    int found = 0;
    while (id < (uint16_t)LV_COUNT) {
        uint16_t p[2];
        (void)link_put_u16(p, 0u, id);
        assert_int_equal(request(LINK_LIST_VARS, seq_next(), p, 2u), 1);
        assert_int_equal(link_get_u16(rep.payload, 1u), id);
        const uint16_t count = rep.payload[3];
        assert_true(count > 0u);
        uint16_t i = 4u;
        for (uint16_t k = 0; k < count; k++) {
            if (id + k == LV_SPEED_EST_RPM) {
                /* capture scale: the overspeed limit's 2400 r/min over 32767 counts */
                assert_float_equal(link_get_f32(rep.payload, (uint16_t)(i + 2u)), 2400.0f / 32767.0f, 1e-6);
            }
            i = (uint16_t)(i + 14u);
            const uint16_t n = rep.payload[i];
            char name[64] = { 0 };
            for (uint16_t c = 0; c < n; c++) {
                name[c] = (char)rep.payload[i + 1u + c];
            }
            assert_string_equal(name, link_var((uint16_t)(id + k))->name);
            found += (strcmp(name, "iq_meas_A") == 0 || strcmp(name, "speed_est_rpm") == 0) ? 1 : 0;
            i = (uint16_t)(i + 1u + n);
            i = (uint16_t)(i + 1u + rep.payload[i]);
        }
        assert_true(i <= LINK_PAYLOAD_MAX);
        id = (uint16_t)(id + count);
    }
    assert_int_equal(found, 2);
}

static void read_returns_values_in_their_types(void **state)
{
    (void)state;
    probe_monitor_rw(&app)->iq_A = 1.25f;
    app.ticks = 70000u;
    uint16_t p[6];
    (void)link_put_u16(p, 0u, LV_IQ_MEAS_A);
    (void)link_put_u16(p, 2u, LV_STATE);
    (void)link_put_u16(p, 4u, LV_TICKS);
    assert_int_equal(request(LINK_READ, seq_next(), p, 6u), 1);
    assert_int_equal(rep.payload[0], LINK_ST_OK);
    assert_true(link_get_f32(rep.payload, 1u) == 1.25f);
    assert_int_equal(link_get_u16(rep.payload, 5u), APP_STATE_INIT);
    assert_int_equal(link_get_u32(rep.payload, 7u), 70000u);        /* u32: not rounded through a float */
    assert_int_equal(rep.len, 11);
    (void)link_put_u16(p, 0u, 999u);
    assert_int_equal(request(LINK_READ, seq_next(), p, 2u), 1);
    assert_int_equal(rep.payload[0], LINK_ST_UNKNOWN_ID);
}

static void write_goes_through_cmd_apply(void **state)
{
    (void)state;
    assert_int_equal(write_f(LV_SPEED_REF_RPM, 500.0f, seq_next()), 1);
    assert_int_equal(rep.payload[0], LINK_ST_OK);
    /* the app's request: 500 r/min = 52.36 rad/s */
    assert_float_equal(app.op_req.ref.speed_ref_rad_s, 500.0f * MATHX_RAD_S_PER_RPM_F, 1e-4);
    assert_int_equal(app.req_op, 1);
    /* beyond the 2000 r/min limit: refused with cmd_apply's reason, the request unchanged */
    assert_int_equal(write_f(LV_SPEED_REF_RPM, 2500.0f, seq_next()), 1);
    assert_int_equal(rep.payload[0], LINK_ST_REFUSED);
    assert_int_equal(link_get_u16(rep.payload, 1u), CMD_ERR_SPEED);
    assert_float_equal(app.op_req.ref.speed_ref_rad_s, 500.0f * MATHX_RAD_S_PER_RPM_F, 1e-4);
    assert_float_equal(cmd.speed_ref_rpm, 500.0f, 1e-3);             /* the refused value was put back */
    /* NaN: refused the same way */
    assert_int_equal(write_f(LV_TE_CMD_NM, NAN, seq_next()), 1);
    assert_int_equal(link_get_u16(rep.payload, 1u), CMD_ERR_TORQUE);
    /* read-only, and write-when-stopped while running */
    assert_int_equal(write_f(LV_SPEED_EST_RPM, 1.0f, seq_next()), 1);
    assert_int_equal(rep.payload[0], LINK_ST_ACCESS);
    app.state = APP_STATE_RUN;
    assert_int_equal(app.op_req.mode, CTRL_MODE_TORQUE);            /* app_init's */
    uint16_t p[6];
    (void)link_put_u16(p, 0u, LV_MODE);
    (void)link_put_u32(p, 2u, CTRL_MODE_SPEED);
    assert_int_equal(request(LINK_WRITE, seq_next(), p, 6u), 1);
    assert_int_equal(rep.payload[0], LINK_ST_ACCESS);
    assert_int_equal(app.op_req.mode, CTRL_MODE_TORQUE);
    app.state = APP_STATE_IDLE;
    assert_int_equal(request(LINK_WRITE, seq_next(), p, 6u), 1);
    assert_int_equal(rep.payload[0], LINK_ST_OK);
    assert_int_equal(app.op_req.mode, CTRL_MODE_SPEED);
    /* a mode beyond 16 bits does not wrap to a valid one */
    (void)link_put_u32(p, 2u, 0x10001ul);
    assert_int_equal(request(LINK_WRITE, seq_next(), p, 6u), 1);
    assert_int_equal(link_get_u16(rep.payload, 1u), CMD_ERR_MODE);
}

static void a_repeated_request_is_answered_from_the_cache(void **state)
{
    (void)state;
    const uint32_t w0 = lk.stats.writes;
    assert_int_equal(write_f(LV_TE_CMD_NM, 2.0f, 77u), 1);
    const link_frame_t first = rep;
    app.op_req.ref.te_ref_Nm = 0.0f;            /* had it run again, it would set 2 N m again */
    assert_int_equal(write_f(LV_TE_CMD_NM, 2.0f, 77u), 1);
    assert_int_equal(rep.len, first.len);
    assert_memory_equal(rep.payload, first.payload, first.len * sizeof first.payload[0]);
    assert_true(app.op_req.ref.te_ref_Nm == 0.0f);
    assert_int_equal(lk.stats.writes, w0 + 1u);
    /* the same seq with another payload is a new request */
    assert_int_equal(write_f(LV_TE_CMD_NM, 3.0f, 77u), 1);
    assert_true(app.op_req.ref.te_ref_Nm == 3.0f);
    assert_int_equal(lk.stats.writes, w0 + 2u);
}

static void actions_start_stop_reset(void **state)
{
    (void)state;
    uint16_t a = LINK_ACTION_START;
    assert_int_equal(request(LINK_ACTION, seq_next(), &a, 1u), 1);
    assert_int_equal(rep.payload[0], LINK_ST_OK);
    assert_int_equal(app.req_start, 1);
    a = LINK_ACTION_STOP;
    assert_int_equal(request(LINK_ACTION, seq_next(), &a, 1u), 1);
    assert_int_equal(app.req_stop, 1);
    a = 9u;
    assert_int_equal(request(LINK_ACTION, seq_next(), &a, 1u), 1);
    assert_int_equal(rep.payload[0], LINK_ST_BAD_REQUEST);
    assert_int_equal(request(0x3Fu, seq_next(), NULL, 0u), 1);
    assert_int_equal(rep.payload[0], LINK_ST_UNKNOWN_TYPE);
}

/* Actions the state makes do nothing are refused, nothing done, the reason as cmd_error: a
 * start or commission in FAULT (CMD_ERR_FAULTED), a commission while running (NOT_STOPPED);
 * from IDLE both are taken. */
static void actions_refused_naming_the_state(void **state)
{
    (void)state;
    uint16_t a = LINK_ACTION_START;
    app.state = APP_STATE_FAULT;
    assert_int_equal(request(LINK_ACTION, seq_next(), &a, 1u), 1);
    assert_int_equal(rep.payload[0], LINK_ST_REFUSED);
    assert_int_equal(link_get_u16(rep.payload, 1u), CMD_ERR_FAULTED);
    assert_int_equal(app.req_start, 0);
    assert_int_equal(cmd.error, CMD_ERR_FAULTED);
    a = LINK_ACTION_COMMISSION;
    assert_int_equal(request(LINK_ACTION, seq_next(), &a, 1u), 1);
    assert_int_equal(link_get_u16(rep.payload, 1u), CMD_ERR_FAULTED);
    assert_int_equal(app.req_commission, 0);
    app.state = APP_STATE_RUN;
    assert_int_equal(request(LINK_ACTION, seq_next(), &a, 1u), 1);
    assert_int_equal(rep.payload[0], LINK_ST_REFUSED);
    assert_int_equal(link_get_u16(rep.payload, 1u), CMD_ERR_NOT_STOPPED);
    assert_int_equal(app.req_commission, 0);
    app.state = APP_STATE_IDLE;
    assert_int_equal(request(LINK_ACTION, seq_next(), &a, 1u), 1);
    assert_int_equal(rep.payload[0], LINK_ST_OK);         /* taken (this app has no commissioning to run) */
    a = LINK_ACTION_START;
    assert_int_equal(request(LINK_ACTION, seq_next(), &a, 1u), 1);
    assert_int_equal(rep.payload[0], LINK_ST_OK);
    assert_int_equal(app.req_start, 1);
}

/* host_timeout_s = 0.01 s (100 periods): written within 0..600 s, refused outside (nothing
 * changed). A speed reference of 300 r/min (31.42 rad/s) written in RUN arms it; 99 periods of
 * silence do nothing, the 101st starts the ramp with the warning raised: after 50 more periods
 * the reference is 31.42 - accel 50 Ts (accel the drive's ramp rate, app_cfg's
 * rsid.accel_rad_s2); at zero, the rotor still, the drive is stopped. Any valid frame before the
 * timeout restarts the silence; with 0 (off) nothing happens. */
static void host_timeout_ramps_to_zero_and_stops(void **state)
{
    (void)state;
    const float ref_rad_s = 300.0f * MATHX_RAD_S_PER_RPM_F;
    const float accel = app.cfg.rsid.accel_rad_s2;
    assert_int_equal(write_f(LV_HOST_TIMEOUT_S, -1.0f, seq_next()), 1);
    assert_int_equal(rep.payload[0], LINK_ST_REFUSED);
    assert_int_equal(link_get_u16(rep.payload, 1u), CMD_ERR_RANGE);
    assert_int_equal(write_f(LV_HOST_TIMEOUT_S, 601.0f, seq_next()), 1);
    assert_int_equal(link_get_u16(rep.payload, 1u), CMD_ERR_RANGE);
    assert_int_equal(write_f(LV_HOST_TIMEOUT_S, NAN, seq_next()), 1);
    assert_int_equal(link_get_u16(rep.payload, 1u), CMD_ERR_RANGE);
    assert_true(lk.host.timeout_s == 0.0f);
    assert_int_equal(write_f(LV_HOST_TIMEOUT_S, 0.01f, seq_next()), 1);
    assert_int_equal(rep.payload[0], LINK_ST_OK);
    app.state = APP_STATE_RUN;
    app.op_taken.mode = CTRL_MODE_SPEED;
    app.ticks = 1000u;
    assert_int_equal(write_f(LV_SPEED_REF_RPM, 300.0f, seq_next()), 1);
    assert_float_equal(app.op_req.ref.speed_ref_rad_s, ref_rad_s, 1e-4);
    app.ticks += 99u;
    link_poll(&lk);
    assert_int_equal(app.req_warning, 0);
    assert_float_equal(app.op_req.ref.speed_ref_rad_s, ref_rad_s, 1e-4);
    app.ticks += 2u;
    link_poll(&lk);
    assert_int_equal(app.req_warning, APP_WARN_HOST_TIMEOUT);
    app.ticks += 50u;
    link_poll(&lk);
    assert_float_equal(app.op_req.ref.speed_ref_rad_s, ref_rad_s - accel * 50.0f * TS_S, 1e-3);
    assert_int_equal(app.req_stop, 0);
    app.ticks += (uint32_t)(ref_rad_s / accel / TS_S) + 1u;
    link_poll(&lk);                       /* the reference at zero, the rotor still: stopped */
    assert_true(app.op_req.ref.speed_ref_rad_s == 0.0f);
    assert_int_equal(app.req_stop, 1);
    /* off: silence does nothing */
    app.req_warning = 0u;
    app.req_stop = 0u;
    assert_int_equal(write_f(LV_HOST_TIMEOUT_S, 0.0f, seq_next()), 1);
    assert_int_equal(write_f(LV_SPEED_REF_RPM, 300.0f, seq_next()), 1);
    app.ticks += 100000u;
    link_poll(&lk);
    assert_int_equal(app.req_warning, 0);
    assert_float_equal(app.op_req.ref.speed_ref_rad_s, ref_rad_s, 1e-4);
}

static drive_params_t params;
static int applied_k = -1;

static void on_params(void *user, uint16_t k)
{
    (void)user;
    applied_k = (int)k;
}

static int setup_params(void **state)
{
    app_cfg_t cfg;
    link_cfg_t lc = { TS_S, BAUD, "test", 0.0f, { &params, on_params, NULL, NULL } };
    (void)state;
    app_cfg_default(&cfg);
    expect_function_call(hal_pwm_disable);
    app_init(&app, &cfg);
    cmd_init(&cmd);
    drive_params_board(&params);
    (void)drive_params_derive(&params);
    link_init(&lk, &lc, &app, &cmd, &LIM);
    link_rx_init(&host_rx);
    applied_k = -1;
    return 0;
}

/* READ of one variable, answered OK: its value at rep.payload[1]. */
static void read_one(uint16_t id)
{
    uint16_t q[2];
    (void)link_put_u16(q, 0u, id);
    assert_int_equal(request(LINK_READ, seq_next(), q, 2u), 1);
    assert_int_equal(rep.payload[0], LINK_ST_OK);
}

static float read_f(uint16_t id)
{
    read_one(id);
    return link_get_f32(rep.payload, 1u);
}

static uint16_t read_u16(uint16_t id)
{
    read_one(id);
    return link_get_u16(rep.payload, 1u);
}

/* A parameter (R_ohm, the first): ACCESS while running, nothing changed; written while stopped
 * into the parameter set, the glue told which; out of its range (the scenario key's:
 * LINK_PARAM_R_OHM_HI) REFUSED with CMD_ERR_RANGE, nothing changed; read back. pole_pairs
 * (u16) written as an integer. Without a parameter set (NULL) not writable at all. */
static void parameters_written_stopped_within_their_range(void **state)
{
    (void)state;
    const uint16_t r_id = (uint16_t)(LV_PARAM_FIRST + LINK_PARAM_R_OHM);
    const float r0 = params.motor.R_Ohm;
    assert_string_equal(link_var(r_id)->name, "R_ohm");
    app.state = APP_STATE_RUN;
    assert_int_equal(write_f(r_id, 2.5f, seq_next()), 1);
    assert_int_equal(rep.payload[0], LINK_ST_ACCESS);
    assert_true(params.motor.R_Ohm == r0);
    assert_int_equal(applied_k, -1);
    app.state = APP_STATE_IDLE;
    assert_int_equal(write_f(r_id, 2.5f, seq_next()), 1);
    assert_int_equal(rep.payload[0], LINK_ST_OK);
    assert_true(params.motor.R_Ohm == 2.5f);
    assert_int_equal(applied_k, LINK_PARAM_R_OHM);
    assert_true(read_f(r_id) == 2.5f);
    assert_int_equal(write_f(r_id, 2.0f * LINK_PARAM_R_OHM_HI, seq_next()), 1);
    assert_int_equal(rep.payload[0], LINK_ST_REFUSED);
    assert_int_equal(link_get_u16(rep.payload, 1u), CMD_ERR_RANGE);
    assert_true(params.motor.R_Ohm == 2.5f);
    uint16_t p[6];
    (void)link_put_u16(p, 0u, (uint16_t)(LV_PARAM_FIRST + LINK_PARAM_POLE_PAIRS));
    (void)link_put_u32(p, 2u, 4u);
    assert_int_equal(request(LINK_WRITE, seq_next(), p, 6u), 1);
    assert_int_equal(rep.payload[0], LINK_ST_OK);
    assert_int_equal(params.motor.pole_pairs, 4);
    (void)link_put_u32(p, 2u, 0u);                                   /* below 1 */
    assert_int_equal(request(LINK_WRITE, seq_next(), p, 6u), 1);
    assert_int_equal(link_get_u16(rep.payload, 1u), CMD_ERR_RANGE);
    assert_int_equal(params.motor.pole_pairs, 4);
}

static void parameters_need_a_parameter_set(void **state)
{
    (void)state;
    app.state = APP_STATE_IDLE;
    assert_int_equal(write_f((uint16_t)(LV_PARAM_FIRST + LINK_PARAM_R_OHM), 2.5f, seq_next()), 1);
    assert_int_equal(rep.payload[0], LINK_ST_ACCESS);
}

static link_nv_t store;

static int setup_store(void **state)
{
    (void)setup_params(state);
    nv_ram_erase();
    link_nv_init(&store, &NV_RAM_DEV);
    lk.cfg.params.store = &store;   /* link_init's copy: what the table reads */
    return 0;
}

/* ACTION save: refused with CMD_ERR_NOT_STOPPED while the drive runs (nothing asked, nv_status
 * as it was); while stopped (IDLE, FAULT) taken: the store asked, nv_status SAVING, the command
 * block untouched; the glue's save then shows SAVED. Without a store: an unknown action, and
 * nv_status NONE. */
static void action_save_asks_the_store_only_when_stopped(void **state)
{
    (void)state;
    uint16_t a = LINK_ACTION_SAVE;
    assert_int_equal(read_u16(LV_NV_STATUS), LINK_NV_EMPTY);
    app.state = APP_STATE_RUN;
    assert_int_equal(request(LINK_ACTION, seq_next(), &a, 1u), 1);
    assert_int_equal(rep.payload[0], LINK_ST_REFUSED);
    assert_int_equal(link_get_u16(rep.payload, 1u), CMD_ERR_NOT_STOPPED);
    assert_false(link_nv_due(&store));
    assert_int_equal(read_u16(LV_NV_STATUS), LINK_NV_EMPTY);
    app.state = APP_STATE_FAULT;
    assert_int_equal(request(LINK_ACTION, seq_next(), &a, 1u), 1);
    assert_int_equal(rep.payload[0], LINK_ST_OK);
    assert_true(link_nv_due(&store));
    assert_int_equal(read_u16(LV_NV_STATUS), LINK_NV_SAVING);
    assert_int_equal(app.req_start + app.req_stop + app.req_fault_reset, 0);
    assert_int_equal(link_nv_save(&store, &params, app_stopped(&app)), NV_OK);
    assert_int_equal(read_u16(LV_NV_STATUS), LINK_NV_SAVED);
    lk.cfg.params.store = NULL;
    assert_int_equal(request(LINK_ACTION, seq_next(), &a, 1u), 1);
    assert_int_equal(rep.payload[0], LINK_ST_BAD_REQUEST);
    assert_int_equal(read_u16(LV_NV_STATUS), LINK_NV_NONE);
}

/* ACTION LEVEL n: the next start's build level through cmd_apply, refused outside 1..5. */
static void action_level_sets_the_next_start_level(void **state)
{
    (void)state;
    const uint16_t before = app.req_level;
    assert_int_equal(before, LEVEL_PWM);               /* the board's default: level 1 first */
    uint16_t p[2] = { LINK_ACTION_LEVEL, 2u };
    const uint32_t w0 = lk.stats.writes;
    assert_int_equal(request(LINK_ACTION, seq_next(), p, 2u), 1);
    assert_int_equal(rep.payload[0], LINK_ST_OK);
    assert_int_equal(link_get_u16(rep.payload, 1u), CMD_OK);
    assert_int_equal(app.req_level, 2);
    assert_int_equal(cmd.level, 2);
    assert_int_equal(lk.stats.writes, w0 + 1u);
    assert_int_equal(link_var_get(&lk.t, LV_LEVEL_NEXT).u, 2);
    assert_int_equal(link_var_get(&lk.t, LV_LEVEL).u, app.level);
    /* 0 and 6 are not levels: refused with CMD_ERR_LEVEL, nothing changed */
    for (uint16_t bad = 0u; bad <= 6u; bad = (uint16_t)(bad + 6u)) {
        p[1] = bad;
        assert_int_equal(request(LINK_ACTION, seq_next(), p, 2u), 1);
        assert_int_equal(rep.payload[0], LINK_ST_REFUSED);
        assert_int_equal(link_get_u16(rep.payload, 1u), CMD_ERR_LEVEL);
        assert_int_equal(app.req_level, 2);
    }
    assert_int_equal(lk.stats.writes, w0 + 1u);
    /* without its argument: a bad request */
    assert_int_equal(request(LINK_ACTION, seq_next(), p, 1u), 1);
    assert_int_equal(rep.payload[0], LINK_ST_BAD_REQUEST);
}

static void stream_is_refused_above_the_budget_naming_it(void **state)
{
    (void)state;
    /* budget: 115200 / 10 x 0.8 = 9216 B/s. Four values every period: (6 + 4 + 16) B x 10 kHz = 260000 B/s */
    uint16_t p[10];
    uint16_t i = link_put_u16(p, 0u, 1u);
    for (uint16_t k = 0; k < 4u; k++) {
        i = link_put_u16(p, i, LV_IQ_MEAS_A);
    }
    assert_int_equal(request(LINK_STREAM_SET, seq_next(), p, i), 1);
    assert_int_equal(rep.payload[0], LINK_ST_REFUSED);
    assert_int_equal(link_get_u32(rep.payload, 1u), 260000u);
    assert_int_equal(link_get_u32(rep.payload, 5u), 9216u);
    assert_int_equal(lk.stream.n, 0);
    /* every 50 periods: 26 B x 200 /s = 5200 B/s, taken; rows reach the host as STREAM frames */
    (void)link_put_u16(p, 0u, 50u);
    assert_int_equal(request(LINK_STREAM_SET, seq_next(), p, i), 1);
    assert_int_equal(rep.payload[0], LINK_ST_OK);
    assert_int_equal(link_get_u32(rep.payload, 1u), 5200u);
    probe_monitor_rw(&app)->iq_A = 0.5f;
    for (int k = 0; k < 100; k++) {
        app.ticks++;
        link_isr(&lk);
        link_poll(&lk);
    }
    assert_int_equal(drain(LINK_STREAM), 2);                          /* periods 0 and 50 */
    assert_int_equal(link_get_u32(rep.payload, 0u), 50u);
    assert_true(link_get_f32(rep.payload, 4u) == 0.5f);
}

/* The streamed values are READ's at the row's period: a stream of three floats in place (the
 * ISR's copy of every slot, five unused) and a mixed one (a float in its unit, the period count
 * and the state by id, a float in place). Every 25 periods (the first row's three floats:
 * (6 + 4 + 12) B x 400 /s = 8800 B/s, within 9216); each row checked against the values set
 * by hand for its period. */
static void stream_rows_carry_the_values_read_gives(void **state)
{
    (void)state;
    static const uint16_t sets[2][4] = { { LV_TE_EST_NM, LV_IQ_MEAS_A, LV_ID_MEAS_A, 0u },
                                         { LV_SPEED_EST_RPM, LV_TICKS, LV_IQ_MEAS_A, LV_STATE } };
    static const uint16_t n_of[2] = { 3u, 4u };
    static const uint16_t dec_of[2] = { 25u, 50u };   /* the mixed row: 20 B x 200 /s */
    for (int set = 0; set < 2; set++) {
        uint16_t p[10];
        uint16_t i = link_put_u16(p, 0u, dec_of[set]);
        for (uint16_t k = 0; k < n_of[set]; k++) {
            i = link_put_u16(p, i, sets[set][k]);
        }
        assert_int_equal(request(LINK_STREAM_SET, seq_next(), p, i), 1);
        assert_int_equal(rep.payload[0], LINK_ST_OK);
        assert_int_equal(lk.stream.in_place, set == 0);
        int rows = 0;
        for (int k = 0; k < 200; k++) {
            static link_frame_t f;
            uint16_t b;
            ctrl_mon_t *m = probe_monitor_rw(&app);
            app.ticks++;
            m->te_est_Nm = 0.5f * (float)k;
            m->iq_A = -0.25f * (float)k;
            m->id_A = 0.125f + (float)k;
            m->speed_mech_rad_s = 3.0f * (float)k;
            app.state = (k % 2 == 0) ? APP_STATE_IDLE : APP_STATE_RUN;
            link_isr(&lk);
            link_poll(&lk);
            while (link_tx_get(&lk, &b)) {
                if (!link_rx_byte(&host_rx, b, &f) || f.type != LINK_STREAM) {
                    continue;
                }
                assert_int_equal(k % dec_of[set], 0);        /* sent in the period sampled */
                assert_int_equal(link_get_u32(f.payload, 0u), app.ticks - 1u);
                if (set == 0) {
                    assert_int_equal(f.len, 16);
                    assert_true(link_get_f32(f.payload, 4u) == 0.5f * (float)k);
                    assert_true(link_get_f32(f.payload, 8u) == -0.25f * (float)k);
                    assert_true(link_get_f32(f.payload, 12u) == 0.125f + (float)k);
                } else {
                    assert_int_equal(f.len, 18);
                    assert_true(link_get_f32(f.payload, 4u) == 3.0f * (float)k / MATHX_RAD_S_PER_RPM_F);
                    assert_int_equal(link_get_u32(f.payload, 8u), app.ticks);
                    assert_true(link_get_f32(f.payload, 12u) == -0.25f * (float)k);
                    assert_int_equal(link_get_u16(f.payload, 16u), (k % 2 == 0) ? APP_STATE_IDLE : APP_STATE_RUN);
                }
                rows++;
            }
        }
        assert_int_equal(rows, 200 / dec_of[set]);
    }
}

static void arm(uint16_t trig, float level, float hyst, uint16_t pre, uint16_t samples, uint16_t dec)
{
    uint16_t p[22];
    uint16_t i = link_put_u16(p, 0u, dec);
    i = link_put_u16(p, i, pre);
    i = link_put_u16(p, i, samples);
    p[i++] = trig;
    i = link_put_u16(p, i, LV_SPEED_EST_RPM);
    i = link_put_f32(p, i, level);
    i = link_put_f32(p, i, hyst);
    p[i++] = 2u;
    i = link_put_u16(p, i, LV_IQ_MEAS_A);
    i = link_put_u16(p, i, LV_SPEED_EST_RPM);
    assert_int_equal(request(LINK_CAPTURE_ARM, seq_next(), p, i), 1);
    assert_int_equal(rep.payload[0], LINK_ST_OK);
}

/* One ISR period with the given speed [r/min] and iq [A]. */
static void period(float speed_rpm, float iq_A)
{
    ctrl_mon_t *m = probe_monitor_rw(&app);
    app.ticks++;
    m->speed_mech_rad_s = speed_rpm * MATHX_RAD_S_PER_RPM_F;
    m->iq_A = iq_A;
    link_isr(&lk);
}

static void capture_triggers_above_with_pre_rows_and_period_indices(void **state)
{
    (void)state;
    /* speed k r/min at period k from 300 down: above 250 at first (no arming), then at or below,
     * then rising: the trigger is the first period above 250 after one at or below */
    arm(LINK_TRIG_ABOVE, 250.0f, 0.0f, 3u, 8u, 1u);
    uint16_t cs[4] = { 0u, 8u, 0u, 0u };
    assert_int_equal(request(LINK_CAPTURE_READ, seq_next(), cs, 0u), 1);
    assert_int_equal(rep.payload[0], LINK_ST_BAD_REQUEST);
    (void)link_put_u16(cs, 0u, 0u);
    (void)link_put_u16(cs, 2u, 8u);
    const float speed[] = { 300, 260, 240, 250, 251, 252, 200, 255, 256, 257, 258, 259, 260, 261, 262, 263 };
    for (int k = 0; k < 16; k++) {
        period(speed[k], (float)k * 0.1f);
    }
    /* periods 0..15 (ticks 1..16). Rows from period 0; 300, 260: not armed; 240: armed; 251 at
     * period 4 is above after one at or below with 4 rows in (> pre = 3): trigger at period 4.
     * Rows: periods 1..8 (3 before, the trigger, 4 after) */
    assert_int_equal(request(LINK_CAPTURE_STATUS, seq_next(), NULL, 0u), 1);
    assert_int_equal(rep.payload[1], LINK_CAP_DONE);
    assert_int_equal(link_get_u32(rep.payload, 8u), 4u);     /* trigger period */
    assert_int_equal(link_get_u32(rep.payload, 12u), 1u);    /* first row's period */
    const float lsb_n = link_get_f32(rep.payload, 17u + 8u);  /* speed: 2400 r/min / 32767 */
    assert_float_equal(lsb_n, 2400.0f / 32767.0f, 1e-6);
    assert_int_equal(request(LINK_CAPTURE_READ, seq_next(), cs, 4u), 1);
    assert_int_equal(link_get_u16(rep.payload, 3u), 8);
    for (uint16_t r = 0; r < 8u; r++) {
        const int16_t n = (int16_t)link_get_u16(rep.payload, (uint16_t)(5u + 4u * r + 2u));
        assert_float_equal((float)n * lsb_n, speed[r + 1u], lsb_n);
    }
}

static void capture_hysteresis_rearms_only(void **state)
{
    (void)state;
    /* level 250, hyst 20: armed only by a sample at or below 230; it then fires at the first above 250 */
    arm(LINK_TRIG_ABOVE, 250.0f, 20.0f, 0u, 2u, 1u);
    const float speed[] = { 240, 260, 240, 229, 251, 249, 252 };
    for (int k = 0; k < 7; k++) {
        period(speed[k], 0.0f);
    }
    assert_int_equal(request(LINK_CAPTURE_STATUS, seq_next(), NULL, 0u), 1);
    assert_int_equal(rep.payload[1], LINK_CAP_DONE);
    assert_int_equal(link_get_u32(rep.payload, 8u), 4u);     /* 251 at period 4, right after 229 */
    /* decimation: rows every 3 periods; a forced trigger with 2 pre rows */
    arm(LINK_TRIG_FORCED, 0.0f, 0.0f, 2u, 4u, 3u);
    for (int k = 0; k < 30; k++) {
        period(0.0f, 0.0f);
    }
    assert_int_equal(request(LINK_CAPTURE_STATUS, seq_next(), NULL, 0u), 1);
    assert_int_equal(rep.payload[1], LINK_CAP_DONE);
    /* periods 7.. sampled at 7, 10, 13 (3 rows > pre 2: forced at 13); rows 7, 10, 13, 16 */
    assert_int_equal(link_get_u32(rep.payload, 8u), 13u);
    assert_int_equal(link_get_u32(rep.payload, 12u), 7u);
}

/* The int16 counts' rounding and saturation: speed_est_rpm in counts of 2400 / 32767 r/min
 * (0.3 -> 0, 0.7 -> 1, -0.3 -> 0, -0.7 -> -1, 32766.4 -> 32766), beyond +-32767 counts and
 * infinite the end of its side, NaN -32767; rows of a forced capture (no pre rows). */
static void capture_counts_round_and_saturate(void **state)
{
    (void)state;
    const float lsb_rpm = 2400.0f / 32767.0f;
    const float counts[] = { 0.3f, 0.7f, -0.3f, -0.7f, 32766.4f, 32767.6f, 1.0e6f, -1.0e6f };
    const int16_t want[] = { 0, 1, 0, -1, 32766, 32767, 32767, -32767, -32767, 32767, -32767 };
    const uint16_t rows = (uint16_t)(sizeof want / sizeof want[0]);
    arm(LINK_TRIG_FORCED, 0.0f, 0.0f, 0u, rows, 1u);
    for (uint16_t r = 0; r < 8u; r++) {
        period(counts[r] * lsb_rpm, 0.0f);
    }
    period(NAN, 0.0f);
    period(INFINITY, 0.0f);
    period(-INFINITY, 0.0f);
    assert_int_equal(lk.cap.state, LINK_CAP_DONE);
    uint16_t cs[4];
    (void)link_put_u16(cs, 0u, 0u);
    (void)link_put_u16(cs, 2u, rows);
    assert_int_equal(request(LINK_CAPTURE_READ, seq_next(), cs, 4u), 1);
    assert_int_equal(link_get_u16(rep.payload, 3u), rows);
    for (uint16_t r = 0; r < rows; r++) {
        assert_int_equal((int16_t)link_get_u16(rep.payload, (uint16_t)(5u + 4u * r + 2u)), want[r]);
    }
}

static void capture_arm_refuses_bad_arguments(void **state)
{
    (void)state;
    uint16_t p[20];
    memset(p, 0, sizeof p);
    (void)link_put_u16(p, 0u, 1u);
    (void)link_put_u16(p, 2u, 10u);     /* pre 10 */
    (void)link_put_u16(p, 4u, 10u);     /* samples 10: pre must be below */
    p[17] = 1u;
    assert_int_equal(request(LINK_CAPTURE_ARM, seq_next(), p, 20u), 1);
    assert_int_equal(rep.payload[0], LINK_ST_BAD_REQUEST);
    (void)link_put_u16(p, 4u, 2000u);   /* beyond 1024 rows */
    assert_int_equal(request(LINK_CAPTURE_ARM, seq_next(), p, 20u), 1);
    assert_int_equal(rep.payload[0], LINK_ST_BAD_REQUEST);
    assert_int_equal(lk.cap.state, LINK_CAP_IDLE);
}

/* ---- lossy link ------------------------------------------------------------- */

static uint32_t rng = 12345u;
static uint32_t rnd(uint32_t n)
{
    rng = rng * 1103515245u + 12345u;
    return (rng >> 8) % n;
}

/* Bytes through a channel spoiling 10 %: dropped, flipped, duplicated, or garbage before them. */
static uint16_t spoil(const uint16_t *in, uint16_t n, uint16_t *out)
{
    uint16_t m = 0;
    for (uint16_t i = 0; i < n; i++) {
        if (rnd(10u) != 0u) {
            out[m++] = in[i];
            continue;
        }
        switch (rnd(4u)) {
        case 0: break;
        case 1: out[m++] = (uint16_t)(in[i] ^ (1u << rnd(8u))); break;
        case 2: out[m++] = in[i]; out[m++] = in[i]; break;
        default: out[m++] = (uint16_t)rnd(256u); out[m++] = in[i]; break;
        }
    }
    return m;
}

static void lossy_link_applies_every_write_once(void **state)
{
    (void)state;
    enum { WRITES = 100, TRIES = 200 };   /* a 12-byte frame passes a 10 % per-byte spoiling 28 % of the time */
    int done = 0;
    int tries_total = 0;
    const uint32_t w0 = lk.stats.writes;
    for (int k = 0; k < WRITES; k++) {
        const float v = (float)(k % 10);
        static link_frame_t f;
        uint16_t w[LINK_ENCODED_MAX];
        uint16_t s[2 * LINK_ENCODED_MAX + 8];
        f.type = LINK_WRITE;
        f.seq = seq_next();
        f.len = link_put_f32(f.payload, link_put_u16(f.payload, 0u, LV_TE_CMD_NM), v);
        const uint16_t n = link_frame_encode(&f, w);
        bool ok = false;
        for (int t = 0; t < TRIES && !ok; t++) {
            tries_total++;
            const uint32_t before = lk.stats.writes;
            const uint16_t m = spoil(w, n, s);
            for (uint16_t i = 0; i < m; i++) {
                (void)link_rx_put(&lk, s[i]);
            }
            for (int p = 0; p < 8; p++) {
                link_poll(&lk);
            }
            /* applied at most once over all tries */
            assert_true(lk.stats.writes - before <= 1u);
            uint16_t b;
            uint16_t out[2 * LINK_ENCODED_MAX + 8];
            uint16_t r = 0;
            while (link_tx_get(&lk, &b) && r < LINK_ENCODED_MAX) {
                out[r++] = b;
            }
            uint16_t back[2 * LINK_ENCODED_MAX + 8];
            const uint16_t q = spoil(out, r, back);
            static link_frame_t g;
            for (uint16_t i = 0; i < q; i++) {
                if (link_rx_byte(&host_rx, back[i], &g) && g.type == (LINK_WRITE | LINK_REPLY) && g.seq == f.seq) {
                    assert_int_equal(g.payload[0], LINK_ST_OK);
                    ok = true;
                }
            }
            /* a lost delimiter leaves a partial block behind: the host starts each try clean */
            (void)link_rx_byte(&host_rx, 0u, &g);
            (void)link_rx_put(&lk, 0u);
        }
        assert_true(ok);
        done++;
        assert_int_equal(lk.stats.writes - w0, (uint32_t)done);    /* exactly once */
        assert_true(app.op_req.ref.te_ref_Nm == v);
    }
    /* the spoiling reached both sides and cost retries */
    assert_true(tries_total > WRITES);
    assert_true(lk.stats.err_crc + lk.stats.err_framing > 0u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(hello_names_version_table_and_period, setup),
        cmocka_unit_test_setup(list_vars_pages_through_the_table_with_csv_names, setup),
        cmocka_unit_test_setup(read_returns_values_in_their_types, setup),
        cmocka_unit_test_setup(write_goes_through_cmd_apply, setup),
        cmocka_unit_test_setup(a_repeated_request_is_answered_from_the_cache, setup),
        cmocka_unit_test_setup(actions_start_stop_reset, setup),
        cmocka_unit_test_setup(action_level_sets_the_next_start_level, setup),
        cmocka_unit_test_setup(actions_refused_naming_the_state, setup),
        cmocka_unit_test_setup(host_timeout_ramps_to_zero_and_stops, setup),
        cmocka_unit_test_setup(parameters_written_stopped_within_their_range, setup_params),
        cmocka_unit_test_setup(parameters_need_a_parameter_set, setup),
        cmocka_unit_test_setup(action_save_asks_the_store_only_when_stopped, setup_store),
        cmocka_unit_test_setup(stream_is_refused_above_the_budget_naming_it, setup),
        cmocka_unit_test_setup(stream_rows_carry_the_values_read_gives, setup),
        cmocka_unit_test_setup(capture_triggers_above_with_pre_rows_and_period_indices, setup),
        cmocka_unit_test_setup(capture_hysteresis_rearms_only, setup),
        cmocka_unit_test_setup(capture_counts_round_and_saturate, setup),
        cmocka_unit_test_setup(capture_arm_refuses_bad_arguments, setup),
        cmocka_unit_test_setup(lossy_link_applies_every_write_once, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
