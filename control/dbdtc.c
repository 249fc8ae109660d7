/* dbdtc.c - conventional deadbeat direct torque control; see dbdtc.h. */
#include "dbdtc.h"

#include <float.h>

#include "mathx.h"
#include "spmsm.h"


#define TWO_THIRDS   CLARKE_TWO_THIRDS /* hexagon vertex = 2/3 Vdc */
#define HALF_SQRT3   CLARKE_HALF_SQRT3 /* cos 30 deg */

/* Below this |e_d . n| a hexagon side is parallel to the d axis: its
 * constraint does not depend on u_d (avoids dividing by ~0). */
#define SIDE_PARALLEL_EPS 1.0e-6f

/* dbdtc_init: dbdtc_cfg.c (start-up, from flash). */

void dbdtc_reset(dbdtc_t *db)
{
    dbdtc_set_params(db, db->cfg.R_Ohm, db->cfg.L_H, db->cfg.psi_f_Wb);
}

void dbdtc_set_params(dbdtc_t *db, float R_Ohm, float L_H, float psi_f_Wb)
{
    dbdtc_set_params_zm(db, R_Ohm, L_H, psi_f_Wb, NULL);
}

void dbdtc_set_params_zm(dbdtc_t *db, float R_Ohm, float L_H, float psi_f_Wb, const zoh_model_t *zm)
{
    const dbdtc_cfg_t *cfg = &db->cfg;
    dbdtc_par_t *p = &db->par;

    p->R_Ohm = mathx_clampf(R_Ohm, db->R_lo_Ohm, db->R_hi_Ohm);
    p->L_H = mathx_clampf(L_H, db->L_lo_H, db->L_hi_H);
    p->psi_f_Wb = mathx_clampf(psi_f_Wb, db->psi_lo_Wb, db->psi_hi_Wb);

    const float inv_L = 1.0f / p->L_H;                                  /* division 1 */
    if ((zm != NULL) && (zm->R_Ohm == p->R_Ohm) && (zm->tau_s > 0.0f)) {
        p->zm = *zm; /* the observer's decay at this R and its L (within SMO_MODEL_UPDATE_REL) */
    } else if (!zoh_model(p->R_Ohm, p->L_H, cfg->Ts_s, &p->zm)) {        /* divisions 2, 3 */
        /* a refused configuration (dbdtc_init said so): no decay, Euler's gains */
        p->zm.R_Ohm = p->R_Ohm;
        p->zm.L_H = p->L_H;
        p->zm.tau_s = 0.0f;
        p->zm.rho = 1.0f;
        p->zm.one_m_rho = 0.0f;
        p->zm.gamma_A_V = 0.0f;
        p->zm.kappa_1_s = 0.0f;
    }
    p->inv_L_1_H = inv_L;
    p->psiR_Wb_Ohm = p->psi_f_Wb * p->R_Ohm;
    p->L_gamma_Wb_V = p->L_H * p->zm.gamma_A_V;
    p->kt_Nm_per_A = db->kt_per_Wb_Nm_A * p->psi_f_Wb; /* spmsm_kt_Nm_A: (1.5 p) psi_f, the same product */
    p->te_per_Wb = p->kt_Nm_per_A * inv_L;
    p->psiq_per_Nm = p->L_H / p->kt_Nm_per_A;                           /* division 4 */
    p->inv_psi_f_1_Wb = db->kt_per_Wb_Nm_A * p->psiq_per_Nm * inv_L; /* 1.5 p / kt */
    db->st.taken = DBDTC_TAKEN_NONE; /* the period is taken again */
}

/* The interval [lo, hi] of t where a line a_j t + b_j fixed meets the
 * hexagon |a_j t + b_j fixed| <= r (j = the three side pairs); hit false
 * when a side parallel to the line misses it. */
typedef struct {
    float lo;
    float hi;
    bool hit;
} chord_t;

/* One side pair's part in the chord: t in [-c/a - |r/a|, -c/a + |r/a|]
 * (either sign of a, no branch), c = b fixed; a side parallel to the line
 * (|a| small: no division by ~0) bounds nothing or misses it. One
 * division. */
static inline void chord_side(chord_t *ch, float a, float b, float fixed, float r)
{
    const float c = fixed * b;

    if (mathx_fabsf(a) > SIDE_PARALLEL_EPS) {
        const float inv_a = 1.0f / a;
        const float mid = -c * inv_a;
        const float half = mathx_fabsf(r * inv_a);
        const float t1 = mid - half;
        const float t2 = mid + half;
        ch->lo = (t1 > ch->lo) ? t1 : ch->lo;
        ch->hi = (t2 < ch->hi) ? t2 : ch->hi;
    } else if (mathx_fabsf(c) > r) {
        ch->hit = false;
    }
}

