/* csv_writer (drive_sil's CSV thread): rows in give the bytes of
 * sil_csv_row() on the same rows, in order, across the ring's wrap-around
 * and a last partial block; a hand-built line anchors the format; a write
 * error (/dev/full) comes back as its errno and the producer never hangs;
 * a size limit ends the file at a whole row. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "csv_writer.h"

#define N_DOUBLES (sizeof(sil_row_t) / sizeof(double))
/* enough rows to wrap the ring three times and end in a partial block */
#define N_ROWS (3u * CSV_WRITER_BLOCKS * CSV_WRITER_BLOCK_ROWS + 17u)
#define LCG_A 6364136223846793005ull
#define LCG_C 1442695040888963407ull

static csv_writer_t g_w;   /* large: not on the stack */
static sil_row_t g_rows[N_ROWS];

/* Rows of every kind of value a column holds: small integers, zero, NaN, signed decimals. */
static void make_rows(void)
{
    uint64_t s = 7u;
    for (unsigned k = 0; k < N_ROWS; k++) {
        double v[N_DOUBLES];
        for (unsigned i = 0; i < N_DOUBLES; i++) {
            s = s * LCG_A + LCG_C;
            const double u = (double)(s >> 11) / 9007199254740992.0;
            switch ((s >> 5) % 5u) {
            case 0: v[i] = (double)((s >> 20) % 40u); break;
            case 1: v[i] = 0.0; break;
            case 2: v[i] = NAN; break;
            case 3: v[i] = (u - 0.5) * 3000.0; break;
            default: v[i] = u * 1e-5; break;
            }
        }
        v[0] = (double)k * 1e-3;
        memcpy(&g_rows[k], v, sizeof v);
    }
}

/* rows[0..n) through a writer into a memory stream: its bytes (free them) and length. */
static char *write_through_thread(const sil_row_t *rows, unsigned n, size_t *len)
{
    char *got = NULL;
    FILE *f = open_memstream(&got, len);
    assert_non_null(f);
    assert_int_equal(csv_writer_start(&g_w, f, 0u, CSV_WRITER_NO_LIMIT), 0);
    for (unsigned k = 0; k < n; k++) {
        assert_int_equal(csv_writer_put(&g_w, &rows[k]), 0);
    }
    assert_int_equal(csv_writer_finish(&g_w), 0);
    assert_int_equal(fclose(f), 0);
    return got;
}

static void rows_come_out_as_sil_csv_row_in_order(void **state)
{
    (void)state;
    make_rows();
    char *want = NULL;
    size_t want_len = 0;
    FILE *fw = open_memstream(&want, &want_len);
    assert_non_null(fw);
    for (unsigned k = 0; k < N_ROWS; k++) {
        sil_csv_row(fw, &g_rows[k]);
    }
    assert_int_equal(fclose(fw), 0);
    size_t got_len = 0;
    char *got = write_through_thread(g_rows, N_ROWS, &got_len);
    assert_true(want_len > N_ROWS * N_DOUBLES);
    assert_int_equal(got_len, want_len);
    assert_memory_equal(got, want, want_len);
    free(want);
    free(got);
}

/* One row written through the thread against a line built by hand with
 * printf: t_s = 0.25 (the first column), state = 3 (the second), 0 elsewhere. */
static void one_row_matches_a_hand_built_line(void **state)
{
    (void)state;
    char *head = NULL;
    size_t head_len = 0;
    FILE *fh = open_memstream(&head, &head_len);
    assert_non_null(fh);
    sil_csv_header(fh);
    assert_int_equal(fclose(fh), 0);
    assert_true(strncmp(head, "t_s,state,", 10) == 0);
    unsigned n_cols = 1;
    for (size_t i = 0; i < head_len; i++) {
        n_cols += (head[i] == ',') ? 1u : 0u;
    }
    char want[1024];
    int n = snprintf(want, sizeof want, "%.9g,%.9g", 0.25, 3.0);
    for (unsigned i = 2; i < n_cols; i++) {
        n += snprintf(want + n, sizeof want - (size_t)n, ",%.9g", 0.0);
    }
    snprintf(want + n, sizeof want - (size_t)n, "\n");

    sil_row_t row;
    memset(&row, 0, sizeof row);
    row.t_s = 0.25;
    row.state = 3.0;
    size_t got_len = 0;
    char *got = write_through_thread(&row, 1u, &got_len);
    assert_string_equal(got, want);
    free(head);
    free(got);
}

