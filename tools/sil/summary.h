/*
 * summary.h - the figures of one SIL run over its steady window, computed
 * from the logged rows as they are produced (drive_sil --summary), so a
 * sweep needs no CSV per point. The definitions are tools/drivekit/drivekit/metrics.py's
 * (steady() and estimates()): over the rows with t0 <= t_s < t1,
 *   te_err_Nm      mean |Te - Te*|          te_ripple_Nm  RMS of Te - Te*
 *   psi_err_Wb     mean |psi_s - psi_s*|    psi_err_pct   mean |.| / psi_s* [%]
 *   speed_err_rpm  mean speed - speed*      speed_err_max_rpm  max |.|
 *   id_A, iq_A     means of the true currents
 *   R/L/psif_err_pct  mean (x^ - x) / x [%] against the plant's values
 * Means skip non-finite terms (a NaN reference column in the mode), a mean
 * of nothing is NaN (null in the JSON). Window membership is decided on
 * t_s as the CSV prints it (%.9g), so both see the same rows.
 * tests/test_summary.py checks the figures against metrics.py on one run.
 */
#ifndef SUMMARY_H
#define SUMMARY_H

#include <stdint.h>
#include <stdio.h>

#include "scenario.h"
#include "sil.h"

/* A run that reaches this far is measured over the paper's window, a shorter one over its tail
 * (tools/drivekit/drivekit/sil_report.py's rule). */
#define SUMMARY_PAPER_T0_S 0.8
#define SUMMARY_PAPER_T1_S 0.95
#define SUMMARY_PAPER_MIN_RUN_S 1.05
#define SUMMARY_TAIL_FRACTION 0.25

typedef struct {
    double sum, n;            /* of finite terms */
} summary_mean_t;

typedef struct {
    double t0_s, t1_s;        /* window [t0, t1) */
    double R_ohm, L_H, psif_Wb;   /* the plant's (truth) */
    uint32_t rows;            /* rows inside the window */
    summary_mean_t te_abs, te_sq, psi_abs, psi_rel, speed, id, iq, R_rel, L_rel, psif_rel;
    double speed_abs_max;     /* NaN until a finite term */
} summary_t;

/* The default window of a run of duration_s (see SUMMARY_PAPER_*). */
void summary_default_window(double duration_s, double *t0_s, double *t1_s);

/* Start an empty summary over [t0_s, t1_s) for the plant of *sc. */
void summary_init(summary_t *s, const scenario_t *sc, double t0_s, double t1_s);

/* Add one logged row (rows outside the window are skipped). */
void summary_add(summary_t *s, const sil_row_t *row);

/* The summary as one JSON object on one line to f: id (when not NULL), the figures above, the
 * window and its row count, the run's result (final state and fault with their names, peak |i|,
 * periods), the resolved plant and controller parameters and the method. NaN is written null. */
void summary_write_json(FILE *f, const summary_t *s, const scenario_t *sc, const sil_result_t *res,
                        const char *scenario_path, const char *id);

/* Room for summary_warning_text's every warning at once, with their reasons. */
#define SUMMARY_WARNING_LEN 160

/* The run's warnings by name (app.h APP_WARN_*: "STEP1_REFUSED (RSID_...)", "HOST_TIMEOUT (...)",
 * joined by ", "), "" without; len: SUMMARY_WARNING_LEN for all of them. */
const char *summary_warning_text(const sil_result_t *res, char *buf, size_t len);

/* Names of app_state_t / app_fault_t values ("FAULT_<n>" for one this table does not know). */
const char *summary_state_name(int state, char *buf, size_t len);
const char *summary_fault_name(int fault, char *buf, size_t len);

#endif /* SUMMARY_H */
