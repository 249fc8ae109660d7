/* est.c - the proposed method's estimation under one owner; see est.h. */
#include "est.h"

#include "mathx.h"

/* A per-leg square wave of amplitude dv (dead time, device drop) has the
 * rotor-frame fundamental (4/pi) dv against the current (design sec. 9). */
#define FUNDAMENTAL_OF_SQUARE 1.27323954f
#define QUARTER_PI 0.785398163f
/* Step 1's windows suggest an encoder angle error beyond this [rad el]:
 * L^ held, EST_FLAG_ANGLE_SUSPECT (observer_design.md sec. 6h; 1.5 deg:
 * 0.12 deg at most without one, 4.9 deg read for a 5 deg offset). */
#define EST_ANGLE_SUSPECT_RAD 0.026f
/* ... read only where the windows' iq differ by this share of the larger [1] */
#define EST_ANGLE_IQ_SPREAD_MIN 0.2f

/* Default floor of L^: this factor above the observer's stability bound
 * L > (Ks/phi + R_max) Ts / 2 (smo_init), so an estimate near the floor
 * still leaves the linear region a pole margin. */
#define EST_L_MIN_STABILITY_MARGIN 1.25f
/* est_obs_gains_design (observer_design.md sec. 3b): the lowest floor of
 * L^ the gain must allow, x the told L (an L told 1.4x high leaves the
 * true one at 0.71x); the R^ band's top that (36) leaves, x G (the
 * band's 0.9 (Ks - ef_max)/phi with Ks = 2 ef_max); Ks over ef_max:
 * (36)'s floor ef_max / (1 - 0.45) with a 10 % margin. Table I: Ks 100 V,
 * G = 40 V/A, R^ up to 18 Ohm, the cap 0.8 L/(1.45 Ts) = 61 V/A not reached. */
#define EST_OBS_L_FLOOR_SHARE 0.5f
#define EST_OBS_R_TOP_PER_G   0.45f
#define EST_OBS_KS_PER_EF     2.0f
#define HALF 0.5f
/* The default R^ band's top stays this fraction of the largest R that
 * meets (36) with the observer's gains (18 Ohm for Table I). */
#define EST_RSID_BAND_KS_MARGIN 0.9f

/* est_hold passes the gate's reasons through unchanged */
typedef char est_hold_is_gate[((EST_HOLD_ACCEL == EST_GATE_ACCEL) && (EST_HOLD_CURRENT == EST_GATE_CURRENT) &&
                               (EST_HOLD_TORQUE == EST_GATE_TORQUE) && (EST_HOLD_VOLTAGE == EST_GATE_VOLTAGE) &&
                               (EST_HOLD_SETTLE == EST_GATE_HOLD)) ? 1 : -1];

/* The output while step 2 is not running: the told model, the
 * conventional path, the observer's disturbances as they are. */
static void out_told(est_t *e)
{
    est_out_t *o = &e->out;
    o->R_Ohm = e->cfg.R_Ohm;
    o->L_H = e->cfg.L_H;
    o->psi_f_Wb = e->cfg.psi_f_Wb;
    o->inv_dv_V = 0.0f;
    o->inv_err_V = FUNDAMENTAL_OF_SQUARE * e->inv_dv_V;
    o->src = EST_SRC_TOLD;
    o->moved = 0u;
    o->hold = EST_HOLD_NO_STEP2;
    o->flags = e->rt_flags;
    o->phase = e->phase;
}

void est_obs_gains_default(est_obs_gains_t *g)
{
    g->Ks_V = SMO_KS_DEFAULT_V;
    g->phi_A = SMO_PHI_DEFAULT_A;
    g->ef_max_V = SMO_EF_MAX_DEFAULT_V;
}

bool est_obs_gains_design(float Ts_s, float R_Ohm, float L_H, float ef_max_V, float phi_A, est_obs_gains_t *g,
                          float *G_max_V_A)
{
    /* 1.25 (Ts/2)(G + R_max) <= L_FLOOR_SHARE L with R_max <= R_TOP_PER_G G */
    const float G_max = (2.0f * EST_OBS_L_FLOOR_SHARE * L_H / (EST_L_MIN_STABILITY_MARGIN * Ts_s)) /
                        (1.0f + EST_OBS_R_TOP_PER_G);
    g->Ks_V = EST_OBS_KS_PER_EF * ef_max_V;
    g->phi_A = phi_A;
    g->ef_max_V = ef_max_V;
    if (g->Ks_V / phi_A > G_max) {
        g->phi_A = g->Ks_V / G_max; /* the cap: a wider layer keeps (36)'s margin */
    }
    *G_max_V_A = G_max;
    return (G_max > 0.0f) && (EST_OBS_R_TOP_PER_G * (g->Ks_V / g->phi_A) >= R_Ohm);
}

