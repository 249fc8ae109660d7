/* link_codec.c - CRC, COBS and frames of the link; see link_codec.h and link_protocol.md. */
#include "link_codec.h"

#define CRC_INIT 0xFFFFu
#define CRC_POLY 0x1021u
#define CRC_TOP_BIT 0x8000u
#define BITS_PER_BYTE 8u
#define COBS_BLOCK_MAX 0xFFu   /* a code byte of 0xFF: 254 data bytes, no zero after them */
#define FRAME_HEADER 2u        /* type, seq */
#define FRAME_CRC 2u
#define FRAME_MIN (FRAME_HEADER + FRAME_CRC)
#define COUNT_MAX 0xFFFFu

uint16_t link_crc16_byte(uint16_t crc, uint16_t byte)
{
    uint16_t c = (uint16_t)(crc ^ (uint16_t)((byte & LINK_BYTE_MASK) << BITS_PER_BYTE));
    for (uint16_t k = 0u; k < BITS_PER_BYTE; k++) {
        c = ((c & CRC_TOP_BIT) != 0u) ? (uint16_t)((uint16_t)(c << 1) ^ CRC_POLY) : (uint16_t)(c << 1);
    }
    return c;
}

uint16_t link_crc16(const uint16_t *b, uint16_t n)
{
    uint16_t crc = CRC_INIT;
    for (uint16_t i = 0u; i < n; i++) {
        crc = link_crc16_byte(crc, b[i]);
    }
    return crc;
}

uint16_t link_cobs_encode(const uint16_t *in, uint16_t n, uint16_t *out)
{
    uint16_t code_at = 0u;   /* where the current block's code byte goes */
    uint16_t o = 1u;
    uint16_t code = 1u;
    for (uint16_t i = 0u; i < n; i++) {
        const uint16_t v = (uint16_t)(in[i] & LINK_BYTE_MASK);
        if (v == 0u) {
            out[code_at] = code;
            code_at = o++;
            code = 1u;
        } else {
            out[o++] = v;
            code++;
            if (code == COBS_BLOCK_MAX) {
                out[code_at] = code;
                if ((uint16_t)(i + 1u) == n) {
                    return o;            /* a full block ends the data: no empty block after it */
                }
                code_at = o++;
                code = 1u;
            }
        }
    }
    out[code_at] = code;
    return o;
}

int16_t link_cobs_decode(const uint16_t *in, uint16_t n, uint16_t *out, uint16_t out_max)
{
    uint16_t i = 0u;
    uint16_t o = 0u;
    while (i < n) {
        const uint16_t code = (uint16_t)(in[i] & LINK_BYTE_MASK);
        if (code == 0u || (uint16_t)(n - i) < code) {
            return -1;                   /* a zero inside, or the block runs past the end */
        }
        i++;
        for (uint16_t k = 1u; k < code; k++) {
            const uint16_t v = (uint16_t)(in[i++] & LINK_BYTE_MASK);
            if (v == 0u || o >= out_max) {
                return -1;
            }
            out[o++] = v;
        }
        if (code < COBS_BLOCK_MAX && i < n) {
            if (o >= out_max) {
                return -1;
            }
            out[o++] = 0u;               /* the zero the block's end stood for */
        }
    }
    return (int16_t)o;
}

/* Byte j of the frame before COBS: type, seq, payload, CRC low, CRC high. */
static uint16_t raw_at(const link_frame_t *f, uint16_t len, uint16_t crc, uint16_t j)
{
    if (j < FRAME_HEADER) {
        return (uint16_t)(((j == 0u) ? f->type : f->seq) & LINK_BYTE_MASK);
    }
    if (j < (uint16_t)(len + FRAME_HEADER)) {
        return (uint16_t)(f->payload[j - FRAME_HEADER] & LINK_BYTE_MASK);
    }
    return (j == (uint16_t)(len + FRAME_HEADER)) ? (uint16_t)(crc & LINK_BYTE_MASK) : (uint16_t)(crc >> BITS_PER_BYTE);
}

uint16_t link_frame_encode_ring(const link_frame_t *f, uint16_t *out, uint16_t start, uint16_t mask)
{
    const uint16_t len = (f->len <= LINK_PAYLOAD_MAX) ? f->len : LINK_PAYLOAD_MAX;
    uint16_t crc = link_crc16_byte(CRC_INIT, f->type);
    crc = link_crc16_byte(crc, f->seq);
    for (uint16_t i = 0u; i < len; i++) {
        crc = link_crc16_byte(crc, f->payload[i]);
    }
    /* COBS over the frame's bytes as they are produced: no copy of the frame */
    const uint16_t n = (uint16_t)(len + FRAME_MIN);
    uint16_t code_at = 0u;
    uint16_t o = 1u;
    uint16_t code = 1u;
    for (uint16_t i = 0u; i < n; i++) {
        const uint16_t v = raw_at(f, len, crc, i);
        if (v == 0u) {
            out[(uint16_t)(start + code_at) & mask] = code;
            code_at = o++;
            code = 1u;
        } else {
            out[(uint16_t)(start + o) & mask] = v;
            o++;
            code++;
            if (code == COBS_BLOCK_MAX && (uint16_t)(i + 1u) < n) {
                out[(uint16_t)(start + code_at) & mask] = code;
                code_at = o++;
                code = 1u;
            }
        }
    }
    out[(uint16_t)(start + code_at) & mask] = code;
    out[(uint16_t)(start + o) & mask] = 0u;
    return (uint16_t)(o + 1u);
}

