/*
 * ctrl.c - the drive controller; see ctrl.h.
 *
 * Cost per ctrl_step() in speed mode on the normal path, as measured by
 * `make bench-ctrl` (callgrind, x86-64 -O2; the bench closes the loop over
 * a motor model; how it was brought down: observer_design.md sec. 10):
 *   instructions: conventional 994; proposed (step 2 running) 1343
 *            (+35 %); proposed with track_R (observer_design.md sec. 9)
 *            1405; the dead-time feedforward is about 100 of them (both);
 *   sin/cos: one angle (mathx_sincosf at theta; the advanced angle is a
 *            rotation by a short series), both methods;
 *   divisions: conventional 2 (MTPA's q flux L Te* / kt, svpwm_duty's
 *            1/Vdc); proposed 3.62 on average: + 1 guarded one in the
 *            transfer law whose turn it is (param_est: the laws
 *            alternate), 0.5 in the observer's gain (L^'s turns), 2 in
 *            dbdtc_set_params only when L^ or psi^ moved by more than
 *            CTRL_MODEL_UPDATE_REL (0.12 per step); with track_R 3.84
 *            (the injection moves the estimates past it in 17 % of the
 *            periods: 0.34); plus 3 only in the periods the hexagon limit
 *            acts; none more while the field is weakened (oplim.h);
 *   square roots: 3 (MTPA, eq. 17, the monitor's |psi_s|), both methods,
 *            + 1 while the field is weakened.
 */
#include "ctrl.h"

#include "mathx.h"
#include "oplim.h"
#include "svpwm.h"

/* The voltage computed now is applied over [k+1, k+2]: its middle lies
 * 1.5 periods after the sample instant. */
#define ANGLE_ADVANCE_PERIODS 1.5f
/* Bound on that advance [rad]: the series below is exact to float within it
 * (error < delta^7/5040 = 1.5e-6 at the bound). */
#define ANGLE_ADVANCE_MAX_RAD 0.5f
#define SERIES_INV_2   0.5f
#define SERIES_INV_6   0.166666667f
#define SERIES_INV_24  0.0416666667f
#define SERIES_INV_120 0.00833333333f
#define SERIES_INV_720 0.00138888889f
#define DUTY_ZERO_VOLTAGE 0.5f
/* Default floor of L^: this factor above the observer's stability bound
 * L > (Ks/phi + R_max) Ts / 2 (smo_init), so an estimate near the floor
 * still leaves the linear region a pole margin. */
#define OBS_L_MIN_STABILITY_MARGIN 1.25f
/* ctrl_obs_gains_design (observer_design.md sec. 3b): the lowest floor of
 * L^ the gain must allow, x the told L (an L told 1.4x high leaves the
 * true one at 0.71x); the R^ band's top that (36) leaves, x G (the
 * band's 0.9 (Ks - ef_max)/phi with Ks = 2 ef_max); Ks over ef_max:
 * (36)'s floor ef_max / (1 - 0.45) with a 10 % margin. Table I: Ks 100 V,
 * G = 40 V/A, R^ up to 18 Ohm, the cap 0.8 L/(1.45 Ts) = 61 V/A not reached. */
#define OBS_L_FLOOR_SHARE 0.5f
#define OBS_R_TOP_PER_G   0.45f
#define OBS_KS_PER_EF     2.0f
#define HALF 0.5f
/* The default R^ band's top stays this fraction of the largest R that
 * meets (36) with the observer's default gains (18 Ohm for Table I). */
#define RSID_BAND_KS_MARGIN 0.9f
/* Longest dead time taken as such, in periods; beyond it the cfg is refused (0 used). */
#define DEADTIME_FRAC_MAX 0.1f
/* Share of the hexagon's inscribed circle Vdc/sqrt(3) the flux reference
 * leaves for steady state when cfg.u_margin is not in (0, 1] (design
 * sec. 7): the rest is the deadbeat's headroom for torque changes. */
#define CTRL_U_MARGIN_DEFAULT 0.92f

/* The model takes the observer's L^, psi^ when they moved by more than
 * this share since it last did: below it the change of the torque and
 * flux targets is 1e-4 of theirs, and the 2 divisions of
 * dbdtc_set_params are saved in the periods of steady state. */
#define CTRL_MODEL_UPDATE_REL 1.0e-4f
/* A per-leg square wave of amplitude dv (dead time, device drop) has the
 * rotor-frame fundamental (4/pi) dv against the current (design sec. 9). */
#define FUNDAMENTAL_OF_SQUARE 1.27323954f
#define QUARTER_PI 0.785398163f

/* What db.par holds (ctrl_t.model_src). */
#define MODEL_OBSERVER 0u      /* the observer's estimates, up to date */
#define MODEL_NOMINAL  1u      /* the configured parameters */
#define MODEL_STALE    2u      /* the observer's, but R^ changed since */

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

void ctrl_obs_gains_default(ctrl_obs_gains_t *g)
{
    g->Ks_V = SMO_KS_DEFAULT_V;
    g->phi_A = SMO_PHI_DEFAULT_A;
    g->ef_max_V = SMO_EF_MAX_DEFAULT_V;
}

