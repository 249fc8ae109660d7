/*
 * smo.h - sliding-mode current and disturbance observer of the proposed
 * method (paper sec. V-A, eq. 28-32, discrete 51b and 55), with the
 * corrections of the design (smo_design.md, corrected_model_design.md).
 *
 * Design note (replaces (25)-(28), (32), (43)-(55); derivations:
 * corrected_model_design.md, smo_design.md, step2_design.md; figures:
 * build/sil/report.md and tests/test_smo.c, test_param_est.c).
 *  - Signs: with d = x^ - x0 and the model L^ di/dt = u - R^ i +- w L^ i -
 *    w psi^ - f: fd = -dL did/dt - dR id + dL w iq, fq = -dL diq/dt - dR iq
 *    - dL w id - dpsi w, all opposite to (26)-(27) (root of the errors in
 *    (41)-(42), (50), (54)). L^ de/dt = -R^ e - (f^ - f) - U needs
 *    U = +Ks sat(e/phi), f^' = +mu U; (32)'s A11 e term is dropped.
 *  - psi_f: in (46)-(50) fq^ and w psi^ both integrate U, so only their sum
 *    is pinned: psi^ keeps up to half its error (b = 1/w^2), a fixed b is
 *    unstable at 2000 r/min. Transfer laws instead (param_est.h): gamma*Ts
 *    of fq^ (fd^) moves into psi^ (L^) per period with w psi^ + fq^
 *    (w L^ iq - fd^) kept, so the observer never sees it; the only
 *    equilibrium is f^ = 0 with U = 0, and the slow errors obey
 *    dDL/dt = -gL DL, dDpsi/dt = -gpsi (Dpsi + DL id) -> 0. 1/w, 1/(w iq)
 *    are the speed schedule: 2 % in 22 ms (L) and 66 ms (psi) at 200, 500
 *    and 2000 r/min alike.
 *  - Boundary layer Ks/phi = 100 V / 2.5 A: sign() chattered 0.9 A/step and
 *    L^ diverged (Ks = 20 V: 0.1 N m rms, L^ off 1.5 %); inside the layer a
 *    linear observer, double pole ~0.80, 3.5x below the stability limit.
 *  - g = (Ts/L^)(1 - Ts R^/(2 L^)) (ZOH 2nd-order term) replaces Ts/L of
 *    (51b), (55): removes a 0.6 % tail after torque steps.
 *
 * Timing (k = sample just taken): smo_step() gets i(k), w(k) and the
 * clamped voltage u(k) applied over [k, k+1], and gives i^(k+1).
 */
#ifndef SMO_H
#define SMO_H

#include <stdbool.h>
#include <stdint.h>

#include "clarke_park.h"

/* Design defaults (smo_design.md sec. 3), filled in by smo_cfg_defaults(). */
#define SMO_KS_DEFAULT_V        100.0f  /* switching gain */
#define SMO_PHI_DEFAULT_A       2.5f    /* boundary layer: G = 40 V/A */
#define SMO_MU_DEFAULT_1_S      1100.0f /* near critical damping of the linear region */
#define SMO_EF_MAX_DEFAULT_V    50.0f   /* |f^ - f| the observer must dominate, (36) */
#define SMO_R_MIN_FACTOR        0.2f    /* accepted R^ range, x nominal */
#define SMO_R_MAX_FACTOR        2.0f
#define SMO_LPSI_MIN_FACTOR     0.3f    /* accepted L^, psi^ range, x nominal */
#define SMO_LPSI_MAX_FACTOR     3.0f

typedef enum {
    SMO_CFG_OK = 0,
    SMO_CFG_INVALID = 1,      /* non-finite, non-positive or inconsistent field */
    SMO_CFG_UNSTABLE = 2,     /* Ks/phi >= 2 L_min/Ts - R_max, or mu*Ts >= 1 */
    SMO_CFG_KS_TOO_SMALL = 3  /* (36): Ks <= ef_max + R_max*phi */
} smo_status_t;

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
    float G_V_per_A;          /* Ks/phi: gain inside the boundary layer */
    float inv_phi_1_A;        /* 1/phi */
    float mu_d_Ts;            /* mu*Ts [1] */
    float mu_q_Ts;
    float R_Ohm;              /* parameters in use: R^, L^, psi^ */
    float L_H;
    float psi_f_Wb;
    float g_A_per_V;          /* (Ts/L^)(1 - Ts R^/(2 L^)) [A/V per period] */
    dq_t i_hat_A;             /* prediction i^(k+1) made by the last step */
    float fd_V;               /* disturbance estimates f^ [V] */
    float fq_V;
    dq_t U_V;                 /* switching term of the last step [V] (monitor) */
} smo_t;

/* Design defaults for nominal R_Ohm, L_H, psi_f_Wb [Ohm, H, Wb] and
 * period Ts_s [s]; the caller then sets the bounds i_max_A, u_max_V,
 * omega_max_rad_s and f_max_V (defaults 0: init refuses them). Background. */
void smo_cfg_defaults(smo_cfg_t *cfg, float Ts_s, float R_Ohm, float L_H, float psi_f_Wb);

/* Copies cfg, checks it (finite, positive, ranges ordered and holding the
 * initial values; stability Ks/phi < 2 L_min/Ts - R_max and mu*Ts < 1;
 * condition (36) Ks > ef_max + R_max*phi) and resets. Anything but
 * SMO_CFG_OK is a fault for the caller. Background. */
smo_status_t smo_init(smo_t *smo, const smo_cfg_t *cfg);

/* Initial parameters, f^ = 0; the next smo_step() seeds i^ with i(k).
 * Background, or ISR before the observer is enabled. */
void smo_reset(smo_t *smo);

/* One period: i_A = measured i(k) [A], omega_el_rad_s = w(k), u_V = the
 * voltage applied over [k, k+1] after the hexagon clamp [V]. Returns and
 * stores i^(k+1) [A] (eq. 51b, 55 as corrected in this header). ISR. */
dq_t smo_step(smo_t *smo, dq_t i_A, float omega_el_rad_s, dq_t u_V);

/* Sets R^ [Ohm] bumplessly: f^ += (R^old - R^new) i^ keeps -R^ i^ - f^;
 * the next prediction moves only through g (zero in steady state).
 * Returns false (nothing changed) when R_Ohm is non-finite or outside
 * [R_min, R_max]. Background or ISR (1 division). */
bool smo_set_R(smo_t *smo, float R_Ohm);

/* Sets L^ [H], limited to [L_min, L_max], keeping w L^ iq - fd^ at the
 * given omega_el_rad_s and iq_A (the transfer law's invariant); returns
 * the L^ now in use. ISR (1 division). */
float smo_set_L(smo_t *smo, float L_H, float omega_el_rad_s, float iq_A);

/* Sets psi^ [Wb], limited to [psi_min, psi_max], keeping w psi^ + fq^ at
 * the given omega_el_rad_s; returns the psi^ now in use. ISR. */
float smo_set_psi(smo_t *smo, float psi_f_Wb, float omega_el_rad_s);

/* A voltage the model now compensates: f^ gives up (dfd_V, dfq_V) [V] it
 * no longer has to explain (the inverter error identified,
 * inverter_error_design.md sec. 5); the caller's compensation moves u by the same, so the prediction
 * does not move (bumpless). ISR. */
void smo_shift_f(smo_t *smo, float dfd_V, float dfq_V);

#endif /* SMO_H */
