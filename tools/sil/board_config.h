/*
 * board_config.h - `drive_sil --board-config DIR` (`make board
 * MOTOR=FILE.ini`): the F28335 image's configuration from the motor file
 * a run reads, resolved as a run resolves it (scenario_finish: the same
 * key table, bounds and derivation; sil_drive_config: the same parameter
 * set and app configuration):
 *   DIR/drive_config.h     the image's configuration header. The board
 *                          facts the HAL builds from, as macros
 *                          (hal/f28335/board_hw.h takes them when
 *                          DRIVE_CONFIG is defined); every field of the
 *                          parameter set (DRIVE_CONFIG_PARAMS, applied at
 *                          the end of drive_params_board) and of the app's
 *                          configuration a scenario key sets
 *                          (DRIVE_CONFIG_APP, at the end of app_cfg_default)
 *   DIR/drive_config.json  every value the image holds, SI units, keyed by
 *                          the scenario key names, grouped: "controller"
 *                          (what the drive is told), "motor" (the ratings),
 *                          "identify", "run" (the start level, the bus
 *                          limit of levels 1-2, calibration, alignment),
 *                          "board" (the board facts under their [plant]
 *                          names: bus, ADC range, trip, encoder lines, dead
 *                          time); no plant: the image has none
 * A run's defaults are a simulation's (an ideal inverter, the paper's
 * timeline at build level 5); an image's are the bench's: the keys
 * board_config_bench() lists take the board's values unless the motor
 * file sets them. Host only.
 */
#ifndef BOARD_CONFIG_H
#define BOARD_CONFIG_H

#include <stddef.h>
#include <stdio.h>

#include "scenario.h"

/* After the file and the overrides, before scenario_finish: the keys the
 * file left unset whose simulation default is no board's take the board's
 * value: [plant] deadtime_s, adc_full_scale_A, trip_A (board_hw.h), [run]
 * level, calibrate (app_cfg_default) and align (the board's, or off when
 * the file tells [controller] encoder_offset_el_rad: a measured offset).
 * Returns 0, or -1 with err. */
int board_config_bench(scenario_t *sc, char *err, size_t errlen);

/* The finished scenario *sc (from scenario_path, with overrides[n_sets])
 * as the header into h and the JSON into js. 0, or -1 with err naming the
 * key (a board fact the F28335 cannot hold: a dead time beyond the dead
 * band's 10 bits). */
int board_config_write(FILE *h, FILE *js, const scenario_t *sc, const char *scenario_path,
                       const char *const *overrides, int n_sets, char *err, size_t errlen);

#endif /* BOARD_CONFIG_H */
