/*
 * smo.h - sliding-mode current and disturbance observer of the proposed
 * method (paper sec. V-A, eq. 28-32, discrete 51b and 55), on the exact
 * discrete model of the motor (zoh.h), with the corrections of the
 * design (smo_design.md, corrected_model_design.md; discrete_model_design.md).
 *
 * Model (replaces (25)-(28), (32), (43)-(55); derivations: the notes above
 * and step2_design.md; figures: build/sil/report.md and tests/test_smo.c,
 * test_param_est.c):
 *  - Signs: with d = x^ - x0 and the model L^ di/dt = u - R^ i +- w L^ i -
 *    w psi^ - f: fd = -dL did/dt - dR id + dL w iq, fq = -dL diq/dt - dR iq
 *    - dL w id - dpsi w, all opposite to (26)-(27) (root of the errors in
 *    (41)-(42), (50), (54)). The error obeys e(k+1) = rho e(k) - g_c (f^
 *    - f + U) and needs U = +Ks sat(e/phi), f^' = +mu U; (32)'s A11 e
 *    term is dropped.
 *  - One period, exact under zero-order hold (discrete_model_design.md):
 *      i^(k+1) = rho i^(k) + (Phi - rho) i(k) + g_u u(k) + g_c (-j w psi^ - f^ - U)
 *    the rotor's turn on the measured current (the paper's cross terms
 *    w Ts i(k) in (51b), (55) as their limit), the inverter's voltage
 *    through g_u, the rotor-frame ones through g_c (zoh.h).
 *  - psi_f: in (46)-(50) fq^ and w psi^ both integrate U, so only their sum
 *    is pinned: psi^ keeps up to half its error (b = 1/w^2), a fixed b is
 *    unstable at 2000 r/min. Transfer laws instead (param_est.h): gamma*Ts
 *    of fq^ (fd^) moves into psi^ (L^) per period with w psi^ + fq^
 *    (w L^ iq - fd^) kept, so the observer never sees it; the only
 *    equilibrium is f^ = 0 with U = 0, and the slow errors obey
 *    dDL/dt = -gL DL, dDpsi/dt = -gpsi (Dpsi + DL id) -> 0.
 *  - Boundary layer: sign() chattered 0.9 A/step and L^ diverged; inside
 *    the layer the observer is linear with G = Ks/phi. The gains come
 *    from the told R, L at Ts (smo_gains_design): a double pole at
 *    SMO_POLE_DEFAULT per period, Ks = SMO_KS_PER_EF ef_max (the discrete
 *    reaching condition's side towards the layer, whose limit Ts -> 0 is
 *    the paper's (36)), phi = Ks/G.
 *
 * Timing (k = sample just taken): smo_step() gets i(k), w(k) and the
 * clamped voltage u(k) applied over [k, k+1] (its rotor-frame value at
 * the period's middle angle), and gives i^(k+1).
 */
#ifndef SMO_H
#define SMO_H

#include <stdbool.h>
#include <stdint.h>

#include "clarke_park.h"
#include "mathx.h"
#include "zoh.h"

/* Design (discrete_model_design.md sec. 5), used by smo_gains_design(). */
#define SMO_POLE_DEFAULT        0.8f    /* the linear region's double pole per period: tau 4.5
                                         * periods, what r_track's blanking and est_gate's holds
                                         * count on; its first root 2 x 0.8 - 1 = 0.6 = rho - G g */
#define SMO_KS_PER_EF           2.0f    /* switching gain over the disturbance error, (36) with a 2x margin */
#define SMO_LR_MIN_PERIODS      2.0f    /* L/R below this x Ts: the motor's own decay e^(-Ts R/L)
                                         * below 0.61 < 0.6 + a feedback: no gain places the pole */
#define SMO_EF_MAX_DEFAULT_V    50.0f   /* |f^ - f| the observer must dominate, (36), at 311 V */
/* The decay over a period (zoh.h) follows L^ when it moved by more than
 * this share since it was taken: the transfer law moves L^ every second
 * period, and a model 1e-4 off changes the prediction by 1e-4 of w L iq
 * Ts/L (the L law then reads it within that). */