void est_rsid_band(const est_told_t *told, const est_obs_gains_t *g, float *R_min_Ohm, float *R_max_Ohm)
{
    /* (36): Ks > ef_max + R_max phi, with a margin */
    const float R_ks_Ohm = EST_RSID_BAND_KS_MARGIN * (g->Ks_V - g->ef_max_V) / g->phi_A;
    const float R_top_Ohm = RS_IDENT_BAND_MAX_FACTOR * told->R_Ohm;
    *R_min_Ohm = RS_IDENT_BAND_MIN_FACTOR * told->R_Ohm;
    *R_max_Ohm = (R_top_Ohm < R_ks_Ohm) ? R_top_Ohm : R_ks_Ohm;
    *R_max_Ohm = (*R_max_Ohm > told->R_Ohm) ? *R_max_Ohm : told->R_Ohm;
}

void est_cfg_defaults(est_cfg_t *cfg, const est_told_t *told, const est_obs_gains_t *g, float R_min_Ohm,
                      float R_max_Ohm)
{
    smo_cfg_t *sc = &cfg->smo;
    param_est_cfg_t *ec = &cfg->pe;

    cfg->R_min_Ohm = R_min_Ohm;
    cfg->R_max_Ohm = R_max_Ohm;
    smo_cfg_defaults(sc, told->Ts_s, told->R_Ohm, told->L_H, told->psi_f_Wb);
    sc->Ks_V = g->Ks_V;
    sc->phi_A = g->phi_A;
    sc->ef_max_V = g->ef_max_V;
    const float L_stable_H = EST_L_MIN_STABILITY_MARGIN * HALF * told->Ts_s * (sc->Ks_V / sc->phi_A + R_max_Ohm);
    /* not capped at L_max: a floor above it is refused by smo_init */
    sc->L_min_H = (sc->L_min_H >= L_stable_H) ? sc->L_min_H : L_stable_H;
    sc->f_max_V = told->u_max_V; /* a disturbance beyond the voltage bound is no estimate */
    param_est_cfg_defaults(ec, told->Ts_s, told->L_H, told->psi_f_Wb);
    ec->L_min_H = sc->L_min_H; /* clamps = the observer's ranges */
    ec->L_max_H = sc->L_max_H;
    ec->psi_min_Wb = sc->psi_min_Wb;
    ec->psi_max_Wb = sc->psi_max_Wb;
    rs_ident_cfg_defaults(&cfg->rsid, told->R_Ohm);
    r_track_cfg_defaults(&cfg->rtrack);
    cfg->track_R = EST_TRACK_R_OFF;
    cfg->untold_deadtime_s = EST_UNTOLD_DEADTIME_DEFAULT_S;
    est_gate_cfg_defaults(&cfg->gate, told->Ts_s);
    /* above the speed estimate's count quantisation (design sec. 7) */
    cfg->gate.accel_floor_rad_s2 =
        est_gate_accel_floor_rad_s2(told->enc_counts_per_rev, told->pole_pairs, told->enc_pll_bw_rad_s);
}

