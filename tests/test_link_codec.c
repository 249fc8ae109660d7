/* Unit tests for firmware/link_codec: the golden vectors of
 * tests/link_vectors.txt (shared with tests/test_link_codec.py: the CRC
 * check value and the published COBS examples, every frame type), and the
 * receiver: resync at the next 0x00 after garbage, a flipped or lost byte
 * costing only its own frame, overlong input dropped and counted. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "link_codec.h"

#define VECTORS "tests/link_vectors.txt"
#define LINE_MAX_CHARS 4096
#define BYTES_MAX 1024

/* Hex (or "-") into bytes; returns the count. */
static uint16_t hex(const char *s, uint16_t *out)
{
    uint16_t n = 0;
    if (strcmp(s, "-") == 0) {
        return 0;
    }
    for (size_t i = 0; s[i] != '\0' && s[i + 1] != '\0'; i += 2) {
        char b[3] = { s[i], s[i + 1], '\0' };
        out[n++] = (uint16_t)strtoul(b, NULL, 16);
    }
    return n;
}

typedef struct {
    int crc, cobs, frame, bad;
} counts_t;

static void check_line(char *line, counts_t *c)
{
    static uint16_t a[BYTES_MAX], b[BYTES_MAX], out[BYTES_MAX];
    char *kind = strtok(line, " \n");
    if (kind == NULL || kind[0] == '#') {
        return;
    }
    if (strcmp(kind, "crc") == 0) {
        uint16_t n = hex(strtok(NULL, " \n"), a);
        unsigned want = (unsigned)strtoul(strtok(NULL, " \n"), NULL, 16);
        assert_int_equal(link_crc16(a, n), want);
        c->crc++;
    } else if (strcmp(kind, "cobs") == 0) {
        uint16_t n = hex(strtok(NULL, " \n"), a);
        uint16_t m = hex(strtok(NULL, " \n"), b);
        assert_int_equal(link_cobs_encode(a, n, out), m);
        assert_memory_equal(out, b, m * sizeof b[0]);
        assert_int_equal(link_cobs_decode(b, m, out, BYTES_MAX), n);
        assert_memory_equal(out, a, n * sizeof a[0]);
        c->cobs++;
    } else if (strcmp(kind, "frame") == 0) {
        static link_frame_t f, g;
        f.type = (uint16_t)strtoul(strtok(NULL, " \n"), NULL, 16);
        f.seq = (uint16_t)strtoul(strtok(NULL, " \n"), NULL, 16);
        f.len = hex(strtok(NULL, " \n"), f.payload);
        uint16_t m = hex(strtok(NULL, " \n"), b);
        assert_int_equal(link_frame_encode(&f, out), m);
        assert_memory_equal(out, b, m * sizeof b[0]);
        /* the receiver, byte by byte, gives the frame back at the delimiter only */
        link_rx_t rx;
        link_rx_init(&rx);
        for (uint16_t i = 0; i < m; i++) {
            assert_int_equal(link_rx_byte(&rx, b[i], &g), i + 1u == m);
        }
        assert_int_equal(g.type, f.type);
        assert_int_equal(g.seq, f.seq);
        assert_int_equal(g.len, f.len);
        assert_memory_equal(g.payload, f.payload, f.len * sizeof f.payload[0]);
        c->frame++;
    } else if (strcmp(kind, "bad") == 0) {
        static link_frame_t g;
        uint16_t m = hex(strtok(NULL, " \n"), b);
        link_rx_t rx;
        link_rx_init(&rx);
        for (uint16_t i = 0; i < m; i++) {
            assert_false(link_rx_byte(&rx, b[i], &g));
        }
        assert_int_equal(rx.err_crc + rx.err_framing, 1);
        c->bad++;
    } else {
        fail_msg("unknown vector kind %s", kind);
    }
}

static void golden_vectors_pass(void **state)
{
    (void)state;
    FILE *f = fopen(VECTORS, "r");
    assert_non_null(f);
    static char line[LINE_MAX_CHARS];
    counts_t c = { 0, 0, 0, 0 };
    while (fgets(line, sizeof line, f) != NULL) {
        check_line(line, &c);
    }
    fclose(f);
    /* the file has each kind; every request and reply type is among the frames */
    assert_true(c.crc >= 5 && c.cobs >= 11 && c.frame >= 15 && c.bad >= 3);
}

