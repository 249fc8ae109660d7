/*
 * obs_plant.h - test-side SPMSM current plant in double for the observer
 * tests (smo, param_est, rs_ident): rotor-frame model at constant speed
 * over a period, discretised exactly (matrix exponential), with the TRUE
 * parameters R0, L0, psi0, which the tests choose different from the
 * observer's. The voltage is the inverter's: constant in the stator frame
 * over the period, given as its rotor-frame value at the period's middle
 * angle (the controller's u(k)).
 *
 *   L0 di/dt = u(t) - R0 i + w L0 J i - [0, w psi0],  J = [[0, 1], [-1, 0]]
 *   u(t) = Rot(-w (t - Ts/2)) u_m
 *   di/dt = A i + b(t),  A = -alpha I + w J,  alpha = R0/L0
 *   i(k+1) = e^{A Ts} i(k) + int_0^Ts e^{A (Ts - t)} b(t) dt
 * in complex form (x = x_d + j x_q: J is -j), written out independently
 * of control/zoh.h (double, cexp).
 */
#ifndef OBS_PLANT_H
#define OBS_PLANT_H

#include <complex.h>
#include <math.h>

#include "smo.h"

/* Table I of the paper; Ts = 1/(10 kHz). */
#define OP_TS   1e-4
#define OP_R0   3.0
#define OP_L0   0.011
#define OP_PSI0 0.24
#define OP_PP   3
#define OP_PI   3.14159265358979323846

/* The disturbance error the tests' observer dominates [V]. */
#define OP_EF_MAX_V 50.0

/* Observer cfg of the tests: the design gains at the observer's nominal
 * (R, L, psi), ranges that hold R^ 4.3x off (step 1) and [0.3, 3] x the
 * true L and psi, L^'s floor raised to 1.25 x the reaching condition's
 * (as est_cfg_defaults does). */
static inline smo_cfg_t op_smo_cfg(double R, double L, double psi)
{
    smo_cfg_t c;
    smo_gains_t g;
    (void)smo_gains_design((float)OP_TS, (float)R, (float)L, (float)OP_EF_MAX_V, &g);
    smo_cfg_defaults(&c, (float)OP_TS, (float)R, (float)L, (float)psi, &g);
    c.R_min_Ohm = 0.5f;
    c.R_max_Ohm = 15.0f;
    const float L_floor = 1.25f * smo_L_floor_H((float)OP_TS, 0.5f, &g);
    c.L_min_H = ((float)(0.3 * OP_L0) > L_floor) ? (float)(0.3 * OP_L0) : L_floor;
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

/* The period's coefficients at R, L, w (complex, independently of zoh.h):
 * i(k+1) = phi i(k) + g_u u_m + g_c v for a stator-frame constant u and a
 * rotor-frame constant v. */
static inline void op_coeffs(double R, double L, double w, double complex *phi, double complex *g_u,
                             double complex *g_c)
{
    const double complex lam = -(R / L) - I * w; /* A as a complex number */
    *phi = cexp(lam * OP_TS);
    /* int_0^Ts e^{lam (Ts - t)} e^{-j w (t - Ts/2)} dt / L */
    *g_u = cexp(lam * OP_TS) * cexp(0.5 * I * w * OP_TS) * (cexp(-(lam + I * w) * OP_TS) - 1.0) /
           (-(lam + I * w)) / L;
    *g_c = (*phi - 1.0) / (lam * L);
}

/* One period of the inverter's u (rotor-frame value at the period's middle) and w. */
static inline void op_step(op_plant_t *p, double ud, double uq, double w)
{
    double complex phi;
    double complex g_u;
    double complex g_c;
    op_coeffs(p->R, p->L, w, &phi, &g_u, &g_c);
    const double complex i1 = phi * (p->id + I * p->iq) + g_u * (ud + I * uq) + g_c * (-I * w * p->psi);
    p->id = creal(i1);
    p->iq = cimag(i1);
}

/* The inverter's voltage that holds (id, iq) in steady state at w:
 * (1 - phi) i = g_u u + g_c (-j w psi0). */
static inline void op_u_for(const op_plant_t *p, double id, double iq, double w, double *ud,
                            double *uq)
{
    double complex phi;
    double complex g_u;
    double complex g_c;
    op_coeffs(p->R, p->L, w, &phi, &g_u, &g_c);
    const double complex u = ((1.0 - phi) * (id + I * iq) + g_c * I * w * p->psi) / g_u;
    *ud = creal(u);
    *uq = cimag(u);
}

/* Corrected steady-state disturbances (corrected_model_design.md sec. 2) the observer with
 * R^, L^, psi^ must find: d = x^ - x0; on the exact model also the
 * inverter voltage's gain ratio g_u/g_c of the model against the
 * plant's (second order in Ts R/L and w Ts; discrete_model_design.md). */
static inline void op_f_ss(const op_plant_t *p, double Rh, double Lh, double psih, double id,
                           double iq, double w, double *fd, double *fq)
{
    double complex phi;
    double complex g_u;
    double complex g_c;
    double ud;
    double uq;
    op_u_for(p, id, iq, w, &ud, &uq);
    op_coeffs(Rh, Lh, w, &phi, &g_u, &g_c);
    /* the model's steady state: (1 - phi^) i = g_u^ u + g_c^ (-j w psi^ - f) */
    const double complex f = (g_u * (ud + I * uq) - (1.0 - phi) * (id + I * iq)) / g_c - I * w * psih;
    *fd = creal(f);
    *fq = cimag(f);
}

/* The same in the continuous model's steady state (corrected_model_design.md sec. 2, the
 * relations step 1's solve is built on): fd = dL w iq - dR id, fq = -dR iq
 * - dL w id - dpsi w. */
static inline void op_f_cont(const op_plant_t *p, double Rh, double Lh, double psih, double id,
                             double iq, double w, double *fd, double *fq)
{
    const double dR = Rh - p->R;
    const double dL = Lh - p->L;
    const double dpsi = psih - p->psi;
    *fd = dL * w * iq - dR * id;
    *fq = -dR * iq - dL * w * id - dpsi * w;
}

#endif /* OBS_PLANT_H */
