/* dbdtc_cfg.c - the deadbeat's start-up; see dbdtc.h. Background only
 * (runs from flash on the target: target.mk). */
#include "dbdtc.h"

#include "mathx.h"

static bool positive(float x)
{
    return mathx_isfinitef(x) && (x > 0.0f);
}

bool dbdtc_init(dbdtc_t *db, const dbdtc_cfg_t *cfg)
{
    const bool ok = positive(cfg->Ts_s) && positive(cfg->R_Ohm) && positive(cfg->L_H) &&
                    positive(cfg->psi_f_Wb) && (cfg->pole_pairs > 0u) && positive(cfg->i_max_A) &&
                    positive(cfg->omega_max_rad_s) && positive(cfg->u_max_V) && positive(cfg->te_max_Nm) &&
                    positive(cfg->psi_max_Wb);
    zoh_turn_t still;

    db->cfg = *cfg;
    db->u_lo_V = -cfg->u_max_V;
    db->i_lo_A = -cfg->i_max_A;
    db->te_lo_Nm = -cfg->te_max_Nm;
    dbdtc_reset(db);
    db->st.free_Wb.d = 0.0f;
    db->st.free_Wb.q = 0.0f;
    zoh_turn(0.0f, 0.0f, &still);
    dbdtc_period(db, &still); /* a model at standstill until the first period's turn */
    return ok;
}
