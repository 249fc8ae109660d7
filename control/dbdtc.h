/*
 * dbdtc.h - deadbeat direct torque control of a surface PMSM (Ld = Lq = L),
 * conventional form: one-step delay compensation (eq. 10-12) and the
 * deadbeat voltage (eq. 17), plus the inverter voltage-limit policy. The
 * discrete model of both is the exact zero-order hold over the period
 * (zoh.h; discrete_model_design.md) in place of the paper's Euler forms
 * (4) and (10), which it has as its limit Ts -> 0.
 *
 * Timing (index k = the sample just taken):
 *   u(k)   was computed in the previous step and is being applied now;
 *   dbdtc_period() takes this period's turn of the rotor (after any
 *   dbdtc_set_params() of the period);
 *   dbdtc_predict() gives the state at k+1 from i(k), u(k) (eq. 10-12);
 *   dbdtc_solve() gives u(k+1), applied over [k+1, k+2], that puts
 *   Te(k+2) = Te* and |psi_s(k+2)| = psi_s* in the discrete model.
 *   Voltages are rotor-frame values at the middle angle of the period
 *   they act in (the modulation applies them there).
 *
 * The model parameters (R, L, psi_f) live in one place, dbdtc_t.par, set by
 * dbdtc_set_params(): the observer-based method replaces both the
 * prediction (its own i(k+1)) and the parameters (its estimates) through
 * dbdtc_set_params() and dbdtc_state_from_currents().
 *
 * The deadbeat solution (eq. 17) in a form with no division and one
 * square root per step (2L/(3p psi_f), 1.5 p psi_f and the model's decay
 * precomputed in dbdtc_set_params(), the period's rotation in
 * dbdtc_period(): 1 division): discrete_model_design.md sec. 4.
 *
 * Negative discriminant (psi_q*^2 > psi_s*^2: the torque asks for more
 * q flux than the whole flux target): psi_d(k+2) = 0, i.e. u_d = -X1/Ts,
 * the vertex of the parabola, which gives the |psi_s(k+2)| closest to the
 * target while keeping the torque; DBDTC_FLAG_FLUX_UNREACHABLE is set.
 *
 * Voltage limit (dbdtc_limit): torque first, unless that raises the flux.
 * u_q is kept and u_d is moved to the nearest point of the hexagon chord at
 * that u_q (the flux error is what gives, not the torque); when u_q alone
 * is outside the hexagon, the hexagon vertex with the largest q component
 * in the direction of u_q is taken (the most torque the inverter can
 * make). Torque first because the torque is what the speed loop and the
 * load see. But when either would put u_d above the request, psi_d(k+2) =
 * X1 + Ts u_d rises above its target: at the voltage limit i_d then runs
 * positive and the torque falls (SIL, 2200 r/min, Te* 3 -> 12 N m: i_d
 * +7.8 A, Te 1.4 N m). Then flux first: u_d as requested and the most u_q
 * along the request the hexagon has at that u_d (DB-DTFC at the voltage
 * limit, the paper's refs [4], [5]; limits_design.md sec. 3). A u_d
 * request below -Vdc/sqrt(3) is no flux target the deadbeat step can
 * mean (an open phase asks for such): torque first there.
 */
#ifndef DBDTC_H
#define DBDTC_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "clarke_park.h"
#include "mathx.h"
#include "zoh.h"

/* Parameters handed to dbdtc_set_params() are kept within these factors of
 * the configured ones, so an estimator gone astray cannot divide by ~0. */
#define DBDTC_PARAM_FACTOR_MIN 0.1f
#define DBDTC_PARAM_FACTOR_MAX 10.0f

/* Inside this share of the hexagon's inscribed circle (radius
 * Vdc/sqrt(3), squared here) no side can bind, whatever the angle: the
 * normal period's one test instead of three projections. Below 1 by far
 * more than the projections' rounding and |(sin, cos)| - 1 (1e-6). */
#define DBDTC_INSCRIBED_SAFE_SQ 0.998f

/* Flags returned by dbdtc_solve() and dbdtc_limit(), a bit set. */
#define DBDTC_FLAG_VOLTAGE_LIMIT    0x0001u /* moved onto the inverter hexagon */
#define DBDTC_FLAG_FLUX_UNREACHABLE 0x0002u /* negative discriminant */

