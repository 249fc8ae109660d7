/*
 * link_nv.h - the link's parameters (link_params.h) in the parameter store
 * (nv_params.h, nv_store.h): the one list of saved parameters, an adapter
 * over the link's table walked by index (LINK_NV_PARAMS: its keys, bounds
 * and places in drive_params_t; the block's table id follows the table,
 * so a table changed by an update reads an older block as NV_INVALID),
 * and the store's state the link shows as `nv_status` and acts on with
 * the action save (link_protocol.md, "Parameters").
 *
 * Contexts: link_nv_load at start-up, before the ISR is attached;
 * link_nv_ask from the link (link_poll, background); link_nv_save from
 * the background loop with the control ISR held off (hal_isr_pause on the
 * board, between periods in the SIL), the outputs off (the drive
 * stopped), never from the ISR: an erase holds the CPU for about a second.
 */
#ifndef LINK_NV_H
#define LINK_NV_H

#include <stdbool.h>
#include <stdint.h>

#include "drive_params.h"
#include "nv_params.h"

/* The link's variable nv_status: what the store holds and did. */
typedef enum {
    LINK_NV_NONE = 0,           /* no parameter store on this drive (the action save unknown) */
    LINK_NV_EMPTY = 1,          /* nothing saved: the image's values */
    LINK_NV_VALID = 2,          /* the saved values taken at start-up */
    LINK_NV_INVALID = 3,        /* a saved block failed its check (CRC, table, a bound): the image's values */
    LINK_NV_SAVING = 4,         /* a save asked for, not written yet */
    LINK_NV_SAVED = 5,          /* the parameters saved since start-up, read back from the flash */
    LINK_NV_SAVE_FAILED = 6     /* the flash refused the save or it did not read back, or the drive was
                                 * started before it ran: nothing new is saved */
} link_nv_status_t;
#define LINK_NV_STATUS_LAST LINK_NV_SAVE_FAILED

/* The store of the link's parameters: its sector and the one block buffer. */
typedef struct {
    nv_dev_t dev;
    uint16_t buf[NV_BLOCK_WORDS_MAX];   /* the block read at start-up, or the one being saved (RAM) */
    volatile uint16_t status;           /* link_nv_status_t: the link's nv_status */
    uint16_t taken;                     /* the saved values taken at start-up (LINK_NV_VALID) */
    volatile uint16_t asked;            /* 1: a save asked for (link_nv_ask), not done yet */
} link_nv_t;

/* The list a block of the drive holds: the link's parameter table, in its order. */
extern const nv_param_list_t LINK_NV_PARAMS;

/* Start-up or host: the store on the sector dev, nothing asked, status
 * LINK_NV_EMPTY until a load says otherwise. */
void link_nv_init(link_nv_t *s, const nv_dev_t *dev);

/* The status a load's result means (NV_OK: LINK_NV_VALID, NV_EMPTY:
 * LINK_NV_EMPTY, else LINK_NV_INVALID). Any context. */
uint16_t link_nv_status_of(nv_status_t loaded);

/* Start-up, before the ISR: the sector's newest block over *p (the board's
 * parameter set, its defaults in it), all of its values or none
 * (nv_params_load over LINK_NV_PARAMS); status and taken say what it took. */
nv_status_t link_nv_load(link_nv_t *s, drive_params_t *p);

/* Background (the link's action save, the drive stopped): a save asked
 * for, status LINK_NV_SAVING until link_nv_save runs. */
void link_nv_ask(link_nv_t *s);

/* Background: a save asked for and not yet done. */
bool link_nv_due(const link_nv_t *s);

/* Background, the control ISR held off (hal_isr_pause; the SIL between
 * periods): the asked save of every link parameter of *p as the sector's
 * newest block when stopped (the drive in INIT, IDLE or FAULT, read with
 * the ISR held off), else nothing written; status LINK_NV_SAVED or
 * LINK_NV_SAVE_FAILED. Returns nv_params_save's status (NV_WRITE_FAILED
 * when not stopped). */
nv_status_t link_nv_save(link_nv_t *s, const drive_params_t *p, bool stopped);

#endif /* LINK_NV_H */
