/* csv_num.c - "%.9g" without printf; see csv_num.h. */
#include "csv_num.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SIG 9                       /* significant digits */
#define SIG_LO 1e8L                 /* 10^(SIG-1): a scaled value holds SIG digits in [SIG_LO, SIG_HI) */
#define SIG_HI 1e9L
#define SIG_HI_U 1000000000u
#define TIE_BAND 1e-6L              /* closer than this to x.5: libc decides */
#define EXP_FIXED_MIN (-4)          /* %g's fixed notation for -4 <= exponent < precision */
#define LOG10_2 0.30102999566398120

/* Powers of ten exact in long double (x87 64-bit mantissa: 5^27 < 2^63). */
static const long double P10[] = {
    1e0L, 1e1L, 1e2L, 1e3L, 1e4L, 1e5L, 1e6L, 1e7L, 1e8L, 1e9L, 1e10L, 1e11L, 1e12L, 1e13L,
    1e14L, 1e15L, 1e16L, 1e17L, 1e18L, 1e19L, 1e20L, 1e21L, 1e22L, 1e23L, 1e24L, 1e25L, 1e26L, 1e27L,
};
#define N_P10 ((int)(sizeof P10 / sizeof P10[0]))

/* v x 10^k, rounded once where the power is exact. */
static long double scale10(double v, int k)
{
    long double x = (long double)v;
    if (k >= 0) {
        return (k < N_P10) ? x * P10[k] : x * powl(10.0L, (long double)k);
    }
    return (-k < N_P10) ? x / P10[-k] : x / powl(10.0L, (long double)-k);
}

static char *put_digits(char *p, const char *d, int from, int to)
{
    for (int i = from; i < to; i++) {
        *p++ = d[i];
    }
    return p;
}

int csv_num_g9(char *out, double v)
{
    char *p = out;
    if (isnan(v)) {
        strcpy(out, "nan");
        return 3;
    }
    if (signbit(v)) {
        *p++ = '-';
        v = -v;
    }
    if (isinf(v)) {
        strcpy(p, "inf");
        return (int)(p - out) + 3;
    }
    if (v == 0.0) {
        *p++ = '0';
        *p = '\0';
        return (int)(p - out);
    }
    int e2 = 0;
    (void)frexp(v, &e2);   /* v in [2^(e2-1), 2^e2) */
    int e = (int)floor((double)(e2 - 1) * LOG10_2);   /* the decimal exponent, or one below: corrected here */
    long double s = scale10(v, SIG - 1 - e);
    while (s >= SIG_HI) {
        e++;
        s = scale10(v, SIG - 1 - e);
    }
    while (s < SIG_LO) {
        e--;
        s = scale10(v, SIG - 1 - e);
    }
    long double whole = floorl(s);
    if (fabsl(s - whole - 0.5L) < TIE_BAND) {
        return (int)(p - out) + snprintf(p, CSV_NUM_MAX - (size_t)(p - out), "%.9g", v);
    }
    uint64_t m = (uint64_t)whole + ((s - whole > 0.5L) ? 1u : 0u);
    if (m >= SIG_HI_U) {   /* rounded up to the next power of ten */
        m /= 10u;
        e++;
    }
    char d[SIG];
    for (int i = SIG - 1; i >= 0; i--) {
        d[i] = (char)('0' + (int)(m % 10u));
        m /= 10u;
    }
    int nd = SIG;   /* %g drops trailing zeros */
    while (nd > 1 && d[nd - 1] == '0') {
        nd--;
    }
    if (e >= EXP_FIXED_MIN && e < SIG) {
        if (e >= 0) {
            for (int i = 0; i <= e; i++) {
                *p++ = (i < nd) ? d[i] : '0';
            }
            if (nd > e + 1) {
                *p++ = '.';
                p = put_digits(p, d, e + 1, nd);
            }
        } else {
            *p++ = '0';
            *p++ = '.';
            for (int i = 0; i < -e - 1; i++) {
                *p++ = '0';
            }
            p = put_digits(p, d, 0, nd);
        }
    } else {
        *p++ = d[0];
        if (nd > 1) {
            *p++ = '.';
            p = put_digits(p, d, 1, nd);
        }
        *p++ = 'e';
        *p++ = (e < 0) ? '-' : '+';
        int a = abs(e);
        if (a >= 100) {
            *p++ = (char)('0' + a / 100);
            a %= 100;
        }
        *p++ = (char)('0' + a / 10);
        *p++ = (char)('0' + a % 10);
    }
    *p = '\0';
    return (int)(p - out);
}
