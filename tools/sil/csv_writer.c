/* csv_writer.c - the SIL CSV written by a second thread; see csv_writer.h. */
#include "csv_writer.h"

#include <errno.h>
#include <string.h>

/* Format block b's rows and write those that fit under the limit; 0 or an errno value.
 * *capped_at: t_s of the first row that did not fit, else left as it is. */
static int write_block(csv_writer_t *w, unsigned b, int *capped, double *capped_at)
{
    size_t n = 0;
    for (unsigned i = 0; i < w->n_rows[b] && !*capped; i++) {
        const size_t len = sil_csv_format(w->text + n, &w->rows[b][i]);
        if (w->bytes + n + len > w->max_bytes) {
            *capped = 1;
            *capped_at = w->rows[b][i].t_s;
        } else {
            n += len;
        }
    }
    errno = 0;
    if (fwrite(w->text, 1, n, w->f) != n || ferror(w->f)) {
        return (errno != 0) ? errno : EIO;
    }
    w->bytes += n;
    return 0;
}

/* The writer thread: every queued block in order until the end; after an
 * error the blocks are dropped unwritten (the producer stops at its next hand-over),
 * after the size limit too (the producer stops copying rows). */
static void *writer_main(void *arg)
{
    csv_writer_t *w = arg;
    int err = 0;
    int capped = 0;
    double capped_at = 0.0;
    pthread_mutex_lock(&w->lock);
    for (;;) {
        while (w->n_queued == 0u && !w->done) {
            pthread_cond_wait(&w->queued, &w->lock);
        }
        if (w->n_queued == 0u) {
            break;   /* done and drained */
        }
        const unsigned b = w->next;
        pthread_mutex_unlock(&w->lock);
        if (err == 0 && !capped) {
            err = write_block(w, b, &capped, &capped_at);
        }
        pthread_mutex_lock(&w->lock);
        w->next = (b + 1u) % CSV_WRITER_BLOCKS;
        w->n_queued--;
        if (w->err == 0) {
            w->err = err;
        }
        if (capped && !w->capped) {
            w->capped = 1;
            w->t_capped_s = capped_at;
        }
        pthread_cond_signal(&w->freed);
    }
    pthread_mutex_unlock(&w->lock);
    return NULL;
}

int csv_writer_start(csv_writer_t *w, FILE *f, uint64_t header_bytes, uint64_t max_bytes)
{
    w->f = f;
    w->max_bytes = max_bytes;
    w->bytes = header_bytes;
    w->capped = 0;
    w->seen_capped = 0;
    w->t_capped_s = 0.0;
    w->fill = 0u;
    w->next = 0u;
    w->n_queued = 0u;
    w->done = 0;
    w->err = 0;
    w->seen_err = 0;
    w->n_rows[0] = 0u;
    int rc = pthread_mutex_init(&w->lock, NULL);
    if (rc != 0) {
        return rc;
    }
    rc = pthread_cond_init(&w->queued, NULL);
    if (rc == 0) {
        rc = pthread_cond_init(&w->freed, NULL);
        if (rc == 0) {
            rc = pthread_create(&w->thread, NULL, writer_main, w);
            if (rc == 0) {
                return 0;
            }
            pthread_cond_destroy(&w->freed);
        }
        pthread_cond_destroy(&w->queued);
    }
    pthread_mutex_destroy(&w->lock);
    return rc;
}

/* Queue the block being filled (the lock held), waiting for a free one to fill next. */
static void queue_fill(csv_writer_t *w)
{
    while (w->n_queued == CSV_WRITER_BLOCKS - 1u) {   /* the last free block is the one being filled */
        pthread_cond_wait(&w->freed, &w->lock);
    }
    w->n_queued++;
    w->fill = (w->fill + 1u) % CSV_WRITER_BLOCKS;
    w->n_rows[w->fill] = 0u;
    pthread_cond_signal(&w->queued);
}

int csv_writer_put(csv_writer_t *w, const sil_row_t *row)
{
    if (w->seen_err != 0 || w->seen_capped) {
        return w->seen_err;
    }
    const unsigned b = w->fill;
    w->rows[b][w->n_rows[b]++] = *row;
    if (w->n_rows[b] < CSV_WRITER_BLOCK_ROWS) {
        return 0;
    }
    pthread_mutex_lock(&w->lock);
    queue_fill(w);
    w->seen_err = w->err;
    w->seen_capped = w->capped;
    pthread_mutex_unlock(&w->lock);
    return w->seen_err;
}

int csv_writer_finish(csv_writer_t *w)
{
    pthread_mutex_lock(&w->lock);
    if (w->n_rows[w->fill] > 0u) {
        queue_fill(w);
    }
    w->done = 1;
    pthread_cond_signal(&w->queued);
    pthread_mutex_unlock(&w->lock);
    pthread_join(w->thread, NULL);
    pthread_cond_destroy(&w->freed);
    pthread_cond_destroy(&w->queued);
    pthread_mutex_destroy(&w->lock);
    return w->err;
}
