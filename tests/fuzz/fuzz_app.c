/*
 * fuzz_app.c - libFuzzer harness for the control ISR: app_isr() on the
 * fuzz HAL stub (fuzz_hal.h) through arbitrary sample sequences and
 * operator commands (cmd_apply, the path the operator's block takes).
 * The stub aborts on a broken output rule, the harness on a state out of
 * app_state_t or a fault code that disagrees with FAULT; ASan and UBSan
 * (float casts included) catch the rest. `make fuzz` runs it for >= 10^8 ISR steps,
 * `make test` a short seeded pass (tests/module.mk, tests/fuzz/fuzz.sh).
 *
 * Input: an 8-byte header, then 16-byte records (a short tail is dropped).
 *   header[0]  bit 0 calibrate, bit 1 align, bits 2-3 app_rsid_mode_t,
 *              bit 4 proposed method, bits 5-6 ctrl_mode_t (3: speed),
 *              bit 7 start at power-on (cmd.run = 1 before the first record)
 *   header[2]  bit 0: a persistent operator, through cmd_apply: after
 *              every ISR that ends in FAULT fault_reset = 1, after every
 *              one that ends in IDLE run 0 then 1
 *   header[1]  start-up times in periods (1 .. 256): calibration settle and
 *              samples, alignment ramps and holds, step 1 settles and windows,
 *              so that a short input gets through the sequence
 *   record[0]  the kind: KIND_RAW (and above) periods with raw float
 *              samples (NaN, Inf, denormal, huge), KIND_SPECIAL periods
 *              with samples from a table of special values, KIND_COMMAND an
 *              operator command, below those periods with plausible
 *              samples (|i| < 14 A, bus 247 .. 375 V, count steps below the
 *              jump limit): most records run, the pathological ones are rarer
 *   periods:   record[1] & 63: repeats - 1; the same currents and bus, the
 *              count moving by the record's step each period; record[12]
 *              entry jitter; record[15] an event (rare, so that most
 *              records run): EV_TRIP the trip input, EV_MISSED a missed
 *              period before each, EV_LONG_ISR an ISR over its budget,
 *              EV_COUNT_JUMP the count jumps to record[13..14] x 131
 *   command:   record[1] & 7 the cmd_t field (1: fault_reset bit 0 and
 *              commission bit 1 of the value), record[2..3] a uint16 value,
 *              bit 3 of record[1]: record[4..7] a float's bits, else
 *              record[2..3] scaled
 */
#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "app.h"
#include "cmd.h"
#include "fuzz_hal.h"

#define HEADER_BYTES 8u
#define RECORD_BYTES 16u
#define PERIOD_CYCLES 15000u
#define REPEAT_MASK 63u
#define JITTER_CYCLES_PER_LSB 32
enum { KIND_PLAUSIBLE = 0x00, KIND_COMMAND = 0xC0, KIND_SPECIAL = 0xF0, KIND_RAW = 0xF8 };
enum { EV_TRIP = 0xF1, EV_MISSED = 0xF2, EV_LONG_ISR = 0xF3, EV_COUNT_JUMP = 0xF4 };
#define COUNT_JUMP_SCALE 131u        /* reaches beyond the 10000-count cpr */
#define RUN_SHORT_CYCLES 3000u       /* an ISR well inside the 12000-cycle budget */
#define RUN_LONG_CYCLES 13000u       /* one over it */
#define I_SCALE_A_PER_LSB (13.9f / 128.0f)   /* plausible: int8 -> |i| < 14 A */
#define VDC_MID_V 311.0f
#define VDC_SCALE_V_PER_LSB 0.5f             /* plausible: 311 V + int8 -> 247 .. 375 V */
#define STEP_DIV 4                           /* plausible count step: int8 / 4 -> |step| <= 32 < jump limit */
#define REF_SCALE_PER_LSB (1.0f / 8.0f)

#define N_STATES 11u   /* app_state_t's values, INIT .. COMMISSION */
static uint64_t g_isr_steps;
static uint64_t g_inputs;
static uint64_t g_state_steps[N_STATES]; /* ISR steps that ended in each app_state_t */
#define N_FAULTS 32u
static uint64_t g_faults[N_FAULTS];      /* faults latched, by app_fault_t */

static const float SPECIAL[16] = {
    0.0f, -0.0f, 1.0e-45f /* smallest denormal */, -1.0e-39f, FLT_MIN, 1.0f, -13.9f, 14.1f,
    311.0f, 399.9f, 1.0e30f, -FLT_MAX, FLT_MAX, INFINITY, -INFINITY, NAN,
};

static uint16_t u16_at(const uint8_t *p)
{
    return (uint16_t)((uint16_t)p[0] | ((uint16_t)p[1] << 8));
}

