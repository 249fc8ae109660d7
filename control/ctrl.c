/*
 * ctrl.c - the drive controller; see ctrl.h.
 *
 * Cost per ctrl_step(): `make bench-ctrl` measures it (instructions,
 * divisions, square roots and sin/cos per step, both methods, track_R on
 * and off). Where the divisions are: MTPA's q flux and svpwm_duty's 1/Vdc
 * (both methods); the transfer law whose turn it is and the observer's
 * gain on L^'s turns (proposed); dbdtc_set_params only when the model
 * moved by more than CTRL_MODEL_UPDATE_REL; 3 more only in the periods
 * the hexagon limit acts. One sin/cos (the advanced angle is a rotation
 * by a short series).
 */
#include "ctrl.h"

#include "mathx.h"
#include "oplim.h"
#include "spmsm.h"
#include "svpwm.h"

/* Bound on the angle advance (spmsm.h) [rad]: the series below is exact to float within it
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
/* ctrl_obs_gains_design (smo_design.md sec. 4): the lowest floor of
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
/* Longest dead time taken as such, in periods, and the largest device drop,
 * x the model's voltage bound: the same share of the bus; beyond either the
 * cfg is refused (0 used). */
#define DEADTIME_FRAC_MAX 0.1f
/* Share of the hexagon's inscribed circle Vdc/sqrt(3) the flux reference
 * leaves for steady state when cfg.u_margin is not in (0, 1]
 * (limits_design.md sec. 2): the rest is the deadbeat's headroom for torque changes. */
#define CTRL_U_MARGIN_DEFAULT 0.92f

/* The model takes the observer's L^, psi^ when they moved by more than
 * this share since it last did: below it the change of the torque and
 * flux targets is 1e-4 of theirs, and the 2 divisions of
 * dbdtc_set_params are saved in the periods of steady state. */
#define CTRL_MODEL_UPDATE_REL 1.0e-4f
/* What db.par holds (ctrl_t.model_src). */
#define MODEL_EST      0u      /* the estimation's model */
#define MODEL_NOMINAL  1u      /* the configured parameters */

/* ctrl_cfg_t.track_R is the estimation's */
typedef char ctrl_track_r_is_est[((CTRL_TRACK_R_OFF == EST_TRACK_R_OFF) && (CTRL_TRACK_R_ON == EST_TRACK_R_ON) &&
                                  (CTRL_TRACK_R_AUTO == EST_TRACK_R_AUTO)) ? 1 : -1];

/* ctrl_ident_t is the estimation's phase */
typedef char ctrl_ident_is_est_phase[((CTRL_IDENT_OFF == (int)EST_OFF) && (CTRL_IDENT_STEP1 == (int)EST_STEP1) &&
                                      (CTRL_IDENT_STEP2 == (int)EST_STEP2)) ? 1 : -1];

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
    cfg->untold_deadtime_s = EST_UNTOLD_DEADTIME_DEFAULT_S;
    est_gate_cfg_defaults(&cfg->gate, cfg->Ts_s);
    /* above the speed estimate's count quantisation (step2_design.md sec. 5) */
    cfg->gate.accel_floor_rad_s2 =
        est_gate_accel_floor_rad_s2(ENCODER_COUNTS_PER_LINE * cfg->enc_lines, cfg->pole_pairs, cfg->enc_pll_bw_rad_s);
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

/* The estimation, with the told values and bounds from ctrl_cfg_t. */
static ctrl_status_t init_est(ctrl_t *c, const ctrl_cfg_t *cfg)
{
    est_cfg_t e;
    e.Ts_s = cfg->Ts_s;
    e.R_Ohm = cfg->R_Ohm;
    e.L_H = cfg->L_H;
    e.psi_f_Wb = cfg->psi_f_Wb;
    e.R_min_Ohm = cfg->R_min_Ohm;
    e.R_max_Ohm = cfg->R_max_Ohm;
    e.i_max_A = cfg->i_max_A;
    e.u_max_V = cfg->u_max_V;
    e.omega_max_el_rad_s = cfg->omega_max_el_rad_s;
    e.deadtime_s = c->deadtime_frac * cfg->Ts_s; /* as taken (0 when refused) */
    e.untold_deadtime_s = cfg->untold_deadtime_s;
    e.smo = cfg->smo;
    e.pe = cfg->pe;
    e.rsid = cfg->rsid;
    e.rtrack = cfg->rtrack;
    e.track_R = cfg->track_R;
    e.gate = cfg->gate;
    return est_init(&c->est, &e);
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
    ctrl_status_t status = CTRL_CFG_OK;

    c->cfg = *cfg;

    ec.counts_per_rev = ENCODER_COUNTS_PER_LINE * cfg->enc_lines;
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
    c->device_drop_V = cfg->device_drop_V;
    if (!((c->device_drop_V >= 0.0f) && (c->device_drop_V <= DEADTIME_FRAC_MAX * cfg->u_max_V))) {
        c->device_drop_V = 0.0f;
        status = refused_if(false, CTRL_CFG_DEADTIME, status);
    }
    c->i_lim_A = ((cfg->i_lim_A > 0.0f) && (cfg->i_lim_A <= cfg->i_max_A)) ? cfg->i_lim_A : cfg->i_max_A;
    c->u_lim_per_vdc = MATHX_INV_SQRT3_F * (((cfg->u_margin > 0.0f) && (cfg->u_margin <= 1.0f))
                                                ? cfg->u_margin : CTRL_U_MARGIN_DEFAULT);
    oplim_init(&c->lim, cfg->Ts_s, OPLIM_FW_RATE_DEFAULT_WB_S, OPLIM_FW_HYST_DEFAULT);
    c->status = (ctrl_status_t)(status | init_est(c, cfg));
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
    est_reset(&c->est);
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
    c->mon.i_aim_alpha_A = 0.0f;
    c->mon.i_aim_beta_A = 0.0f;
    c->mon.ud_V = 0.0f;
    c->mon.uq_V = 0.0f;
    c->mon.te_ref_Nm = 0.0f;
    c->mon.te_est_Nm = 0.0f;
    c->mon.psi_ref_Wb = 0.0f;
    c->mon.psi_est_Wb = 0.0f;
    c->mon.model_from_observer = 0u;
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
    return est_rsid_begin(&c->est);
}

