/* commission.c - commissioning: measure the motor; see commission.h and
 * firmware/commission_design.md. */
#include "commission.h"

#include "mathx.h"


/* Torque per (pole pair x flux x i_q) of an SPMSM: Te = 1.5 p psi_f i_q. */
#define TORQUE_FACTOR 1.5f
/* R seek: the regulator's error is judged over blocks of this length, and
 * the seek ends when a block's mean |error| is below this share of I1. */
#define SEEK_BLOCK_S 0.01f
#define SEEK_TOL 0.05f
/* The output vector's angle: the middle of the period it is applied in,
 * 1.5 periods after the sample (one period of computation delay). */
#define OUT_ANGLE_PERIODS 1.5f
/* Fewest samples a fit accepts. */
#define FIT_N_MIN 20.0f

/* R phases */
enum { R_SEEK = 0, R_SETTLE_1, R_WIN_1, R_SETTLE_2, R_WIN_2 };
/* L phases */
enum { L_DOWN = 0, L_UP };
/* ENCODER phases */
enum { E_HOLD_0 = 0, E_FWD, E_HOLD_1, E_BACK, E_HOLD_2 };
/* SPIN phases */
enum { S_ACCEL = 0, S_BRAKE };
/* WIRING phases */
enum { W_RAMP = 0, W_HOLD, W_MEASURE };
/* WIRING: the weaker sequence of the current above this share of the
 * stronger is no phase order but an open phase (single phase: 1). */
#define WIRING_SEQ_RATIO_MAX 0.5f

/* Field by field: a struct copy may become a memset, a library call
 * that runs from flash (the ISR path's check, make check). */
FLASHFUNC static void ls_clear(comm_ls_t *s)
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

FLASHFUNC static void ls_add(comm_ls_t *s, float x1, float x2, float y)
{
    s->n += 1.0f;
    s->s1 += x1;
    s->s2 += x2;
    s->sy += y;
    s->s11 += x1 * x1;
    s->s12 += x1 * x2;
    s->s22 += x2 * x2;
    s->s1y += x1 * y;
    s->s2y += x2 * y;
}

/* Slope of y on x1 with a constant; 0 when it cannot be solved (every use needs one of a sign). */
FLASHFUNC static float ls_slope1(const comm_ls_t *s)
{
    const float c11 = s->s11 - s->s1 * s->s1 / s->n;
    const float c1y = s->s1y - s->s1 * s->sy / s->n;
    return ((s->n >= FIT_N_MIN) && (c11 > 0.0f)) ? c1y / c11 : 0.0f;
}

/* Coefficient of x1 in y = b1 x1 + b2 x2 + c; 0 when it cannot be solved. */
FLASHFUNC static float ls_coef1(const comm_ls_t *s)
{
    const float c11 = s->s11 - s->s1 * s->s1 / s->n;
    const float c12 = s->s12 - s->s1 * s->s2 / s->n;
    const float c22 = s->s22 - s->s2 * s->s2 / s->n;
    const float c1y = s->s1y - s->s1 * s->sy / s->n;
    const float c2y = s->s2y - s->s2 * s->sy / s->n;
    const float det = c11 * c22 - c12 * c12;
    return ((s->n >= FIT_N_MIN) && (det > 0.0f)) ? (c1y * c22 - c2y * c12) / det : 0.0f;
}

FLASHFUNC static uint32_t periods(const comm_t *m, float t_s)
{
    return app_periods_of(t_s, m->Ts_s);
}

FLASHFUNC static void next_phase(comm_t *m, uint16_t phase)
{
    m->phase = phase;
    m->ticks = 0u;
}

FLASHFUNC static void next_stage(comm_t *m, comm_stage_t stage)
{
    m->stage = stage;
    m->stage_ticks = 0u;
    next_phase(m, 0u);
}

FLASHFUNC void comm_speed_pi(const comm_cfg_t *cfg, float J_kgm2, float *kp_Nms_rad, float *ki_Nm_rad)
{
    *kp_Nms_rad = cfg->speed_kp_per_J_1_s * J_kgm2;
    *ki_Nm_rad = cfg->speed_ki_per_J_1_s2 * J_kgm2;
}

