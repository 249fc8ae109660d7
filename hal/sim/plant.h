/*
 * plant.h - the TRUE surface-mounted PMSM (Ld = Lq) and its shaft, for the
 * simulated board. Host-only, double precision.
 *
 * Model (paper eqs. (1)-(3), amplitude-invariant dq, d on the magnet):
 *   L did/dt = ud - R id + w_el L iq
 *   L diq/dt = uq - R iq - w_el (L id + psi_f)
 *   J dw_m/dt = Te - TL - B w_m,   Te = 1.5 p psi_f iq,   w_el = p w_m
 * The stator voltage is given in the stator frame (alpha-beta) over a
 * period as a sum of constant pulses, as an inverter applies it. The
 * period is solved in closed form: the currents exactly at a held speed
 * (linear ODE, exponentials as short series), the shaft from the torque's
 * integral and first moment, the outputs carried to the mean speed by
 * their derivatives, the acceleration to first order; derivation, error
 * bounds and series orders in hal/sim/plant_design.md. One constant
 * voltage over a period may take one RK4 step instead (plant_step_rk4).
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

/* A constant stator voltage over |t - T/2 - centre_s| < half_s of a period of T. */
typedef struct {
    double ua_V, ub_V;
    double centre_s;   /* from the period's middle */
    double half_s;
} plant_pulse_t;

/* Room for the pulses of one period: 3 legs + 3 dead-band corrections + 3
 * device drops, or up to 13 pieces between the edges of 3 legs. */
#define PLANT_MAX_PULSES 16
#define PLANT_N_MOMENTS 6

/* Working data of one period (plant.c; times from the period's middle). */
typedef struct {
    double T_s, tau_s, TL_Nm;
    double ia0_A, ib0_A;       /* stator-frame current at the start */
    double w_el_rad_s;         /* predicted mean electrical speed (pass 1) */
    double alpha_el_rad_s2;    /* its acceleration */
    double E;                  /* e^(-a tau), a = R/L */
    double E_key;              /* a tau it was computed for */
    double ir0_d_A, ir0_q_A;   /* rotor-frame current at the start */
    double zc_c, zc_s;         /* walker: the d axis's phasor at the middle, speed w_el */
    bool walk_zc_ok;           /* zc_c/zc_s computed for this period */
    double S_a, S_b;           /* int e^(a s) u ds over the pulses [V s] */
    double M_a[PLANT_N_MOMENTS], M_b[PLANT_N_MOMENTS];   /* centred pulses: sum of u 2 r^(2n+1) */
    int n_pulses;
    int n_off;                 /* pulses not centred */
    bool legs_given;           /* plant_period_legs(): in the moments, not yet in pulse[] */
    double leg_vdc_V, leg_half_s[3];
    plant_pulse_t pulse[PLANT_MAX_PULSES];
    double walk_s, walk_g;     /* walker: time, e^(a s) */
    double walk_Pa, walk_Pb;   /* walker: integral of e^(a s) u from -tau [V s] */
} plant_period_t;

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
    /* cos and sin of the present electrical angle (the d axis's phasor) */
    double z_cos;
    double z_sin;
    plant_period_t per;   /* the period in hand, plant_period_begin() .. plant_period_end() */
    /* the speed's predictor: the last period's mean acceleration and start's force */
    bool shaft_prev_valid;
    double alpha_prev_el_rad_s2;
    double F_prev_Nm;
} plant_t;

/* Plant with zero currents and angle at speed omega0, d axis at enc_offset_el_rad for theta_m = 0. */
void plant_init(plant_t *p, const plant_cfg_t *cfg, double enc_offset_el_rad);

/* One period of h_s with the stator-frame voltage (u_alpha_V, u_beta_V) and load TL_Nm held. */
void plant_step(plant_t *p, double u_alpha_V, double u_beta_V, double TL_Nm, double h_s);

/* h_s in n_steps equal classical RK4 steps (the old integrator, and the cheapest for one
 * constant voltage over a period: the averaged inverter's; error 4e-7 A at one 100 us step,
 * plant_design.md sec. 5), with (u_alpha_V, u_beta_V) and TL_Nm held; adds to acc. */
void plant_step_rk4(plant_t *p, double u_alpha_V, double u_beta_V, double TL_Nm, double h_s, int n_steps);

/* A period of T_s > 0 with load TL_Nm held: plant_period_begin(), the voltage as pulses
 * (plant_period_pulse(), superposed), plant_period_end() advances the state and adds to acc.
 * In between, the walker gives the currents at instants of the period in time order under
 * a voltage it is told piece by piece (plant_walk_iabc_A(), plant_walk_advance()): an
 * inverter whose voltage depends on the current uses it; it does not change the pulses. */
void plant_period_begin(plant_t *p, double T_s, double TL_Nm);
/* Voltage (u_alpha_V, u_beta_V) for |t - T/2 - centre_s| < half_s; half_s <= 0 adds nothing.
 * Returns false (nothing added) when PLANT_MAX_PULSES are given. */
bool plant_period_pulse(plant_t *p, double u_alpha_V, double u_beta_V, double centre_s, double half_s);
/* The three legs of a two-level inverter on a bus of vdc_V, leg k high for |t - T/2| <
 * half_s[k] (a pulse each, centred; <= 0: low all period), as three plant_period_pulse(). */
void plant_period_legs(plant_t *p, double vdc_V, const double half_s[3]);
/* Forget the pulses given since plant_period_begin(). */
void plant_period_clear(plant_t *p);
void plant_period_end(plant_t *p);
/* Phase currents [A] at the walker's instant (the period's start after plant_period_begin()). */
void plant_walk_iabc_A(const plant_t *p, double i_abc_A[3]);
/* The walker applies (u_alpha_V, u_beta_V) from its instant to t_s (from the period's start). */
void plant_walk_advance(plant_t *p, double u_alpha_V, double u_beta_V, double t_s);

/* Longest step of the gates-off solver (plant_step_rectified): 20 a 10 kHz period. */
#define PLANT_OFF_SUBSTEP_MAX_S 5.0e-6

/* h_s with the gates off: each leg's two freewheeling diodes between the motor's terminal and a
 * stiff bus of vdc_V, each dropping vd_V when it conducts (hal/sim/plant_design.md sec. 9). While
 * the line back-EMF's peak stays below vdc_V + 2 vd_V and no current flows, the diodes block and
 * only the shaft moves (TL_Nm, B); above it they conduct into the bus and brake: the currents by
 * backward-Euler steps of at most PLANT_OFF_SUBSTEP_MAX_S, the diodes' states of each step from
 * the complementarity of their currents and voltages. Adds to acc (the terminal voltage over the
 * star: the back-EMF while all block). */
void plant_step_rectified(plant_t *p, double vdc_V, double vd_V, double TL_Nm, double h_s);

/* The shaft's speed from now on [rad/s mechanical] (a friction that stopped it). */
void plant_set_speed(plant_t *p, double omega_m_rad_s);

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

/* Zero the integrals of plant_acc_t. */
void plant_acc_clear(plant_t *p);

#endif /* PLANT_H */
