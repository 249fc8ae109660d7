/*
 * pi.h - discrete PI controller with output limits and anti-windup based
 * on the realised output (motulator's PIController with k_t = k_p).
 *
 *   u      = Kp*e + xi                 unlimited output
 *   u_sat  = clamp(u, u_min, u_max)    returned
 *   xi    += (Ts*Ki/Kp) * (u_real - xi)
 *
 * u_real is u_sat unless pi_apply() reports a value an outer stage really
 * applied. Unsaturated, u_real - xi = Kp*e, so this is the plain integrator
 * xi += Ts*Ki*e; saturated, xi relaxes towards the applied output with the
 * integral time Kp/Ki, so it never winds up beyond what was applied.
 */
#ifndef PI_H
#define PI_H

#include <stdbool.h>

#include "mathx.h"

typedef struct {
    float Kp;    /* proportional gain [output unit / error unit] */
    float Ki;    /* integral gain [output unit / (error unit * s)] */
    float Ts_s;  /* sampling period [s] */
    float u_min; /* lower output limit [output unit] */
    float u_max; /* upper output limit [output unit] */
} pi_cfg_t;

typedef struct {
    pi_cfg_t cfg;
    float k_aw;   /* Ts*Ki/Kp: per-step pull of xi towards the realised output */
    float xi;     /* integral state [output unit], kept within the limits */
    float xi_old; /* xi before the last pi_step(), for pi_apply() */
} pi_t;

/*
 * Copies cfg and resets. Needs finite values, Kp > 0, Ki >= 0, Ts_s > 0,
 * u_min <= u_max and Ts*Ki/Kp <= 1 (integral time not below one period).
 * Returns false otherwise and leaves a PI whose output is always 0.
 * Background, or ISR in commissioning (from flash).
 */
bool pi_init(pi_t *pi, const pi_cfg_t *cfg);

/* Sets the integral state to xi_init [output unit], limited, for bumpless
 * start (zero error then gives xi_init). Background or ISR context. */
void pi_reset(pi_t *pi, float xi_init);

/* The output limits from now on, u_min_out <= u_max_out (finite; else
 * nothing changes): the integral state is clamped into them. A PI that
 * init refused keeps its zero limits. ISR (a limit that follows a model)
 * or background. */
void pi_set_limits(pi_t *pi, float u_min_out, float u_max_out);

/* One period with control error err [error unit]; returns the limited
 * output. A non-finite err counts as 0. ISR context (inline: a few
 * lines every period, no call). */
static inline float pi_step(pi_t *pi, float err)
{
    const float e = mathx_isfinitef(err) ? err : 0.0f;
    const float u = pi->cfg.Kp * e + pi->xi;
    /* u can only overflow to +-Inf for absurd errors; clamp maps it to a limit. */
    const float u_sat = mathx_clampf(u, pi->cfg.u_min, pi->cfg.u_max);
    pi->xi_old = pi->xi;
    pi->xi += pi->k_aw * (u_sat - pi->xi);
    return u_sat;
}

/* Optional, after pi_step() in the same period: the output an outer stage
 * really applied [output unit]; re-bases the last integrator update on it.
 * Non-finite values are ignored. ISR context (inline, as pi_step). */
static inline void pi_apply(pi_t *pi, float u_applied)
{
    if (!mathx_isfinitef(u_applied)) {
        return;
    }
    const float u_real = mathx_clampf(u_applied, pi->cfg.u_min, pi->cfg.u_max);
    pi->xi = pi->xi_old + pi->k_aw * (u_real - pi->xi_old);
}

#endif /* PI_H */