bool ctrl_obs_gains_design(float Ts_s, float R_Ohm, float L_H, float ef_max_V, float phi_A,
                           ctrl_obs_gains_t *g, float *G_max_V_A)
{
    /* 1.25 (Ts/2)(G + R_max) <= L_FLOOR_SHARE L with R_max <= R_TOP_PER_G G */
    const float G_max = (2.0f * OBS_L_FLOOR_SHARE * L_H / (OBS_L_MIN_STABILITY_MARGIN * Ts_s)) /
                        (1.0f + OBS_R_TOP_PER_G);
    g->Ks_V = OBS_KS_PER_EF * ef_max_V;
    g->phi_A = phi_A;
    g->ef_max_V = ef_max_V;
    if (g->Ks_V / phi_A > G_max) {
        g->phi_A = g->Ks_V / G_max;   /* the cap: a wider layer keeps (36)'s margin */
    }
    *G_max_V_A = G_max;
    return (G_max > 0.0f) && (OBS_R_TOP_PER_G * (g->Ks_V / g->phi_A) >= R_Ohm);
}

void ctrl_cfg_proposed_defaults(ctrl_cfg_t *cfg, float R_min_Ohm, float R_max_Ohm)
{
    ctrl_obs_gains_t g;
    ctrl_obs_gains_default(&g);
    ctrl_cfg_proposed_with(cfg, R_min_Ohm, R_max_Ohm, &g);
}

void ctrl_cfg_proposed_with(ctrl_cfg_t *cfg, float R_min_Ohm, float R_max_Ohm, const ctrl_obs_gains_t *g)
{
    smo_cfg_t *sc = &cfg->smo;
    param_est_cfg_t *ec = &cfg->pe;

    cfg->R_min_Ohm = R_min_Ohm;
    cfg->R_max_Ohm = R_max_Ohm;
    smo_cfg_defaults(sc, cfg->Ts_s, cfg->R_Ohm, cfg->L_H, cfg->psi_f_Wb);
    sc->Ks_V = g->Ks_V;
    sc->phi_A = g->phi_A;
    sc->ef_max_V = g->ef_max_V;
    const float L_stable_H = OBS_L_MIN_STABILITY_MARGIN * HALF * cfg->Ts_s *
                             (sc->Ks_V / sc->phi_A + R_max_Ohm);
    /* not capped at L_max: a floor above it is refused by smo_init */
    sc->L_min_H = (sc->L_min_H >= L_stable_H) ? sc->L_min_H : L_stable_H;
    sc->f_max_V = cfg->u_max_V; /* a disturbance beyond the voltage bound is no estimate */
    param_est_cfg_defaults(ec, cfg->Ts_s, cfg->L_H, cfg->psi_f_Wb);
    ec->L_min_H = sc->L_min_H;  /* clamps = the observer's ranges */
    ec->L_max_H = sc->L_max_H;
    ec->psi_min_Wb = sc->psi_min_Wb;
    ec->psi_max_Wb = sc->psi_max_Wb;
    rs_ident_cfg_defaults(&cfg->rsid, cfg->R_Ohm);
    r_track_cfg_defaults(&cfg->rtrack);
    cfg->track_R = 0u;
    est_gate_cfg_defaults(&cfg->gate, cfg->Ts_s);
}

void ctrl_rsid_band_default(const ctrl_cfg_t *cfg, float *R_min_Ohm, float *R_max_Ohm)
{
    ctrl_obs_gains_t g;
    ctrl_obs_gains_default(&g);
    ctrl_rsid_band_with(cfg, &g, R_min_Ohm, R_max_Ohm);
}

void ctrl_rsid_band_with(const ctrl_cfg_t *cfg, const ctrl_obs_gains_t *g, float *R_min_Ohm, float *R_max_Ohm)
{
    /* (36): Ks > ef_max + R_max phi, with a margin */
    const float R_ks_Ohm = RSID_BAND_KS_MARGIN * (g->Ks_V - g->ef_max_V) / g->phi_A;
    const float R_top_Ohm = RS_IDENT_BAND_MAX_FACTOR * cfg->R_Ohm;
    *R_min_Ohm = RS_IDENT_BAND_MIN_FACTOR * cfg->R_Ohm;
    *R_max_Ohm = (R_top_Ohm < R_ks_Ohm) ? R_top_Ohm : R_ks_Ohm;
    *R_max_Ohm = (*R_max_Ohm > cfg->R_Ohm) ? *R_max_Ohm : cfg->R_Ohm;
}

