/*
 * zoh.h - the surface PMSM's rotor-frame model over one PWM period,
 * exact under zero-order hold (design: discrete_model_design.md).
 *
 * In complex rotor-frame notation (x = x_d + j x_q), with a = R/L,
 * w = omega_el constant over the period, alpha = a Ts, theta = w Ts:
 *
 *   L di/dt = u - (R + j w L) i - j w psi_f - f
 *   i(k+1) = Phi i(k) + g_u u_m + g_c v,         Phi = rho e^(-j theta), rho = e^(-alpha)
 *   g_u = ((1 - rho)/R) e^(-j theta/2)            the inverter's voltage, constant in the
 *                                                 stator frame, u_m its rotor-frame value at
 *                                                 the period's middle angle
 *   g_c = (1 - Phi)/Z,  Z = R + j w L             a voltage constant in the rotor frame
 *                                                 (back-EMF -j w psi_f, disturbance f)
 *
 * and in flux (psi = L i + psi_f):
 *
 *   psi(k+1) = Phi psi(k) + psi_f R g_c + L g_u u_m
 *
 * Per period the rotor's turn (zoh_turn_t: cos, sin of theta and theta/2,
 * short series) is shared by every model, and taken anew only when the
 * speed moved it by more than ZOH_THETA_TOL_RAD; per model (R, L at Ts)
 * the decay (zoh_model_t) is computed when R or L change. The two mixed
 * (zoh_step: Phi, g_u, g_c) cost one division when either changed.
 *
 * Calling context: zoh_turn, zoh_step ISR (inline); zoh_model ISR when a
 * model changes, or background.
 */
#ifndef ZOH_H
#define ZOH_H

#include <stdbool.h>
#include <stdint.h>

#include "clarke_park.h"

/* |theta| per period beyond which the model is taken at this turn [rad]:
 * 6.3 periods per electrical turn (a one-period deadbeat step means little
 * beyond; the campaigns' fastest motor turns 0.5 rad at its top speed);
 * the half-angle series below are exact to float up to it (|theta/2| <=
 * 0.5: error < 0.5^9/9! = 5.4e-9). */
#define ZOH_THETA_MAX_RAD 1.0f

/* A turn is taken anew when the speed moved it by more than this since it
 * was taken [rad]: a turn 5e-6 rad stale moves a one-period prediction by
 * 5e-6 |i|, 0.05 mA at 10 A, a 150th of the board's ADC step. The speed
 * estimate moves by ~0.02 rad/s el a period at steady speed (2e-6 rad at
 * 10 kHz), by 0.08 rad/s el on a 2500 r/min/s ramp: the turn, and what
 * each model computes from it (zoh_step, dbdtc_period), is kept over
 * most periods (discrete_model_design.md sec. 2). The observer's back-EMF
 * -j w psi^ takes w(k) itself: a w 0.05 rad/s el stale moves w psi by
 * 12 mV on the paper motor, what step 1's R^ at 0.25 % must not carry. */
#define ZOH_THETA_TOL_RAD 5e-6f

/* The rotor's turn over a period: theta = w Ts. */
typedef struct {
    float c1, s1; /* cos, sin of theta */
    float ch, sh; /* cos, sin of theta / 2 */
    float w_rad_s; /* the speed it was taken at [rad/s el] */
    uint32_t seq;  /* which turn: every zoh_turn() a new number (what was taken from a turn keeps it) */
} zoh_turn_t;

/* The number of the last turn taken (zoh.c). */
extern uint32_t zoh_turn_seq;

/* One model's decay over a period: R, L at Ts. */
typedef struct {
    float R_Ohm;        /* [Ohm] */
    float L_H;          /* [H] */
    float tau_s;        /* L/R [s] */
    float rho;          /* e^(-Ts R/L) [-] */
    float one_m_rho;    /* 1 - rho, without cancellation [-] */
    float gamma_A_V;    /* (1 - rho)/R: the current a volt makes over a period [A/V] */
    float kappa_1_s;    /* 1/(L gamma): the volts a flux change over a period takes, per Wb [1/s] */
} zoh_model_t;

