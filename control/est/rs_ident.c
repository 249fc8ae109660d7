/* rs_ident.c - step 1, offline stator resistance; see rs_ident.h. */
#include "rs_ident.h"

#include <stddef.h>

#include "mathx.h"

/* Fixed iteration count of the dR/dpsi/dL solve (step1_design.md sec. 1): dL
 * enters fq only through dL w id, a small correction, so the error shrinks
 * by a factor ~ |id/iq| per pass; four passes reach float resolution. */
#define SOLVE_ITERATIONS 4
/* Counts stay exact in a float up to 2^24; a window stops growing there. */
#define WIN_N_MAX 16777216u
/* Absolute floor of |iq2 w1 - iq1 w2| [A rad/s] below which (41) is not
 * solved even when the relative test passes (both points near standstill). */
#define DEN_MIN_A_RAD_S 1.0f
/* |w iq| [A rad/s] below which a point gives no dL, and |w| [rad/s] below
 * which it gives no dpsi (ill-conditioned divisions). */
#define WIQ_MIN_A_RAD_S 30.0f
#define W_MIN_RAD_S 30.0f
#define HALF 0.5f
#define INV_12 0.0833333333f

void rs_ident_cfg_defaults(rs_ident_cfg_t *cfg, float R_nom_Ohm)
{
    cfg->R_nom_Ohm = R_nom_Ohm;
    cfg->R_min_Ohm = RS_IDENT_BAND_MIN_FACTOR * R_nom_Ohm;
    cfg->R_max_Ohm = RS_IDENT_BAND_MAX_FACTOR * R_nom_Ohm;
    cfg->R_se_max_rel = RS_IDENT_R_SE_MAX_REL_DEFAULT;
    cfg->den_ratio_min = RS_IDENT_DEN_RATIO_DEFAULT;
    cfg->n_min = RS_IDENT_N_MIN_DEFAULT;
    cfg->n_batch = RS_IDENT_N_BATCH_DEFAULT;
    cfg->Ts_s = 0.0f;
}

bool rs_ident_init(rs_ident_t *ri, const rs_ident_cfg_t *cfg)
{
    const float sum = cfg->R_nom_Ohm + cfg->R_min_Ohm + cfg->R_max_Ohm + cfg->R_se_max_rel +
                      cfg->den_ratio_min + cfg->Ts_s;
    ri->cfg = *cfg;
    ri->valid = mathx_isfinitef(sum) && (cfg->R_nom_Ohm > 0.0f) && (cfg->R_min_Ohm >= 0.0f) &&
                (cfg->R_min_Ohm <= cfg->R_nom_Ohm) && (cfg->R_nom_Ohm <= cfg->R_max_Ohm) &&
                (cfg->R_se_max_rel > 0.0f) && (cfg->den_ratio_min > 0.0f) &&
                (cfg->den_ratio_min < 1.0f) && (cfg->n_min >= 2u) && (cfg->n_min <= WIN_N_MAX) &&
                (cfg->n_batch > RS_IDENT_SOLVE_STAGES) && (cfg->n_batch <= WIN_N_MAX) && (cfg->Ts_s >= 0.0f);
    ri->inv_n_batch = ri->valid ? 1.0f / (float)cfg->n_batch : 0.0f;
    rs_ident_reset(ri);
    return ri->valid;
}

RAMFUNC void rs_ident_reset(rs_ident_t *ri)
{
    int16_t j;
    int16_t ch;
    for (j = 0; j < 2; j++) {
        rs_ident_win_t *w = &ri->win[j];
        w->h.n = 0u;
        w->h.s2_iq = 0.0f;
        for (ch = 0; ch < (int16_t)RS_CH_COUNT; ch++) {
            w->h.x0[ch] = 0.0f;
            w->h.s1[ch] = 0.0f;
        }
        w->bn = 0u;
        w->nb = 0u;
        for (ch = 0; ch < (int16_t)RS_ST_COUNT; ch++) {
            w->bsum[ch] = 0.0f;
            w->m1[ch] = 0.0f;
        }
        for (ch = 0; ch < (int16_t)RS_ST_PAIRS; ch++) {
            w->m2[ch] = 0.0f;
        }
        for (ch = 0; ch < 5; ch++) {
            w->g[ch] = 0.0f;
        }
        w->bcs[0] = 0.0f;
        w->bcs[1] = 0.0f;
        w->km_iq = 0.0f;
        for (ch = 0; ch < (int16_t)RS_ST_COUNT; ch++) {
            w->mcs[ch][0] = 0.0f;
            w->mcs[ch][1] = 0.0f;
            w->mcs6[ch][0] = 0.0f;
            w->mcs6[ch][1] = 0.0f;
        }
        for (ch = 0; ch < 9; ch++) {
            w->g6[ch] = 0.0f;
        }
        w->bcs6[0] = 0.0f;
        w->bcs6[1] = 0.0f;
    }
}

