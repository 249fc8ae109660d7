/* csv_num_g9() against snprintf("%.9g"): special values, values next to
 * powers of ten and rounding ties, and random values of every magnitude
 * (random bit patterns, scaled uniforms, short decimals); then the edges of
 * its fast paths: whole numbers, signed zero, powers of ten and their
 * neighbours, exact ties of the 10th digit, subnormals, inf and NaN. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "csv_num.h"

#define N_RANDOM 300000
#define LCG_A 6364136223846793005ull
#define LCG_C 1442695040888963407ull

static uint64_t g_rng = 1u;

static uint64_t next_u64(void)
{
    g_rng = g_rng * LCG_A + LCG_C;
    return g_rng ^ (g_rng >> 29);
}

static void check(double v)
{
    char got[CSV_NUM_MAX];
    char want[64];
    int n = csv_num_g9(got, v);
    if (isnan(v)) {
        strcpy(want, "nan");
    } else {
        snprintf(want, sizeof want, "%.9g", v);
    }
    if (strcmp(got, want) != 0 || n != (int)strlen(want)) {
        fail_msg("%.17g: csv_num_g9 \"%s\" (%d), printf \"%s\"", v, got, n, want);
    }
}

static void special_values_print_as_printf(void **state)
{
    (void)state;
    const double v[] = { 0.0, -0.0, 1.0, -1.0, 0.5, 1e-4, 9.9999999995e-5, 1.00000000005e-4, 999999999.5,
                         999999999.4, 1e9, 123456789.0, 1234567890.0, 0.1, 0.3, 2.5e-7, 1e300, -1e-300,
                         5e-324, 1.7976931348623157e308, 0.9999999995, 9.9999999949999, 99999.99995,
                         INFINITY, -INFINITY, NAN, -NAN, 0.011, 0.24, 311.0, 1.05, 0.8, 0.95, 1e-5, 1e8 };
    for (size_t i = 0; i < sizeof v / sizeof v[0]; i++) {
        check(v[i]);
    }
}

static void random_values_print_as_printf(void **state)
{
    (void)state;
    for (int k = 0; k < N_RANDOM; k++) {
        double v;
        uint64_t u = next_u64();
        switch (k % 3) {
        case 0:
            memcpy(&v, &u, sizeof v);
            if (!isfinite(v)) {
                continue;
            }
            break;
        case 1:
            v = ((double)(u >> 11) / 9007199254740992.0 - 0.5) * pow(10.0, (double)((int)(u % 24u) - 12));
            break;
        default:   /* short decimals: many land next to a tie of the 10th digit */
            v = (double)(u % 2000000000u) / pow(10.0, (double)(u % 15u));
            break;
        }
        check(v);
    }
}

/* v and its two neighbouring doubles. */
static void check_around(double v)
{
    check(v);
    check(nextafter(v, INFINITY));
    check(nextafter(v, -INFINITY));
}

static void whole_numbers_print_as_printf(void **state)
{
    (void)state;
    for (int i = -2000; i <= 2000; i++) {
        check((double)i);
    }
    for (int k = 0; k <= 62; k++) {   /* the fast path ends at 2^30 and 10^9 */
        check_around(ldexp(1.0, k));
        check_around(-ldexp(1.0, k));
        check(ldexp(1.0, k) - 1.0);
        check(ldexp(1.0, k) + 1.0);
    }
    for (int k = 0; k <= 15; k++) {
        check(pow(10.0, k) - 1.0);
        check(pow(10.0, k) + 1.0);
        check(-pow(10.0, k) - 1.0);
    }
    const double v[] = { 999999999.0, 1000000000.0, 1000000001.0, 999999998.0, 536870911.0, 536870912.0,
                         1073741823.0, 1073741824.0, 123456789.0, 1234567891.0, 4294967295.0, 4294967296.0,
                         65535.0, 0x7fffffff.0p0, 2.0 * 0x7fffffff.0p0 };
    for (size_t i = 0; i < sizeof v / sizeof v[0]; i++) {
        check(v[i]);
        check(-v[i]);
    }
}

static void zero_infinity_nan_print_as_printf(void **state)
{
    (void)state;
    check(0.0);
    check(-0.0);
    check(INFINITY);
    check(-INFINITY);
    check(NAN);
    check(-NAN);
    uint64_t payload = 0x7ff0000000000001ull;   /* a signalling NaN's bits */
    double snan;
    memcpy(&snan, &payload, sizeof snan);
    check(snan);
    check(nan("12345"));
}

static void powers_of_ten_print_as_printf(void **state)
{
    (void)state;
    for (int k = -40; k <= 40; k++) {
        const double p = pow(10.0, k);
        check_around(p);
        check_around(-p);
        check_around(1.23456789 * p);
        check_around(9.99999999 * p);
        check_around(9.999999995 * p);
        check_around(9.9999999949 * p);
    }
}

/* Exact decimal ties of the 10th significant digit: (10 m + 5) x 10^j is a
 * whole number, (10 m + 5) / 2 ends in .5; both exact in double. */
static void rounding_ties_print_as_printf(void **state)
{
    (void)state;
    const uint64_t m9[] = { 100000000u, 123456789u, 999999999u, 500000000u, 314159265u, 100000001u };
    for (size_t i = 0; i < sizeof m9 / sizeof m9[0]; i++) {
        const double tie = (double)(10u * m9[i] + 5u);
        for (int j = 0; j <= 8; j++) {
            check_around(tie * pow(10.0, j));
            check_around(-tie * pow(10.0, j));
        }
        check_around(tie / 2.0);
        check_around((double)m9[i] + 0.5);
        check_around(-((double)m9[i] + 0.5));
    }
}

static void subnormals_print_as_printf(void **state)
{
    (void)state;
    check_around(DBL_MIN);
    check_around(-DBL_MIN);
    const double true_min = nextafter(0.0, 1.0);
    check(true_min);
    check(-true_min);
    check(DBL_MIN - true_min);   /* the largest subnormal */
    for (int k = 0; k < 1000; k++) {
        uint64_t u = next_u64() & 0x800FFFFFFFFFFFFFull;   /* exponent field 0 */
        double v;
        memcpy(&v, &u, sizeof v);
        check(v);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(special_values_print_as_printf),
        cmocka_unit_test(random_values_print_as_printf),
        cmocka_unit_test(whole_numbers_print_as_printf),
        cmocka_unit_test(zero_infinity_nan_print_as_printf),
        cmocka_unit_test(powers_of_ten_print_as_printf),
        cmocka_unit_test(rounding_ties_print_as_printf),
        cmocka_unit_test(subnormals_print_as_printf),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
