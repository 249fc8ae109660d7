/* calib.c - current-offset calibration; see calib.h. */
#include "calib.h"

#include "mathx.h"

void calib_init(calib_t *c, const calib_cfg_t *cfg, float Ts_s)
{
    c->cfg = *cfg;
    if (c->cfg.samples == 0u) {
        c->cfg.samples = 1u;
    }
    c->settle_ticks = app_periods_of(cfg->settle_s, Ts_s);
    c->offset_ia_A = 0.0f;
    c->offset_ib_A = 0.0f;
    calib_start(c);
}

FLASHFUNC void calib_start(calib_t *c)
{
    c->ticks = 0u;
    c->sum_ia_A = 0.0f;
    c->sum_ib_A = 0.0f;
}

FLASHFUNC app_step_t calib_step(calib_t *c, float ia_A, float ib_A)
{
    const uint32_t n = c->cfg.samples;
    const float lim = c->cfg.offset_max_A;

    c->ticks++;
    if (c->ticks <= c->settle_ticks) {
        return app_step_running();
    }
    c->sum_ia_A += ia_A;
    c->sum_ib_A += ib_A;
    if (c->ticks < c->settle_ticks + n) {
        return app_step_running();
    }
    const float oa = c->sum_ia_A / (float)n;
    const float ob = c->sum_ib_A / (float)n;
    if (!(mathx_fabsf(oa) <= lim)) { /* !(x <= max): NaN is refused too */
        return app_step_fault(APP_FAULT_CURRENT_OFFSET, oa, lim);
    }
    if (!(mathx_fabsf(ob) <= lim)) {
        return app_step_fault(APP_FAULT_CURRENT_OFFSET, ob, lim);
    }
    c->offset_ia_A = oa;
    c->offset_ib_A = ob;
    return app_step_done();
}
