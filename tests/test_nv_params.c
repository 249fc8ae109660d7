/*
 * Unit tests for firmware/params/nv_params: the store's blocks over the
 * parameter set through a list of parameters (here a list of three of
 * its own; the drive's, the link's table, in test_link_nv): the table id
 * from the keys, a block's pairs replace the defaults all or none, a save
 * holds every parameter of the list, a list that changed reads it as
 * NV_INVALID.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>
#include <string.h>

#include "drive_params.h"
#include "nv_pairs.h"
#include "nv_params.h"
#include "nv_ram_sector.h"

/* The list: R (1 mOhm .. 1 kOhm), pole pairs (whole, 1 .. 64), the speed PI's kp (> 0). */
static const char *const KEYS[3] = { "R_ohm", "pole_pairs", "speed_kp_Nms_rad" };

static const char *key(uint16_t k)
{
    return KEYS[k];
}

static bool ok(uint16_t k, float v)
{
    switch (k) {
    case 0: return (v >= 1e-3f) && (v <= 1e3f);
    case 1: return (v >= 1.0f) && (v <= 64.0f) && (v == floorf(v));
    default: return v > 0.0f;
    }
}

static float get(const drive_params_t *p, uint16_t k)
{
    switch (k) {
    case 0: return p->motor.R_Ohm;
    case 1: return (float)p->motor.pole_pairs;
    default: return p->tuning.speed_kp_Nms_rad;
    }
}

static bool set(drive_params_t *p, uint16_t k, float v)
{
    if (!ok(k, v)) {
        return false;
    }
    switch (k) {
    case 0: p->motor.R_Ohm = v; break;
    case 1: p->motor.pole_pairs = (uint16_t)v; break;
    default: p->tuning.speed_kp_Nms_rad = v; break;
    }
    return true;
}

static const nv_param_list_t LIST = { 3u, key, ok, get, set };

static uint16_t buf[NV_BLOCK_WORDS_MAX];
static drive_params_t defaults;

static int setup(void **state)
{
    (void)state;
    nv_ram_erase();
    drive_params_board(&defaults);
    return 0;
}

/* A block of the list's table holding pairs. */
static void save_pairs(const nv_pair_t *pairs, uint16_t n)
{
    assert_int_equal(nv_save_pairs(&NV_RAM_DEV, nv_params_table_id(&LIST), pairs, n, buf), NV_OK);
}

/* nv_params_load over the defaults gives st and taken, and *p equal to want. */
static void assert_load(nv_status_t st, uint16_t taken, const drive_params_t *want)
{
    drive_params_t p = defaults;
    uint16_t n = 99u;

    assert_int_equal(nv_params_load(&NV_RAM_DEV, &LIST, &p, buf, &n), st);
    assert_int_equal(n, taken);
    assert_memory_equal(&p, want, sizeof p);
}

/* The table id: CRC32_PRIME of the keys' ids as words, folded; another
 * order or one key fewer gives another. */
static void the_table_id_is_the_crc_of_the_keys_ids(void **state)
{
    (void)state;
    const uint16_t ids[3] = { nv_key_id("R_ohm"), nv_key_id("pole_pairs"), nv_key_id("speed_kp_Nms_rad") };
    const uint32_t crc = nv_ref_crc(ids, 3);
    assert_int_equal(nv_params_table_id(&LIST), (uint16_t)((crc >> 16) ^ (crc & 0xFFFFu)));
    nv_param_list_t shorter = LIST;
    shorter.count = 2u;
    assert_true(nv_params_table_id(&shorter) != nv_params_table_id(&LIST));
}

static void an_empty_sector_keeps_the_defaults(void **state)
{
    (void)state;
    assert_load(NV_EMPTY, 0u, &defaults);
}

static void a_save_holds_the_list_and_a_load_takes_it_back(void **state)
{
    (void)state;
    drive_params_t told = defaults;
    told.motor.R_Ohm = 0.731f;
    told.motor.pole_pairs = 7u;
    told.tuning.speed_kp_Nms_rad = 0.0421f;
    told.motor.L_H = 9.9f;   /* not in the list: not saved */
    assert_int_equal(nv_params_save(&NV_RAM_DEV, &LIST, &told, buf), NV_OK);
    /* the block: 3 pairs of the list's table, in the list's order, ids the key names' */
    assert_int_equal(nv_ram_sector[2], 6u + 3u * 3u);
    assert_int_equal(nv_ram_sector[3], nv_params_table_id(&LIST));
    assert_int_equal(nv_ram_sector[4], nv_key_id("R_ohm"));
    assert_int_equal(nv_ram_sector[7], nv_key_id("pole_pairs"));
    assert_int_equal(nv_ram_sector[10], nv_key_id("speed_kp_Nms_rad"));

    drive_params_t want = defaults;
    want.motor.R_Ohm = 0.731f;
    want.motor.pole_pairs = 7u;
    want.tuning.speed_kp_Nms_rad = 0.0421f;
    assert_load(NV_OK, 3u, &want);
}

