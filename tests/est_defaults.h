/*
 * est_defaults.h - the estimation's settings for a test's controller
 * configuration: est_cfg_defaults() for ctrl_cfg_told() of it, with the
 * observer's default gains (smo.h's Table I design). Tests only.
 */
#ifndef EST_DEFAULTS_H
#define EST_DEFAULTS_H

#include "ctrl.h"

/* cfg->est for cfg's told values (set them first), the R^ band [R_min_Ohm, R_max_Ohm]. */
static inline void test_est_defaults(ctrl_cfg_t *cfg, float R_min_Ohm, float R_max_Ohm)
{
    est_told_t told;
    est_obs_gains_t g;
    ctrl_cfg_told(cfg, &told);
    est_obs_gains_default(&g);
    est_cfg_defaults(&cfg->est_cfg, &told, &g, R_min_Ohm, R_max_Ohm);
}

/* The default R^ band for cfg's told R with the default gains. */
static inline void test_est_band_default(const ctrl_cfg_t *cfg, float *R_min_Ohm, float *R_max_Ohm)
{
    est_told_t told;
    est_obs_gains_t g;
    ctrl_cfg_told(cfg, &told);
    est_obs_gains_default(&g);
    est_rsid_band(&told, &g, R_min_Ohm, R_max_Ohm);
}

#endif /* EST_DEFAULTS_H */