RAMFUNC void rs_ident_copy_head(rs_ident_head_t *dst, const rs_ident_t *src, rs_ident_window_t win)
{
    const rs_ident_head_t *h = &src->win[(win == RS_IDENT_WINDOW_1) ? 0 : 1].h;

    /* field by field, no loop a compiler turns into a library memcpy (from
     * flash on the target's ISR path): the copy shares a period with a
     * batch's close */
    dst->n = h->n;
    dst->x0[RS_CH_FD] = h->x0[RS_CH_FD];
    dst->x0[RS_CH_FQ] = h->x0[RS_CH_FQ];
    dst->x0[RS_CH_ID] = h->x0[RS_CH_ID];
    dst->x0[RS_CH_IQ] = h->x0[RS_CH_IQ];
    dst->x0[RS_CH_W] = h->x0[RS_CH_W];
    dst->s1[RS_CH_FD] = h->s1[RS_CH_FD];
    dst->s1[RS_CH_FQ] = h->s1[RS_CH_FQ];
    dst->s1[RS_CH_ID] = h->s1[RS_CH_ID];
    dst->s1[RS_CH_IQ] = h->s1[RS_CH_IQ];
    dst->s1[RS_CH_W] = h->s1[RS_CH_W];
    dst->s2_iq = h->s2_iq;
}

RAMFUNC bool rs_ident_batch_closed(const rs_ident_t *ri, rs_ident_window_t win)
{
    return ri->win[(win == RS_IDENT_WINDOW_1) ? 0 : 1].bn == 0u;
}

/* rs_ident_win_t.g */
#define G_C  0
#define G_S  1
#define G_CC 2
#define G_CS 3
#define G_SS 4
/* rs_ident_win_t.g6 */
#define G6_C    0
#define G6_S    1
#define G6_CC   2
#define G6_CS   3
#define G6_SS   4
#define G6_C_C  5  /* C C6 */
#define G6_C_S  6  /* C S6 */
#define G6_S_C  7  /* S C6 */
#define G6_S_S  8  /* S S6 */

/* Index of the pair (a, b), a <= b, in rs_ident_win_t.m2 (ff, fi, fw, ii, iw, ww). */
RAMFUNC static int16_t pair_index(int16_t a, int16_t b)
{
    static const int16_t idx[RS_ST_COUNT][RS_ST_COUNT] = { { 0, 1, 2 }, { 1, 3, 4 }, { 2, 4, 5 } };
    return idx[a][b];
}

/* Channel a's batch mean m (relative to x0) into its sums, its batch sum emptied. */
RAMFUNC static inline void close_channel(rs_ident_win_t *w, int16_t a, float m, float C, float S, float C6, float S6)
{
    w->m1[a] += m;
    w->mcs[a][0] += m * C;
    w->mcs[a][1] += m * S;
    w->mcs6[a][0] += m * C6;
    w->mcs6[a][1] += m * S6;
    w->bsum[a] = 0.0f;
}

/* A batch is complete: its mean (relative to x0) into the batch sums. The
 * channels and pairs written out: a period that closes a batch is one of
 * the ISR's longest (loops and pair_index's table cost more than the sums). */
RAMFUNC static void close_batch(rs_ident_win_t *w, float inv_n_batch)
{
    const float C = w->bcs[0] * inv_n_batch;
    const float S = w->bcs[1] * inv_n_batch;
    const float C6 = w->bcs6[0] * inv_n_batch;
    const float S6 = w->bcs6[1] * inv_n_batch;
    const float mf = w->bsum[RS_ST_FQ] * inv_n_batch;
    const float mi = w->bsum[RS_ST_IQ] * inv_n_batch;
    const float mw = w->bsum[RS_ST_W] * inv_n_batch;

    close_channel(w, RS_ST_FQ, mf, C, S, C6, S6);
    close_channel(w, RS_ST_IQ, mi, C, S, C6, S6);
    close_channel(w, RS_ST_W, mw, C, S, C6, S6);
    w->g6[G6_C] += C6;
    w->g6[G6_S] += S6;
    w->g6[G6_CC] += C6 * C6;
    w->g6[G6_CS] += C6 * S6;
    w->g6[G6_SS] += S6 * S6;
    w->g6[G6_C_C] += C * C6;
    w->g6[G6_C_S] += C * S6;
    w->g6[G6_S_C] += S * C6;
    w->g6[G6_S_S] += S * S6;
    w->bcs6[0] = 0.0f;
    w->bcs6[1] = 0.0f;
    w->km_iq += (float)w->nb * mi;
    w->g[G_C] += C;
    w->g[G_S] += S;
    w->g[G_CC] += C * C;
    w->g[G_CS] += C * S;
    w->g[G_SS] += S * S;
    w->bcs[0] = 0.0f;
    w->bcs[1] = 0.0f;
    /* m2's pairs in its order: ff, fi, fw, ii, iw, ww (pair_index) */
    w->m2[0] += mf * mf;
    w->m2[1] += mf * mi;
    w->m2[2] += mf * mw;
    w->m2[3] += mi * mi;
    w->m2[4] += mi * mw;
    w->m2[5] += mw * mw;
    w->bn = 0u;
    w->nb++;
}

