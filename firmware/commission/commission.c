/* commission.c - commissioning: the sequence, its timing and its refusals;
 * the motor math is control/ident.h's. See commission.h and
 * firmware/commission/commission_design.md. */
#include "commission.h"

#include "mathx.h"
#include "spmsm.h"

/* R seek: the regulator's error is judged over blocks of this length, and
 * the seek ends when a block's mean |error| is below this share of I1. */
#define SEEK_BLOCK_S 0.01f
#define SEEK_TOL 0.05f
/* A raised cosine's time per (half-turn angle x top speed), T = pi^2 / (2 w_top) for pi [-] */
#define HALF_TURN_T_PER_PI2 0.5f
#define HALF 0.5f

/* R phases */
enum { R_SEEK = 0, R_POINT_1, R_POINT_2 };
/* L phases */
enum { L_DOWN = 0, L_UP };
/* INVERTER phases: half a turn, the two points with every current reversed
 * (the ENCODER stage starts where it ends: no turn back, no swing) */
enum { INV_TURN = 0, INV_POINT_1, INV_POINT_2 };
/* ENCODER phases */
enum { E_HOLD_0 = 0, E_FWD, E_HOLD_1, E_BACK, E_HOLD_2 };
/* SPIN phases */
enum { S_ACCEL = 0, S_BRAKE, S_RETURN };
/* WIRING phases */
enum { W_RAMP = 0, W_HOLD, W_MEASURE };
/* WIRING: the weaker sequence of the current above this share of the
 * stronger is no phase order but an open phase (single phase: 1). */
#define WIRING_SEQ_RATIO_MAX 0.5f

FLASHFUNC static uint32_t periods(const comm_t *m, float t_s)
{
    return app_periods_of(t_s, m->Ts_s);
}

FLASHFUNC static void next_phase(comm_t *m, uint16_t phase)
{
    m->phase = phase;
    m->ticks = 0u;
    m->phase_new = true;
    m->in_window = false;
}

