/*
 * nv_file.h - drive_sil --nv FILE: the parameter store's sector of the
 * simulated board (hal_sim_nv_image, hal.h's hal_nv_*) kept in FILE
 * between runs, as the board's flash keeps sector B between power cycles.
 * FILE holds the sector's HAL_SIM_NV_WORDS words, each low octet first
 * (an erased word: 0xFF 0xFF); no FILE is an erased sector, written as
 * one at the start. Before the run the sector's newest block
 * (firmware/params/nv_store.h) is applied as the board applies it at
 * start-up, a block of the link's parameter table (firmware/link/link_nv.h)
 * only: its values replace the [controller] keys of the same names (set,
 * origin "--nv FILE"), all or none; the run then starts from them. Every
 * write of the sector during the run (the link's save) writes FILE again,
 * whole, under a temporary name renamed over it. Host only.
 */
#ifndef NV_FILE_H
#define NV_FILE_H

#include <stddef.h>

#include "nv_store.h"
#include "scenario.h"

/* FILE into the sector (absent: erased, and FILE written so); then every
 * write of the sector rewrites FILE. 0, or -1 with err: FILE unreadable or
 * unwritable, or not a sector image (its size). */
int nv_file_open(const char *path, char *err, size_t errlen);

/* The sector's newest block applied to *sc (after the file and the
 * overrides, before scenario_finish): NV_OK with every pair taken, *sc
 * changed; NV_EMPTY, or NV_INVALID (the block, a block of another table, a
 * value its parameter's bounds or its scenario key refuse), *sc untouched.
 * msg: what was taken, in words, for stderr. */
nv_status_t nv_file_apply(scenario_t *sc, const char *path, char *msg, size_t len);

/* True when a write of FILE during the run failed (named on stderr then). */
int nv_file_failed(void);

#endif /* NV_FILE_H */
