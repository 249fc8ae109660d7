/*
 * ctrl.c - the drive controller; see ctrl.h.
 *
 * Cost per ctrl_step(): `make bench-ctrl` measures it (instructions,
 * divisions, square roots and sin/cos per step, both methods, track_R on
 * and off). Where the divisions are: MTPA's q flux, svpwm_duty's 1/Vdc
 * and the inverter error's 1/Vdc (both methods); the transfer law whose turn it is and the observer's
 * gain on L^'s turns (proposed); dbdtc_set_params only when the model
 * moved by more than CTRL_MODEL_UPDATE_REL; 3 more only in the periods
 * the hexagon limit acts. One sin/cos (the advanced angle is a rotation
 * by a short series). The start-up (ctrl_init, ctrl_cfg_told), the
 * reset and the current limit's and the alignment's setters are in
 * ctrl_cfg.c (flash).
 */
#include "ctrl.h"

#include "inverr.h"
#include "mathx.h"
#include "oplim.h"
#include "svpwm.h"

#define DUTY_ZERO_VOLTAGE 0.5f

/* The model takes the observer's L^, psi^ when they moved by more than
 * this share since it last did: below it the change of the torque and
 * flux targets is 1e-4 of theirs, and the 2 divisions of
 * dbdtc_set_params are saved in the periods of steady state. */
#define CTRL_MODEL_UPDATE_REL 1.0e-4f
#define MODEL_EST      CTRL_MODEL_EST
#define MODEL_NOMINAL  CTRL_MODEL_NOMINAL

static uint16_t map_dbdtc_flags(uint16_t f)
{
    uint16_t out = 0u;
    if ((f & DBDTC_FLAG_VOLTAGE_LIMIT) != 0u) {
        out |= CTRL_FLAG_VOLTAGE_LIMIT;
    }
    if ((f & DBDTC_FLAG_FLUX_UNREACHABLE) != 0u) {
        out |= CTRL_FLAG_FLUX_UNREACHABLE;
    }
    return out;
}

/* The torque limit for the model now in c->db.par: te_max, times the
 * model's kt over the told one's when it follows kt (the torque the same
 * current gives with the learned psi_f); the speed PI's output limits
 * with it, when it moved. When the model changes. */
void ctrl_take_te_limit(ctrl_t *c)
{
    const float te = (c->te_per_psi_Nm_Wb > 0.0f) ? (c->te_per_psi_Nm_Wb * c->db.par.psi_f_Wb) : c->cfg.te_max_Nm;
    if (te != c->te_lim_Nm) {
        c->te_lim_Nm = te;
        pi_set_limits(&c->speed_pi, -te, te);
    }
}


rs_ident_result_t ctrl_rsid_finish(ctrl_t *c, rs_ident_result_t r_solved)
{
    const rs_ident_result_t r = est_rsid_finish_with(&c->est, r_solved);
    const float d = est_angle_error_el_rad(&c->est);
    if ((r == RS_IDENT_OK) && ((d > 0.0f) || (d < 0.0f))) {
        /* the angle read lags the rotor's by d: the offset takes it up */
        encoder_set_offset(&c->enc, c->enc.offset_el_rad + d);
        est_angle_corrected(&c->est);
    }
    return r;
}

void ctrl_set_mode(ctrl_t *c, ctrl_mode_t mode)
{
    c->mode_req = mode;
}

bool ctrl_set_method(ctrl_t *c, ctrl_method_t method)
{
    if ((method == CTRL_METHOD_PROPOSED) && ((c->status & CTRL_CFG_NEEDED_PROPOSED) != 0u)) {
        return false;
    }
    c->method = method; /* one store: the ISR sees the old or the new method */
    return true;
}

void ctrl_set_ref(ctrl_t *c, const ctrl_ref_t *ref)
{
    c->ref = *ref;
}

void ctrl_set_speed_ref(ctrl_t *c, float speed_ref_rad_s)
{
    c->ref.speed_ref_rad_s = speed_ref_rad_s;
}

/*
 * The model stage: the parameters in use (c->db.par) and the state at
 * k+1 that compensates the one-period delay; the one place the methods
 * differ. The proposed method takes the estimation's model as its src
 * says (est.h): the state from the observer's i^(k+1) (eq. 11, 12), or
 * eq. (10) with held estimates; the told model otherwise, as the
 * conventional method. 2 divisions in dbdtc_set_params, only when the
 * model moved by more than CTRL_MODEL_UPDATE_REL or was re-based.
 */
