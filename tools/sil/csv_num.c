/* csv_num.c - "%.9g" without printf; see csv_num.h. */
#include "csv_num.h"

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#define SIG 9                       /* significant digits */
#define SIG_LO 1e8                  /* 10^(SIG-1): a scaled value holds SIG digits in [SIG_LO, SIG_HI) */
#define SIG_HI 1e9
#define SIG_HI_U 1000000000u
#define TIE_BAND 1e-6               /* closer than this to x.5: libc decides */
#define EXP_FIXED_MIN (-4)          /* %g's fixed notation for -4 <= exponent < precision */

/* IEEE 754 binary64 fields. */
#define F64_SIGN 0x8000000000000000ull
#define F64_MANT_BITS 52
#define F64_MANT_MASK 0x000FFFFFFFFFFFFFull
#define F64_HIDDEN (1ull << F64_MANT_BITS)
#define F64_EXP_MASK 0x7FFu
#define F64_BIAS 1023
#define INT_FAST_E2_MAX 29          /* 2^30 > 1e9: integers below this binary exponent may print whole */
/* floor(e2 log10 2) = (e2 * LOG10_2_Q18) >> 18 for |e2| < 1650 (the correction below absorbs an error of 1) */
#define LOG10_2_Q18 78913
#define LOG10_2_SHIFT 18

/* Powers of ten exact in double (5^22 < 2^53). */
static const double P10[] = {
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11,
    1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
};
#define N_P10 ((int)(sizeof P10 / sizeof P10[0]))

/* "00" .. "99": two digits per division by 100. */
static const char PAIRS[] =
    "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
    "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
    "8081828384858687888990919293949596979899";

/* The SIG decimal digits of m < 10^SIG, zero-padded, into d[0..SIG-1]. */
static inline void digits9(char *d, uint32_t m)
{
    const uint32_t hi = m / 10000u;           /* 5 digits */
    const uint32_t lo = m - 10000u * hi;      /* 4 digits */
    const uint32_t h1 = hi / 100u;
    const uint32_t h0 = h1 / 100u;
    const uint32_t l1 = lo / 100u;
    d[0] = (char)('0' + h0);
    memcpy(d + 1, &PAIRS[2u * (h1 - 100u * h0)], 2);
    memcpy(d + 3, &PAIRS[2u * (hi - 100u * h1)], 2);
    memcpy(d + 5, &PAIRS[2u * l1], 2);
    memcpy(d + 7, &PAIRS[2u * (lo - 100u * l1)], 2);
}

static double scale10(double v, int k)
{
    return (k >= 0) ? v * P10[k] : v / P10[-k];
}

static int fallback(char *out, char *p, double v)
{
    return (int)(p - out) + snprintf(p, CSV_NUM_MAX - (size_t)(p - out), "%.9g", v);
}

/* A whole number below 10^9 (state, fault, flags, counts: v = (mant |
 * hidden bit) 2^(e2 - 52)) as itself into p, NUL-terminated; its length,
 * or -1 when v is no such number. */
static int whole(char *p, int e2, uint64_t mant)
{
    if (e2 < 0 || e2 > INT_FAST_E2_MAX || (mant & (F64_MANT_MASK >> e2)) != 0u) {
        return -1;
    }
    const uint32_t m = (uint32_t)((mant | F64_HIDDEN) >> (F64_MANT_BITS - e2));
    if (m < 100u) {   /* the flags and counts: one or two digits */
        memcpy(p, &PAIRS[2u * m + ((m < 10u) ? 1u : 0u)], 2);
        p[(m < 10u) ? 1 : 2] = '\0';
        return (m < 10u) ? 1 : 2;
    }
    if (m >= SIG_HI_U) {
        return -1;
    }
    char d[2 * SIG] = { 0 };   /* the digits, and room for the fixed-size copy below to read */
    digits9(d, m);
    int lead = 0;   /* leading zeros; m >= 100 */
    while (d[lead] == '0') {
        lead++;
    }
    memcpy(p, d + lead, SIG);   /* within out[]: the NUL below ends it */
    p[SIG - lead] = '\0';
    return SIG - lead;
}

/* v > 0, normal, in [2^e2, 2^(e2+1)), rounded to SIG significant digits:
 * *m (SIG digits) x 10^(*e - SIG + 1). False where that is not exact
 * (beyond the exact powers of ten, or a tie within TIE_BAND): snprintf's. */