void comm_init(comm_t *m, const comm_cfg_t *cfg, float Ts_s, uint32_t enc_cpr, uint16_t pole_pairs)
{
    const enc_check_cfg_t ecfg = { enc_cpr, pole_pairs };

    m->cfg = *cfg;
    m->Ts_s = Ts_s;
    m->enc_cpr = enc_cpr;
    m->pole_pairs = pole_pairs;
    m->w_turn_ticks = app_periods_of(1.0f / cfg->wiring_el_hz, Ts_s);
    m->w_dangle_el_rad = (m->w_turn_ticks > 0u) ? MATHX_TWO_PI_F / (float)m->w_turn_ticks : 0.0f;
    /* whole turns over the R stage's window, at least one */
    m->w_turns = (m->w_turn_ticks > 0u) ? app_periods_of(cfg->r_window_s, Ts_s) / m->w_turn_ticks : 1u;
    m->w_turns = (m->w_turns > 0u) ? m->w_turns : 1u;
    enc_check_init(&m->chk, &ecfg);
    comm_start(m);
    m->stage = COMM_STAGE_NONE;
}

FLASHFUNC void comm_start(comm_t *m)
{
    next_stage(m, COMM_STAGE_WIRING);
    m->w_u_V = 0.0f;
    m->w_angle_el_rad = 0.0f;
    enc_check_start(&m->chk, 0u);
    (void)enc_check_verdict(&m->chk, &m->chk_out); /* the empty figures */
    m->cycles = 0u;
    m->u_a_V = 0.0f;
    m->u_b_V = 0.0f;
    m->xd_V = 0.0f;
    m->xq_V = 0.0f;
    m->ki_V_As = 0.0f;
    m->ki0_V_As = 0.0f;
    m->kp_V_A = 0.0f;
    m->out_a_V = 0.0f;
    m->out_b_V = 0.0f;
    m->i_ref_A = m->cfg.r_i1_frac * m->cfg.i_max_A;
    m->err_abs_A = 0.0f;
    m->sum_u = 0.0f;
    m->sum_i = 0.0f;
    m->n_win = 0.0f;
    m->U1_V = 0.0f;
    m->I1_A = 0.0f;
    m->U2_V = 0.0f;
    m->I2_A = 0.0f;
    m->R0_Ohm = 0.0f;
    m->y_Vs = 0.0f;
    m->u_prev_V = 0.0f;
    m->u_prev2_V = 0.0f;
    m->di_prev_A = 0.0f;
    ls_clear(&m->ls);
    ls_clear(&m->ls2);
    ls_clear(&m->ls3);
    m->iq_sum1 = 0.0f;
    m->w_sum1 = 0.0f;
    m->iq_sum2 = 0.0f;
    m->w_sum2 = 0.0f;
    m->theta_c_rad = 0.0f;
    m->count0 = 0u;
    m->count_last = 0u;
    m->dcount = 0.0f;
    m->top_rad_s = 0.0f;
    m->w_ref_rad_s = 0.0f;
    m->y_ref_V = 0.0f;
    m->res.R_Ohm = 0.0f;
    m->res.L_H = 0.0f;
    m->res.psi_f_Wb = 0.0f;
    m->res.pole_pairs = 0u;
    m->res.J_kgm2 = 0.0f;
    m->res.B_Nms = 0.0f;
    m->res.enc_offset_el_rad = 0.0f;
    m->res.speed_kp_Nms_rad = 0.0f;
    m->res.speed_ki_Nm_rad = 0.0f;
    m->res.u_err_V = 0.0f;
    m->res.cpr_per_el = 0.0f;
}

/* The voltage limit of the stages [V]: u_frac of the inscribed circle. */
FLASHFUNC static float u_limit_V(const comm_t *m, float vdc_V)
{
    return m->cfg.u_frac * vdc_V * MATHX_INV_SQRT3_F;
}

/* count - from [counts], the shorter way round the turn (signed). */
FLASHFUNC static float count_diff(const comm_t *m, uint32_t count, uint32_t from)
{
    int32_t d = (int32_t)count - (int32_t)from;
    const int32_t half = (int32_t)(m->enc_cpr / 2u);

    if (d > half) {
        d -= (int32_t)m->enc_cpr;
    } else if (d < -half) {
        d += (int32_t)m->enc_cpr;
    }
    return (float)d;
}

/* ---- R: integral regulator on alpha (I1, I2) and beta (0) --------------- */

FLASHFUNC static void window_add(comm_t *m, float u, float i)
{
    m->sum_u += u;
    m->sum_i += i;
    m->n_win += 1.0f;
}

