/* summary.c - steady-window figures of one SIL run; see summary.h. */
#include "summary.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "app.h"
#include "json_out.h"

#define CSV_T_FORMAT "%.9g"       /* sil_csv_row()'s number format */
#define EDGE_CHECK_S 1e-6         /* rows this close to a window edge are decided on the printed t */
#define TEXT_LEN 64
#define PERCENT 100.0

static const char *const STATE_NAMES[] = {
    [APP_STATE_INIT] = "INIT", [APP_STATE_IDLE] = "IDLE", [APP_STATE_CALIBRATE] = "CALIBRATE",
    [APP_STATE_ALIGN] = "ALIGN", [APP_STATE_IDENTIFY_R] = "IDENTIFY_R", [APP_STATE_RUN] = "RUN",
    [APP_STATE_FAULT] = "FAULT", [APP_STATE_PWM_CHECK] = "PWM_CHECK", [APP_STATE_ADC_CHECK] = "ADC_CHECK",
    [APP_STATE_ENC_CHECK] = "ENC_CHECK", [APP_STATE_COMMISSION] = "COMMISSION",
};

static const char *const FAULT_NAMES[] = {
    [APP_FAULT_NONE] = "NONE", [APP_FAULT_HW_TRIP] = "HW_TRIP", [APP_FAULT_OVERCURRENT] = "OVERCURRENT",
    [APP_FAULT_NONFINITE_OUTPUT] = "NONFINITE_OUTPUT", [APP_FAULT_NONFINITE_SAMPLE] = "NONFINITE_SAMPLE",
    [APP_FAULT_OVERVOLTAGE] = "OVERVOLTAGE", [APP_FAULT_UNDERVOLTAGE] = "UNDERVOLTAGE",
    [APP_FAULT_OVERSPEED] = "OVERSPEED", [APP_FAULT_ENCODER] = "ENCODER", [APP_FAULT_OVERRUN] = "OVERRUN",
    [APP_FAULT_CURRENT_OFFSET] = "CURRENT_OFFSET", [APP_FAULT_CONFIG] = "CONFIG",
    [APP_FAULT_RSID_TOO_FEW] = "RSID_TOO_FEW", [APP_FAULT_RSID_NOT_STEADY] = "RSID_NOT_STEADY",
    [APP_FAULT_RSID_DEGENERATE] = "RSID_DEGENERATE", [APP_FAULT_RSID_NON_FINITE] = "RSID_NON_FINITE",
    [APP_FAULT_RSID_OUT_OF_BAND] = "RSID_OUT_OF_BAND",
    [APP_FAULT_OPEN_PHASE] = "OPEN_PHASE", [APP_FAULT_CURRENT_SENSOR] = "CURRENT_SENSOR",
    [APP_FAULT_ENCODER_LOST] = "ENCODER_LOST",
    [APP_FAULT_WATCHDOG_RESET] = "WATCHDOG_RESET", [APP_FAULT_FLASH_CRC] = "FLASH_CRC",
    [APP_FAULT_ENCODER_DIRECTION] = "ENCODER_DIRECTION", [APP_FAULT_POLE_PAIRS] = "POLE_PAIRS",
    [APP_FAULT_PHASE_ORDER] = "PHASE_ORDER",
    [APP_FAULT_RSID_D_AXIS] = "RSID_D_AXIS",
    [APP_FAULT_COMM_TIMEOUT] = "COMM_TIMEOUT", [APP_FAULT_COMM_NO_ROTATION] = "COMM_NO_ROTATION",
    [APP_FAULT_COMM_IMPLAUSIBLE] = "COMM_IMPLAUSIBLE",
    [APP_FAULT_BUS_CHARGED] = "BUS_CHARGED",
    [APP_FAULT_RSID_INVERTER] = "RSID_INVERTER",
};

static const char *name_of(const char *const *names, size_t n, int v, const char *prefix, char *buf, size_t len)
{
    if (v >= 0 && (size_t)v < n && names[v] != NULL) {
        return names[v];
    }
    snprintf(buf, len, "%s_%d", prefix, v);
    return buf;
}

const char *summary_state_name(int state, char *buf, size_t len)
{
    return name_of(STATE_NAMES, sizeof STATE_NAMES / sizeof STATE_NAMES[0], state, "STATE", buf, len);
}