typedef struct {
    float Ts_s;            /* control period [s] */
    uint16_t pole_pairs;   /* p */
    float R_Ohm;          /* initial model resistance */
    float L_H;            /* initial model inductance, Ld = Lq */
    float psi_f_Wb;        /* initial model PM flux linkage */
    float i_max_A;         /* bound on |id|, |iq| used by the model */
    float omega_max_rad_s; /* bound on |omega_el| used by the model */
    float u_max_V;         /* bound on |ud|, |uq| in and out */
    float te_max_Nm;       /* bound on |Te*| */
    float psi_max_Wb;      /* bound on psi_s* */
} dbdtc_cfg_t;

typedef struct {           /* model parameters in use and what follows from them */
    float R_Ohm;
    float L_H;
    float psi_f_Wb;
    zoh_model_t zm;        /* the decay over a period (zoh.h) */
    float psiR_Wb_Ohm;     /* psi_f R: the back-EMF's share of the free flux, psi_f R g_c [Wb Ohm] */
    float L_gamma_Wb_V;    /* L gamma = 1/kappa: the flux a volt moves over a period [Wb/V] */
    float inv_L_1_H;       /* 1/L [1/H] */
    float te_per_Wb;       /* 1.5*p*psi_f/L [N m/Wb], eq. (5) */
    float kt_Nm_per_A;     /* 1.5*p*psi_f, eq. (12) */
    float psiq_per_Nm;     /* 2L/(3p psi_f) [Wb/(N m)], eq. (5) inverted */
    float inv_psi_f_1_Wb;  /* 1/psi_f [1/Wb] (oplim's weakened flux) */
} dbdtc_par_t;

typedef struct {           /* predicted state at k+1, eq. (10)-(12) */
    dq_t i_dq_A;
    dq_t psi_dq_Wb;
    float te_Nm;
} dbdtc_state_t;

typedef struct {           /* the model in this period's turn (dbdtc_period) */
    dq_t Phi;              /* rho e^(-j theta): the free flux's decay and turn [-] */
    dq_t D_Wb;             /* psi_f R g_c: the back-EMF's part of the free flux [Wb] */
    dq_t gu_Wb_V;          /* L g_u: the flux a volt at the middle angle moves [Wb/V] */
    dq_t ku_V_Wb;          /* 1/(L g_u): the volts a flux change takes [V/Wb] */
    dq_t free_Wb;          /* dbdtc_solve's free flux at k+2 (dbdtc_torque_after's) [Wb] */
    uint16_t taken;        /* what Phi .. ku were taken from: DBDTC_TAKEN_* */
    uint32_t turn;         /* ... in the turn of this number (zoh_turn_t.seq) */
    uint32_t g_rev;        /* ... with the g_c of this number (dbdtc_period_from's) */
} dbdtc_step_t;

#define DBDTC_TAKEN_NONE 0u /* the parameters changed since: to take */
#define DBDTC_TAKEN_OWN  1u /* dbdtc_period: the model's own g_c */
#define DBDTC_TAKEN_FROM 2u /* dbdtc_period_from: a g_c handed over */

typedef struct {
    dbdtc_cfg_t cfg;
    float u_lo_V;          /* -cfg.u_max_V, -cfg.i_max_A, -cfg.te_max_Nm: the clamps' lower */
    float i_lo_A;          /* bounds, negated once (dbdtc_init) */
    float te_lo_Nm;
    float R_lo_Ohm, R_hi_Ohm;     /* the model's bands (DBDTC_PARAM_FACTOR_* x cfg), */
    float L_lo_H, L_hi_H;         /* taken once (dbdtc_init): a model update's */
    float psi_lo_Wb, psi_hi_Wb;   /* clamps without their products */
    float kt_per_Wb_Nm_A;         /* 1.5 p: kt per Wb of psi_f (spmsm.h) [N m/(A Wb)] */
    dbdtc_par_t par;
    dbdtc_step_t st;
} dbdtc_t;

/* Start-up: copy *cfg and set the model parameters from it. False (the
 * configuration refused; the caller must not run it) when a value is not
 * finite, Ts_s, R_Ohm, L_H, psi_f_Wb or a bound is not positive, or
 * pole_pairs is 0. */
bool dbdtc_init(dbdtc_t *db, const dbdtc_cfg_t *cfg);

/* Back to the configured parameters. Background, before PWM is enabled. */
void dbdtc_reset(dbdtc_t *db);

