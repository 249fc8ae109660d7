/* smo.c - sliding-mode current and disturbance observer; see smo.h. */
#include "smo.h"

#include "mathx.h"

RAMFUNC static bool in_range(float x, float lo, float hi)
{
    return (x >= lo) && (x <= hi);
}

/* Phi, g_u, g_c follow at the next step. */
RAMFUNC void smo_update_model(smo_t *smo)
{
    smo->zm_stale = false;
    smo->z_turn = 0u; /* no turn's number: taken again at the next step */
    if ((smo->status != SMO_CFG_OK) || !zoh_model(smo->R_Ohm, smo->L_H, smo->cfg.Ts_s, &smo->zm)) {
        /* a refused cfg: no decay, no gain (smo_step passes i(k) through) */
        smo->zm.R_Ohm = 1.0f;
        smo->zm.L_H = 1.0f;
        smo->zm.tau_s = 0.0f;
        smo->zm.rho = 1.0f;
        smo->zm.one_m_rho = 0.0f;
        smo->zm.gamma_A_V = 0.0f;
        smo->zm.kappa_1_s = 0.0f;
    }
}

RAMFUNC void smo_take_model(smo_t *smo)
{
    smo->zm_stale = false;
    smo->z_turn = 0u; /* no turn's number: taken again at the next step */
    zoh_model_of(smo->R_Ohm, smo->L_H, smo->cfg.Ts_s, &smo->zm);
}

RAMFUNC void smo_reset(smo_t *smo)
{
    zoh_turn_t still;

    smo->seeded = false;
    smo->R_Ohm = smo->cfg.R_Ohm;
    smo->L_H = smo->cfg.L_H;
    smo->psi_f_Wb = smo->cfg.psi_f_Wb;
    smo_update_model(smo);
    zoh_turn(0.0f, 0.0f, &still); /* at standstill until the first step's turn */
    zoh_step(&smo->zm, &still, &smo->z);
    smo->z_rc = 0.0f;
    smo->z_rs = 0.0f;
    smo->z_turn = still.seq;
    smo->z_rev++;
    smo->i_hat_A.d = 0.0f;
    smo->i_hat_A.q = 0.0f;
    smo->fd_V = 0.0f;
    smo->fq_V = 0.0f;
    smo->U_V.d = 0.0f;
    smo->U_V.q = 0.0f;
}

RAMFUNC void smo_take_period(smo_t *smo, const zoh_turn_t *turn)
{
    if (smo->zm_stale) {
        smo_update_model(smo); /* L^ moved since: 2 divisions */
    }
    if (turn->seq != smo->z_turn) {
        const float rho = smo->zm.rho;
        zoh_step(&smo->zm, turn, &smo->z); /* 1 division */
        /* (Phi - rho) i = rho (cos theta - 1 - j sin theta) i, cos theta - 1 = -2 sin^2(theta/2) */
        smo->z_rc = -2.0f * rho * turn->sh * turn->sh;
        smo->z_rs = rho * turn->s1;
        smo->z_turn = turn->seq;
        smo->z_rev++;
    }
}

RAMFUNC void smo_shift_f(smo_t *smo, float dfd_V, float dfq_V)
{
    smo->fd_V += dfd_V;
    smo->fq_V += dfq_V;
}

RAMFUNC bool smo_set_R(smo_t *smo, float R_Ohm)
{
    const smo_cfg_t *c = &smo->cfg;
    if ((smo->status != SMO_CFG_OK) || !mathx_isfinitef(R_Ohm) ||
        !in_range(R_Ohm, c->R_min_Ohm, c->R_max_Ohm)) {
        return false;
    }
    /* step1_design.md sec. 1: f^ += dR i^ with dR = R^old - R^new */
    const float dR = smo->R_Ohm - R_Ohm;
    smo->fd_V = mathx_clampf(smo->fd_V + dR * smo->i_hat_A.d, -c->f_max_V, c->f_max_V);
    smo->fq_V = mathx_clampf(smo->fq_V + dR * smo->i_hat_A.q, -c->f_max_V, c->f_max_V);
    smo->R_Ohm = R_Ohm;
    smo_update_model(smo);
    return true;
}

RAMFUNC float smo_set_L(smo_t *smo, float L_H, float omega_el_rad_s, float iq_A)
{
    const float L_new = smo_set_L_deferred(smo, L_H, omega_el_rad_s, iq_A);
    if (smo->zm_stale) {
        smo_update_model(smo); /* the decay at the L^ in use; 2 divisions */
    }
    return L_new;
}

RAMFUNC float smo_set_L_deferred(smo_t *smo, float L_H, float omega_el_rad_s, float iq_A)
{
    const smo_cfg_t *c = &smo->cfg;
    if (smo->status != SMO_CFG_OK) {
        return smo->L_H;
    }
    const float w = mathx_clampf(omega_el_rad_s, -c->omega_max_rad_s, c->omega_max_rad_s);
    const float iq = mathx_clampf(iq_A, -c->i_max_A, c->i_max_A);
    /* NaN maps to L_min: never a division by ~0 below */
    const float L_new = mathx_clampf(L_H, c->L_min_H, c->L_max_H);

    smo_take_L_deferred(smo, L_new, w, iq);
    return L_new;
}

RAMFUNC float smo_set_psi(smo_t *smo, float psi_f_Wb, float omega_el_rad_s)
{
    const smo_cfg_t *c = &smo->cfg;
    if (smo->status != SMO_CFG_OK) {
        return smo->psi_f_Wb;
    }
    const float w = mathx_clampf(omega_el_rad_s, -c->omega_max_rad_s, c->omega_max_rad_s);
    const float psi_new = mathx_clampf(psi_f_Wb, c->psi_min_Wb, c->psi_max_Wb);

    smo_take_psi(smo, psi_new, w);
    return psi_new;
}