FLASHFUNC static void window_drop(comm_t *m)
{
    m->sum_u = 0.0f;
    m->sum_i = 0.0f;
    m->n_win = 0.0f;
}

/* The window's means (it has at least one period), emptied. */
FLASHFUNC static void window_take(comm_t *m, float *U, float *I)
{
    *U = m->sum_u / m->n_win;
    *I = m->sum_i / m->n_win;
    window_drop(m);
}

/* ---- WIRING: a fast voltage vector, the phase order (enc_check) --------- */

/* The stage's planned length [periods]: the ramp, the hold, the window in
 * whole turns of the vector. */
FLASHFUNC static uint32_t wiring_periods(const comm_t *m)
{
    return periods(m, m->cfg.r_ramp_s) + periods(m, m->cfg.enc_hold_s) + m->w_turns * m->w_turn_ticks;
}

FLASHFUNC static app_step_t wiring_verdict(comm_t *m)
{
    const app_step_t r = enc_check_phase_order(&m->chk, &m->chk_out);
    const float hi = (m->chk_out.i_pos_A > m->chk_out.i_neg_A) ? m->chk_out.i_pos_A : m->chk_out.i_neg_A;
    const float lo = (m->chk_out.i_pos_A > m->chk_out.i_neg_A) ? m->chk_out.i_neg_A : m->chk_out.i_pos_A;

    /* one sequence dominates unless a phase is open (a single-phase
     * current is half positive, half negative sequence) */
    if (!(lo <= WIRING_SEQ_RATIO_MAX * hi)) {
        return app_step_fault(APP_FAULT_COMM_IMPLAUSIBLE, lo, WIRING_SEQ_RATIO_MAX * hi);
    }
    return r;
}

FLASHFUNC static app_step_t stage_wiring(comm_t *m, const ctrl_in_t *in, ab_t i, ab_t *u_ab)
{
    const comm_cfg_t *c = &m->cfg;
    const float I = c->enc_frac * c->i_max_A;
    /* the amplitude's integral regulator on |i|: the R seek's gain */
    const float k_V_As = in->vdc_V / (c->i_max_A * c->r_seek_s);
    const float i_abs = mathx_sqrtf(i.a * i.a + i.b * i.b);
    float i_ref = I;
    float s;
    float co;
    app_step_t r = app_step_running();

    /* the currents sampled now answer the vector applied over the last period */
    mathx_sincosf(m->w_angle_el_rad, &s, &co);
    switch (m->phase) {
    case W_RAMP:
        i_ref = I * mathx_clampf((float)m->ticks * m->Ts_s / c->r_ramp_s, 0.0f, 1.0f);
        if (m->ticks >= periods(m, c->r_ramp_s)) {
            next_phase(m, W_HOLD);
        }
        break;
    case W_HOLD:
        if (m->ticks >= periods(m, c->enc_hold_s)) {
            enc_check_start(&m->chk, in->enc_count);
            next_phase(m, W_MEASURE);
        }
        break;
    default: /* W_MEASURE */
        enc_check_step(&m->chk, m->w_dangle_el_rad, co, s, i.a, i.b, in->enc_count);
        if (m->ticks >= m->w_turns * m->w_turn_ticks) {
            r = wiring_verdict(m);
        }
        break;
    }
    m->w_angle_el_rad = mathx_wrap_2pi(m->w_angle_el_rad + m->w_dangle_el_rad);
    m->w_u_V += k_V_As * m->Ts_s * (i_ref - i_abs);
    m->w_u_V = (m->w_u_V > 0.0f) ? m->w_u_V : 0.0f;
    if ((r.status == APP_STEP_RUNNING) && (m->w_u_V > u_limit_V(m, in->vdc_V))) {
        r = app_step_fault(APP_FAULT_COMM_IMPLAUSIBLE, m->w_u_V, u_limit_V(m, in->vdc_V));
    }
    if (r.status == APP_STEP_DONE) {
        m->w_u_V = 0.0f;
        next_stage(m, COMM_STAGE_R);
        r = app_step_running();
    }
    mathx_sincosf(m->w_angle_el_rad, &s, &co);
    u_ab->a = m->w_u_V * co;
    u_ab->b = m->w_u_V * s;
    return r;
}