void rs_ident_step(rs_ident_t *ri, rs_ident_window_t win, float fd_V, float fq_V, float id_A,
                   float iq_A, float omega_el_rad_s)
{
    /* no angle: C = S = 0, the ripple fit is never conditioned */
    rs_ident_step_el(ri, win, fd_V, fq_V, id_A, iq_A, omega_el_rad_s, 0.0f, 0.0f);
}

RAMFUNC void rs_ident_step_el(rs_ident_t *ri, rs_ident_window_t win, float fd_V, float fq_V, float id_A, float iq_A,
                      float omega_el_rad_s, float cos_el, float sin_el)
{
    const float x[RS_CH_COUNT] = { fd_V, fq_V, id_A, iq_A, omega_el_rad_s };
    rs_ident_win_t *w;
    int16_t ch;

    if ((win != RS_IDENT_WINDOW_1) && (win != RS_IDENT_WINDOW_2)) {
        return;
    }
    w = &ri->win[(win == RS_IDENT_WINDOW_1) ? 0 : 1];
    if (w->h.n >= WIN_N_MAX) {
        return;
    }
    if (w->h.n == 0u) {
        for (ch = 0; ch < (int16_t)RS_CH_COUNT; ch++) {
            w->h.x0[ch] = x[ch];
        }
    }
    /* shifted sums: the first sample is close to the mean in a steady
     * window, so s2 - s1^2/n does not cancel in float */
    for (ch = 0; ch < (int16_t)RS_CH_COUNT; ch++) {
        w->h.s1[ch] += x[ch] - w->h.x0[ch];
    }
    const float diq = x[RS_CH_IQ] - w->h.x0[RS_CH_IQ];
    w->h.s2_iq += diq * diq;
    w->h.n++;
    w->bsum[RS_ST_FQ] += x[RS_CH_FQ] - w->h.x0[RS_CH_FQ];
    w->bsum[RS_ST_IQ] += diq;
    w->bsum[RS_ST_W] += x[RS_CH_W] - w->h.x0[RS_CH_W];
    w->bcs[0] += cos_el;
    w->bcs[1] += sin_el;
    /* cos, sin 6 theta_el: double, triple, double angle (10 multiplications) */
    const float c2 = cos_el * cos_el - sin_el * sin_el;
    const float s2 = 2.0f * cos_el * sin_el;
    const float c3 = c2 * cos_el - s2 * sin_el;
    const float s3 = s2 * cos_el + c2 * sin_el;
    w->bcs6[0] += c3 * c3 - s3 * s3;
    w->bcs6[1] += 2.0f * c3 * s3;
    w->bn++;
    if (w->bn >= ri->cfg.n_batch) {
        close_batch(w, ri->inv_n_batch);
    }
}

/* The ripple fit of a window (step1_design.md sec. 4): inverse of G = Z'Z, Z the
 * rows (1, C_i, S_i); false (plain means) when there are too few batches
 * or det(G / nb) is below RS_IDENT_RIPPLE_DET_MIN. 1 division. */