/* The list grown by a parameter (or cut by one) since the save: the old
 * block is not its table's, the defaults stay. */
static void a_block_of_a_changed_list_keeps_every_default(void **state)
{
    (void)state;
    nv_param_list_t older = LIST;
    older.count = 2u;
    drive_params_t told = defaults;
    told.motor.R_Ohm = 0.5f;
    assert_int_equal(nv_params_save(&NV_RAM_DEV, &older, &told, buf), NV_OK);
    assert_load(NV_INVALID, 0u, &defaults);
    setup(NULL);
    assert_int_equal(nv_params_save(&NV_RAM_DEV, &LIST, &told, buf), NV_OK);
    drive_params_t p = defaults;
    uint16_t n = 99u;
    assert_int_equal(nv_params_load(&NV_RAM_DEV, &older, &p, buf, &n), NV_INVALID);
    assert_int_equal(n, 0u);
}

static void a_block_of_some_of_the_list_sets_those(void **state)
{
    (void)state;
    const nv_pair_t one[1] = { { nv_key_id("speed_kp_Nms_rad"), 1.5f } };
    save_pairs(one, 1u);
    drive_params_t want = defaults;
    want.tuning.speed_kp_Nms_rad = 1.5f;
    assert_load(NV_OK, 1u, &want);
}

static void a_pair_the_list_refuses_keeps_every_default(void **state)
{
    (void)state;
    /* the first pair fits; the second names no parameter of the list: none is taken */
    const nv_pair_t foreign[2] = { { nv_key_id("R_ohm"), 2.0f }, { nv_key_id("L_H"), 0.01f } };
    uint16_t n = 0u;
    save_pairs(foreign, 2u);
    assert_load(NV_INVALID, 0u, &defaults);
    assert_int_equal(nv_load(&NV_RAM_DEV, nv_params_table_id(&LIST), buf, &n), NV_OK);
    assert_int_equal(nv_params_refused(&LIST, buf, n), 1u);
    assert_int_equal(nv_params_of(&LIST, buf, 0u), 0u);
    assert_int_equal(nv_params_of(&LIST, buf, 1u), NV_PARAMS_NOT_LISTED);
    /* out of bounds (a unit slip: mOhm as Ohm), a fraction of a pole pair, a NaN */
    const nv_pair_t bad[3][2] = {
        { { nv_key_id("pole_pairs"), 4.0f }, { nv_key_id("R_ohm"), 2000.0f } },
        { { nv_key_id("R_ohm"), 2.0f }, { nv_key_id("pole_pairs"), 4.5f } },
        { { nv_key_id("pole_pairs"), 4.0f }, { nv_key_id("speed_kp_Nms_rad"), NAN } },
    };
    for (int k = 0; k < 3; k++) {
        save_pairs(bad[k], 2u);
        assert_load(NV_INVALID, 0u, &defaults);
    }
}

static void a_corrupted_block_keeps_every_default(void **state)
{
    (void)state;
    drive_params_t told = defaults;
    told.motor.R_Ohm = 0.5f;
    assert_int_equal(nv_params_save(&NV_RAM_DEV, &LIST, &told, buf), NV_OK);
    nv_ram_sector[5] ^= 0x0001u;   /* R's value, its lowest bit */
    assert_load(NV_INVALID, 0u, &defaults);
}

static void a_list_of_none_or_too_many_is_not_saved(void **state)
{
    (void)state;
    nv_param_list_t none = LIST;
    none.count = 0u;
    assert_int_equal(nv_params_save(&NV_RAM_DEV, &none, &defaults, buf), NV_INVALID);
    nv_param_list_t many = LIST;
    many.count = NV_PAIRS_MAX + 1u;
    assert_int_equal(nv_params_save(&NV_RAM_DEV, &many, &defaults, buf), NV_INVALID);
    assert_load(NV_EMPTY, 0u, &defaults);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(the_table_id_is_the_crc_of_the_keys_ids),
        cmocka_unit_test_setup(an_empty_sector_keeps_the_defaults, setup),
        cmocka_unit_test_setup(a_save_holds_the_list_and_a_load_takes_it_back, setup),
        cmocka_unit_test_setup(a_block_of_a_changed_list_keeps_every_default, setup),
        cmocka_unit_test_setup(a_block_of_some_of_the_list_sets_those, setup),
        cmocka_unit_test_setup(a_pair_the_list_refuses_keeps_every_default, setup),
        cmocka_unit_test_setup(a_corrupted_block_keeps_every_default, setup),
        cmocka_unit_test_setup(a_list_of_none_or_too_many_is_not_saved, setup),
    };
    return cmocka_run_group_tests_name("nv_params", tests, NULL, NULL);
}
