/* sil_board.c - the simulated board from a scenario; see sil_board.h. */
#include "sil_board.h"


void sil_board_from(const scenario_t *sc, hal_sim_cfg_t *hc)
{
    hal_sim_default_cfg(hc);
    scenario_map(sc, SC_TO_SIM, hc, hc->inv.Ts_s);
}

void sil_board_default(hal_sim_cfg_t *hc)
{
    static scenario_t sc; /* large: not on the stack */
    scenario_defaults(&sc);
    sil_board_from(&sc, hc);
}
