/* est.c - the proposed method's estimation under one owner; see est.h. */
#include "est.h"

#include "mathx.h"

#define QUARTER_PI 0.785398163f
/* Step 1's windows suggest an encoder angle error beyond this [rad el]:
 * L^ held, EST_FLAG_ANGLE_SUSPECT (holds_design.md sec. 8; 1.5 deg:
 * 0.12 deg at most without one, 4.9 deg read for a 5 deg offset). */
#define EST_ANGLE_SUSPECT_RAD 0.026f
/* ... read only where the windows' iq differ by this share of the larger [1] */
#define EST_ANGLE_IQ_SPREAD_MIN 0.2f

/* est_hold passes the gate's reasons through unchanged */
typedef char est_hold_is_gate[((EST_HOLD_ACCEL == EST_GATE_ACCEL) && (EST_HOLD_CURRENT == EST_GATE_CURRENT) &&
                               (EST_HOLD_TORQUE == EST_GATE_TORQUE) && (EST_HOLD_VOLTAGE == EST_GATE_VOLTAGE) &&
                               (EST_HOLD_SETTLE == EST_GATE_HOLD)) ? 1 : -1];

/* The output while step 2 is not running: the told model, the
 * conventional path, the observer's disturbances as they are. */
RAMFUNC static void out_told(est_t *e)
{
    est_out_t *o = &e->out;
    o->R_Ohm = e->cfg.R_Ohm;
    o->L_H = e->cfg.L_H;
    o->psi_f_Wb = e->cfg.psi_f_Wb;
    o->inv_dv_V = 0.0f;
    o->inv_err_V = EST_FUNDAMENTAL_OF_SQUARE * e->inv_dv_V;
    o->src = EST_SRC_TOLD;
    o->moved = 0u;
    o->hold = (uint16_t)(EST_HOLD_NO_STEP2 | (e->refused ? EST_HOLD_STEP1_REFUSED : 0u));
    o->flags = e->rt_flags;
    o->phase = e->phase;
}

FLASHFUNC void est_reset(est_t *e)
{
    smo_reset(&e->smo);
    param_est_reset(&e->pe);
    rs_ident_reset(&e->ri);
    e->win = RS_IDENT_WINDOW_NONE;
    e->phase = EST_OFF;
    r_track_reset(&e->rt);
    e->inv_dv_V = 0.0f;
    e->rt_flags = 0u;
    e->force = 0u;
    e->hold_fixed = 0u;
    e->refused = false;
    e->trusted = false;
    e->w_psi_min_rad_s = e->cfg.w_min_rad_s;
    e->step1_ripple_A = 0.0f;
    e->angle_fix_el_rad = 0.0f;
    e->step1_vdc_V = 0.0f;
    est_gate_reset(&e->gate, &e->smo);
    out_told(e);
}

FLASHFUNC bool est_rsid_begin(est_t *e)
{
    if (e->status != EST_CFG_OK) {
        return false;
    }
    smo_reset(&e->smo); /* the told R, L, psi: rs_ident's dR is relative to them */
    param_est_run(&e->pe, false);
    rs_ident_reset(&e->ri);
    e->win = RS_IDENT_WINDOW_NONE;
    e->phase = EST_STEP1;
    r_track_reset(&e->rt); /* identified again after this step 1 */
    e->inv_dv_V = 0.0f;
    e->w_psi_min_rad_s = e->cfg.w_min_rad_s;
    e->rt_flags = 0u;
    e->hold_fixed = 0u;
    e->refused = false;
    e->step1_ripple_A = 0.0f;
    e->angle_fix_el_rad = 0.0f;
    e->step1_vdc_V = 0.0f;
    out_told(e);
    return true;
}

RAMFUNC void est_rsid_window(est_t *e, rs_ident_window_t win)
{
    e->win = win;
}

/* R^ tracked from now on when configured; psi^ learns only where w psi_f
 * dominates what the identification may have left (the speed floor of
 * the transfer law, an input of param_est_step). */
RAMFUNC static void start_tracking(est_t *e)
{
    const float w_min = r_track_w_psi_min(&e->rt, e->cfg.psi_f_Wb);
    e->w_psi_min_rad_s = (w_min > e->cfg.w_min_rad_s) ? w_min : e->cfg.w_min_rad_s;
    r_track_start(&e->rt, (e->cfg.track_R != EST_TRACK_R_OFF) ? R_TRACK_TRACK : R_TRACK_OFF);
    if (e->cfg.track_R == EST_TRACK_R_AUTO) {
        r_track_delay(&e->rt, e->cfg.auto_delay_periods);
    }
}