const char *summary_fault_name(int fault, char *buf, size_t len)
{
    return name_of(FAULT_NAMES, sizeof FAULT_NAMES / sizeof FAULT_NAMES[0], fault, "FAULT", buf, len);
}

const char *summary_warning_text(const sil_result_t *res, char *buf, size_t len)
{
    char fbuf[32];
    size_t n = 0u;
    buf[0] = '\0';
    if ((res->warnings & APP_WARN_STEP1_REFUSED) != 0u) {
        const int k = snprintf(buf, len, "STEP1_REFUSED (%s)", summary_fault_name(res->rsid_refusal, fbuf, sizeof fbuf));
        n = (k > 0) ? (size_t)k : 0u;
    }
    if (((res->warnings & APP_WARN_HOST_TIMEOUT) != 0u) && (n < len)) {
        const int k = snprintf(buf + n, len - n, "%sHOST_TIMEOUT (the link's host went quiet: ramped to zero, stopped)",
                               (n > 0u) ? ", " : "");
        n += (k > 0) ? (size_t)k : 0u;
    }
    if (((res->warnings & APP_WARN_OSCILLATION) != 0u) && (n < len)) {
        (void)snprintf(buf + n, len - n, "%sOSCILLATION (the current oscillated on step 2's L^: the told model since)",
                       (n > 0u) ? ", " : "");
    }
    return buf;
}

void summary_default_window(double duration_s, double *t0_s, double *t1_s)
{
    if (duration_s >= SUMMARY_PAPER_MIN_RUN_S) {
        *t0_s = SUMMARY_PAPER_T0_S;
        *t1_s = SUMMARY_PAPER_T1_S;
    } else {
        *t0_s = (1.0 - SUMMARY_TAIL_FRACTION) * duration_s;
        *t1_s = duration_s;   /* the last row is at duration - Ts */
    }
}

void summary_init(summary_t *s, const scenario_t *sc, double t0_s, double t1_s)
{
    memset(s, 0, sizeof *s);
    s->t0_s = t0_s;
    s->t1_s = t1_s;
    s->R_ohm = sc->plant.R_ohm;
    s->L_H = sc->plant.L_H;
    s->psif_Wb = sc->plant.psif_Wb;
    s->speed_abs_max = NAN;
    s->proposed = (sc->controller.method == SC_METHOD_PROPOSED);
}

static void add(summary_mean_t *m, double x)
{
    if (isfinite(x)) {
        m->sum += x;
        m->n += 1.0;
    }
}

static double mean(const summary_mean_t *m)
{
    return (m->n > 0.0) ? m->sum / m->n : NAN;
}

/* t as the CSV prints it: the window edges must cut the same rows metrics.py sees. */
static double printed_t(double t)
{
    char buf[TEXT_LEN];
    snprintf(buf, sizeof buf, CSV_T_FORMAT, t);
    return strtod(buf, NULL);
}

static int in_window(const summary_t *s, double t)
{
    if (fabs(t - s->t0_s) < EDGE_CHECK_S || fabs(t - s->t1_s) < EDGE_CHECK_S) {
        t = printed_t(t);
    }
    return (t >= s->t0_s) && (t < s->t1_s);
}

void summary_add(summary_t *s, const sil_row_t *r)
{
    if (!in_window(s, r->t_s)) {
        return;
    }
    s->rows++;
    const double e_te = r->te_Nm - r->te_ref_Nm;
    const double e_psi = r->psi_Wb - r->psi_ref_Wb;
    const double e_w = r->speed_rpm - r->speed_ref_rpm;
    add(&s->te_abs, fabs(e_te));
    add(&s->te_sq, e_te * e_te);
    add(&s->psi_abs, fabs(e_psi));
    add(&s->psi_rel, (r->psi_ref_Wb > 0.0) ? fabs(e_psi) / r->psi_ref_Wb : NAN);
    add(&s->speed, e_w);
    if (isfinite(e_w) && !(fabs(e_w) <= s->speed_abs_max)) {
        s->speed_abs_max = fabs(e_w);
    }
    add(&s->id, r->id_A);
    add(&s->iq, r->iq_A);
    add(&s->R_rel, (r->R_est_ohm - s->R_ohm) / s->R_ohm);
    add(&s->L_rel, (r->L_est_H - s->L_H) / s->L_H);
    add(&s->psif_rel, (r->psif_est_Wb - s->psif_Wb) / s->psif_Wb);
    if (!s->proposed || ((int)r->est_src == (int)EST_SRC_TOLD)) {
        s->told_rows++;
        const uint16_t bit = est_hold_reason_bit((uint16_t)r->est_hold);
        for (int k = 0; s->proposed && (bit != 0u) && (k < SUMMARY_HOLD_BITS); k++) {
            if (bit == (uint16_t)(1u << k)) {
                s->reason_rows[k]++;
            }
        }
    }
}

