/*
 * rs_ident.h - step 1 of the proposed method: offline stator resistance
 * from the observer's disturbances at two steady operating points
 * (paper sec. V-B, eq. 39-42, corrected per step1_design.md sec. 1).
 *
 * Steady state with the corrected signs (d = x^ - x0, x^ = the observer's):
 *   fd_j = dL w_j iq_j - dR id_j,   fq_j = -dR iq_j - dL w_j id_j - dpsi w_j
 * Four fixed iterations from dL = 0:
 *   g_j  = fq_j + dL w_j id_j  (+ dL <diq/dt>_j, step1_design.md sec. 5)
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
 * the window that is active; then rs_ident_solve(), and on RS_IDENT_OK
 * smo_set_R(R_est_Ohm) (bumpless) and param_est_run().
 *
 * Steadiness from the windows' own statistics (step1_design.md sec. 3):
 * each window is also cut into batches of n_batch samples; the spread of
 * the batch means of (fq, iq, w) gives the standard error of the model's
 * residual r_j = fq_j + dR iq_j + dpsi w_j in each window (batch means:
 * the samples are correlated over the observer's and the speed loop's
 * time constants), and (41) carries it into the standard error of R^:
 *   se(R^)^2 = (w1^2 se(r2)^2 + w2^2 se(r1)^2) / den^2.
 * A ripple at the electrical frequency (ADC offsets) is no noise: with
 * the angle given (rs_ident_step_el), the batch means are fitted as
 * alpha + a C_i + b S_i (C_i, S_i the batch means of cos, sin theta_el)
 * and the intercept alpha - the mean over whole turns - and its standard
 * error are used (step1_design.md sec. 4); where the fit is ill-conditioned
 * (batches of whole turns, standstill, no angle) the plain means. The
 * fit also takes the 6th harmonic (C6_i, S6_i: batch means of cos, sin
 * 6 theta_el), the ripple an untold inverter error (dead time) leaves in
 * fq^, where it is conditioned and there are RS_IDENT_RIPPLE6_BATCHES_MIN
 * batches.
 * A window that is still settling carries -dL <diq/dt> in fq^: with Ts_s
 * set, each window's mean slope of iq (least squares on its batch means)
 * and the estimated dL take it out (step1_design.md sec. 5).
 * R^ is refused (NOT_STEADY) when se(R^) > R_se_max_rel |R^|; the caller
 * may go on filling window 2 and solve again (rs_ident_solve() does not
 * change the windows): out.R_se_part_Ohm[0] says whether window 2 alone
 * can still bring se(R^) under the limit.
 */
#ifndef RS_IDENT_H
#define RS_IDENT_H

#include <stdbool.h>
#include <stdint.h>

/* Design defaults (step1_design.md sec. 1, 3, 4, 8). */
#define RS_IDENT_R_SE_MAX_REL_DEFAULT  0.015f /* se(R^) / R^: psi_f^ within 0.5 % at 500 r/min per se (step1_design.md sec. 3) */
#define RS_IDENT_DEN_RATIO_DEFAULT     0.3f  /* |den| >= ratio * max(|iq2 w1|, |iq1 w2|) */
#define RS_IDENT_BAND_MIN_FACTOR       0.1f  /* plausible R^, x nominal: a controller R up to 5x */
#define RS_IDENT_BAND_MAX_FACTOR       6.0f  /*   or down to 0.25x the motor's stays 2x / 1.5x inside */
#define RS_IDENT_N_MIN_DEFAULT         100u  /* samples per window (10 ms at 10 kHz) */
#define RS_IDENT_N_BATCH_DEFAULT       50u   /* samples per batch (5 ms: 5x the observer's time constant) */
#define RS_IDENT_BATCHES_MIN           4u    /* batches per window for a spread at all */
#define RS_IDENT_RIPPLE_BATCHES_MIN    6u    /* and for the fit of the electrical-frequency ripple */
#define RS_IDENT_RIPPLE_DET_MIN        0.01f /* det(Z'Z / nb) below which the fit is not used */
#define RS_IDENT_RIPPLE6_BATCHES_MIN   8u    /* batches for the fit with the 6th harmonic too (3 dof left) */

