/*
 * Unit tests for the parameter store on the F28335 HAL (hal/f28335/
 * hal_f28335_nv.c) against the register fake and its fake of TI's
 * Flash2833x API (tests/c2000_fake/flash_api_fake.c): what the HAL asks
 * the API for, in which order, and in which state of the CPU and the
 * ePWMs; then nv_store's blocks through the HAL into sector B.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <string.h>

#include "DSP2833x_Device.h"
#include "Flash2833x_API_Library.h"
#include "c2000_fake.h"
#include "hal.h"
#include "hal_f28335_cfg.h"
#include "nv_pairs.h"
#include "nv_store.h"

static int setup(void **state)
{
    (void)state;
    c2000_fake_reset();
    c2000_fake_intm = 0U;   /* the background, interrupts on */
    return 0;
}

static const uint16_t BLOCK[5] = { 0x4E56u, 1u, 0x1234u, 0x00FFu, 0xA5A5u };

/* 32K words of sector B; erased; a range past its end refused. */
static void the_sector_is_sector_b(void **state)
{
    (void)state;
    uint16_t w[4];
    assert_int_equal(hal_nv_words(), 0x8000u);
    assert_int_equal(F28335_NV_SECTOR_ADDR, 0x330000u);
    assert_true(hal_nv_read(0x7FFCu, w, 4));
    assert_int_equal(w[3], 0xFFFFu);
    assert_false(hal_nv_read(0x7FFDu, w, 4));
    assert_false(hal_nv_read(0xFFFFFFFFu, w, 4));
    c2000_fake_flash_b[10] = 0x1234u;
    assert_true(hal_nv_read(10, w, 1));
    assert_int_equal(w[0], 0x1234u);
}

/* An erase and a program: the outputs forced off and every interrupt held
 * off before the first API call and throughout; the API's scale for 150 MHz
 * (1048576 x 150 / 5 = 31457280); erase sector B only, the watchdog kicked
 * at each of the API's callbacks; program, then verify the same range;
 * interrupts on again and no callback left installed. */
static void a_write_erases_programs_verifies_with_everything_off(void **state)
{
    (void)state;
    EPwm1Regs.TZFRC.all = EPwm2Regs.TZFRC.all = EPwm3Regs.TZFRC.all = 0U;   /* outputs "on" */
    c2000_fake_flash_b[100] = 0x0000u;                                     /* an old block */
    assert_true(hal_nv_write(40u, BLOCK, 5u, true));
    assert_int_equal(c2000_fake_flash.n, 3);
    const c2000_fake_flash_call_t *c = c2000_fake_flash.call;
    assert_int_equal(c[0].op, C2000_FAKE_ERASE);
    assert_int_equal(c[0].sector_mask, SECTORB);
    assert_int_equal(c[0].callback_kicks, 3);
    assert_int_equal(c[1].op, C2000_FAKE_PROGRAM);
    assert_int_equal(c[1].offset, 40u);
    assert_int_equal(c[1].length, 5u);
    assert_int_equal(c[2].op, C2000_FAKE_VERIFY);
    assert_int_equal(c[2].offset, 40u);
    assert_int_equal(c[2].length, 5u);
    for (int k = 0; k < 3; k++) {
        assert_int_equal(c[k].ints_masked, 1);
        assert_int_equal(c[k].pwm_forced_off, 1);
        assert_int_equal(c[k].scale_factor, 31457280u);
    }
    assert_int_equal(F28335_FLASH_API_SCALE, 31457280u);
    assert_memory_equal(&c2000_fake_flash_b[40], BLOCK, sizeof BLOCK);
    assert_int_equal(c2000_fake_flash_b[100], 0xFFFFu);   /* erased */
    assert_int_equal(c2000_fake_intm, 0);
    assert_null(Flash_CallbackPtr);
    assert_int_equal(EPwm1Regs.TZFRC.bit.OST, 1);         /* the outputs stay off */
}

