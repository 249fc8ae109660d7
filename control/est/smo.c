/* smo.c - sliding-mode current and disturbance observer; see smo.h. */
#include "smo.h"

#include "mathx.h"

RAMFUNC static bool in_range(float x, float lo, float hi)
{
    return (x >= lo) && (x <= hi);
}

/* The decay at R^, L^ (zoh.h): 2 divisions; Phi, g_u, g_c follow at the next step. */
RAMFUNC static void update_model(smo_t *smo)
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

RAMFUNC void smo_reset(smo_t *smo)
{
    zoh_turn_t still;

    smo->seeded = false;
    smo->R_Ohm = smo->cfg.R_Ohm;
    smo->L_H = smo->cfg.L_H;
    smo->psi_f_Wb = smo->cfg.psi_f_Wb;
    update_model(smo);
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

/* The period's Phi, g_u, g_c (and Phi - rho) in the turn *turn: taken
 * again when the turn or the decay changed (the decay first when L^
 * moved: smo_set_L_deferred). */
RAMFUNC static void take_period(smo_t *smo, const zoh_turn_t *turn)
{
    if (smo->zm_stale) {
        update_model(smo); /* L^ moved since: 2 divisions */
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

/* Boundary-layer switching term Ks sat(e/phi) [V] (replaces sign() of (32)). */
RAMFUNC static float switching(const smo_t *smo, float e_A)
{
    return smo->cfg.Ks_V * mathx_clampf(e_A * smo->inv_phi_1_A, -1.0f, 1.0f);
}

RAMFUNC dq_t smo_step_turn(smo_t *smo, dq_t i_A, dq_t u_V, float omega_el_rad_s, const zoh_turn_t *turn)
{
    const smo_cfg_t *c = &smo->cfg;
    dq_t i;
    dq_t u;
    dq_t v;
    dq_t next;

    i.d = mathx_clampf(i_A.d, -c->i_max_A, c->i_max_A);
    i.q = mathx_clampf(i_A.q, -c->i_max_A, c->i_max_A);
    /* u as applied: the inverter bounds it (a non-finite u is the caller's
     * NONFINITE fault; smo_reset at the next start clears what it left) */
    u = u_V;
    if (smo->status != SMO_CFG_OK) {
        smo->i_hat_A = i;
        return smo->i_hat_A;
    }
    if (!smo->seeded) {
        /* i^(k) = i(k) at enable: no error, no switching kick. */
        smo->i_hat_A = i;
        smo->seeded = true;
    }

    /* (30): e = i^ - i, with i^(k) the previous prediction */
    const float Ud = switching(smo, smo->i_hat_A.d - i.d);
    const float Uq = switching(smo, smo->i_hat_A.q - i.q);
    take_period(smo, turn);
    const float rho = smo->zm.rho;
    const zoh_step_t *z = &smo->z;

    /* (51b), (55) exact: the rotor's turn on the measured current (the
     * paper's cross terms w Ts i(k)), rho on the observer's own; U with +
     * sign from the error dynamics; -w psi^ with the psi^ in use */
    v.d = -smo->fd_V - Ud;
    v.q = -omega_el_rad_s * smo->psi_f_Wb - smo->fq_V - Uq; /* w(k) itself: a kept turn's w is up to
                                                               * ZOH_THETA_TOL_RAD/Ts off, w psi by that x psi */
    const dq_t gu = zoh_mul(z->g_u, u);
    const dq_t gv = zoh_mul(z->g_c, v);
    const float rc = smo->z_rc;
    const float rs = smo->z_rs;
    next.d = rho * smo->i_hat_A.d + rc * i.d + rs * i.q + gu.d + gv.d;
    next.q = rho * smo->i_hat_A.q + rc * i.q - rs * i.d + gu.q + gv.q;
    /* (51b), (55): f^ += mu Ts U, the sign that makes (37) converge */
    smo->fd_V = mathx_clampf(smo->fd_V + smo->mu_d_Ts * Ud, -c->f_max_V, c->f_max_V);
    smo->fq_V = mathx_clampf(smo->fq_V + smo->mu_q_Ts * Uq, -c->f_max_V, c->f_max_V);

    smo->i_hat_A.d = mathx_clampf(next.d, -c->i_max_A, c->i_max_A);
    smo->i_hat_A.q = mathx_clampf(next.q, -c->i_max_A, c->i_max_A);
    smo->U_V.d = Ud;
    smo->U_V.q = Uq;
    return smo->i_hat_A;
}

dq_t smo_step(smo_t *smo, dq_t i_A, float omega_el_rad_s, dq_t u_V)
{
    const float w = mathx_clampf(omega_el_rad_s, -smo->cfg.omega_max_rad_s, smo->cfg.omega_max_rad_s);
    zoh_turn_t t;
    zoh_turn(w * smo->cfg.Ts_s, w, &t);
    return smo_step_turn(smo, i_A, u_V, w, &t);
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
    update_model(smo);
    return true;
}

RAMFUNC float smo_set_L(smo_t *smo, float L_H, float omega_el_rad_s, float iq_A)
{
    const float L_new = smo_set_L_deferred(smo, L_H, omega_el_rad_s, iq_A);
    if (smo->zm_stale) {
        update_model(smo); /* the decay at the L^ in use; 2 divisions */
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

    /* step2_design.md sec. 1: w L^ iq - fd^ unchanged */
    smo->fd_V = mathx_clampf(smo->fd_V + (L_new - smo->L_H) * w * iq, -c->f_max_V, c->f_max_V);
    smo->L_H = L_new;
    if (mathx_fabsf(L_new - smo->zm.L_H) > SMO_MODEL_UPDATE_REL * smo->zm.L_H) {
        smo->zm_stale = true; /* the decay at the L^ in use at the next step (2 divisions there) */
    }
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

    /* step2_design.md sec. 2: w psi^ + fq^ unchanged */
    smo->fq_V = mathx_clampf(smo->fq_V - (psi_new - smo->psi_f_Wb) * w, -c->f_max_V, c->f_max_V);
    smo->psi_f_Wb = psi_new;
    return psi_new;
}
