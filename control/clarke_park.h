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

/* Clarke from two measured phase currents (ic = -ia - ib). Any context. */
static inline ab_t clarke_2ph(float ia, float ib)
{
    ab_t out;
    out.a = ia;
    out.b = (ia + 2.0f * ib) * MATHX_INV_SQRT3_F;
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