/* The proposed method's blocks, with the fields that repeat ctrl_cfg_t taken from it. */
static ctrl_status_t init_proposed(ctrl_t *c, const ctrl_cfg_t *cfg)
{
    smo_cfg_t sc = cfg->smo;
    param_est_cfg_t ec = cfg->pe;
    rs_ident_cfg_t rc = cfg->rsid;
    est_gate_cfg_t gc = cfg->gate;

    sc.Ts_s = cfg->Ts_s;
    sc.R_Ohm = cfg->R_Ohm;
    sc.L_H = cfg->L_H;
    sc.psi_f_Wb = cfg->psi_f_Wb;
    sc.R_min_Ohm = cfg->R_min_Ohm;
    sc.R_max_Ohm = cfg->R_max_Ohm;
    sc.i_max_A = cfg->i_max_A;
    sc.u_max_V = cfg->u_max_V;
    sc.omega_max_rad_s = cfg->omega_max_el_rad_s;
    ec.Ts_s = cfg->Ts_s;
    rc.R_nom_Ohm = cfg->R_Ohm;
    rc.Ts_s = cfg->Ts_s;
    rc.R_min_Ohm = cfg->R_min_Ohm;
    rc.R_max_Ohm = cfg->R_max_Ohm;
    gc.Ts_s = cfg->Ts_s;
    const ctrl_status_t gate = est_gate_init(&c->gate, &gc) ? CTRL_CFG_OK : CTRL_CFG_GATE;

    if (smo_init(&c->smo, &sc) != SMO_CFG_OK) {
        (void)param_est_init(&c->pe, &ec, &c->smo); /* refused too: frozen for good */
        (void)rs_ident_init(&c->ri, &rc);
        return (ctrl_status_t)(CTRL_CFG_OBSERVER | gate);
    }
    if (!r_track_init(&c->rt, &cfg->rtrack)) {
        (void)param_est_init(&c->pe, &ec, &c->smo);
        (void)rs_ident_init(&c->ri, &rc);
        return CTRL_CFG_RTRACK;
    }
    psi_band_cfg_t bc;
    psi_band_cfg_defaults(&bc, cfg->Ts_s, ec.w_min_rad_s, ec.psi_min_Wb, ec.psi_max_Wb);
    if (!param_est_init(&c->pe, &ec, &c->smo) || !psi_band_init(&c->pb, &bc)) {
        (void)rs_ident_init(&c->ri, &rc);
        return (ctrl_status_t)(CTRL_CFG_ESTIMATOR | gate);
    }
    return (ctrl_status_t)((rs_ident_init(&c->ri, &rc) ? CTRL_CFG_OK : CTRL_CFG_RSID) | gate);
}

/* status with bit added unless ok. */
static ctrl_status_t refused_if(bool ok, ctrl_status_t bit, ctrl_status_t status)
{
    return ok ? status : (ctrl_status_t)(status | bit);
}

ctrl_status_t ctrl_init(ctrl_t *c, const ctrl_cfg_t *cfg)
{
    encoder_cfg_t ec;
    dbdtc_cfg_t dc;
    pi_cfg_t pc;
    const rs_ident_out_t no_result = { 0 };
    ctrl_status_t status = CTRL_CFG_OK;

    c->cfg = *cfg;

    ec.counts_per_rev = 4u * cfg->enc_lines;
    ec.pole_pairs = cfg->pole_pairs;
    ec.offset_el_rad = cfg->enc_offset_el_rad;
    ec.Ts_s = cfg->Ts_s;
    ec.pll_bw_rad_s = cfg->enc_pll_bw_rad_s;
    status = refused_if(encoder_init(&c->enc, &ec), CTRL_CFG_ENCODER, status); /* refused: angle 0, speed 0 */

    dc.Ts_s = cfg->Ts_s;
    dc.pole_pairs = cfg->pole_pairs;
    dc.R_Ohm = cfg->R_Ohm;
    dc.L_H = cfg->L_H;
    dc.psi_f_Wb = cfg->psi_f_Wb;
    dc.i_max_A = cfg->i_max_A;
    dc.omega_max_rad_s = cfg->omega_max_el_rad_s;
    dc.u_max_V = cfg->u_max_V;
    dc.te_max_Nm = cfg->te_max_Nm;
    dc.psi_max_Wb = cfg->psi_max_Wb;
    status = refused_if(dbdtc_init(&c->db, &dc), CTRL_CFG_DBDTC, status);

    pc.Kp = cfg->speed_kp_Nms_rad;
    pc.Ki = cfg->speed_ki_Nm_rad;
    pc.Ts_s = cfg->Ts_s;
    pc.u_min = -cfg->te_max_Nm;
    pc.u_max = cfg->te_max_Nm;
    status = refused_if(pi_init(&c->speed_pi, &pc), CTRL_CFG_SPEED_PI, status); /* refused: Te* = 0 */

    /* td/Ts; a non-finite or implausible dead time is refused (and not compensated) */
    c->deadtime_frac = cfg->deadtime_s / cfg->Ts_s;
    if (!((c->deadtime_frac >= 0.0f) && (c->deadtime_frac <= DEADTIME_FRAC_MAX))) {
        c->deadtime_frac = 0.0f;
        status = refused_if(false, CTRL_CFG_DEADTIME, status);
    }
    c->i_lim_A = ((cfg->i_lim_A > 0.0f) && (cfg->i_lim_A <= cfg->i_max_A)) ? cfg->i_lim_A : cfg->i_max_A;
    c->u_lim_per_vdc = MATHX_INV_SQRT3_F * (((cfg->u_margin > 0.0f) && (cfg->u_margin <= 1.0f))
                                                ? cfg->u_margin : CTRL_U_MARGIN_DEFAULT);
    oplim_init(&c->lim, cfg->Ts_s, OPLIM_FW_RATE_DEFAULT_WB_S, OPLIM_FW_HYST_DEFAULT);
    c->status = (ctrl_status_t)(status | init_proposed(c, cfg));
    c->rsid_out = no_result;
    c->rsid_out.R_est_Ohm = cfg->R_Ohm;
    c->mode = CTRL_MODE_TORQUE;
    c->mode_req = CTRL_MODE_TORQUE;
    c->method = CTRL_METHOD_CONVENTIONAL;
    c->ref.speed_ref_rad_s = 0.0f;
    c->ref.te_ref_Nm = 0.0f;
    c->ref.ud_ref_V = 0.0f;
    c->ref.uq_ref_V = 0.0f;
    c->tracked = false;
    ctrl_reset(c);
    return c->status;
}

