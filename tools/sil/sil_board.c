/* sil_board.c - the simulated board from a scenario; see sil_board.h. */
#include "sil_board.h"
#include "sim_units.h"


void sil_board_from(const scenario_t *sc, hal_sim_cfg_t *hc)
{
    hal_sim_default_cfg(hc);
    hc->plant.R_Ohm = sc->plant.R_ohm;
    hc->plant.L_H = sc->plant.L_H;
    hc->plant.psi_f_Wb = sc->plant.psif_Wb;
    hc->plant.pole_pairs = sc->plant.pole_pairs;
    hc->plant.J_kgm2 = sc->plant.J_kgm2;
    hc->plant.B_Nms = sc->plant.B_Nms;
    hc->plant.speed_held = (sc->plant.speed_held != 0u);
    hc->plant.omega0_m_rad_s = sc->plant.speed0_rpm / SIM_RPM_PER_RAD_S;
    hc->enc_offset_el_rad = sc->plant.encoder_offset_el_rad;
    hc->inv.model = (sc->plant.model == SC_MODEL_SWITCHING) ? INV_SWITCHING : INV_AVERAGED;
    hc->inv.vdc_V = sc->plant.vdc_V;
    hc->inv.deadtime_s = sc->plant.deadtime_s;
    hc->inv.device_drop_V = sc->plant.device_drop_V;
    hc->inv.substep_max_s = sc->plant.substep_s;
    hc->sens.enc_lines = sc->plant.encoder_lines;
    hc->sens.adc_full_scale_A = sc->plant.adc_full_scale_A;
    hc->sens.adc_offset_a_A = sc->plant.adc_offset_a_A;
    hc->sens.adc_offset_b_A = sc->plant.adc_offset_b_A;
    hc->sens.adc_noise_A = sc->plant.adc_noise_A;
    hc->sens.seed = sc->plant.seed;
    hc->trip_current_A = sc->plant.trip_A;
    hc->enc_reversed = (sc->plant.encoder_direction == SC_DIRECTION_REVERSED);
    hc->phases_acb = (sc->plant.phase_order == SC_PHASES_ACB);
}

void sil_board_default(hal_sim_cfg_t *hc)
{
    static scenario_t sc; /* large: not on the stack */
    scenario_defaults(&sc);
    sil_board_from(&sc, hc);
}