#define SMO_MODEL_UPDATE_REL    1.0e-4f
#define SMO_R_MIN_FACTOR        0.2f    /* accepted R^ range, x nominal */
#define SMO_R_MAX_FACTOR        2.0f
/* The bands of L^ and psi_f^, x the told value: written once, for the
 * observer and the transfer laws (param_est.c) alike. A told value within
 * a factor of about 3 of the motor's (the paper's and the campaigns' worst
 * are 2: psi_f 0.5x and 2x, L 0.66x and 1.5x); est_cfg_defaults raises
 * L^'s floor to the observer's own stability (smo_L_floor_H at R_min).
 * The deadbeat's stability (L^ < 2 L) is no band: it depends on the
 * motor's L, which a band from the told value cannot know; ctrl.h's
 * oscillation watch judges it (discrete_model_design.md sec. 7). */
#define SMO_LPSI_MIN_FACTOR     0.3f    /* [-] */
#define SMO_LPSI_MAX_FACTOR     3.0f    /* [-] */

typedef enum {
    SMO_CFG_OK = 0,
    SMO_CFG_INVALID = 1,      /* non-finite, non-positive or inconsistent field */
    SMO_CFG_UNSTABLE = 2,     /* the linear region's poles leave the unit circle at a corner of the
                               * R^, L^ ranges (Jury) */
    SMO_CFG_KS_TOO_SMALL = 3  /* the discrete reaching condition ((36)'s) fails at a corner */
} smo_status_t;

/* The observer's gains for a motor (smo_gains_design). */
typedef struct {
    float Ks_V;               /* switching gain [V] */
    float phi_A;              /* boundary layer [A]; G = Ks/phi [V/A] */
    float mu_1_s;             /* disturbance integrator gain [1/s] */
    float ef_max_V;           /* |f^ - f| the reaching condition dominates [V] */
} smo_gains_t;

typedef struct {
    float Ts_s;               /* sampling period [s] */
    float R_Ohm;              /* initial R^ (the controller's nominal) */
    float L_H;                /* initial L^ */
    float psi_f_Wb;           /* initial psi^ */
    float R_min_Ohm;          /* range the setters accept for R^ */
    float R_max_Ohm;
    float L_min_H;            /* range L^ is kept in; stability is checked at L_min_H, R_max_Ohm */
    float L_max_H;
    float psi_min_Wb;         /* range psi^ is kept in */
    float psi_max_Wb;
    float Ks_V;               /* switching gain Ks [V] */
    float phi_A;              /* boundary-layer half-width [A] */
    float mu_d_1_s;           /* disturbance integrator gains mu [1/s] */
    float mu_q_1_s;
    float ef_max_V;           /* configured bound on |f^ - f| in operation, for (36) */
    float f_max_V;            /* |f^| is kept below this [V] */
    float i_max_A;            /* bound on |i|, |i^| */
    float u_max_V;            /* bound on |u| */
    float omega_max_rad_s;    /* bound on |omega_el| */
} smo_cfg_t;

typedef struct {
    smo_cfg_t cfg;
    smo_status_t status;      /* from smo_init(); not OK: smo_step() passes i(k) through */
    bool seeded;              /* false until the first smo_step() after reset */
    float i_lo_A;             /* -cfg.i_max_A, -cfg.f_max_V, -cfg.omega_max_rad_s: the clamps' lower */
    float f_lo_V;             /* bounds, negated once (smo_init) */
    float omega_lo_rad_s;
    float G_V_per_A;          /* Ks/phi: gain inside the boundary layer */
    float inv_phi_1_A;        /* 1/phi */
    float mu_d_Ts;            /* mu*Ts [1] */
    float mu_q_Ts;
    float R_Ohm;              /* parameters in use: R^, L^, psi^ */
    float L_H;
    float psi_f_Wb;
    zoh_model_t zm;           /* the decay over a period at R^, L^ (zoh.h) */
    zoh_step_t z;             /* Phi, g_u, g_c of zm in the turn z_turn (zoh.h): taken again when the
                               * turn or zm changed (g_c: the model's too while it follows the observer,
                               * dbdtc_period_from) */
    bool zm_stale;            /* L^ moved by more than SMO_MODEL_UPDATE_REL since zm: taken at the next step */
    uint32_t z_turn;          /* the turn's number (zoh_turn_t.seq) z was taken in; 0: zm changed since */
    uint32_t z_rev;           /* z's own number: one more each time it is taken */
    float z_rc;               /* Phi - rho = z_rc - j z_rs, taken with z: rho (cos theta - 1) = -2 rho sin^2(theta/2) */
    float z_rs;               /* ... and rho sin theta [-] */
    dq_t i_hat_A;             /* prediction i^(k+1) made by the last step */
    float fd_V;               /* disturbance estimates f^ [V] */
    float fq_V;
    dq_t U_V;                 /* switching term of the last step [V] (monitor) */
} smo_t;

