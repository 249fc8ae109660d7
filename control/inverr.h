/*
 * inverr.h - the inverter's mean voltage error over one PWM period, with
 * the current's ripple at each leg's switching edges (beyond the paper;
 * derivation: inverter_error_design.md sec. 8).
 *
 * Centre-aligned PWM, every leg low at the period's start (the sample,
 * the middle of the zero vector 000: the current there is the period's
 * mean). Leg x turns on at t_x = (1 - d_x) Ts/2 and off at Ts - t_x; its
 * phase current's ripple about the mean is point-symmetric about Ts/2,
 * -r_x at turn-on and +r_x at turn-off, with
 *
 *   r_x = Ts/(2 L) [ (pos(u_y - u_x) + pos(u_z - u_x))/3 + u_x (1 - d_x) ]   (8.1)
 *
 * (u_x the phase voltages, d_x the min-max SVPWM duties). The dead band
 * after each edge takes the current's sign at that edge: the leg loses
 * Vdc td/Ts against the sign of i_x when |i_x| > r_x, and nothing when the
 * ripple takes the current through zero between its edges (the two dead
 * bands then cancel). The device drop follows the sign over the whole
 * period: counted where 2 |i_x| > r_x (the step the share of the period
 * the current keeps its sign crosses 1/2). A hard sign overstates the
 * error near a zero crossing by the ripple's share; on a low-inductance
 * motor (the ripple a third of the current) that share is what the
 * observer would learn as R and L.
 *
 * Stateless; any context.
 */
#ifndef INVERR_H
#define INVERR_H

#include <stdint.h>

#include "clarke_park.h"
#include "mathx.h"

/* The dead band's current sign per edge; the drop's share of the period
 * crosses 1/2 where the ripple is twice the current (8.1's step) */
#define INVERR_DROP_RIPPLE_PER_I 2.0f
#define INVERR_ONE_THIRD 0.333333333f
#define INVERR_DUTY_MID 0.5f
/* mid - cm = 1.5 mid when the phase voltages sum to 0 */
#define INVERR_MID_PER_VDC 1.5f

/* Ts/(2 L) [A/V] of (8.1) for the period Ts_s [s] and 1/L inv_L_1_H [1/H]. Any context. */
static inline float inverr_k_A_V(float Ts_s, float inv_L_1_H)
{
    return INVERR_DUTY_MID * Ts_s * inv_L_1_H;
}

/* One leg's mean voltage error [V]: its current i_A [A] (the period's
 * mean), ripple r_A [A], dead-time voltage dv_dead_V = Vdc td/Ts and
 * device drop dv_drop_V [V]. Any context. */
static inline float inverr_leg_V(float i_A, float r_A, float dv_dead_V, float dv_drop_V)
{
    const float a = mathx_fabsf(i_A);
    const float dv = ((a > r_A) ? dv_dead_V : 0.0f) + ((INVERR_DROP_RIPPLE_PER_I * a > r_A) ? dv_drop_V : 0.0f);
    return (i_A > 0.0f) ? -dv : dv; /* dv = 0 at i = 0 (r >= 0) */
}

/* The ripples r_x [A] of (8.1) of the three legs for their phase
 * voltages u_V [V] (no zero sequence: they sum to 0), 1/Vdc inv_vdc_1_V
 * [1/V] and Ts/(2 L) k_A_V [A/V]. With the legs sorted hi >= mid >= lo,
 * the min-max zero sequence cm = (hi + lo)/2 = -mid/2 gives 1 - d_hi =
 * d_lo = (1 - (hi - lo)/Vdc)/2 and 1 - d_mid = 1/2 - 1.5 mid/Vdc:
 *   r_hi = k hi (1 - d_hi),  r_lo = -k lo d_lo,
 *   r_mid = k ((hi - mid)/3 + mid (1 - d_mid))
 * all >= 0 (hi >= 0 >= lo; with mid < 0, hi >= -2 mid makes (hi - mid)/3
 * >= |mid|) (inverter_error_design.md sec. 8). Returns the largest [A]
 * (the mid leg's near the hexagon). Any context. */
/* u0, u1, u2 at the leg index i (0, 1, 2): a select, not an index, so
 * the caller's arrays stay in registers. */
static inline float inverr_at(uint16_t i, float u0, float u1, float u2)
{
    return (i == 0u) ? u0 : ((i == 1u) ? u1 : u2);
}

static inline float inverr_ripples_A(const float u_V[3], float inv_vdc_1_V, float k_A_V, float r_A[3])
{
    const float u0 = u_V[0];
    const float u1 = u_V[1];
    const float u2 = u_V[2];
    const uint16_t ih = (u0 >= u1) ? ((u0 >= u2) ? 0u : 2u) : ((u1 >= u2) ? 1u : 2u);
    const uint16_t j = (ih == 2u) ? 0u : (uint16_t)(ih + 1u); /* the next legs round */
    const uint16_t k = (j == 2u) ? 0u : (uint16_t)(j + 1u);
    const uint16_t il = (inverr_at(j, u0, u1, u2) <= inverr_at(k, u0, u1, u2)) ? j : k;
    const uint16_t im = (il == j) ? k : j;
    const float hi = inverr_at(ih, u0, u1, u2);
    const float lo = inverr_at(il, u0, u1, u2);
    const float mid = inverr_at(im, u0, u1, u2);
    const float d_edge = mathx_clampf(INVERR_DUTY_MID * (1.0f - (hi - lo) * inv_vdc_1_V), 0.0f, 1.0f);
    const float d_mid = mathx_clampf(INVERR_DUTY_MID - INVERR_MID_PER_VDC * mid * inv_vdc_1_V, 0.0f, 1.0f);
    const float k_edge = k_A_V * d_edge;
    const float r_hi = k_edge * hi;
    const float r_lo = -k_edge * lo;
    const float r_mid = k_A_V * ((hi - mid) * INVERR_ONE_THIRD + mid * d_mid);
    r_A[0] = (ih == 0u) ? r_hi : ((il == 0u) ? r_lo : r_mid);
    r_A[1] = (ih == 1u) ? r_hi : ((il == 1u) ? r_lo : r_mid);
    r_A[2] = (ih == 2u) ? r_hi : ((il == 2u) ? r_lo : r_mid);
    const float r_edge = k_edge * ((hi > -lo) ? hi : -lo);
    return (r_edge > r_mid) ? r_edge : r_mid;
}

/* The stator-frame mean voltage error [V] of the period for the phase
 * currents i_A [A] and the stator-frame voltage u_V the duties realise
 * [V] (the ripple's), the bus 1/Vdc [1/V], Ts/(2 L) [A/V] and the per-leg
 * dead-time and drop voltages [V]; *ripple_max_A the largest r_x [A].
 * Any context. */
static inline ab_t inverr_error_V(abc_t i_A, ab_t u_V, float inv_vdc_1_V, float k_A_V, float dv_dead_V,
                                  float dv_drop_V, float *ripple_max_A)
{
    const abc_t u = clarke_inv(u_V);
    const float u3[3] = { u.a, u.b, u.c };
    float r[3];
    *ripple_max_A = inverr_ripples_A(u3, inv_vdc_1_V, k_A_V, r);
    return clarke_3ph(inverr_leg_V(i_A.a, r[0], dv_dead_V, dv_drop_V), inverr_leg_V(i_A.b, r[1], dv_dead_V, dv_drop_V),
                      inverr_leg_V(i_A.c, r[2], dv_dead_V, dv_drop_V));
}

#endif /* INVERR_H */
