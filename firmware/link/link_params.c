/* link_params.c - the drive's parameters on the link; see link_params.h. */
#include "link_params.h"

#define LINK_PARAM_ROW(id, key, unit, type, field, lo, hi, lo_open) \
    { key, unit, (uint16_t)(type), offsetof(drive_params_t, field), lo, hi, lo_open },
const link_param_t LINK_PARAM_TABLE[LINK_PARAM_COUNT] = { LINK_PARAMS(LINK_PARAM_ROW) };
#undef LINK_PARAM_ROW

bool link_param_ok(uint16_t k, float v)
{
    const link_param_t *d = link_param(k);
    const bool above = d->lo_open ? (v > d->lo) : (v >= d->lo);
    if (!(mathx_isfinitef(v) && above && (v <= d->hi))) {
        return false;
    }
    if (d->type == (uint16_t)LINK_PARAM_U16) {
        const float whole = (float)(uint16_t)v; /* in range here: the cast is defined */
        return !(v > whole);                    /* v >= whole: a fraction is refused */
    }
    return true;
}

bool link_param_set(drive_params_t *p, uint16_t k, float v)
{
    const link_param_t *d = link_param(k);
    char *at = (char *)p + d->offset;
    if (!link_param_ok(k, v)) {
        return false;
    }
    if (d->type == (uint16_t)LINK_PARAM_U16) {
        *(uint16_t *)(void *)at = (uint16_t)v;
    } else {
        *(float *)(void *)at = v;
    }
    return true;
}