RAMFUNC static bool ripple_fit(const rs_ident_win_t *w, float Gi[3][3])
{
    const float nb = (float)w->nb;
    const float G[3][3] = { { nb, w->g[G_C], w->g[G_S] },
                            { w->g[G_C], w->g[G_CC], w->g[G_CS] },
                            { w->g[G_S], w->g[G_CS], w->g[G_SS] } };
    int16_t r;
    int16_t k;

    if (w->nb < RS_IDENT_RIPPLE_BATCHES_MIN) {
        return false;
    }
    /* adjugate: Gi[r][k] = cofactor(k, r); G is symmetric */
    for (r = 0; r < 3; r++) {
        for (k = 0; k < 3; k++) {
            const int16_t r1 = (int16_t)((k + 1) % 3);
            const int16_t r2 = (int16_t)((k + 2) % 3);
            const int16_t c1 = (int16_t)((r + 1) % 3);
            const int16_t c2 = (int16_t)((r + 2) % 3);
            Gi[r][k] = G[r1][c1] * G[r2][c2] - G[r1][c2] * G[r2][c1];
        }
    }
    const float det = G[0][0] * Gi[0][0] + G[0][1] * Gi[1][0] + G[0][2] * Gi[2][0];
    if (!(det > RS_IDENT_RIPPLE_DET_MIN * nb * nb * nb)) {
        return false;
    }
    const float inv_det = 1.0f / det;
    for (r = 0; r < 3; r++) {
        for (k = 0; k < 3; k++) {
            Gi[r][k] *= inv_det;
        }
    }
    return true;
}

/* Z'x for channel a of the batch stats: (sum m_a, sum m_a C, sum m_a S). */
RAMFUNC static void zt_channel(const rs_ident_win_t *w, int16_t a, float h[3])
{
    h[0] = w->m1[a];
    h[1] = w->mcs[a][0];
    h[2] = w->mcs[a][1];
}

/* The fit's 6th harmonic (step1_design.md sec. 4), by partitioned regression on
 * the fit of (1, C, S) (f->Gi): with B the cross sums of (C6, S6) with
 * (1, C, S), D theirs, P = Gi B, the Schur complement Sc = D - B' P; false
 * (the 3-term fit alone) with fewer than RS_IDENT_RIPPLE6_BATCHES_MIN
 * batches or det(Sc / nb) below RS_IDENT_RIPPLE_DET_MIN (batches of whole
 * ripple periods, the 6th aliased onto the 1st). Else f gets P and Sc^-1;
 * the intercepts move by -u' Sc^-1 q_a (u = P's row 0, ripple6_q). 1 division. */
RAMFUNC static bool ripple6_fit(const rs_ident_win_t *w, rs_ident_ripple_t *f)
{
    const float(*Gi)[3] = f->Gi;
    const float nb = (float)w->nb;
    const float B[3][2] = { { w->g6[G6_C], w->g6[G6_S] },
                            { w->g6[G6_C_C], w->g6[G6_C_S] },
                            { w->g6[G6_S_C], w->g6[G6_S_S] } };
    float(*P)[2] = f->P;
    int16_t r;
    int16_t k;

    if (w->nb < RS_IDENT_RIPPLE6_BATCHES_MIN) {
        return false;
    }
    for (r = 0; r < 3; r++) {
        for (k = 0; k < 2; k++) {
            P[r][k] = Gi[r][0] * B[0][k] + Gi[r][1] * B[1][k] + Gi[r][2] * B[2][k];
        }
    }
    const float s00 = w->g6[G6_CC] - (B[0][0] * P[0][0] + B[1][0] * P[1][0] + B[2][0] * P[2][0]);
    const float s01 = w->g6[G6_CS] - (B[0][0] * P[0][1] + B[1][0] * P[1][1] + B[2][0] * P[2][1]);
    const float s11 = w->g6[G6_SS] - (B[0][1] * P[0][1] + B[1][1] * P[1][1] + B[2][1] * P[2][1]);
    const float det = s00 * s11 - s01 * s01;
    if (!(det > RS_IDENT_RIPPLE_DET_MIN * nb * nb)) {
        return false;
    }
    const float inv_det = 1.0f / det;
    f->Si6[0] = s11 * inv_det;
    f->Si6[1] = -s01 * inv_det;
    f->Si6[2] = s00 * inv_det;
    return true;
}

/* Channel a's q_a = Z6'm_a - P' Z'm_a (the 6th harmonic's part of its
 * batch means the 3 terms do not explain). */
RAMFUNC static void ripple6_q(const rs_ident_win_t *w, const rs_ident_ripple_t *f, int16_t a, float q[2])
{
    float h[3];
    int16_t k;

    zt_channel(w, a, h);
    for (k = 0; k < 2; k++) {
        q[k] = w->mcs6[a][k] - (f->P[0][k] * h[0] + f->P[1][k] * h[1] + f->P[2][k] * h[2]);
    }
}

/* x' Sc^-1 y for a 6th-harmonic fit (Si6 symmetric). */
RAMFUNC static float si6_form(const rs_ident_ripple_t *f, const float x[2], const float y[2])
{
    const float *si = f->Si6;
    return x[0] * (si[0] * y[0] + si[1] * y[1]) + x[1] * (si[1] * y[0] + si[2] * y[1]);
}

