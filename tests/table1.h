/*
 * table1.h - the paper's Table I motor on the simulated board, for tests
 * that build the board themselves: the values drive_sil gives the plant
 * by default (tools/sil/sil_board.h: the drive's parameter set, in the
 * double the SIL reads), so the motor data keeps one home. Tests that
 * include it link "silrun firmware sim control".
 */
#ifndef TABLE1_H
#define TABLE1_H

#include "plant.h"
#include "sil_board.h"

/* The Table I motor, shaft at rest and free. */
static inline plant_cfg_t table1_plant(void)
{
    hal_sim_cfg_t hc;
    sil_board_default(&hc);
    return hc.plant;
}

#endif /* TABLE1_H */