/* A frame's wire bytes (type 3, seq, two payload bytes). */
static uint16_t wire_of(uint16_t seq, uint16_t *w)
{
    link_frame_t f;
    f.type = 3u;
    f.seq = seq;
    f.len = 2u;
    f.payload[0] = 0u;
    f.payload[1] = 7u;
    return link_frame_encode(&f, w);
}

static int feed(link_rx_t *rx, const uint16_t *b, uint16_t n, link_frame_t *f)
{
    int frames = 0;
    for (uint16_t i = 0; i < n; i++) {
        frames += link_rx_byte(rx, b[i], f) ? 1 : 0;
    }
    return frames;
}

static void receiver_resyncs_within_one_frame(void **state)
{
    (void)state;
    uint16_t w[LINK_ENCODED_MAX];
    const uint16_t n = wire_of(9u, w);
    static link_frame_t f;
    link_rx_t rx;
    link_rx_init(&rx);
    /* garbage with no delimiter, then a whole frame: the garbage spoils only the first block */
    const uint16_t garbage[] = { 0x55u, 0x13u, 0xFFu, 0x01u, 0x80u };
    assert_int_equal(feed(&rx, garbage, 5u, &f), 0);
    assert_int_equal(feed(&rx, w, n, &f), 0);          /* garbage + frame: one bad block */
    assert_int_equal(feed(&rx, w, n, &f), 1);          /* the next frame is whole */
    assert_int_equal(f.seq, 9u);
    /* a flipped byte: that frame is lost, the next one is taken */
    uint16_t bad[LINK_ENCODED_MAX];
    memcpy(bad, w, sizeof w);
    bad[2] ^= 0x04u;
    assert_int_equal(feed(&rx, bad, n, &f), 0);
    assert_int_equal(feed(&rx, w, n, &f), 1);
    /* a lost delimiter: two frames run together, both lost, the third taken */
    assert_int_equal(feed(&rx, w, (uint16_t)(n - 1u), &f), 0);
    assert_int_equal(feed(&rx, w, n, &f), 0);
    assert_int_equal(feed(&rx, w, n, &f), 1);
    assert_int_equal(rx.err_crc + rx.err_framing, 3);
}

static void overlong_input_is_dropped_and_counted(void **state)
{
    (void)state;
    uint16_t w[LINK_ENCODED_MAX];
    const uint16_t n = wire_of(1u, w);
    static link_frame_t f;
    link_rx_t rx;
    link_rx_init(&rx);
    for (int i = 0; i < 3 * (int)LINK_ENCODED_MAX; i++) {
        assert_false(link_rx_byte(&rx, 0x41u, &f));
    }
    assert_false(link_rx_byte(&rx, 0u, &f));
    assert_int_equal(rx.err_framing, 1);
    assert_int_equal(feed(&rx, w, n, &f), 1);
    /* idle fill between frames is no error */
    const uint16_t idle[] = { 0u, 0u, 0u };
    assert_int_equal(feed(&rx, idle, 3u, &f), 0);
    assert_int_equal(rx.err_framing, 1);
}

static void values_are_little_endian(void **state)
{
    (void)state;
    uint16_t b[8];
    assert_int_equal(link_put_u32(b, 0u, 0x12345678ul), 4);
    assert_int_equal(b[0], 0x78);
    assert_int_equal(b[3], 0x12);
    assert_int_equal(link_get_u32(b, 0u), 0x12345678ul);
    (void)link_put_f32(b, 0u, 500.0f);   /* 0x43FA0000 */
    assert_int_equal(b[2], 0xFA);
    assert_int_equal(b[3], 0x43);
    assert_true(link_get_f32(b, 0u) == 500.0f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(golden_vectors_pass),
        cmocka_unit_test(receiver_resyncs_within_one_frame),
        cmocka_unit_test(overlong_input_is_dropped_and_counted),
        cmocka_unit_test(values_are_little_endian),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
