/* app_probe.h - the one place the app's tests look inside the app's
 * controller (app_t.ctrl) and its estimation: what app.h and ctrl.h give
 * no reader or call for, and the test seams that put a state there.
 * Tests read through the public surface (app_ctrl() with ctrl.h's
 * readers, app_monitor(), app_estimate()) and come here only for the
 * rest, so a change of ctrl_t or est_t touches this file, not the tests.
 * `make check` (tools/check/test_surface.sh) keeps app_t.ctrl out of the
 * tests other than this file. Any test runner may include it; no state. */
#ifndef APP_PROBE_H
#define APP_PROBE_H

#include "app.h"

/* ---- readers: no public one ------------------------------------------- */

/* ctrl_t's copy of its configuration (ctrl_kept_t). */
static inline const ctrl_kept_t *probe_ctrl_kept(const app_t *a)
{
    return &app_ctrl(a)->cfg;
}

/* The speed PI's gains and limits in use. */
static inline const pi_cfg_t *probe_speed_pi_cfg(const app_t *a)
{
    return &app_ctrl(a)->speed_pi.cfg;
}

/* The model the deadbeat uses now (told or the estimation's) [Ohm, H, Wb]. */
static inline const dbdtc_par_t *probe_model(const app_t *a)
{
    return &app_ctrl(a)->db.par;
}

/* The observer's R^ [Ohm] (est_output()'s R is the model's, not the observer's). */
static inline float probe_obs_R_Ohm(const app_t *a)
{
    return ctrl_est(app_ctrl(a))->smo.R_Ohm;
}

/* Step 1: the window the coming periods go into. */
static inline rs_ident_window_t probe_rsid_window(const app_t *a)
{
    return ctrl_est(app_ctrl(a))->win;
}

/* Step 1: the samples in window w (0: window 1, 1: window 2). */
static inline uint32_t probe_rsid_samples(const app_t *a, int w)
{
    return ctrl_est(app_ctrl(a))->ri.win[w].h.n;
}

/* ---- seams: a state put in by the test, between ISR calls -------------- */

/* The controller for ctrl.h's calls a harness makes between periods
 * (ctrl_set_ref, ctrl_set_mode), past the app's request (app_request_op). */
static inline ctrl_t *probe_ctrl_rw(app_t *a)
{
    return &a->ctrl;
}

/* The monitor, for a test that writes the readings the link sends. */
static inline ctrl_mon_t *probe_monitor_rw(app_t *a)
{
    return &a->ctrl.mon;
}

/* ctrl_init's refusals as if it had returned `status` (CTRL_CFG_*, EST_CFG_*). */
static inline void probe_set_status(app_t *a, ctrl_status_t status)
{
    a->ctrl.status = status;
}

/* The encoder's PLL at speed_m_rad_s [rad/s mech], its prediction landing
 * on count: the next ctrl_track's error is 0 and its estimate stays. */
static inline void probe_put_pll(app_t *a, float speed_m_rad_s, uint32_t count)
{
    encoder_t *e = &a->ctrl.enc;
    e->vel = speed_m_rad_s / e->rad_per_count;
    e->pos = (float)count - e->cfg.Ts_s * e->vel;
}

/* Step 1: the sample sums of window w (0: window 1, 1: window 2), to corrupt. */
static inline rs_ident_head_t *probe_rsid_sums_rw(app_t *a, int w)
{
    return &ctrl_est_rw(&a->ctrl)->ri.win[w].h;
}

#endif /* APP_PROBE_H */
