/* drive_params.c - the one parameter set, its derived values and its
 * mapping; see drive_params.h and params_design.md. */
#include "drive_params.h"

#include "board_cfg.h"
#include "mathx.h"
#include "spmsm.h"

#define DRIVE_S_PER_NS 1.0e-9f
#define DRIVE_DEFAULT_BAND (-1.0f) /* R^ band end: est_rsid_band()'s */
#define SQRT3 1.7320508f
/* A per-leg square wave of amplitude dv has the fundamental (4/pi) dv. */
#define FUNDAMENTAL_OF_SQUARE 1.27323954f
/* +- full scale over the ADC's counts: a step is full scale / (counts / 2) */
#define HALF_ADC_COUNTS (0.5f * BOARD_ADC_COUNTS)

#define DRIVE_PARAM_DEFAULT(group, field, type, dflt, to) p->group.field = (type)(dflt);

void drive_params_board(drive_params_t *p)
{
    DRIVE_PARAMS(DRIVE_PARAM_DEFAULT)
    p->derived = 0u;
    DRIVE_CONFIG_PARAMS(p); /* a motor file's (make board), else nothing */
}

float drive_rated_torque_Nm(const drive_params_t *p)
{
    return spmsm_kt_Nm_A(p->motor.pole_pairs, p->motor.psi_f_Wb) * p->rating.i_rated_A;
}

/* *x = v unless the user set it (>= 0; NaN and DRIVE_PARAM_DERIVED are not). */
static void derive(float *x, float v)
{
    if (!(*x >= 0.0f)) {
        *x = v;
    }
}

static float min_f(float a, float b)
{
    return (a < b) ? a : b;
}

float drive_scaled(float ref_value, float q, float q_ref)
{
    return ref_value * (q / q_ref);
}

void drive_speed_pi(float J_kgm2, float speed_bw_rad_s, float *kp_Nms_rad, float *ki_Nm_rad)
{
    /* kp = J w_c, ki = kp w_i, w_i in proportion to w_c (params_design.md sec. 4) */
    const float bw = speed_bw_rad_s / REF_SPEED_BW_RAD_S;
    *kp_Nms_rad = REF_SPEED_KP_NMS_RAD * (J_kgm2 / REF_J_KGM2) * bw;
    *ki_Nm_rad = REF_SPEED_KI_NM_RAD * (J_kgm2 / REF_J_KGM2) * bw * bw;
}

/* The voltage the drive cannot explain [V]: (4/pi) bus (dead-time
 * uncertainty x f_s + device drop per bus). */
static float unexplained_V(float vdc_V, float Ts_s)
{
    return FUNDAMENTAL_OF_SQUARE * vdc_V * (EST_DT_UNC_S / Ts_s + EST_DROP_UNC_PER_VDC);
}

float drive_i_readable_A(const drive_params_t *p)
{
    /* a reading tops out at the range less the offset calibration subtracted,
     * which may be up to the accepted offset (5 % of the range) */
    return p->board.i_full_scale_A - drive_scaled(BOARD_I_OFFSET_MAX_A, p->board.i_full_scale_A, BOARD_I_FULL_SCALE_A);
}

float drive_trip_margin_A(const drive_params_t *p)
{
    /* a sample at the limit reads above it by the ADC's noise: BOARD_TRIP_NOISE_SIGMAS of it */
    return BOARD_TRIP_NOISE_SIGMAS * BOARD_ADC_NOISE_CODES_RMS * p->board.i_full_scale_A / HALF_ADC_COUNTS;
}

drive_derive_t drive_params_derive(drive_params_t *p)
{
    const drive_rating_t *r = &p->rating;
    drive_derive_t st = DRIVE_DERIVE_OK;
    const float kt_Nm_A = spmsm_kt_Nm_A(p->motor.pole_pairs, p->motor.psi_f_Wb);
    const float n_rated_ref_rad_s = MOTOR_RATED_SPEED_RPM * MATHX_RAD_S_PER_RPM_F;

    if (!(r->i_rated_A > 0.0f) || !(r->i_peak_A >= r->i_rated_A) || !(r->t_peak_s > 0.0f) ||
        !(r->n_rated_rad_s > 0.0f) || !(r->n_max_rad_s >= r->n_rated_rad_s)) {
        st |= DRIVE_DERIVE_RATINGS;
    }
    /* sec. 3: limits from the ratings and the ADC's range */
    if (!(p->limits.te_max_Nm >= 0.0f)) {
        p->derived |= DRIVE_DERIVED_TE_MAX;
    }
    derive(&p->limits.te_max_Nm, kt_Nm_A * r->i_peak_A);
    derive(&p->limits.i_limit_A, r->i_peak_A);
    derive(&p->limits.i_trip_A, min_f(drive_scaled(REF_I_TRIP_A, r->i_peak_A, REF_I_PEAK_A), drive_i_readable_A(p)));
    derive(&p->limits.speed_max_rad_s, LIM_OVERSPEED_PER_MAX * r->n_max_rad_s);
    if (p->limits.i_limit_A > r->i_peak_A) {
        st |= DRIVE_DERIVE_I_LIMIT;
    }
    if (!(p->limits.i_limit_A + drive_trip_margin_A(p) <= p->limits.i_trip_A)) {
        st |= DRIVE_DERIVE_ADC_RANGE;
    }
    /* sec. 4: speed PI from J and the crossover */
    const float bw = p->tuning.speed_bw_rad_s / REF_SPEED_BW_RAD_S;
    float kp;
    float ki;
    drive_speed_pi(p->motor.J_kgm2, p->tuning.speed_bw_rad_s, &kp, &ki);
    derive(&p->tuning.speed_kp_Nms_rad, kp);
    derive(&p->tuning.speed_ki_Nm_rad, ki);
    /* sec. 5: step 1 from the ratings and the speed loop's settling (1 / w_i) */
    derive(&p->step1.settle_2_s, REF_RSID_SETTLE_2_S / bw);
    derive(&p->step1.settle_1_s, RSID_SETTLE_1_PER_2 * p->step1.settle_2_s);
    derive(&p->step1.speed_1_rad_s, RSID_SPEED_1_PER_RATED * r->n_rated_rad_s);
    derive(&p->step1.speed_2_rad_s, RSID_SPEED_2_PER_RATED * r->n_rated_rad_s);
    derive(&p->step1.accel_rad_s2,
           min_f(drive_scaled(REF_RSID_ACCEL_RPM_S * MATHX_RAD_S_PER_RPM_F, r->n_rated_rad_s, n_rated_ref_rad_s),
                 RSID_RAMP_TORQUE_PER_RATED * kt_Nm_A * r->i_rated_A / p->motor.J_kgm2));
    /* sec. 7: back-EMF at n_max against the bus's phase-voltage limit */
    if (r->n_max_rad_s * (float)p->motor.pole_pairs * p->motor.psi_f_Wb > p->board.vdc_nominal_V / SQRT3) {
        st |= DRIVE_DERIVE_WARN_BEMF;
    }
    smo_gains_t g;
    if (!drive_params_obs_gains(p, &g)) {
        st |= DRIVE_DERIVE_OBSERVER;
    }
    return st;
}