/* The gains for the told R_Ohm, L_H [Ohm, H] at Ts_s [s] and the
 * disturbance error ef_max_V [V] to dominate (discrete_model_design.md
 * sec. 5): G g = rho - (2 z - 1), mu Ts G g = (1 - z)^2 (a double pole at
 * z = SMO_POLE_DEFAULT, g = (1 - rho)/R), Ks = SMO_KS_PER_EF ef_max,
 * phi = Ks/G. False (g filled for the diagnosis) when L/R is
 * below SMO_LR_MIN_PERIODS x Ts or a value is not finite and positive.
 * Background. */
bool smo_gains_design(float Ts_s, float R_Ohm, float L_H, float ef_max_V, smo_gains_t *g);

/* The lowest L^ [H] at which the reaching condition still holds for
 * R^ = R_Ohm with the gains *g (discrete_model_design.md sec. 5): phi
 * (1 + rho^) > g^ (ef_max + Ks), i.e. L^ > Ts R^ / ln((c + R^)/(c - R^)),
 * c = G + ef_max/phi (the logarithm's series: the floor at or above it);
 * 0 where c <= R^ (it holds at any L^). Background. */
float smo_L_floor_H(float Ts_s, float R_Ohm, const smo_gains_t *g);

/* Design defaults for nominal R_Ohm, L_H, psi_f_Wb [Ohm, H, Wb] and
 * period Ts_s [s] with the gains *g; the caller then sets the bounds
 * i_max_A, u_max_V, omega_max_rad_s and f_max_V (defaults 0: init
 * refuses them). Background. */
void smo_cfg_defaults(smo_cfg_t *cfg, float Ts_s, float R_Ohm, float L_H, float psi_f_Wb, const smo_gains_t *g);

/* Copies cfg, checks it (finite, positive, ranges ordered and holding the
 * initial values; at the four corners of the R^, L^ ranges the linear
 * region stable (Jury) and the discrete reaching condition Ks + R^ phi >
 * ef_max, phi (1 + rho^) > g^ (ef_max + Ks)) and resets. Anything but
 * SMO_CFG_OK is a fault for the caller. Background. */
smo_status_t smo_init(smo_t *smo, const smo_cfg_t *cfg);

/* Initial parameters, f^ = 0; the next smo_step() seeds i^ with i(k).
 * Background, or ISR before the observer is enabled. */
void smo_reset(smo_t *smo);

/* The period's Phi, g_u, g_c (and Phi - rho) in the turn *turn: taken
 * again when the turn or the decay changed (the decay first when L^
 * moved: smo_set_L_deferred). ISR (the periods whose turn or decay moved). */
void smo_take_period(smo_t *smo, const zoh_turn_t *turn);

/* Boundary-layer switching term Ks sat(e/phi) [V] (replaces sign() of (32)). */
static inline float smo_switching(const smo_t *smo, float e_A)
{
    return smo->cfg.Ks_V * mathx_clampf(e_A * smo->inv_phi_1_A, -1.0f, 1.0f);
}

