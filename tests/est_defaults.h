/*
 * est_defaults.h - the estimation's settings for a test's controller
 * configuration: est_cfg_defaults() for ctrl_cfg_told() of it, with the
 * observer's gains designed for it at SMO_EF_MAX_DEFAULT_V. Tests only.
 */
#ifndef EST_DEFAULTS_H
#define EST_DEFAULTS_H

#include "ctrl.h"

/* cfg->est_cfg for cfg's told values (set them first), the R^ band [R_min_Ohm, R_max_Ohm]. */
static inline void test_est_defaults(ctrl_cfg_t *cfg, float R_min_Ohm, float R_max_Ohm)
{
    est_told_t told;
    smo_gains_t g;
    ctrl_cfg_told(cfg, &told);
    (void)est_obs_gains(&told, SMO_EF_MAX_DEFAULT_V, &g);
    est_cfg_defaults(&cfg->est_cfg, &told, &g, R_min_Ohm, R_max_Ohm);
}

/* The default R^ band for cfg's told R. */
static inline void test_est_band_default(const ctrl_cfg_t *cfg, float *R_min_Ohm, float *R_max_Ohm)
{
    est_told_t told;
    ctrl_cfg_told(cfg, &told);
    est_rsid_band(&told, R_min_Ohm, R_max_Ohm);
}

#endif /* EST_DEFAULTS_H */