est_status_t est_init(est_t *e, est_cfg_t *cfg, const est_told_t *told)
{
    const rs_ident_out_t no_result = { 0 };
    est_cfg_t *c = cfg; /* patched in place: no second copy on the start-up stack */
    const est_told_t *t = told;
    est_status_t status;

    e->cfg.R_Ohm = t->R_Ohm;
    e->cfg.L_H = t->L_H;
    e->cfg.psi_f_Wb = t->psi_f_Wb;
    e->cfg.R_min_Ohm = c->R_min_Ohm;
    e->cfg.R_max_Ohm = c->R_max_Ohm;
    e->cfg.w_min_rad_s = c->pe.w_min_rad_s;
    e->cfg.wiq_min_A_rad_s = c->pe.wiq_min_A_rad_s;
    e->cfg.track_R = c->track_R;
    e->cfg.auto_delay_periods = c->rtrack.auto_delay_periods;
    c->smo.Ts_s = t->Ts_s;
    c->smo.R_Ohm = t->R_Ohm;
    c->smo.L_H = t->L_H;
    c->smo.psi_f_Wb = t->psi_f_Wb;
    c->smo.R_min_Ohm = c->R_min_Ohm;
    c->smo.R_max_Ohm = c->R_max_Ohm;
    c->smo.i_max_A = t->i_max_A;
    c->smo.u_max_V = t->u_max_V;
    c->smo.omega_max_rad_s = t->omega_max_el_rad_s;
    c->pe.Ts_s = t->Ts_s;
    c->rsid.R_nom_Ohm = t->R_Ohm;
    c->rsid.Ts_s = t->Ts_s;
    c->rsid.R_min_Ohm = c->R_min_Ohm;
    c->rsid.R_max_Ohm = c->R_max_Ohm;
    c->gate.Ts_s = t->Ts_s;
    c->rtrack.Ts_s = t->Ts_s;

    psi_band_cfg_t bc;
    psi_band_cfg_defaults(&bc, t->Ts_s, c->pe.w_min_rad_s, c->pe.psi_min_Wb, c->pe.psi_max_Wb);
    bc.ve_told_per_vdc = (t->Ts_s > 0.0f) ? (FUNDAMENTAL_OF_SQUARE * t->deadtime_s / t->Ts_s) : 0.0f;
    bc.ve_prior_per_vdc = (t->Ts_s > 0.0f) ? (FUNDAMENTAL_OF_SQUARE * c->untold_deadtime_s / t->Ts_s) : 0.0f;
    const est_status_t gate = est_gate_init(&e->gate, &c->gate) ? EST_CFG_OK : EST_CFG_GATE;
    const bool obs_ok = (smo_init(&e->smo, &c->smo) == SMO_CFG_OK);
    const bool rt_ok = r_track_init(&e->rt, &c->rtrack);
    /* every block initialised; the first refusal in this order names the cause (a refused
     * observer also freezes the estimator: not reported again) */
    const bool pe_ok = param_est_init(&e->pe, &c->pe, &e->smo) && psi_band_init(&e->pb, &bc);
    const bool ri_ok = rs_ident_init(&e->ri, &c->rsid);
    if (!obs_ok) {
        status = (est_status_t)(EST_CFG_OBSERVER | gate);
    } else if (!rt_ok) {
        status = EST_CFG_RTRACK;
    } else if (!pe_ok) {
        status = (est_status_t)(EST_CFG_ESTIMATOR | gate);
    } else {
        status = (est_status_t)((ri_ok ? EST_CFG_OK : EST_CFG_RSID) | gate);
    }
    e->status = status;
    e->rsid_out = no_result;
    e->rsid_out.R_est_Ohm = t->R_Ohm;
    est_reset(e);
    return status;
}

void est_reset(est_t *e)
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
    e->trusted = false;
    e->w_psi_min_rad_s = e->cfg.w_min_rad_s;
    est_gate_reset(&e->gate, &e->smo);
    out_told(e);
}

bool est_rsid_begin(est_t *e)
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
    out_told(e);
    return true;
}

void est_rsid_window(est_t *e, rs_ident_window_t win)
{
    e->win = win;
}

/* R^ tracked from now on when configured; psi^ learns only where w psi_f
 * dominates what the identification may have left (the speed floor of
 * the transfer law, an input of param_est_step). */
static void start_tracking(est_t *e)
{
    const float w_min = r_track_w_psi_min(&e->rt, e->cfg.psi_f_Wb);
    e->w_psi_min_rad_s = (w_min > e->cfg.w_min_rad_s) ? w_min : e->cfg.w_min_rad_s;
    r_track_start(&e->rt, (e->cfg.track_R != EST_TRACK_R_OFF) ? R_TRACK_TRACK : R_TRACK_OFF);
    if (e->cfg.track_R == EST_TRACK_R_AUTO) {
        r_track_delay(&e->rt, e->cfg.auto_delay_periods);
    }
}