/* The sums of the residual r = fq + dR iq + dpsi w over window w's batch
 * means into sums: r'r, Z'r (3), Z6'r (2) (Z the rows (1, C_i, S_i), Z6
 * (C6_i, S6_i)). */
RAMFUNC static void residual_sums(const rs_ident_win_t *w, float dR, float dpsi, float sums[6])
{
    const float c[RS_ST_COUNT] = { 1.0f, dR, dpsi };
    int16_t a;
    int16_t b;

    sums[0] = 0.0f;
    for (a = 0; a < (int16_t)RS_ST_COUNT; a++) {
        for (b = 0; b < (int16_t)RS_ST_COUNT; b++) {
            sums[0] += c[a] * c[b] * w->m2[(a <= b) ? pair_index(a, b) : pair_index(b, a)];
        }
    }
    for (b = 1; b < 6; b++) {
        sums[b] = 0.0f;
    }
    for (a = 0; a < (int16_t)RS_ST_COUNT; a++) {
        sums[1] += c[a] * w->m1[a];
        sums[2] += c[a] * w->mcs[a][0];
        sums[3] += c[a] * w->mcs[a][1];
        sums[4] += c[a] * w->mcs6[a][0];
        sums[5] += c[a] * w->mcs6[a][1];
    }
}

/* Variance of the window's mean of r from its sums (residual_sums; nb >=
 * RS_IDENT_BATCHES_MIN >= 2): from the spread of its batch means, or, with
 * the ripple fit (f->Gi), from the fit's residuals: the intercept's variance
 * sigma^2 (G^-1)_00 with sigma^2 = SSR / (nb - 3); with the 6th harmonic
 * too, SSR less q_r' Sc^-1 q_r (q_r = Z6'r - P' Z'r) over nb - 5,
 * (G^-1)_00 plus u' Sc^-1 u. */
RAMFUNC static float residual_se2(const rs_ident_win_t *w, const rs_ident_ripple_t *f, const float sums[6])
{
    const float(*Gi)[3] = f->Gi;
    const float *h = &sums[1];
    const float nb = (float)w->nb;
    int16_t a;
    int16_t b;

    if (!f->fit) {
        const float var = sums[0] - h[0] * h[0] / nb;
        return ((var > 0.0f) ? var : 0.0f) / (nb * (nb - 1.0f)); /* sample variance of the batch means / nb */
    }
    float ssr = sums[0];
    for (a = 0; a < 3; a++) {
        for (b = 0; b < 3; b++) {
            ssr -= h[a] * Gi[a][b] * h[b];
        }
    }
    if (!f->fit6) {
        ssr = (ssr > 0.0f) ? ssr : 0.0f; /* >= 0 up to rounding */
        return ssr / (nb - 3.0f) * Gi[0][0];
    }
    float q[2];
    for (b = 0; b < 2; b++) {
        q[b] = sums[4 + b] - (f->P[0][b] * h[0] + f->P[1][b] * h[1] + f->P[2][b] * h[2]);
    }
    ssr -= si6_form(f, q, q);
    ssr = (ssr > 0.0f) ? ssr : 0.0f;
    return ssr / (nb - 5.0f) * (Gi[0][0] + si6_form(f, f->P[0], f->P[0]));
}

RAMFUNC static void zero_out(rs_ident_out_t *out, float R_nom)
{
    int16_t j;
    out->R_est_Ohm = R_nom;
    out->R_raw_Ohm = 0.0f;
    out->dR_Ohm = 0.0f;
    out->dL_H = 0.0f;
    out->dpsi_Wb = 0.0f;
    out->R_se_Ohm = 0.0f;
    out->R_se_max_Ohm = 0.0f;
    for (j = 0; j < 2; j++) {
        out->R_se_part_Ohm[j] = 0.0f;
        out->r_se_V[j] = 0.0f;
        out->ripple_fit[j] = false;
        out->ripple6_fit[j] = false;
        out->diq_dt_A_s[j] = 0.0f;
        out->batches[j] = 0u;
        out->iq_std_A[j] = 0.0f;
        out->mean_fd_V[j] = 0.0f;
        out->mean_fq_V[j] = 0.0f;
        out->mean_id_A[j] = 0.0f;
        out->mean_iq_A[j] = 0.0f;
        out->mean_w_rad_s[j] = 0.0f;
    }
}

/* The solve's stages (rs_ident_solve_step), one per call: what each does
 * (op_t) and on which window. The solver keeps one window's ripple fit:
 * the standard errors take window 2 first, whose fit is still there. */
