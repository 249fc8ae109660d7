/*
 * Unit tests for firmware/params/nv_store: the parameter store's blocks in
 * a sector emulated as flash (a program only clears bits, an erase sets
 * every word to 0xFFFF), against the format nv_store.h states word by word
 * and a CRC computed here independently (CRC32_PRIME bit by bit over the
 * octets, MSB first, as test_startup checks the linker's).
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <string.h>

#include "nv_pairs.h"
#include "nv_store.h"

#define SECTOR_WORDS 256u

static uint16_t flash[SECTOR_WORDS];
static uint32_t sector_words;      /* the emulated sector's size */
static int erases;
static int writes;
static int refuse_writes;          /* the next write fails */
static uint16_t stuck_clear;       /* bits a program cannot clear (a worn cell), every word */

static bool fl_read(uint32_t off, uint16_t *dst, uint16_t n)
{
    if (off + n > sector_words) {
        return false;
    }
    memcpy(dst, &flash[off], n * sizeof *dst);
    return true;
}

static bool fl_write(uint32_t off, const uint16_t *src, uint16_t n, bool erase_first)
{
    writes++;
    if (refuse_writes || off + n > sector_words) {
        refuse_writes = 0;
        return false;
    }
    if (erase_first) {
        erases++;
        for (uint32_t k = 0; k < sector_words; k++) {
            flash[k] = 0xFFFFu;
        }
    }
    for (uint16_t k = 0; k < n; k++) {
        flash[off + k] &= (uint16_t)(src[k] | stuck_clear);   /* a program clears bits only */
    }
    return true;
}

static nv_dev_t dev;
static uint16_t buf[NV_BLOCK_WORDS_MAX];

static int setup(void **state)
{
    (void)state;
    sector_words = SECTOR_WORDS;
    for (uint32_t k = 0; k < SECTOR_WORDS; k++) {
        flash[k] = 0xFFFFu;
    }
    erases = writes = refuse_writes = 0;
    stuck_clear = 0u;
    dev = (nv_dev_t){ SECTOR_WORDS, fl_read, fl_write };
    return 0;
}

static const nv_pair_t THREE[3] = { { 0x1234u, 1.0f }, { 0x0001u, -0.0f }, { 0xFFFFu, 3.0e-39f /* subnormal */ } };
#define TABLE 0xA5C3u              /* the table id the blocks here are saved with */
#define BLOCK3 15u                 /* the words of a block of three pairs: 6 + 3 x 3 */

static nv_status_t save(const nv_pair_t *pairs, uint16_t n)
{
    return nv_save_pairs(&dev, TABLE, pairs, n, buf);
}

static void assert_pairs(const nv_pair_t *a, const nv_pair_t *b, uint16_t n)
{
    for (uint16_t k = 0; k < n; k++) {
        assert_int_equal(a[k].id, b[k].id);
        assert_memory_equal(&a[k].value, &b[k].value, sizeof(float));   /* the bits: -0.0 and subnormals kept */
    }
}

/* nv_load gives NV_OK with n_want pairs equal to want's. */
static void assert_loads(const nv_pair_t *want, uint16_t n_want)
{
    nv_pair_t got[NV_PAIRS_MAX];
    uint16_t n = 0;
    assert_int_equal(nv_load_pairs(&dev, TABLE, got, &n), NV_OK);
    assert_int_equal(n, n_want);
    assert_pairs(got, want, n_want);
}

/* nv_load gives st (NV_INVALID, NV_EMPTY) and no pairs. */
static void assert_none(nv_status_t st)
{
    nv_pair_t got[NV_PAIRS_MAX];
    uint16_t n = 9;
    assert_int_equal(nv_load_pairs(&dev, TABLE, got, &n), st);
    assert_int_equal(n, 0);
}

static void assert_invalid(void)
{
    assert_none(NV_INVALID);
}