FLASHFUNC static app_step_t stage_r(comm_t *m, ab_t i, uint32_t count)
{
    const comm_cfg_t *c = &m->cfg;
    const float I1 = c->r_i1_frac * c->i_max_A;
    bool still;
    float e_a;
    float i_ref_b = 0.0f;
    app_step_t r = app_step_running();

    if (m->phase == R_SEEK) {
        /* ramped at the pre-position, then turned onto phase a: the rotor
         * follows without a swing, and no start angle is a dead point of
         * both (startup_design.md, "Alignment") */
        const float t = (float)m->stage_ticks * m->Ts_s;
        const float mag = I1 * mathx_clampf(t / c->r_ramp_s, 0.0f, 1.0f);
        const float phi = c->r_prepos_el_rad * (1.0f - mathx_clampf((t - c->r_ramp_s) / c->r_ramp_s, 0.0f, 1.0f));
        float sn;
        float cs;
        mathx_sincosf(phi, &sn, &cs);
        m->i_ref_A = mag * cs;
        i_ref_b = mag * sn;
    }
    e_a = m->i_ref_A - i.a;

    /* integral, plus a virtual resistance that bounds the current the
     * rotor's swing induces; beta's integral slow: a current the back-EMF
     * drives on it damps the swing */
    m->u_a_V += m->ki_V_As * m->Ts_s * e_a;
    m->u_b_V += m->ki0_V_As * m->Ts_s * (i_ref_b - i.b);
    m->out_a_V = m->u_a_V + m->kp_V_A * e_a;
    m->out_b_V = m->u_b_V + m->kp_V_A * (i_ref_b - i.b);
    /* still: the count within r_still_rad of where the settling began */
    if ((m->phase == R_SETTLE_1) || (m->phase == R_SETTLE_2)) {
        if (m->ticks == 0u) {
            m->count_last = count;
        }
    }
    still = mathx_fabsf(count_diff(m, count, m->count_last)) <=
            c->r_still_rad * (float)m->enc_cpr / MATHX_TWO_PI_F;
    if (!still) {
        m->count_last = count;
    }
    switch (m->phase) {
    case R_SEEK:
        m->err_abs_A += mathx_fabsf(e_a);
        if (m->stage_ticks < 2u * periods(m, c->r_ramp_s)) {
            m->err_abs_A = 0.0f;
            m->ticks = 0u;
        } else if (m->ticks >= periods(m, SEEK_BLOCK_S)) {
            if (m->err_abs_A < SEEK_TOL * m->i_ref_A * (float)m->ticks) {
                m->R0_Ohm = m->u_a_V / m->i_ref_A; /* with the inverter's error: a first estimate */
                if (!(m->R0_Ohm > 0.0f)) {
                    return app_step_fault(APP_FAULT_COMM_IMPLAUSIBLE, m->R0_Ohm, 0.0f);
                }
                m->ki_V_As = c->r_bw_rad_s * m->R0_Ohm;
                next_phase(m, R_SETTLE_1);
            } else {
                m->err_abs_A = 0.0f;
                m->ticks = 0u;
            }
        }
        break;
    case R_SETTLE_1:
    case R_SETTLE_2:
        if (!still) {
            m->ticks = 0u; /* the rotor still turns onto phase a: its back-EMF would bias R */
        } else if (m->ticks >= periods(m, c->r_settle_s)) {
            next_phase(m, (uint16_t)(m->phase + 1u));
        }
        break;
    case R_WIN_1:
        if (!still) {
            window_drop(m);
            next_phase(m, R_SETTLE_1);
            break;
        }
        window_add(m, m->out_a_V, i.a);
        if (m->ticks >= periods(m, c->r_window_s)) {
            window_take(m, &m->U1_V, &m->I1_A);
            m->i_ref_A = c->r_i2_frac * c->i_max_A;
            next_phase(m, R_SETTLE_2);
        }
        break;
    default: /* R_WIN_2 */
        if (!still) {
            window_drop(m);
            next_phase(m, R_SETTLE_2);
            break;
        }
        window_add(m, m->out_a_V, i.a);
        if (m->ticks >= periods(m, c->r_window_s)) {
            float R;
            window_take(m, &m->U2_V, &m->I2_A);
            R = (m->U2_V - m->U1_V) / (m->I2_A - m->I1_A);
            if (!mathx_isfinitef(R) || !(R > 0.0f)) {
                return app_step_fault(APP_FAULT_COMM_IMPLAUSIBLE, R, 0.0f);
            }
            m->res.R_Ohm = R;
            m->res.u_err_V = m->U1_V - R * m->I1_A;
            next_stage(m, COMM_STAGE_L);
            m->u_a_V = m->U2_V - R * c->l_step_frac * c->i_max_A;
        }
        break;
    }
    return r;
}

