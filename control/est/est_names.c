/* est_names.c - the names of the estimation's hold reasons, for the
 * summaries and the link; see est.h. Any context (runs from flash on the
 * target: target.mk). */
#include "est.h"

/* Ranked: the reason that explains the told model best first. */
static const struct {
    uint16_t bit;
    const char *name;
} HOLD_NAMES[EST_HOLD_NAMES_N] = {
    { EST_HOLD_OSCILLATION, "OSCILLATION" },
    { EST_HOLD_STEP1_REFUSED, "STEP1_REFUSED" },
    { EST_HOLD_NO_STEP2, "NO_STEP2" },
    { EST_HOLD_ANGLE, "ANGLE" },
    { EST_HOLD_INVERTER_UNKNOWN, "INVERTER_UNKNOWN" },
    { EST_HOLD_SPEED_FLOOR, "SPEED_FLOOR" },
    { EST_HOLD_VOLTAGE, "VOLTAGE" },
    { EST_HOLD_CURRENT, "CURRENT" },
    { EST_HOLD_TORQUE, "TORQUE" },
    { EST_HOLD_ACCEL, "ACCEL" },
    { EST_HOLD_SETTLE, "SETTLE" },
};

const char *est_hold_name(uint16_t bit)
{
    for (uint16_t k = 0u; k < EST_HOLD_NAMES_N; k++) {
        if (HOLD_NAMES[k].bit == bit) {
            return HOLD_NAMES[k].name;
        }
    }
    return "";
}

uint16_t est_hold_reason_bit(uint16_t hold)
{
    for (uint16_t k = 0u; k < EST_HOLD_NAMES_N; k++) {
        if ((hold & HOLD_NAMES[k].bit) != 0u) {
            return HOLD_NAMES[k].bit;
        }
    }
    return 0u;
}

const char *est_hold_reason(uint16_t hold)
{
    return est_hold_name(est_hold_reason_bit(hold));
}
