/*
 * nv_ram_sector.h - a parameter sector for the test runners
 * (firmware/params/nv_store.h's nv_dev_t) in an array, with the flash's
 * rules: an erase sets every word to 0xFFFF, a program only clears bits.
 * Header only; a runner that includes it uses it.
 */
#ifndef NV_RAM_SECTOR_H
#define NV_RAM_SECTOR_H

#include <stdbool.h>
#include <stdint.h>

#include "nv_store.h"

#define NV_RAM_SECTOR_WORDS 256u

static uint16_t nv_ram_sector[NV_RAM_SECTOR_WORDS];

static inline void nv_ram_erase(void)
{
    for (uint32_t k = 0; k < NV_RAM_SECTOR_WORDS; k++) {
        nv_ram_sector[k] = NV_ERASED;
    }
}

static inline bool nv_ram_read(uint32_t off, uint16_t *dst, uint16_t n)
{
    if (off + n > NV_RAM_SECTOR_WORDS) {
        return false;
    }
    for (uint16_t k = 0; k < n; k++) {
        dst[k] = nv_ram_sector[off + k];
    }
    return true;
}

static inline bool nv_ram_write(uint32_t off, const uint16_t *src, uint16_t n, bool erase_first)
{
    if (off + n > NV_RAM_SECTOR_WORDS) {
        return false;
    }
    if (erase_first) {
        nv_ram_erase();
    }
    for (uint16_t k = 0; k < n; k++) {
        nv_ram_sector[off + k] &= src[k];
    }
    return true;
}

static const nv_dev_t NV_RAM_DEV = { NV_RAM_SECTOR_WORDS, nv_ram_read, nv_ram_write };

#endif /* NV_RAM_SECTOR_H */