/* Step 2 starts: estimator running, the model re-based on the observer's values. */
RAMFUNC static void start_step2(est_t *e)
{
    param_est_run(&e->pe, true);
    est_gate_reset(&e->gate, &e->smo);
    psi_band_start(&e->pb, e->smo.psi_f_Wb); /* the model's value then (holds_design.md sec. 2) */
    e->phase = EST_STEP2;
    e->trusted = false;
    e->force = EST_MOVED_ALL;
    e->out.R_Ohm = e->smo.R_Ohm;
    e->out.L_H = e->smo.L_H;
    e->out.psi_f_Wb = e->pb.psi_Wb;
    e->out.src = EST_SRC_OBSERVER;
    e->out.hold = 0u;
    e->out.phase = EST_STEP2;
    start_tracking(e);
}

/* Per-leg voltage error dv_V [V] of the dead time's shape added to the
 * compensation, bumplessly: f^ gives up the fundamental -(4/pi) dv i/|i|
 * it no longer has to explain (inverter_error_design.md sec. 5). 1 square root, 1 division, once. */
RAMFUNC static void add_inverter_error(est_t *e, float dv_V, dq_t i_dq_A)
{
    const float i_abs = mathx_sqrtf(i_dq_A.d * i_dq_A.d + i_dq_A.q * i_dq_A.q);
    float dfq = 0.0f;
    e->inv_dv_V += dv_V;
    if (i_abs > 0.0f) {
        const float k = -EST_FUNDAMENTAL_OF_SQUARE * dv_V / i_abs;
        dfq = k * i_dq_A.q;
        smo_shift_f(&e->smo, k * i_dq_A.d, dfq);
    }
    psi_band_rebase(&e->pb, dfq, e->rt.ident_sync); /* the fine bound from here (holds_design.md sec. 3) */
    e->out.inv_err_V = EST_FUNDAMENTAL_OF_SQUARE * e->inv_dv_V;
}

/* The told compensation's fundamental with the identified error on top
 * [V] at the bus vdc_V [V] (inverter_error_design.md sec. 2). */
RAMFUNC static float compensated_fundamental_V(const est_t *e, float vdc_V)
{
    return EST_FUNDAMENTAL_OF_SQUARE *
           (e->cfg.deadtime_frac * mathx_fabsf(vdc_V) + e->cfg.device_drop_V + mathx_fabsf(e->inv_dv_V));
}

RAMFUNC void est_r_track_event(est_t *e, r_track_event_t ev, const est_in_t *in)
{
    const dq_t i_dq_A = in->i_dq_A;
    if (ev == R_TRACK_IDENT_DONE) {
        add_inverter_error(e, QUARTER_PI * e->rt.Ve_V, i_dq_A); /* per leg: (pi/4) Ve */
        e->rt_flags &= EST_FLAG_ANGLE_SUSPECT;
        e->force = EST_MOVED_ALL; /* taken again, now trusted */
        start_tracking(e);
    } else if (ev == R_TRACK_IDENT_REFUSED) {
        e->rt_flags = (uint16_t)((e->rt_flags & EST_FLAG_ANGLE_SUSPECT) | EST_FLAG_INV_UNIDENTIFIED); /* says so,
                                                            * and keeps the dead time as told */
        /* nothing bounds the error then: the told model at every speed (holds_design.md sec. 7) */
        psi_band_bound_unknown(&e->pb);
        e->force = EST_MOVED_ALL;
        start_tracking(e);
    } else if (ev == R_TRACK_CYCLE) {
        /* rho = dR with the inverter error compensated: R^ += -k_R rho + rate, within the band,
         * where the compensation's uncertainty leaves R resolvable (r_tracking_design.md sec. 6) */
        const float fq_V = e->smo.fq_V;
        const float i_abs = mathx_sqrtf(i_dq_A.d * i_dq_A.d + i_dq_A.q * i_dq_A.q);
        if (!r_track_resolves(&e->rt, compensated_fundamental_V(e, in->vdc_V), in->ripple_A, i_abs, e->smo.R_Ohm)) {
            r_track_discard(&e->rt);
            e->rt_flags |= EST_FLAG_R_HELD;
        } else if (smo_set_R(&e->smo, e->smo.R_Ohm + e->rt.dR_step_Ohm)) {
            psi_band_r_moved(&e->pb, e->smo.fq_V - fq_V); /* holds_design.md sec. 4 */
            e->rt_flags &= (uint16_t)~EST_FLAG_R_HELD;
            e->force = EST_MOVED_ALL;
        } else {
            e->rt_flags |= EST_FLAG_R_HELD;
        }
    } else if (ev == R_TRACK_HELD) {
        e->rt_flags |= EST_FLAG_R_HELD;
    } else {
        /* cycle under way */
    }
}