static float f32_at(const uint8_t *p)
{
    uint32_t u = (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) | ((uint32_t)p[3] << 24);
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

typedef struct {
    app_t app;
    volatile cmd_t cmd;
    volatile cmd_comm_t comm;   /* the commissioning's request and report */
    comm_t comm_state;          /* the commissioning's state (app_attach_comm) */
    cmd_limits_t lim;
    uint32_t base_cycles;
    uint32_t count;
    bool persistent;       /* header[2] bit 0 */
} harness_t;

static harness_t g_h;

static void configure(const uint8_t *h)
{
    app_cfg_t cfg;
    const float Ts = 1.0e-4f;
    const float t_s = (float)(h[1] + 1u) * Ts;

    app_cfg_default(&cfg);
    cfg.calibrate = (h[0] & 1u) != 0u;
    cfg.align = (h[0] & 2u) != 0u;
    cfg.rsid.mode = (app_rsid_mode_t)((h[0] >> 2) & 3u);
    cfg.cal.settle_s = t_s;
    cfg.cal.samples = h[1] + 1u;
    cfg.aln.ramp_s = t_s;
    cfg.aln.prepos_s = t_s;
    cfg.aln.settle_s = t_s;
    cfg.rsid.settle_1_s = t_s;
    cfg.rsid.window_s = t_s;
    cfg.rsid.settle_2_s = t_s;

    fuzz_hal_reset();
    app_init(&g_h.app, &cfg);
    app_attach_comm(&g_h.app, &g_h.comm_state);
    cmd_init(&g_h.cmd);
    cmd_comm_init(&g_h.comm);
    g_h.cmd.method = (uint16_t)((h[0] >> 4) & 1u);
    g_h.cmd.mode = (uint16_t)((((h[0] >> 5) & 3u) == 3u) ? 2u : ((h[0] >> 5) & 3u));
    g_h.cmd.run = (uint16_t)((h[0] >> 7) & 1u);
    g_h.lim.speed_max_rpm = 2000.0f;
    g_h.lim.te_max_Nm = cfg.ctrl.te_max_Nm;
    g_h.lim.u_max_V = cfg.ctrl.u_max_V;
    cmd_apply(&g_h.cmd, &g_h.lim, &g_h.app);
    g_h.base_cycles = 0u;
    g_h.count = 0u;
    g_h.persistent = (h[2] & 1u) != 0u;
}

/* The persistent operator: reset a fault; start again when stopped. */
static void operator_restart(void)
{
    if (g_h.app.state == APP_STATE_FAULT) {
        g_h.cmd.fault_reset = 1u;
        cmd_apply(&g_h.cmd, &g_h.lim, &g_h.app);
    } else if (g_h.app.state == APP_STATE_IDLE) {
        g_h.cmd.run = 0u;
        cmd_apply(&g_h.cmd, &g_h.lim, &g_h.app);
        g_h.cmd.run = 1u;
        cmd_apply(&g_h.cmd, &g_h.lim, &g_h.app);
    }
}

/* One ISR call with sample s, then the output rules the app itself owns. */
static void isr_step(const hal_sample_t *s, const uint8_t *r)
{
    fuzz_hal_period_t p;
    const uint32_t missed = (r[15] == EV_MISSED) ? 1u : 0u;
    const int32_t jitter = (int32_t)(int8_t)r[12] * JITTER_CYCLES_PER_LSB;
    app_fault_t fault_before;

    g_h.base_cycles += PERIOD_CYCLES * (1u + missed);
    p.sample = *s;
    p.trip = (r[15] == EV_TRIP);
    p.entry_cycles = g_h.base_cycles + (uint32_t)jitter;
    p.run_cycles = (r[15] == EV_LONG_ISR) ? RUN_LONG_CYCLES : RUN_SHORT_CYCLES;
    fuzz_hal_begin_isr(&p);
    fault_before = (g_h.app.state == APP_STATE_FAULT) ? g_h.app.fault : APP_FAULT_NONE;
    app_isr(&g_h.app);
    g_isr_steps++;
    if ((g_h.app.state == APP_STATE_FAULT) && (fault_before == APP_FAULT_NONE)) {
        g_faults[(uint32_t)g_h.app.fault % N_FAULTS]++;
    }
    if ((uint32_t)g_h.app.state >= N_STATES) {
        fuzz_hal_fail("state out of app_state_t");
    }
    g_state_steps[(uint32_t)g_h.app.state % N_STATES]++;
    if ((g_h.app.state == APP_STATE_FAULT) != (g_h.app.fault != APP_FAULT_NONE)) {
        fuzz_hal_fail("a fault code without FAULT, or FAULT without one");
    }
    if (fuzz_hal_end_isr()) {
        const app_state_t st = g_h.app.state;
        if ((st == APP_STATE_FAULT) || (st == APP_STATE_INIT) || (st == APP_STATE_IDLE) ||
            (st == APP_STATE_CALIBRATE)) {
            fuzz_hal_fail("outputs on in a state that keeps them off");
        }
    }
    app_background(&g_h.app);
    if (g_h.persistent) {
        operator_restart();
    }
}

static void periods(const uint8_t *r)
{
    const uint8_t kind = (r[0] >= KIND_RAW) ? KIND_RAW : ((r[0] >= KIND_SPECIAL) ? KIND_SPECIAL : KIND_PLAUSIBLE);
    const uint32_t n = (uint32_t)(r[1] & REPEAT_MASK) + 1u;
    int32_t step = (int32_t)(int8_t)r[11] / STEP_DIV;
    hal_sample_t s;

    if (kind == KIND_RAW) {
        s.ia_A = f32_at(&r[2]);
        s.ib_A = f32_at(&r[6]);
        s.vdc_V = f32_at(&r[8]); /* overlaps ib's upper half: both stay arbitrary */
        step = (int32_t)(int16_t)u16_at(&r[10]);
    } else if (kind == KIND_SPECIAL) {
        s.ia_A = SPECIAL[r[2] & 15u];
        s.ib_A = SPECIAL[r[2] >> 4];
        s.vdc_V = SPECIAL[r[3] & 15u];
    } else {
        s.ia_A = (float)(int8_t)r[2] * I_SCALE_A_PER_LSB;
        s.ib_A = (float)(int8_t)r[3] * I_SCALE_A_PER_LSB;
        s.vdc_V = VDC_MID_V + (float)(int8_t)r[4] * VDC_SCALE_V_PER_LSB;
    }
    if (r[15] == EV_COUNT_JUMP) {
        g_h.count = (uint32_t)u16_at(&r[13]) * COUNT_JUMP_SCALE; /* anywhere, beyond cpr too */
    }
    for (uint32_t k = 0u; k < n; k++) {
        g_h.count += (uint32_t)step;
        s.enc_count = g_h.count;
        isr_step(&s, r);
    }
}

static void command(const uint8_t *r)
{
    const uint16_t v = u16_at(&r[2]);
    const float f = ((r[1] & 8u) != 0u) ? f32_at(&r[4]) : (float)(int16_t)v * REF_SCALE_PER_LSB;

    switch (r[1] & 7u) {
    case 0: g_h.cmd.run = v & 1u; break;
    case 1: g_h.cmd.fault_reset = v & 1u; g_h.comm.start = (v >> 1) & 1u; break;
    case 2: g_h.cmd.method = v; break;
    case 3: g_h.cmd.mode = v; break;
    case 4: g_h.cmd.speed_ref_rpm = f; break;
    case 5: g_h.cmd.te_ref_Nm = f; break;
    case 6: g_h.cmd.ud_ref_V = f; break;
    default: g_h.cmd.uq_ref_V = f; break;
    }
    cmd_apply(&g_h.cmd, &g_h.lim, &g_h.app);
    cmd_comm_apply(&g_h.comm, &g_h.cmd, &g_h.app);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const uint8_t default_header[HEADER_BYTES] = { 0xC0u /* start, speed mode */, 0u, 0u, 0u, 0u, 0u, 0u, 0u };
    const uint8_t *h = (size >= HEADER_BYTES) ? data : default_header;
    size_t off = (size >= HEADER_BYTES) ? HEADER_BYTES : size;

    g_inputs++;
    configure(h);
    for (; off + RECORD_BYTES <= size; off += RECORD_BYTES) {
        const uint8_t *r = &data[off];
        if ((r[0] >= KIND_COMMAND) && (r[0] < KIND_SPECIAL)) {
            command(r);
        } else {
            periods(r);
        }
    }
    return 0;
}

/* At exit (libFuzzer's end of -runs): the figure tests/fuzz/fuzz.sh adds up. */
__attribute__((destructor)) static void report(void)
{
    printf("fuzz_app: %llu ISR steps, %llu inputs\n", (unsigned long long)g_isr_steps,
           (unsigned long long)g_inputs);
    printf("fuzz_app: steps ending in INIT IDLE CALIBRATE ALIGN IDENTIFY_R RUN FAULT PWM_CHECK ADC_CHECK ENC_CHECK "
           "COMMISSION:");
    for (uint32_t k = 0u; k < N_STATES; k++) {
        printf(" %llu", (unsigned long long)g_state_steps[k]);
    }
    printf("\nfuzz_app: faults latched (app_fault_t: count):");
    for (uint32_t k = 0u; k < N_FAULTS; k++) {
        if (g_faults[k] > 0u) {
            printf(" %u: %llu", k, (unsigned long long)g_faults[k]);
        }
    }
    printf("\n");
    fflush(stdout);
}
