/*
 * link_params.h - the drive's parameters on the link: the values of the
 * parameter set (drive_params.h) the controller is told or derives and an
 * operator sets, each under its drive_sil scenario key's name in
 * [controller], with the one range that key and the link's WRITE are
 * checked against (tools/sil/scenario.c reads it from here). One table,
 * walked by index: the link's variables (link_vars.h, after the fixed
 * ones), drivetool's backup (an INI [controller] section), and a save to
 * flash can take it whole. Written only while the drive is stopped; the
 * glue then rebuilds the app's configuration from the set
 * (link_cfg_t.params_apply). Pure: no state.
 */
#ifndef LINK_PARAMS_H
#define LINK_PARAMS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "drive_params.h"
#include "mathx.h"

/* Plausibility ranges: they refuse the absurd (a unit slip: mH written as
 * H, degrees as radians, a typo), not the merely beyond a rating. */
#define LINK_PARAM_R_OHM_LO     1e-3f    /* [ohm] */
#define LINK_PARAM_R_OHM_HI     1e3f
#define LINK_PARAM_L_H_LO       1e-6f    /* [H] */
#define LINK_PARAM_L_H_HI       10.0f
#define LINK_PARAM_PSIF_WB_LO   1e-4f    /* [Wb] */
#define LINK_PARAM_PSIF_WB_HI   10.0f
#define LINK_PARAM_POLE_PAIRS_HI 64.0f   /* [-] */
#define LINK_PARAM_J_KGM2_LO    1e-8f    /* [kg m^2] */
#define LINK_PARAM_J_KGM2_HI    100.0f
#define LINK_PARAM_B_NMS_HI     100.0f   /* [N m s/rad]: as J's top, a shaft that stops in its own time constant */
#define LINK_PARAM_DEADTIME_HI_S 1e-5f   /* [s]: 0.1 of a 10 kHz period, the most ctrl_init compensates */
#define LINK_PARAM_DROP_HI_V    10.0f    /* [V]: above any switch's or diode's on-state drop (1-3 V); mV as V refused */
#define LINK_PARAM_UNBOUNDED    3.4e38f  /* no plausible top: the largest float, rounded down */

typedef enum { LINK_PARAM_F32 = 0, LINK_PARAM_U16 = 1 } link_param_type_t;

/* The list: X(ID, key, unit, type, field of drive_params_t, lo, hi, lo_open)
 * lo_open: lo itself refused (> lo); else lo <= v. Always v <= hi. */
#define LINK_PARAMS(X) \
    X(R_OHM, "R_ohm", "ohm", LINK_PARAM_F32, motor.R_Ohm, LINK_PARAM_R_OHM_LO, LINK_PARAM_R_OHM_HI, false) \
    X(L_H, "L_H", "H", LINK_PARAM_F32, motor.L_H, LINK_PARAM_L_H_LO, LINK_PARAM_L_H_HI, false) \
    X(PSIF_WB, "psif_Wb", "Wb", LINK_PARAM_F32, motor.psi_f_Wb, LINK_PARAM_PSIF_WB_LO, LINK_PARAM_PSIF_WB_HI, false) \
    X(POLE_PAIRS, "pole_pairs", "", LINK_PARAM_U16, motor.pole_pairs, 1.0f, LINK_PARAM_POLE_PAIRS_HI, false) \
    X(J_KGM2, "J_kgm2", "kg m^2", LINK_PARAM_F32, motor.J_kgm2, LINK_PARAM_J_KGM2_LO, LINK_PARAM_J_KGM2_HI, false) \
    X(B_NMS, "B_Nms", "N m s/rad", LINK_PARAM_F32, motor.B_Nms, 0.0f, LINK_PARAM_B_NMS_HI, false) \
    X(ENC_OFFSET, "encoder_offset_el_rad", "rad", LINK_PARAM_F32, board.enc_offset_el_rad, -MATHX_TWO_PI_F, \
      MATHX_TWO_PI_F, false) \
    X(SPEED_KP, "speed_kp_Nms_rad", "N m s/rad", LINK_PARAM_F32, tuning.speed_kp_Nms_rad, 0.0f, \
      LINK_PARAM_UNBOUNDED, true) \
    X(SPEED_KI, "speed_ki_Nm_rad", "N m/rad", LINK_PARAM_F32, tuning.speed_ki_Nm_rad, 0.0f, LINK_PARAM_UNBOUNDED, \
      true) \
    X(TE_MAX, "te_max_Nm", "N m", LINK_PARAM_F32, limits.te_max_Nm, 0.0f, LINK_PARAM_UNBOUNDED, true) \
    X(I_LIMIT, "i_limit_A", "A", LINK_PARAM_F32, limits.i_limit_A, 0.0f, LINK_PARAM_UNBOUNDED, true) \
    X(DEADTIME, "deadtime_s", "s", LINK_PARAM_F32, board.deadtime_s, 0.0f, LINK_PARAM_DEADTIME_HI_S, false) \
    X(DEVICE_DROP, "device_drop_V", "V", LINK_PARAM_F32, board.device_drop_V, 0.0f, LINK_PARAM_DROP_HI_V, false)

#define LINK_PARAM_ENUM(id, key, unit, type, field, lo, hi, lo_open) LINK_PARAM_##id,
typedef enum { LINK_PARAMS(LINK_PARAM_ENUM) LINK_PARAM_COUNT } link_param_id_t;
#undef LINK_PARAM_ENUM

typedef struct {
    const char *key;            /* [controller] key of drive_sil: the link variable's name */
    const char *unit;
    uint16_t type;              /* link_param_type_t */
    size_t offset;              /* of the value in drive_params_t */
    float lo, hi;               /* the range (lo excluded when lo_open) */
    bool lo_open;
} link_param_t;

/* The table, in the list's order (link_params.c). */
extern const link_param_t LINK_PARAM_TABLE[LINK_PARAM_COUNT];

/* Parameter k (< LINK_PARAM_COUNT; another: the first). Any context; inline: a capture's read in
 * the ISR calls nothing in flash. */
static inline const link_param_t *link_param(uint16_t k)
{
    return &LINK_PARAM_TABLE[(k < (uint16_t)LINK_PARAM_COUNT) ? k : 0u];
}

/* Parameter k's value in *p (a float; pole pairs as a whole number). Any context; inline. */
static inline float link_param_get(const drive_params_t *p, uint16_t k)
{
    const link_param_t *d = link_param(k);
    const char *at = (const char *)p + d->offset;
    if (d->type == (uint16_t)LINK_PARAM_U16) {
        return (float)*(const uint16_t *)(const void *)at;
    }
    return *(const float *)(const void *)at;
}

/* v within parameter k's range (and whole for an integer one); a NaN never is. Any context. */
bool link_param_ok(uint16_t k, float v);

/* Set parameter k of *p to v (checked first: false, *p unchanged, when not link_param_ok). Background. */
bool link_param_set(drive_params_t *p, uint16_t k, float v);

#endif /* LINK_PARAMS_H */
