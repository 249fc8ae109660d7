/* ident.c - identification of the motor and the inverter; see ident.h and
 * firmware/commission/commission_design.md. */
#include "ident.h"

#include "mathx.h"
#include "spmsm.h"

/* Alpha's share of a leg's error -dv sign(i) with phase a at I and b, c at
 * -I/2: (2/3)(-dv - dv) = -(4/3) dv sign(I) (Clarke, amplitude-invariant);
 * the voltage commanded for a DC current carries +(4/3) dv sign(I). */
#define ALPHA_PER_LEG (2.0f * CLARKE_TWO_THIRDS)
#define HALF 0.5f

FLASHFUNC void ident_ls_reset(ident_ls_t *s)
{
    s->n = 0.0f;
    s->s1 = 0.0f;
    s->s2 = 0.0f;
    s->sy = 0.0f;
    s->s11 = 0.0f;
    s->s12 = 0.0f;
    s->s22 = 0.0f;
    s->s1y = 0.0f;
    s->s2y = 0.0f;
}

FLASHFUNC float ident_ls_slope(const ident_ls_t *s)
{
    if (!(s->n >= IDENT_LS_N_MIN)) {
        return 0.0f;
    }
    const float c11 = s->s11 - s->s1 * s->s1 / s->n;
    const float c1y = s->s1y - s->s1 * s->sy / s->n;
    return (c11 > 0.0f) ? c1y / c11 : 0.0f;
}

FLASHFUNC float ident_ls_coef1(const ident_ls_t *s)
{
    if (!(s->n >= IDENT_LS_N_MIN)) {
        return 0.0f;
    }
    const float c11 = s->s11 - s->s1 * s->s1 / s->n;
    const float c12 = s->s12 - s->s1 * s->s2 / s->n;
    const float c22 = s->s22 - s->s2 * s->s2 / s->n;
    const float c1y = s->s1y - s->s1 * s->sy / s->n;
    const float c2y = s->s2y - s->s2 * s->sy / s->n;
    const float det = c11 * c22 - c12 * c12;
    return (det > 0.0f) ? (c1y * c22 - c2y * c12) / det : 0.0f;
}

FLASHFUNC void ident_win_reset(ident_win_t *w)
{
    w->sum_u = 0.0f;
    w->sum_i = 0.0f;
    w->n = 0.0f;
}

FLASHFUNC ident_point_t ident_win_take(ident_win_t *w)
{
    ident_point_t p;
    p.U_V = w->sum_u / w->n;
    p.I_A = w->sum_i / w->n;
    ident_win_reset(w);
    return p;
}

/* ---- the DC-current regulator ------------------------------------------- */

FLASHFUNC static bool dc_axis_init(pi_t *pi, const ident_dc_cfg_t *cfg, float ki_V_As)
{
    pi_cfg_t c;
    c.Kp = cfg->kp_V_A;
    c.Ki = ki_V_As;
    c.Ts_s = cfg->Ts_s;
    c.u_min = -cfg->u_max_V;
    c.u_max = cfg->u_max_V;
    return pi_init(pi, &c);
}

FLASHFUNC bool ident_dc_init(ident_dc_t *r, const ident_dc_cfg_t *cfg)
{
    r->cfg = *cfg;
    const bool ok_a = dc_axis_init(&r->a, cfg, cfg->ki_V_As);
    const bool ok_b = dc_axis_init(&r->b, cfg, cfg->ki_V_As);
    return ok_a && ok_b;
}

FLASHFUNC bool ident_dc_set_ki_a(ident_dc_t *r, float ki_V_As)
{
    pi_t next;
    if (!dc_axis_init(&next, &r->cfg, ki_V_As)) {
        return false;
    }
    pi_reset(&next, r->a.xi);
    r->a = next;
    return true;
}

FLASHFUNC ab_t ident_dc_step(ident_dc_t *r, ab_t i_ref_A, ab_t i_A)
{
    ab_t u;
    u.a = pi_step(&r->a, i_ref_A.a - i_A.a);
    u.b = pi_step(&r->b, i_ref_A.b - i_A.b);
    return u;
}

FLASHFUNC float ident_dc_step_b(ident_dc_t *r, float i_b_A)
{
    return pi_step(&r->b, -i_b_A);
}

