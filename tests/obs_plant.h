/*
 * obs_plant.h - test-side SPMSM current plant in double for the observer
 * tests (smo, param_est, rs_ident): rotor-frame model at constant speed
 * over a period, discretised exactly (matrix exponential), with the TRUE
 * parameters R0, L0, psi0, which the tests choose different from the
 * observer's.
 *
 *   L0 di/dt = u - R0 i + w L0 J i - [0, w psi0],  J = [[0, 1], [-1, 0]]
 *   di/dt = A i + b,  A = -alpha I + w J,  alpha = R0/L0
 *   i(k+1) = i_ss + e^{A Ts} (i(k) - i_ss),  i_ss = -A^-1 b
 */
#ifndef OBS_PLANT_H
#define OBS_PLANT_H

#include <math.h>

#include "smo.h"

/* Table I of the paper; Ts = 1/(10 kHz). */
#define OP_TS   1e-4
#define OP_R0   3.0
#define OP_L0   0.011
#define OP_PSI0 0.24
#define OP_PP   3
#define OP_PI   3.14159265358979323846

/* Observer cfg of the tests: the design gains at the observer's nominal
 * (R, L, psi), ranges that hold R^ 4.3x off (step 1) and [0.3, 3] x the
 * true L and psi, with the stability bound and (36) still met. */
static inline smo_cfg_t op_smo_cfg(double R, double L, double psi)
{
    smo_cfg_t c;
    smo_cfg_defaults(&c, (float)OP_TS, (float)R, (float)L, (float)psi);
    c.R_min_Ohm = 0.5f;
    c.R_max_Ohm = 15.0f;
    c.L_min_H = (float)(0.3 * OP_L0);
    c.L_max_H = (float)(3.0 * OP_L0);
    c.psi_min_Wb = (float)(0.3 * OP_PSI0);
    c.psi_max_Wb = (float)(3.0 * OP_PSI0);
    c.f_max_V = 400.0f;
    c.i_max_A = 60.0f;
    c.u_max_V = 600.0f;
    c.omega_max_rad_s = 3000.0f;
    return c;
}

typedef struct {
    double R, L, psi; /* true parameters */
    double id, iq;    /* state [A] */
} op_plant_t;

static inline double op_w_el(double rpm)
{
    return rpm * 2.0 * OP_PI / 60.0 * OP_PP;
}

/* Torque [N m] to iq [A] at id = 0 with the true psi0 (eq. 3). */
static inline double op_iq_of_te(double te)
{
    return te / (1.5 * OP_PP * OP_PSI0);
}

/* One period of constant u (rotor frame) and w. */
static inline void op_step(op_plant_t *p, double ud, double uq, double w)
{
    const double al = p->R / p->L;
    const double bd = ud / p->L;
    const double bq = (uq - w * p->psi) / p->L;
    const double det = al * al + w * w;
    /* -A^-1 = [[al, w], [-w, al]] / det */
    const double sd = (al * bd + w * bq) / det;
    const double sq = (-w * bd + al * bq) / det;
    const double dd = p->id - sd;
    const double dq = p->iq - sq;
    const double e = exp(-al * OP_TS);
    const double c = cos(w * OP_TS);
    const double s = sin(w * OP_TS);
    p->id = sd + e * (c * dd + s * dq);
    p->iq = sq + e * (-s * dd + c * dq);
}

/* Constant voltage that holds (id, iq) in steady state at w. */
static inline void op_u_for(const op_plant_t *p, double id, double iq, double w, double *ud,
                            double *uq)
{
    *ud = p->R * id - w * p->L * iq;
    *uq = p->R * iq + w * p->L * id + w * p->psi;
}

/* Corrected steady-state disturbances (corrected_model_design.md sec. 2) the observer with
 * R^, L^, psi^ must find: d = x^ - x0. */
static inline void op_f_ss(const op_plant_t *p, double Rh, double Lh, double psih, double id,
                           double iq, double w, double *fd, double *fq)
{
    const double dR = Rh - p->R;
    const double dL = Lh - p->L;
    const double dpsi = psih - p->psi;
    *fd = dL * w * iq - dR * id;
    *fq = -dR * iq - dL * w * id - dpsi * w;
}

#endif /* OBS_PLANT_H */
