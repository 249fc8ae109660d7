/*
 * link.h - the drive's side of the link (link_protocol.md): requests in,
 * replies, stream and event frames out; the triggered capture and the
 * stream's sampling in the control ISR. No hardware: the glue (main.c on
 * the board, tools/sil/link_sil.c in the SIL) moves bytes between the
 * serial port and link_rx_put()/link_tx_get().
 *
 * Contexts: link_isr() at the end of every control ISR call (bounded: the
 * capture's 4 channels and trigger, the stream's values); everything else
 * in the background loop, link_poll() handling at most LINK_RX_BUDGET
 * received bytes per call, so a flood of bytes costs bounded time.
 */
#ifndef LINK_H
#define LINK_H

#include <stdbool.h>
#include <stdint.h>

#include "link_codec.h"
#include "link_vars.h"

#define LINK_PROTOCOL_VERSION 1u
#define LINK_RX_LEN 64u                  /* received bytes waiting for link_poll (power of two) */
#define LINK_TX_LEN 256u                 /* bytes waiting for the port (power of two): the largest frame */
#define LINK_RX_BUDGET 64u               /* received bytes handled per link_poll */
#define LINK_CAP_CHANNELS 4u
#define LINK_CAP_ROWS 1024u
#define LINK_CAP_SLOTS (LINK_CAP_CHANNELS * LINK_CAP_ROWS)  /* int16 slots: rows x the channels' slots */
#define LINK_CAP_F32_SLOTS 2u            /* a float32 channel's slots a row (an int16's: 1) */
#define LINK_STREAM_VARS 8u
#define LINK_STREAM_ROWS 4u              /* sampled rows waiting for the background */
#define LINK_LINE_BUDGET_PCT 80u         /* a stream may use this share of the line */
#define LINK_BITS_PER_BYTE_ON_LINE 10u   /* 8N1: start, 8 data, stop */
#define LINK_WRITTEN_BITS 32u            /* link_t.written's width: the writable ids sit below it */
#define LINK_LIST_PARAM 0x02u            /* LIST_VARS' byte after the descriptors: a parameter (link_params.h);
                                          * its bit 0 the capture format (link_cap_fmt_t) */
/* The host timeout's stop: standstill is a speed below this share of the rated speed (or the ramp's
 * own time again, an active load holding the shaft), then PWM off. */
#define LINK_STOP_STANDSTILL_PER_RATED 0.01f

/* Frame types (link_protocol.md). A reply is its request's type | LINK_REPLY. */
enum {
    LINK_HELLO = 0x01, LINK_LIST_VARS = 0x02, LINK_READ = 0x03, LINK_WRITE = 0x04, LINK_ACTION = 0x05,
    LINK_STREAM_SET = 0x06, LINK_CAPTURE_ARM = 0x07, LINK_CAPTURE_STATUS = 0x08, LINK_CAPTURE_READ = 0x09,
    LINK_PING = 0x0A,
    LINK_EVENT = 0x40, LINK_STREAM = 0x41,   /* unsolicited, seq 0 */
    LINK_NOTICE = 0x42,                      /* unsolicited: the port's own news, then it closes (drive_sil) */
    LINK_REPLY = 0x80
};

/* LINK_NOTICE's first payload byte (then ASCII text to the end): why the port closes this client. */
enum { LINK_NOTICE_HELD = 1, LINK_NOTICE_IDLE = 2 };

/* A reply's first payload byte. */
enum {
    LINK_ST_OK = 0, LINK_ST_REFUSED = 1, LINK_ST_BAD_REQUEST = 2, LINK_ST_UNKNOWN_ID = 3,
    LINK_ST_ACCESS = 4, LINK_ST_UNKNOWN_TYPE = 5, LINK_ST_BUSY = 6
};

enum { LINK_TRIG_FORCED = 0, LINK_TRIG_ABOVE = 1, LINK_TRIG_BELOW = 2, LINK_TRIG_FAULT = 3, LINK_TRIG_STATE = 4 };
enum { LINK_CAP_IDLE = 0, LINK_CAP_PRE = 1, LINK_CAP_POST = 2, LINK_CAP_DONE = 3 };

typedef struct {
    /* written by the background only while state is IDLE or DONE */
    uint16_t nch;
    uint16_t ids[LINK_CAP_CHANNELS];
    const volatile float *fp[LINK_CAP_CHANNELS];  /* a float channel in place (link_var_source), or NULL:
                                                   * link_var_get */
    uint16_t fmt[LINK_CAP_CHANNELS];     /* link_cap_fmt_t: int16 (one slot a row) or float32 (two) */
    float per_lsb[LINK_CAP_CHANNELS];    /* int16: counts per unit, 32767 / max(|lo|, |hi|), 1 for integers;
                                          * float32: 1 */
    float per_raw[LINK_CAP_CHANNELS];    /* what the ISR multiplies *fp by: per_lsb / raw_per_unit */
    uint16_t stride;                     /* slots a row: the channels' sum */
    bool i16_in_place;                   /* every channel int16 and a float in place (fp non-NULL) */
    uint16_t samples, pre, decimate;
    uint16_t trig, trig_id;
    link_src_t trig_src;                 /* the trigger variable's float in place, or p NULL */
    float level, hyst;
    /* the ISR's */
    volatile uint16_t state;             /* LINK_CAP_*: IDLE, DONE set by the background, PRE by arming */
    uint16_t dec_left, head, filled, post_left;
    bool trig_ready;                     /* ABOVE/BELOW: a sample at or beyond the re-arm level was seen */
    uint16_t last_app_state;             /* FAULT and STATE triggers: the state at the last sample */
    uint32_t trig_index, first_index;    /* period indices (0 = the first ISR call since app_init) */
    uint16_t buf[LINK_CAP_SLOTS];        /* rows of `stride` slots */
} link_capture_t;