/* The most frequent reason of the proposed method's rows on the told model ("" for none). */
static const char *hold_reason(const summary_t *s)
{
    uint32_t best = 0u;
    uint16_t bit = 0u;
    for (int k = 0; k < SUMMARY_HOLD_BITS; k++) {
        if (s->reason_rows[k] > best) {
            best = s->reason_rows[k];
            bit = (uint16_t)(1u << k);
        }
    }
    return est_hold_name(bit);
}

static void put_str(FILE *f, const char *key, const char *text)
{
    fprintf(f, "\"%s\": ", key);
    json_string(f, text);
    fputs(", ", f);
}

void summary_write_json(FILE *f, const summary_t *s, const scenario_t *sc, const sil_result_t *res,
                        const char *scenario_path, const char *id)
{
    char buf[TEXT_LEN];
    fputc('{', f);
    if (id != NULL) {
        put_str(f, "id", id);
    }
    put_str(f, "scenario", scenario_path);
    put_str(f, "method", (sc->controller.method == SC_METHOD_PROPOSED) ? "proposed" : "conventional");
    json_num(f, "plant.R_ohm", sc->plant.R_ohm, ", ");
    json_num(f, "plant.L_H", sc->plant.L_H, ", ");
    json_num(f, "plant.psif_Wb", sc->plant.psif_Wb, ", ");
    json_num(f, "controller.R_ohm", sc->controller.R_ohm, ", ");
    json_num(f, "controller.L_H", sc->controller.L_H, ", ");
    json_num(f, "controller.psif_Wb", sc->controller.psif_Wb, ", ");
    json_num(f, "window_t0_s", s->t0_s, ", ");
    json_num(f, "window_t1_s", s->t1_s, ", ");
    json_num(f, "window_rows", (double)s->rows, ", ");
    json_num(f, "periods", (double)res->periods, ", ");
    json_num(f, "final_state", (double)res->final_state, ", ");
    put_str(f, "final_state_name", summary_state_name(res->final_state, buf, sizeof buf));
    json_num(f, "final_fault", (double)res->final_fault, ", ");
    put_str(f, "fault_name", summary_fault_name(res->final_fault, buf, sizeof buf));
    json_num(f, "warnings", (double)res->warnings, ", ");
    char wbuf[SUMMARY_WARNING_LEN];
    put_str(f, "warning", summary_warning_text(res, wbuf, sizeof wbuf));
    json_num(f, "t_run_s", res->t_run_s, ", ");
    json_num(f, "max_abs_i_A", res->max_abs_i_A, ", ");
    json_num(f, "te_err_Nm", mean(&s->te_abs), ", ");
    json_num(f, "te_ripple_Nm", sqrt(mean(&s->te_sq)), ", ");
    json_num(f, "psi_err_Wb", mean(&s->psi_abs), ", ");
    json_num(f, "psi_err_pct", PERCENT * mean(&s->psi_rel), ", ");
    json_num(f, "speed_err_rpm", mean(&s->speed), ", ");
    json_num(f, "speed_err_max_rpm", s->speed_abs_max, ", ");
    json_num(f, "id_A", mean(&s->id), ", ");
    json_num(f, "iq_A", mean(&s->iq), ", ");
    const double held = (s->rows > 0u) ? (double)s->told_rows / (double)s->rows : NAN;
    put_str(f, "method_ran", (s->rows == 0u) ? "" : ((held > SUMMARY_METHOD_RAN_SHARE) ? "conventional" : "proposed"));
    json_num(f, "held_share", held, ", ");
    put_str(f, "hold_reason", hold_reason(s));
    json_num(f, "R_err_pct", PERCENT * mean(&s->R_rel), ", ");
    json_num(f, "L_err_pct", PERCENT * mean(&s->L_rel), ", ");
    json_num(f, "psif_err_pct", PERCENT * mean(&s->psif_rel), "}\n");
}
