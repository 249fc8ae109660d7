/*
 * Unit tests for firmware/params/nv_params: the store's blocks over the
 * parameter set through a list of parameters (here a list of three of
 * its own, as the link's table will be one): a block's pairs replace the
 * defaults all or none, a save holds every parameter of the list.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>
#include <string.h>

#include "drive_params.h"
#include "nv_params.h"

#define SECTOR_WORDS 128u

static uint16_t sector[SECTOR_WORDS];

static bool ram_read(uint32_t off, uint16_t *dst, uint16_t n)
{
    if (off + n > SECTOR_WORDS) {
        return false;
    }
    memcpy(dst, &sector[off], n * sizeof *dst);
    return true;
}

static bool ram_write(uint32_t off, const uint16_t *src, uint16_t n, bool erase_first)
{
    if (off + n > SECTOR_WORDS) {
        return false;
    }
    if (erase_first) {
        memset(sector, 0xFF, sizeof sector);
    }
    memcpy(&sector[off], src, n * sizeof *src);
    return true;
}

static const nv_dev_t DEV = { SECTOR_WORDS, ram_read, ram_write };

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

static nv_pair_t pairs[NV_PAIRS_MAX];
static uint16_t buf[NV_BLOCK_WORDS_MAX];
static drive_params_t defaults;

static int setup(void **state)
{
    (void)state;
    memset(sector, 0xFF, sizeof sector);
    drive_params_board(&defaults);
    return 0;
}

/* nv_params_load over the defaults gives st and taken, and *p equal to want. */
static void assert_load(nv_status_t st, uint16_t taken, const drive_params_t *want)
{
    drive_params_t p = defaults;
    uint16_t n = 99u;

    assert_int_equal(nv_params_load(&DEV, &LIST, &p, pairs, &n), st);
    assert_int_equal(n, taken);
    assert_memory_equal(&p, want, sizeof p);
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
    assert_int_equal(nv_params_save(&DEV, &LIST, &told, pairs, buf), NV_OK);
    /* the block: 3 pairs, in the list's order, ids the key names' */
    assert_int_equal(sector[2], 5u + 3u * 3u);
    assert_int_equal(sector[3], nv_key_id("R_ohm"));
    assert_int_equal(sector[6], nv_key_id("pole_pairs"));
    assert_int_equal(sector[9], nv_key_id("speed_kp_Nms_rad"));

    drive_params_t want = defaults;
    want.motor.R_Ohm = 0.731f;
    want.motor.pole_pairs = 7u;
    want.tuning.speed_kp_Nms_rad = 0.0421f;
    assert_load(NV_OK, 3u, &want);
}

static void a_block_of_some_of_the_list_sets_those(void **state)
{
    (void)state;
    const nv_pair_t one[1] = { { nv_key_id("speed_kp_Nms_rad"), 1.5f } };
    assert_int_equal(nv_save(&DEV, one, 1u, buf), NV_OK);
    drive_params_t want = defaults;
    want.tuning.speed_kp_Nms_rad = 1.5f;
    assert_load(NV_OK, 1u, &want);
}

static void a_pair_the_list_refuses_keeps_every_default(void **state)
{
    (void)state;
    /* the first pair fits; the second names no parameter of the list: none is taken */
    const nv_pair_t foreign[2] = { { nv_key_id("R_ohm"), 2.0f }, { nv_key_id("L_H"), 0.01f } };
    assert_int_equal(nv_save(&DEV, foreign, 2u, buf), NV_OK);
    assert_load(NV_INVALID, 0u, &defaults);
    /* out of bounds (a unit slip: mOhm as Ohm), a fraction of a pole pair, a NaN */
    const nv_pair_t bad[3][2] = {
        { { nv_key_id("pole_pairs"), 4.0f }, { nv_key_id("R_ohm"), 2000.0f } },
        { { nv_key_id("R_ohm"), 2.0f }, { nv_key_id("pole_pairs"), 4.5f } },
        { { nv_key_id("pole_pairs"), 4.0f }, { nv_key_id("speed_kp_Nms_rad"), NAN } },
    };
    for (int k = 0; k < 3; k++) {
        assert_int_equal(nv_save(&DEV, bad[k], 2u, buf), NV_OK);
        assert_load(NV_INVALID, 0u, &defaults);
    }
}

static void a_corrupted_block_keeps_every_default(void **state)
{
    (void)state;
    drive_params_t told = defaults;
    told.motor.R_Ohm = 0.5f;
    assert_int_equal(nv_params_save(&DEV, &LIST, &told, pairs, buf), NV_OK);
    sector[4] ^= 0x0001u;   /* R's value, its lowest bit */
    assert_load(NV_INVALID, 0u, &defaults);
}

static void a_list_of_none_or_too_many_is_not_saved(void **state)
{
    (void)state;
    nv_param_list_t none = LIST;
    none.count = 0u;
    assert_int_equal(nv_params_save(&DEV, &none, &defaults, pairs, buf), NV_INVALID);
    nv_param_list_t many = LIST;
    many.count = NV_PAIRS_MAX + 1u;
    assert_int_equal(nv_params_save(&DEV, &many, &defaults, pairs, buf), NV_INVALID);
    assert_load(NV_EMPTY, 0u, &defaults);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(an_empty_sector_keeps_the_defaults, setup),
        cmocka_unit_test_setup(a_save_holds_the_list_and_a_load_takes_it_back, setup),
        cmocka_unit_test_setup(a_block_of_some_of_the_list_sets_those, setup),
        cmocka_unit_test_setup(a_pair_the_list_refuses_keeps_every_default, setup),
        cmocka_unit_test_setup(a_corrupted_block_keeps_every_default, setup),
        cmocka_unit_test_setup(a_list_of_none_or_too_many_is_not_saved, setup),
    };
    return cmocka_run_group_tests_name("nv_params", tests, NULL, NULL);
}