/* Step 2 starts: estimator running, the model re-based on the observer's values. */
static void start_step2(est_t *e)
{
    param_est_run(&e->pe, true);
    est_gate_reset(&e->gate, &e->smo);
    psi_band_start(&e->pb, e->smo.psi_f_Wb); /* the model's value then (design sec. 9f) */
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
 * it no longer has to explain (design sec. 9). 1 square root, 1 division, once. */
static void add_inverter_error(est_t *e, float dv_V, dq_t i_dq_A)
{
    const float i_abs = mathx_sqrtf(i_dq_A.d * i_dq_A.d + i_dq_A.q * i_dq_A.q);
    float dfq = 0.0f;
    e->inv_dv_V += dv_V;
    if (i_abs > 0.0f) {
        const float k = -FUNDAMENTAL_OF_SQUARE * dv_V / i_abs;
        dfq = k * i_dq_A.q;
        smo_shift_f(&e->smo, k * i_dq_A.d, dfq);
    }
    psi_band_rebase(&e->pb, dfq, e->rt.ident_sync); /* the fine bound from here (design sec. 9f) */
    e->out.inv_err_V = FUNDAMENTAL_OF_SQUARE * e->inv_dv_V;
}

void est_r_track_event(est_t *e, r_track_event_t ev, dq_t i_dq_A)
{
    if (ev == R_TRACK_IDENT_DONE) {
        add_inverter_error(e, QUARTER_PI * e->rt.Ve_V, i_dq_A); /* per leg: (pi/4) Ve */
        e->rt_flags &= EST_FLAG_ANGLE_SUSPECT;
        e->force = EST_MOVED_ALL; /* taken again, now trusted */
        start_tracking(e);
    } else if (ev == R_TRACK_IDENT_REFUSED) {
        e->rt_flags = (uint16_t)((e->rt_flags & EST_FLAG_ANGLE_SUSPECT) | EST_FLAG_INV_UNIDENTIFIED); /* says so,
                                                            * and keeps the dead time as told */
        /* nothing bounds the error then: the told model at every speed (design sec. 9g) */
        psi_band_bound_unknown(&e->pb);
        e->force = EST_MOVED_ALL;
        start_tracking(e);
    } else if (ev == R_TRACK_CYCLE) {
        /* rho = dR with the inverter error compensated: R^ += -k_R rho + rate, within the band */
        const float fq_V = e->smo.fq_V;
        if (smo_set_R(&e->smo, e->smo.R_Ohm + e->rt.dR_step_Ohm)) {
            psi_band_r_moved(&e->pb, e->smo.fq_V - fq_V); /* design sec. 9f */
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

/* Step 1's result with the d-axis check (observer_design.md sec. 6g): an
 * error e_L of dL moves R^ by w1 w2 (id2 - id1) e_L / den when the
 * windows' id differ (field weakening at the voltage limit). Where the
 * correction the solve applied, |k dL^|, exceeds se(R^)'s limit, the two
 * windows' own dL_j = (fd_j + dR id_j)/(w_j iq_j) must agree within it
 * too, |k (dL1 - dL2)|; else the model does not hold on the d axis and R^
 * hangs on it: refused (RS_IDENT_D_AXIS). */
static rs_ident_result_t rsid_checks(const est_t *e, rs_ident_result_t r_solved, rs_ident_out_t *o)
{
    rs_ident_result_t r = r_solved;
    o->R_d_axis_Ohm = 0.0f;
    o->angle_el_rad = 0.0f;
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
            /* an angle error d adds -w psi_f d to fd: dL_j = dL - psi_f d / iq_j (sec. 6h) */
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
        }
    }
    return r;
}

static rs_ident_result_t rsid_solve(const est_t *e, rs_ident_out_t *o)
{
    return rsid_checks(e, rs_ident_solve(&e->ri, o), o);
}

bool est_rsid_stage_begin(est_t *e, rs_ident_solver_t *s, rs_ident_head_t *win2_copy)
{
    if (!rs_ident_batch_closed(&e->ri, RS_IDENT_WINDOW_2)) {
        return false;
    }
    rs_ident_copy_head(win2_copy, &e->ri, RS_IDENT_WINDOW_2);
    rs_ident_solve_begin(s, &e->ri, win2_copy);
    return true;
}

bool est_rsid_stage_step(est_t *e, rs_ident_solver_t *s)
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

rs_ident_result_t est_rsid_finish(est_t *e)
{
    return est_rsid_finish_with(e, rsid_solve(e, &e->rsid_out));
}

rs_ident_result_t est_rsid_finish_with(est_t *e, rs_ident_result_t r_solved)
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
        /* a suspected angle error would be learned as L: L^ held, a warning (sec. 6h) */
        const bool suspect = !(mathx_fabsf(e->rsid_out.angle_el_rad) <= EST_ANGLE_SUSPECT_RAD);
        param_est_hold_L(&e->pe, suspect);
        psi_band_hold(&e->pb, suspect); /* the told model, the conventional path */
        e->hold_fixed = suspect ? EST_HOLD_ANGLE : 0u;
        e->rt_flags = suspect ? EST_FLAG_ANGLE_SUSPECT : 0u;
        e->out.hold = e->hold_fixed;
        e->out.flags = e->rt_flags;
        if (!suspect) {
            /* first the inverter error, at R^ = R0 (design sec. 9); not with the
             * told model held: its injection would only disturb the torque */
            r_track_start(&e->rt, R_TRACK_IDENT);
        }
    } else {
        e->phase = EST_OFF;
        out_told(e);
    }
    return r;
}

bool est_start_trusted(est_t *e, float R_Ohm)
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
    start_step2(e); /* no inverter-error identification: R is trusted, not measured */
    psi_band_bound_final(&e->pb);
    return true;
}
