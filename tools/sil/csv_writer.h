/*
 * csv_writer.h - drive_sil's CSV written by a second thread. The run (the
 * producer) copies each row into a block of a bounded ring; a full block
 * is handed to the writer thread, which formats its rows
 * (sil_csv_format) and writes them, so on a machine with a free core the
 * run does not wait for the text. The bytes equal sil_csv_row() on the
 * same rows in the same order. Hand-overs are per block under one mutex
 * with two condition variables: neither thread spins; the producer waits
 * only when every block is still queued. A size limit ends the file at
 * the last whole row that fits (later rows are dropped, the run goes on).
 *
 * Host only (POSIX threads). One producer thread per writer; the FILE
 * belongs to the writer thread from csv_writer_start() until
 * csv_writer_finish() returns.
 */
#ifndef CSV_WRITER_H
#define CSV_WRITER_H

#include <pthread.h>
#include <stdint.h>
#include <stdio.h>

#include "sil.h"

#define CSV_WRITER_BLOCK_ROWS 64u   /* rows per hand-over */
#define CSV_WRITER_BLOCKS 8u        /* blocks in the ring */
#define CSV_WRITER_NO_LIMIT UINT64_MAX

typedef struct {
    FILE *f;
    pthread_t thread;
    pthread_mutex_t lock;
    pthread_cond_t queued;      /* signalled: a block was queued, or the end */
    pthread_cond_t freed;       /* signalled: a block was written (or dropped after an error) */
    sil_row_t rows[CSV_WRITER_BLOCKS][CSV_WRITER_BLOCK_ROWS];
    unsigned n_rows[CSV_WRITER_BLOCKS];
    unsigned fill;              /* producer: the block being filled (not queued) */
    unsigned next;              /* writer: the oldest queued block */
    unsigned n_queued;          /* under lock */
    int done;                   /* under lock: no more blocks */
    int err;                    /* under lock: errno of the first failed write, 0 if none */
    int seen_err;               /* producer: err as seen at the last hand-over */
    uint64_t max_bytes;         /* writer: rows stop before the file would pass this */
    uint64_t bytes;             /* writer: bytes written */
    int capped;                 /* under lock: a row did not fit; nothing more is written */
    int seen_capped;            /* producer: capped as seen at the last hand-over */
    double t_capped_s;          /* under lock: t_s of the first row dropped (valid once capped) */
    char text[CSV_WRITER_BLOCK_ROWS * SIL_CSV_LINE_MAX];   /* writer: one block's lines */
} csv_writer_t;

/* Start the writer thread on f (open for writing, header_bytes already in it); rows end
 * before f would pass max_bytes (CSV_WRITER_NO_LIMIT: none). Returns 0, or an errno value (no thread). */
int csv_writer_start(csv_writer_t *w, FILE *f, uint64_t header_bytes, uint64_t max_bytes);

/* Producer: queue one row (copied). Blocks only while every block is queued. Returns 0, or
 * the errno of a failed write, seen at a hand-over and from then on at once (stop, then finish).
 * Once the size limit is seen at a hand-over (seen_capped), rows are no longer copied. */
int csv_writer_put(csv_writer_t *w, const sil_row_t *row);

/* Producer: queue the rows put since the last hand-over, wait until the writer has written
 * everything and joined. Returns 0 if every row reached f without an error (f not flushed),
 * else the errno of the first failed write. Call exactly once after a successful start. */
int csv_writer_finish(csv_writer_t *w);

#endif /* CSV_WRITER_H */