/* Without erase_first: no erase, the block programmed where asked. */
static void an_append_programs_without_erasing(void **state)
{
    (void)state;
    assert_true(hal_nv_write(7u, BLOCK, 5u, false));
    assert_int_equal(c2000_fake_flash.n, 2);
    assert_int_equal(c2000_fake_flash.call[0].op, C2000_FAKE_PROGRAM);
    assert_int_equal(c2000_fake_flash.call[1].op, C2000_FAKE_VERIFY);
    assert_memory_equal(&c2000_fake_flash_b[7], BLOCK, sizeof BLOCK);
}

/* A failing erase stops before programming, a failing program before the
 * verify; a failing verify is a failure; a range outside the sector asks
 * the API nothing. Interrupts are on again after each. */
static void failures_stop_the_write(void **state)
{
    (void)state;
    c2000_fake_flash.fail_next = C2000_FAKE_ERASE;
    assert_false(hal_nv_write(0u, BLOCK, 5u, true));
    assert_int_equal(c2000_fake_flash.n, 1);
    assert_int_equal(c2000_fake_intm, 0);
    c2000_fake_flash.n = 0;
    c2000_fake_flash.fail_next = C2000_FAKE_PROGRAM;
    assert_false(hal_nv_write(0u, BLOCK, 5u, false));
    assert_int_equal(c2000_fake_flash.n, 1);
    c2000_fake_flash.n = 0;
    c2000_fake_flash.fail_next = C2000_FAKE_VERIFY;
    assert_false(hal_nv_write(20u, BLOCK, 5u, false));
    assert_int_equal(c2000_fake_flash.n, 2);
    c2000_fake_flash.n = 0;
    assert_false(hal_nv_write(0x7FFEu, BLOCK, 5u, true));
    assert_int_equal(c2000_fake_flash.n, 0);
    /* a block over programmed words (no erase asked): the API refuses, so does the write */
    assert_false(hal_nv_write(20u, BLOCK + 1, 4u, false));
    assert_int_equal(c2000_fake_intm, 0);
}

/* nv_store's save and load through the HAL into sector B. */
static void the_store_saves_and_loads_through_the_hal(void **state)
{
    (void)state;
    const nv_dev_t dev = { hal_nv_words(), hal_nv_read, hal_nv_write };
    static uint16_t buf[NV_BLOCK_WORDS_MAX];
    const nv_pair_t pairs[2] = { { nv_key_id("speed_kp_Nms_rad"), 0.75f }, { nv_key_id("R_ohm"), 2.5f } };
    const uint16_t table = 0x1357u;
    nv_pair_t got[NV_PAIRS_MAX];
    uint16_t n = 9;
    assert_int_equal(nv_load_pairs(&dev, table, got, &n), NV_EMPTY);
    assert_int_equal(nv_save_pairs(&dev, table, pairs, 2, buf), NV_OK);
    assert_int_equal(c2000_fake_flash.call[0].op, C2000_FAKE_PROGRAM);   /* an erased sector: no erase */
    assert_int_equal(nv_load_pairs(&dev, table, got, &n), NV_OK);
    assert_int_equal(n, 2);
    assert_int_equal(got[0].id, pairs[0].id);
    assert_true(got[0].value == 0.75f);
    assert_true(got[1].value == 2.5f);
    c2000_fake_flash_b[5] ^= 0x0001u;   /* one bit of the first value */
    assert_int_equal(nv_load_pairs(&dev, table, got, &n), NV_INVALID);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(the_sector_is_sector_b, setup),
        cmocka_unit_test_setup(a_write_erases_programs_verifies_with_everything_off, setup),
        cmocka_unit_test_setup(an_append_programs_without_erasing, setup),
        cmocka_unit_test_setup(failures_stop_the_write, setup),
        cmocka_unit_test_setup(the_store_saves_and_loads_through_the_hal, setup),
    };
    return cmocka_run_group_tests_name("nv_f28335", tests, NULL, NULL);
}