uint16_t link_frame_encode(const link_frame_t *f, uint16_t *out)
{
    return link_frame_encode_ring(f, out, 0u, 0xFFFFu);
}

void link_rx_resync(link_rx_t *rx)
{
    rx->m = 0u;
    rx->left = 0u;
    rx->zero_pending = false;
    rx->started = false;
    rx->bad = false;
}

void link_rx_init(link_rx_t *rx)
{
    link_rx_resync(rx);
    rx->err_crc = 0u;
    rx->err_framing = 0u;
}

static void count(uint16_t *c)
{
    if (*c < COUNT_MAX) {
        (*c)++;
    }
}

/* Decoded byte j of the frame into *f: type, seq, then payload (the CRC lands after it). */
static void rx_emit(link_rx_t *rx, uint16_t v, link_frame_t *f)
{
    if (rx->m >= LINK_FRAME_MAX) {
        rx->bad = true;
        return;
    }
    if (rx->m == 0u) {
        f->type = v;
    } else if (rx->m == 1u) {
        f->seq = v;
    } else {
        f->payload[rx->m - FRAME_HEADER] = v;
    }
    rx->m++;
}

/* The block since the last 0x00 is whole: true when it is a frame with a good CRC. */
static bool rx_finish(link_rx_t *rx, link_frame_t *f)
{
    if (rx->bad || rx->left != 0u || rx->m < FRAME_MIN) {
        count(&rx->err_framing);         /* overlong, a block running past the end, or too short */
        return false;
    }
    const uint16_t len = (uint16_t)(rx->m - FRAME_MIN);
    uint16_t crc = link_crc16_byte(CRC_INIT, f->type);
    crc = link_crc16_byte(crc, f->seq);
    for (uint16_t i = 0u; i < len; i++) {
        crc = link_crc16_byte(crc, f->payload[i]);
    }
    if (crc != link_get_u16(f->payload, len)) {
        count(&rx->err_crc);
        return false;
    }
    f->len = len;
    return true;
}

bool link_rx_byte(link_rx_t *rx, uint16_t byte, link_frame_t *f)
{
    const uint16_t v = (uint16_t)(byte & LINK_BYTE_MASK);
    if (v == 0u) {
        /* a delimiter: whatever came before it is one block */
        const bool ok = rx->started && rx_finish(rx, f);
        link_rx_resync(rx);
        return ok;                       /* an empty block is idle fill, or the end of a dropped one */
    }
    rx->started = true;
    if (rx->left > 0u) {
        rx_emit(rx, v, f);
        rx->left--;
    } else {
        if (rx->zero_pending) {
            rx_emit(rx, 0u, f);          /* the previous block stood for a zero, and data follows */
        }
        rx->left = (uint16_t)(v - 1u);
        rx->zero_pending = (v < COBS_BLOCK_MAX);
    }
    return false;
}

uint16_t link_put_u16(uint16_t *b, uint16_t i, uint16_t v)
{
    b[i] = (uint16_t)(v & LINK_BYTE_MASK);
    b[i + 1u] = (uint16_t)((v >> BITS_PER_BYTE) & LINK_BYTE_MASK);
    return (uint16_t)(i + 2u);
}

uint16_t link_put_u32(uint16_t *b, uint16_t i, uint32_t v)
{
    (void)link_put_u16(b, i, (uint16_t)(v & 0xFFFFul));
    return link_put_u16(b, (uint16_t)(i + 2u), (uint16_t)(v >> 16));
}

/* float <-> IEEE-754 binary32 bits: float is 32 bits on every target (C28x FPU32 included) */
typedef union {
    float f;
    uint32_t u;
} f32_bits_t;

uint16_t link_put_f32(uint16_t *b, uint16_t i, float v)
{
    f32_bits_t x;
    x.f = v;
    return link_put_u32(b, i, x.u);
}

uint16_t link_get_u16(const uint16_t *b, uint16_t i)
{
    return (uint16_t)((b[i] & LINK_BYTE_MASK) | (uint16_t)((b[i + 1u] & LINK_BYTE_MASK) << BITS_PER_BYTE));
}

uint32_t link_get_u32(const uint16_t *b, uint16_t i)
{
    return (uint32_t)link_get_u16(b, i) | ((uint32_t)link_get_u16(b, (uint16_t)(i + 2u)) << 16);
}

float link_get_f32(const uint16_t *b, uint16_t i)
{
    f32_bits_t x;
    x.u = link_get_u32(b, i);
    return x.f;
}

float link_f32_of_bits(uint32_t u)
{
    f32_bits_t x;
    x.u = u;
    return x.f;
}