/* ---- the current PI in a rotating frame ---------------------------------- */

FLASHFUNC bool ident_cur_init(ident_cur_t *c, float Ts_s, float bw_rad_s, float R_Ohm, float L_H, float u_max_V, dq_t u0_V)
{
    pi_cfg_t k;
    k.Kp = bw_rad_s * L_H;
    k.Ki = bw_rad_s * R_Ohm;
    k.Ts_s = Ts_s;
    k.u_min = -u_max_V;
    k.u_max = u_max_V;
    const bool ok_d = pi_init(&c->d, &k);
    const bool ok_q = pi_init(&c->q, &k);
    pi_reset(&c->d, u0_V.d);
    pi_reset(&c->q, u0_V.q);
    return ok_d && ok_q;
}

/* ---- R and the inverter -------------------------------------------------- */

FLASHFUNC float ident_r_of_points(ident_point_t p1, ident_point_t p2)
{
    const float dI = p2.I_A - p1.I_A;
    return (mathx_fabsf(dI) > 0.0f) ? (p2.U_V - p1.U_V) / dI : 0.0f;
}

FLASHFUNC void ident_inv_solve(float R_Ohm, const ident_point_t pos[2], const ident_point_t neg[2], ident_inv_t *out)
{
    /* E = U - R I on alpha: +(4/3) dv at a positive current, -(4/3) dv at a negative one, plus asym */
    float e[4];
    float spread = 0.0f;
    e[0] = pos[0].U_V - R_Ohm * pos[0].I_A;
    e[1] = pos[1].U_V - R_Ohm * pos[1].I_A;
    e[2] = neg[0].U_V - R_Ohm * neg[0].I_A;
    e[3] = neg[1].U_V - R_Ohm * neg[1].I_A;
    out->asym_V = 0.25f * (e[0] + e[1] + e[2] + e[3]);
    out->dv_V = 0.25f * ((e[0] + e[1]) - (e[2] + e[3])) / ALPHA_PER_LEG;
    for (uint16_t k = 0u; k < 4u; k++) {
        const float sgn = (k < 2u) ? 1.0f : -1.0f;
        const float d = mathx_fabsf(sgn * (e[k] - out->asym_V) / ALPHA_PER_LEG - out->dv_V);
        spread = (d > spread) ? d : spread;
    }
    out->spread_V = spread;
}

FLASHFUNC void ident_inv_split(float dv_V, float vdc_V, float Ts_s, float td_told_s, float *td_s, float *drop_V)
{
    const float dv_told_V = vdc_V * td_told_s / Ts_s;
    if (dv_V >= dv_told_V) {
        *td_s = td_told_s;
        *drop_V = dv_V - dv_told_V;
    } else {
        *td_s = (dv_V > 0.0f) ? dv_V * Ts_s / vdc_V : 0.0f;
        *drop_V = 0.0f;
    }
}

/* ---- L -------------------------------------------------------------------- */

FLASHFUNC void ident_l_start(ident_l_t *l, float Ts_s, ident_point_t op)
{
    l->Ts_s = Ts_s;
    l->op = op;
    l->y_Vs = 0.0f;
    l->di_prev_A = 0.0f;
    l->k = 0u;
    ident_ls_reset(&l->ls);
}

FLASHFUNC void ident_l_step(ident_l_t *l, float i_A, float u_V, float R_Ohm)
{
    const float di = i_A - l->op.I_A;
    /* L (di(k) - di(k-1)) = Ts (du - R (di(k) + di(k-1)) / 2) over the period just ended */
    if (l->k > 0u) {
        l->y_Vs += l->Ts_s * ((u_V - l->op.U_V) - R_Ohm * HALF * (di + l->di_prev_A));
    }
    ident_ls_add(&l->ls, di, (float)l->k * l->Ts_s, l->y_Vs);
    l->di_prev_A = di;
    l->k++;
}

FLASHFUNC float ident_l_solve(const ident_l_t *l)
{
    return ident_ls_coef1(&l->ls);
}

/* ---- the encoder ------------------------------------------------------------ */

