/*
 * ident.h - identification of the motor and the inverter on a free shaft:
 * the motor math of the commissioning (firmware/commission/commission.c
 * keeps the sequence, its timing and its faults; derivations and error
 * budget in firmware/commission/commission_design.md). Float-only, no
 * globals, SI units.
 *
 *   ident_ls_*   least-squares sums of y on up to two regressors and a
 *                constant; each solve runs once, when its data is in;
 *   ident_win_*  a window's means of a voltage and a current;
 *   ident_dc_*   the stationary-frame DC-current regulator (R, the beta
 *                axis under L's steps): a PI per axis (pi.h) whose
 *                proportional gain is a virtual resistance, alpha's
 *                integral gain raised once a first R is known;
 *   ident_cur_*  the current PI in a rotating frame (pi.h): Kp = w L^,
 *                Ki = w R^ (the inverter error, the encoder, the spin);
 *   ident_l_*    L from open-loop voltage steps: the integrated voltage
 *                balance against the current by least squares;
 *   ident_spin_* psi_f, J and B from an acceleration and a braking at
 *                constant |i_q|;
 *   solves       R from two DC points; the inverter's per-leg error from
 *                both polarities and its split into dead time and device
 *                drop; the encoder offset from a swept vector.
 *
 * The torque constant and the timing of a computed voltage are spmsm.h's,
 * shared with the controller. Calling context: per-period functions ISR;
 * the solves ISR once (a few divisions) or background. Only COMMISSION
 * calls them: from flash (FLASHFUNC; firmware/f28335/target.mk
 * RAMFUNC_ALL_EXCEPT), the rest of control/ runs from RAM.
 */
#ifndef IDENT_H
#define IDENT_H

#include <stdbool.h>
#include <stdint.h>

#include "clarke_park.h"
#include "pi.h"

/* ---- least squares ------------------------------------------------------ */

typedef struct {
    float n, s1, s2, sy, s11, s12, s22, s1y, s2y;
} ident_ls_t;

/* Empty sums. Field by field: a struct copy may become a memset, a library
 * call that would run from flash in the ISR (make check's ISR-path gate). */
void ident_ls_reset(ident_ls_t *s);

/* One sample of y against x1, x2. */
static inline void ident_ls_add(ident_ls_t *s, float x1, float x2, float y)
{
    s->n += 1.0f;
    s->s1 += x1;
    s->s2 += x2;
    s->sy += y;
    s->s11 += x1 * x1;
    s->s12 += x1 * x2;
    s->s22 += x2 * x2;
    s->s1y += x1 * y;
    s->s2y += x2 * y;
}

/* b of y = b x1 + c; 0 when it cannot be solved (fewer than
 * IDENT_LS_N_MIN samples, x1 constant): every use needs one of a sign. */
float ident_ls_slope(const ident_ls_t *s);

/* b1 of y = b1 x1 + b2 x2 + c; 0 when it cannot be solved. */
float ident_ls_coef1(const ident_ls_t *s);

/* Fewest samples a fit accepts [-] */
#define IDENT_LS_N_MIN 20.0f

/* ---- windows: the means of a voltage and a current ---------------------- */

typedef struct {
    float U_V, I_A;                 /* the window's means [V, A] */
} ident_point_t;

typedef struct {
    float sum_u, sum_i, n;
} ident_win_t;

void ident_win_reset(ident_win_t *w);

static inline void ident_win_add(ident_win_t *w, float u_V, float i_A)
{
    w->sum_u += u_V;
    w->sum_i += i_A;
    w->n += 1.0f;
}

/* The means (the window holds at least one period), the window emptied. */
ident_point_t ident_win_take(ident_win_t *w);

/* ---- the stationary-frame DC-current regulator -------------------------- */

typedef struct {
    float Ts_s;                     /* period [s] */
    float kp_V_A;                   /* virtual resistance, both axes [V/A] */
    float ki_V_As;                  /* integral gain, both axes until ident_dc_set_ki_a [V/(A s)] */
    float u_max_V;                  /* each axis within +-this: the inscribed circle vdc/sqrt 3 [V] */
} ident_dc_cfg_t;

typedef struct {
    pi_t a, b;                      /* alpha, beta */
    ident_dc_cfg_t cfg;
} ident_dc_t;

/* Copies cfg, states 0. False when pi_init refuses the gains (Ts Ki > Kp). */
bool ident_dc_init(ident_dc_t *r, const ident_dc_cfg_t *cfg);

/* Alpha's integral gain from now on [V/(A s)], its state kept (bumpless).
 * False (gain unchanged) when pi_init refuses it. */
bool ident_dc_set_ki_a(ident_dc_t *r, float ki_V_As);

/* One period: the voltage for the currents i_A towards i_ref_A [A]; each axis within +-u_max_V. */
ab_t ident_dc_step(ident_dc_t *r, ab_t i_ref_A, ab_t i_A);

/* One period of beta alone (alpha open loop): its voltage for i_b_A towards 0 [V]. */
float ident_dc_step_b(ident_dc_t *r, float i_b_A);

/* ---- the current PI in a rotating frame ---------------------------------- */

typedef struct {
    pi_t d, q;
} ident_cur_t;

/* Kp = bw_rad_s L_H, Ki = bw_rad_s R_Ohm (the PI's zero on the winding's
 * pole: a first-order loop of bandwidth bw), each axis within +-u_max_V;
 * the integral states u0_V (bumpless from what was applied). False when
 * pi_init refuses (L/R below a period). */
bool ident_cur_init(ident_cur_t *c, float Ts_s, float bw_rad_s, float R_Ohm, float L_H, float u_max_V,
                    dq_t u0_V);

