/* Unit tests for hal/sim/sensors.c: encoder quantization and wrap, ADC
 * rounding, range and offset, and the seeded noise (reproducible, unit
 * variance). Expectations are hand values. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>

#include "sensors.h"

#define TWO_PI 6.283185307179586
#define CPR 10000u                     /* 2500 lines x4 */
#define LSB_A (15.0 / 2048.0)          /* 12 bits over +-15 A */

static sensors_cfg_t cfg(void)
{
    sensors_cfg_t c;
    sensors_default_cfg(&c);
    return c;
}

/* The chain of *c, ready to sample. */
static sensors_t chain(const sensors_cfg_t *c)
{
    sensors_t s;
    sensors_init(&s, c);
    return s;
}

static void encoder_counts_and_wraps(void **state)
{
    (void)state;
    sensors_cfg_t c = cfg();
    sensors_t s = chain(&c);
    const double count_rad = TWO_PI / CPR;
    assert_int_equal(sensor_encoder_count(&s, 0.0), 0);
    assert_int_equal(sensor_encoder_count(&s, 0.4 * count_rad), 0);
    assert_int_equal(sensor_encoder_count(&s, 1.6 * count_rad), 1);
    assert_int_equal(sensor_encoder_count(&s, 0.25 * TWO_PI), CPR / 4u);
    assert_int_equal(sensor_encoder_count(&s, TWO_PI - 0.5 * count_rad), CPR - 1u);
    assert_int_equal(sensor_encoder_count(&s, TWO_PI), 0);
    assert_int_equal(sensor_encoder_count(&s, TWO_PI + 2.5 * count_rad), 2);
    assert_int_equal(sensor_encoder_count(&s, -0.5 * count_rad), CPR - 1u);
    assert_int_equal(sensor_encoder_count(&s, -3.0 * TWO_PI + 0.5 * TWO_PI), CPR / 2u);
    assert_int_equal(sensor_encoder_count(&s, -1e-300), 0);   /* rounds to a full turn: wraps to 0 */
    c.enc_lines = 1000u;
    s = chain(&c);
    assert_int_equal(sensor_encoder_count(&s, 0.5 * TWO_PI), 2000u);
}

static void adc_rounds_clamps_and_offsets(void **state)
{
    (void)state;
    const sensors_cfg_t c = cfg();
    const sensors_t s = chain(&c);
    prng_t g;
    prng_seed(&g, 1u);
    assert_float_equal(sensor_adc_current_A(&s, &g, 0.0, 0.0), 0.0, 1e-15);
    assert_float_equal(sensor_adc_current_A(&s, &g, 0.4 * LSB_A, 0.0), 0.0, 1e-15);
    assert_float_equal(sensor_adc_current_A(&s, &g, 0.6 * LSB_A, 0.0), LSB_A, 1e-15);
    assert_float_equal(sensor_adc_current_A(&s, &g, 3.0, 0.0), 410.0 * LSB_A, 1e-12);   /* 3/LSB = 409.6 */
    assert_float_equal(sensor_adc_current_A(&s, &g, -3.0, 0.0), -410.0 * LSB_A, 1e-12);
    assert_float_equal(sensor_adc_current_A(&s, &g, 100.0, 0.0), 2047.0 * LSB_A, 1e-12);
    assert_float_equal(sensor_adc_current_A(&s, &g, -100.0, 0.0), -15.0, 1e-12);
    assert_float_equal(sensor_adc_current_A(&s, &g, 1.0, 0.5), 205.0 * LSB_A, 1e-12);   /* 1.5/LSB = 204.8 */
    assert_float_equal(sensor_adc_vdc_V(&s, 311.0), 2123.0 * 600.0 / 4096.0, 1e-9);     /* 311/LSB = 2123.1 */
    assert_float_equal(sensor_adc_vdc_V(&s, 900.0), 4095.0 * 600.0 / 4096.0, 1e-9);
}

static void noise_is_reproducible_for_a_seed(void **state)
{
    (void)state;
    sensors_cfg_t c = cfg();
    c.adc_noise_A = 0.1;
    const sensors_t s = chain(&c);
    prng_t g1;
    prng_t g2;
    prng_t g3;
    prng_seed(&g1, 42u);
    prng_seed(&g2, 42u);
    prng_seed(&g3, 43u);
    int differ = 0;
    for (int k = 0; k < 1000; k++) {
        double a = sensor_adc_current_A(&s, &g1, 1.0, 0.0);
        double b = sensor_adc_current_A(&s, &g2, 1.0, 0.0);
        double d = sensor_adc_current_A(&s, &g3, 1.0, 0.0);
        assert_true(a == b);
        differ += (a != d);
    }
    assert_true(differ > 500);
}

/* 200000 deviates: mean within 5 sigma/sqrt(n) of 0, variance within 2 % of 1. */
static void gauss_has_unit_variance(void **state)
{
    (void)state;
    const int n = 200000;
    prng_t g;
    prng_seed(&g, 7u);
    double s = 0.0;
    double s2 = 0.0;
    for (int k = 0; k < n; k++) {
        double x = prng_gauss(&g);
        s += x;
        s2 += x * x;
    }
    double mean = s / n;
    double var = s2 / n - mean * mean;
    assert_true(fabs(mean) < 5.0 / sqrt((double)n));
    assert_true(fabs(var - 1.0) < 0.02);
    prng_seed(&g, 0u);   /* a zero seed still gives a working generator */
    double u = prng_uniform(&g);
    assert_true(u > 0.0 && u < 1.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(encoder_counts_and_wraps),
        cmocka_unit_test(adc_rounds_clamps_and_offsets),
        cmocka_unit_test(noise_is_reproducible_for_a_seed),
        cmocka_unit_test(gauss_has_unit_variance),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
