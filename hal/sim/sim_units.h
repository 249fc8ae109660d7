/*
 * sim_units.h - the constants of the host simulation (hal/sim and the SIL
 * runner in tools/sil), in double precision. The firmware's float ones are
 * in control/mathx.h and clarke_park.h.
 */
#ifndef SIM_UNITS_H
#define SIM_UNITS_H

#define SIM_TWO_PI 6.283185307179586          /* [rad] */
#define SIM_RPM_PER_RAD_S (60.0 / SIM_TWO_PI) /* [r/min per rad/s] */

#endif /* SIM_UNITS_H */