/* "123456789": CRC32_PRIME 0x89A1897F (crc32.h's check value), halves XORed: 0x89A1 ^ 0x897F = 0x00DE. */
static void key_id_is_the_crc_of_the_name_folded(void **state)
{
    (void)state;
    assert_int_equal(nv_key_id("123456789"), 0x00DEu);
    assert_int_equal(nv_crc_fold(0x89A1897FUL), 0x00DEu);
    assert_true(nv_key_id("speed_kp_Nms_rad") != nv_key_id("speed_ki_Nm_rad"));
}

static void an_erased_sector_is_empty(void **state)
{
    (void)state;
    assert_none(NV_EMPTY);
}

/* The block word by word: magic, version 2, length 6 + 3 x 3 = 15, the
 * table, the pairs (1.0f = 0x3F800000, -0.0f = 0x80000000), the CRC of
 * words 0..12, low word first. */
static void a_save_writes_the_documented_block_and_reads_back(void **state)
{
    (void)state;
    assert_int_equal(save(THREE, 3), NV_OK);
    assert_int_equal(erases, 0);                      /* an erased sector is written as it is */
    const uint16_t want[13] = { 0x4E56u, 2u, BLOCK3, TABLE, 0x1234u, 0x0000u, 0x3F80u, 0x0001u, 0x0000u, 0x8000u,
                                0xFFFFu, 0x0000u, 0x0000u };
    uint32_t sub;
    const float f = 3.0e-39f;
    memcpy(&sub, &f, sizeof sub);
    uint16_t w[13];
    memcpy(w, want, sizeof w);
    w[11] = (uint16_t)(sub & 0xFFFFu);
    w[12] = (uint16_t)(sub >> 16);
    assert_memory_equal(flash, w, sizeof w);
    const uint32_t crc = nv_ref_crc(w, 13);
    assert_int_equal(flash[13], crc & 0xFFFFu);
    assert_int_equal(flash[14], crc >> 16);
    assert_int_equal(flash[15], 0xFFFFu);
    assert_loads(THREE, 3);
}

/* A block saved with another table reads as NV_INVALID (the table word
 * is under the CRC: the block itself is whole); the table's next save
 * appends after it and is read. */
static void a_block_of_another_table_is_invalid(void **state)
{
    (void)state;
    assert_int_equal(nv_save_pairs(&dev, (uint16_t)(TABLE ^ 0x0100u), THREE, 3, buf), NV_OK);
    assert_invalid();
    assert_int_equal(save(THREE, 2), NV_OK);
    assert_int_equal(erases, 0);
    assert_loads(THREE, 2);
}

/* A second save goes after the first (no erase); the newest is the one read. */
static void saves_append_and_the_newest_is_read(void **state)
{
    (void)state;
    const nv_pair_t one[1] = { { 7u, 42.5f } };
    assert_int_equal(save(THREE, 3), NV_OK);
    assert_int_equal(save(one, 1), NV_OK);
    assert_int_equal(erases, 0);
    assert_int_equal(flash[BLOCK3], 0x4E56u);         /* the second block right after the first's 15 words */
    assert_loads(one, 1);
}

/* One flipped bit in the newest block: NV_INVALID (no pairs); the next save
 * appends a good block after it and that one is read. */
static void a_flipped_bit_is_invalid_until_the_next_save(void **state)
{
    (void)state;
    assert_int_equal(save(THREE, 3), NV_OK);
    for (uint16_t k = 3; k < BLOCK3; k++) {   /* the table, every pair and CRC word, one bit each */
        const uint16_t keep = flash[k];
        flash[k] ^= 0x0010u;
        assert_invalid();
        flash[k] = keep;
    }
    flash[6] ^= 0x0100u;
    assert_int_equal(save(THREE, 2), NV_OK);
    assert_int_equal(erases, 0);
    assert_loads(THREE, 2);
}

/* A header that is not one (magic, version, length), or a word written
 * after the blocks: NV_INVALID; a save then erases the sector first. */
