/* nv_params.c - the parameter store's blocks and the parameter set; see
 * nv_params.h. Start-up and background code: runs from flash. */
#include "nv_params.h"

#define NOT_LISTED 0xFFFFu

/* The list's parameter whose key's id is id, or NOT_LISTED. */
static uint16_t listed(const nv_param_list_t *list, uint16_t id)
{
    uint16_t k;

    for (k = 0u; k < list->count; k++) {
        if (nv_key_id(list->key(k)) == id) {
            return k;
        }
    }
    return NOT_LISTED;
}

nv_status_t nv_params_load(const nv_dev_t *dev, const nv_param_list_t *list, drive_params_t *p, nv_pair_t *pairs,
                           uint16_t *taken)
{
    uint16_t n = 0u;
    uint16_t j;
    nv_status_t st = nv_load(dev, pairs, NV_PAIRS_MAX, &n);

    *taken = 0u;
    if (st != NV_OK) {
        return st;
    }
    for (j = 0u; j < n; j++) {   /* all checked before one is set: all or none */
        const uint16_t k = listed(list, pairs[j].id);
        if ((k == NOT_LISTED) || !list->ok(k, pairs[j].value)) {
            return NV_INVALID;
        }
    }
    for (j = 0u; j < n; j++) {
        (void)list->set(p, listed(list, pairs[j].id), pairs[j].value);
    }
    *taken = n;
    return NV_OK;
}

nv_status_t nv_params_save(const nv_dev_t *dev, const nv_param_list_t *list, const drive_params_t *p,
                           nv_pair_t *pairs, uint16_t *buf)
{
    uint16_t k;

    if ((list->count == 0u) || (list->count > NV_PAIRS_MAX)) {
        return NV_INVALID;
    }
    for (k = 0u; k < list->count; k++) {
        pairs[k].id = nv_key_id(list->key(k));
        pairs[k].value = list->get(p, k);
    }
    return nv_save(dev, pairs, list->count, buf);
}
