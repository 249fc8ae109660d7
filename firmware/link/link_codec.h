/*
 * link_codec.h - the link's framing (firmware/link/link_protocol.md): CRC-16/
 * CCITT-FALSE, COBS, and the frame [type, seq, payload..., crc lo, crc hi]
 * COBS-encoded and ended by one 0x00. Pure, no hardware, no state but the
 * receiver's. A protocol byte is one uint16_t holding 0..255: on the C28x
 * char is 16 bits, so bytes are never packed two to a word.
 */
#ifndef LINK_CODEC_H
#define LINK_CODEC_H

#include <stdbool.h>
#include <stdint.h>

#define LINK_PAYLOAD_MAX 240u                           /* bytes of payload in one frame */
#define LINK_FRAME_MAX (LINK_PAYLOAD_MAX + 4u)          /* type, seq, payload, CRC */
/* COBS adds one byte per started block of 254, then the 0x00 delimiter: the most a frame of
 * `len` payload bytes takes on the wire */
#define LINK_ENCODED_SIZE(len) ((len) + 4u + (((len) + 4u) / 254u) + 2u)
#define LINK_ENCODED_MAX LINK_ENCODED_SIZE(LINK_PAYLOAD_MAX)
#define LINK_BYTE_MASK 0x00FFu

typedef struct {
    uint16_t type;                       /* link_protocol.md: requests 0x01.., replies type | 0x80 */
    uint16_t seq;                        /* 0..255, chosen by the host, echoed in the reply */
    uint16_t len;                        /* payload bytes, <= LINK_PAYLOAD_MAX */
    uint16_t payload[LINK_PAYLOAD_MAX + 2u];  /* one byte per word; the receiver puts the CRC after it */
} link_frame_t;

/* Receiver: bytes in, whole checked frames out, COBS decoded as the bytes
 * come (straight into the caller's frame: no block buffer). Resyncs at
 * every 0x00. */
typedef struct {
    uint16_t m;                  /* bytes decoded since the last 0x00 */
    uint16_t left;               /* data bytes left in the current COBS block; 0: a code byte is next */
    bool zero_pending;           /* the current block ends in an implied zero (its code was below 0xFF) */
    bool started;                /* a byte came since the last 0x00 */
    bool bad;                    /* overlong since the last 0x00: dropped at the next one */
    uint16_t err_crc;            /* frames with a bad CRC (saturating counts) */
    uint16_t err_framing;        /* bad COBS, too short, too long */
} link_rx_t;

/* CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF, no reflection, no final xor) of n bytes. Any context. */
uint16_t link_crc16(const uint16_t *b, uint16_t n);

/* CRC update with one more byte (the same CRC, byte by byte). Any context. */
uint16_t link_crc16_byte(uint16_t crc, uint16_t byte);

/* COBS-encode n bytes into out (room for n + n/254 + 1); returns the encoded length (no delimiter). */
uint16_t link_cobs_encode(const uint16_t *in, uint16_t n, uint16_t *out);

/* COBS-decode n bytes (no delimiter) into out[out_max]; returns the decoded length, or -1 on a
 * zero inside, a code running past the end or an output longer than out_max. */
int16_t link_cobs_decode(const uint16_t *in, uint16_t n, uint16_t *out, uint16_t out_max);

/* The frame f as wire bytes into out[LINK_ENCODED_MAX]: COBS of type, seq, payload, CRC, then
 * 0x00. Returns the byte count. Background. */
uint16_t link_frame_encode(const link_frame_t *f, uint16_t *out);

/* The same into a ring: byte k at out[(start + k) & mask] (mask + 1 a power of two, the
 * caller checked the room). No copy of the frame is made. Background. */
uint16_t link_frame_encode_ring(const link_frame_t *f, uint16_t *out, uint16_t start, uint16_t mask);

/* Start a receiver with no bytes and zero counts. */
void link_rx_init(link_rx_t *rx);

/* Forget the bytes since the last 0x00 (a new cable), keeping the counts. */
void link_rx_resync(link_rx_t *rx);

/* One received byte, decoded into *f (the same frame on every call); true when it ended a
 * valid frame, now in *f. Errors are counted (err_crc, err_framing); an empty block
 * (0x00 0x00) is silently ignored. Background. */
bool link_rx_byte(link_rx_t *rx, uint16_t byte, link_frame_t *f);

/* Little-endian helpers over byte words: put returns the index after the value. */
uint16_t link_put_u16(uint16_t *b, uint16_t i, uint16_t v);
uint16_t link_put_u32(uint16_t *b, uint16_t i, uint32_t v);
uint16_t link_put_f32(uint16_t *b, uint16_t i, float v);
uint16_t link_get_u16(const uint16_t *b, uint16_t i);
uint32_t link_get_u32(const uint16_t *b, uint16_t i);
float link_get_f32(const uint16_t *b, uint16_t i);

/* The float whose IEEE-754 bits are u. Any context. */
float link_f32_of_bits(uint32_t u);

#endif /* LINK_CODEC_H */
