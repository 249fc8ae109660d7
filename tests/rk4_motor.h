/*
 * rk4_motor.h - the surface PMSM's continuous rotor-frame model
 * integrated over one PWM period by classical Runge-Kutta (fine steps,
 * double): the independent reference the exact discrete model
 * (control/zoh.h, dbdtc, smo) is checked against.
 *
 *   L di/dt = u(t) - R i - w L J' i - [0, w psi_f] - v
 *   d: L did/dt = ud - R id + w L iq - vd
 *   q: L diq/dt = uq - R iq - w L id - w psi_f - vq
 *   u(t) = Rot(-w (t - Ts/2)) u_m: the inverter's voltage, constant in the
 *   stator frame over [0, Ts], given as its rotor-frame value at Ts/2;
 *   v a voltage constant in the rotor frame (a disturbance).
 */
#ifndef RK4_MOTOR_H
#define RK4_MOTOR_H

#include <math.h>

/* Sub-steps per period: the RK4 error (h/tau)^4 is below 1e-12 of the
 * state for tau = L/R >= Ts and w Ts <= 1.6. */
#define RK4_MOTOR_STEPS 2000

typedef struct {
    double R, L, psi_f; /* [Ohm, H, Wb] */
    double w;           /* electrical speed [rad/s] */
    double Ts;          /* period [s] */
    double um_d, um_q;  /* the inverter's voltage, rotor frame at the period's middle [V] */
    double v_d, v_q;    /* a rotor-frame constant voltage [V] */
} rk4_motor_t;

static inline void rk4_motor_deriv(const rk4_motor_t *m, double t, double id, double iq, double *did, double *diq)
{
    const double a = -m->w * (t - 0.5 * m->Ts); /* the stator-frame vector seen from the rotor */
    const double ud = cos(a) * m->um_d - sin(a) * m->um_q;
    const double uq = sin(a) * m->um_d + cos(a) * m->um_q;
    *did = (ud - m->R * id + m->w * m->L * iq - m->v_d) / m->L;
    *diq = (uq - m->R * iq - m->w * m->L * id - m->w * m->psi_f - m->v_q) / m->L;
}

/* One period from (id, iq) [A], in place. */
static inline void rk4_motor_period(const rk4_motor_t *m, double *id, double *iq)
{
    const double h = m->Ts / RK4_MOTOR_STEPS;
    double x = *id;
    double y = *iq;
    for (int k = 0; k < RK4_MOTOR_STEPS; k++) {
        const double t = k * h;
        double k1x, k1y, k2x, k2y, k3x, k3y, k4x, k4y;
        rk4_motor_deriv(m, t, x, y, &k1x, &k1y);
        rk4_motor_deriv(m, t + 0.5 * h, x + 0.5 * h * k1x, y + 0.5 * h * k1y, &k2x, &k2y);
        rk4_motor_deriv(m, t + 0.5 * h, x + 0.5 * h * k2x, y + 0.5 * h * k2y, &k3x, &k3y);
        rk4_motor_deriv(m, t + h, x + h * k3x, y + h * k3y, &k4x, &k4y);
        x += h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
        y += h / 6.0 * (k1y + 2.0 * k2y + 2.0 * k3y + k4y);
    }
    *id = x;
    *iq = y;
}

#endif /* RK4_MOTOR_H */
