/* fuzz_hal.c - hal.h for the ISR fuzz harness, with its output checks; see fuzz_hal.h. */
#include "fuzz_hal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define N_PHASES 3
#define DUTY_ZERO_VOLTAGE 0.5f

static struct {
    fuzz_hal_period_t now;
    bool in_isr;
    bool acked;
    uint32_t cycles_calls;     /* hal_cycles() calls in this ISR */
    bool pwm_on;
    bool trip_input;           /* level of the trip input in the current period */
    bool trip_latched;
    float duty[N_PHASES];      /* last written */
} g_hal;

void fuzz_hal_fail(const char *rule)
{
    fprintf(stderr, "fuzz_hal: rule broken: %s (duties %g %g %g, outputs %s)\n", rule, (double)g_hal.duty[0],
            (double)g_hal.duty[1], (double)g_hal.duty[2], g_hal.pwm_on ? "on" : "off");
    abort();
}

static bool duty_in_range(float d)
{
    return (d >= 0.0f) && (d <= 1.0f); /* false for NaN */
}

static void check_duties_if_on(void)
{
    if (g_hal.pwm_on) {
        for (int k = 0; k < N_PHASES; k++) {
            if (!duty_in_range(g_hal.duty[k])) {
                fuzz_hal_fail("duty outside [0, 1] while the outputs are on");
            }
        }
    }
}

void fuzz_hal_reset(void)
{
    g_hal.in_isr = false;
    g_hal.acked = false;
    g_hal.cycles_calls = 0u;
    g_hal.pwm_on = false;
    g_hal.trip_input = false;
    g_hal.trip_latched = false;
    for (int k = 0; k < N_PHASES; k++) {
        g_hal.duty[k] = DUTY_ZERO_VOLTAGE;
    }
}

void fuzz_hal_begin_isr(const fuzz_hal_period_t *p)
{
    g_hal.now = *p;
    g_hal.trip_input = p->trip;
    if (p->trip) {
        g_hal.trip_latched = true; /* the trip zone forces the outputs off at once */
        g_hal.pwm_on = false;
    }
    g_hal.in_isr = true;
    g_hal.acked = false;
    g_hal.cycles_calls = 0u;
}

bool fuzz_hal_end_isr(void)
{
    if (!g_hal.acked) {
        fuzz_hal_fail("ISR returned without hal_isr_ack()");
    }
    g_hal.in_isr = false;
    check_duties_if_on();
    return g_hal.pwm_on;
}

/* Any HAL call after the ack breaks "ack is the last HAL call". */
static void check_not_acked(void)
{
    if (g_hal.in_isr && g_hal.acked) {
        fuzz_hal_fail("HAL call after hal_isr_ack()");
    }
}

void hal_init(void)
{
    fuzz_hal_reset();
}

void hal_isr_attach(hal_isr_fn isr)
{
    (void)isr;
}

void hal_sample_read(hal_sample_t *out)
{
    check_not_acked();
    *out = g_hal.now.sample;
}

void hal_pwm_write(const float duty[3])
{
    check_not_acked();
    for (int k = 0; k < N_PHASES; k++) {
        if (!isfinite(duty[k])) {
            fuzz_hal_fail("non-finite duty written");
        }
        g_hal.duty[k] = duty[k];
    }
    check_duties_if_on();
}

void hal_pwm_enable(void)
{
    check_not_acked();
    if (g_hal.trip_latched) {
        fuzz_hal_fail("outputs enabled while the trip input is latched");
    }
    g_hal.pwm_on = true;
    check_duties_if_on();
}

void hal_pwm_disable(void)
{
    g_hal.pwm_on = false;
}

bool hal_trip_active(void)
{
    check_not_acked();
    return g_hal.trip_latched;
}

void hal_trip_clear(void)
{
    g_hal.trip_latched = g_hal.trip_input; /* an input still active latches again */
}

void hal_isr_ack(void)
{
    if (!g_hal.in_isr || g_hal.acked) {
        fuzz_hal_fail("hal_isr_ack() outside an ISR or twice");
    }
    g_hal.acked = true;
}

uint32_t hal_cycles(void)
{
    const uint32_t t = g_hal.now.entry_cycles + ((g_hal.cycles_calls > 0u) ? g_hal.now.run_cycles : 0u);
    g_hal.cycles_calls++;
    return t;
}

void hal_watchdog_kick(void)
{
}