typedef enum {
    OP_FIT = 0,    /* the window's ripple fit of (1, C, S): s->fit */
    OP_FIT6,       /*   its 6th harmonic */
    OP_MEANS,      /* the window's means, iq's slope: *out */
    OP_INTERCEPTS, /* the means over whole turns where the fit holds: *out */
    OP_POINTS,     /* dR, dpsi, dL from both windows' points */
    OP_SE_SUMS,    /* the window's residual sums: s->se_sums */
    OP_SE,         /*   its standard error and share of se(R^) */
    OP_VERDICT     /* se(R^) against its limit, the band */
} op_t;
#define STAGE(op, j) ((uint16_t)(((uint16_t)(op) << 1) | (uint16_t)(j)))
static const uint16_t STAGES[RS_IDENT_SOLVE_STAGES] = {
    STAGE(OP_FIT, 0),     STAGE(OP_FIT6, 0),    STAGE(OP_MEANS, 0), STAGE(OP_INTERCEPTS, 0),
    STAGE(OP_FIT, 1),     STAGE(OP_FIT6, 1),    STAGE(OP_MEANS, 1), STAGE(OP_INTERCEPTS, 1),
    STAGE(OP_POINTS, 0),  STAGE(OP_SE_SUMS, 1), STAGE(OP_SE, 1),    STAGE(OP_FIT, 0),
    STAGE(OP_FIT6, 0),    STAGE(OP_SE_SUMS, 0), STAGE(OP_SE, 0),    STAGE(OP_VERDICT, 0)
};

/* The ripple fit's intercept of channel a in window j (relative to x0):
 * the mean over whole turns (and whole ripple periods with the 6th). */
RAMFUNC static float intercept(const rs_ident_win_t *w, const rs_ident_ripple_t *f, int16_t a)
{
    const float(*Gi)[3] = f->Gi;
    float h[3];
    zt_channel(w, a, h);
    const float alpha = Gi[0][0] * h[0] + Gi[0][1] * h[1] + Gi[0][2] * h[2];
    if (!f->fit6) {
        return alpha;
    }
    float q[2];
    ripple6_q(w, f, a, q);
    return alpha - si6_form(f, f->P[0], q);
}

/* Window j's means and iq's slope into *out (the points the later stages
 * read there; step1_design.md sec. 5); RS_IDENT_OK or why the window is refused. */
RAMFUNC static rs_ident_result_t solve_means(const rs_ident_solver_t *s, int16_t j, rs_ident_out_t *out)
{
    const rs_ident_cfg_t *c = &s->ri->cfg;
    const rs_ident_win_t *wn = s->win[j];
    const rs_ident_head_t *hd = s->head[j];

    out->batches[j] = wn->nb;
    if ((hd->n < c->n_min) || (wn->nb < RS_IDENT_BATCHES_MIN)) {
        return RS_IDENT_TOO_FEW;
    }
    const float inv_n = 1.0f / (float)hd->n; /* n >= n_min >= 2 */
    out->mean_fd_V[j] = hd->x0[RS_CH_FD] + hd->s1[RS_CH_FD] * inv_n;
    out->mean_fq_V[j] = hd->x0[RS_CH_FQ] + hd->s1[RS_CH_FQ] * inv_n;
    out->mean_id_A[j] = hd->x0[RS_CH_ID] + hd->s1[RS_CH_ID] * inv_n;
    out->mean_iq_A[j] = hd->x0[RS_CH_IQ] + hd->s1[RS_CH_IQ] * inv_n;
    out->mean_w_rad_s[j] = hd->x0[RS_CH_W] + hd->s1[RS_CH_W] * inv_n;
    const float m1 = hd->s1[RS_CH_IQ] * inv_n;
    const float var = hd->s2_iq * inv_n - m1 * m1; /* >= 0 up to rounding */
    out->iq_std_A[j] = mathx_sqrtf(var);
    if (!mathx_isfinitef(out->mean_fd_V[j] + out->mean_fq_V[j] + out->mean_id_A[j] + out->mean_iq_A[j] +
                         out->mean_w_rad_s[j] + hd->s2_iq)) {
        return RS_IDENT_NON_FINITE;
    }
    /* step1_design.md sec. 5: iq's slope over the window, least squares on its batch
     * means: sum (k - kbar) m_k / sum (k - kbar)^2, kbar = (nb - 1)/2 */
    const float nbf = (float)wn->nb;
    const float kbar = HALF * (nbf - 1.0f);
    const float skk = nbf * (nbf * nbf - 1.0f) * INV_12;
    out->diq_dt_A_s[j] = (c->Ts_s > 0.0f)
                             ? (wn->km_iq - kbar * wn->m1[RS_ST_IQ]) / (skk * (float)c->n_batch * c->Ts_s)
                             : 0.0f;
    return RS_IDENT_OK;
}

