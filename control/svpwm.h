/*
 * svpwm.h - space-vector PWM: alpha-beta voltage command to three
 * centre-aligned duty cycles with min-max zero-sequence injection.
 *
 * The realisable set is the hexagon with vertices 2/3*Vdc on the phase
 * axes (inscribed circle Vdc/sqrt(3)). Commands inside the hexagon are
 * reproduced exactly; commands outside are scaled back onto its boundary,
 * angle kept. The voltage actually realised is returned so the caller's
 * observer and anti-windup see what the inverter will apply.
 */
#ifndef SVPWM_H
#define SVPWM_H

#include <stdint.h>

#include "clarke_park.h"

/* Result flags of svpwm_duty(), a bit set; 0 means exact and valid. */
#define SVPWM_OK            0x0000u
#define SVPWM_SATURATED     0x0001u /* command outside the hexagon, scaled back */
#define SVPWM_INVALID_INPUT 0x0002u /* non-finite input or Vdc too low: 50 % duties */

/* Below this DC-bus voltage [V] no modulation is attempted. */
#define SVPWM_VDC_MIN_V 1.0e-3f

typedef struct {
    float a; /* phase a high-side duty, 0..1 */
    float b;
    float c;
} svpwm_duty_t;

/*
 * Duties for the alpha-beta command u_ab_V [V] at DC-bus voltage vdc_V [V].
 * Writes *duty (each in [0,1]) and *u_real_V, the alpha-beta voltage [V]
 * the duties realise (0 when invalid). Returns SVPWM_* flags. Both
 * pointers must be valid. ISR context.
 */
uint16_t svpwm_duty(ab_t u_ab_V, float vdc_V, svpwm_duty_t *duty, ab_t *u_real_V);

#endif /* SVPWM_H */
