/*
 * nv_params.h - the parameter store (nv_store.h) and the parameter set
 * (drive_params.h): which of the set's values a block holds, through an
 * enumerable list of parameters, each with its key name (a block's id is
 * nv_key_id of it), its bounds, and its place in drive_params_t. The
 * list is the link's parameter table (issue 29: the [controller] values an
 * operator writes over the link; drivetool save saves exactly those); this
 * file does not hold one. Pure.
 *
 * At start-up the board's defaults (drive_params_board) go first, then
 * nv_params_load puts the sector's newest block over them, all of its
 * pairs or none: a pair whose id names no parameter of the list, or whose
 * value its parameter's bounds refuse, makes the block NV_INVALID (a block
 * saved by another image, with another table), and the defaults stay. The
 * drive starts either way; the status is the caller's warning.
 */
#ifndef NV_PARAMS_H
#define NV_PARAMS_H

#include <stdbool.h>
#include <stdint.h>

#include "drive_params.h"
#include "nv_store.h"

/* The parameters a block may hold: 0 .. count - 1 (at most NV_PAIRS_MAX). */
typedef struct {
    uint16_t count;
    const char *(*key)(uint16_t k);                       /* its key name; its id: nv_key_id(key) */
    bool (*ok)(uint16_t k, float v);                      /* v within its bounds (a NaN never is) */
    float (*get)(const drive_params_t *p, uint16_t k);    /* its value in *p */
    bool (*set)(drive_params_t *p, uint16_t k, float v);  /* *p's value set; false (unchanged) when not ok */
} nv_param_list_t;

/* Start-up: the newest block of dev over *p, every pair on its parameter
 * of list (NV_OK, *taken its count), or *p unchanged (NV_EMPTY;
 * NV_INVALID: the block, or a pair the list does not take; *taken 0).
 * pairs: NV_PAIRS_MAX of scratch. */
nv_status_t nv_params_load(const nv_dev_t *dev, const nv_param_list_t *list, drive_params_t *p, nv_pair_t *pairs,
                           uint16_t *taken);

/* Background, the drive stopped: every parameter of list, its value in
 * *p, saved as the sector's newest block (nv_save: NV_OK, NV_WRITE_FAILED;
 * NV_INVALID for a list of none or more than NV_PAIRS_MAX). pairs:
 * NV_PAIRS_MAX, buf: NV_BLOCK_WORDS_MAX words of scratch in RAM. */
nv_status_t nv_params_save(const nv_dev_t *dev, const nv_param_list_t *list, const drive_params_t *p,
                           nv_pair_t *pairs, uint16_t *buf);

#endif /* NV_PARAMS_H */