/* ---- L: open-loop steps on alpha around (U2, I2) ------------------------ */

FLASHFUNC static app_step_t stage_l(comm_t *m, ab_t i)
{
    const comm_cfg_t *c = &m->cfg;
    const float R = m->res.R_Ohm;
    const float dI = c->l_step_frac * c->i_max_A;
    const float di = i.a - m->I2_A;

    /* the period just ended had the voltage commanded two calls ago
     * applied (hal.h: duties take effect at the next period's start):
     * L (di(k) - di(k-1)) = Ts (du(k-2) - R (di(k) + di(k-1)) / 2) */
    if (m->stage_ticks > 0u) {
        m->y_Vs += m->Ts_s * ((m->u_prev2_V - m->U2_V) - R * 0.5f * (di + m->di_prev_A));
    }
    ls_add(&m->ls, di, (float)m->stage_ticks * m->Ts_s, m->y_Vs);
    m->di_prev_A = di;
    m->u_b_V -= m->ki0_V_As * m->Ts_s * i.b;
    m->out_b_V = m->u_b_V - m->kp_V_A * i.b;
    if ((m->phase == L_DOWN) && (di <= -c->l_rise_frac * dI)) {
        m->u_a_V = m->U2_V;
        next_phase(m, L_UP);
    } else if ((m->phase == L_UP) && (di >= -(1.0f - c->l_rise_frac) * dI)) {
        m->cycles++;
        if (m->cycles >= c->l_cycles) {
            const float L = ls_coef1(&m->ls);
            /* a time constant L / R of at least a period */
            if (!mathx_isfinitef(L) || !(L > R * m->Ts_s)) {
                return app_step_fault(APP_FAULT_COMM_IMPLAUSIBLE, L, R * m->Ts_s);
            }
            m->res.L_H = L;
            next_stage(m, COMM_STAGE_ENCODER);
            m->xd_V = m->u_a_V;
            m->xq_V = m->out_b_V;
            m->theta_c_rad = 0.0f;
            ls_clear(&m->ls);
        } else {
            m->u_a_V = m->U2_V - R * dI;
            next_phase(m, L_DOWN);
        }
    }
    return app_step_running();
}

/* ---- dq current PI (ENCODER, SPIN) --------------------------------------- */

/* One period of the PI at the measurement angle theta (sin/cos given) for
 * i_ref; the voltage at theta_out into *u_ab; returns |u_dq| [V]. */
FLASHFUNC static float current_pi(comm_t *m, ab_t i, float s, float co, dq_t i_ref, float theta_out, ab_t *u_ab, dq_t *u_dq)
{
    const dq_t i_dq = park(i, s, co);
    const float kp = m->cfg.i_bw_rad_s * m->res.L_H;
    const float kiT = m->cfg.i_bw_rad_s * m->res.R_Ohm * m->Ts_s;
    const float ed = i_ref.d - i_dq.d;
    const float eq = i_ref.q - i_dq.q;
    float so;
    float cout;

    u_dq->d = kp * ed + m->xd_V;
    u_dq->q = kp * eq + m->xq_V;
    m->xd_V += kiT * ed;
    m->xq_V += kiT * eq;
    mathx_sincosf(theta_out, &so, &cout);
    *u_ab = park_inv(*u_dq, so, cout);
    return mathx_sqrtf(u_dq->d * u_dq->d + u_dq->q * u_dq->q);
}

/* Signed count change since the last period, the shorter way round [counts]. */
FLASHFUNC static float count_step(comm_t *m, uint32_t count)
{
    const float d = count_diff(m, count, m->count_last);

    m->count_last = count;
    return d;
}

/* ---- ENCODER: a vector swept one electrical turn forward and back -------- */