void ctrl_reset(ctrl_t *c)
{
    dbdtc_reset(&c->db);
    c->model_src = MODEL_NOMINAL;
    smo_reset(&c->smo);
    param_est_reset(&c->pe);
    rs_ident_reset(&c->ri);
    c->rsid_win = RS_IDENT_WINDOW_NONE;
    c->ident = CTRL_IDENT_OFF;
    r_track_reset(&c->rt);
    c->inv_dv_V = 0.0f;
    c->rt_flags = 0u;
    c->psi_held = 0u;
    c->pe.cfg.w_min_rad_s = c->cfg.pe.w_min_rad_s;
    est_gate_reset(&c->gate, &c->smo);
    oplim_reset(&c->lim);
    c->flags_last = 0u;
    pi_reset(&c->speed_pi, 0.0f);
    c->mode = c->mode_req;
    c->u_applied_V.d = 0.0f;
    c->u_applied_V.q = 0.0f;
    c->mon.theta_el_rad = 0.0f;
    c->mon.omega_el_rad_s = 0.0f;
    c->mon.speed_mech_rad_s = 0.0f;
    c->mon.id_A = 0.0f;
    c->mon.iq_A = 0.0f;
    c->mon.ud_V = 0.0f;
    c->mon.uq_V = 0.0f;
    c->mon.te_ref_Nm = 0.0f;
    c->mon.te_est_Nm = 0.0f;
    c->mon.psi_ref_Wb = 0.0f;
    c->mon.psi_est_Wb = 0.0f;
    c->mon.R_est_Ohm = c->db.par.R_Ohm;
    c->mon.L_est_H = c->db.par.L_H;
    c->mon.psi_f_est_Wb = c->db.par.psi_f_Wb;
    c->mon.fd_est_V = 0.0f;
    c->mon.fq_est_V = 0.0f;
    c->mon.ident = CTRL_IDENT_OFF;
    c->mon.est_hold = 0u;
    c->mon.model_from_observer = 0u;
    c->mon.inv_err_V = 0.0f;
    c->mon.psi_f_model_Wb = c->db.par.psi_f_Wb;
}

void ctrl_track(ctrl_t *c, uint32_t enc_count)
{
    encoder_step(&c->enc, enc_count);
    c->tracked = true;
}

void ctrl_encoder_align(ctrl_t *c, uint32_t enc_count)
{
    encoder_align(&c->enc, enc_count);
}