static dbdtc_state_t ctrl_model(ctrl_t *c, dq_t i_dq_A, const zoh_turn_t *turn)
{
    const est_out_t *e = est_output(&c->est);
    bool from = false;     /* the period's model with the observer's g_c */
    bool observed = false; /* the state at k+1 the observer's i^(k+1) */
    if ((c->method == CTRL_METHOD_PROPOSED) && (e->src != EST_SRC_TOLD)) {
        const dbdtc_par_t *p = &c->db.par;
        if ((c->model_src != MODEL_EST) || ((e->moved & EST_MOVED_ALL) != 0u) ||
            (p->zm.L_H != est_zoh_model(&c->est)->L_H) || /* the observer's decay, taken since */
            (((e->moved & EST_MOVED_LPSI) != 0u) &&
             ((mathx_fabsf(e->L_H - p->L_H) > CTRL_MODEL_UPDATE_REL * p->L_H) ||
              (mathx_fabsf(e->psi_f_Wb - p->psi_f_Wb) > CTRL_MODEL_UPDATE_REL * p->psi_f_Wb)))) {
            dbdtc_set_params_zm(&c->db, e->R_Ohm, e->L_H, e->psi_f_Wb, est_zoh_model(&c->est));
            ctrl_take_te_limit(c);
            c->model_src = MODEL_EST;
            c->mon.model_from_observer = 1u; /* the monitor's, written when it changes */
        }
        /* the observer's R^, L^: its period's model (one division for both); held estimates,
         * eq. (10): the observer's g_c when it was taken in this turn for this R and L (within the
         * observer's own SMO_MODEL_UPDATE_REL), else the model's own */
        const zoh_model_t *zo = est_zoh_model(&c->est);
        observed = (e->src == EST_SRC_OBSERVER);
        from = observed || (est_zoh_taken_in(&c->est, turn) && (zo->R_Ohm == p->zm.R_Ohm) &&
                            (mathx_fabsf(zo->L_H - p->L_H) <= SMO_MODEL_UPDATE_REL * p->L_H));
    } else if (c->model_src != MODEL_NOMINAL) {
        dbdtc_reset(&c->db); /* back to the told model: 4 divisions once */
        ctrl_take_te_limit(c);
        c->model_src = MODEL_NOMINAL;
        c->mon.model_from_observer = 0u;
    } else {
        /* the told model, taken */
    }
    /* one place each below: each is inline (ctrl_step_design.md sec. 3) */
    if (from) {
        dbdtc_period_from(&c->db, turn, est_zoh_g_c(&c->est), est_zoh_rev(&c->est));
    } else {
        dbdtc_period(&c->db, turn);
    }
    /* the observer's i^(k+1) replaces eq. (10) (within the observer's i_max, the model's:
     * init_est); else eq. (10)-(12) */
    return observed ? dbdtc_state_from_bounded(&c->db, est_i_hat_A(&c->est))
                    : dbdtc_predict(&c->db, i_dq_A, c->u_applied_V);
}

/* Mean stator-frame voltage error [V] the dead time and the device drop add
 * over the period whose middle is at the angle (sin_a, cos_a), for the
 * voltage u_V the duties will realise: each leg loses or gains vdc*td/Ts
 * + drop against the sign of its current (the currents taken as i_dq at
 * that angle) where the current's ripple at its edges does not take it
 * through zero (inverr.h, inverter_error_design.md sec. 8); the ripple's
 * largest into c->ripple_A for the estimation. 1 division. */
static ab_t deadtime_error(ctrl_t *c, dq_t i_dq_A, float sin_a, float cos_a, float vdc_V, ab_t u_V)
{
    const abc_t i = clarke_inv(park_inv(i_dq_A, sin_a, cos_a));
    /* below the speed floor the conventional path: the told dead time and drop only */
    const float dv_dead = c->deadtime_frac * vdc_V;
    const float dv_drop = c->device_drop_V + est_output(&c->est)->inv_dv_V;
    /* an identified over-compensation at most cancels the told one */
    const bool some = (dv_dead + dv_drop) > 0.0f;
    /* a bus below SVPWM's floor is refused there: no ripple (mid duties) here */
    const float inv_vdc = (vdc_V >= SVPWM_VDC_MIN_V) ? (1.0f / vdc_V) : 0.0f;
    return inverr_error_V(i, u_V, inv_vdc, inverr_k_A_V(c->cfg.Ts_s, c->db.par.inv_L_1_H), some ? dv_dead : 0.0f,
                          some ? dv_drop : 0.0f, &c->ripple_A);
}