static bool round_sig(double v, int e2, uint32_t *m_out, int *e_out)
{
    /* the decimal exponent, or one below: corrected after scaling */
    int e = (e2 >= 0) ? (e2 * LOG10_2_Q18) >> LOG10_2_SHIFT
                      : -((-e2 * LOG10_2_Q18 + (1 << LOG10_2_SHIFT) - 1) >> LOG10_2_SHIFT);
    if (SIG - 1 - e >= N_P10 - 1 || e - (SIG - 1) >= N_P10 - 1) {   /* beyond 1e-13 .. 1e29 (with the
                                                                      * correction below): no exact power */
        return false;
    }
    /* v x 10^k rounded once (the power is exact): within 2^-53 relative of the true product, i.e.
     * within 1.2e-7 of it in units of the last of SIG digits, far inside TIE_BAND. */
    double s = scale10(v, SIG - 1 - e);
    if (s >= SIG_HI) {
        e++;
        s = scale10(v, SIG - 1 - e);
    } else if (s < SIG_LO) {
        e--;
        s = scale10(v, SIG - 1 - e);
    }
    uint32_t m = (uint32_t)s;   /* s > 0: truncation is floor */
    const double frac = s - (double)m;
    if (frac > 0.5 - TIE_BAND && frac < 0.5 + TIE_BAND) {
        return false;
    }
    m += (frac > 0.5) ? 1u : 0u;
    if (m >= SIG_HI_U) {   /* rounded up to the next power of ten */
        m /= 10u;
        e++;
    }
    *m_out = m;
    *e_out = e;
    return true;
}

/* The SIG digits d[] (the first nd significant) at decimal exponent e in
 * %g's layout into p, NUL-terminated; returns the end (at the NUL). Fixed-size
 * copies: a few bytes past the text, within out[CSV_NUM_MAX]. */
static char *layout(char *p, const char *d, int nd, int e)
{
    if (e >= EXP_FIXED_MIN && e < SIG) {
        if (e < 0) {   /* 0.000ddd */
            memcpy(p, "0.000", 5);
            p += 1 - e;
            memcpy(p, d, SIG);
            p += nd;
        } else if (nd <= e + 1) {   /* ddd000: whole, the zeros are d's */
            memcpy(p, d, SIG);
            p += e + 1;
        } else {   /* ddd.ddd (e < SIG - 1 here) */
            memcpy(p, d, SIG - 1);
            p[e + 1] = '.';
            memcpy(p + e + 2, d + e + 1, SIG - 1);
            p += nd + 1;
        }
    } else {   /* d.ddde+XX (|e| < 100 here: larger went to snprintf) */
        p[0] = d[0];
        p[1] = '.';
        memcpy(p + 2, d + 1, SIG - 1);
        p += (nd > 1) ? nd + 1 : 1;
        *p++ = 'e';
        *p++ = (e < 0) ? '-' : '+';
        const int a = (e < 0) ? -e : e;
        memcpy(p, &PAIRS[2 * a], 2);
        p += 2;
    }
    *p = '\0';
    return p;
}

int csv_num_g9(char *out, double v)
{
    uint64_t bits;
    memcpy(&bits, &v, sizeof bits);
    const unsigned ef = (unsigned)(bits >> F64_MANT_BITS) & F64_EXP_MASK;
    const uint64_t mant = bits & F64_MANT_MASK;
    char *p = out;
    if (ef == F64_EXP_MASK && mant != 0u) {
        memcpy(out, "nan", 4);
        return 3;
    }
    if ((bits & F64_SIGN) != 0u) {
        *p++ = '-';
        v = -v;
    }
    if (ef == F64_EXP_MASK) {
        memcpy(p, "inf", 4);
        return (int)(p - out) + 3;
    }
    if (ef == 0u) {
        if (mant != 0u) {   /* subnormal */
            return fallback(out, p, v);
        }
        *p++ = '0';
        *p = '\0';
        return (int)(p - out);
    }
    const int e2 = (int)ef - F64_BIAS;   /* v in [2^e2, 2^(e2+1)) */
    const int n = whole(p, e2, mant);
    if (n >= 0) {
        return (int)(p - out) + n;
    }
    uint32_t m;
    int e;
    if (!round_sig(v, e2, &m, &e)) {
        return fallback(out, p, v);
    }
    char d[2 * SIG] = { 0 };   /* the digits, and room for layout's fixed-size copies to read */
    digits9(d, m);
    int nd = SIG;   /* %g drops trailing zeros */
    while (d[nd - 1] == '0') {
        nd--;
    }
    return (int)(layout(p, d, nd, e) - out);
}