static void no_rows_write_nothing(void **state)
{
    (void)state;
    size_t got_len = 0;
    char *got = write_through_thread(g_rows, 0u, &got_len);
    assert_int_equal(got_len, 0);
    free(got);
}

/* A full disk: the error comes back (from put at a hand-over, and from
 * finish) as ENOSPC; puts after it return at once instead of hanging. */
static void write_error_comes_back_as_its_errno(void **state)
{
    (void)state;
    FILE *f = fopen("/dev/full", "w");
    if (f == NULL) {
        skip();
    }
    make_rows();
    assert_int_equal(csv_writer_start(&g_w, f, 0u, CSV_WRITER_NO_LIMIT), 0);
    int first = 0;
    for (unsigned k = 0; k < N_ROWS; k++) {
        const int rc = csv_writer_put(&g_w, &g_rows[k]);
        if (first == 0) {
            first = rc;
        } else {
            assert_int_equal(rc, first);   /* stays reported */
        }
    }
    assert_int_equal(first, ENOSPC);
    assert_int_equal(csv_writer_finish(&g_w), ENOSPC);
    fclose(f);
}

/* A size limit (drive_sil --max-csv-mb): the file ends at the last whole
 * line of sil_csv_row()'s output that keeps header + rows within the
 * limit; the rows after it are dropped without an error, and the first
 * dropped row's time is reported. */
static void size_limit_ends_at_a_whole_row(void **state)
{
    (void)state;
    make_rows();
    char *want = NULL;
    size_t want_len = 0;
    FILE *fw = open_memstream(&want, &want_len);
    assert_non_null(fw);
    for (unsigned k = 0; k < N_ROWS; k++) {
        sil_csv_row(fw, &g_rows[k]);
    }
    assert_int_equal(fclose(fw), 0);
    const uint64_t header = 100u;
    const uint64_t limit = header + want_len / 2u;
    /* by hand: whole lines while header + their bytes <= limit */
    size_t keep = 0;
    unsigned kept_rows = 0;
    for (size_t i = 0; i < want_len; i++) {
        if (want[i] == '\n') {
            if (header + i + 1u > limit) {
                break;
            }
            keep = i + 1u;
            kept_rows++;
        }
    }
    assert_true(kept_rows > 0u && kept_rows < N_ROWS);

    char *got = NULL;
    size_t got_len = 0;
    FILE *f = open_memstream(&got, &got_len);
    assert_non_null(f);
    assert_int_equal(csv_writer_start(&g_w, f, header, limit), 0);
    for (unsigned k = 0; k < N_ROWS; k++) {
        assert_int_equal(csv_writer_put(&g_w, &g_rows[k]), 0);
    }
    assert_int_equal(csv_writer_finish(&g_w), 0);
    assert_int_equal(fclose(f), 0);
    assert_int_equal(got_len, keep);
    assert_memory_equal(got, want, keep);
    assert_true(g_w.capped);
    assert_float_equal(g_w.t_capped_s, g_rows[kept_rows].t_s, 0.0);
    free(want);
    free(got);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(rows_come_out_as_sil_csv_row_in_order),
        cmocka_unit_test(one_row_matches_a_hand_built_line),
        cmocka_unit_test(no_rows_write_nothing),
        cmocka_unit_test(write_error_comes_back_as_its_errno),
        cmocka_unit_test(size_limit_ends_at_a_whole_row),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