bool drive_params_obs_gains(const drive_params_t *p, smo_gains_t *g)
{
    est_told_t told = { 0 };
    told.Ts_s = p->board.Ts_s;
    told.R_Ohm = p->motor.R_Ohm;
    told.L_H = p->motor.L_H;
    return est_obs_gains(&told, drive_scaled(REF_OBS_EF_MAX_V, p->board.vdc_nominal_V, REF_VDC_V), g);
}

/* sec. 6: step 2's thresholds, the injections and the speed floor. */
static void estimator_from(const drive_params_t *p, est_cfg_t *c)
{
    const float i_r = p->rating.i_rated_A;
    const float T_r = drive_rated_torque_Nm(p);
    const float vdc = p->board.vdc_nominal_V;
    c->gate.di_max_A = drive_scaled(REF_EST_DI_MAX_A, i_r, REF_I_RATED_A);
    c->gate.dte_max_Nm = drive_scaled(REF_EST_DTE_MAX_NM, T_r, REF_T_RATED_NM);
    c->rtrack.i_ident_A = drive_scaled(REF_RT_I_IDENT_A, i_r, REF_I_RATED_A);
    /* R I against the PWM's voltage noise, which scales with the bus */
    c->rtrack.i_track_A = min_f(drive_scaled(REF_RT_I_TRACK_A, vdc / p->motor.R_Ohm, REF_VDC_V / REF_R_OHM),
                                RT_I_TRACK_MAX_PER_RATED * i_r);
    c->rtrack.iq_min_A = drive_scaled(REF_RT_IQ_MIN_A, i_r, REF_I_RATED_A);
    c->rtrack.iq_step_max_A = drive_scaled(REF_RT_IQ_STEP_A, i_r, REF_I_RATED_A);
    c->rtrack.ve_max_V = drive_scaled(REF_RT_VE_MAX_V, vdc, REF_VDC_V);
    /* w_min psi_f in proportion to the voltage the drive cannot explain */
    const float w_min = drive_scaled(REF_EST_W_MIN_RAD_S, unexplained_V(vdc, p->board.Ts_s),
                               unexplained_V(REF_VDC_V, p->board.Ts_s)) * (REF_PSI_F_WB / p->motor.psi_f_Wb);
    c->pe.w_min_rad_s = w_min;
    c->pe.wiq_min_A_rad_s = drive_scaled(REF_EST_WIQ_MIN_A_RAD_S, w_min * i_r, REF_EST_W_MIN_RAD_S * REF_I_RATED_A);
}

void drive_params_to_ctrl_cfg(const drive_params_t *p, ctrl_cfg_t *c)
{
    smo_gains_t g;
    est_told_t told;
    float R_min_Ohm;
    float R_max_Ohm;

    /* the model's bounds: generous, never the active limit */
    c->i_max_A = MODEL_I_BOUND_PER_TRIP * p->limits.i_trip_A;
    c->omega_max_el_rad_s = MODEL_SPEED_BOUND_RPM * MATHX_RAD_S_PER_RPM_F * (float)p->motor.pole_pairs;
    c->psi_max_Wb = MODEL_PSI_BOUND_PER_PSIF * p->motor.psi_f_Wb;
    /* the oscillation watch judges innovations above what the ADC's noise reads */
    c->osc_i_min_A = drive_trip_margin_A(p);

    /* the proposed method's settings for these values; the R^ band in ohms.
     * Gains refused here make smo_init refuse too (CONFIG at the start). */
    (void)drive_params_obs_gains(p, &g);
    ctrl_cfg_told(c, &told);
    est_rsid_band(&told, &R_min_Ohm, &R_max_Ohm);
    if (p->tuning.R_min_Ohm >= 0.0f) {
        R_min_Ohm = p->tuning.R_min_Ohm;
    }
    if (p->tuning.R_max_Ohm > 0.0f) {
        R_max_Ohm = p->tuning.R_max_Ohm;
    }
    est_cfg_defaults(&c->est_cfg, &told, &g, R_min_Ohm, R_max_Ohm);
    estimator_from(p, &c->est_cfg);
}