/* sin/cos of the angle the voltage computed now acts at, the middle of
 * [k+1, k+2]: theta(k) + 1.5 w Ts (spmsm.h's timing), a rotation by the
 * period's turn and its half (zoh.h), saving a second sincos. */
static void advance_sincos(float s, float c, const zoh_turn_t *t, float *s_out, float *c_out)
{
    const float c15 = t->c1 * t->ch - t->s1 * t->sh;
    const float s15 = t->s1 * t->ch + t->c1 * t->sh;
    *s_out = s * c15 + c * s15;
    *c_out = c * c15 - s * s15;
}

/* The period's duties out; when not finite (the period's check sum, or
 * SVPWM refused its input), 50 % duties, no realised voltage and
 * CTRL_FLAG_NONFINITE. */
static void output_duties(ctrl_t *c, svpwm_duty_t duty, bool finite, uint16_t flags, ctrl_out_t *out)
{
    if (!finite) {
        duty.a = DUTY_ZERO_VOLTAGE;
        duty.b = DUTY_ZERO_VOLTAGE;
        duty.c = DUTY_ZERO_VOLTAGE;
        c->u_applied_V.d = 0.0f;
        c->u_applied_V.q = 0.0f;
        flags |= CTRL_FLAG_NONFINITE;
    }
    out->duty[0] = duty.a;
    out->duty[1] = duty.b;
    out->duty[2] = duty.c;
    out->flags = flags;
}

void ctrl_step_ab(ctrl_t *c, ab_t u_ab_V, float vdc_V, ctrl_out_t *out)
{
    svpwm_duty_t duty;
    ab_t u_real;
    float s;
    float co;
    uint16_t flags = 0u;
    const uint16_t pwm_flags = svpwm_duty(u_ab_V, vdc_V, &duty, &u_real);

    if ((pwm_flags & SVPWM_SATURATED) != 0u) {
        flags |= CTRL_FLAG_VOLTAGE_LIMIT;
    }
    mathx_sincosf(c->enc.theta_e_rad, &s, &co);
    c->u_applied_V = park(u_real, s, co);
    /* one finiteness check: NaN and Inf survive a sum */
    const float chk = u_ab_V.a + u_ab_V.b + vdc_V + duty.a + duty.b + duty.c + c->u_applied_V.d + c->u_applied_V.q;
    output_duties(c, duty, mathx_isfinitef(chk) && ((pwm_flags & SVPWM_INVALID_INPUT) == 0u), flags, out);
}

/* One period's working values, stage to stage. */
typedef struct {
    float s, co;             /* sin, cos of theta_el(k) */
    float omega;             /* w(k) [rad/s electrical] */
    dq_t i_dq;               /* i(k) [A] */
    dbdtc_state_t x;         /* the model's state at k+1 */
    float te_ref;            /* Te* [N m] (0 in open loop) */
    float psi_ref;           /* psi_s* [Wb] (0 in open loop) */
    dq_t u;                  /* the voltage for [k+1, k+2] [V] */
    svpwm_duty_t duty;
    uint16_t flags;          /* CTRL_FLAG_* */
} ctrl_period_t;

/* Stage mode: the mode asked for, bumplessly into speed mode. */
static void stage_mode(ctrl_t *c)
{
    if (c->mode_req != c->mode) {
        if (c->mode_req == CTRL_MODE_SPEED) {
            pi_reset(&c->speed_pi, c->te_est_last_Nm); /* start from the torque there is */
        }
        c->mode = c->mode_req;
    }
}

/* Stage sample: angle and speed (this period's ctrl_track), i(k) in the rotor frame. */
static void stage_sample(ctrl_t *c, const ctrl_in_t *in, ctrl_period_t *p)
{
    if (!c->tracked) {
        encoder_step(&c->enc, in->enc_count);
    }
    c->tracked = false;
    /* w(k) within the model's bound (every user's) */
    p->omega = mathx_clampf(c->enc.omega_e_rad_s, c->omega_lo_rad_s, c->cfg.omega_max_el_rad_s);
    if (!(mathx_fabsf(p->omega - c->turn.w_rad_s) <= c->turn_tol_rad_s)) {
        zoh_turn(p->omega * c->cfg.Ts_s, p->omega, &c->turn); /* the turn moved: taken anew (zoh.h) */
    }
    mathx_sincosf(c->enc.theta_e_rad, &p->s, &p->co);
    p->i_dq = park(clarke_2ph(in->ia_A, in->ib_A), p->s, p->co);
}