/* One period: i_A = measured i(k) [A], u_V = the voltage applied over
 * [k, k+1] after the hexagon clamp [V], omega_el_rad_s = w(k) within
 * +-omega_max [rad/s el] (the back-EMF's), *turn the rotor's turn over it
 * (zoh_turn at w(k), or within ZOH_THETA_TOL_RAD of it). Returns and stores i^(k+1) [A]
 * (eq. 51b, 55 as corrected in this header). 1 division when the turn or
 * the decay changed since the last step, else none. ISR (inline: once a
 * period; the period's model a call when it moved). */
static inline dq_t smo_step_turn(smo_t *smo, dq_t i_A, dq_t u_V, float omega_el_rad_s, const zoh_turn_t *turn)
{
    const smo_cfg_t *c = &smo->cfg;
    dq_t i;
    dq_t u;
    dq_t v;
    dq_t next;

    i.d = mathx_clampf(i_A.d, smo->i_lo_A, c->i_max_A);
    i.q = mathx_clampf(i_A.q, smo->i_lo_A, c->i_max_A);
    /* u as applied: the inverter bounds it (a non-finite u is the caller's
     * NONFINITE fault; smo_reset at the next start clears what it left) */
    u = u_V;
    if (smo->status != SMO_CFG_OK) {
        smo->i_hat_A = i;
        return smo->i_hat_A;
    }
    if (!smo->seeded) {
        /* i^(k) = i(k) at enable: no error, no switching kick. */
        smo->i_hat_A = i;
        smo->seeded = true;
    }

    /* (30): e = i^ - i, with i^(k) the previous prediction */
    const float Ud = smo_switching(smo, smo->i_hat_A.d - i.d);
    const float Uq = smo_switching(smo, smo->i_hat_A.q - i.q);
    if (smo->zm_stale || (turn->seq != smo->z_turn)) {
        smo_take_period(smo, turn); /* the turn or the decay moved: 1 division (3 with the decay) */
    }
    const float rho = smo->zm.rho;
    const zoh_step_t *z = &smo->z;

    /* (51b), (55) exact: the rotor's turn on the measured current (the
     * paper's cross terms w Ts i(k)), rho on the observer's own; U with +
     * sign from the error dynamics; -w psi^ with the psi^ in use */
    v.d = -smo->fd_V - Ud;
    v.q = -omega_el_rad_s * smo->psi_f_Wb - smo->fq_V - Uq; /* w(k) itself: a kept turn's w is up to
                                                               * ZOH_THETA_TOL_RAD/Ts off, w psi by that x psi */
    const dq_t gu = zoh_mul(z->g_u, u);
    const dq_t gv = zoh_mul(z->g_c, v);
    const float rc = smo->z_rc;
    const float rs = smo->z_rs;
    next.d = rho * smo->i_hat_A.d + rc * i.d + rs * i.q + gu.d + gv.d;
    next.q = rho * smo->i_hat_A.q + rc * i.q - rs * i.d + gu.q + gv.q;
    /* (51b), (55): f^ += mu Ts U, the sign that makes (37) converge */
    smo->fd_V = mathx_clampf(smo->fd_V + smo->mu_d_Ts * Ud, smo->f_lo_V, c->f_max_V);
    smo->fq_V = mathx_clampf(smo->fq_V + smo->mu_q_Ts * Uq, smo->f_lo_V, c->f_max_V);

    smo->i_hat_A.d = mathx_clampf(next.d, smo->i_lo_A, c->i_max_A);
    smo->i_hat_A.q = mathx_clampf(next.q, smo->i_lo_A, c->i_max_A);
    smo->U_V.d = Ud;
    smo->U_V.q = Uq;
    return smo->i_hat_A;
}

/* As smo_step_turn at omega_el_rad_s = w(k) [rad/s el] (the turn taken
 * here). Background: off the ISR's path (smo_cfg.c, flash on the target). */
dq_t smo_step(smo_t *smo, dq_t i_A, float omega_el_rad_s, dq_t u_V);

/* Sets R^ [Ohm] bumplessly: f^ += (R^old - R^new) i^ keeps -R^ i^ - f^;
 * the next prediction moves only through the decay (zero in steady
 * state). Returns false (nothing changed) when R_Ohm is non-finite or
 * outside [R_min, R_max]. Background or ISR (2 divisions). */