/* The inverter check of step 1's result (step1_design.md sec. 9): each
 * window's q disturbance may carry what the compensation leaves,
 * delta_j = (e0 + c r/|i_j|) Ve (Ve the compensated error's fundamental
 * with the untold prior on top, r the largest ripple step 1 saw; e0, c
 * r_track's inv_unc_frac, ripple_unc), which moves R^ by
 * (delta_1 w2 - delta_2 w1)/den: at most |e0 Ve (w2 - w1)| +
 * c r Ve (|w2|/|i1| + |w1|/|i2|) over |den|. True when that is within
 * R_res_max R^ (into o->R_inverter_Ohm, o->R_inverter_max_Ohm). */
RAMFUNC static bool rsid_inverter_ok(const est_t *e, rs_ident_out_t *o, float den)
{
    const r_track_cfg_t *rc = &e->rt.cfg;
    const float vdc = mathx_fabsf(e->step1_vdc_V);
    const float ve = EST_FUNDAMENTAL_OF_SQUARE *
                     ((e->cfg.deadtime_frac + e->cfg.untold_frac) * vdc + e->cfg.device_drop_V);
    const float w1 = mathx_fabsf(o->mean_w_rad_s[0]);
    const float w2 = mathx_fabsf(o->mean_w_rad_s[1]);
    const float i1 = mathx_sqrtf(o->mean_id_A[0] * o->mean_id_A[0] + o->mean_iq_A[0] * o->mean_iq_A[0]);
    const float i2 = mathx_sqrtf(o->mean_id_A[1] * o->mean_id_A[1] + o->mean_iq_A[1] * o->mean_iq_A[1]);
    /* times |i1| |i2|: no division by a current */
    const float num_x_i12 = rc->inv_unc_frac * ve * mathx_fabsf(w2 - w1) * i1 * i2 +
                            rc->ripple_unc * e->step1_ripple_A * ve * (w2 * i2 + w1 * i1);
    const float lim = rc->R_res_max * mathx_fabsf(o->R_raw_Ohm);
    o->R_inverter_max_Ohm = lim;
    o->R_inverter_Ohm = ((i1 > 0.0f) && (i2 > 0.0f)) ? (num_x_i12 / (mathx_fabsf(den) * i1 * i2)) : 0.0f;
    return num_x_i12 <= lim * mathx_fabsf(den) * i1 * i2;
}

/* Step 1's result with the d-axis check (step1_design.md sec. 6): an
 * error e_L of dL moves R^ by w1 w2 (id2 - id1) e_L / den when the
 * windows' id differ (field weakening at the voltage limit). Where the
 * correction the solve applied, |k dL^|, exceeds se(R^)'s limit, the two
 * windows' own dL_j = (fd_j + dR id_j)/(w_j iq_j) must agree within it
 * too, |k (dL1 - dL2)|; else the model does not hold on the d axis and R^
 * hangs on it: refused (RS_IDENT_D_AXIS). */