/* One period: the voltage for the frame's current i_A towards i_ref_A [V]. */
static inline dq_t ident_cur_step(ident_cur_t *c, dq_t i_ref_A, dq_t i_A)
{
    dq_t u;
    u.d = pi_step(&c->d, i_ref_A.d - i_A.d);
    u.q = pi_step(&c->q, i_ref_A.q - i_A.q);
    return u;
}

/* ---- R and the inverter's voltage error ---------------------------------- */

/* R [Ohm] from two DC points of one polarity on alpha: U = R I + E, E the
 * inverter's constant error, cancels; 0 when the currents coincide. */
float ident_r_of_points(ident_point_t p1, ident_point_t p2);

typedef struct {
    float dv_V;                     /* per-leg error against the current, a current beyond the ripple [V] */
    float asym_V;                   /* the polarities' mean on alpha [V]: an asymmetric drop, a sensor offset */
    float spread_V;                 /* the four points' largest distance from dv, per leg [V] */
} ident_inv_t;

/* From R and four DC points on alpha, two currents of each polarity (the
 * rotor's d axis on the current): each leg's error -dv sign(i) puts
 * -(4/3) dv sign(I) on alpha (phase a carries I, b and c -I/2), which the
 * commanded voltage U = R I + (4/3) dv sign(I) + asym makes up for. */
void ident_inv_solve(float R_Ohm, const ident_point_t pos[2], const ident_point_t neg[2], ident_inv_t *out);

/* At one bus vdc_V [V] a dead time td (error vdc td/Ts) and a drop look
 * alike: the board's told dead time td_told_s [s] is kept and the rest of
 * dv_V [V] booked as the drop; a dv below the told dead time's error is
 * all dead time (no negative drop). Ts_s the PWM period [s]. */
void ident_inv_split(float dv_V, float vdc_V, float Ts_s, float td_told_s, float *td_s, float *drop_V);

/* ---- L: open-loop steps -------------------------------------------------- */

typedef struct {
    float Ts_s;
    ident_point_t op;               /* the operating point the steps are taken around [V, A] */
    float y_Vs;                     /* integral of (du - R^ di) [V s] */
    float di_prev_A;
    uint32_t k;                     /* periods since the start */
    ident_ls_t ls;                  /* y = L di + b t + c */
} ident_l_t;

/* Steps around op (the steady DC point the stage starts from). */
void ident_l_start(ident_l_t *l, float Ts_s, ident_point_t op);

/* One period: the current i_A [A] sampled now, and the voltage u_V [V]
 * that acted over the period just ended (computed SPMSM_VOLTAGE_SEEN_PERIODS
 * calls ago); R^ R_Ohm. The trapezoid rule on R^ di. */
void ident_l_step(ident_l_t *l, float i_A, float u_V, float R_Ohm);

/* L [H] (0: not solvable). */
float ident_l_solve(const ident_l_t *l);

/* ---- the encoder's offset from a swept vector ----------------------------- */

/* From the sums of the count (unwrapped, since count0) against the
 * vector's angle - pi [rad el] over whole electrical turns: the offset in
 * encoder.h's convention theta = offset + p 2 pi (count + 1/2) / cpr, in
 * [0, 2 pi) [rad el]; *counts_per_rad the slope (<= 0: not the vector's). */
float ident_enc_offset(const ident_ls_t *ls, uint32_t count0, uint16_t pole_pairs, uint32_t cpr,
                       float *counts_per_rad);

/* ---- the spin: psi_f, J, B ----------------------------------------------- */

typedef struct {
    ident_ls_t psi;                 /* u_q - R^ i_q against w_el and the current's sign */
    ident_ls_t acc, dec;            /* speed against time, accelerating and braking */
    float iq_acc_A, w_acc_rad_s;    /* sums of i_q and speed of the acceleration's fit */
    float iq_dec_A, w_dec_rad_s;    /* ... and of the braking's */
    float w0_rad_s;                 /* the flux fit's centre: its first sample's speed, mechanical [rad/s] */
    float y0_V;                     /* ... and its u_q - R^ i_q [V] */
    bool centred;
} ident_spin_t;

typedef struct {
    float psi_f_Wb, J_kgm2, B_Nms;
    float acc_rad_s2, dec_rad_s2;   /* the fits' accelerations [rad/s^2] */
} ident_spin_out_t;

void ident_spin_reset(ident_spin_t *s);

/* One period of the flux fit: mechanical speed w_rad_s [rad/s], pole
 * pairs, the rotor-frame current i_dq_A [A] and the voltage u_q_V [V] in
 * the frame of the period it acts in, R^ R_Ohm, negative: the current
 * commanded is -I (else +I). */
void ident_spin_add_flux(ident_spin_t *s, float w_rad_s, uint16_t pole_pairs, dq_t i_dq_A, float u_q_V,
                         float R_Ohm, bool negative);

/* One period of the motion fits: time t_s [s], speed w_rad_s [rad/s],
 * i_q [A]; braking: the current -I (else +I). */
void ident_spin_add_motion(ident_spin_t *s, float t_s, float w_rad_s, float i_q_A, bool braking);

/* psi_f from one slope over every sweep (the inverter's error and an R^
 * error are odd in i_q: in the sign's coefficient; swept over the same
 * speeds both ways, an error that changes with |w| leaves the slope), J
 * and B from the two accelerations at the mean torques 1.5 p psi_f
 * mean(i_q). False when psi_f <= 0, the accelerations are not of opposite
 * signs (or too few samples), or J is not positive; a negative B (the
 * fits' noise) reads 0. */
bool ident_spin_solve(const ident_spin_t *s, uint16_t pole_pairs, ident_spin_out_t *out);

#endif /* IDENT_H */