/* Stage estimate: the estimation's period (est.h) on i(k), w(k) and the
 * voltage u(k) the last period realised. */
static void stage_estimate(ctrl_t *c, const ctrl_period_t *p, float vdc_V)
{
    est_in_t *e = &c->est_in; /* in ctrl_t, not on the ISR's stack */
    e->i_dq_A = p->i_dq;
    e->omega_el_rad_s = p->omega;
    e->turn = &c->turn;
    e->sin_el = p->s;
    e->cos_el = p->co;
    e->u_V = c->u_applied_V;
    e->vdc_V = vdc_V;
    e->te_ref_Nm = c->te_ref_last_Nm;
    e->voltage_limited = (c->flags_last & CTRL_FLAG_VOLTAGE_LIMIT) != 0u;
    e->dpsi_weak_Wb = c->lim.dpsi_Wb;
    e->ripple_A = c->ripple_A;
    est_step(&c->est, e);
}

/* Stage references: Te* from the speed PI (speed mode) or the reference (torque mode). */
static void stage_references(ctrl_t *c, ctrl_period_t *p)
{
    p->te_ref = 0.0f;
    if (c->mode == CTRL_MODE_SPEED) {
        p->te_ref = pi_step(&c->speed_pi, c->ref.speed_ref_rad_s - c->enc.omega_m_rad_s);
    } else if (c->mode == CTRL_MODE_TORQUE) {
        p->te_ref = mathx_clampf(c->ref.te_ref_Nm, -c->te_lim_Nm, c->te_lim_Nm);
    } else {
        /* open loop: no torque reference */
    }
}

/* Stage limits: current limit, MTPA (sec. III), flux weakening (oplim.h)
 * -> Te*, psi_s*; the injection's L id* on psi_s* (inverter_error_design.md sec. 3). */
static void stage_limits(ctrl_t *c, ctrl_period_t *p)
{
    p->psi_ref = 0.0f;
    if (c->mode != CTRL_MODE_OPEN_LOOP) {
        const oplim_out_t tgt = oplim_targets(&c->lim, &c->db.par, c->i_lim_A, p->te_ref);
        p->te_ref = tgt.te_Nm;
        p->psi_ref = est_psi_ref(&c->est, tgt.psi_Wb, c->db.par.L_H);
    }
}

/* Stage deadbeat: eq. (17) -> u(k+1), the field weakening's voltage
 * check; open loop: u from the reference. */
static void stage_deadbeat(ctrl_t *c, ctrl_period_t *p, float vdc_V)
{
    p->flags = 0u;
    if (c->mode == CTRL_MODE_OPEN_LOOP) {
        p->u.d = mathx_clampf(c->ref.ud_ref_V, -c->cfg.u_max_V, c->cfg.u_max_V);
        p->u.q = mathx_clampf(c->ref.uq_ref_V, -c->cfg.u_max_V, c->cfg.u_max_V);
    } else {
        p->flags = map_dbdtc_flags(dbdtc_solve(&c->db, &p->x, p->te_ref, p->psi_ref, &p->u));
        if (!est_identifying(&c->est)) {
            oplim_fw_update(&c->lim, p->u, c->u_lim_per_vdc * vdc_V);
        }
    }
}

/* Stage modulate: at the angle of the middle of [k+1, k+2], the
 * torque-first hexagon limit, the dead time's error fed forward, SVPWM;
 * what the inverter will realise is u(k) for the next period's
 * prediction and estimation (a dead-time error left in it would end up
 * in f^, then in psi_f^: 1 us at 311 V put +10 % into psi_f^ in the SIL);
 * the speed PI's anti-windup on the torque it achieves. */