/* Model parameters [Ohm, H, Wb], bounded to 0.1..10 x the configured value;
 * recomputes the derived constants and the decay (4 divisions). The
 * period's turn must be taken again (dbdtc_period). ISR or background. */
void dbdtc_set_params(dbdtc_t *db, float R_Ohm, float L_H, float psi_f_Wb);

/* As dbdtc_set_params with the decay *zm of the same R (the observer's,
 * taken at its L within SMO_MODEL_UPDATE_REL): 2 divisions less; zm NULL,
 * a bounded R that is not zm's or a refused zm: as dbdtc_set_params. ISR. */
void dbdtc_set_params_zm(dbdtc_t *db, float R_Ohm, float L_H, float psi_f_Wb, const zoh_model_t *zm);

/* Takes the period's Phi, D, gu, ku (dbdtc_period, dbdtc_period_from):
 * the model's own g_c (taken = DBDTC_TAKEN_OWN: 1 division) or g_c_A_V of
 * number g_rev (DBDTC_TAKEN_FROM). ISR (inline: in the periods whose turn
 * or model moved, the ISR's busiest). */
static inline void dbdtc_take_period(dbdtc_t *db, const zoh_turn_t *t, dq_t g_c_A_V, uint32_t g_rev, uint16_t taken)
{
    const dbdtc_par_t *p = &db->par;
    dbdtc_step_t *st = &db->st;
    dq_t g_c = g_c_A_V;

    if (taken == DBDTC_TAKEN_OWN) {
        zoh_step_t z;
        zoh_step(&p->zm, t, &z); /* 1 division */
        g_c = z.g_c;
    }
    st->taken = taken;
    st->turn = t->seq;
    st->g_rev = g_rev;
    if (!(p->zm.R_Ohm > 0.0f) || !(p->zm.tau_s > 0.0f)) {
        /* refused parameters: the identity, no voltage (a refused model is never run) */
        st->Phi.d = 1.0f;
        st->Phi.q = 0.0f;
        st->D_Wb.d = 0.0f;
        st->D_Wb.q = 0.0f;
        st->gu_Wb_V.d = 0.0f;
        st->gu_Wb_V.q = 0.0f;
        st->ku_V_Wb.d = 0.0f;
        st->ku_V_Wb.q = 0.0f;
        return;
    }
    st->Phi.d = p->zm.rho * t->c1;         /* rho e^(-j theta) */
    st->Phi.q = -p->zm.rho * t->s1;
    st->D_Wb.d = p->psiR_Wb_Ohm * g_c.d;
    st->D_Wb.q = p->psiR_Wb_Ohm * g_c.q;
    st->gu_Wb_V.d = p->L_gamma_Wb_V * t->ch;  /* L gamma e^(-j theta/2) */
    st->gu_Wb_V.q = -p->L_gamma_Wb_V * t->sh;
    st->ku_V_Wb.d = p->zm.kappa_1_s * t->ch;  /* kappa e^(+j theta/2) */
    st->ku_V_Wb.q = p->zm.kappa_1_s * t->sh;
}

/* This period's model from the rotor's turn *t (w within +-omega_max;
 * zoh_turn): once a period, after any dbdtc_set_params of it, before
 * dbdtc_predict, dbdtc_solve, dbdtc_torque_after. 1 division when the
 * turn or the parameters changed since it was last taken, else none. ISR
 * (inline: the check). */
static inline void dbdtc_period(dbdtc_t *db, const zoh_turn_t *t)
{
    if ((db->st.taken != DBDTC_TAKEN_OWN) || (db->st.turn != t->seq)) {
        const dq_t none = { 0.0f, 0.0f };
        dbdtc_take_period(db, t, none, 0u, DBDTC_TAKEN_OWN);
    }
}

/* As dbdtc_period with the period's gain g_c_A_V (zoh_step_t.g_c) of a
 * model with the same R, L (the observer's, whose estimates the model
 * takes: one division for both), g_rev its number (smo_t.z_rev). No
 * division; nothing when the turn, the parameters and g_c are those it
 * was last taken with. ISR (inline: the check). */
static inline void dbdtc_period_from(dbdtc_t *db, const zoh_turn_t *t, dq_t g_c_A_V, uint32_t g_rev)
{
    if ((db->st.taken != DBDTC_TAKEN_FROM) || (db->st.turn != t->seq) || (db->st.g_rev != g_rev)) {
        dbdtc_take_period(db, t, g_c_A_V, g_rev, DBDTC_TAKEN_FROM);
    }
}

