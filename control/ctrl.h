/*
 * ctrl.h - the drive controller: one ctrl_step() per 10 kHz PWM period.
 *
 *   encoder -> theta_el, omega_el
 *   Clarke/Park of the sampled currents (one sincos at theta_el)
 *   model: parameters in use and the predicted state at k+1 (delay
 *          compensation), from one place: ctrl_model_step(); conventional
 *          method = nominal parameters and eq. (10)-(12)
 *   speed PI -> Te* (speed mode; |Te*| <= te_max_Nm, anti-windup fed by
 *          the torque the applied voltage achieves) | Te* from the
 *          reference (torque mode)
 *   MTPA -> psi_s*; DB-DTC (eq. 17) -> u_dq(k+1)
 *   (open-loop mode: u_dq(k+1) from the reference)
 *   torque-first hexagon limit, inverse Park and SVPWM at the angle of the
 *   middle of the period the voltage is applied in: theta + 1.5*omega*Ts
 *   the realised voltage is kept for the next step's prediction.
 *
 * Non-finite inputs or results give 50 % duties and CTRL_FLAG_NONFINITE.
 */
#ifndef CTRL_H
#define CTRL_H

#include <stdint.h>

#include "clarke_park.h"
#include "dbdtc.h"
#include "encoder.h"
#include "pi.h"

typedef enum { CTRL_MODE_OPEN_LOOP = 0, CTRL_MODE_TORQUE = 1, CTRL_MODE_SPEED = 2 } ctrl_mode_t;
typedef enum { CTRL_METHOD_CONVENTIONAL = 0, CTRL_METHOD_PROPOSED = 1 } ctrl_method_t;

/* Flags in ctrl_out_t.flags */
#define CTRL_FLAG_VOLTAGE_LIMIT    0x0001u /* vector clamped to the hexagon */
#define CTRL_FLAG_FLUX_UNREACHABLE 0x0002u /* negative discriminant: flux target not reachable in one period */
#define CTRL_FLAG_NONFINITE        0x0004u /* a non-finite value appeared; duties are 0.5 and the app must fault */

typedef struct {
    float Ts_s;                 /* control period [s], 1e-4 */
    float Rs_Ohm;               /* controller's stator resistance (may differ from the motor's) */
    float Ls_H;                 /* controller's inductance, Ld = Lq */
    float psi_f_Wb;             /* controller's PM flux linkage */
    uint16_t pole_pairs;
    uint32_t enc_lines;         /* encoder lines; counts per revolution = 4 * lines */
    float enc_offset_el_rad;    /* electrical angle at encoder count 0 */
    float enc_pll_bw_rad_s;     /* speed-estimator bandwidth [rad/s] */
    float speed_kp_Nms_rad;     /* speed PI: N m per (rad/s) of mechanical speed error */
    float speed_ki_Nm_rad;      /* speed PI: N m per rad of integrated speed error */
    float te_max_Nm;            /* |Te*| limit, 2x rated = 12 N m */
    float i_max_A;              /* bound on the currents the model uses */
    float u_max_V;              /* bound on |ud|, |uq| before the hexagon */
    float omega_max_el_rad_s;   /* bound on |omega_el| the model uses */
    float psi_max_Wb;           /* bound on psi_s* */
} ctrl_cfg_t;

typedef struct { float ia_A; float ib_A; float vdc_V; uint32_t enc_count; } ctrl_in_t; /* one period's samples */

typedef struct {
    float speed_ref_rad_s;      /* mechanical speed reference (speed mode) */
    float te_ref_Nm;            /* torque reference (torque mode) */
    float ud_ref_V, uq_ref_V;   /* rotor-frame voltage (open-loop mode) */
} ctrl_ref_t;

typedef struct { float duty[3]; uint16_t flags; } ctrl_out_t;

typedef struct {                /* monitor: written by every ctrl_step, for logging/telemetry */
    float theta_el_rad, omega_el_rad_s, speed_mech_rad_s;   /* as the controller sees them */
    float id_A, iq_A;                     /* measured this period */
    float ud_V, uq_V;                     /* rotor-frame voltage commanded for the next period, after the hexagon clamp */
    float te_ref_Nm, te_est_Nm;           /* torque reference and the controller's torque estimate (at k+1) */
    float psi_ref_Wb, psi_est_Wb;         /* stator-flux reference and estimate (at k+1) */
    float R_est_Ohm, L_est_H, psi_f_est_Wb;   /* parameters in use (nominal for the conventional method) */
    float fd_est, fq_est;                 /* observer disturbances (0 for the conventional method) */
} ctrl_mon_t;

typedef struct {
    ctrl_cfg_t cfg;
    ctrl_mode_t mode;           /* active mode */
    ctrl_mode_t mode_req;       /* set in background, taken at the next step */
    ctrl_method_t method;
    ctrl_ref_t ref;
    encoder_t enc;
    dbdtc_t db;                 /* parameters in use live in db.par */
    pi_t speed_pi;
    dq_t u_applied_V;           /* realised rotor-frame voltage being applied this period, u(k) */
    ctrl_mon_t mon;
} ctrl_t;

/* Start-up: copy *cfg, build the blocks, reset; mode torque, method conventional. */
void ctrl_init(ctrl_t *c, const ctrl_cfg_t *cfg);

/* Clear states (integrator, speed estimate, applied voltage). Background, before PWM is enabled. */
void ctrl_reset(ctrl_t *c);

/* Background; takes effect at the next step (bumpless into speed mode). */
void ctrl_set_mode(ctrl_t *c, ctrl_mode_t mode);

/* Background; switchable at run time. Until the observer exists the
 * proposed method runs as the conventional one. */
void ctrl_set_method(ctrl_t *c, ctrl_method_t method);

/* References [rad/s mech, N m, V]. Background or ISR. */
void ctrl_set_ref(ctrl_t *c, const ctrl_ref_t *ref);

/* One control period from the samples *in; duties and flags to *out. ISR, 10 kHz. */
void ctrl_step(ctrl_t *c, const ctrl_in_t *in, ctrl_out_t *out);

#endif /* CTRL_H */