typedef struct {
    volatile uint16_t n;                 /* variables streamed; 0: off. Set last by the background */
    uint16_t ids[LINK_STREAM_VARS];
    const volatile float *fp[LINK_STREAM_VARS];   /* as link_capture_t.fp */
    uint16_t f32_mask;                   /* bit k: variable k is a float (its raw word: the float's bits) */
    bool in_place;                       /* every variable a float in place: fp[k] set for all
                                          * LINK_STREAM_VARS slots, the unused repeating fp[0] */
    uint16_t decimate, dec_left;
    /* rows: written by the ISR at wr, read by the background at rd; raw values (a float's bits, an integer),
     * converted to their units by the background */
    volatile uint16_t wr, rd;
    uint32_t index[LINK_STREAM_ROWS];
    uint32_t raw[LINK_STREAM_ROWS][LINK_STREAM_VARS];
} link_stream_t;

typedef struct {
    float Ts_s;                          /* control period [s] */
    uint32_t baud;                       /* the line's rate [bit/s]: the stream's budget */
    const char *firmware_id;             /* HELLO's identification text */
    float host_timeout_s;                /* host_timeout_s at start-up (link_host_t; 0: off) [s] */
    link_params_glue_t params;           /* the drive's parameter set on the link (link_params.h; set NULL:
                                          * none) and the glue's hook after a write (the drive stopped) */
} link_cfg_t;

typedef struct {
    link_cfg_t cfg;
    link_target_t t;
    link_stats_t stats;
    link_rx_t rx;
    uint16_t rx_ring[LINK_RX_LEN];
    uint16_t rx_head, rx_tail;
    uint16_t tx_ring[LINK_TX_LEN];
    uint16_t tx_head, tx_tail;
    link_frame_t req, rep;               /* working frames */
    /* the reply cache: a repeated request (type, seq, payload CRC) is answered from it */
    bool cache_valid;
    uint16_t cache_type, cache_seq, cache_crc, cache_len;
    uint16_t cache[LINK_ENCODED_MAX];
    uint16_t ev_state, ev_fault;         /* last state and fault told by an event frame */
    bool quit;                           /* ACTION quit seen (the SIL ends its run) */
    uint32_t written;                    /* bit per variable id (< LINK_WRITTEN_BITS) written over the link
                                          * (the SIL's overrides) */
    link_host_t host;                    /* the host timeout (link_protocol.md, "Host timeout") */
    link_capture_t cap;
    link_stream_t stream;
} link_t;

/* The board's defaults of link_cfg_t's settings (host_timeout_s: BOARD_HOST_TIMEOUT_S, board_cfg.h);
 * Ts_s, baud and firmware_id are the glue's (0, NULL here). Start-up or host. */
void link_cfg_default(link_cfg_t *cfg);

/* Start-up: bind the link to the drive and its operator block; empty queues, capture and stream off. */
void link_init(link_t *l, const link_cfg_t *cfg, app_t *app, volatile cmd_t *cmd, const cmd_limits_t *lim);

/* One received byte from the port; false (counted as an overrun) when the queue is full. Background. */
bool link_rx_put(link_t *l, uint16_t byte);

/* The next byte for the port, false when none. Background. */
bool link_tx_get(link_t *l, uint16_t *byte);

/* Bytes waiting for the port. Background. */
uint16_t link_tx_pending(const link_t *l);

/* Handle up to LINK_RX_BUDGET received bytes (requests answered into the transmit queue, each
 * only once the queue has room for the largest reply), then, when no received byte waits,
 * queue stream and event frames as room allows (stream rows the ISR cannot queue meanwhile are
 * counted as dropped); then the host timeout: once a host wrote a reference or started the
 * drive, no valid frame for host_timeout_s ramps the references to zero (speed at the drive's
 * ramp rate, step 1's accel_rad_s2; torque and voltage from their limits in the time the rated
 * speed takes) through cmd_apply(), stops the drive at standstill and raises
 * APP_WARN_HOST_TIMEOUT. Background. */
void link_poll(link_t *l);

/* Drop every byte not yet received or sent (the cable was pulled). Background. */
void link_drop(link_t *l);

/* Capture and stream sampling for the period that just ran: per capture channel a read, a multiply
 * and a store, the trigger's comparison, per streamed variable a copy of its raw value; no frame
 * building, no search by id. Control ISR, after app_isr. */
void link_isr(link_t *l);

/* The bytes per second a stream of n variables every `decimate` periods needs on the line. */
uint32_t link_stream_need_Bps(const link_t *l, uint16_t n, uint16_t decimate);

/* The bytes per second a stream may use: LINK_LINE_BUDGET_PCT of the line. */
uint32_t link_stream_budget_Bps(const link_t *l);

#endif /* LINK_H */