static void stage_modulate(ctrl_t *c, ctrl_period_t *p, float vdc_V)
{
    float sa;
    float ca;
    ab_t u_real;

    advance_sincos(p->s, p->co, &c->turn, &sa, &ca);
    p->flags |= map_dbdtc_flags(dbdtc_limit(&p->u, sa, ca, vdc_V));
    ab_t u_cmd = park_inv(p->u, sa, ca);
    const ab_t u_dt = deadtime_error(c, p->i_dq, sa, ca, vdc_V, u_cmd);
    u_cmd.a -= u_dt.a; /* fed forward: the inverter adds u_dt back */
    u_cmd.b -= u_dt.b;
    if ((svpwm_duty(u_cmd, vdc_V, &p->duty, &u_real) & SVPWM_SATURATED) != 0u) {
        p->flags |= CTRL_FLAG_VOLTAGE_LIMIT;
    }
    u_real.a += u_dt.a;
    u_real.b += u_dt.b;
    c->u_applied_V = park(u_real, sa, ca);
    if (c->mode == CTRL_MODE_SPEED) {
        pi_apply(&c->speed_pi, dbdtc_torque_after(&c->db, c->u_applied_V));
    }
}

/* The current the step aimed at, with the model in use (oplim.h: psi_q* = Te* psiq_per_Nm,
 * psi_d* = sqrt(psi_s*^2 - psi_q*^2), i* = (psi_d* - psi_f, psi_q*) / L), in the stator frame at
 * the step's angle; 0 in open loop (no targets). Protection's OPEN_PHASE judges a phase by it. */
static ab_t aimed_current(const ctrl_t *c, const ctrl_period_t *p)
{
    const dbdtc_par_t *m = &c->db.par;
    const float inv_L = m->inv_L_1_H;
    const float psi_q = p->te_ref * m->psiq_per_Nm;
    const float psi_d2 = p->psi_ref * p->psi_ref - psi_q * psi_q;
    ab_t i = { 0.0f, 0.0f };

    if (p->psi_ref > 0.0f) {
        const float id = (((psi_d2 > 0.0f) ? mathx_sqrtf(psi_d2) : 0.0f) - m->psi_f_Wb) * inv_L;
        const float iq = psi_q * inv_L;
        i.a = id * p->co - iq * p->s;
        i.b = id * p->s + iq * p->co;
    }
    return i;
}

/* Stage monitor: what the period saw and decided. */
static void stage_monitor(ctrl_t *c, const ctrl_period_t *p)
{
    const ab_t aim = aimed_current(c, p);

    c->mon.theta_el_rad = c->enc.theta_e_rad;
    c->mon.omega_el_rad_s = p->omega;
    c->mon.speed_mech_rad_s = c->enc.omega_m_rad_s;
    c->mon.id_A = p->i_dq.d;
    c->mon.iq_A = p->i_dq.q;
    c->mon.ud_V = c->u_applied_V.d;
    c->mon.uq_V = c->u_applied_V.q;
    c->mon.i_aim_alpha_A = aim.a;
    c->mon.i_aim_beta_A = aim.b;
    c->mon.te_ref_Nm = p->te_ref;
    c->mon.te_est_Nm = p->x.te_Nm;
    c->mon.psi_ref_Wb = p->psi_ref;
    c->mon.psi_est_Wb = mathx_sqrtf(p->x.psi_dq_Wb.d * p->x.psi_dq_Wb.d + p->x.psi_dq_Wb.q * p->x.psi_dq_Wb.q);
}

void ctrl_monitor_readings(ctrl_t *c, const ctrl_in_t *in, bool outputs_on)
{
    const dbdtc_par_t *m = &c->db.par;
    float s;
    float co;
    mathx_sincosf(c->enc.theta_e_rad, &s, &co);
    const dq_t i = park(clarke_2ph(in->ia_A, in->ib_A), s, co);
    const float psi_d = m->L_H * i.d + m->psi_f_Wb;   /* Ld = Lq: the reluctance torque is 0 */
    const float psi_q = m->L_H * i.q;
    c->mon.theta_el_rad = c->enc.theta_e_rad;
    c->mon.omega_el_rad_s = c->enc.omega_e_rad_s;
    c->mon.speed_mech_rad_s = c->enc.omega_m_rad_s;
    c->mon.id_A = i.d;
    c->mon.iq_A = i.q;
    c->mon.ud_V = outputs_on ? c->u_applied_V.d : 0.0f;
    c->mon.uq_V = outputs_on ? c->u_applied_V.q : 0.0f;
    c->mon.i_aim_alpha_A = 0.0f;
    c->mon.i_aim_beta_A = 0.0f;
    c->mon.te_ref_Nm = 0.0f;
    c->mon.te_est_Nm = m->kt_Nm_per_A * i.q;         /* eq. (3) */
    c->mon.psi_ref_Wb = 0.0f;
    c->mon.psi_est_Wb = mathx_sqrtf(psi_d * psi_d + psi_q * psi_q);
}

