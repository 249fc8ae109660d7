/* test_startup.c - what runs before the drive does: the flash CRC check
 * (flash_crc.h) against a fake image, and the start-up faults the app
 * latches (app_latch_startup_fault: WATCHDOG_RESET, FLASH_CRC), against
 * the cmocka mock of the HAL (tests/app_harness.h).
 *
 * The CRC's expected values are independent of the code under test: the
 * check value of "123456789" is CRC-32/POSIX's 0x765E7680 (the catalogue
 * of parametrised CRC algorithms: poly 0x04C11DB7, init 0, no reflection,
 * final XOR 0xFFFFFFFF) with the final XOR undone, 0x89A1897F; the fake
 * image's CRC is computed here by a table-driven CRC, not the bitwise one
 * of flash_crc.c. */
#include "app_harness.h"
#include "flash_crc.h"

#include <string.h>

#define CHECK_POSIX 0x765E7680UL       /* CRC-32/POSIX("123456789") */
#define POSIX_XOROUT 0xFFFFFFFFUL
#define IMAGE_WORDS 1000u              /* not a multiple of the chunk: a short last chunk */

/* ---- an independent CRC32_PRIME: MSB-first table over octets ------------- */

static uint32_t table[256];

static void table_init(void)
{
    for (uint32_t n = 0; n < 256u; n++) {
        uint32_t c = n << 24;
        for (int k = 0; k < 8; k++) {
            c = (c & 0x80000000UL) ? (c << 1) ^ 0x04C11DB7UL : (c << 1);
        }
        table[n] = c;
    }
}

static uint32_t table_crc_octets(const uint8_t *p, size_t n)
{
    uint32_t c = 0;
    for (size_t k = 0; k < n; k++) {
        c = (c << 8) ^ table[((c >> 24) ^ p[k]) & 0xFFu];
    }
    return c;
}

/* The image's octets as the linker sees a C28x word: low octet first. */
static uint32_t table_crc_words(const uint16_t *w, size_t n)
{
    uint8_t o[2 * IMAGE_WORDS];
    for (size_t k = 0; k < n; k++) {
        o[2 * k] = (uint8_t)(w[k] & 0xFFu);
        o[2 * k + 1] = (uint8_t)(w[k] >> 8);
    }
    return table_crc_octets(o, 2 * n);
}

static uint16_t image[IMAGE_WORDS];

static void image_fill(void)
{
    uint32_t x = 12345u; /* any fixed content: a linear congruential sequence */
    for (size_t k = 0; k < IMAGE_WORDS; k++) {
        x = x * 1103515245u + 12345u;
        image[k] = (uint16_t)(x >> 16);
    }
}

/* The watchdog service: counts calls and the largest run of words between two. */
static uint32_t services;

static void service(void)
{
    services++;
}

/* ---- the CRC ---------------------------------------------------------- */

static void crc_check_value(void **state)
{
    (void)state;
    const char *s = "123456789";
    uint32_t c = 0;
    for (size_t k = 0; k < strlen(s); k++) {
        c = crc32_prime_octet(c, (uint16_t)s[k]);
    }
    assert_int_equal(c, CHECK_POSIX ^ POSIX_XOROUT);
    assert_int_equal(c, 0x89A1897FUL);
}

/* Low octet first: the words 0x3231, 0x3433, ... are "12345678". */
static void crc_words_low_octet_first(void **state)
{
    (void)state;
    const uint16_t w[4] = { 0x3231u, 0x3433u, 0x3635u, 0x3837u };
    table_init();
    assert_int_equal(crc32_prime_words(0, w, 4), table_crc_octets((const uint8_t *)"12345678", 8));
}

static void crc_record_matches_fake_image(void **state)
{
    (void)state;
    table_init();
    image_fill();
    const uint32_t expected = table_crc_words(image, IMAGE_WORDS);
    services = 0;
    assert_true(flash_crc_record_ok(FLASH_CRC32_PRIME_ID, image, IMAGE_WORDS, expected, service));
    /* one service before each of the 16 chunks (15 x 64 + 40 words), one at the end */
    assert_int_equal(services, (IMAGE_WORDS + FLASH_CRC_CHUNK_WORDS - 1u) / FLASH_CRC_CHUNK_WORDS + 1u);
}