FLASHFUNC static app_step_t encoder_result(comm_t *m)
{
    const float s = ls_slope1(&m->ls); /* counts per rad el */
    const float cpr = (float)m->enc_cpr;
    const uint16_t p = m->pole_pairs;  /* WIRING checked it against the counts */
    uint32_t c0p;
    float mean_theta;
    float mean_dc;

    if (!(s > 0.0f)) { /* WIRING saw the counts follow the vector */
        return app_step_fault(APP_FAULT_COMM_IMPLAUSIBLE, s, 0.0f);
    }
    m->res.pole_pairs = p;
    m->res.cpr_per_el = MATHX_TWO_PI_F * s;
    /* theta_c = offset + p 2 pi (count0 + dcount + 1/2) / cpr on average
     * (encoder.h's count centre); count0 p reduced mod cpr first */
    c0p = mathx_umod_u32(m->count0 * (uint32_t)p, m->enc_cpr);
    mean_theta = m->ls.s1 / m->ls.n + MATHX_PI_F;
    mean_dc = m->ls.sy / m->ls.n;
    m->res.enc_offset_el_rad =
        mathx_wrap_2pi(mean_theta - ((float)c0p + (float)p * (0.5f + mean_dc)) * (MATHX_TWO_PI_F / cpr));
    return app_step_done();
}

/* The ENCODER stage's planned length [periods]: the told pole pairs'
 * turns forward, one back, three holds. */
FLASHFUNC static uint32_t encoder_periods(const comm_t *m)
{
    return (1u + (uint32_t)m->pole_pairs) * periods(m, MATHX_TWO_PI_F / m->cfg.enc_speed_el_rad_s) +
           3u * periods(m, m->cfg.enc_hold_s);
}

FLASHFUNC static app_step_t stage_encoder(comm_t *m, const ctrl_in_t *in, ab_t i, ab_t *u_ab)
{
    const comm_cfg_t *c = &m->cfg;
    const float step = c->enc_speed_el_rad_s * m->Ts_s;
    const uint32_t sweep = periods(m, MATHX_TWO_PI_F / c->enc_speed_el_rad_s);
    const uint32_t fwd = (uint32_t)m->pole_pairs * sweep; /* one mechanical turn */
    const uint32_t hold = periods(m, c->enc_hold_s);
    const dq_t i_ref = { c->enc_frac * c->i_max_A, 0.0f };
    bool fit = false;
    float dir = 0.0f;
    float s;
    float co;
    dq_t u_dq;
    app_step_t r = app_step_running();

    if (m->stage_ticks == 0u) {
        m->count_last = in->enc_count;
    }
    m->dcount += count_step(m, in->enc_count);
    switch (m->phase) {
    case E_HOLD_0:
        if (m->ticks >= hold) {
            m->count0 = in->enc_count;
            m->dcount = 0.0f;
            enc_check_start(&m->chk, in->enc_count);
            next_phase(m, E_FWD);
        }
        break;
    case E_FWD:
        /* the current follows the vector: its angle is the measurement's */
        mathx_sincosf(m->theta_c_rad, &s, &co);
        enc_check_step(&m->chk, step, co, s, i.a, i.b, in->enc_count);
        dir = 1.0f;
        m->theta_c_rad = (float)m->ticks * step;
        fit = (m->ticks + sweep > fwd); /* the last electrical turn */
        if (m->ticks >= fwd) {
            const float moved = m->dcount;
            const float min_moved = 0.5f * (float)m->enc_cpr / (float)c->pole_pairs_max;
            if (mathx_fabsf(moved) < min_moved) {
                return app_step_fault(APP_FAULT_COMM_NO_ROTATION, moved, min_moved);
            }
            r = enc_check_verdict(&m->chk, &m->chk_out); /* direction, counts per turn, pole pairs */
            if (r.status != APP_STEP_DONE) {
                return r;
            }
            r = app_step_running();
            dir = 0.0f;
            next_phase(m, E_HOLD_1);
        }
        break;
    case E_HOLD_1:
        if (m->ticks >= hold) {
            next_phase(m, E_BACK);
        }
        break;
    case E_BACK:
        dir = -1.0f;
        fit = true;
        m->theta_c_rad = (float)(fwd - m->ticks) * step;
        if (m->ticks >= sweep) {
            dir = 0.0f;
            next_phase(m, E_HOLD_2);
        }
        break;
    default: /* E_HOLD_2 */
        if (m->ticks >= hold) {
            r = encoder_result(m);
            if (r.status == APP_STEP_DONE) {
                next_stage(m, COMM_STAGE_SPIN);
                ls_clear(&m->ls);
                r = app_step_running();
            }
        }
        break;
    }
    if (fit) {
        ls_add(&m->ls, m->theta_c_rad - MATHX_PI_F, 0.0f, m->dcount);
    }
    mathx_sincosf(m->theta_c_rad, &s, &co);
    if (current_pi(m, i, s, co, i_ref, m->theta_c_rad + OUT_ANGLE_PERIODS * dir * step, u_ab, &u_dq) >
        u_limit_V(m, in->vdc_V)) {
        return app_step_fault(APP_FAULT_COMM_IMPLAUSIBLE, mathx_sqrtf(u_dq.d * u_dq.d + u_dq.q * u_dq.q),
                              u_limit_V(m, in->vdc_V));
    }
    return r;
}

