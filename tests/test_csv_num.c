/* csv_num_g9() against snprintf("%.9g"): special values, values next to
 * powers of ten and rounding ties, and random values of every magnitude
 * (random bit patterns, scaled uniforms, short decimals). */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(special_values_print_as_printf),
        cmocka_unit_test(random_values_print_as_printf),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
