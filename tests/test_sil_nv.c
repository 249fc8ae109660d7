/*
 * Unit tests for drive_sil --nv FILE (tools/sil/nv_file.h) on the
 * simulated board's parameter sector (hal/sim/hal_sim_nv.c): the flash's
 * rules, a save through the HAL as the link's save makes it rewriting
 * FILE at once, the next start (a new process: the sector from FILE)
 * taking its values into the scenario, and what it refuses.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "hal.h"
#include "hal_sim.h"
#include "link_nv.h"
#include "nv_file.h"
#include "nv_pairs.h"
#include "nv_store.h"
#include "scenario.h"

static char path[64];
static const nv_dev_t DEV = { HAL_SIM_NV_WORDS, hal_nv_read, hal_nv_write };
static uint16_t buf[NV_BLOCK_WORDS_MAX];

static int setup(void **state)
{
    (void)state;
    snprintf(path, sizeof path, "/tmp/test_sil_nv.%ld.bin", (long)getpid());
    remove(path);
    hal_sim_nv_erase();
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    remove(path);
    hal_sim_nv_on_write(NULL, NULL);
    return 0;
}

/* The flash's rules: a program only clears bits, one that would set a bit fails. */
static void the_sector_keeps_the_flash_rules(void **state)
{
    (void)state;
    const uint16_t w[2] = { 0x0F0Fu, 0x00FFu };
    const uint16_t more[1] = { 0x0FFFu };
    uint16_t r[2];
    assert_int_equal(hal_nv_words(), 0x8000u);
    assert_true(hal_nv_write(10, w, 2, false));
    assert_true(hal_nv_read(10, r, 2));
    assert_memory_equal(r, w, sizeof w);
    assert_false(hal_nv_write(10, more, 1, false));   /* 0x0F0F -> 0x0FFF sets bits */
    assert_true(hal_nv_write(10, more, 1, true));     /* erased first: fine */
    assert_true(hal_nv_read(10, r, 2));
    assert_int_equal(r[0], 0x0FFFu);
    assert_int_equal(r[1], 0xFFFFu);
    assert_false(hal_nv_read(0x7FFFu, r, 2));
}

static long file_size(const char *p)
{
    FILE *f = fopen(p, "rb");
    if (f == NULL) {
        return -1;
    }
    fseek(f, 0, SEEK_END);
    const long n = ftell(f);
    fclose(f);
    return n;
}

/* No FILE: an erased sector, FILE written as one; a save through the HAL
 * writes FILE again at once (its first octets the block's magic, low octet
 * first); the next start, a new process with the sector read from FILE,
 * takes the values into the scenario as set by "--nv FILE". */
static void a_save_is_in_the_file_and_the_next_start_takes_it(void **state)
{
    (void)state;
    char err[256];
    char msg[512];
    static scenario_t sc;
    assert_int_equal(nv_file_open(path, err, sizeof err), 0);
    assert_int_equal(file_size(path), 65536);
    scenario_defaults(&sc);
    assert_int_equal(nv_file_apply(&sc, path, msg, sizeof msg), NV_EMPTY);
    assert_non_null(strstr(msg, "NV_EMPTY"));

    const nv_pair_t pairs[2] = { { nv_key_id("speed_kp_Nms_rad"), 0.625f }, { nv_key_id("pole_pairs"), 4.0f } };
    assert_int_equal(nv_save_pairs(&DEV, nv_params_table_id(&LINK_NV_PARAMS), pairs, 2, buf), NV_OK);
    FILE *f = fopen(path, "rb");
    unsigned char head[2];
    assert_non_null(f);
    assert_int_equal(fread(head, 1, 2, f), 2);
    fclose(f);
    assert_int_equal(head[0], 0x56);
    assert_int_equal(head[1], 0x4E);

    hal_sim_nv_erase();   /* a new process: nothing but FILE */
    assert_int_equal(nv_file_open(path, err, sizeof err), 0);
    scenario_defaults(&sc);
    assert_int_equal(nv_file_apply(&sc, path, msg, sizeof msg), NV_OK);
    assert_non_null(strstr(msg, "loaded 2 parameters"));
    assert_float_equal(sc.controller.speed_kp_Nms_rad, 0.625, 0.0);
    assert_int_equal(sc.controller.pole_pairs, 4);
    assert_true(scenario_key_set(&sc, "controller", "speed_kp_Nms_rad"));
}

/* One corrupted octet of FILE's block: NV_INVALID, the scenario untouched;
 * a file of another size: refused, named. */
static void a_corrupted_file_is_invalid(void **state)
{
    (void)state;
    char err[256];
    char msg[512];
    static scenario_t sc;
    const nv_pair_t pairs[1] = { { nv_key_id("J_kgm2"), 0.002f } };
    assert_int_equal(nv_file_open(path, err, sizeof err), 0);
    assert_int_equal(nv_save_pairs(&DEV, nv_params_table_id(&LINK_NV_PARAMS), pairs, 1, buf), NV_OK);
    FILE *f = fopen(path, "r+b");
    assert_non_null(f);
    fseek(f, 11, SEEK_SET);   /* the value's low word, high octet */
    fputc(0x55, f);
    fclose(f);
    hal_sim_nv_erase();
    assert_int_equal(nv_file_open(path, err, sizeof err), 0);
    scenario_defaults(&sc);
    const double J = sc.controller.J_kgm2;
    assert_int_equal(nv_file_apply(&sc, path, msg, sizeof msg), NV_INVALID);
    assert_non_null(strstr(msg, "NV_INVALID"));
    assert_true(isnan(J) ? isnan(sc.controller.J_kgm2) : sc.controller.J_kgm2 == J);
    assert_false(scenario_key_set(&sc, "controller", "J_kgm2"));

    f = fopen(path, "wb");
    assert_non_null(f);
    fputs("short", f);
    fclose(f);
    assert_int_equal(nv_file_open(path, err, sizeof err), -1);
    assert_non_null(strstr(err, "not a parameter sector"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(the_sector_keeps_the_flash_rules, setup, teardown),
        cmocka_unit_test_setup_teardown(a_save_is_in_the_file_and_the_next_start_takes_it, setup, teardown),
        cmocka_unit_test_setup_teardown(a_corrupted_file_is_invalid, setup, teardown),
    };
    return cmocka_run_group_tests_name("sil_nv", tests, NULL, NULL);
}