/* ---- SPIN: accelerate at +I, brake at -I -------------------------------- */

FLASHFUNC static app_step_t spin_result(comm_t *m)
{
    const float p = (float)m->res.pole_pairs;
    const float psi = ls_slope1(&m->ls);
    const float a1 = ls_slope1(&m->ls2);
    const float a2 = ls_slope1(&m->ls3);
    float T1;
    float T2;
    float w1;
    float w2;
    float det;
    float J;
    float B;

    if (!mathx_isfinitef(psi) || !(psi > 0.0f)) {
        return app_step_fault(APP_FAULT_COMM_IMPLAUSIBLE, psi, 0.0f);
    }
    if (!(a1 > 0.0f) || !(a2 < 0.0f)) { /* 0: too few samples */
        return app_step_fault(APP_FAULT_COMM_IMPLAUSIBLE, a1, a2);
    }
    T1 = TORQUE_FACTOR * p * psi * m->iq_sum1 / m->ls2.n;
    T2 = TORQUE_FACTOR * p * psi * m->iq_sum2 / m->ls3.n;
    w1 = m->w_sum1 / m->ls2.n;
    w2 = m->w_sum2 / m->ls3.n;
    /* J a1 = T1 - B w1, J a2 = T2 - B w2 */
    det = a1 * w2 - a2 * w1;
    J = (T1 * w2 - T2 * w1) / det;
    B = (a1 * T2 - a2 * T1) / det;
    if (!mathx_isfinitef(J) || !(J > 0.0f) || !mathx_isfinitef(B)) {
        return app_step_fault(APP_FAULT_COMM_IMPLAUSIBLE, J, 0.0f);
    }
    m->res.psi_f_Wb = psi;
    m->res.J_kgm2 = J;
    m->res.B_Nms = (B > 0.0f) ? B : 0.0f; /* a negative B is the fits' noise */
    comm_speed_pi(&m->cfg, J, &m->res.speed_kp_Nms_rad, &m->res.speed_ki_Nm_rad);
    return app_step_done();
}

FLASHFUNC static app_step_t stage_spin(comm_t *m, const ctrl_in_t *in, ab_t i, float w, ab_t *u_ab)
{
    const comm_cfg_t *c = &m->cfg;
    const float p = (float)m->res.pole_pairs;
    const float top = c->spin_top_frac * c->speed_max_rad_s;
    const float lo = c->spin_lo_frac * top;
    const bool fit = (m->ticks >= periods(m, c->spin_skip_s)) && (w >= lo);
    const uint32_t elec = mathx_umod_u32(in->enc_count * (uint32_t)m->res.pole_pairs, m->enc_cpr);
    const float theta = m->res.enc_offset_el_rad +
                        ((float)elec + 0.5f * p) * (MATHX_TWO_PI_F / (float)m->enc_cpr);
    const float w_e = p * w;
    const float t = (float)m->ticks * m->Ts_s;
    dq_t i_ref = { 0.0f, c->spin_frac * c->i_max_A };
    dq_t i_dq;
    dq_t u_dq;
    float s;
    float co;
    float u_abs;

    mathx_sincosf(theta, &s, &co);
    i_dq = park(i, s, co);
    if (m->phase == S_BRAKE) {
        i_ref.q = -i_ref.q;
    }
    u_abs = current_pi(m, i, s, co, i_ref, theta + OUT_ANGLE_PERIODS * w_e * m->Ts_s, u_ab, &u_dq);
    if (m->phase == S_ACCEL) {
        if (fit) {
            if (m->ls.n < 0.5f) {
                m->w_ref_rad_s = w;
                m->y_ref_V = u_dq.q - m->res.R_Ohm * i_dq.q;
            }
            ls_add(&m->ls, w_e - p * m->w_ref_rad_s, 0.0f, (u_dq.q - m->res.R_Ohm * i_dq.q) - m->y_ref_V);
            ls_add(&m->ls2, t, 0.0f, w - m->w_ref_rad_s);
            m->iq_sum1 += i_dq.q;
            m->w_sum1 += w;
        }
        if ((w >= top) || (u_abs > u_limit_V(m, in->vdc_V))) {
            m->top_rad_s = w;
            next_phase(m, S_BRAKE);
        }
    } else {
        if (fit && (m->ticks > 0u)) {
            ls_add(&m->ls3, t, 0.0f, w - m->w_ref_rad_s);
            m->iq_sum2 += i_dq.q;
            m->w_sum2 += w;
        }
        if (w < lo) {
            return spin_result(m);
        }
    }
    return app_step_running();
}