FLASHFUNC static void next_stage(comm_t *m, comm_stage_t stage)
{
    m->stage = stage;
    m->stage_ticks = 0u;
    m->stage_new = true;
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

FLASHFUNC static void clear_result(comm_result_t *r)
{
    r->R_Ohm = 0.0f;
    r->L_H = 0.0f;
    r->psi_f_Wb = 0.0f;
    r->pole_pairs = 0u;
    r->J_kgm2 = 0.0f;
    r->B_Nms = 0.0f;
    r->enc_offset_el_rad = 0.0f;
    r->speed_kp_Nms_rad = 0.0f;
    r->speed_ki_Nm_rad = 0.0f;
    r->u_err_V = 0.0f;
    r->inv_dv_V = 0.0f;
    r->deadtime_s = 0.0f;
    r->device_drop_V = 0.0f;
    r->untold_deadtime_s = 0.0f;
    r->cpr_per_el = 0.0f;
}

FLASHFUNC void comm_start(comm_t *m)
{
    next_stage(m, COMM_STAGE_WIRING);
    m->w_angle_el_rad = 0.0f;
    enc_check_start(&m->chk, 0u);
    (void)enc_check_verdict(&m->chk, &m->chk_out); /* the empty figures */
    m->cycles = 0u;
    m->u_a_V = 0.0f;
    m->u_prev_V = 0.0f;
    m->u_prev2_V = 0.0f;
    m->i_ref_A = m->cfg.r_i1_frac * m->cfg.i_max_A;
    m->err_abs_A = 0.0f;
    m->u_lim_V = 0.0f;
    ident_win_reset(&m->win);
    ident_ls_reset(&m->ls);
    ident_spin_reset(&m->spin);
    m->theta_c_rad = 0.0f;
    m->theta0_rad = 0.0f;
    m->count0 = 0u;
    m->count_last = 0u;
    m->still_count = 0u;
    m->dcount = 0.0f;
    clear_result(&m->res);
    m->phase_new = false; /* the next call is the stage's first period */
    m->stage_new = false;
}

/* The voltage bound of the stages [V]: u_frac of the inscribed circle. */
FLASHFUNC static float u_limit_V(const comm_t *m, float vdc_V)
{
    return m->cfg.u_frac * vdc_V * MATHX_INV_SQRT3_F;
}

/* The regulators' output bound [V]: the inscribed circle, the linear
 * range of the modulation (the plausibility bound u_frac of it faults first). */
FLASHFUNC static float u_pi_max_V(float vdc_V)
{
    return vdc_V * MATHX_INV_SQRT3_F;
}

/* The virtual resistance of the DC regulators [V/A] (R_v, design sec. 1). */
FLASHFUNC static float r_virtual_Ohm(const comm_t *m, float vdc_V)
{
    return m->cfg.r_kp_frac * vdc_V / m->cfg.i_max_A;
}

/* The seek's integral gain [V/(A s)]: a full-bound error ramps the voltage through vdc in r_seek_s. */
FLASHFUNC static float ki_seek_V_As(const comm_t *m, float vdc_V)
{
    return vdc_V / (m->cfg.i_max_A * m->cfg.r_seek_s);
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

/* Signed count change since the last period, the shorter way round [counts]. */
FLASHFUNC static float count_step(comm_t *m, uint32_t count)
{
    const float d = count_diff(m, count, m->count_last);

    m->count_last = count;
    return d;
}

/* ---- a DC point: settle with the rotor still, then a window ------------- */

/* Still: the count within r_still_rad of where the settling began (the
 * back-EMF of a swinging rotor would bias the window). */
FLASHFUNC static bool rotor_still(comm_t *m, uint32_t count)
{
    bool still;

    if (!m->in_window && (m->ticks == 0u)) {
        m->still_count = count;
    }
    still = mathx_fabsf(count_diff(m, count, m->still_count)) <=
            m->cfg.r_still_rad * (float)m->enc_cpr / MATHX_TWO_PI_F;
    if (!still) {
        m->still_count = count;
    }
    return still;
}

/* Settling for r_settle_s of a still rotor, then a window of r_window_s of
 * the alpha voltage commanded u_V and current i_A (a moving rotor starts
 * the settling again): true in the period the point is in *pt. */
FLASHFUNC static bool dc_point(comm_t *m, uint32_t count, float u_V, float i_A, ident_point_t *pt)
{
    const bool still = rotor_still(m, count);

    if (!m->in_window) {
        if (!still) {
            m->ticks = 0u;
        } else if (m->ticks >= periods(m, m->cfg.r_settle_s)) {
            m->in_window = true;
            m->ticks = 0u;
        }
        return false;
    }
    if (!still) {
        ident_win_reset(&m->win);
        m->in_window = false;
        m->ticks = 0u;
        return false;
    }
    ident_win_add(&m->win, u_V, i_A);
    if (m->ticks >= periods(m, m->cfg.r_window_s)) {
        *pt = ident_win_take(&m->win);
        m->in_window = false;
        return true;
    }
    return false;
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

/* The amplitude's regulator on |i| (pi.h): the R seek's gains, its output
 * within [0, the inscribed circle]; false when pi_init refuses them. */
FLASHFUNC static bool wiring_begin(comm_t *m, float vdc_V)
{
    pi_cfg_t c;
    c.Kp = r_virtual_Ohm(m, vdc_V);
    c.Ki = ki_seek_V_As(m, vdc_V);
    c.Ts_s = m->Ts_s;
    c.u_min = 0.0f;
    c.u_max = u_pi_max_V(vdc_V);
    return pi_init(&m->wiring, &c);
}

FLASHFUNC static app_step_t stage_wiring(comm_t *m, const ctrl_in_t *in, ab_t i, ab_t *u_ab)
{
    const comm_cfg_t *c = &m->cfg;
    const float I = c->enc_frac * c->i_max_A;
    float i_ref = I;
    float s;
    float co;
    app_step_t r = app_step_running();

    if ((m->stage_ticks == 0u) && !wiring_begin(m, in->vdc_V)) {
        return app_step_fault(APP_FAULT_COMM_IMPLAUSIBLE, r_virtual_Ohm(m, in->vdc_V), 0.0f);
    }
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
    const float u = pi_step(&m->wiring, i_ref - mathx_sqrtf(i.a * i.a + i.b * i.b));
    if ((r.status == APP_STEP_RUNNING) && (u > u_limit_V(m, in->vdc_V))) {
        r = app_step_fault(APP_FAULT_COMM_IMPLAUSIBLE, u, u_limit_V(m, in->vdc_V));
    }
    mathx_sincosf(m->w_angle_el_rad, &s, &co);
    u_ab->a = u * co;
    u_ab->b = u * s;
    if (r.status == APP_STEP_DONE) {
        u_ab->a = 0.0f;
        u_ab->b = 0.0f;
        next_stage(m, COMM_STAGE_R);
        r = app_step_running();
    }
    return r;
}

/* ---- R: DC injection on alpha (I1, I2), beta on 0 ------------------------ */

/* The DC regulator from the bus of the stage's first period: seek gains. */
FLASHFUNC static bool r_begin(comm_t *m, float vdc_V)
{
    ident_dc_cfg_t c;
    c.Ts_s = m->Ts_s;
    c.kp_V_A = r_virtual_Ohm(m, vdc_V);
    c.ki_V_As = ki_seek_V_As(m, vdc_V);
    c.u_max_V = u_pi_max_V(vdc_V);
    return ident_dc_init(&m->dc, &c);
}

/* The seek's reference [A]: I1 ramped at the pre-position, then turned
 * onto phase a: the rotor follows without a swing, and no start angle is a
 * dead point of both (startup_design.md, "Alignment"). */
FLASHFUNC static ab_t r_seek_ref(const comm_t *m)
{
    const comm_cfg_t *c = &m->cfg;
    const float t = (float)m->stage_ticks * m->Ts_s;
    const float mag = c->r_i1_frac * c->i_max_A * mathx_clampf(t / c->r_ramp_s, 0.0f, 1.0f);
    const float phi = c->r_prepos_el_rad * (1.0f - mathx_clampf((t - c->r_ramp_s) / c->r_ramp_s, 0.0f, 1.0f));
    float sn;
    float cs;
    ab_t ref;

    mathx_sincosf(phi, &sn, &cs);
    ref.a = mag * cs;
    ref.b = mag * sn;
    return ref;
}

/* The seek's end: a block's mean |error| on alpha below SEEK_TOL of I1
 * once the ramp and the turn are over; then R0 = U / I1 (the inverter's
 * error in it: a first estimate) sets alpha's faster integral gain. */
FLASHFUNC static app_step_t r_seek(comm_t *m, float e_a, float u_a)
{
    const comm_cfg_t *c = &m->cfg;
    const float I1 = c->r_i1_frac * c->i_max_A;

    m->err_abs_A += mathx_fabsf(e_a);
    if (m->stage_ticks < 2u * periods(m, c->r_ramp_s)) {
        m->err_abs_A = 0.0f;
        m->ticks = 0u;
    } else if (m->ticks >= periods(m, SEEK_BLOCK_S)) {
        if (m->err_abs_A < SEEK_TOL * I1 * (float)m->ticks) {
            const float R0 = u_a / I1;
            if (!(R0 > 0.0f) || !ident_dc_set_ki_a(&m->dc, c->r_bw_rad_s * R0)) {
                return app_step_fault(APP_FAULT_COMM_IMPLAUSIBLE, R0, 0.0f);
            }
            m->i_ref_A = I1;
            next_phase(m, R_POINT_1);
        } else {
            m->err_abs_A = 0.0f;
            m->ticks = 0u;
        }
    }
    return app_step_running();
}

/* R from the two points; the constant error at I1 kept (u_err_V). */
FLASHFUNC static app_step_t r_finish(comm_t *m)
{
    const float R = ident_r_of_points(m->pos[0], m->pos[1]);

    if (!mathx_isfinitef(R) || !(R > 0.0f)) {
        return app_step_fault(APP_FAULT_COMM_IMPLAUSIBLE, R, 0.0f);
    }
    m->res.R_Ohm = R;
    m->res.u_err_V = m->pos[0].U_V - R * m->pos[0].I_A;
    next_stage(m, COMM_STAGE_L);
    ident_l_start(&m->l, m->Ts_s, m->pos[1]);
    m->u_a_V = m->pos[1].U_V - R * m->cfg.l_step_frac * m->cfg.i_max_A;
    return app_step_running();
}

FLASHFUNC static app_step_t stage_r(comm_t *m, const ctrl_in_t *in, ab_t i, ab_t *u_ab)
{
    const comm_cfg_t *c = &m->cfg;
    ab_t ref = { m->i_ref_A, 0.0f };
    ident_point_t pt;
    app_step_t r = app_step_running();

    if ((m->stage_ticks == 0u) && !r_begin(m, in->vdc_V)) {
        return app_step_fault(APP_FAULT_COMM_IMPLAUSIBLE, r_virtual_Ohm(m, in->vdc_V), 0.0f);
    }
    if (m->phase == R_SEEK) {
        ref = r_seek_ref(m);
    }
    /* integral, plus a virtual resistance that bounds the current the
     * rotor's swing induces; beta's integral slow: a current the back-EMF
     * drives on it damps the swing */
    *u_ab = ident_dc_step(&m->dc, ref, i);
    switch (m->phase) {
    case R_SEEK:
        r = r_seek(m, ref.a - i.a, u_ab->a);
        break;
    case R_POINT_1:
        if (dc_point(m, in->enc_count, u_ab->a, i.a, &pt)) {
            m->pos[0] = pt;
            m->i_ref_A = c->r_i2_frac * c->i_max_A;
            next_phase(m, R_POINT_2);
        }
        break;
    default: /* R_POINT_2 */
        if (dc_point(m, in->enc_count, u_ab->a, i.a, &pt)) {
            m->pos[1] = pt;
            r = r_finish(m);
        }
        break;
    }
    return r;
}

/* ---- L: open-loop steps on alpha around (U2, I2) ------------------------ */

/* The dq PI (INVERTER, ENCODER, SPIN) from R^ and L^, bumpless from the
 * voltage applied at the L stage's end (the rotor's d axis on alpha). */
FLASHFUNC static app_step_t l_finish(comm_t *m, float L, float vdc_V, float u_b_V)
{
    const float R = m->res.R_Ohm;
    const dq_t u0 = { m->u_a_V, u_b_V };

    /* a time constant L / R of at least a period (the PI's Ts Ki <= Kp) */
    if (!mathx_isfinitef(L) || !(L > R * m->Ts_s) ||
        !ident_cur_init(&m->cur, m->Ts_s, m->cfg.i_bw_rad_s, R, L, u_pi_max_V(vdc_V), u0)) {
        return app_step_fault(APP_FAULT_COMM_IMPLAUSIBLE, L, R * m->Ts_s);
    }
    m->res.L_H = L;
    next_stage(m, COMM_STAGE_INVERTER);
    m->theta_c_rad = 0.0f;
    m->i_ref_A = m->cfg.r_i2_frac * m->cfg.i_max_A;
    return app_step_running();
}

FLASHFUNC static app_step_t stage_l(comm_t *m, const ctrl_in_t *in, ab_t i, ab_t *u_ab)
{
    const comm_cfg_t *c = &m->cfg;
    const float R = m->res.R_Ohm;
    const float dI = c->l_step_frac * c->i_max_A;
    const float di = i.a - m->l.op.I_A;

    /* the period just ended had the voltage commanded two calls ago (spmsm.h) */
    ident_l_step(&m->l, i.a, m->u_prev2_V, R);
    u_ab->b = ident_dc_step_b(&m->dc, i.b);
    if ((m->phase == L_DOWN) && (di <= -c->l_rise_frac * dI)) {
        m->u_a_V = m->l.op.U_V;
        next_phase(m, L_UP);
    } else if ((m->phase == L_UP) && (di >= -(1.0f - c->l_rise_frac) * dI)) {
        m->cycles++;
        if (m->cycles >= c->l_cycles) {
            u_ab->a = m->u_a_V;
            return l_finish(m, ident_l_solve(&m->l), in->vdc_V, u_ab->b);
        }
        m->u_a_V = m->l.op.U_V - R * dI;
        next_phase(m, L_DOWN);
    }
    u_ab->a = m->u_a_V;
    return app_step_running();
}

/* ---- the vector's current PI (INVERTER, ENCODER) -------------------------- */

/* One period of the dq PI in the vector's frame at theta_c (the current
 * follows the vector: the measurement's angle), the voltage turned at the
 * angle it acts at, the vector turning at speed_el_rad_s [rad/s el]
 * (spmsm.h's advance). */
FLASHFUNC static void vector_pi(comm_t *m, ab_t i, float i_ref_A, float speed_el_rad_s, ab_t *u_ab)
{
    const dq_t ref = { i_ref_A, 0.0f };
    float s;
    float co;
    float so;
    float cout;

    mathx_sincosf(m->theta_c_rad, &s, &co);
    const dq_t u = ident_cur_step(&m->cur, ref, park(i, s, co));
    mathx_sincosf(m->theta_c_rad + spmsm_angle_advance_rad(speed_el_rad_s, m->Ts_s), &so, &cout);
    *u_ab = park_inv(u, so, cout);
}

/* ---- INVERTER: the R stage's points with every current reversed ---------- */

/* Periods of half an electrical turn on a raised cosine whose top speed is
 * the sweep's, pi^2 / (2 T): it starts and stops without a step of speed,
 * so it leaves the rotor little swing to settle from. */
FLASHFUNC static uint32_t half_turn_periods(const comm_t *m)
{
    return periods(m, HALF_TURN_T_PER_PI2 * MATHX_PI_F * MATHX_PI_F / m->cfg.enc_speed_el_rad_s);
}

/* The stage's planned length [periods]: the half turn, two settlings, two windows. */
FLASHFUNC static uint32_t inverter_periods(const comm_t *m)
{
    return half_turn_periods(m) + 2u * (periods(m, m->cfg.r_settle_s) + periods(m, m->cfg.r_window_s));
}

/* The per-leg error, its split at this bus and what the measurement leaves uncertain. */
FLASHFUNC static app_step_t inverter_finish(comm_t *m, float vdc_V)
{
    ident_inv_t inv;

    ident_inv_solve(m->res.R_Ohm, m->pos, m->neg, &inv);
    if (!mathx_isfinitef(inv.dv_V) || !mathx_isfinitef(inv.spread_V) || !(vdc_V > 0.0f)) {
        return app_step_fault(APP_FAULT_COMM_IMPLAUSIBLE, inv.dv_V, 0.0f);
    }
    m->res.inv_dv_V = inv.dv_V;
    ident_inv_split(inv.dv_V, vdc_V, m->Ts_s, m->cfg.deadtime_s, &m->res.deadtime_s, &m->res.device_drop_V);
    m->res.untold_deadtime_s = inv.spread_V * m->Ts_s / vdc_V;
    return app_step_done();
}

/* The vector's angle this period: half a turn on a raised cosine, then
 * held; its speed [rad/s el]. */
FLASHFUNC static float inverter_angle(comm_t *m)
{
    const uint32_t N = half_turn_periods(m);
    const float x = MATHX_PI_F * (float)((m->ticks < N) ? m->ticks : N) / (float)N;
    float s;
    float co;

    if (m->phase != INV_TURN) {
        return 0.0f;
    }
    mathx_sincosf(x, &s, &co);
    m->theta_c_rad = HALF * MATHX_PI_F * (1.0f - co);
    return HALF * MATHX_PI_F * MATHX_PI_F / ((float)N * m->Ts_s) * s;
}

FLASHFUNC static app_step_t stage_inverter(comm_t *m, const ctrl_in_t *in, ab_t i, ab_t *u_ab)
{
    const comm_cfg_t *c = &m->cfg;
    ident_point_t pt;
    app_step_t r = app_step_running();

    vector_pi(m, i, m->i_ref_A, inverter_angle(m), u_ab);
    switch (m->phase) {
    case INV_TURN:
        if (m->ticks >= half_turn_periods(m)) {
            next_phase(m, INV_POINT_1);
        }
        break;
    case INV_POINT_1:
        if (dc_point(m, in->enc_count, u_ab->a, i.a, &pt)) {
            m->neg[0] = pt;
            m->i_ref_A = c->r_i1_frac * c->i_max_A;
            next_phase(m, INV_POINT_2);
        }
        break;
    default: /* INV_POINT_2 */
        if (dc_point(m, in->enc_count, u_ab->a, i.a, &pt)) {
            m->neg[1] = pt;
            r = inverter_finish(m, in->vdc_V);
        }
        break;
    }
    if (r.status == APP_STEP_DONE) {
        m->theta0_rad = m->theta_c_rad; /* the sweeps start from the vector's angle here */
        next_stage(m, COMM_STAGE_ENCODER);
        ident_ls_reset(&m->ls);
        r = app_step_running();
    }
    return r;
}

/* ---- ENCODER: a vector swept one mechanical turn forward, one electrical back */

/* Periods of one electrical turn at the sweep speed. */
FLASHFUNC static uint32_t turn_periods(const comm_t *m)
{
    return periods(m, MATHX_TWO_PI_F / m->cfg.enc_speed_el_rad_s);
}

/* The ENCODER stage's planned length [periods]: the told pole pairs'
 * turns forward, one back, three holds. */
FLASHFUNC static uint32_t encoder_periods(const comm_t *m)
{
    return (1u + (uint32_t)m->pole_pairs) * turn_periods(m) + 3u * periods(m, m->cfg.enc_hold_s);
}

/* The offset from the fit over the last turn forward and the turn back. */
FLASHFUNC static app_step_t encoder_result(comm_t *m)
{
    float s; /* counts per rad el */
    const float off = ident_enc_offset(&m->ls, m->count0, m->pole_pairs, m->enc_cpr, &s);

    if (!(s > 0.0f)) { /* WIRING saw the counts follow the vector */
        return app_step_fault(APP_FAULT_COMM_IMPLAUSIBLE, s, 0.0f);
    }
    m->res.pole_pairs = m->pole_pairs; /* checked against the counts by the forward sweep */
    m->res.cpr_per_el = MATHX_TWO_PI_F * s;
    m->res.enc_offset_el_rad = off;
    return app_step_done();
}

/* The forward sweep's end: travel, direction, counts per turn, pole pairs. */
FLASHFUNC static app_step_t encoder_fwd_verdict(comm_t *m)
{
    const float min_moved = 0.5f * (float)m->enc_cpr / (float)m->cfg.pole_pairs_max;

    if (mathx_fabsf(m->dcount) < min_moved) {
        return app_step_fault(APP_FAULT_COMM_NO_ROTATION, m->dcount, min_moved);
    }
    return enc_check_verdict(&m->chk, &m->chk_out);
}

/* One period of the sweep's phases: the vector's angle and direction,
 * whether the period joins the offset's fit, and the phase's end. */
/* The forward sweep's period: enc_check's sample, the vector one step
 * on, the last electrical turn into the offset's fit; at its end (one
 * mechanical turn) the verdict, then the hold. */
FLASHFUNC static app_step_t encoder_fwd(comm_t *m, const ctrl_in_t *in, ab_t i, float *speed, bool *fit)
{
    const float step = m->cfg.enc_speed_el_rad_s * m->Ts_s;
    const uint32_t fwd = (uint32_t)m->pole_pairs * turn_periods(m); /* one mechanical turn */
    float s;
    float co;
    app_step_t r = app_step_running();

    mathx_sincosf(m->theta_c_rad, &s, &co);
    enc_check_step(&m->chk, step, co, s, i.a, i.b, in->enc_count);
    *speed = m->cfg.enc_speed_el_rad_s;
    m->theta_c_rad = m->theta0_rad + (float)m->ticks * step;
    *fit = (m->ticks + turn_periods(m) > fwd);
    if (m->ticks >= fwd) {
        r = encoder_fwd_verdict(m);
        if (r.status == APP_STEP_DONE) {
            r = app_step_running();
            *speed = 0.0f;
            next_phase(m, E_HOLD_1);
        }
    }
    return r;
}

FLASHFUNC static app_step_t encoder_phase(comm_t *m, const ctrl_in_t *in, ab_t i, float *speed, bool *fit)
{
    const uint32_t hold = periods(m, m->cfg.enc_hold_s);
    app_step_t r = app_step_running();

    *speed = 0.0f;
    *fit = false;
    switch (m->phase) {
    case E_HOLD_0:
        /* the sweep starts from a still rotor: the count0 must not catch a swing */
        if (!rotor_still(m, in->enc_count)) {
            m->ticks = 0u;
        } else if (m->ticks >= hold) {
            m->count0 = in->enc_count;
            m->dcount = 0.0f;
            enc_check_start(&m->chk, in->enc_count);
            next_phase(m, E_FWD);
        }
        break;
    case E_FWD:
        r = encoder_fwd(m, in, i, speed, fit);
        break;
    case E_HOLD_1:
        if (m->ticks >= hold) {
            next_phase(m, E_BACK);
        }
        break;
    case E_BACK:
        *speed = -m->cfg.enc_speed_el_rad_s;
        *fit = true;
        /* from the forward sweep's end, one mechanical turn on, back */
        m->theta_c_rad = m->theta0_rad + (float)((uint32_t)m->pole_pairs * turn_periods(m) - m->ticks) *
                                             (m->cfg.enc_speed_el_rad_s * m->Ts_s);
        if (m->ticks >= turn_periods(m)) {
            *speed = 0.0f;
            next_phase(m, E_HOLD_2);
        }
        break;
    default: /* E_HOLD_2 */
        if (m->ticks >= hold) {
            r = encoder_result(m);
        }
        break;
    }
    return r;
}

FLASHFUNC static app_step_t stage_encoder(comm_t *m, const ctrl_in_t *in, ab_t i, ab_t *u_ab)
{
    float speed;
    bool fit;
    app_step_t r;

    if (m->stage_ticks == 0u) {
        m->count_last = in->enc_count;
    }
    m->dcount += count_step(m, in->enc_count);
    r = encoder_phase(m, in, i, &speed, &fit);
    if (fit) {
        ident_ls_add(&m->ls, m->theta_c_rad - MATHX_PI_F, 0.0f, m->dcount);
    }
    vector_pi(m, i, m->cfg.enc_frac * m->cfg.i_max_A, speed, u_ab);
    if (r.status == APP_STEP_DONE) {
        next_stage(m, COMM_STAGE_SPIN);
        ident_spin_reset(&m->spin);
        m->sweep_n = 0.0f;
        r = app_step_running();
    }
    return r;
}

/* ---- SPIN: accelerate at +I, brake at -I -------------------------------- */

FLASHFUNC static app_step_t spin_result(comm_t *m)
{
    ident_spin_out_t o;

    if (!ident_spin_solve(&m->spin, m->res.pole_pairs, &o)) {
        return app_step_fault(APP_FAULT_COMM_IMPLAUSIBLE, o.psi_f_Wb, o.J_kgm2);
    }
    m->res.psi_f_Wb = o.psi_f_Wb;
    m->res.J_kgm2 = o.J_kgm2;
    m->res.B_Nms = o.B_Nms;
    comm_speed_pi(&m->cfg, o.J_kgm2, &m->res.speed_kp_Nms_rad, &m->res.speed_ki_Nm_rad);
    return app_step_done();
}

/* The sweep's end, at the bound [rad/s] in the direction dir (+1 up, -1
 * down): where the speed w [rad/s], moving at the acceleration seen since
 * the sweep's fits began, would reach it within the lag before a new
 * current acts on the true speed: the speed estimate's (speed_lag_s), the
 * current's reversal (1/i_bw) and the voltage's delay (spmsm.h). t_s the
 * phase's time [s]. No division: dir (w - bound + (w - w0) lag / (t - t0)) >= 0. */
FLASHFUNC static bool spin_at_bound(const comm_t *m, float w, float bound, float dir, float t_s)
{
    const float lag = m->cfg.speed_lag_s + 1.0f / m->cfg.i_bw_rad_s + (float)SPMSM_VOLTAGE_SEEN_PERIODS * m->Ts_s;

    if (dir * (w - bound) >= 0.0f) {
        return true;
    }
    /* the acceleration from at least a fit's fewest samples */
    return (m->sweep_n >= IDENT_LS_N_MIN) &&
           (dir * ((w - bound) * (t_s - m->sweep_t0_s) + (w - m->sweep_w0_rad_s) * lag) >= 0.0f);
}

/* The current commanded in phase `phase`: +I up to the top, -I down to
 * -top, +I back to standstill [A]. */
FLASHFUNC static float spin_iq_A(const comm_t *m)
{
    const float I = m->cfg.spin_frac * m->cfg.i_max_A;
    return (m->phase == S_BRAKE) ? -I : I;
}

/* One period of the current PI at the rotor's angle (the measured offset
 * and pole pairs), the voltage in the frame of the period it acts in;
 * u_dq and i_dq out. */
FLASHFUNC static void spin_pi(comm_t *m, const ctrl_in_t *in, ab_t i, float w, ab_t *u_ab, dq_t *u_dq, dq_t *i_dq)
{
    const uint16_t p = m->res.pole_pairs;
    const uint32_t elec = mathx_umod_u32(in->enc_count * (uint32_t)p, m->enc_cpr);
    const float theta =
        m->res.enc_offset_el_rad + ((float)elec + HALF * (float)p) * (MATHX_TWO_PI_F / (float)m->enc_cpr);
    const dq_t i_ref = { 0.0f, spin_iq_A(m) };
    float s;
    float co;

    mathx_sincosf(theta, &s, &co);
    *i_dq = park(i, s, co);
    *u_dq = ident_cur_step(&m->cur, i_ref, *i_dq);
    mathx_sincosf(theta + spmsm_angle_advance_rad((float)p * w, m->Ts_s), &s, &co);
    *u_ab = park_inv(*u_dq, s, co);
}

/* The sweeps' fits: the flux fit over every sweep once the speed estimate
 * has settled on its acceleration (spin_skip_s), the motion fits above
 * spin_lo_frac of the top speed on the way up and the way down. */
FLASHFUNC static void spin_fits(comm_t *m, float w, dq_t i_dq, float u_q_V)
{
    const comm_cfg_t *c = &m->cfg;
    const float t = (float)m->ticks * m->Ts_s;
    const bool negative = (m->phase == S_BRAKE);

    if (m->ticks < periods(m, c->spin_skip_s)) {
        return;
    }
    if (m->sweep_n < 0.5f) {
        m->sweep_t0_s = t;
        m->sweep_w0_rad_s = w;
    }
    m->sweep_n += 1.0f;
    ident_spin_add_flux(&m->spin, w, m->res.pole_pairs, i_dq, u_q_V, m->res.R_Ohm, negative);
    if ((m->phase != S_RETURN) && (w >= c->spin_lo_frac * c->spin_top_frac * c->speed_max_rad_s)) {
        ident_spin_add_motion(&m->spin, t, w, i_dq.q, negative);
    }
}

FLASHFUNC static void spin_next(comm_t *m, uint16_t phase)
{
    next_phase(m, phase);
    m->sweep_n = 0.0f;
}

FLASHFUNC static app_step_t stage_spin(comm_t *m, const ctrl_in_t *in, ab_t i, float w, ab_t *u_ab)
{
    const float top = m->cfg.spin_top_frac * m->cfg.speed_max_rad_s;
    const float t = (float)m->ticks * m->Ts_s;
    dq_t u_dq;
    dq_t i_dq;

    spin_pi(m, in, i, w, u_ab, &u_dq, &i_dq);
    spin_fits(m, w, i_dq, u_dq.q);
    /* a sweep ends at its speed bound, or where the back-EMF takes the voltage */
    const bool u_top = mathx_sqrtf(u_dq.d * u_dq.d + u_dq.q * u_dq.q) > u_limit_V(m, in->vdc_V);
    switch (m->phase) {
    case S_ACCEL:
        if (u_top || spin_at_bound(m, w, top, 1.0f, t)) {
            spin_next(m, S_BRAKE);
        }
        break;
    case S_BRAKE:
        if (u_top || spin_at_bound(m, w, -top, -1.0f, t)) {
            spin_next(m, S_RETURN);
        }
        break;
    default: /* S_RETURN: up to standstill, the gates off there */
        if (w >= 0.0f) {
            return spin_result(m);
        }
        break;
    }
    return app_step_running();
}

/* ---- the sequence ------------------------------------------------------- */

FLASHFUNC static float stage_max_s(const comm_t *m)
{
    switch (m->stage) {
    case COMM_STAGE_WIRING:
        return (float)wiring_periods(m) * m->Ts_s + m->cfg.enc_max_s;
    case COMM_STAGE_INVERTER:
        return (float)inverter_periods(m) * m->Ts_s + m->cfg.enc_max_s;
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
    return (float)(wiring_periods(m) + inverter_periods(m) + encoder_periods(m)) * m->Ts_s +
           3.0f * m->cfg.enc_max_s + m->cfg.r_max_s + m->cfg.l_max_s + m->cfg.spin_max_s;
}

/* The stage's period: its voltage into *u_ab_V. */
FLASHFUNC static app_step_t stage_step(comm_t *m, const ctrl_in_t *in, ab_t i, float speed_m_rad_s, ab_t *u_ab_V)
{
    switch (m->stage) {
    case COMM_STAGE_WIRING:
        return stage_wiring(m, in, i, u_ab_V);
    case COMM_STAGE_R:
        return stage_r(m, in, i, u_ab_V);
    case COMM_STAGE_L:
        return stage_l(m, in, i, u_ab_V);
    case COMM_STAGE_INVERTER:
        return stage_inverter(m, in, i, u_ab_V);
    case COMM_STAGE_ENCODER:
        return stage_encoder(m, in, i, u_ab_V);
    default:
        return stage_spin(m, in, i, speed_m_rad_s, u_ab_V);
    }
}

FLASHFUNC app_step_t comm_step(comm_t *m, const ctrl_in_t *in, float speed_m_rad_s, ab_t *u_ab_V)
{
    const ab_t i = clarke_2ph(in->ia_A, in->ib_A);
    /* WIRING judges its amplitude, SPIN ends its acceleration at the bound */
    const bool bounded = (m->stage != COMM_STAGE_WIRING) && (m->stage != COMM_STAGE_SPIN);
    app_step_t r;

    u_ab_V->a = 0.0f;
    u_ab_V->b = 0.0f;
    if (m->stage_ticks > periods(m, stage_max_s(m))) {
        return app_step_fault(APP_FAULT_COMM_TIMEOUT, (float)m->stage_ticks * m->Ts_s, stage_max_s(m));
    }
    if (m->stage_ticks == 0u) {
        m->u_lim_V = u_limit_V(m, in->vdc_V);
    }
    r = stage_step(m, in, i, speed_m_rad_s, u_ab_V);
    if (bounded && (r.status == APP_STEP_RUNNING)) {
        const float u_abs = mathx_sqrtf(u_ab_V->a * u_ab_V->a + u_ab_V->b * u_ab_V->b);
        if (u_abs > m->u_lim_V) {
            r = app_step_fault(APP_FAULT_COMM_IMPLAUSIBLE, u_abs, m->u_lim_V);
        }
    }
    if (r.status == APP_STEP_DONE) {
        m->stage = COMM_STAGE_DONE;
    }
    m->u_prev2_V = m->u_prev_V;
    m->u_prev_V = u_ab_V->a;
    /* a phase or stage begun in this call has its first period in the next */
    m->ticks = m->phase_new ? 0u : (m->ticks + 1u);
    m->stage_ticks = m->stage_new ? 0u : (m->stage_ticks + 1u);
    m->phase_new = false;
    m->stage_new = false;
    return r;
}