RAMFUNC static rs_ident_result_t rsid_checks(const est_t *e, rs_ident_result_t r_solved, rs_ident_out_t *o)
{
    rs_ident_result_t r = r_solved;
    o->R_d_axis_Ohm = 0.0f;
    o->angle_el_rad = 0.0f;
    o->R_inverter_Ohm = 0.0f;
    o->R_inverter_max_Ohm = 0.0f;
    if (r == RS_IDENT_OK) {
        const float w1 = o->mean_w_rad_s[0];
        const float w2 = o->mean_w_rad_s[1];
        const float wiq1 = w1 * o->mean_iq_A[0];
        const float wiq2 = w2 * o->mean_iq_A[1];
        const float den = o->mean_iq_A[1] * w1 - o->mean_iq_A[0] * w2; /* (41)'s, |den| > 0 when OK */
        const float dR = e->cfg.R_Ohm - o->R_raw_Ohm;
        const float wiq_min = e->cfg.wiq_min_A_rad_s;
        const float k = w1 * w2 * (o->mean_id_A[1] - o->mean_id_A[0]) / den; /* dR per dL */
        const float iq1 = o->mean_iq_A[0];
        const float iq2 = o->mean_iq_A[1];
        const float iq_big = (mathx_fabsf(iq1) > mathx_fabsf(iq2)) ? mathx_fabsf(iq1) : mathx_fabsf(iq2);
        if ((mathx_fabsf(wiq1) > wiq_min) && (mathx_fabsf(wiq2) > wiq_min) &&
            (mathx_fabsf(iq2 - iq1) > EST_ANGLE_IQ_SPREAD_MIN * iq_big)) {
            /* an angle error d adds -w psi_f d to fd: dL_j = dL - psi_f d / iq_j (holds_design.md sec. 8) */
            const float dL1 = (o->mean_fd_V[0] + dR * o->mean_id_A[0]) / wiq1;
            const float dL2 = (o->mean_fd_V[1] + dR * o->mean_id_A[1]) / wiq2;
            o->angle_el_rad = (dL1 - dL2) * iq1 * iq2 / (e->cfg.psi_f_Wb * (iq1 - iq2));
        }
        if ((mathx_fabsf(wiq1) > wiq_min) && (mathx_fabsf(wiq2) > wiq_min) && /* both dL_j defined */
            !(mathx_fabsf(k * o->dL_H) <= o->R_se_max_Ohm)) {                  /* and the correction matters */
            const float dL1 = (o->mean_fd_V[0] + dR * o->mean_id_A[0]) / wiq1;
            const float dL2 = (o->mean_fd_V[1] + dR * o->mean_id_A[1]) / wiq2;
            o->R_d_axis_Ohm = mathx_fabsf(k * (dL1 - dL2));
        }
        if (!(o->R_d_axis_Ohm <= o->R_se_max_Ohm)) {
            o->R_est_Ohm = e->cfg.R_Ohm; /* refused: R_nom, as rs_ident's refusals */
            r = RS_IDENT_D_AXIS;
        } else if (!rsid_inverter_ok(e, o, den)) {
            o->R_est_Ohm = e->cfg.R_Ohm;
            r = RS_IDENT_INVERTER;
        }
    }
    return r;
}

static rs_ident_result_t rsid_solve(const est_t *e, rs_ident_out_t *o)
{
    return rsid_checks(e, rs_ident_solve(&e->ri, o), o);
}

RAMFUNC bool est_rsid_stage_begin(est_t *e, rs_ident_solver_t *s, rs_ident_head_t *win2_copy)
{
    if (!rs_ident_batch_closed(&e->ri, RS_IDENT_WINDOW_2)) {
        return false;
    }
    rs_ident_copy_head(win2_copy, &e->ri, RS_IDENT_WINDOW_2);
    rs_ident_solve_begin(s, &e->ri, win2_copy);
    return true;
}

RAMFUNC bool est_rsid_stage_step(est_t *e, rs_ident_solver_t *s)
{
    if (s->stage >= RS_IDENT_SOLVE_STAGES) {
        return true; /* over: nothing more */
    }
    if (!rs_ident_solve_step(s, &e->rsid_out)) {
        return false;
    }
    s->result = rsid_checks(e, s->result, &e->rsid_out);
    return true;
}

/* The angle d step 1's windows suggest where its d-axis voltage w psi_f d
 * at the windows' lower speed exceeds the bound on what the inverter may
 * leave before its identification (the coarse bound on the told error
 * and the prior of an untold one, psi_band.h): else 0 (holds_design.md
 * sec. 8: 1 us untold read 0.4-0.5 V of angle at 50-100 r/min). */
RAMFUNC static float correctable_angle_el_rad(const est_t *e)
{
    const psi_band_cfg_t *bc = &e->pb.cfg;
    const rs_ident_out_t *o = &e->rsid_out;
    const float vdc = mathx_fabsf(e->step1_vdc_V);
    const float vb = bc->unc_told_frac * (bc->ve_told_per_vdc * vdc + bc->ve_told_drop_V) +
                     bc->ve_prior_per_vdc * vdc + bc->unc_abs_V;
    const float w1 = mathx_fabsf(o->mean_w_rad_s[0]);
    const float w2 = mathx_fabsf(o->mean_w_rad_s[1]);
    const float v_angle = ((w1 < w2) ? w1 : w2) * e->cfg.psi_f_Wb * mathx_fabsf(o->angle_el_rad);
    return (v_angle > vb) ? o->angle_el_rad : 0.0f;
}

rs_ident_result_t est_rsid_finish(est_t *e)
{
    return est_rsid_finish_with(e, rsid_solve(e, &e->rsid_out));
}

