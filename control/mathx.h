/*
 * mathx.h - the one math shim of the control core.
 *
 * On the F28335 (TI cl2000, FPU32) these map to C2000Ware's FPU fast
 * run-time-support library (FPUfastRTS); on every other target to the
 * single-precision libm functions. Only float in, float out: no double
 * ever appears in the ISR path.
 */
#ifndef MATHX_H
#define MATHX_H

#include <math.h>
#include <stdbool.h>
#include <stdint.h>

#if defined(__TMS320C28XX__)
#include "C28x_FPU_FastRTS.h"
#endif

/* Square root; x < 0 returns 0 rather than NaN. Any context. */
static inline float mathx_sqrtf(float x)
{
    return (x > 0.0f) ? sqrtf(x) : 0.0f;
}

/* sin and cos of one angle [rad], for Park and inverse Park. Any context. */
static inline void mathx_sincosf(float angle_rad, float *sin_out, float *cos_out)
{
#if defined(__TMS320C28XX__)
    sincos(angle_rad, sin_out, cos_out);
#else
    *sin_out = sinf(angle_rad);
    *cos_out = cosf(angle_rad);
#endif
}

/* Four-quadrant arctangent [rad], in (-pi, pi]. Any context. */
static inline float mathx_atan2f(float y, float x)
{
    return atan2f(y, x);
}

/* Absolute value. Any context. gcc's builtin clears the sign bit in one
 * instruction (andps, vabs.f32) where the select compared and branched;
 * cl2000 keeps the select. */
static inline float mathx_fabsf(float x)
{
#if defined(__TMS320C28XX__)
    return (x < 0.0f) ? -x : x;
#else
    return fabsf(x);
#endif
}

/* IEEE-754 binary32: an exponent field of all ones is Inf or NaN. */
#define MATHX_F32_EXP_MASK 0x7F800000UL

/* Non-zero when x is neither NaN nor infinite. A test of the exponent bits,
 * inline on every target: the C library's isfinite macro may call a library
 * function (cl2000's RTS: in flash, out of the RAM-resident ISR path). Any
 * context. */
static inline bool mathx_isfinitef(float x)
{
    union {
        float f;
        uint32_t u;
    } bits;

    bits.f = x;
    return (bits.u & MATHX_F32_EXP_MASK) != MATHX_F32_EXP_MASK;
}

/* x mod m without a division instruction or library call: the C28x has no
 * integer divide and cl2000's 32-bit % calls an RTS helper that lives in
 * flash. x < m (a count already in range, the usual case) returns at once;
 * else 32 shift-and-subtract steps. m = 0 gives 0. Any context. */
static inline uint32_t mathx_umod_u32(uint32_t x, uint32_t m)
{
    uint32_t r = 0u;
    uint16_t k;

    if (x < m) {
        return x;
    }
    if (m == 0u) {
        return 0u;
    }
    for (k = 32u; k > 0u; k--) {
        const bool top = (r & 0x80000000UL) != 0u; /* r << 1 would leave 32 bits: then r > m */
        r = (r << 1) | ((x >> (k - 1u)) & 1u);
        if (top || (r >= m)) {
            r -= m;
        }
    }
    return r;
}

/* x limited to [lo, hi] (lo <= hi); NaN maps to lo. Any context.
 * Written as max then min, each a select on one comparison, so that a
 * compiler can use the FPU's max/min instructions (gcc: SSE maxss/minss,
 * whose unordered case takes the bound; the C28x FPU has MAXF32/MINF32)
 * instead of two compares and branches: the most frequent operation of
 * the ISR path (about 40 per ctrl_step). */
static inline float mathx_clampf(float x, float lo, float hi)
{
    const float above_lo = (x > lo) ? x : lo;
    return (above_lo < hi) ? above_lo : hi;
}

#define MATHX_PI_F        3.14159265358979f
#define MATHX_TWO_PI_F    6.28318530717959f
#define MATHX_SQRT3_F     1.73205080756888f
#define MATHX_INV_SQRT3_F 0.577350269189626f
#define MATHX_RAD_S_PER_RPM_F (MATHX_TWO_PI_F / 60.0f) /* r/min -> rad/s: the one conversion */

/* Beyond this |angle| [rad] a float has no useful fraction of a turn left
 * (spacing 0.06 rad); mathx_wrap_2pi() gives 0 there. */
#define MATHX_WRAP_MAX_RAD 1.0e6f

/* Angle [rad] wrapped into [0, 2*pi); NaN, Inf and |x| >= MATHX_WRAP_MAX_RAD
 * give 0. Bounded time, no loop. Any context. */
static inline float mathx_wrap_2pi(float x_rad)
{
    if (!(mathx_fabsf(x_rad) < MATHX_WRAP_MAX_RAD)) {
        return 0.0f;
    }
    const int32_t turns = (int32_t)(x_rad * (1.0f / MATHX_TWO_PI_F));
    x_rad -= (float)turns * MATHX_TWO_PI_F;
    if (x_rad < 0.0f) {
        x_rad += MATHX_TWO_PI_F;
    }
    /* Rounding can land exactly on 2*pi (e.g. -1e-9 + 2*pi); that is angle 0. */
    if ((x_rad >= 0.0f) && (x_rad < MATHX_TWO_PI_F)) {
        return x_rad;
    }
    return 0.0f;
}

#endif /* MATHX_H */