void ctrl_rsid_window(ctrl_t *c, rs_ident_window_t win)
{
    est_rsid_window(&c->est, win);
}

rs_ident_result_t ctrl_rsid_finish(ctrl_t *c)
{
    return est_rsid_finish(&c->est);
}

bool ctrl_rsid_stage_begin(ctrl_t *c, rs_ident_solver_t *s, rs_ident_head_t *win2_copy)
{
    return est_rsid_stage_begin(&c->est, s, win2_copy);
}

bool ctrl_rsid_stage_step(ctrl_t *c, rs_ident_solver_t *s)
{
    return est_rsid_stage_step(&c->est, s);
}

rs_ident_result_t ctrl_rsid_finish_with(ctrl_t *c, rs_ident_result_t r_solved)
{
    return est_rsid_finish_with(&c->est, r_solved);
}

bool ctrl_est_start(ctrl_t *c, float R_Ohm)
{
    if ((c->status & CTRL_CFG_NEEDED_PROPOSED) != 0u) {
        return false;
    }
    return est_start_trusted(&c->est, R_Ohm);
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
 * The model stage: the parameters in use (c->db.par) and the state at
 * k+1 that compensates the one-period delay; the one place the methods
 * differ. The proposed method takes the estimation's model as its src
 * says (est.h): the state from the observer's i^(k+1) (eq. 11, 12), or
 * eq. (10) with held estimates; the told model otherwise, as the
 * conventional method. 2 divisions in dbdtc_set_params, only when the
 * model moved by more than CTRL_MODEL_UPDATE_REL or was re-based.
 */
static dbdtc_state_t ctrl_model(ctrl_t *c, dq_t i_dq_A, float omega_el_rad_s)
{
    const est_out_t *e = est_output(&c->est);
    if ((c->method == CTRL_METHOD_PROPOSED) && (e->src != EST_SRC_TOLD)) {
        const dbdtc_par_t *p = &c->db.par;
        if ((c->model_src != MODEL_EST) || ((e->moved & EST_MOVED_ALL) != 0u) ||
            (((e->moved & EST_MOVED_LPSI) != 0u) &&
             ((mathx_fabsf(e->L_H - p->L_H) > CTRL_MODEL_UPDATE_REL * p->L_H) ||
              (mathx_fabsf(e->psi_f_Wb - p->psi_f_Wb) > CTRL_MODEL_UPDATE_REL * p->psi_f_Wb)))) {
            dbdtc_set_params(&c->db, e->R_Ohm, e->L_H, e->psi_f_Wb);
            c->model_src = MODEL_EST;
            c->mon.model_from_observer = 1u; /* the monitor's, written when it changes */
        }
        if (e->src == EST_SRC_OBSERVER) {
            return dbdtc_state_from_currents(&c->db, est_i_hat_A(&c->est)); /* replaces eq. (10) */
        }
        return dbdtc_predict(&c->db, i_dq_A, c->u_applied_V, omega_el_rad_s);
    }
    if (c->model_src != MODEL_NOMINAL) {
        dbdtc_reset(&c->db); /* back to the told model: 2 divisions once */
        c->model_src = MODEL_NOMINAL;
        c->mon.model_from_observer = 0u;
    }
    return dbdtc_predict(&c->db, i_dq_A, c->u_applied_V, omega_el_rad_s); /* eq. (10)-(12) */
}

/* Mean rotor-frame voltage error [V] the dead time and the device drop add
 * over the period whose middle is at the angle (sin_a, cos_a): each leg
 * loses or gains vdc*td/Ts + drop against the sign of its current (diode
 * conduction in the dead band, the conducting device's drop), the currents
 * taken as i_dq at that angle. Hard sign: near a zero
 * crossing the real error is smaller (left in f^ for those periods). */
static dq_t deadtime_error(const ctrl_t *c, dq_t i_dq_A, float sin_a, float cos_a, float vdc_V)
{
    const abc_t i = clarke_inv(park_inv(i_dq_A, sin_a, cos_a));
    /* below the speed floor the conventional path: the told dead time and drop only */
    const float dv_sum = c->deadtime_frac * vdc_V + c->device_drop_V + est_output(&c->est)->inv_dv_V;
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
            pi_reset(&c->speed_pi, c->mon.te_est_Nm); /* start from the torque there is */
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
    p->omega = c->enc.omega_e_rad_s;
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
    e->sin_el = p->s;
    e->cos_el = p->co;
    e->u_V = c->u_applied_V;
    e->vdc_V = vdc_V;
    e->te_ref_Nm = c->mon.te_ref_Nm;
    e->voltage_limited = (c->flags_last & CTRL_FLAG_VOLTAGE_LIMIT) != 0u;
    e->dpsi_weak_Wb = c->lim.dpsi_Wb;
    est_step(&c->est, e);
}

/* Stage references: Te* from the speed PI (speed mode) or the reference (torque mode). */
static void stage_references(ctrl_t *c, ctrl_period_t *p)
{
    p->te_ref = 0.0f;
    if (c->mode == CTRL_MODE_SPEED) {
        p->te_ref = pi_step(&c->speed_pi, c->ref.speed_ref_rad_s - c->enc.omega_m_rad_s);
    } else if (c->mode == CTRL_MODE_TORQUE) {
        p->te_ref = mathx_clampf(c->ref.te_ref_Nm, -c->cfg.te_max_Nm, c->cfg.te_max_Nm);
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
        p->flags = map_dbdtc_flags(dbdtc_solve(&c->db, &p->x, p->te_ref, p->psi_ref, p->omega, &p->u));
        oplim_fw_update(&c->lim, p->u, c->u_lim_per_vdc * vdc_V);
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
    dq_t u_cmd;

    rotate_sincos(p->s, p->co, spmsm_angle_advance_rad(p->omega, c->cfg.Ts_s), &sa, &ca);
    p->flags |= map_dbdtc_flags(dbdtc_limit(&p->u, sa, ca, vdc_V));
    const dq_t u_dt = deadtime_error(c, p->i_dq, sa, ca, vdc_V);
    u_cmd.d = p->u.d - u_dt.d; /* fed forward: the inverter adds u_dt back */
    u_cmd.q = p->u.q - u_dt.q;
    if ((svpwm_duty(park_inv(u_cmd, sa, ca), vdc_V, &p->duty, &u_real) & SVPWM_SATURATED) != 0u) {
        p->flags |= CTRL_FLAG_VOLTAGE_LIMIT;
    }
    c->u_applied_V = park(u_real, sa, ca);
    c->u_applied_V.d += u_dt.d;
    c->u_applied_V.q += u_dt.q;
    if (c->mode == CTRL_MODE_SPEED) {
        pi_apply(&c->speed_pi, dbdtc_torque_after(&c->db, &p->x, c->u_applied_V.q, p->omega));
    }
}

/* The current the step aimed at, with the model in use (oplim.h: psi_q* = Te* psiq_per_Nm,
 * psi_d* = sqrt(psi_s*^2 - psi_q*^2), i* = (psi_d* - psi_f, psi_q*) / L), in the stator frame at
 * the step's angle; 0 in open loop (no targets). Protection's OPEN_PHASE judges a phase by it. */
static ab_t aimed_current(const ctrl_t *c, const ctrl_period_t *p)
{
    const dbdtc_par_t *m = &c->db.par;
    const float inv_L = m->Ts_over_L * c->db.inv_Ts_1_s;
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
    c->flags_last = p->flags; /* before any NONFINITE: the estimation's voltage check */
    output_duties(c, p->duty, mathx_isfinitef(chk), (uint16_t)(p->flags | e->flags), out);
}

/* The ISR's order: each stage one call. */
void ctrl_step(ctrl_t *c, const ctrl_in_t *in, ctrl_out_t *out)
{
    ctrl_period_t p;

    stage_mode(c);                             /* the mode asked for */
    stage_sample(c, in, &p);                   /* angle, speed, i(k) */
    stage_estimate(c, &p, in->vdc_V);          /* observer, steps 1 and 2 (est.h) */
    p.x = ctrl_model(c, p.i_dq, p.omega);      /* the model in use and the state at k+1 */
    stage_references(c, &p);                   /* Te*: speed PI or torque reference */
    stage_limits(c, &p);                       /* current limit, MTPA, flux weakening: Te*, psi_s* */
    stage_deadbeat(c, &p, in->vdc_V);          /* eq. (17): u(k+1) */
    stage_modulate(c, &p, in->vdc_V);          /* hexagon, dead time, SVPWM, u realised */
    stage_monitor(c, &p);                      /* monitor */
    stage_output(c, &p, in, out);              /* finiteness, duties, flags */
}
