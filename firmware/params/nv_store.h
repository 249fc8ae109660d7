/*
 * nv_store.h - the parameter store: the parameters an operator saved
 * (drivetool save: the link's parameters), kept in one reserved flash
 * sector (the F28335's sector B: f28335_flash.cmd; the SIL's drive_sil --nv
 * FILE) as blocks of (id, value) pairs, the newest last, read at start-up,
 * where a valid newest block replaces the image's defaults of the
 * parameters it holds. The sector is reached through the HAL's
 * hal_nv_read / hal_nv_write, or a test's array (nv_dev_t). Pure.
 *
 * A block, in 16-bit words (the F28335 flash's unit; the SIL's file holds
 * each word low octet first):
 *   0         NV_MAGIC, 0x4E56
 *   1         NV_VERSION, 1: the format below
 *   2         the block's length in words, 5 + 3 n for n pairs (1 .. NV_PAIRS_MAX)
 *   3 + 3 k   pair k's id: nv_key_id() of the parameter's key name
 *   4 + 3 k   its value, IEEE 754 binary32: the low word ...
 *   5 + 3 k   ... and the high word
 *   3 + 3 n   CRC32_PRIME (crc32.h) of words 0 .. 2 + 3 n: the low word ...
 *   4 + 3 n   ... and the high word
 * The sector holds blocks back to back from word 0, then erased words
 * (0xFFFF) to its end. A save appends a block after the newest, or erases
 * the sector first when the block does not fit or the sector is not in
 * that form; a flash sector takes few erases (the F28335's: 100 cycles
 * guaranteed, SPRS439 "Flash endurance"), and 32K words hold 799 saves of
 * 12 parameters between two. Reading it:
 *   NV_EMPTY    every word erased (a new board, or an image programmed
 *               with the whole flash erased)
 *   NV_INVALID  a block header that is not one (magic, version, length),
 *               a newest block whose CRC fails (one flipped bit, a save cut
 *               short by a power loss), or written words after the blocks
 *   NV_OK       the newest block's pairs
 * Ids are 16-bit hashes of the key names, so a block stays readable when
 * the table of parameters is reordered or grows; an id the reader does
 * not know, or a value outside its parameter's bounds, is the reader's to
 * refuse (the whole block: NV_INVALID).
 */
#ifndef NV_STORE_H
#define NV_STORE_H

#include <stdbool.h>
#include <stdint.h>

#define NV_MAGIC 0x4E56u
#define NV_VERSION 1u
#define NV_HEADER_WORDS 3u           /* magic, version, length */
#define NV_PAIR_WORDS 3u             /* id, value low, value high */
#define NV_CRC_WORDS 2u
#define NV_PAIRS_MAX 32u             /* pairs a block holds at most */
#define NV_BLOCK_WORDS_MAX (NV_HEADER_WORDS + NV_PAIR_WORDS * NV_PAIRS_MAX + NV_CRC_WORDS)
#define NV_ERASED 0xFFFFu            /* an erased flash word */

typedef struct {
    uint16_t id;                     /* nv_key_id() of the parameter's key name */
    float value;                     /* in the key's unit */
} nv_pair_t;

typedef enum {
    NV_OK = 0,                       /* the newest block read, or a save read back */
    NV_EMPTY = 1,                    /* nothing saved: the sector erased */
    NV_INVALID = 2,                  /* the sector holds no valid newest block: see above */
    NV_WRITE_FAILED = 3              /* a save the flash refused, or that did not read back */
} nv_status_t;

/* The sector: its size and its reads and writes (hal_nv_read, hal_nv_write,
 * hal_nv_words on the board and in the SIL). */
typedef struct {
    uint32_t words;                                                   /* [words] */
    bool (*read)(uint32_t off, uint16_t *dst, uint16_t n);            /* n words from word off */
    bool (*write)(uint32_t off, const uint16_t *src, uint16_t n, bool erase_first); /* program at off */
} nv_dev_t;

/* A parameter's id: CRC32_PRIME of its key name's characters, the two
 * halves XORed. Any context. */
uint16_t nv_key_id(const char *name);

/* Start-up or background: the newest block's pairs into pairs[max] and
 * their count into *n (0 unless NV_OK). */
nv_status_t nv_load(const nv_dev_t *dev, nv_pair_t *pairs, uint16_t max, uint16_t *n);

/* Background, the drive stopped: n pairs (1 .. NV_PAIRS_MAX) saved as the
 * newest block, appended or into the sector erased first; NV_OK when the
 * flash took it and it reads back word for word, else NV_WRITE_FAILED
 * (NV_INVALID for no pairs or too many). buf: NV_BLOCK_WORDS_MAX words of
 * scratch in RAM (the flash API reads its source from RAM). */
nv_status_t nv_save(const nv_dev_t *dev, const nv_pair_t *pairs, uint16_t n, uint16_t *buf);

#endif /* NV_STORE_H */