void ctrl_set_i_lim(ctrl_t *c, float i_lim_A)
{
    c->i_lim_A = ((i_lim_A > 0.0f) && (i_lim_A <= c->cfg.i_max_A)) ? i_lim_A : c->cfg.i_max_A;
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

bool ctrl_rsid_begin(ctrl_t *c)
{
    if ((c->status & CTRL_CFG_NEEDED_PROPOSED) != 0u) {
        return false;
    }
    smo_reset(&c->smo); /* nominal R, L, psi: rs_ident's dR is relative to them */
    param_est_run(&c->pe, false);
    rs_ident_reset(&c->ri);
    c->rsid_win = RS_IDENT_WINDOW_NONE;
    c->ident = CTRL_IDENT_STEP1;
    r_track_reset(&c->rt); /* identified again after this step 1 */
    c->inv_dv_V = 0.0f;
    c->pe.cfg.w_min_rad_s = c->cfg.pe.w_min_rad_s;
    c->rt_flags = 0u;
    return true;
}

void ctrl_rsid_window(ctrl_t *c, rs_ident_window_t win)
{
    c->rsid_win = win;
}

/* R^ tracked from now on when configured. */
static void start_tracking(ctrl_t *c)
{
    /* psi^ learns only where w psi_f dominates what the identification may have left */
    const float w_min = r_track_w_psi_min(&c->rt, c->cfg.psi_f_Wb);
    c->pe.cfg.w_min_rad_s = (w_min > c->cfg.pe.w_min_rad_s) ? w_min : c->cfg.pe.w_min_rad_s;
    r_track_start(&c->rt, (c->cfg.track_R != CTRL_TRACK_R_OFF) ? R_TRACK_TRACK : R_TRACK_OFF);
    if (c->cfg.track_R == CTRL_TRACK_R_AUTO) {
        r_track_delay(&c->rt, c->cfg.rtrack.auto_delay_periods);
    }
}

/* Step 2 starts: estimator running, R tracked when configured. */
static void start_step2(ctrl_t *c)
{
    param_est_run(&c->pe, true);
    est_gate_reset(&c->gate, &c->smo);
    psi_band_start(&c->pb, c->smo.psi_f_Wb); /* the model's value then (design sec. 9f) */
    c->ident = CTRL_IDENT_STEP2;
    if (c->model_src == MODEL_OBSERVER) {
        c->model_src = MODEL_STALE;
    }
    start_tracking(c);
}

/* Per-leg voltage error dv_V [V] of the dead time's shape added to the
 * compensation, bumplessly: f^ takes the fundamental -(4/pi) dv i/|i| it
 * no longer has to explain (design sec. 9). 1 square root, 1 division, once. */
static void add_inverter_error(ctrl_t *c, float dv_V, dq_t i_dq_A)
{
    const float i_abs = mathx_sqrtf(i_dq_A.d * i_dq_A.d + i_dq_A.q * i_dq_A.q);
    float dfq = 0.0f;
    c->inv_dv_V += dv_V;
    if (i_abs > 0.0f) {
        const float k = -FUNDAMENTAL_OF_SQUARE * dv_V / i_abs;
        dfq = k * i_dq_A.q;
        c->smo.fd_V += k * i_dq_A.d;
        c->smo.fq_V += dfq;
    }
    psi_band_rebase(&c->pb, dfq); /* the fine bound from here (design sec. 9f) */
}

/* The injection's period: after step 1 the inverter error, in step 2 R^. */
static void ctrl_r_track_step(ctrl_t *c, dq_t i_dq_A, float omega_el_rad_s)
{
    const float z = c->smo.fd_V - omega_el_rad_s * c->smo.L_H * i_dq_A.q; /* L^ law's invariant */
    const r_track_event_t ev = r_track_step(&c->rt, z, i_dq_A.d, i_dq_A.q, omega_el_rad_s, c->smo.L_H);

    if (ev == R_TRACK_IDENT_DONE) {
        add_inverter_error(c, QUARTER_PI * c->rt.Ve_V, i_dq_A); /* per leg: (pi/4) Ve */
        c->rt_flags = 0u;
        start_tracking(c);
    } else if (ev == R_TRACK_IDENT_REFUSED) {
        c->rt_flags = CTRL_FLAG_INV_UNIDENTIFIED; /* says so, and keeps the dead time as told */
        start_tracking(c);
    } else if (ev == R_TRACK_CYCLE) {
        /* rho = dR with the inverter error compensated: R^ += -k_R rho + rate, within the band */
        if (smo_set_R(&c->smo, c->smo.R_Ohm + c->rt.dR_step_Ohm)) {
            c->rt_flags &= (uint16_t)~CTRL_FLAG_R_HELD;
            if (c->model_src == MODEL_OBSERVER) {
                c->model_src = MODEL_STALE;
            }
        } else {
            c->rt_flags |= CTRL_FLAG_R_HELD;
        }
    } else if (ev == R_TRACK_HELD) {
        c->rt_flags |= CTRL_FLAG_R_HELD;
    } else {
        /* cycle under way */
    }
}

rs_ident_result_t ctrl_rsid_check(const ctrl_t *c, rs_ident_out_t *out)
{
    return rs_ident_solve(&c->ri, out);
}

rs_ident_result_t ctrl_rsid_finish(ctrl_t *c)
{
    return ctrl_rsid_finish_with(c, rs_ident_solve(&c->ri, &c->rsid_out));
}

rs_ident_result_t ctrl_rsid_finish_with(ctrl_t *c, rs_ident_result_t r_solved)
{
    rs_ident_result_t r = r_solved;

    rs_ident_reset(&c->ri); /* a second finish without a begin finds no data */
    c->rsid_win = RS_IDENT_WINDOW_NONE;
    if (c->ident != CTRL_IDENT_STEP1) {
        r = RS_IDENT_TOO_FEW; /* no step 1 under way */
    } else if ((r == RS_IDENT_OK) && !smo_set_R(&c->smo, c->rsid_out.R_est_Ohm)) {
        r = RS_IDENT_OUT_OF_BAND; /* same band as rs_ident's: not expected */
    }
    if (r == RS_IDENT_OK) {
        start_step2(c);
        /* first the inverter error, at R^ = R0 (design sec. 9) */
        r_track_start(&c->rt, R_TRACK_IDENT);
    } else {
        c->ident = CTRL_IDENT_OFF;
    }
    return r;
}

bool ctrl_est_start(ctrl_t *c, float R_Ohm)
{
    /* ! (in band): NaN fails too */
    if (((c->status & CTRL_CFG_NEEDED_PROPOSED) != 0u) ||
        !((R_Ohm >= c->cfg.R_min_Ohm) && (R_Ohm <= c->cfg.R_max_Ohm))) {
        return false;
    }
    if (c->ident == CTRL_IDENT_OFF) {
        smo_reset(&c->smo); /* seeded with i(k) at the next step, f^ = 0 */
    }
    (void)smo_set_R(&c->smo, R_Ohm); /* in band: accepted */
    rs_ident_reset(&c->ri);
    c->rsid_win = RS_IDENT_WINDOW_NONE;
    start_step2(c); /* no inverter-error identification: R is trusted, not measured */
    return true;
}

void ctrl_set_i_limit(ctrl_t *c, float i_lim_A)
{
    const float cfg_A = ((c->cfg.i_lim_A > 0.0f) && (c->cfg.i_lim_A <= c->cfg.i_max_A)) ? c->cfg.i_lim_A
                                                                                         : c->cfg.i_max_A;
    c->i_lim_A = ((i_lim_A > 0.0f) && (i_lim_A <= cfg_A)) ? i_lim_A : cfg_A;
}

void ctrl_set_ref(ctrl_t *c, const ctrl_ref_t *ref)
{
    c->ref = *ref;
}

/*
 * The model: parameters in use (in c->db.par) and the state at k+1 that
 * compensates the one-period delay; the one place the methods differ
 * (steps 2-4 of the header's sequence).
 */
static dbdtc_state_t ctrl_model_step(ctrl_t *c, dq_t i_dq_A, float omega_el_rad_s, float sin_el, float cos_el,
                                      float vdc_V)
{
    if (c->ident != CTRL_IDENT_OFF) {
        /* u(k) is the clamped voltage the last step realised, as the observer needs */
        const dq_t i_hat = smo_step(&c->smo, i_dq_A, omega_el_rad_s, c->u_applied_V); /* (51b), (55) */
        if (c->rt.phase != R_TRACK_OFF) {
            if ((c->lim.dpsi_Wb > 0.0f) || ((c->flags_last & CTRL_FLAG_VOLTAGE_LIMIT) != 0u)) {
                /* tracking only: the field weakened or the voltage at its limit (last period) */
                r_track_hold(&c->rt);
            }
            ctrl_r_track_step(c, i_dq_A, omega_el_rad_s); /* may end step 1 */
        }
        if (c->ident == CTRL_IDENT_STEP1) {
            /* the angle for the fit of the electrical-frequency ripple (design sec. 6e) */
            rs_ident_step_el(&c->ri, c->rsid_win, c->smo.fd_V, c->smo.fq_V, i_dq_A.d, i_dq_A.q,
                             omega_el_rad_s, cos_el, sin_el);
        } else {
            /* pause and hold while the laws' assumptions are broken (est_gate.h); the
             * injected d current is no transient (design sec. 9) */
            dq_t i_gate = i_dq_A;
            i_gate.d -= c->rt.id_expect_A;
            uint16_t moved = est_gate_step(&c->gate, &c->smo, omega_el_rad_s, i_gate, c->mon.te_ref_Nm,
                                           (c->flags_last & CTRL_FLAG_VOLTAGE_LIMIT) != 0u) ? 1u : 0u;
            c->psi_held = CTRL_FLAG_PSI_HELD;
            if (c->gate.reasons == 0u) {
                moved |= param_est_step(&c->pe, &c->smo, omega_el_rad_s, i_dq_A.q);
                /* the model's psi_f: only what the voltage it cannot explain
                 * (the inverter error compensated, noise) cannot fake (design sec. 9f) */
                if (psi_band_step(&c->pb, c->smo.psi_f_Wb, c->smo.fq_V, omega_el_rad_s,
                                  FUNDAMENTAL_OF_SQUARE * c->deadtime_frac * vdc_V, FUNDAMENTAL_OF_SQUARE * c->inv_dv_V)) {
                    moved = 1u;
                    c->psi_held = 0u;
                }
            } else {
                psi_band_pause(&c->pb);
            }
            if (c->method == CTRL_METHOD_PROPOSED) {
                /* 2 divisions, only when an estimate moved by more than
                 * CTRL_MODEL_UPDATE_REL since the model took it */
                const dbdtc_par_t *p = &c->db.par;
                const bool far = (mathx_fabsf(c->smo.L_H - p->L_H) > CTRL_MODEL_UPDATE_REL * p->L_H) ||
                                 (mathx_fabsf(c->pb.psi_Wb - p->psi_f_Wb) > CTRL_MODEL_UPDATE_REL * p->psi_f_Wb);
                if (((moved != 0u) && far) || (c->model_src != MODEL_OBSERVER)) {
                    dbdtc_set_params(&c->db, c->smo.R_Ohm, c->smo.L_H, c->pb.psi_Wb);
                    c->model_src = MODEL_OBSERVER;
                }
                if (!est_gate_f_usable(&c->gate)) {
                    /* f^ carries a current transient: eq. (10)-(12) with the
                     * held estimates (design sec. 7) */
                    return dbdtc_predict(&c->db, i_dq_A, c->u_applied_V, omega_el_rad_s);
                }
                return dbdtc_state_from_currents(&c->db, i_hat); /* replaces eq. (10) */
            }
        }
    }
    if (c->model_src != MODEL_NOMINAL) {
        dbdtc_reset(&c->db); /* back from the proposed method: 2 divisions once */
        c->model_src = MODEL_NOMINAL;
    }
    return dbdtc_predict(&c->db, i_dq_A, c->u_applied_V, omega_el_rad_s); /* eq. (10)-(12) */
}

/* Mean rotor-frame voltage error [V] the dead time adds over the period
 * whose middle is at the angle (sin_a, cos_a): each leg loses or gains
 * vdc*td/Ts against the sign of its current (diode conduction in the dead
 * band), the currents taken as i_dq at that angle. Hard sign: near a zero
 * crossing the real error is smaller (left in f^ for those periods). */
static dq_t deadtime_error(const ctrl_t *c, dq_t i_dq_A, float sin_a, float cos_a, float vdc_V)
{
    const abc_t i = clarke_inv(park_inv(i_dq_A, sin_a, cos_a));
    const float dv_sum = c->deadtime_frac * vdc_V + c->inv_dv_V;
    const float dv = (dv_sum > 0.0f) ? dv_sum : 0.0f; /* an identified over-compensation at most cancels it */
    const float va = (i.a > 0.0f) ? -dv : ((i.a < 0.0f) ? dv : 0.0f);
    const float vb = (i.b > 0.0f) ? -dv : ((i.b < 0.0f) ? dv : 0.0f);
    const float vc = (i.c > 0.0f) ? -dv : ((i.c < 0.0f) ? dv : 0.0f);
    return park(clarke_3ph(va, vb, vc), sin_a, cos_a);
}

/* sin/cos of theta + delta from those of theta: rotation by a series in
 * delta (|delta| <= ANGLE_ADVANCE_MAX_RAD), saving a second sincos. */
static void rotate_sincos(float s, float c, float delta_rad, float *s_out, float *c_out)
{
    const float d = mathx_clampf(delta_rad, -ANGLE_ADVANCE_MAX_RAD, ANGLE_ADVANCE_MAX_RAD);
    const float d2 = d * d;
    const float sd = d * (1.0f - d2 * SERIES_INV_6 * (1.0f - d2 * (SERIES_INV_120 / SERIES_INV_6)));
    const float cd = 1.0f - d2 * SERIES_INV_2 * (1.0f - d2 * (SERIES_INV_24 / SERIES_INV_2) *
                                                          (1.0f - d2 * (SERIES_INV_720 / SERIES_INV_24)));
    *s_out = s * cd + c * sd;
    *c_out = c * cd - s * sd;
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

void ctrl_step(ctrl_t *c, const ctrl_in_t *in, ctrl_out_t *out)
{
    const ctrl_cfg_t *cfg = &c->cfg;
    float s;
    float co;
    float sa;
    float ca;
    float te_ref = 0.0f;
    float psi_ref = 0.0f;
    uint16_t flags = 0u;
    dq_t u;
    dq_t u_cmd;
    ab_t u_real;
    svpwm_duty_t duty;
    uint16_t pwm_flags;
    float chk;

    if (c->mode_req != c->mode) {
        if (c->mode_req == CTRL_MODE_SPEED) {
            pi_reset(&c->speed_pi, c->mon.te_est_Nm); /* bumpless: start from the torque there is */
        }
        c->mode = c->mode_req;
    }

    /* angle and speed (this period's ctrl_track), current in the rotor frame */
    if (!c->tracked) {
        encoder_step(&c->enc, in->enc_count);
    }
    c->tracked = false;
    const float theta = c->enc.theta_e_rad;
    const float omega = c->enc.omega_e_rad_s;
    mathx_sincosf(theta, &s, &co);
    const dq_t i_dq = park(clarke_2ph(in->ia_A, in->ib_A), s, co);

    /* delay compensation and the parameters in use */
    const dbdtc_state_t x = ctrl_model_step(c, i_dq, omega, s, co, in->vdc_V);
    const dbdtc_par_t *par = &c->db.par;

    if (c->mode == CTRL_MODE_OPEN_LOOP) {
        u.d = mathx_clampf(c->ref.ud_ref_V, -cfg->u_max_V, cfg->u_max_V);
        u.q = mathx_clampf(c->ref.uq_ref_V, -cfg->u_max_V, cfg->u_max_V);
    } else {
        if (c->mode == CTRL_MODE_SPEED) {
            te_ref = pi_step(&c->speed_pi, c->ref.speed_ref_rad_s - c->enc.omega_m_rad_s);
        } else {
            te_ref = mathx_clampf(c->ref.te_ref_Nm, -cfg->te_max_Nm, cfg->te_max_Nm);
        }
        /* current limit, MTPA (sec. III), flux weakening (oplim.h) */
        const oplim_out_t tgt = oplim_targets(&c->lim, par, c->i_lim_A, te_ref);
        te_ref = tgt.te_Nm;
        psi_ref = tgt.psi_Wb;
        psi_ref = r_track_psi_ref(&c->rt, psi_ref, par->L_H); /* + L id* (design sec. 9) */
        flags |= map_dbdtc_flags(dbdtc_solve(&c->db, &x, te_ref, psi_ref, omega, &u)); /* eq. (17) */
        oplim_fw_update(&c->lim, u, c->u_lim_per_vdc * in->vdc_V);
    }

    /* applied over [k+1, k+2]: rotor angle of its middle */
    rotate_sincos(s, co, ANGLE_ADVANCE_PERIODS * omega * cfg->Ts_s, &sa, &ca);
    flags |= map_dbdtc_flags(dbdtc_limit(&u, sa, ca, in->vdc_V));
    const dq_t u_dt = deadtime_error(c, i_dq, sa, ca, in->vdc_V);
    u_cmd.d = u.d - u_dt.d; /* fed forward: the inverter adds u_dt back */
    u_cmd.q = u.q - u_dt.q;
    pwm_flags = svpwm_duty(park_inv(u_cmd, sa, ca), in->vdc_V, &duty, &u_real);
    if ((pwm_flags & SVPWM_SATURATED) != 0u) {
        flags |= CTRL_FLAG_VOLTAGE_LIMIT;
    }
    /* what the inverter will realise is what the next prediction and the
     * observer use (a dead-time error left in it would end up in f^, then
     * in psi_f^: 1 us at 311 V put +10 % into psi_f^ in the SIL) */
    c->u_applied_V = park(u_real, sa, ca);
    c->u_applied_V.d += u_dt.d;
    c->u_applied_V.q += u_dt.q;

    if (c->mode == CTRL_MODE_SPEED) {
        /* anti-windup on the torque the applied voltage achieves */
        pi_apply(&c->speed_pi, dbdtc_torque_after(&c->db, &x, c->u_applied_V.q, omega));
    }

    c->mon.theta_el_rad = theta;
    c->mon.omega_el_rad_s = omega;
    c->mon.speed_mech_rad_s = c->enc.omega_m_rad_s;
    c->mon.id_A = i_dq.d;
    c->mon.iq_A = i_dq.q;
    c->mon.ud_V = c->u_applied_V.d;
    c->mon.uq_V = c->u_applied_V.q;
    c->mon.te_ref_Nm = te_ref;
    c->mon.te_est_Nm = x.te_Nm;
    c->mon.psi_ref_Wb = psi_ref;
    c->mon.psi_est_Wb = mathx_sqrtf(x.psi_dq_Wb.d * x.psi_dq_Wb.d + x.psi_dq_Wb.q * x.psi_dq_Wb.q);
    if (c->ident != CTRL_IDENT_OFF) { /* the observer's estimates, used or not */
        c->mon.R_est_Ohm = c->smo.R_Ohm;
        c->mon.L_est_H = c->smo.L_H;
        c->mon.psi_f_est_Wb = c->smo.psi_f_Wb;
        c->mon.fd_est_V = c->smo.fd_V;
        c->mon.fq_est_V = c->smo.fq_V;
    } else {
        c->mon.R_est_Ohm = par->R_Ohm;
        c->mon.L_est_H = par->L_H;
        c->mon.psi_f_est_Wb = par->psi_f_Wb;
        c->mon.fd_est_V = 0.0f;
        c->mon.fq_est_V = 0.0f;
    }
    c->mon.ident = c->ident;
    c->mon.est_hold = c->gate.reasons;
    c->mon.model_from_observer = (c->model_src == MODEL_OBSERVER) ? 1u : 0u;
    c->mon.inv_err_V = FUNDAMENTAL_OF_SQUARE * c->inv_dv_V;
    c->mon.psi_f_model_Wb = par->psi_f_Wb;

    /* One finiteness check per ISR: NaN and Inf survive a sum. The inputs
     * are in it because the blocks clamp (a NaN would become a bound); the
     * observer state because it carries over to the next periods. */
    chk = in->ia_A + in->ib_A + in->vdc_V + c->ref.speed_ref_rad_s + c->ref.te_ref_Nm +
          c->ref.ud_ref_V + c->ref.uq_ref_V + omega + x.te_Nm + u.d + u.q + duty.a + duty.b +
          duty.c + c->u_applied_V.d + c->u_applied_V.q + c->smo.fd_V + c->smo.fq_V +
          c->smo.i_hat_A.d + c->smo.i_hat_A.q + c->smo.L_H + c->smo.psi_f_Wb;
    c->flags_last = flags; /* before any NONFINITE: the gate's voltage check */
    output_duties(c, duty, mathx_isfinitef(chk), flags | c->rt_flags | ((c->ident == CTRL_IDENT_STEP2) ? c->psi_held : 0u), out);
}