static void a_sector_out_of_form_is_invalid_and_erased_by_the_next_save(void **state)
{
    (void)state;
    /* (word, value): another magic, version 1 (the format before the table word), length 14 (not
     * 6 + 3 n), length 3, a length past the end */
    static const uint16_t bad[][2] = { { 0u, 0x4E50u }, { 1u, 1u }, { 2u, 14u }, { 2u, 3u }, { 2u, 0x0800u } };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        setup(NULL);
        assert_int_equal(save(THREE, 3), NV_OK);
        flash[bad[i][0]] = bad[i][1];
        assert_invalid();
        assert_int_equal(save(THREE, 1), NV_OK);
        assert_int_equal(erases, 1);
        assert_loads(THREE, 1);
    }
    setup(NULL);
    assert_int_equal(save(THREE, 3), NV_OK);
    flash[200] = 0x0000u;
    assert_invalid();
}

/* A save cut short by a power loss (the first 7 of 15 words programmed):
 * NV_INVALID; the next save appends after it. */
static void a_save_cut_short_is_invalid(void **state)
{
    (void)state;
    assert_int_equal(save(THREE, 3), NV_OK);
    for (uint16_t k = 7; k < BLOCK3; k++) {
        flash[k] = 0xFFFFu;
    }
    assert_invalid();
    assert_int_equal(save(THREE, 3), NV_OK);
    assert_loads(THREE, 3);
}

/* A block that no longer fits erases the sector first: 32 words hold two
 * 15-word blocks, not a third of 12. */
static void a_full_sector_is_erased_first(void **state)
{
    (void)state;
    sector_words = 32u;
    dev.words = 32u;
    assert_int_equal(save(THREE, 3), NV_OK);
    assert_int_equal(save(THREE, 3), NV_OK);   /* 15 + 15 <= 32 */
    assert_int_equal(erases, 0);
    assert_int_equal(save(THREE, 2), NV_OK);   /* 30 + 12 > 32 */
    assert_int_equal(erases, 1);
    assert_loads(THREE, 2);
    assert_int_equal(flash[0], 0x4E56u);
}

/* The flash refusing a write, or a word that does not read back (a bit it
 * cannot clear): NV_WRITE_FAILED. No pairs, or more than a block holds:
 * refused, nothing written. */
static void failures_are_named(void **state)
{
    (void)state;
    refuse_writes = 1;
    assert_int_equal(save(THREE, 3), NV_WRITE_FAILED);
    stuck_clear = 0x0400u;
    assert_int_equal(save(THREE, 3), NV_WRITE_FAILED);
    stuck_clear = 0u;
    setup(NULL);
    assert_int_equal(nv_save(&dev, TABLE, 0, buf), NV_INVALID);
    assert_int_equal(nv_save(&dev, TABLE, NV_PAIRS_MAX + 1u, buf), NV_INVALID);
    assert_int_equal(writes, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(key_id_is_the_crc_of_the_name_folded),
        cmocka_unit_test_setup(an_erased_sector_is_empty, setup),
        cmocka_unit_test_setup(a_save_writes_the_documented_block_and_reads_back, setup),
        cmocka_unit_test_setup(a_block_of_another_table_is_invalid, setup),
        cmocka_unit_test_setup(saves_append_and_the_newest_is_read, setup),
        cmocka_unit_test_setup(a_flipped_bit_is_invalid_until_the_next_save, setup),
        cmocka_unit_test_setup(a_sector_out_of_form_is_invalid_and_erased_by_the_next_save, setup),
        cmocka_unit_test_setup(a_save_cut_short_is_invalid, setup),
        cmocka_unit_test_setup(a_full_sector_is_erased_first, setup),
        cmocka_unit_test_setup(failures_are_named, setup),
    };
    return cmocka_run_group_tests_name("nv_store", tests, NULL, NULL);
}
