/*
 * rs_ident.h - step 1 of the proposed method: offline stator resistance
 * from the observer's disturbances at two steady operating points
 * (paper sec. V-B, eq. 39-42, corrected per observer_design.md sec. 1c).
 *
 * Steady state with the corrected signs (d = x^ - x0, x^ = the observer's):
 *   fd_j = dL w_j iq_j - dR id_j,   fq_j = -dR iq_j - dL w_j id_j - dpsi w_j
 * Four fixed iterations from dL = 0:
 *   g_j  = fq_j + dL w_j id_j
 *   dR   = -(w1 g2 - w2 g1)/(iq2 w1 - iq1 w2)      (41) with the sign of (27) fixed
 *   dpsi = -(g_j + dR iq_j)/w_j                   (at the faster point)
 *   dL   = mean_j (fd_j + dR id_j)/(w_j iq_j)     (points with |w iq| large enough)
 *   R^   = R - dR                                  (42) with the opposite sign
 * The literal (42) would give 2R - R0. The d-axis correction matters only
 * when id != 0 (L or psi_f also wrong); dpsi w cancels exactly, so the two
 * points may differ in speed, in load, or both.
 *
 * Use: during the averaging windows the caller passes, each period after
 * smo_step(), the observer's fd^, fq^ and the measured id, iq, omega with
 * the window that is active; then rs_ident_solve() once, and on
 * RS_IDENT_OK smo_set_R(R_est_Ohm) (bumpless) and param_est_run().
 */
#ifndef RS_IDENT_H
#define RS_IDENT_H

#include <stdbool.h>
#include <stdint.h>

/* Design defaults (observer_design.md sec. 3). */
#define RS_IDENT_IQ_STD_MAX_DEFAULT_A  0.05f /* steady window */
#define RS_IDENT_DEN_RATIO_DEFAULT     0.3f  /* |den| >= ratio * max(|iq2 w1|, |iq1 w2|) */
#define RS_IDENT_BAND_MIN_FACTOR       0.2f  /* plausible R^, x nominal */
#define RS_IDENT_BAND_MAX_FACTOR       2.0f  /* = SMO_R_MAX_FACTOR: smo_set_R takes any accepted R^ */
#define RS_IDENT_N_MIN_DEFAULT         100u  /* samples per window (10 ms at 10 kHz) */

typedef enum { RS_IDENT_WINDOW_NONE = 0, RS_IDENT_WINDOW_1 = 1, RS_IDENT_WINDOW_2 = 2 } rs_ident_window_t;

typedef enum {
    RS_IDENT_OK = 0,
    RS_IDENT_INVALID_CFG = 1,   /* init refused the configuration */
    RS_IDENT_TOO_FEW = 2,       /* a window has fewer than n_min samples */
    RS_IDENT_NOT_STEADY = 3,    /* std of iq in a window above iq_std_max_A */
    RS_IDENT_DEGENERATE = 4,    /* operating points too alike: denominator of (41) too small */
    RS_IDENT_NON_FINITE = 5,    /* NaN/Inf in the data or the result */
    RS_IDENT_OUT_OF_BAND = 6    /* R^ outside [R_min, R_max] */
} rs_ident_result_t;

typedef struct {
    float R_nom_Ohm;          /* R^ the observer used during step 1 [Ohm] */
    float R_min_Ohm;          /* plausible band for the result */
    float R_max_Ohm;
    float iq_std_max_A;       /* steadiness: std of iq per window [A] */
    float den_ratio_min;      /* conditioning of (41) [1] */
    uint32_t n_min;           /* minimum samples per window */
} rs_ident_cfg_t;

/* Channels averaged per window. */
typedef enum { RS_CH_FD = 0, RS_CH_FQ, RS_CH_ID, RS_CH_IQ, RS_CH_W, RS_CH_COUNT } rs_ident_ch_t;

typedef struct {              /* sums relative to the first sample: no cancellation */
    uint32_t n;
    float x0[RS_CH_COUNT];    /* first sample */
    float s1[RS_CH_COUNT];    /* sum of (x - x0) */
    float s2_iq;              /* sum of (iq - iq0)^2 */
} rs_ident_win_t;

typedef struct {
    rs_ident_cfg_t cfg;
    bool valid;
    rs_ident_win_t win[2];
} rs_ident_t;

typedef struct {
    float R_est_Ohm;          /* R^ = R_nom - dR */
    float dR_Ohm;             /* by-products, d = model - true: */
    float dL_H;               /*   warm start for L^ = L - dL */
    float dpsi_Wb;            /*   and psi^ = psi - dpsi (optional) */
    float iq_std_A[2];        /* measured std of iq per window */
    float mean_fd_V[2];       /* window means used */
    float mean_fq_V[2];
    float mean_id_A[2];
    float mean_iq_A[2];
    float mean_w_rad_s[2];
} rs_ident_out_t;

/* Design defaults for the nominal R_nom_Ohm [Ohm]. Background. */
void rs_ident_cfg_defaults(rs_ident_cfg_t *cfg, float R_nom_Ohm);

/* Copies cfg (finite, R_nom > 0, 0 <= R_min <= R_nom <= R_max, std > 0,
 * 0 < ratio < 1, n_min >= 2) and empties both windows. Background. */
bool rs_ident_init(rs_ident_t *ri, const rs_ident_cfg_t *cfg);

/* Empties both windows. Background or ISR. */
void rs_ident_reset(rs_ident_t *ri);

/* One period, after smo_step(): the observer's fd_V, fq_V [V] and the
 * measured id_A, iq_A [A], omega_el_rad_s [rad/s] into window win
 * (RS_IDENT_WINDOW_NONE: ignored). No division. ISR. */
void rs_ident_step(rs_ident_t *ri, rs_ident_window_t win, float fd_V, float fq_V, float id_A,
                   float iq_A, float omega_el_rad_s);

/* Checks the windows and solves (design sec. 1c); *out is filled as far as
 * the checks got (R_est_Ohm = R_nom unless OK). Background, or ISR once
 * (about 20 divisions, 1 square root per window). */
rs_ident_result_t rs_ident_solve(const rs_ident_t *ri, rs_ident_out_t *out);

#endif /* RS_IDENT_H */
