/* nv_store.c - the parameter store's blocks in their sector; see
 * nv_store.h. Start-up and background code: runs from flash. */
#include "nv_store.h"

#include <string.h>

#include "crc32.h"

#define WORD_BITS 16u
#define WORD_MASK 0xFFFFUL
#define NAME_MAX_CHARS 64u           /* a key name's characters hashed at most */
#define CHUNK_WORDS 16u              /* words read at once (on the stack) */
#define BLOCK_WORDS(n) (NV_HEADER_WORDS + NV_PAIR_WORDS * (uint32_t)(n) + NV_CRC_WORDS)

typedef char nv_float_is_32_bits[(sizeof(float) == sizeof(uint32_t)) ? 1 : -1];

uint16_t nv_crc_fold(uint32_t crc)
{
    return (uint16_t)((crc >> WORD_BITS) ^ (crc & WORD_MASK));
}

uint16_t nv_key_id(const char *name)
{
    uint32_t crc = 0UL;
    uint16_t k;

    for (k = 0u; (k < NAME_MAX_CHARS) && (name[k] != '\0'); k++) {
        crc = crc32_prime_octet(crc, (uint16_t)name[k]);
    }
    return nv_crc_fold(crc);
}

static uint32_t float_bits(float v)
{
    uint32_t u;
    memcpy(&u, &v, sizeof u);
    return u;
}

static float bits_float(uint32_t u)
{
    float v;
    memcpy(&v, &u, sizeof v);
    return v;
}

/* A header's length word, when it is one: 6 + 3 n words, 1 <= n <= NV_PAIRS_MAX. */
static bool length_ok(uint16_t len)
{
    return (len >= BLOCK_WORDS(1u)) && (len <= NV_BLOCK_WORDS_MAX) &&
           (((uint16_t)(len - NV_HEADER_WORDS - NV_CRC_WORDS) % NV_PAIR_WORDS) == 0u);
}

/* The sector's form: the newest block's offset in *newest (NV_OK), where a
 * new one goes in *next; NV_EMPTY (all erased), NV_INVALID (a header that
 * is not one, a block past the end, written words after the blocks). */
static nv_status_t scan(const nv_dev_t *dev, uint32_t *newest, uint32_t *next)
{
    uint16_t w[CHUNK_WORDS];
    uint32_t at = 0UL;
    bool any = false;

    while ((at + NV_HEADER_WORDS <= dev->words) && dev->read(at, w, NV_HEADER_WORDS) && (w[0] != NV_ERASED)) {
        if ((w[0] != NV_MAGIC) || (w[1] != NV_VERSION) || !length_ok(w[2]) || (at + w[2] > dev->words)) {
            return NV_INVALID;
        }
        *newest = at;
        any = true;
        at += w[2];
    }
    *next = at;
    while (at < dev->words) {   /* the rest erased, the tail shorter than a header included */
        const uint32_t left = dev->words - at;
        const uint16_t n = (left < CHUNK_WORDS) ? (uint16_t)left : (uint16_t)CHUNK_WORDS;
        uint16_t k;
        if (!dev->read(at, w, n)) {
            return NV_INVALID;
        }
        for (k = 0u; k < n; k++) {
            if (w[k] != NV_ERASED) {
                return NV_INVALID;
            }
        }
        at += n;
    }
    return any ? NV_OK : NV_EMPTY;
}

/* The block's CRC32_PRIME over its header and pairs (len - NV_CRC_WORDS words). */
static uint32_t block_crc(const uint16_t *buf, uint16_t len)
{
    return crc32_prime_words(0UL, buf, (uint32_t)len - NV_CRC_WORDS);
}

nv_status_t nv_load(const nv_dev_t *dev, uint16_t table, uint16_t *buf, uint16_t *n)
{
    uint32_t newest = 0UL;
    uint32_t next = 0UL;
    uint16_t len;
    nv_status_t st = scan(dev, &newest, &next);

    *n = 0u;
    if (st != NV_OK) {
        return st;
    }
    (void)dev->read(newest + 2UL, &len, 1u);   /* its length: checked by the scan */
    if (!dev->read(newest, buf, len) ||
        ((((uint32_t)buf[len - 1u] << WORD_BITS) | buf[len - 2u]) != block_crc(buf, len)) ||
        (buf[3] != table)) {
        return NV_INVALID;
    }
    *n = (uint16_t)((len - NV_HEADER_WORDS - NV_CRC_WORDS) / NV_PAIR_WORDS);
    return NV_OK;
}

nv_pair_t nv_block_get(const uint16_t *buf, uint16_t k)
{
    const uint16_t *p = &buf[NV_HEADER_WORDS + NV_PAIR_WORDS * k];
    nv_pair_t pair;

    pair.id = p[0];
    pair.value = bits_float((uint32_t)p[1] | ((uint32_t)p[2] << WORD_BITS));
    return pair;
}

void nv_block_put(uint16_t *buf, uint16_t k, nv_pair_t pair)
{
    const uint32_t u = float_bits(pair.value);
    uint16_t *p = &buf[NV_HEADER_WORDS + NV_PAIR_WORDS * k];

    p[0] = pair.id;
    p[1] = (uint16_t)(u & WORD_MASK);
    p[2] = (uint16_t)(u >> WORD_BITS);
}

/* The header and CRC around the n pairs in buf; the block's length in words. */
static uint16_t seal(uint16_t table, uint16_t n, uint16_t *buf)
{
    const uint16_t len = (uint16_t)BLOCK_WORDS(n);
    uint32_t crc;

    buf[0] = NV_MAGIC;
    buf[1] = NV_VERSION;
    buf[2] = len;
    buf[3] = table;
    crc = block_crc(buf, len);
    buf[len - 2u] = (uint16_t)(crc & WORD_MASK);
    buf[len - 1u] = (uint16_t)(crc >> WORD_BITS);
    return len;
}

/* len words at off equal buf's. */
static bool reads_back(const nv_dev_t *dev, uint32_t off, const uint16_t *buf, uint16_t len)
{
    uint16_t w[CHUNK_WORDS];
    uint16_t done = 0u;

    while (done < len) {
        const uint16_t n = ((uint16_t)(len - done) < CHUNK_WORDS) ? (uint16_t)(len - done) : (uint16_t)CHUNK_WORDS;
        uint16_t k;
        if (!dev->read(off + done, w, n)) {
            return false;
        }
        for (k = 0u; k < n; k++) {
            if (w[k] != buf[done + k]) {
                return false;
            }
        }
        done = (uint16_t)(done + n);
    }
    return true;
}

nv_status_t nv_save(const nv_dev_t *dev, uint16_t table, uint16_t n, uint16_t *buf)
{
    uint32_t newest = 0UL;
    uint32_t next = 0UL;
    uint16_t len;
    bool erase;

    if ((n == 0u) || (n > NV_PAIRS_MAX)) {
        return NV_INVALID;
    }
    len = seal(table, n, buf);
    /* appended after the newest block while the sector is in form and has room; else from an erased sector */
    erase = (scan(dev, &newest, &next) == NV_INVALID) || (next + len > dev->words);
    if (erase) {
        next = 0UL;
    }
    if (!dev->write(next, buf, len, erase) || !reads_back(dev, next, buf, len)) {
        return NV_WRITE_FAILED;
    }
    return NV_OK;
}
