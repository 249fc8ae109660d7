/* nv_params.c - the parameter store's blocks and the parameter set; see
 * nv_params.h. Start-up and background code: runs from flash. */
#include "nv_params.h"

#include "crc32.h"

uint16_t nv_params_table_id(const nv_param_list_t *list)
{
    uint32_t crc = 0UL;
    uint16_t k;

    for (k = 0u; k < list->count; k++) {
        const uint16_t id = nv_key_id(list->key(k));
        crc = crc32_prime_words(crc, &id, 1UL);
    }
    return nv_crc_fold(crc);
}

/* The list's parameter whose key's id is id, or NV_PARAMS_NOT_LISTED. */
static uint16_t listed(const nv_param_list_t *list, uint16_t id)
{
    uint16_t k;

    for (k = 0u; k < list->count; k++) {
        if (nv_key_id(list->key(k)) == id) {
            return k;
        }
    }
    return NV_PARAMS_NOT_LISTED;
}

uint16_t nv_params_of(const nv_param_list_t *list, const uint16_t *buf, uint16_t j)
{
    return listed(list, nv_block_get(buf, j).id);
}

uint16_t nv_params_refused(const nv_param_list_t *list, const uint16_t *buf, uint16_t n)
{
    uint16_t j;

    for (j = 0u; j < n; j++) {
        const uint16_t k = nv_params_of(list, buf, j);
        if ((k == NV_PARAMS_NOT_LISTED) || !list->ok(k, nv_block_get(buf, j).value)) {
            break;
        }
    }
    return j;
}

nv_status_t nv_params_read(const nv_dev_t *dev, const nv_param_list_t *list, uint16_t *buf, uint16_t *n)
{
    const nv_status_t st = nv_load(dev, nv_params_table_id(list), buf, n);

    if ((st == NV_OK) && (nv_params_refused(list, buf, *n) < *n)) {
        *n = 0u;
        return NV_INVALID;
    }
    return st;
}

nv_status_t nv_params_load(const nv_dev_t *dev, const nv_param_list_t *list, drive_params_t *p, uint16_t *buf,
                           uint16_t *taken)
{
    uint16_t n = 0u;
    uint16_t j;
    const nv_status_t st = nv_params_read(dev, list, buf, &n);

    for (j = 0u; j < n; j++) {   /* all checked by the read: all or none */
        (void)list->set(p, nv_params_of(list, buf, j), nv_block_get(buf, j).value);
    }
    *taken = n;
    return st;
}

nv_status_t nv_params_save(const nv_dev_t *dev, const nv_param_list_t *list, const drive_params_t *p,
                           uint16_t *buf)
{
    uint16_t k;

    if ((list->count == 0u) || (list->count > NV_PAIRS_MAX)) {
        return NV_INVALID;
    }
    for (k = 0u; k < list->count; k++) {
        nv_pair_t pair;
        pair.id = nv_key_id(list->key(k));
        pair.value = list->get(p, k);
        nv_block_put(buf, k, pair);
    }
    return nv_save(dev, nv_params_table_id(list), list->count, buf);
}
