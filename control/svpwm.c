/*
 * svpwm.c - min-max zero-sequence SVPWM with hexagon limiting.
 *
 * Phase voltages come from the inverse Clarke transform; subtracting the
 * mid-point of the largest and smallest centres them in the DC bus, which
 * is the same switching pattern as classic sector-based SVPWM. The spread
 * max - min of the phase voltages is the line-to-line voltage the bus must
 * carry: the command is realisable exactly when spread <= Vdc, otherwise
 * all three are scaled by Vdc/spread, which keeps the angle and puts the
 * vector on the hexagon.
 */
#include "svpwm.h"

#include "mathx.h"

/* Centre of the duty range: zero output voltage. */
#define SVPWM_DUTY_MID 0.5f
/* Exact power-of-two prescale of the phase voltages, so that their spread
 * stays finite even for commands near FLT_MAX. */
#define SVPWM_PRESCALE 0.25f

static float max3f(float x, float y, float z)
{
    float m = (x > y) ? x : y;
    return (m > z) ? m : z;
}

static float min3f(float x, float y, float z)
{
    float m = (x < y) ? x : y;
    return (m < z) ? m : z;
}

uint16_t svpwm_duty(ab_t u_ab_V, float vdc_V, svpwm_duty_t *duty, ab_t *u_real_V)
{
    const float xa = SVPWM_PRESCALE * u_ab_V.a;
    const float sb = (SVPWM_PRESCALE * CLARKE_HALF_SQRT3) * u_ab_V.b;
    const float vdc_scaled = SVPWM_PRESCALE * vdc_V;

    /* One finiteness test for the three inputs: scaled, each term is at
     * most 0.25 FLT_MAX, so their sum cannot overflow and is finite
     * exactly when all three are. NaN fails the Vdc test too. */
    if (!mathx_isfinitef(xa + sb + vdc_scaled) || !(vdc_V >= SVPWM_VDC_MIN_V)) {
        duty->a = SVPWM_DUTY_MID;
        duty->b = SVPWM_DUTY_MID;
        duty->c = SVPWM_DUTY_MID;
        u_real_V->a = 0.0f;
        u_real_V->b = 0.0f;
        return SVPWM_INVALID_INPUT;
    }

    const float half_a = SVPWM_DUTY_MID * xa;
    const float xb = sb - half_a;
    const float xc = -sb - half_a;

    const float hi = max3f(xa, xb, xc);
    const float lo = min3f(xa, xb, xc);
    const float spread = hi - lo;

    uint16_t flags = SVPWM_OK;
    float duty_per_unit;
    if (spread <= vdc_scaled) {
        duty_per_unit = 1.0f / vdc_scaled;
    } else {
        /* Normalising by the spread makes max duty - min duty exactly 1. */
        duty_per_unit = 1.0f / spread;
        flags |= SVPWM_SATURATED;
    }

    /* Min-max zero sequence: the mid-point of hi and lo goes to duty 0.5. */
    const float mid = SVPWM_DUTY_MID * (hi + lo);
    duty->a = mathx_clampf(SVPWM_DUTY_MID + (xa - mid) * duty_per_unit, 0.0f, 1.0f);
    duty->b = mathx_clampf(SVPWM_DUTY_MID + (xb - mid) * duty_per_unit, 0.0f, 1.0f);
    duty->c = mathx_clampf(SVPWM_DUTY_MID + (xc - mid) * duty_per_unit, 0.0f, 1.0f);

    /* Realised voltage from the final duties (zero sequence drops out of
     * Clarke); in duty units first so that a huge Vdc cannot overflow. */
    const ab_t u_pu = clarke_3ph(duty->a, duty->b, duty->c);
    u_real_V->a = vdc_V * u_pu.a;
    u_real_V->b = vdc_V * u_pu.b;
    return flags;
}