typedef enum { RS_IDENT_WINDOW_NONE = 0, RS_IDENT_WINDOW_1 = 1, RS_IDENT_WINDOW_2 = 2 } rs_ident_window_t;

typedef enum {
    RS_IDENT_OK = 0,
    RS_IDENT_INVALID_CFG = 1,   /* init refused the configuration */
    RS_IDENT_TOO_FEW = 2,       /* a window has fewer than n_min samples or RS_IDENT_BATCHES_MIN batches */
    RS_IDENT_NOT_STEADY = 3,    /* standard error of R^ above R_se_max_rel |R^| (noise, transient) */
    RS_IDENT_DEGENERATE = 4,    /* operating points too alike: denominator of (41) too small */
    RS_IDENT_NON_FINITE = 5,    /* NaN/Inf in the data or the result */
    RS_IDENT_OUT_OF_BAND = 6,   /* R^ outside [R_min, R_max] */
    RS_IDENT_D_AXIS = 7,        /* R^ hangs on the d-axis term dL w id (field weakening, voltage limit) more
                                 * than se(R^)'s limit allows (est.c, step1_design.md sec. 6) */
    RS_IDENT_INVERTER = 8       /* what the inverter's compensation may leave could move R^ by more than
                                 * a share of it (est.c, step1_design.md sec. 9) */
} rs_ident_result_t;

typedef struct {
    float R_nom_Ohm;          /* R^ the observer used during step 1 [Ohm] */
    float R_min_Ohm;          /* plausible band for the result */
    float R_max_Ohm;
    float R_se_max_rel;       /* steadiness: largest standard error of R^, x |R^| [1] */
    float den_ratio_min;      /* conditioning of (41) [1] */
    uint32_t n_min;           /* minimum samples per window */
    uint32_t n_batch;         /* samples per batch of the standard error */
    float Ts_s;               /* sample period [s] for the windows' mean diq/dt; 0: not corrected (step1_design.md sec. 5) */
} rs_ident_cfg_t;

/* Channels averaged per window. */
typedef enum { RS_CH_FD = 0, RS_CH_FQ, RS_CH_ID, RS_CH_IQ, RS_CH_W, RS_CH_COUNT } rs_ident_ch_t;

/* Channels of the batch statistics, and their pairs (upper triangle). */
typedef enum { RS_ST_FQ = 0, RS_ST_IQ, RS_ST_W, RS_ST_COUNT } rs_ident_st_t;
#define RS_ST_PAIRS 6

typedef struct {              /* a window's sample sums, relative to the first sample: no cancellation */
    uint32_t n;
    float x0[RS_CH_COUNT];    /* first sample */
    float s1[RS_CH_COUNT];    /* sum of (x - x0) */
    float s2_iq;              /* sum of (iq - iq0)^2 */
} rs_ident_head_t;

typedef struct {
    rs_ident_head_t h;        /* the sample sums: they change every sample */
    uint32_t bn;              /* samples in the batch being filled */
    float bsum[RS_ST_COUNT];  /* its sums of (x - x0) */
    uint32_t nb;              /* complete batches */
    float m1[RS_ST_COUNT];    /* sum of batch means (relative to x0) */
    float m2[RS_ST_PAIRS];    /* sums of their products: ff, fi, fw, ii, iw, ww */
    float bcs[2];             /* batch being filled: sums of cos, sin theta_el */
    float g[5];               /* over batches: sum of C, S, C C, C S, S S (batch means of cos, sin) */
    float mcs[RS_ST_COUNT][2];   /* sum of m_a C and of m_a S */
    float bcs6[2];            /* batch being filled: sums of cos, sin 6 theta_el (step1_design.md sec. 4) */
    float g6[9];              /* over batches: sum of C6, S6, C6 C6, C6 S6, S6 S6, C C6, C S6, S C6, S S6 */
    float mcs6[RS_ST_COUNT][2];  /* sum of m_a C6 and of m_a S6 */
    float km_iq;              /* sum of k m_iq(k), k = 0, 1, ...: the slope of iq's batch means */
} rs_ident_win_t;

