/*
 * clarke_park.h - stateless reference-frame transforms (amplitude-invariant).
 *
 * Frames: abc (phase), ab = alpha-beta (stator), dq (rotor, d on the magnet).
 * Park and its inverse take sin/cos of the electrical angle, so one
 * mathx_sincosf() per ISR serves both directions.
 */
#ifndef CLARKE_PARK_H
#define CLARKE_PARK_H

#include "mathx.h"

typedef struct {
    float a;
    float b;
} ab_t;

typedef struct {
    float d;
    float q;
} dq_t;

typedef struct {
    float a;
    float b;
    float c;
} abc_t;

/* The transforms' constants, here only (amplitude-invariant Clarke). */
#define CLARKE_HALF        0.5f                  /* the other phases' share: cos 120 deg = -1/2 */
#define CLARKE_HALF_SQRT3  (0.5f * MATHX_SQRT3_F) /* sin 120 deg = sqrt(3)/2 */
#define CLARKE_TWO_THIRDS  0.666666667f          /* amplitude-invariant scale */

/* Clarke from two measured phase currents (ic = -ia - ib). Any context. */
static inline ab_t clarke_2ph(float ia, float ib)
{
    ab_t out;
    out.a = ia;
    out.b = (ia + 2.0f * ib) * MATHX_INV_SQRT3_F;
    return out;
}

/* Clarke from three phase quantities (any zero sequence drops out). Any context. */
static inline ab_t clarke_3ph(float a, float b, float c)
{
    ab_t out;
    out.a = CLARKE_TWO_THIRDS * (a - CLARKE_HALF * (b + c));
    out.b = MATHX_INV_SQRT3_F * (b - c);
    return out;
}

/* Inverse Clarke: alpha-beta to the three phases (no zero sequence). Any context. */
static inline abc_t clarke_inv(ab_t x)
{
    abc_t out;
    out.a = x.a;
    out.b = -CLARKE_HALF * x.a + CLARKE_HALF_SQRT3 * x.b;
    out.c = -CLARKE_HALF * x.a - CLARKE_HALF_SQRT3 * x.b;
    return out;
}

/* Park: alpha-beta to dq at the angle whose sin/cos are given. Any context. */
static inline dq_t park(ab_t x, float sin_th, float cos_th)
{
    dq_t out;
    out.d = x.a * cos_th + x.b * sin_th;
    out.q = -x.a * sin_th + x.b * cos_th;
    return out;
}

/* Inverse Park: dq to alpha-beta at the angle whose sin/cos are given. Any context. */
static inline ab_t park_inv(dq_t x, float sin_th, float cos_th)
{
    ab_t out;
    out.a = x.d * cos_th - x.q * sin_th;
    out.b = x.d * sin_th + x.q * cos_th;
    return out;
}

#endif /* CLARKE_PARK_H */