/* The chord of the line a_j t + b_j fixed, written out side by side (no
 * loop: the values stay in registers); false when it misses the hexagon.
 * Two sides at least bound t: max |a_j| >= cos 30 deg for the unit vectors
 * used here. 3 divisions. */
static inline bool hex_chord(float a0, float a1, float a2, float b0, float b1, float b2, float fixed, float r,
                             chord_t *ch)
{
    ch->lo = -FLT_MAX;
    ch->hi = FLT_MAX;
    ch->hit = true;
    chord_side(ch, a0, b0, fixed, r);
    chord_side(ch, a1, b1, fixed, r);
    chord_side(ch, a2, b2, fixed, r);
    return ch->hit && (ch->lo <= ch->hi);
}

uint16_t dbdtc_limit_hexagon(dq_t *u_dq_V, float sin_in, float cos_in, float vdc, float r)
{
    const float sin_th = mathx_clampf(sin_in, -1.0f, 1.0f);
    const float cos_th = mathx_clampf(cos_in, -1.0f, 1.0f);
    /* Hexagon sides: |u . n_j| <= Vdc/sqrt(3), n_j at 30, 90, 150 deg.
     * g_j = e_d . n_j and h_j = e_q . n_j with e_d = (c, s), e_q = (-s, c). */
    const float kc = HALF_SQRT3 * cos_th;
    const float ks = HALF_SQRT3 * sin_th;
    const float hc = 0.5f * cos_th;
    const float hs = 0.5f * sin_th;
    const float g0 = kc + hs;
    const float g1 = sin_th;
    const float g2 = hs - kc;
    const float h0 = hc - ks;
    const float h1 = cos_th;
    const float h2 = ks + hc;
    const float ud = u_dq_V->d;
    const float uq = u_dq_V->q;

    /* The hexagon's vertices: 2/3 Vdc on a phase axis at 0, 60 or 120 deg,
     * either sign; in the rotor frame the axes point along (c, -s) = (h_1,
     * -g_1), (h_2, -g_2) and (-h_0, g_0) (written as the rotation gives
     * them). The one with the largest |q| (the first of equals in that
     * order) gives the hexagon's reach in q: a request beyond it is
     * outside, and the line at its uq misses the hexagon; within it, the
     * sides and then the chord say exactly. */
    const float vmag = TWO_THIRDS * vdc;
    const float ga0 = mathx_fabsf(g0);
    const float ga1 = mathx_fabsf(g1);
    const float ga2 = mathx_fabsf(g2);
    float reach = ga1;
    float vd = h1;
    float vq = -g1;
    if (ga2 > reach) {
        reach = ga2;
        vd = h2;
        vq = kc - hs;
    }
    if (ga0 > reach) {
        reach = ga0;
        vd = ks - hc;
        vq = g0;
    }

    /* Torque first: keep uq, the u_d interval where the line meets the hexagon. */
    chord_t dch = { 0.0f, 0.0f, false };
    bool chord = false;
    if (mathx_fabsf(uq) <= vmag * reach) {
        if ((mathx_fabsf(ud * g0 + uq * h0) <= r) && (mathx_fabsf(ud * g1 + uq * h1) <= r) &&
            (mathx_fabsf(ud * g2 + uq * h2) <= r)) {
            return 0u;
        }
        chord = hex_chord(g0, g1, g2, h0, h1, h2, uq, r, &dch);
    }
    bool flux_first;
    if (chord) {
        /* The chord would push u_d up, psi_d above its target: at the
         * voltage limit i_d then runs positive and the torque falls. Flux
         * first instead: keep u_d, the u_q nearest the request on the
         * hexagon at that u_d (the most torque the limit allows while the
         * flux goes where the deadbeat step wants it). */
        flux_first = (ud < dch.lo);
    } else {
        /* uq alone is out of reach: the vertex with the largest q component
         * along uq (the most torque the inverter can make), unless it would
         * raise psi_d above its target: flux first, the most u_q along the
         * request on the hexagon at the requested u_d. */
        if (!((uq >= 0.0f) ? (vq >= 0.0f) : (vq <= 0.0f))) { /* the vertex on uq's side */
            vd = -vd;
            vq = -vq;
        }
        flux_first = (vmag * vd > ud);
    }
    chord_t qch = { 0.0f, 0.0f, false };
    if (flux_first && (ud >= -r) && hex_chord(h0, h1, h2, g0, g1, g2, ud, r, &qch)) {
        u_dq_V->q = chord ? mathx_clampf(uq, qch.lo, qch.hi) : ((uq >= 0.0f) ? qch.hi : qch.lo);
    } else if (chord) {
        u_dq_V->d = mathx_clampf(ud, dch.lo, dch.hi);
    } else {
        u_dq_V->d = vmag * vd;
        u_dq_V->q = vmag * vq;
    }
    return DBDTC_FLAG_VOLTAGE_LIMIT;
}