typedef struct {
    rs_ident_cfg_t cfg;
    bool valid;
    float inv_n_batch;        /* 1 / n_batch */
    rs_ident_win_t win[2];
} rs_ident_t;

typedef struct {
    float R_est_Ohm;          /* R^ = R_nom - dR when accepted, else R_nom */
    float R_raw_Ohm;          /* R_nom - dR as solved, accepted or not (0 until the solve got that far) */
    float dR_Ohm;             /* by-products, d = model - true: */
    float dL_H;               /*   warm start for L^ = L - dL */
    float dpsi_Wb;            /*   and psi^ = psi - dpsi (optional) */
    float R_se_Ohm;           /* standard error of R^ (0 until the solve got that far) */
    float R_se_max_Ohm;       /*   and the limit it was held to */
    float R_se_part_Ohm[2];   /* window j's share: |w_other| se(r_j) / |den| */
    float angle_el_rad;       /* angle error the windows' dL_j suggest: (dL1 - dL2) / (psi_f (1/iq2 - 1/iq1))
                               * [rad el] (est.c; 0 unless both |w iq| and the iq differ enough) */
    float R_d_axis_Ohm;       /* R^'s d-axis uncertainty |w1 w2 (id2 - id1) (dL1 - dL2) / den| where the d-axis
                               * correction exceeds se(R^)'s limit (est.c; else 0) */
    float R_inverter_Ohm;     /* the R^ error the inverter's compensation may cause (est.c; 0 until checked) */
    float R_inverter_max_Ohm; /*   and the limit it was held to */
    float r_se_V[2];          /* standard error of the residual's mean per window */
    bool ripple_fit[2];       /* the means are the ripple fit's intercepts (step1_design.md sec. 4) */
    bool ripple6_fit[2];      /*   and the fit has the 6th harmonic (an untold inverter error) too */
    float diq_dt_A_s[2];      /* mean diq/dt per window (0 without Ts_s) [A/s] */
    uint32_t batches[2];      /* complete batches per window */
    float iq_std_A[2];        /* measured std of iq per window (monitor) */
    float mean_fd_V[2];       /* window means used */
    float mean_fq_V[2];
    float mean_id_A[2];
    float mean_iq_A[2];
    float mean_w_rad_s[2];
} rs_ident_out_t;

/* Design defaults for the nominal R_nom_Ohm [Ohm]. Background. */
void rs_ident_cfg_defaults(rs_ident_cfg_t *cfg, float R_nom_Ohm);

/* Copies cfg (finite, R_nom > 0, 0 <= R_min <= R_nom <= R_max,
 * R_se_max_rel > 0, 0 < ratio < 1, n_min >= 2, n_batch >
 * RS_IDENT_SOLVE_STAGES) and empties
 * both windows. Background. */
bool rs_ident_init(rs_ident_t *ri, const rs_ident_cfg_t *cfg);

/* Empties both windows. Background or ISR. */
void rs_ident_reset(rs_ident_t *ri);

/* Window win's sample sums of *src into *dst, field by field (no library
 * memcpy): for a staged solve while the window goes on filling (its batch
 * sums hold still for n_batch - 1 samples after a batch closed). ISR. */
void rs_ident_copy_head(rs_ident_head_t *dst, const rs_ident_t *src, rs_ident_window_t win);

/* true when window win has no incomplete batch (none begun, or one just
 * closed): a staged solve of it may begin. ISR. */
bool rs_ident_batch_closed(const rs_ident_t *ri, rs_ident_window_t win);

