/* csv_num.c - "%.9g" without printf; see csv_num.h. */
#include "csv_num.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SIG 9                       /* significant digits */
#define SIG_LO 1e8                  /* 10^(SIG-1): a scaled value holds SIG digits in [SIG_LO, SIG_HI) */
#define SIG_HI 1e9
#define SIG_HI_U 1000000000u
#define TIE_BAND 1e-6               /* closer than this to x.5: libc decides */
#define EXP_FIXED_MIN (-4)          /* %g's fixed notation for -4 <= exponent < precision */
#define LOG10_2 0.30102999566398120

/* Powers of ten exact in double (5^22 < 2^53). */
static const double P10[] = {
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11,
    1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
};
#define N_P10 ((int)(sizeof P10 / sizeof P10[0]))

/* v x 10^k rounded once (the power is exact): within 2^-53 relative of the true product, i.e.
 * within 1.2e-7 of it in units of the last of SIG digits, far inside TIE_BAND. */
static double scale10(double v, int k)
{
    return (k >= 0) ? v * P10[k] : v / P10[-k];
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
    if (SIG - 1 - e >= N_P10 - 1 || e - (SIG - 1) >= N_P10 - 1) {   /* beyond 1e-13 .. 1e29 (with the
                                                                      * correction below): no exact power */
        return (int)(p - out) + snprintf(p, CSV_NUM_MAX - (size_t)(p - out), "%.9g", v);
    }
    double s = scale10(v, SIG - 1 - e);
    if (s >= SIG_HI) {
        e++;
        s = scale10(v, SIG - 1 - e);
    } else if (s < SIG_LO) {
        e--;
        s = scale10(v, SIG - 1 - e);
    }
    double whole = floor(s);
    if (fabs(s - whole - 0.5) < TIE_BAND) {
        return (int)(p - out) + snprintf(p, CSV_NUM_MAX - (size_t)(p - out), "%.9g", v);
    }
    uint32_t m = (uint32_t)whole + ((s - whole > 0.5) ? 1u : 0u);
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
