/*
 * spmsm.h - the two facts the controller and the identification share,
 * one home each:
 *
 *   torque    Te = 1.5 p psi_f i_q                     eq. (3), amplitude-
 *             invariant dq, an SPMSM (Ld = Lq): i_d makes no torque;
 *   timing    a voltage computed from the samples of instant k acts over
 *             [k+1, k+2] (the duties' shadow load, hal.h: one period of
 *             computation delay), its middle 1.5 periods after the
 *             sample: the rotor has turned by 1.5 w Ts by then, the angle
 *             a rotor-frame voltage is turned to the stator frame at.
 *
 * Stateless; any context.
 */
#ifndef SPMSM_H
#define SPMSM_H

#include <stdint.h>

/* Te / (p psi_f i_q), eq. (3) [-] */
#define SPMSM_TORQUE_PER_P_PSI_I 1.5f
/* Periods from the sample to the middle of the period the voltage computed
 * from it acts in [-] */
#define SPMSM_VOLTAGE_AT_PERIODS 1.5f
/* Whole periods from a voltage's computation to the end of the period it
 * acts in: the current sampled then is the first to have seen all of it [-] */
#define SPMSM_VOLTAGE_SEEN_PERIODS 2u

/* Torque constant 1.5 p psi_f [N m/A] (eq. 3). */
static inline float spmsm_kt_Nm_A(uint16_t pole_pairs, float psi_f_Wb)
{
    return SPMSM_TORQUE_PER_P_PSI_I * (float)pole_pairs * psi_f_Wb;
}

/* Angle [rad el] the rotor turns from the sample to the middle of the
 * period the voltage computed from it acts in, at omega_el_rad_s [rad/s el]
 * and the period Ts_s [s]. */
static inline float spmsm_angle_advance_rad(float omega_el_rad_s, float Ts_s)
{
    return SPMSM_VOLTAGE_AT_PERIODS * omega_el_rad_s * Ts_s;
}

#endif /* SPMSM_H */
