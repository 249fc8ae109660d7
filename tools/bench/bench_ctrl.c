/* bench_ctrl.c STEPS [conventional|proposed|proposed_track_R] - drives ctrl_step() in speed
 * mode at 500 r/min with 4 N m worth of current, for tools/bench/bench_ctrl.sh
 * (callgrind). Inputs are synthesised: a counting encoder and the currents
 * of the Table I motor's rotor-frame model, exact over the period, fed the
 * voltage the controller realises (a fixed current phasor that ignored the
 * voltage kept both methods on the hexagon limit every period: flags 3).
 * The first TORQUE_STEPS run in torque mode at 4 N m, so the speed PI
 * starts from it (bumpless) and holds it at zero speed error: the normal
 * path every period. proposed: step 2 from the start (est_start_trusted with
 * the nominal R), so every period runs observer, estimator and the
 * observer-based model; proposed_track_R: the same with R^ tracked by the
 * d-current injection (est_cfg_t.track_R, control/r_tracking_design.md).
 * Host only. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <complex.h>
#include <math.h>

#include "ctrl.h"

#define TS_S        1e-4
#define POLE_PAIRS  3u
#define LINES       2500u
#define SPEED_RPM   500.0
#define IQ_A        3.7
#define TE_NM       4.0       /* 1.5 p psi_f IQ_A */
#define PLANT_R_OHM       3.0
#define PLANT_L_H         0.011
#define PLANT_PSI_F_WB    0.24
#define TORQUE_STEPS 200L
#define PI_D        3.14159265358979323846
#define R_MIN_OHM   0.6f   /* R^ band, [0.2, 2] x nominal */
#define R_MAX_OHM   6.0f

static ctrl_t c;

/* The controller of the bench (argv[2]: conventional, proposed or
 * proposed_track_R) into c; 0, or 1 with the refusal named. */
static int bench_init(int argc, char **argv, int *proposed)
{
    const ctrl_cfg_t cfg = {
        .Ts_s = (float)TS_S, .R_Ohm = 3.0f, .L_H = 0.011f, .psi_f_Wb = 0.24f,
        .pole_pairs = POLE_PAIRS, .enc_lines = LINES, .enc_offset_el_rad = 0.0f,
        .enc_pll_bw_rad_s = 500.0f, .speed_kp_Nms_rad = 0.3f, .speed_ki_Nm_rad = 20.0f,
        .te_max_Nm = 12.0f, .i_max_A = 30.0f, .u_max_V = 311.0f,
        .omega_max_el_rad_s = 2000.0f, .psi_max_Wb = 0.5f,
        .osc_i_min_A = 12.0f * 15.0f / 2048.0f, /* the oscillation watch: drive_trip_margin_A on the board */
    };
    const int track_R = (argc > 2) && (strcmp(argv[2], "proposed_track_R") == 0);
    *proposed = track_R || ((argc > 2) && (strcmp(argv[2], "proposed") == 0));
    ctrl_cfg_t full = cfg;
    est_told_t told;
    smo_gains_t g;
    ctrl_cfg_told(&full, &told);
    (void)est_obs_gains(&told, SMO_EF_MAX_DEFAULT_V, &g);
    est_cfg_defaults(&full.est_cfg, &told, &g, R_MIN_OHM, R_MAX_OHM);
    full.est_cfg.track_R = track_R ? EST_TRACK_R_ON : EST_TRACK_R_OFF;
    if (ctrl_init(&c, &full) != CTRL_CFG_OK) {
        fprintf(stderr, "bench_ctrl: ctrl_init refused the proposed method's settings\n");
        return 1;
    }
    if (*proposed && (!ctrl_set_method(&c, CTRL_METHOD_PROPOSED) || !est_start_trusted(ctrl_est_rw(&c), full.R_Ohm))) {
        fprintf(stderr, "bench_ctrl: proposed method unavailable\n");
        return 1;
    }
    return 0;
}

int main(int argc, char **argv)
{
    const long n = (argc > 1) ? atol(argv[1]) : 10000;
    const double w_m = SPEED_RPM * 2.0 * PI_D / 60.0;
    const ctrl_ref_t ref = { (float)w_m, 0.0f, 0.0f, 0.0f };
    ctrl_out_t out;
    double sum = 0.0;
    int proposed;

    if (bench_init(argc, argv, &proposed) != 0) {
        return 1;
    }
    const ctrl_ref_t ref_te = { 0.0f, (float)TE_NM, 0.0f, 0.0f };
    const double w_e = POLE_PAIRS * w_m;
    double id = 0.0;
    double iq = IQ_A;
    ctrl_set_mode(&c, CTRL_MODE_TORQUE);
    ctrl_set_ref(&c, &ref_te);
    for (long k = 0; k < n; k++) {
        const double th_m = fmod(w_m * TS_S * (double)k, 2.0 * PI_D);
        const double th = POLE_PAIRS * th_m;
        const dq_t u = c.u_applied_V; /* computed last period, applied over [k, k+1] */
        ctrl_in_t in;
        if (k == TORQUE_STEPS) {
            ctrl_set_mode(&c, CTRL_MODE_SPEED);
            ctrl_set_ref(&c, &ref);
        }
        /* i_ab = inverse Park of i_dq at th (amplitude-invariant) */
        in.ia_A = (float)(id * cos(th) - iq * sin(th));
        in.ib_A = (float)(id * cos(th - 2.0 * PI_D / 3.0) - iq * sin(th - 2.0 * PI_D / 3.0));
        in.vdc_V = 311.0f;
        in.enc_count = (uint32_t)(th_m / (2.0 * PI_D) * 4.0 * LINES) % (4u * LINES);
        ctrl_step(&c, &in, &out);
        sum += out.duty[0];
        {
            /* exact over the period (control/discrete_model_design.md): i' = Phi i + g_u u + g_c (-j w psi_f) */
            const double complex i0 = id + I * iq;
            const double rho = exp(-TS_S * PLANT_R_OHM / PLANT_L_H);
            const double turn = w_e * TS_S;
            const double complex phi = rho * cexp(-I * turn);
            const double complex g_u = (1.0 - rho) / PLANT_R_OHM * cexp(-0.5 * I * turn);
            const double complex g_c = (1.0 - phi) / (PLANT_R_OHM + I * w_e * PLANT_L_H);
            const double complex i1 = phi * i0 + g_u * ((double)u.d + I * (double)u.q) + g_c * (-I * w_e * PLANT_PSI_F_WB);
            id = creal(i1);
            iq = cimag(i1);
        }
    }
    printf("bench_ctrl: %s, %ld steps, mean duty a %.4f, flags %u, L^ %.5f H, Te* %.3f N m, iq %.3f A\n",
           proposed ? "proposed" : "conventional", n, sum / (double)n, out.flags, (double)est_output(ctrl_est(&c))->L_H,
           (double)c.mon.te_ref_Nm, iq);
    return 0;
}
