/*
 * csv_num.h - numbers as the SIL CSV writes them: the text of printf's
 * "%.9g" (NaN as "nan"), about 10 x faster than printf, which dominated a
 * whole-process drive_sil run (callgrind: 54 % of its instructions).
 * Exact: a value whose 10th significant digit sits within 1e-6 of a
 * rounding tie is handed to snprintf; tests/test_csv_num.c compares both
 * on random values of every magnitude.
 */
#ifndef CSV_NUM_H
#define CSV_NUM_H

/* Longest text csv_num_g9() writes, with the terminating NUL ("-1.23456789e-308"). */
#define CSV_NUM_MAX 24

/* Write v into out[CSV_NUM_MAX] as "%.9g" does ("nan" for any NaN); returns the length. */
int csv_num_g9(char *out, double v);

#endif /* CSV_NUM_H */