/* step1_design.md sec. 4: window j's means of fq, iq, w over whole turns (and whole
 * ripple periods with the 6th) where its ripple fit s->fit holds. */
RAMFUNC static void solve_intercepts(const rs_ident_solver_t *s, int16_t j, rs_ident_out_t *out)
{
    const rs_ident_win_t *wn = s->win[j];
    const float *x0 = s->head[j]->x0;
    const rs_ident_ripple_t *f = &s->fit;

    out->ripple_fit[j] = f->fit;
    out->ripple6_fit[j] = f->fit6;
    if (f->fit) {
        out->mean_fq_V[j] = x0[RS_CH_FQ] + intercept(wn, f, RS_ST_FQ);
        out->mean_iq_A[j] = x0[RS_CH_IQ] + intercept(wn, f, RS_ST_IQ);
        out->mean_w_rad_s[j] = x0[RS_CH_W] + intercept(wn, f, RS_ST_W);
    }
}

/* dR, dpsi, dL from both windows' points (step1_design.md sec. 1; (41), (42)
 * with the signs corrected) into *s and *out; RS_IDENT_OK or why not. */
RAMFUNC static rs_ident_result_t solve_points(rs_ident_solver_t *s, rs_ident_out_t *out)
{
    const rs_ident_cfg_t *c = &s->ri->cfg;
    const float *fd = out->mean_fd_V;
    const float *fq = out->mean_fq_V;
    const float *id = out->mean_id_A;
    const float *iq = out->mean_iq_A;
    const float *w = out->mean_w_rad_s;
    const float *diq_dt = out->diq_dt_A_s;
    float inv_wiq[2];
    int16_t j;
    int16_t it;

    /* (41)'s denominator: equal speeds need iq1 != iq2, equal loads w1 != w2 */
    const float den = iq[1] * w[0] - iq[0] * w[1];
    const float a1 = mathx_fabsf(iq[1] * w[0]);
    const float a2 = mathx_fabsf(iq[0] * w[1]);
    const float scale = (a1 > a2) ? a1 : a2;
    if (!(mathx_fabsf(den) >= c->den_ratio_min * scale) || !(mathx_fabsf(den) > DEN_MIN_A_RAD_S)) {
        return RS_IDENT_DEGENERATE;
    }
    const float inv_den = 1.0f / den;
    /* dpsi from the faster point: the better-conditioned division */
    const int16_t jf = (mathx_fabsf(w[0]) >= mathx_fabsf(w[1])) ? 0 : 1;
    const bool use_w = mathx_fabsf(w[jf]) > W_MIN_RAD_S;
    const float inv_wf = use_w ? 1.0f / w[jf] : 0.0f;
    int16_t n_wiq = 0;
    for (j = 0; j < 2; j++) {
        const float wiq = w[j] * iq[j];
        const bool use_wiq = mathx_fabsf(wiq) > WIQ_MIN_A_RAD_S;
        inv_wiq[j] = use_wiq ? 1.0f / wiq : 0.0f;
        n_wiq = (int16_t)(n_wiq + (use_wiq ? 1 : 0));
    }
    const float inv_n_wiq = (n_wiq == 2) ? 0.5f : 1.0f;

    float dR = 0.0f;
    float dL = 0.0f;
    float dpsi = 0.0f;
    for (it = 0; it < SOLVE_ITERATIONS; it++) {
        /* step1_design.md sec. 1: g_j = fq_j + dL w_j id_j (+ dL diq/dt_j, sec. 5) = -dR iq_j - dpsi w_j */
        const float g0 = fq[0] + dL * (w[0] * id[0] + diq_dt[0]);
        const float g1 = fq[1] + dL * (w[1] * id[1] + diq_dt[1]);
        /* (41) with the corrected sign of (27) */
        dR = -(w[0] * g1 - w[1] * g0) * inv_den;
        dpsi = -(((jf == 0) ? g0 : g1) + dR * iq[jf]) * inv_wf;
        /* (54) corrected: fd_j + dR id_j = dL w_j iq_j */
        float sum = 0.0f;
        for (j = 0; j < 2; j++) {
            sum += (fd[j] + dR * id[j]) * inv_wiq[j];
        }
        dL = (n_wiq > 0) ? sum * inv_n_wiq : 0.0f;
    }

    /* (42) with the opposite sign: R^ = R - dR */
    const float R_est = c->R_nom_Ohm - dR;
    if (!mathx_isfinitef(R_est + dL + dpsi)) {
        return RS_IDENT_NON_FINITE;
    }
    out->R_raw_Ohm = R_est;
    out->dR_Ohm = dR;
    out->dL_H = dL;
    out->dpsi_Wb = dpsi;
    s->abs_inv_den = mathx_fabsf(inv_den);
    return RS_IDENT_OK;
}

