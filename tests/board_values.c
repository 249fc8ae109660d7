/*
 * board_values.c - what an image built by `make board` holds, read from
 * its own objects (the target's sources compiled against drive_config.h,
 * linked here without main.c): the app's configuration app_cfg_default()
 * gives, the parameter set drive_params_board() gives and the HAL's
 * register values of the board facts, printed as JSON under the names of
 * drive_config.json (tests/cli/test_board.py compares the two).
 * Built by tests/cli/module.mk as $(BOARD_OUT)/board_values.
 */
#include <stdio.h>

#include "app.h"
#include "board_cfg.h"
#include "drive_params.h"
#include "hal_f28335_cfg.h"

#define RPM_PER_RAD_S 9.54929658551372
#define ADC_HALF_RANGE_COUNTS 2048.0 /* +-full scale: half the 12-bit range */

static void num(const char *key, double v, const char *sep)
{
    printf("\"%s\": %.9g%s", key, v, sep);
}

int main(void)
{
    static app_cfg_t cfg;
    drive_params_t p;
    app_cfg_default(&cfg);
    drive_params_board(&p);
    (void)drive_params_derive(&p);
    const ctrl_cfg_t *k = &cfg.ctrl;

    printf("{\"controller\": {");
    num("R_ohm", (double)k->R_Ohm, ", ");
    num("L_H", (double)k->L_H, ", ");
    num("psif_Wb", (double)k->psi_f_Wb, ", ");
    num("pole_pairs", (double)k->pole_pairs, ", ");
    num("J_kgm2", (double)p.motor.J_kgm2, ", ");
    num("B_Nms", (double)p.motor.B_Nms, ", ");
    num("encoder_offset_el_rad", (double)k->enc_offset_el_rad, ", ");
    num("speed_kp_Nms_rad", (double)k->speed_kp_Nms_rad, ", ");
    num("speed_ki_Nm_rad", (double)k->speed_ki_Nm_rad, ", ");
    num("te_max_Nm", (double)k->te_max_Nm, ", ");
    num("i_limit_A", (double)k->i_lim_A, ", ");
    num("i_max_A", (double)cfg.prot.i_max_A, ", ");
    num("overspeed_rpm", (double)cfg.prot.speed_max_rad_s * RPM_PER_RAD_S, ", ");
    num("deadtime_s", (double)k->deadtime_s, "},\n");
    printf(" \"motor\": {");
    num("i_rated_A", (double)p.rating.i_rated_A, ", ");
    num("i_peak_A", (double)p.rating.i_peak_A, ", ");
    num("t_peak_s", (double)p.rating.t_peak_s, ", ");
    num("n_rated_rpm", (double)p.rating.n_rated_rad_s * RPM_PER_RAD_S, "},\n");
    printf(" \"run\": {");
    num("level", (double)cfg.lvl.level, ", ");
    num("level4_i_limit_A", (double)cfg.lvl.i_lim_4_A, ", ");
    num("level12_vdc_max_V", (double)cfg.lvl.vdc_max_12_V, ", ");
    printf("\"calibrate\": \"%s\", \"align\": \"%s\"},\n", cfg.calibrate ? "on" : "off", cfg.align ? "on" : "off");
    printf(" \"board\": {");
    num("vdc_V", (double)p.board.vdc_nominal_V, ", ");
    num("adc_full_scale_A", (double)F28335_I_A_PER_COUNT * ADC_HALF_RANGE_COUNTS, ", ");
    num("trip_A", (double)BOARD_HW_TRIP_A, ", ");
    num("encoder_lines", (double)(F28335_QPOSMAX + 1UL) / 4.0, ", ");
    num("deadtime_s", (double)F28335_DB_COUNTS / (double)F28335_TBCLK_HZ, "}}\n");
    return 0;
}
