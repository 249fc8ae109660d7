/* link_nv.c - the link's parameters in the parameter store; see link_nv.h.
 * Start-up and background code: runs from flash. */
#include "link_nv.h"

#include "link_params.h"

static const char *key(uint16_t k)
{
    return link_param(k)->key;
}

static float get(const drive_params_t *p, uint16_t k)
{
    return link_param_get(p, k);
}

const nv_param_list_t LINK_NV_PARAMS = { (uint16_t)LINK_PARAM_COUNT, key, link_param_ok, get, link_param_set };

typedef char link_nv_table_fits_a_block[(LINK_PARAM_COUNT <= NV_PAIRS_MAX) ? 1 : -1];

void link_nv_init(link_nv_t *s, const nv_dev_t *dev)
{
    s->dev = *dev;
    s->status = (uint16_t)LINK_NV_EMPTY;
    s->taken = 0u;
    s->asked = 0u;
}

uint16_t link_nv_status_of(nv_status_t loaded)
{
    if (loaded == NV_OK) {
        return (uint16_t)LINK_NV_VALID;
    }
    return (loaded == NV_EMPTY) ? (uint16_t)LINK_NV_EMPTY : (uint16_t)LINK_NV_INVALID;
}

nv_status_t link_nv_load(link_nv_t *s, drive_params_t *p)
{
    uint16_t taken = 0u;
    const nv_status_t st = nv_params_load(&s->dev, &LINK_NV_PARAMS, p, s->buf, &taken);

    s->taken = taken;
    s->status = link_nv_status_of(st);
    return st;
}

void link_nv_ask(link_nv_t *s)
{
    s->asked = 1u;
    s->status = (uint16_t)LINK_NV_SAVING;
}

bool link_nv_due(const link_nv_t *s)
{
    return s->asked != 0u;
}

nv_status_t link_nv_save(link_nv_t *s, const drive_params_t *p, bool stopped)
{
    const nv_status_t st = stopped ? nv_params_save(&s->dev, &LINK_NV_PARAMS, p, s->buf) : NV_WRITE_FAILED;

    s->asked = 0u;
    s->status = (st == NV_OK) ? (uint16_t)LINK_NV_SAVED : (uint16_t)LINK_NV_SAVE_FAILED;
    return st;
}
