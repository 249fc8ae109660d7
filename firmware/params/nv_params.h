/*
 * nv_params.h - the parameter store (nv_store.h) and the parameter set
 * (drive_params.h): which of the set's values a block holds, through an
 * enumerable list of parameters, each with its key name (a pair's id is
 * nv_key_id of it), its bounds, and its place in drive_params_t. The
 * drive's list is the link's parameter table (firmware/link/link_nv.h:
 * what drivetool save saves); this file holds none. Pure.
 *
 * A block is saved with the list's table id (nv_params_table_id: its keys
 * in their order) and read only by a list with the same id: a table that
 * gained, lost, renamed or reordered a parameter reads an older block as
 * NV_INVALID, never as values for the wrong parameters.
 *
 * At start-up the board's defaults (drive_params_board) go first, then
 * nv_params_load puts the sector's newest block over them, all of its
 * pairs or none: a block of another table, a pair whose id names no
 * parameter of the list, or whose value its parameter's bounds refuse,
 * makes the block NV_INVALID, and the defaults stay. The drive starts
 * either way; the status is the caller's warning.
 */
#ifndef NV_PARAMS_H
#define NV_PARAMS_H

#include <stdbool.h>
#include <stdint.h>

#include "drive_params.h"
#include "nv_store.h"

#define NV_PARAMS_NOT_LISTED 0xFFFFu   /* nv_params_of: the pair names no parameter of the list */

/* The parameters a block may hold: 0 .. count - 1 (at most NV_PAIRS_MAX). */
typedef struct {
    uint16_t count;
    const char *(*key)(uint16_t k);                       /* its key name; its id: nv_key_id(key) */
    bool (*ok)(uint16_t k, float v);                      /* v within its bounds (a NaN never is) */
    float (*get)(const drive_params_t *p, uint16_t k);    /* its value in *p */
    bool (*set)(drive_params_t *p, uint16_t k, float v);  /* *p's value set; false (unchanged) when not ok */
} nv_param_list_t;

/* The list's table id: CRC32_PRIME of its keys' ids (nv_key_id, in the
 * list's order, each a 16-bit word low octet first), folded
 * (nv_crc_fold). Any context. */
uint16_t nv_params_table_id(const nv_param_list_t *list);

/* Start-up or background: dev's newest block into buf (NV_BLOCK_WORDS_MAX
 * words), *n its pairs, when it is list's: its table id, every pair's id a
 * parameter of list and its value within that parameter's bounds (NV_OK);
 * else NV_EMPTY or NV_INVALID, *n 0. */
nv_status_t nv_params_read(const nv_dev_t *dev, const nv_param_list_t *list, uint16_t *buf, uint16_t *n);

/* The parameter of list that pair j of the block in buf names
 * (NV_PARAMS_NOT_LISTED: none; after nv_params_read's NV_OK one always
 * does). Any context. */
uint16_t nv_params_of(const nv_param_list_t *list, const uint16_t *buf, uint16_t j);

/* The first of the n pairs of the block in buf (nv_load's) that names no
 * parameter of list or whose value that parameter's bounds refuse; n when
 * none does. Any context. */
uint16_t nv_params_refused(const nv_param_list_t *list, const uint16_t *buf, uint16_t n);

/* Start-up: the newest block of dev over *p, every pair on its parameter
 * of list (NV_OK, *taken its count), or *p unchanged (nv_params_read's
 * NV_EMPTY or NV_INVALID; *taken 0). buf: NV_BLOCK_WORDS_MAX words of
 * scratch. */
nv_status_t nv_params_load(const nv_dev_t *dev, const nv_param_list_t *list, drive_params_t *p, uint16_t *buf,
                           uint16_t *taken);

/* Background, the drive stopped: every parameter of list, its value in
 * *p, saved as the sector's newest block of list's table (nv_save: NV_OK,
 * NV_WRITE_FAILED; NV_INVALID for a list of none or more than
 * NV_PAIRS_MAX). buf: NV_BLOCK_WORDS_MAX words of scratch in RAM. */
nv_status_t nv_params_save(const nv_dev_t *dev, const nv_param_list_t *list, const drive_params_t *p,
                           uint16_t *buf);

#endif /* NV_PARAMS_H */
