/*
 * pi.c - PI controller, anti-windup on the realised output.
 *
 * With 0 <= k_aw <= 1 the integrator update is a convex combination of xi
 * and a value inside [u_min, u_max], so xi stays inside the limits without
 * a separate clamp.
 */
#include "pi.h"

#include "mathx.h"

FLASHFUNC static bool pi_cfg_valid(const pi_cfg_t *cfg)
{
    if (!mathx_isfinitef(cfg->Kp) || !mathx_isfinitef(cfg->Ki) || !mathx_isfinitef(cfg->Ts_s)
        || !mathx_isfinitef(cfg->u_min) || !mathx_isfinitef(cfg->u_max)) {
        return false;
    }
    if (!(cfg->Kp > 0.0f) || !(cfg->Ki >= 0.0f) || !(cfg->Ts_s > 0.0f)
        || !(cfg->u_min <= cfg->u_max)) {
        return false;
    }
    /* Ts*Ki/Kp > 1 would overshoot the realised output in one step. */
    return (cfg->Ts_s * cfg->Ki) <= cfg->Kp;
}

FLASHFUNC bool pi_init(pi_t *pi, const pi_cfg_t *cfg)
{
    const bool ok = pi_cfg_valid(cfg);
    if (ok) {
        pi->cfg = *cfg;
        pi->k_aw = (cfg->Ts_s * cfg->Ki) / cfg->Kp;
    } else {
        /* Safe fallback: no gain, both limits at 0. */
        pi->cfg.Kp = 0.0f;
        pi->cfg.Ki = 0.0f;
        pi->cfg.Ts_s = 0.0f;
        pi->cfg.u_min = 0.0f;
        pi->cfg.u_max = 0.0f;
        pi->k_aw = 0.0f;
    }
    pi_reset(pi, 0.0f);
    return ok;
}

RAMFUNC void pi_reset(pi_t *pi, float xi_init)
{
    pi->xi = mathx_clampf(xi_init, pi->cfg.u_min, pi->cfg.u_max);
    pi->xi_old = pi->xi;
}

RAMFUNC void pi_set_limits(pi_t *pi, float u_min_out, float u_max_out)
{
    if (!(pi->cfg.Kp > 0.0f) || !mathx_isfinitef(u_min_out) || !mathx_isfinitef(u_max_out) ||
        !(u_min_out <= u_max_out)) {
        return;
    }
    pi->cfg.u_min = u_min_out;
    pi->cfg.u_max = u_max_out;
    pi->xi = mathx_clampf(pi->xi, u_min_out, u_max_out);
    pi->xi_old = mathx_clampf(pi->xi_old, u_min_out, u_max_out);
}
