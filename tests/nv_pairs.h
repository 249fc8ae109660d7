/*
 * nv_pairs.h - the tests' way to the parameter store (firmware/params/
 * nv_store.h) in pairs: n pairs saved as one block through the block
 * buffer (nv_block_put, nv_save), or the newest block's pairs read back
 * (nv_load, nv_block_get); and the block's CRC computed independently.
 * Header only, for the test runners.
 */
#ifndef NV_PAIRS_H
#define NV_PAIRS_H

#include <stddef.h>

#include "nv_store.h"

/* CRC32_PRIME computed here, independently of crc32.c: the octets of n
 * words, each low octet first, bit by bit (poly 0x04C11DB7, init 0, MSB
 * first, no reflection, no final XOR). */
static inline uint32_t nv_ref_crc(const uint16_t *w, size_t n)
{
    uint32_t c = 0;
    for (size_t k = 0; k < 2 * n; k++) {
        const uint32_t octet = (k % 2 == 0) ? (w[k / 2] & 0xFFu) : (uint32_t)(w[k / 2] >> 8);
        c ^= octet << 24;
        for (int b = 0; b < 8; b++) {
            c = (c & 0x80000000UL) ? (c << 1) ^ 0x04C11DB7UL : c << 1;
        }
    }
    return c;
}

/* n pairs (n <= NV_PAIRS_MAX; more: nv_save refuses them) saved as the
 * newest block of table; buf: NV_BLOCK_WORDS_MAX words. */
static inline nv_status_t nv_save_pairs(const nv_dev_t *dev, uint16_t table, const nv_pair_t *pairs, uint16_t n,
                                        uint16_t *buf)
{
    for (uint16_t k = 0; k < n && k < NV_PAIRS_MAX; k++) {
        nv_block_put(buf, k, pairs[k]);
    }
    return nv_save(dev, table, n, buf);
}

/* The newest block of table: its pairs into pairs[NV_PAIRS_MAX], their count into *n. */
static inline nv_status_t nv_load_pairs(const nv_dev_t *dev, uint16_t table, nv_pair_t *pairs, uint16_t *n)
{
    uint16_t buf[NV_BLOCK_WORDS_MAX];
    const nv_status_t st = nv_load(dev, table, buf, n);
    for (uint16_t k = 0; k < *n; k++) {
        pairs[k] = nv_block_get(buf, k);
    }
    return st;
}

#endif /* NV_PAIRS_H */
