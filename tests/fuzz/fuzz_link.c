/*
 * fuzz_link.c - libFuzzer harness for the link's parser and dispatcher
 * (firmware/link/link.h): arbitrary bytes and well-framed requests of any type
 * and payload into link_rx_put()/link_poll(), control periods (link_isr)
 * with the drive's state and monitor from the input. Aborts on:
 *   - bytes the link sent that do not decode as frames (its output must
 *     always parse, with no CRC or framing error);
 *   - the operator's request (app_t.op_req) changed with no WRITE or
 *     ACTION executed (a write that bypassed cmd_apply()), or holding a
 *     value cmd_apply() would refuse (beyond the limits, not finite, a mode
 *     or method out of range);
 *   - a capture state out of range.
 * ASan and UBSan catch the rest. `make fuzz-link` runs >= 10^7 frames,
 * `make test` a short seeded pass (tests/module.mk, tests/fuzz/fuzz_link.sh).
 *
 * Input: records, each starting with a kind byte r[0]:
 *   r[0] < 0xC0   a request framed by the harness (valid CRC): type r[1]
 *                 (its low 4 bits unless bit 7 is set), seq r[2], payload
 *                 length r[3] (capped at what is left and at 240), then
 *                 the payload
 *   0xC0..0xEF    r[1] raw bytes that follow, unframed (the parser alone)
 *   0xF0..0xFF    (r[1] & 63) + 1 control periods with state r[2] % 7 and
 *                 speed and iq from r[3..4] and r[5..6] (int16 / 8)
 */
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app.h"
#include "../app_probe.h"
#include "cmd.h"
#include "fuzz_hal.h"
#include "link.h"
#include "mathx.h"

enum { KIND_RAW = 0xC0, KIND_PERIODS = 0xF0 };
#define PERIODS_MASK 63u
#define VALUE_SCALE 0.125f
#define N_STATES 7u
#define TYPE_LOW_MASK 0x0Fu
#define TYPE_RAW_BIT 0x80u

static uint64_t g_frames;
static uint64_t g_inputs;
static uint64_t g_replies;

static app_t g_app;
static comm_t g_comm_state;  /* the commissioning's state: the link's commission action acts */
static volatile cmd_t g_cmd;
static link_t g_link;
static link_rx_t g_host;
static const cmd_limits_t LIM = { 2000.0f, 12.0f, 300.0f };

static void fail(const char *what)
{
    fprintf(stderr, "fuzz_link: %s\n", what);
    abort();
}

static bool op_equal(const volatile app_op_t *a, const app_op_t *b)
{
    return a->mode == b->mode && a->method == b->method &&
           memcmp((const void *)&a->ref, &b->ref, sizeof b->ref) == 0;
}

static void check_op(void)
{
    const volatile app_op_t *o = &g_app.op_req;
    const float spd = o->ref.speed_ref_rad_s / MATHX_RAD_S_PER_RPM_F;
    if (!(fabsf(spd) <= LIM.speed_max_rpm * 1.0001f) || !(fabsf(o->ref.te_ref_Nm) <= LIM.te_max_Nm) ||
        !(fabsf(o->ref.ud_ref_V) <= LIM.u_max_V) || !(fabsf(o->ref.uq_ref_V) <= LIM.u_max_V) ||
        (unsigned)o->mode > (unsigned)CTRL_MODE_SPEED || (unsigned)o->method > (unsigned)CTRL_METHOD_PROPOSED) {
        fail("the operator's request holds a value cmd_apply() refuses");
    }
}