/* Torque Te(k+2) [N m] the model expects from the state dbdtc_solve was
 * given this period when u_dq_V [V] is applied over [k+1, k+2] (eq. 5 on
 * the discrete model): what a voltage-limited step really asks of the
 * motor, for the speed loop's anti-windup. After dbdtc_solve. ISR
 * (inline: once a period). */
static inline float dbdtc_torque_after(const dbdtc_t *db, dq_t u_dq_V)
{
    const dbdtc_cfg_t *cfg = &db->cfg;
    const dbdtc_step_t *st = &db->st;
    const float ud = mathx_clampf(u_dq_V.d, db->u_lo_V, cfg->u_max_V);
    const float uq = mathx_clampf(u_dq_V.q, db->u_lo_V, cfg->u_max_V);

    /* eq. (5) on psi_q(k+2) */
    return db->par.te_per_Wb * (st->free_Wb.q + st->gu_Wb_V.d * uq + st->gu_Wb_V.q * ud);
}

/* Flux and torque (eq. 11, 12) from the currents i_dq_A [A] (bounded to
 * +-i_max_A). ISR context (inline). */
static inline dbdtc_state_t dbdtc_state_from_currents(const dbdtc_t *db, dq_t i_dq_A)
{
    const dbdtc_par_t *p = &db->par;
    const float i_max = db->cfg.i_max_A;
    dbdtc_state_t x;

    x.i_dq_A.d = mathx_clampf(i_dq_A.d, db->i_lo_A, i_max);
    x.i_dq_A.q = mathx_clampf(i_dq_A.q, db->i_lo_A, i_max);
    x.psi_dq_Wb.d = p->L_H * x.i_dq_A.d + p->psi_f_Wb;   /* eq. (11) */
    x.psi_dq_Wb.q = p->L_H * x.i_dq_A.q;                 /* eq. (11) */
    x.te_Nm = p->kt_Nm_per_A * x.i_dq_A.q;                /* eq. (12) */
    return x;
}

/* As dbdtc_state_from_currents for currents already within +-i_max_A
 * (the observer's prediction, bounded by the same i_max): no clamp. ISR
 * (inline). */
static inline dbdtc_state_t dbdtc_state_from_bounded(const dbdtc_t *db, dq_t i_dq_A)
{
    const dbdtc_par_t *p = &db->par;
    dbdtc_state_t x;
    x.i_dq_A = i_dq_A;
    x.psi_dq_Wb.d = p->L_H * i_dq_A.d + p->psi_f_Wb; /* eq. (11) */
    x.psi_dq_Wb.q = p->L_H * i_dq_A.q;               /* eq. (11) */
    x.te_Nm = p->kt_Nm_per_A * i_dq_A.q;             /* eq. (12) */
    return x;
}


/* The free flux one period on: Phi psi + psi_f R g_c (no voltage) [Wb]. ISR. */
static inline dq_t dbdtc_free_flux(const dbdtc_step_t *st, dq_t psi)
{
    dq_t f = zoh_mul(st->Phi, psi);
    f.d += st->D_Wb.d;
    f.q += st->D_Wb.q;
    return f;
}

/* Delay compensation: state at k+1 from the sampled i_dq_A(k) [A] and the
 * voltage u_dq_V(k) [V] being applied now (eq. 10-12 on the exact
 * discrete model). ISR (inline: once a period on the told model). */
static inline dbdtc_state_t dbdtc_predict(const dbdtc_t *db, dq_t i_dq_A, dq_t u_dq_V)
{
    const dbdtc_cfg_t *cfg = &db->cfg;
    const dbdtc_par_t *p = &db->par;
    dq_t u;
    dq_t psi;
    dq_t i1;

    u.d = mathx_clampf(u_dq_V.d, db->u_lo_V, cfg->u_max_V);
    u.q = mathx_clampf(u_dq_V.q, db->u_lo_V, cfg->u_max_V);
    psi.d = p->L_H * mathx_clampf(i_dq_A.d, db->i_lo_A, cfg->i_max_A) + p->psi_f_Wb;
    psi.q = p->L_H * mathx_clampf(i_dq_A.q, db->i_lo_A, cfg->i_max_A);
    /* eq. (10) exact: psi(k+1) = Phi psi + psi_f R g_c + L g_u u */
    const dq_t f = dbdtc_free_flux(&db->st, psi);
    const dq_t v = zoh_mul(db->st.gu_Wb_V, u);
    i1.d = (f.d + v.d - p->psi_f_Wb) * p->inv_L_1_H;
    i1.q = (f.q + v.q) * p->inv_L_1_H;
    return dbdtc_state_from_currents(db, i1);
}

