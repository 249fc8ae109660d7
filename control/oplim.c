/* oplim.c - torque and flux targets inside the current and voltage limits; see oplim.h. */
#include "oplim.h"

#include "mathx.h"

void oplim_init(oplim_t *o, float Ts_s, float rate_Wb_s, float hyst)
{
    const bool ok = mathx_isfinitef(Ts_s * rate_Wb_s * hyst) && (Ts_s > 0.0f) && (rate_Wb_s > 0.0f) &&
                    (hyst > 0.0f) && (hyst <= 1.0f);
    /* refused: no weakening (dpsi stays 0), the current limit still holds */
    o->dpsi_step_Wb = ok ? rate_Wb_s * Ts_s : 0.0f;
    o->hyst_sq = ok ? hyst * hyst : 1.0f;
    oplim_reset(o);
}

RAMFUNC void oplim_reset(oplim_t *o)
{
    o->dpsi_Wb = 0.0f;
    o->dpsi_max_Wb = 0.0f;
}
