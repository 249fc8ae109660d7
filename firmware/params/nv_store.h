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
 *   1         NV_VERSION, 2: the format below
 *   2         the block's length in words, 6 + 3 n for n pairs (1 .. NV_PAIRS_MAX)
 *   3         the table: the id of the list of parameters it was saved
 *             with (nv_params_table_id); a reader with another list reads
 *             the block as NV_INVALID
 *   4 + 3 k   pair k's id: nv_key_id() of the parameter's key name
 *   5 + 3 k   its value, IEEE 754 binary32: the low word ...
 *   6 + 3 k   ... and the high word
 *   4 + 3 n   CRC32_PRIME (crc32.h) of words 0 .. 3 + 3 n: the low word ...
 *   5 + 3 n   ... and the high word
 * The sector holds blocks back to back from word 0, then erased words
 * (0xFFFF) to its end. A save appends a block after the newest, or erases
 * the sector first when the block does not fit or the sector is not in
 * that form; a flash sector takes few erases (the F28335's: 100 cycles
 * guaranteed, SPRS439 "Flash endurance"), and 32K words hold 728 saves of
 * 13 parameters between two. Reading it:
 *   NV_EMPTY    every word erased (a new board, or an image programmed
 *               with the whole flash erased)
 *   NV_INVALID  a block header that is not one (magic, version, length),
 *               a newest block whose CRC fails (one flipped bit, a save cut
 *               short by a power loss) or that another table saved (an
 *               image whose list of parameters changed), or written words
 *               after the blocks
 *   NV_OK       the newest block's pairs
 * A block is read and written whole through one buffer of
 * NV_BLOCK_WORDS_MAX words in RAM (the flash API reads its source from
 * RAM): nv_block_put() places the pairs, nv_save() seals and writes them;
 * nv_load() fills it, nv_block_get() takes the pairs out.
 */
#ifndef NV_STORE_H
#define NV_STORE_H

#include <stdbool.h>
#include <stdint.h>

#define NV_MAGIC 0x4E56u
#define NV_VERSION 2u
#define NV_HEADER_WORDS 4u           /* magic, version, length, table */
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
    NV_INVALID = 2,                  /* the sector holds no valid newest block of this table: see above */
    NV_WRITE_FAILED = 3              /* a save the flash refused, or that did not read back */
} nv_status_t;

/* The sector: its size and its reads and writes (hal_nv_read, hal_nv_write,
 * hal_nv_words on the board and in the SIL). */
typedef struct {
    uint32_t words;                                                   /* [words] */
    bool (*read)(uint32_t off, uint16_t *dst, uint16_t n);            /* n words from word off */
    bool (*write)(uint32_t off, const uint16_t *src, uint16_t n, bool erase_first); /* program at off */
} nv_dev_t;

/* A CRC32_PRIME folded to 16 bits: its two halves XORed. Any context. */
uint16_t nv_crc_fold(uint32_t crc);

/* A parameter's id: CRC32_PRIME of its key name's characters, folded
 * (nv_crc_fold). Any context. */
uint16_t nv_key_id(const char *name);

/* Start-up or background: the sector's newest block, when it is one of
 * table's, into buf (NV_BLOCK_WORDS_MAX words) and its pair count into *n
 * (0 unless NV_OK). */
nv_status_t nv_load(const nv_dev_t *dev, uint16_t table, uint16_t *buf, uint16_t *n);

/* Pair k of the block in buf (k < its count). Any context. */
nv_pair_t nv_block_get(const uint16_t *buf, uint16_t k);

/* Pair k (< NV_PAIRS_MAX) into its place in the block in buf. Any context. */
void nv_block_put(uint16_t *buf, uint16_t k, nv_pair_t pair);

/* Background, the drive stopped: the n pairs (1 .. NV_PAIRS_MAX) put in
 * buf sealed (header of table, CRC) and saved as the newest block,
 * appended or into the sector erased first; NV_OK when the flash took it
 * and it reads back word for word, else NV_WRITE_FAILED (NV_INVALID for no
 * pairs or too many). */
nv_status_t nv_save(const nv_dev_t *dev, uint16_t table, uint16_t n, uint16_t *buf);

#endif /* NV_STORE_H */
