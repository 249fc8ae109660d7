/*
 * plant.h - the TRUE surface-mounted PMSM (Ld = Lq) and its shaft, for the
 * simulated board. Host-only, double precision.
 *
 * Model (paper eqs. (1)-(3), amplitude-invariant dq, d on the magnet):
 *   L did/dt = ud - R id + w_el L iq
 *   L diq/dt = uq - R iq - w_el (L id + psi_f)
 *   J dw_m/dt = Te - TL - B w_m,   Te = 1.5 p psi_f iq,   w_el = p w_m
 * The stator voltage is given in the stator frame (alpha-beta), held
 * constant over a step, as an inverter applies it; the step is one
 * classical RK4 step, so callers split a period at every switching instant.
 * The step integrates in the stator frame with the d axis's phasor as a
 * state (no sin/cos at its stages); the state kept is the rotor frame's.
 */
#ifndef PLANT_H
#define PLANT_H

#include <stdbool.h>
#include <stdint.h>

typedef struct {
    double R_Ohm;          /* stator phase resistance */
    double L_H;            /* stator inductance, Ld = Lq */
    double psi_f_Wb;        /* permanent-magnet flux linkage */
    uint32_t pole_pairs;
    double J_kgm2;         /* rotor + load inertia */
    double B_Nms;          /* viscous friction */
    bool speed_held;       /* true: the shaft keeps omega0 whatever the torque (locked rotor: omega0 = 0) */
    double omega0_m_rad_s; /* initial mechanical speed */
} plant_cfg_t;

typedef struct {
    double id_A;
    double iq_A;
    double omega_m_rad_s;  /* mechanical speed */
    double theta_m_rad;    /* mechanical angle in [0, 2 pi), 0 at encoder count 0 */
} plant_state_t;

/* Integrals over the steps since plant_acc_clear(), for period means. */
typedef struct {
    double time_s;
    double id_As;
    double iq_As;
    double ud_Vs;          /* applied voltage in the true rotor frame */
    double uq_Vs;
} plant_acc_t;

typedef struct {
    plant_cfg_t cfg;
    plant_state_t x;
    double enc_offset_el_rad;  /* electrical angle of the d axis at theta_m = 0 */
    double inv_L_per_H;          /* 1/L and 1/J: the step multiplies, divisions are slow */
    double inv_J_per_kgm2;
    plant_acc_t acc;
    /* sin/cos anchor: angles near it are turned from it by a short series (see plant.c) */
    double anchor_el_rad;
    double anchor_sin;
    double anchor_cos;
    /* cos and sin of the present electrical angle (the d axis's phasor), kept by every step */
    double z_cos;
    double z_sin;
} plant_t;

/* Plant with zero currents and angle at speed omega0, d axis at enc_offset_el_rad for theta_m = 0. */
void plant_init(plant_t *p, const plant_cfg_t *cfg, double enc_offset_el_rad);

/* One RK4 step of h_s with the stator-frame voltage (u_alpha_V, u_beta_V) and load TL_Nm held. */
void plant_step(plant_t *p, double u_alpha_V, double u_beta_V, double TL_Nm, double h_s);

/* One RK4 step of h_s with the stator open (outputs off): currents forced to zero, only the shaft moves.
 * Valid while the back-EMF stays below the bus, so no freewheeling diode conducts. */
void plant_step_open(plant_t *p, double TL_Nm, double h_s);

/* Stator resistance from now on [ohm] (a winding warming up); > 0 and finite, else ignored. Any context. */
void plant_set_R_Ohm(plant_t *p, double R_Ohm);

/* Electrical angle of the d axis [rad], in [0, 2 pi). */
double plant_theta_el_rad(const plant_t *p);

/* Electromagnetic torque [N m] of the present state. */
double plant_te_Nm(const plant_t *p);

/* Stator flux-linkage magnitude [Wb] of the present state. */
double plant_psi_s_Wb(const plant_t *p);

/* Phase currents [A], positive into the motor, of the present state. */
void plant_iabc_A(const plant_t *p, double i_abc_A[3]);
/* The same at the electrical angle theta_el_rad = plant_theta_el_rad(p), when the caller has it. */
void plant_iabc_at_A(const plant_t *p, double theta_el_rad, double i_abc_A[3]);

/* Zero the integrals of plant_acc_t. */
void plant_acc_clear(plant_t *p);

#endif /* PLANT_H */