/* Deadbeat voltage u(k+1) [V] (eq. 17) that gives Te(k+2) = te_ref_Nm and
 * |psi_s(k+2)| = psi_ref_Wb from the predicted state *x; bounded to
 * +-u_max_V; returns DBDTC_FLAG_*. Keeps the free flux at k+2 for
 * dbdtc_torque_after. 0 divisions, 1 square root. ISR context (inline:
 * once a period, its output kept in the caller's registers). */
static inline uint16_t dbdtc_solve(dbdtc_t *db, const dbdtc_state_t *x, float te_ref_Nm, float psi_ref_Wb,
                                   dq_t *u_dq_V)
{
    const dbdtc_cfg_t *cfg = &db->cfg;
    const dbdtc_par_t *p = &db->par;
    const float te_ref = mathx_clampf(te_ref_Nm, db->te_lo_Nm, cfg->te_max_Nm);
    const float psi_ref = mathx_clampf(psi_ref_Wb, 0.0f, cfg->psi_max_Wb);
    uint16_t flags = 0u;

    /* the state's flux, bounded as dbdtc_state_from_currents() makes it */
    const float psi_bound = p->L_H * cfg->i_max_A + p->psi_f_Wb;
    dq_t psi;
    psi.d = mathx_clampf(x->psi_dq_Wb.d, -psi_bound, psi_bound);
    psi.q = mathx_clampf(x->psi_dq_Wb.q, -psi_bound, psi_bound);

    /* the free flux at k+2 (the voltage's part aside) */
    const dq_t f = dbdtc_free_flux(&db->st, psi);
    db->st.free_Wb = f;

    /* eq. (5): the q flux that makes Te(k+2) = Te* */
    const float psiq_tgt = p->psiq_per_Nm * te_ref;

    /* eq. (17): X1'^2 - X2' = psi_s*^2 - psi_q*^2 */
    const float disc = psi_ref * psi_ref - psiq_tgt * psiq_tgt;
    float psid_tgt = 0.0f; /* vertex when the flux target is out of reach */
    if (disc >= 0.0f) {
        psid_tgt = mathx_sqrtf(disc);
    } else {
        flags |= DBDTC_FLAG_FLUX_UNREACHABLE;
    }

    /* u = (psi* - free) / (L g_u) */
    dq_t dpsi;
    dpsi.d = psid_tgt - f.d;
    dpsi.q = psiq_tgt - f.q;
    const dq_t u = zoh_mul(db->st.ku_V_Wb, dpsi);
    u_dq_V->d = mathx_clampf(u.d, db->u_lo_V, cfg->u_max_V);
    u_dq_V->q = mathx_clampf(u.q, db->u_lo_V, cfg->u_max_V);
    return flags;
}

/* dbdtc_limit for a request outside the inscribed circle: vdc >= 0 [V],
 * r = vdc/sqrt(3) [V]. ISR context. */
uint16_t dbdtc_limit_hexagon(dq_t *u_dq_V, float sin_th, float cos_th, float vdc, float r);

/* Torque-first limit of *u_dq_V [V] (in/out) to the inverter hexagon at
 * vdc_V [V], for a rotor frame at the angle whose sin/cos are given;
 * returns DBDTC_FLAG_VOLTAGE_LIMIT when it moved the vector. One test
 * inside the inscribed circle (the normal period: inline), no division when
 * inside; when limiting, 3 for each hexagon chord it needs: none for a
 * vertex, 3 or 6 otherwise. ISR context. */
static inline uint16_t dbdtc_limit(dq_t *u_dq_V, float sin_th, float cos_th, float vdc_V)
{
    const float vdc = (vdc_V > 0.0f) ? vdc_V : 0.0f; /* NaN too */
    const float r = vdc * MATHX_INV_SQRT3_F;

    if ((u_dq_V->d * u_dq_V->d + u_dq_V->q * u_dq_V->q) <= DBDTC_INSCRIBED_SAFE_SQ * r * r) {
        return 0u;
    }
    return dbdtc_limit_hexagon(u_dq_V, sin_th, cos_th, vdc, r);
}

#endif /* DBDTC_H */