/* Stage output: one finiteness check per ISR (NaN and Inf survive a sum;
 * the inputs are in it because the blocks clamp, a NaN would become a
 * bound; the estimation's state because it carries over), the duties and
 * flags. */
static void stage_output(ctrl_t *c, const ctrl_period_t *p, const ctrl_in_t *in, ctrl_out_t *out)
{
    const est_out_t *e = est_output(&c->est);
    const dq_t f = est_f_V(&c->est);
    const dq_t i_hat = est_i_hat_A(&c->est);
    const float chk = in->ia_A + in->ib_A + in->vdc_V + c->ref.speed_ref_rad_s + c->ref.te_ref_Nm +
                      c->ref.ud_ref_V + c->ref.uq_ref_V + p->omega + p->x.te_Nm + p->u.d + p->u.q +
                      p->duty.a + p->duty.b + p->duty.c + c->u_applied_V.d + c->u_applied_V.q + f.d + f.q +
                      i_hat.d + i_hat.q + e->L_H + est_psi_f_obs_Wb(&c->est);
    /* the next period's memory: the estimation's checks, the bumpless speed mode */
    c->flags_last = p->flags; /* before any NONFINITE: the estimation's voltage check */
    c->te_ref_last_Nm = p->te_ref;
    c->te_est_last_Nm = p->x.te_Nm;
    output_duties(c, p->duty, mathx_isfinitef(chk), (uint16_t)(p->flags | e->flags), out);
}

/* The oscillation watch (ctrl.h CTRL_OSC_*) on the model the estimation
 * gave: at lambda = L^/L >= CTRL_OSC_LAMBDA_HOLD, L^ cut to L^/lambda.
 * The last period at the voltage limit ends the pair under way: the
 * deadbeat did not apply (L^/Ts)(i* - i^), the premise of the regression
 * (discrete_model_design.md sec. 7). Otherwise only the state x at k+1
 * the model starts from this period, the next prediction. */
static void stage_watch(ctrl_t *c, const ctrl_period_t *p)
{
    ctrl_osc_t *o = &c->osc;
    if ((c->flags_last & CTRL_FLAG_VOLTAGE_LIMIT) != 0u) {
        o->pred_A = p->x.i_dq_A;
        o->phase = 0u; /* the next period starts a pair */
    } else if ((c->model_src == MODEL_EST) && (c->osc_den_min_A2 > 0.0f)) {
        const float lambda = ctrl_osc_step(o, p->i_dq, p->x.i_dq_A, c->osc_den_min_A2);
        if (lambda > 0.0f) {
            est_hold_oscillation(&c->est, 1.0f / lambda, p->omega, p->i_dq.q); /* one division, once */
        }
    } else {
        o->pred_A = p->x.i_dq_A;
        o->num_A2 = 0.0f; /* a new watch with the next estimated model */
        o->den_A2 = 0.0f;
    }
}

/* The ISR's order: each stage one call. */
void ctrl_step(ctrl_t *c, const ctrl_in_t *in, ctrl_out_t *out)
{
    ctrl_period_t p;

    stage_mode(c);                             /* the mode asked for */
    stage_sample(c, in, &p);                   /* angle, speed, i(k) */
    stage_estimate(c, &p, in->vdc_V);          /* observer, steps 1 and 2 (est.h) */
    p.x = ctrl_model(c, p.i_dq, &c->turn);      /* the model in use and the state at k+1 */
    stage_watch(c, &p);                        /* the current's oscillation on an estimated model */
    stage_references(c, &p);                   /* Te*: speed PI or torque reference */
    stage_limits(c, &p);                       /* current limit, MTPA, flux weakening: Te*, psi_s* */
    stage_deadbeat(c, &p, in->vdc_V);          /* eq. (17): u(k+1) */
    stage_modulate(c, &p, in->vdc_V);          /* hexagon, dead time, SVPWM, u realised */
    stage_monitor(c, &p);                      /* monitor */
    stage_output(c, &p, in, out);              /* finiteness, duties, flags */
}