FLASHFUNC float ident_enc_offset(const ident_ls_t *ls, uint32_t count0, uint16_t pole_pairs, uint32_t cpr,
                       float *counts_per_rad)
{
    *counts_per_rad = ident_ls_slope(ls);
    if (!(ls->n >= IDENT_LS_N_MIN) || (cpr == 0u)) {
        return 0.0f;
    }
    /* theta_c = offset + p 2 pi (count0 + dcount + 1/2) / cpr on average
     * (encoder.h's count centre); count0 p reduced mod cpr first (float keeps 24 bits) */
    const uint32_t c0p = mathx_umod_u32(count0 * (uint32_t)pole_pairs, cpr);
    const float mean_theta = ls->s1 / ls->n + MATHX_PI_F;
    const float mean_dc = ls->sy / ls->n;
    return mathx_wrap_2pi(mean_theta -
                          ((float)c0p + (float)pole_pairs * (HALF + mean_dc)) * (MATHX_TWO_PI_F / (float)cpr));
}

/* ---- the spin ------------------------------------------------------------- */

FLASHFUNC void ident_spin_reset(ident_spin_t *s)
{
    ident_ls_reset(&s->psi);
    ident_ls_reset(&s->acc);
    ident_ls_reset(&s->dec);
    s->iq_acc_A = 0.0f;
    s->w_acc_rad_s = 0.0f;
    s->iq_dec_A = 0.0f;
    s->w_dec_rad_s = 0.0f;
    s->w0_rad_s = 0.0f;
    s->y0_V = 0.0f;
    s->centred = false;
}

FLASHFUNC void ident_spin_add_flux(ident_spin_t *s, float w_rad_s, uint16_t pole_pairs, dq_t i_dq_A, float u_q_V,
                         float R_Ohm, bool negative)
{
    const float y = u_q_V - R_Ohm * i_dq_A.q;
    if (!s->centred) {
        s->w0_rad_s = w_rad_s; /* centred sums: float keeps the slope's digits */
        s->y0_V = y;
        s->centred = true;
    }
    /* u_q = R i_q + w_el psi_f + E_q: E_q (inverter, R^'s error) odd in i_q */
    ident_ls_add(&s->psi, (float)pole_pairs * (w_rad_s - s->w0_rad_s), negative ? -1.0f : 1.0f, y - s->y0_V);
}

FLASHFUNC void ident_spin_add_motion(ident_spin_t *s, float t_s, float w_rad_s, float i_q_A, bool braking)
{
    if (braking) {
        ident_ls_add(&s->dec, t_s, 0.0f, w_rad_s);
        s->iq_dec_A += i_q_A;
        s->w_dec_rad_s += w_rad_s;
    } else {
        ident_ls_add(&s->acc, t_s, 0.0f, w_rad_s);
        s->iq_acc_A += i_q_A;
        s->w_acc_rad_s += w_rad_s;
    }
}

FLASHFUNC bool ident_spin_solve(const ident_spin_t *s, uint16_t pole_pairs, ident_spin_out_t *out)
{
    const float psi = ident_ls_coef1(&s->psi);
    const float a1 = ident_ls_slope(&s->acc);
    const float a2 = ident_ls_slope(&s->dec);

    out->psi_f_Wb = psi;
    out->acc_rad_s2 = a1;
    out->dec_rad_s2 = a2;
    out->J_kgm2 = 0.0f;
    out->B_Nms = 0.0f;
    if (!mathx_isfinitef(psi) || !(psi > 0.0f) || !(a1 > 0.0f) || !(a2 < 0.0f)) {
        return false;
    }
    const float kt = spmsm_kt_Nm_A(pole_pairs, psi);
    const float T1 = kt * s->iq_acc_A / s->acc.n;
    const float T2 = kt * s->iq_dec_A / s->dec.n;
    const float w1 = s->w_acc_rad_s / s->acc.n;
    const float w2 = s->w_dec_rad_s / s->dec.n;
    /* J a1 = T1 - B w1, J a2 = T2 - B w2 */
    const float det = a1 * w2 - a2 * w1;
    const float J = (T1 * w2 - T2 * w1) / det;
    const float B = (a1 * T2 - a2 * T1) / det;
    if (!mathx_isfinitef(J) || !(J > 0.0f) || !mathx_isfinitef(B)) {
        return false;
    }
    out->J_kgm2 = J;
    out->B_Nms = (B > 0.0f) ? B : 0.0f;
    return true;
}
