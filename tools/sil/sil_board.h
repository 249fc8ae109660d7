/*
 * sil_board.h - the simulated board's configuration (hal_sim_cfg_t: the
 * true motor and shaft, the inverter, the sensors) from a scenario's
 * [plant] keys. hal/sim keeps no motor data of its own: the motor and
 * the bus come from here, whose defaults are the scenario's, i.e. the
 * drive's one parameter set (firmware/params/drive_params.h through
 * tools/sil/scenario_keys.h's SC_PARAMS keys, read into double as the decimals
 * board_cfg.h spells). Host only.
 */
#ifndef SIL_BOARD_H
#define SIL_BOARD_H

#include "hal_sim.h"
#include "scenario.h"

/* The board of scenario *sc into *hc (every field the scenario has). */
void sil_board_from(const scenario_t *sc, hal_sim_cfg_t *hc);

/* The board of the default scenario into *hc: the paper's Table I motor
 * at rest on the nominal bus, as drive_sil simulates it (for tests that
 * build the simulated board themselves). */
void sil_board_default(hal_sim_cfg_t *hc);

#endif /* SIL_BOARD_H */
