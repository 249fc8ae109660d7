/* oplim.c - torque and flux targets inside the current and voltage limits; see oplim.h. */
#include "oplim.h"

#include "mathx.h"
#include "mtpa.h"

#define HALF 0.5f

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

RAMFUNC oplim_out_t oplim_targets(oplim_t *o, const dbdtc_par_t *p, float i_lim_A, float te_req_Nm)
{
    oplim_out_t out;
    /* current limit at id = 0 (MTPA): |Te*| <= kt i_lim */
    const float te_i = p->kt_Nm_per_A * i_lim_A;
    const float Li = p->L_H * i_lim_A;

    out.te_Nm = mathx_clampf(te_req_Nm, -te_i, te_i);
    /* L Te* / kt, not psiq_per_Nm Te* without the division: a last-bit
     * change of the flux target moves the figures of make sil
     * (ctrl_step_design.md sec. 4) */
    out.psi_Wb = mtpa_psi_s_of_psi_q(p->psi_f_Wb, (p->L_H * out.te_Nm) / p->kt_Nm_per_A); /* sec. III */
    o->dpsi_max_Wb = out.psi_Wb - (p->psi_f_Wb - Li);
    if (o->dpsi_Wb > 0.0f) {
        /* weakening: the flux the voltage allows, then the torque the current allows there */
        const float psi = mathx_clampf(out.psi_Wb - o->dpsi_Wb, p->psi_f_Wb - Li, out.psi_Wb);
        const float psid_min = (psi * psi + p->psi_f_Wb * p->psi_f_Wb - Li * Li) * HALF * p->inv_psi_f_1_Wb;
        const float psid_lo = (psid_min > 0.0f) ? psid_min : 0.0f;
        const float te_fw = p->te_per_Wb * mathx_sqrtf(psi * psi - psid_lo * psid_lo);
        out.te_Nm = mathx_clampf(out.te_Nm, -te_fw, te_fw);
        out.psi_Wb = psi;
    }
    return out;
}