/* Poll until the received bytes are handled; every byte sent must decode. */
static void service(void)
{
    const uint32_t writes = g_link.stats.writes;
    app_op_t before;
    before.ref = g_app.op_req.ref;
    before.mode = g_app.op_req.mode;
    before.method = g_app.op_req.method;
    for (int k = 0; k < 8; k++) {
        link_poll(&g_link);
        uint16_t b;
        static link_frame_t f;
        while (link_tx_get(&g_link, &b)) {
            if (link_rx_byte(&g_host, b, &f)) {
                g_replies++;
            }
        }
        if (g_host.err_crc != 0u || g_host.err_framing != 0u) {
            fail("the link sent bytes that do not decode as a frame");
        }
    }
    if (g_link.stats.writes == writes && !op_equal(&g_app.op_req, &before)) {
        fail("the operator's request changed with no WRITE or ACTION executed");
    }
    check_op();
    if (g_link.cap.state > LINK_CAP_DONE) {
        fail("capture state out of range");
    }
}

static void put(const uint16_t *b, uint16_t n)
{
    for (uint16_t i = 0; i < n; i++) {
        if (!link_rx_put(&g_link, b[i])) {
            service();
            (void)link_rx_put(&g_link, b[i]);
        }
    }
}

static void setup(void)
{
    static bool done;
    static app_cfg_t cfg;
    if (!done) {
        fuzz_hal_reset();
        app_cfg_default(&cfg);
        done = true;
    }
    const link_cfg_t lc = { cfg.ctrl.Ts_s, 115200u, "fuzz", 0.0f, { NULL, NULL, NULL, NULL } };
    fuzz_hal_reset();
    app_init(&g_app, &cfg);
    app_attach_comm(&g_app, &g_comm_state);
    cmd_init(&g_cmd);
    link_init(&g_link, &lc, &g_app, &g_cmd, &LIM);
    link_rx_init(&g_host);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static link_frame_t f;
    static uint16_t wire[LINK_ENCODED_MAX];
    setup();
    g_inputs++;
    size_t i = 0;
    while (i + 4u <= size) {
        const uint8_t *r = data + i;
        if (r[0] < KIND_RAW) {
            f.type = (r[1] & TYPE_RAW_BIT) ? r[1] : (uint16_t)(r[1] & TYPE_LOW_MASK);
            f.seq = r[2];
            size_t len = r[3];
            len = (len > size - i - 4u) ? size - i - 4u : len;
            len = (len > LINK_PAYLOAD_MAX) ? LINK_PAYLOAD_MAX : len;
            f.len = (uint16_t)len;
            for (size_t k = 0; k < len; k++) {
                f.payload[k] = r[4 + k];
            }
            put(wire, link_frame_encode(&f, wire));
            g_frames++;
            i += 4u + len;
        } else if (r[0] < KIND_PERIODS) {
            size_t n = r[1];
            n = (n > size - i - 2u) ? size - i - 2u : n;
            for (size_t k = 0; k < n; k++) {
                const uint16_t b = r[2 + k];
                put(&b, 1u);
            }
            i += 2u + n;
        } else {
            const uint16_t periods = (uint16_t)((r[1] & PERIODS_MASK) + 1u);
            g_app.state = (app_state_t)(r[2] % N_STATES);
            g_app.fault = (g_app.state == APP_STATE_FAULT) ? APP_FAULT_OVERCURRENT : APP_FAULT_NONE;
            if (i + 7u <= size) {
                ctrl_mon_t *m = probe_monitor_rw(&g_app);
                m->speed_mech_rad_s = (float)(int16_t)(r[3] | (r[4] << 8)) * VALUE_SCALE;
                m->iq_A = (float)(int16_t)(r[5] | (r[6] << 8)) * VALUE_SCALE;
            }
            for (uint16_t k = 0; k < periods; k++) {
                g_app.ticks++;
                link_isr(&g_link);
                if ((k & 7u) == 0u) {
                    service();
                }
            }
            i += 7u;
        }
        service();
    }
    return 0;
}

__attribute__((destructor)) static void report(void)
{
    printf("fuzz_link: %llu frames, %llu inputs, %llu replies\n", (unsigned long long)g_frames,
           (unsigned long long)g_inputs, (unsigned long long)g_replies);
}