/* Phi, g_u, g_c of one model in one period (complex as dq_t: d = real part). */
typedef struct {
    dq_t Phi;           /* rho e^(-j theta) [-] */
    dq_t g_u;           /* gamma e^(-j theta/2) [A/V] */
    dq_t g_c;           /* (1 - Phi)/Z [A/V] */
} zoh_step_t;

/* The turn for theta_rad = w Ts [rad] (limited to +-ZOH_THETA_MAX_RAD),
 * at w_rad_s. Series of theta/2 to its 7th (sin) and 8th (cos) power. ISR. */
static inline void zoh_turn(float theta_rad, float w_rad_s, zoh_turn_t *t)
{
    const float th = (theta_rad > ZOH_THETA_MAX_RAD) ? ZOH_THETA_MAX_RAD
                                                     : ((theta_rad < -ZOH_THETA_MAX_RAD) ? -ZOH_THETA_MAX_RAD : theta_rad);
    const float h = 0.5f * th;
    const float h2 = h * h;
    /* sin h = h (1 - h^2/6 (1 - h^2/20 (1 - h^2/42))), cos h = 1 - h^2/2 (1 - h^2/12 (1 - h^2/30 (1 - h^2/56))) */
    t->sh = h * (1.0f - h2 * (1.0f / 6.0f) * (1.0f - h2 * (1.0f / 20.0f) * (1.0f - h2 * (1.0f / 42.0f))));
    t->ch = 1.0f - h2 * 0.5f * (1.0f - h2 * (1.0f / 12.0f) * (1.0f - h2 * (1.0f / 30.0f) * (1.0f - h2 * (1.0f / 56.0f))));
    t->s1 = 2.0f * t->sh * t->ch;
    t->c1 = 1.0f - 2.0f * t->sh * t->sh;
    t->w_rad_s = w_rad_s;
    zoh_turn_seq++;
    t->seq = zoh_turn_seq;
}

/* The decay of the model R_Ohm, L_H [Ohm, H] (both > 0) over Ts_s [s];
 * false (m unchanged) when they are not finite and positive. Series of
 * (1 - e^-x)/x with range reduction: 1 division (2 past the series' range). */
bool zoh_model(float R_Ohm, float L_H, float Ts_s, zoh_model_t *m);

/* As zoh_model for values the caller keeps valid (R_Ohm, L_H, Ts_s and
 * their sum finite and positive: an observer within the ranges its init
 * checked), without the check. ISR. */
void zoh_model_of(float R_Ohm, float L_H, float Ts_s, zoh_model_t *m);

/* Phi, g_u, g_c of the model *m in the turn *t: 1 division. ISR. */
static inline void zoh_step(const zoh_model_t *m, const zoh_turn_t *t, zoh_step_t *s)
{
    const float rs1 = m->rho * t->s1;
    /* 1 - rho cos theta = (1 - rho) + 2 rho sin^2(theta/2): no cancellation */
    const float re1 = m->one_m_rho + 2.0f * m->rho * t->sh * t->sh;
    const float wt = t->w_rad_s * m->tau_s; /* w L/R */
    /* 1/Z = (1 - j w tau) / (R (1 + (w tau)^2)) */
    const float k = 1.0f / (m->R_Ohm * (1.0f + wt * wt));
    s->Phi.d = m->rho * t->c1;
    s->Phi.q = -rs1;
    s->g_u.d = m->gamma_A_V * t->ch;
    s->g_u.q = -m->gamma_A_V * t->sh;
    /* (1 - Phi)(1 - j w tau) k, 1 - Phi = re1 + j rho sin theta */
    s->g_c.d = (re1 + rs1 * wt) * k;
    s->g_c.q = (rs1 - re1 * wt) * k;
}

/* Complex product a b of two dq_t (d: real part). ISR. */
static inline dq_t zoh_mul(dq_t a, dq_t b)
{
    dq_t r;
    r.d = a.d * b.d - a.q * b.q;
    r.q = a.d * b.q + a.q * b.d;
    return r;
}

#endif /* ZOH_H */
