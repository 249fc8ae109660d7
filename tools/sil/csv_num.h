/*
 * csv_num.h - numbers as the SIL CSV writes them: the text of printf's
 * "%.9g" (NaN as "nan") without printf, which dominated a whole-process
 * drive_sil run (callgrind: 54 % of its instructions). About 100
 * instructions per number on drive_sil's CSV (callgrind, x86-64): whole
 * numbers below 10^9 and zero print directly, the decimal exponent comes
 * from the double's bits, the 9 digits from a scaled integer by pairs.
 * Exact: a value whose 10th significant digit sits within 1e-6 of a
 * rounding tie, a subnormal and a magnitude beyond 1e-13 .. 1e29 are
 * handed to snprintf; tests/test_csv_num.c compares both on random values
 * of every magnitude and on each fast path's edges.
 */
#ifndef CSV_NUM_H
#define CSV_NUM_H

/* Longest text csv_num_g9() writes, with the terminating NUL ("-1.23456789e-308"). */
#define CSV_NUM_MAX 24

/* Write v into out[CSV_NUM_MAX] as "%.9g" does ("nan" for any NaN); returns the length.
 * Bytes of out[] past the terminating NUL may be overwritten. */
int csv_num_g9(char *out, double v);

#endif /* CSV_NUM_H */
