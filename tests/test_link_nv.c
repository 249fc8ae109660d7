/*
 * Unit tests for firmware/link/link_nv: the link's parameter table as the
 * parameter store's one list (LINK_NV_PARAMS) on a sector in RAM with the
 * flash's rules: every link parameter, each set to a value of its own,
 * saved and loaded back to the bit over the board's defaults; the block
 * holds the table's parameters in its order under its table id; a block
 * saved by a table one parameter shorter (an older image) or read by one
 * (a newer image's block on an older) is NV_INVALID and changes nothing;
 * the store's status as the link shows it through an asked save, one
 * refused when the drive was started, and a start-up load.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <string.h>

#include "drive_params.h"
#include "link_nv.h"
#include "link_params.h"
#include "nv_ram_sector.h"

static link_nv_t store;
static drive_params_t board;       /* drive_params_board(): what a start-up loads over */
static drive_params_t told;        /* the set derived, then every link parameter changed */

/* A value of parameter k other than *p's and within its bounds: a quarter more and a little (the
 * offset from 0 for one that is 0), pole pairs one more. */
static float changed(const drive_params_t *p, uint16_t k)
{
    const float v = link_param_get(p, k);
    return (link_param(k)->type == (uint16_t)LINK_PARAM_U16) ? v + 1.0f : 1.25f * v + 1.0e-6f;
}

static int setup(void **state)
{
    (void)state;
    nv_ram_erase();
    link_nv_init(&store, &NV_RAM_DEV);
    drive_params_board(&board);
    told = board;
    (void)drive_params_derive(&told);
    for (uint16_t k = 0; k < (uint16_t)LINK_PARAM_COUNT; k++) {
        const float v = changed(&told, k);
        assert_true(link_param_ok(k, v));
        assert_true(link_param_set(&told, k, v));
    }
    return 0;
}

/* k's value in a and b: the same bits. */
static void assert_same_param(const drive_params_t *a, const drive_params_t *b, uint16_t k)
{
    const float x = link_param_get(a, k);
    const float y = link_param_get(b, k);
    assert_memory_equal(&x, &y, sizeof x);
}

static void the_list_is_the_links_table(void **state)
{
    (void)state;
    drive_params_t p;
    drive_params_board(&p);
    assert_int_equal(LINK_NV_PARAMS.count, LINK_PARAM_COUNT);
    for (uint16_t k = 0; k < (uint16_t)LINK_PARAM_COUNT; k++) {
        assert_string_equal(LINK_NV_PARAMS.key(k), LINK_PARAM_TABLE[k].key);
        assert_true(LINK_NV_PARAMS.get(&p, k) == link_param_get(&p, k));
        assert_true(LINK_NV_PARAMS.ok == link_param_ok && LINK_NV_PARAMS.set == link_param_set);
    }
}

/* Saved: one block of LINK_PARAM_COUNT pairs (6 + 3 n words) of the table's id, the pairs in the
 * table's order; loaded over the board's defaults: every link parameter the told one, to the bit,
 * status VALID with all of them taken. */
static void every_link_parameter_round_trips_through_a_block(void **state)
{
    (void)state;
    drive_params_t p = board;
    link_nv_ask(&store);
    assert_int_equal(link_nv_save(&store, &told, true), NV_OK);
    assert_int_equal(store.status, LINK_NV_SAVED);
    assert_int_equal(nv_ram_sector[2], 6u + 3u * (uint16_t)LINK_PARAM_COUNT);
    assert_int_equal(nv_ram_sector[3], nv_params_table_id(&LINK_NV_PARAMS));
    for (uint16_t k = 0; k < (uint16_t)LINK_PARAM_COUNT; k++) {
        assert_int_equal(nv_ram_sector[4u + 3u * k], nv_key_id(LINK_PARAM_TABLE[k].key));
    }

    link_nv_init(&store, &NV_RAM_DEV);   /* the next start-up */
    assert_int_equal(link_nv_load(&store, &p), NV_OK);
    assert_int_equal(store.status, LINK_NV_VALID);
    assert_int_equal(store.taken, LINK_PARAM_COUNT);
    for (uint16_t k = 0; k < (uint16_t)LINK_PARAM_COUNT; k++) {
        assert_same_param(&p, &told, k);
        assert_true(link_param_get(&p, k) != link_param_get(&board, k));   /* not the defaults, by setup */
    }
}

/* A table of one parameter fewer (the image before the last was added) saved the block: this
 * image reads it NV_INVALID, the board's defaults untouched; and this image's block read by that
 * shorter table: NV_INVALID too. */
static void a_changed_table_length_invalidates(void **state)
{
    (void)state;
    nv_param_list_t older = LINK_NV_PARAMS;
    older.count = (uint16_t)(LINK_PARAM_COUNT - 1);
    drive_params_t p = board;
    uint16_t taken = 0u;
    assert_int_equal(nv_params_save(&NV_RAM_DEV, &older, &told, store.buf), NV_OK);
    assert_int_equal(link_nv_load(&store, &p), NV_INVALID);
    assert_int_equal(store.status, LINK_NV_INVALID);
    assert_int_equal(store.taken, 0u);
    assert_memory_equal(&p, &board, sizeof p);

    nv_ram_erase();
    link_nv_ask(&store);
    assert_int_equal(link_nv_save(&store, &told, true), NV_OK);
    assert_int_equal(nv_params_load(&NV_RAM_DEV, &older, &p, store.buf, &taken), NV_INVALID);
    assert_memory_equal(&p, &board, sizeof p);
}

/* The status through the store's life: EMPTY on an erased sector; a save asked: SAVING and due;
 * the drive started before it ran: SAVE_FAILED, nothing written, no longer due; asked again and
 * stopped: SAVED; a load's results as the link names them. */
static void the_status_says_what_the_store_did(void **state)
{
    (void)state;
    drive_params_t p = board;
    assert_int_equal(store.status, LINK_NV_EMPTY);
    assert_int_equal(link_nv_load(&store, &p), NV_EMPTY);
    assert_int_equal(store.status, LINK_NV_EMPTY);
    assert_false(link_nv_due(&store));
    link_nv_ask(&store);
    assert_true(link_nv_due(&store));
    assert_int_equal(store.status, LINK_NV_SAVING);
    assert_int_equal(link_nv_save(&store, &told, false), NV_WRITE_FAILED);
    assert_int_equal(store.status, LINK_NV_SAVE_FAILED);
    assert_false(link_nv_due(&store));
    assert_int_equal(nv_ram_sector[0], NV_ERASED);
    link_nv_ask(&store);
    assert_int_equal(link_nv_save(&store, &told, true), NV_OK);
    assert_int_equal(store.status, LINK_NV_SAVED);
    assert_int_equal(link_nv_status_of(NV_OK), LINK_NV_VALID);
    assert_int_equal(link_nv_status_of(NV_EMPTY), LINK_NV_EMPTY);
    assert_int_equal(link_nv_status_of(NV_INVALID), LINK_NV_INVALID);
    assert_int_equal(link_nv_status_of(NV_WRITE_FAILED), LINK_NV_INVALID);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(the_list_is_the_links_table),
        cmocka_unit_test_setup(every_link_parameter_round_trips_through_a_block, setup),
        cmocka_unit_test_setup(a_changed_table_length_invalidates, setup),
        cmocka_unit_test_setup(the_status_says_what_the_store_did, setup),
    };
    return cmocka_run_group_tests_name("link_nv", tests, NULL, NULL);
}