/* step1_design.md sec. 3: window j's share of se(R^), delta dR = -(w1 delta r2 - w2 delta r1) / den */
RAMFUNC static void solve_se(const rs_ident_solver_t *s, int16_t j, rs_ident_out_t *out)
{
    out->r_se_V[j] = mathx_sqrtf(residual_se2(s->win[j], &s->fit, s->se_sums));
    out->R_se_part_Ohm[j] = mathx_fabsf(out->mean_w_rad_s[1 - j]) * out->r_se_V[j] * s->abs_inv_den;
}

/* se(R^) against its limit, then the band. */
RAMFUNC static rs_ident_result_t solve_verdict(const rs_ident_cfg_t *c, rs_ident_out_t *out)
{
    const float R_est = out->R_raw_Ohm;

    out->R_se_Ohm = mathx_sqrtf(out->R_se_part_Ohm[0] * out->R_se_part_Ohm[0] +
                                out->R_se_part_Ohm[1] * out->R_se_part_Ohm[1]);
    /* against |R^|, not below R_min: an R^ near 0 is judged by the band */
    const float R_ref = (mathx_fabsf(R_est) > c->R_min_Ohm) ? mathx_fabsf(R_est) : c->R_min_Ohm;
    out->R_se_max_Ohm = c->R_se_max_rel * R_ref;
    if (!mathx_isfinitef(out->R_se_Ohm) || !(out->R_se_Ohm <= out->R_se_max_Ohm)) {
        return RS_IDENT_NOT_STEADY;
    }
    if (!((R_est >= c->R_min_Ohm) && (R_est <= c->R_max_Ohm))) {
        return RS_IDENT_OUT_OF_BAND;
    }
    out->R_est_Ohm = R_est;
    return RS_IDENT_OK;
}

RAMFUNC void rs_ident_solve_begin(rs_ident_solver_t *s, const rs_ident_t *ri, const rs_ident_head_t *head_2)
{
    s->ri = ri;
    s->win[0] = &ri->win[0];
    s->win[1] = &ri->win[1];
    s->head[0] = &ri->win[0].h;
    s->head[1] = (head_2 != NULL) ? head_2 : &ri->win[1].h;
    s->stage = 0u;
    s->result = RS_IDENT_OK;
    s->abs_inv_den = 0.0f;
    s->fit.fit = false; /* the rest of fit and se_sums: written by their stages before they are read */
    s->fit.fit6 = false;
}

RAMFUNC bool rs_ident_solve_step(rs_ident_solver_t *s, rs_ident_out_t *out)
{
    rs_ident_result_t r = s->result;

    if (s->stage >= RS_IDENT_SOLVE_STAGES) {
        return true; /* over: nothing more */
    }
    if (s->stage == 0u) {
        zero_out(out, s->ri->cfg.R_nom_Ohm);
    }
    if (!s->ri->valid) {
        r = RS_IDENT_INVALID_CFG;
    }
    if (r == RS_IDENT_OK) { /* a refusal skips the stages left, not the calls */
        const uint16_t st = STAGES[s->stage];
        const int16_t j = (int16_t)(st & 1u);
        const rs_ident_win_t *wn = s->win[j];
        switch ((op_t)(st >> 1)) {
        case OP_FIT:
            s->fit.fit = ripple_fit(wn, s->fit.Gi);
            s->fit.fit6 = false;
            break;
        case OP_FIT6:
            s->fit.fit6 = s->fit.fit && ripple6_fit(wn, &s->fit);
            break;
        case OP_MEANS:
            r = solve_means(s, j, out);
            break;
        case OP_INTERCEPTS:
            solve_intercepts(s, j, out);
            break;
        case OP_POINTS:
            r = solve_points(s, out);
            break;
        case OP_SE_SUMS:
            residual_sums(wn, out->dR_Ohm, out->dpsi_Wb, s->se_sums);
            break;
        case OP_SE:
            solve_se(s, j, out);
            break;
        case OP_VERDICT:
        default:
            r = solve_verdict(&s->ri->cfg, out);
            break;
        }
    }
    s->result = r;
    s->stage++;
    return s->stage >= RS_IDENT_SOLVE_STAGES;
}

rs_ident_result_t rs_ident_solve(const rs_ident_t *ri, rs_ident_out_t *out)
{
    rs_ident_solver_t s;
    bool done = false;

    rs_ident_solve_begin(&s, ri, NULL);
    while (!done) {
        done = rs_ident_solve_step(&s, out);
    }
    return s.result;
}
