/* align.c - two-step rotor alignment; see align.h. */
#include "align.h"

#include "mathx.h"

void align_init(align_t *a, const align_cfg_t *cfg, float Ts_s)
{
    a->cfg = *cfg;
    a->ramp_ticks = app_periods_of(cfg->ramp_s, Ts_s);
    a->prepos_ticks = app_periods_of(cfg->prepos_s, Ts_s);
    a->settle_ticks = app_periods_of(cfg->settle_s, Ts_s);
    mathx_sincosf(cfg->prepos_el_rad, &a->prepos_sin, &a->prepos_cos);
    align_start(a);
}

FLASHFUNC void align_start(align_t *a)
{
    a->ticks = 0u;
}

/* The vector of period k: the pre-position vector ramped from 0 and held,
 * then cross-faded onto phase a and held there. */
FLASHFUNC static ab_t align_vector(const align_t *a, uint32_t k)
{
    const uint32_t turn = a->ramp_ticks + a->prepos_ticks; /* first period of the turn */
    float w_pre = 0.0f; /* weights of the pre-position vector and of the one on phase a */
    float w_a = 1.0f;
    ab_t u;

    if (k < a->ramp_ticks) {
        w_pre = (float)k / (float)a->ramp_ticks;
        w_a = 0.0f;
    } else if (k < turn) {
        w_pre = 1.0f;
        w_a = 0.0f;
    } else if (k < turn + a->ramp_ticks) {
        w_a = (float)(k - turn) / (float)a->ramp_ticks;
        w_pre = 1.0f - w_a;
    }
    /* in the final hold w_pre = 0: u_beta is exactly 0 (dead time, sensors: design note) */
    u.a = a->cfg.u_V * (w_pre * a->prepos_cos + w_a);
    u.b = a->cfg.u_V * w_pre * a->prepos_sin;
    return u;
}

FLASHFUNC app_step_t align_step(align_t *a, ab_t *u_ab_V)
{
    const uint32_t k = a->ticks;
    const uint32_t end = 2u * a->ramp_ticks + a->prepos_ticks + a->settle_ticks;

    *u_ab_V = align_vector(a, k);
    a->ticks++;
    return (k >= end) ? app_step_done() : app_step_running();
}