/* One period, after smo_step(): the observer's fd_V, fq_V [V] and the
 * measured id_A, iq_A [A], omega_el_rad_s [rad/s] into window win
 * (RS_IDENT_WINDOW_NONE: ignored). No division. Host (the target's ISR
 * calls rs_ident_step_el; this one runs from flash there). */
void rs_ident_step(rs_ident_t *ri, rs_ident_window_t win, float fd_V, float fq_V, float id_A,
                   float iq_A, float omega_el_rad_s);

/* As rs_ident_step, with the electrical angle's cos_el, sin_el for the
 * ripple fit (step1_design.md sec. 4). ISR. */
void rs_ident_step_el(rs_ident_t *ri, rs_ident_window_t win, float fd_V, float fq_V, float id_A, float iq_A,
                      float omega_el_rad_s, float cos_el, float sin_el);

/* Checks the windows and solves (step1_design.md sec. 1, 3); *out is filled as far
 * as the checks got (R_est_Ohm = R_nom unless OK); the windows are left as
 * they are. Background (about 25 divisions, 4 square roots: the ISR uses
 * the stages below; this one runs from flash on the target). */
rs_ident_result_t rs_ident_solve(const rs_ident_t *ri, rs_ident_out_t *out);

/* rs_ident_solve in RS_IDENT_SOLVE_STAGES bounded stages, one per call
 * (per window: its ripple fit, the fit's 6th harmonic, its means, the
 * fit's intercepts; the points' solve; per window: the ripple fit again
 * where it is not kept, the residual's sums, its standard error; the
 * verdict): the same result and *out, always after exactly that many
 * calls (a refusal skips the work left, not the calls). The windows'
 * points pass from stage to stage in *out: the same *out each call. The
 * windows solved must not change until the last stage: an ISR that goes
 * on filling window 2 begins at a batch boundary (rs_ident_batch_closed)
 * with a copy of its sample sums (rs_ident_copy_head); its batch sums
 * hold still while the stages run (n_batch > RS_IDENT_SOLVE_STAGES,
 * rs_ident_init). */
#define RS_IDENT_SOLVE_STAGES 16u

typedef struct {              /* a window's ripple fit (step1_design.md sec. 4), kept between the stages that use it */
    bool fit;                 /* the fit of (1, C, S) holds */
    bool fit6;                /*   and its 6th harmonic */
    float Gi[3][3];           /* G^-1, G = Z'Z */
    float P[3][2];            /* Gi B (B: the 6th harmonic's cross sums with 1, C, S); u = its row 0 */
    float Si6[3];             /* inverse of the Schur complement D - B' P: 00, 01, 11 */
} rs_ident_ripple_t;

typedef struct {
    const rs_ident_t *ri;     /* the configuration */
    const rs_ident_win_t *win[2];    /* the windows solved (their batch sums) */
    const rs_ident_head_t *head[2];  /* their sample sums: ri's, or a copy of window 2's */
    uint16_t stage;           /* the next stage */
    rs_ident_result_t result; /* valid once rs_ident_solve_step returned true */
    float abs_inv_den;        /* 1 / |(41)'s denominator| [1/(A rad/s)] */
    rs_ident_ripple_t fit;    /* the ripple fit of the window being solved */
    float se_sums[6];         /* the residual's sums between its two stages: r'r, Z'r, Z6'r */
} rs_ident_solver_t;

/* Starts a staged solve of *ri's windows, window 2's sample sums from
 * *head_2 instead when not NULL (a copy). No division. ISR. */
void rs_ident_solve_begin(rs_ident_solver_t *s, const rs_ident_t *ri, const rs_ident_head_t *head_2);

/* One stage into *out (the first sets *out to its empty values, R_est_Ohm
 * = R_nom); true when the solve is over (s->result, *out as rs_ident_solve
 * leaves them; further calls do nothing). At most 2 divisions and 1
 * square root. ISR. */
bool rs_ident_solve_step(rs_ident_solver_t *s, rs_ident_out_t *out);

#endif /* RS_IDENT_H */
