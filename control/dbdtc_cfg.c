/* dbdtc_cfg.c - the deadbeat's start-up; see dbdtc.h. Background only
 * (runs from flash on the target: target.mk). */
#include "dbdtc.h"

#include "mathx.h"
#include "spmsm.h"

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
    db->R_lo_Ohm = DBDTC_PARAM_FACTOR_MIN * cfg->R_Ohm;
    db->R_hi_Ohm = DBDTC_PARAM_FACTOR_MAX * cfg->R_Ohm;
    db->L_lo_H = DBDTC_PARAM_FACTOR_MIN * cfg->L_H;
    db->L_hi_H = DBDTC_PARAM_FACTOR_MAX * cfg->L_H;
    db->psi_lo_Wb = DBDTC_PARAM_FACTOR_MIN * cfg->psi_f_Wb;
    db->psi_hi_Wb = DBDTC_PARAM_FACTOR_MAX * cfg->psi_f_Wb;
    db->kt_per_Wb_Nm_A = spmsm_kt_Nm_A(cfg->pole_pairs, 1.0f);
    dbdtc_reset(db);
    db->st.free_Wb.d = 0.0f;
    db->st.free_Wb.q = 0.0f;
    zoh_turn(0.0f, 0.0f, &still);
    dbdtc_period(db, &still); /* a model at standstill until the first period's turn */
    return ok;
}