/* ---- the sequence ------------------------------------------------------- */

FLASHFUNC static float stage_max_s(const comm_t *m)
{
    switch (m->stage) {
    case COMM_STAGE_WIRING:
        return (float)wiring_periods(m) * m->Ts_s + m->cfg.enc_max_s;
    case COMM_STAGE_ENCODER:
        return (float)encoder_periods(m) * m->Ts_s + m->cfg.enc_max_s;
    case COMM_STAGE_R:
        return m->cfg.r_max_s;
    case COMM_STAGE_L:
        return m->cfg.l_max_s;
    default:
        return m->cfg.spin_max_s;
    }
}

float comm_max_s(const comm_t *m)
{
    return (float)(wiring_periods(m) + encoder_periods(m)) * m->Ts_s + 2.0f * m->cfg.enc_max_s + m->cfg.r_max_s +
           m->cfg.l_max_s + m->cfg.spin_max_s;
}

FLASHFUNC app_step_t comm_step(comm_t *m, const ctrl_in_t *in, float speed_m_rad_s, ab_t *u_ab_V)
{
    const ab_t i = clarke_2ph(in->ia_A, in->ib_A);
    const bool open_loop = (m->stage == COMM_STAGE_R) || (m->stage == COMM_STAGE_L); /* u from u_a, u_b */
    app_step_t r;

    if (m->stage_ticks > periods(m, stage_max_s(m))) {
        u_ab_V->a = 0.0f;
        u_ab_V->b = 0.0f;
        return app_step_fault(APP_FAULT_COMM_TIMEOUT, (float)m->stage_ticks * m->Ts_s, stage_max_s(m));
    }
    if (m->stage == COMM_STAGE_R) {
        if ((m->phase == R_SEEK) && (m->ki_V_As <= 0.0f)) {
            m->ki0_V_As = in->vdc_V / (m->cfg.i_max_A * m->cfg.r_seek_s);
            m->kp_V_A = m->cfg.r_kp_frac * in->vdc_V / m->cfg.i_max_A;
            m->ki_V_As = m->ki0_V_As;
        }
        r = stage_r(m, i, in->enc_count);
    } else if (m->stage == COMM_STAGE_L) {
        r = stage_l(m, i);
    } else if (m->stage == COMM_STAGE_WIRING) {
        r = stage_wiring(m, in, i, u_ab_V);
    } else if (m->stage == COMM_STAGE_ENCODER) {
        r = stage_encoder(m, in, i, u_ab_V);
    } else {
        r = stage_spin(m, in, i, speed_m_rad_s, u_ab_V);
    }
    if (open_loop) {
        float u_abs;
        if (m->stage == COMM_STAGE_L) {
            m->out_a_V = m->u_a_V; /* open loop */
        }
        u_abs = mathx_sqrtf(m->out_a_V * m->out_a_V + m->out_b_V * m->out_b_V);
        u_ab_V->a = m->out_a_V;
        u_ab_V->b = m->out_b_V;
        m->u_prev2_V = m->u_prev_V;
        m->u_prev_V = m->out_a_V;
        if ((r.status == APP_STEP_RUNNING) && (u_abs > u_limit_V(m, in->vdc_V))) {
            r = app_step_fault(APP_FAULT_COMM_IMPLAUSIBLE, u_abs, u_limit_V(m, in->vdc_V));
        }
    }
    if (r.status == APP_STEP_DONE) {
        m->stage = COMM_STAGE_DONE;
    }
    m->ticks++;
    m->stage_ticks++;
    return r;
}