/* Any one flipped bit anywhere, even in the short last chunk, is a mismatch. */
static void crc_record_detects_a_flipped_bit(void **state)
{
    (void)state;
    table_init();
    image_fill();
    const uint32_t expected = table_crc_words(image, IMAGE_WORDS);
    const size_t where[4] = { 0u, 63u, 64u, IMAGE_WORDS - 1u };
    for (int j = 0; j < 4; j++) {
        for (unsigned bit = 0; bit < 16u; bit += 5u) {
            image[where[j]] ^= (uint16_t)(1u << bit);
            assert_false(flash_crc_record_ok(FLASH_CRC32_PRIME_ID, image, IMAGE_WORDS, expected, service));
            image[where[j]] ^= (uint16_t)(1u << bit);
        }
    }
    assert_true(flash_crc_record_ok(FLASH_CRC32_PRIME_ID, image, IMAGE_WORDS, expected, service));
}

/* A record of another crc_tbl.h algorithm cannot be vouched for: false. */
static void crc_record_unknown_algorithm_fails(void **state)
{
    (void)state;
    table_init();
    image_fill();
    const uint32_t expected = table_crc_words(image, IMAGE_WORDS);
    assert_false(flash_crc_record_ok(2u /* CRC16_ALT */, image, IMAGE_WORDS, expected, service));
}

/* ---- start-up faults --------------------------------------------------- */

/* A watchdog reset is latched: PWM off, FAULT, no start until the operator clears it. */
static void watchdog_reset_latched_until_cleared(void **state)
{
    (void)state;
    const hal_sample_t s = sample(0.0f, 0.0f, VDC);
    init_app();
    expect_function_call(hal_pwm_disable);
    app_latch_startup_fault(&app, APP_FAULT_WATCHDOG_RESET, 0.0f, 0.0f);
    assert_int_equal(app.state, APP_STATE_FAULT);
    assert_int_equal(app.fault, APP_FAULT_WATCHDOG_RESET);
    assert_int_equal(app.snapshot.state, APP_STATE_INIT);
    assert_false(app.pwm_on);

    /* a start is not taken while faulted; outputs stay off (no PWM call) */
    app_request_start(&app);
    expect_function_call(hal_sample_read);
    will_return(hal_sample_read, &s);
    expect_function_call(hal_isr_ack);
    app_isr(&app);
    assert_int_equal(app.state, APP_STATE_FAULT);

    /* the operator's fault reset clears it */
    expect_reset_isr(&s, 0);
    assert_int_equal(app.state, APP_STATE_IDLE);
    assert_int_equal(app.fault, APP_FAULT_NONE);
}

/* A flash CRC mismatch is latched with the record's index and no reset clears it. */
static void flash_crc_fault_is_permanent(void **state)
{
    (void)state;
    const hal_sample_t s = sample(0.0f, 0.0f, VDC);
    init_app();
    expect_function_call(hal_pwm_disable);
    app_latch_startup_fault(&app, APP_FAULT_FLASH_CRC, 3.0f, 0.0f);
    assert_int_equal(app.fault, APP_FAULT_FLASH_CRC);
    assert_true(app.snapshot.value == 3.0f);
    for (int k = 0; k < 3; k++) {
        /* the reset request is taken and dropped without a protection check */
        expect_function_call(hal_trip_clear);
        app_fault_reset(&app);
        expect_function_call(hal_sample_read);
        will_return(hal_sample_read, &s);
        expect_function_call(hal_isr_ack);
        app_isr(&app);
        assert_int_equal(app.state, APP_STATE_FAULT);
        assert_int_equal(app.fault, APP_FAULT_FLASH_CRC);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(crc_check_value),
        cmocka_unit_test(crc_words_low_octet_first),
        cmocka_unit_test(crc_record_matches_fake_image),
        cmocka_unit_test(crc_record_detects_a_flipped_bit),
        cmocka_unit_test(crc_record_unknown_algorithm_fails),
        cmocka_unit_test(watchdog_reset_latched_until_cleared),
        cmocka_unit_test(flash_crc_fault_is_permanent),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