bool smo_set_R(smo_t *smo, float R_Ohm);

/* Sets L^ [H], limited to [L_min, L_max], keeping w L^ iq - fd^ at the
 * given omega_el_rad_s and iq_A (the transfer law's invariant); the decay
 * follows when L^ moved by more than SMO_MODEL_UPDATE_REL since it was
 * taken (2 divisions then). Returns the L^ now in use. ISR. */
float smo_set_L(smo_t *smo, float L_H, float omega_el_rad_s, float iq_A);

/* As smo_set_L with the decay taken at the next step (2 divisions there):
 * for the gate's restore at a transient's onset, the ISR's busiest period
 * (the laws paused, the model held: a period's stale decay is harmless). */
float smo_set_L_deferred(smo_t *smo, float L_H, float omega_el_rad_s, float iq_A);

/* Sets psi^ [Wb], limited to [psi_min, psi_max], keeping w psi^ + fq^ at
 * the given omega_el_rad_s; returns the psi^ now in use. ISR. */
float smo_set_psi(smo_t *smo, float psi_f_Wb, float omega_el_rad_s);

/* The decay at R^, L^ (zoh.h; 2 divisions): what smo_set_L does when L^
 * moved by more than SMO_MODEL_UPDATE_REL. ISR or background. */
void smo_update_model(smo_t *smo);

/* smo_set_L_deferred's move for a caller that keeps its checks: the
 * observer accepted (status OK), omega_el_rad_s within +-omega_max, iq_A
 * within +-i_max, L_H within [L_min, L_max] (param_est's clamps are
 * inside them: param_est_init). The same floats, without the checks.
 * ISR (inline: the L law's every second period). */
static inline void smo_take_L_deferred(smo_t *smo, float L_H, float omega_el_rad_s, float iq_A)
{
    /* step2_design.md sec. 1: w L^ iq - fd^ unchanged */
    smo->fd_V = mathx_clampf(smo->fd_V + (L_H - smo->L_H) * omega_el_rad_s * iq_A, smo->f_lo_V, smo->cfg.f_max_V);
    smo->L_H = L_H;
    if (mathx_fabsf(L_H - smo->zm.L_H) > SMO_MODEL_UPDATE_REL * smo->zm.L_H) {
        smo->zm_stale = true; /* the decay at the L^ in use at the next step (2 divisions there) */
    }
}

/* smo_update_model for an accepted observer whose R^, L^ are within the
 * ranges smo_init checked (smo_take_L_deferred's conditions): the decay
 * without zoh_model's check, which cannot fail there. ISR. */
void smo_take_model(smo_t *smo);

/* As smo_set_L under smo_take_L_deferred's conditions. ISR (inline). */
static inline void smo_take_L(smo_t *smo, float L_H, float omega_el_rad_s, float iq_A)
{
    smo_take_L_deferred(smo, L_H, omega_el_rad_s, iq_A);
    if (smo->zm_stale) {
        smo_take_model(smo); /* the decay at the L^ in use; 2 divisions */
    }
}

/* smo_set_psi's move for a caller that keeps its checks: the observer
 * accepted, omega_el_rad_s within +-omega_max, psi_f_Wb within [psi_min,
 * psi_max] (param_est_init). The same floats. ISR (inline). */
static inline void smo_take_psi(smo_t *smo, float psi_f_Wb, float omega_el_rad_s)
{
    /* step2_design.md sec. 2: w psi^ + fq^ unchanged */
    smo->fq_V = mathx_clampf(smo->fq_V - (psi_f_Wb - smo->psi_f_Wb) * omega_el_rad_s, smo->f_lo_V, smo->cfg.f_max_V);
    smo->psi_f_Wb = psi_f_Wb;
}

/* A voltage the model now compensates: f^ gives up (dfd_V, dfq_V) [V] it
 * no longer has to explain (the inverter error identified,
 * inverter_error_design.md sec. 5); the caller's compensation moves u by the same, so the prediction
 * does not move (bumpless). ISR. */
void smo_shift_f(smo_t *smo, float dfd_V, float dfq_V);

#endif /* SMO_H */