RAMFUNC rs_ident_result_t est_rsid_finish_with(est_t *e, rs_ident_result_t r_solved)
{
    rs_ident_result_t r = r_solved;

    rs_ident_reset(&e->ri); /* a second finish without a begin finds no data */
    e->win = RS_IDENT_WINDOW_NONE;
    if (e->phase != EST_STEP1) {
        r = RS_IDENT_TOO_FEW; /* no step 1 under way */
    } else if ((r == RS_IDENT_OK) && !smo_set_R(&e->smo, e->rsid_out.R_est_Ohm)) {
        r = RS_IDENT_OUT_OF_BAND; /* same band as rs_ident's: not expected */
    }
    if (r == RS_IDENT_OK) {
        start_step2(e);
        /* a suspected angle error would be learned as L: L^ held, a warning (holds_design.md sec. 8) */
        const bool suspect = !(mathx_fabsf(e->rsid_out.angle_el_rad) <= EST_ANGLE_SUSPECT_RAD);
        param_est_hold_L(&e->pe, suspect);
        psi_band_hold(&e->pb, suspect); /* the told model, the conventional path */
        e->hold_fixed = suspect ? EST_HOLD_ANGLE : 0u;
        e->angle_fix_el_rad = suspect ? correctable_angle_el_rad(e) : 0.0f;
        e->rt_flags = suspect ? EST_FLAG_ANGLE_SUSPECT : 0u;
        e->out.hold = e->hold_fixed;
        e->out.flags = e->rt_flags;
        if (!suspect) {
            /* first the inverter error, at R^ = R0 (inverter_error_design.md sec. 5); not with the
             * told model held: its injection would only disturb the torque */
            r_track_start(&e->rt, R_TRACK_IDENT);
        }
    } else {
        e->refused = (e->phase == EST_STEP1); /* a step 1 under way was refused */
        e->phase = EST_OFF;
        out_told(e);
    }
    return r;
}

RAMFUNC float est_angle_error_el_rad(const est_t *e)
{
    return ((e->hold_fixed & EST_HOLD_ANGLE) != 0u) ? e->angle_fix_el_rad : 0.0f;
}

RAMFUNC void est_angle_corrected(est_t *e)
{
    if ((e->phase != EST_STEP2) || ((e->hold_fixed & EST_HOLD_ANGLE) == 0u)) {
        return;
    }
    const float R_Ohm = e->smo.R_Ohm;
    smo_reset(&e->smo); /* the frame turned: i^, f^ seeded again at the next step */
    (void)smo_set_R(&e->smo, R_Ohm);
    start_step2(e);
    param_est_hold_L(&e->pe, false);
    psi_band_hold(&e->pb, false);
    e->hold_fixed = (uint16_t)(e->hold_fixed & (uint16_t)~EST_HOLD_ANGLE);
    e->out.hold = e->hold_fixed;
    r_track_start(&e->rt, R_TRACK_IDENT); /* as after an unsuspected step 1 */
}

FLASHFUNC bool est_start_trusted(est_t *e, float R_Ohm)
{
    /* ! (in band): NaN fails too */
    if ((e->status != EST_CFG_OK) || !((R_Ohm >= e->cfg.R_min_Ohm) && (R_Ohm <= e->cfg.R_max_Ohm))) {
        return false;
    }
    if (e->phase == EST_OFF) {
        smo_reset(&e->smo); /* seeded with i(k) at the next step, f^ = 0 */
    }
    (void)smo_set_R(&e->smo, R_Ohm); /* in band: accepted */
    rs_ident_reset(&e->ri);
    e->win = RS_IDENT_WINDOW_NONE;
    start_step2(e); /* no inverter-error identification: R and the inverter were measured */
    psi_band_bound_measured(&e->pb);
    return true;
}

RAMFUNC void est_hold_oscillation(est_t *e, float L_scale, float omega_el_rad_s, float iq_A)
{
    if ((e->phase != EST_STEP2) || !(L_scale > 0.0f) || !(L_scale < 1.0f)) {
        return;
    }
    param_est_hold_L(&e->pe, true);
    const float L_H = smo_set_L(&e->smo, L_scale * e->smo.L_H, omega_el_rad_s, iq_A);
    est_gate_take_L(&e->gate, L_H); /* a transient's restore keeps it */
    e->force = EST_MOVED_ALL;       /* the model takes it this period */
    e->hold_fixed = (uint16_t)(e->hold_fixed | EST_HOLD_OSCILLATION);
}

RAMFUNC bool est_start_told(est_t *e)
{
    if (e->status != EST_CFG_OK) {
        return false;
    }
    if (e->phase == EST_OFF) {
        smo_reset(&e->smo); /* the told R, L, psi_f; seeded with i(k) at the next step */
    }
    (void)smo_set_R(&e->smo, e->cfg.R_Ohm);
    rs_ident_reset(&e->ri);
    e->win = RS_IDENT_WINDOW_NONE;
    e->hold_fixed = 0u;
    e->rt_flags = 0u;
    start_step2(e);
    r_track_start(&e->rt, R_TRACK_IDENT); /* the inverter error first, then R^ tracked (track_R) */
    return true;
}
