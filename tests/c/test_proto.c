/* The serial protocol codec against the shared vectors (tests/vectors/proto_frames.csv, also read
 * by the Python tests) and against every way a frame can be bad. */
#include "ss_test.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ss_proto.h"
#include "ss_proto_stream.h"

static size_t unhex(const char *s, uint8_t *out, size_t cap)
{
    size_t n = 0;
    while (s[0] != '\0' && s[0] != '\n' && s[0] != ',' && s[1] != '\0' && n < cap) {
        char b[3] = {s[0], s[1], 0};
        out[n++] = (uint8_t)strtoul(b, NULL, 16);
        s += 2;
    }
    return n;
}

static void test_crc_check_value(void **unused)
{
    (void)unused;
    /* CRC-16/CCITT-FALSE catalogue check value */
    assert_int_equal(ss_crc16_ccitt((const uint8_t *)"123456789", 9), 0x29B1);
}

static void test_shared_vectors(void **unused)
{
    (void)unused;
    FILE *f = fopen(SS_VECTORS_DIR "/proto_frames.csv", "r");
    assert_non_null(f);
    static char line[8192];
    static uint8_t payload[SS_PROTO_MAX_PAYLOAD], wire[SS_PROTO_MAX_WIRE], mine[SS_PROTO_MAX_WIRE];
    int cases = 0;
    while (fgets(line, sizeof line, f) != NULL) {
        if (line[0] == '#') {
            continue;
        }
        char *c1 = strchr(line, ',');
        char *c2 = strchr(c1 + 1, ',');
        char *c3 = strchr(c2 + 1, ',');
        const unsigned type = (unsigned)atoi(line), seq = (unsigned)atoi(c1 + 1);
        const size_t np = unhex(c2 + 1, payload, sizeof payload);
        const size_t nw = unhex(c3 + 1, wire, sizeof wire);
        /* encode: byte for byte what the Python side produces */
        const size_t nm = ss_proto_build((uint8_t)type, (uint8_t)seq, payload, np, mine, sizeof mine);
        assert_int_equal(nm, nw);
        assert_memory_equal(mine, wire, nw);
        /* decode through the receiver */
        ss_proto_rx_t rx;
        static ss_proto_packet_t pkt;
        ss_proto_rx_init(&rx);
        int complete = 0;
        for (size_t i = 0; i < nw; ++i) {
            assert_int_equal(ss_proto_rx_push(&rx, wire[i], &pkt, &complete), SS_PERR_NONE);
            assert_int_equal(complete, i + 1 == nw);
        }
        assert_int_equal(pkt.type, type);
        assert_int_equal(pkt.seq, seq);
        assert_int_equal(pkt.len, np);
        if (np > 0) {
            assert_memory_equal(pkt.payload, payload, np);
        }
        cases++;
    }
    fclose(f);
    assert_true(cases >= 7);
}

/* Feed bytes; return the last non-NONE code (or NONE) and whether a frame completed. */
static ss_proto_error_t feed(ss_proto_rx_t *rx, const uint8_t *b, size_t n, int *got)
{
    static ss_proto_packet_t pkt;
    ss_proto_error_t last = SS_PERR_NONE;
    *got = 0;
    for (size_t i = 0; i < n; ++i) {
        int c = 0;
        const ss_proto_error_t e = ss_proto_rx_push(rx, b[i], &pkt, &c);
        if (e != SS_PERR_NONE) {
            last = e;
        }
        *got |= c;
    }
    return last;
}

static void test_bad_frames(void **unused)
{
    (void)unused;
    ss_proto_rx_t rx;
    ss_proto_rx_init(&rx);
    uint8_t w[64];
    const uint8_t pl[3] = {1, 2, 3};
    const size_t n = ss_proto_build(0x03, 5, pl, 3, w, sizeof w);
    int got = 0;
    /* bad CRC: flip a payload byte (COBS keeps the position) */
    w[5] ^= 0x40u;
    assert_int_equal(feed(&rx, w, n, &got), SS_PERR_BAD_CRC);
    assert_int_equal(got, 0);
    assert_int_equal(rx.last_type, 0x03); /* the header is still readable */
    w[5] ^= 0x40u;
    /* truncated: a frame cut short, then the next good frame still gets through */
    assert_int_equal(feed(&rx, w, n - 4, &got), SS_PERR_NONE);
    const uint8_t zero = 0;
    assert_true(feed(&rx, &zero, 1, &got) != SS_PERR_NONE);
    assert_int_equal(feed(&rx, w, n, &got), SS_PERR_NONE);
    assert_int_equal(got, 1);
    /* too short to hold a header */
    const uint8_t tiny[3] = {0x02, 0x07, 0x00};
    assert_int_equal(feed(&rx, tiny, 3, &got), SS_PERR_BAD_LENGTH);
    /* invalid COBS: a code byte pointing past the end */
    const uint8_t bad_cobs[3] = {0x09, 0x01, 0x00};
    assert_int_equal(feed(&rx, bad_cobs, 3, &got), SS_PERR_BAD_FRAMING);
    /* oversize: more than a frame can be, discarded up to the delimiter, then resync */
    static uint8_t big[SS_PROTO_MAX_WIRE + 50];
    memset(big, 0x55, sizeof big);
    big[sizeof big - 1] = 0;
    assert_int_equal(feed(&rx, big, sizeof big, &got), SS_PERR_OVERSIZE);
    assert_int_equal(feed(&rx, w, n, &got), SS_PERR_NONE);
    assert_int_equal(got, 1);
    /* length field disagreeing with the data */
    uint8_t pkt[8] = {0x03, 1, 5, 0, 9, 9, 0, 0};
    const uint16_t crc = ss_crc16_ccitt(pkt, 6);
    ss_put_u16(&pkt[6], crc);
    uint8_t wire[16];
    const size_t m = ss_cobs_encode(pkt, 8, wire, sizeof wire);
    wire[m] = 0;
    assert_int_equal(feed(&rx, wire, m + 1, &got), SS_PERR_BAD_LENGTH);
    /* idle delimiters are no error */
    const uint8_t idle[3] = {0, 0, 0};
    assert_int_equal(feed(&rx, idle, 3, &got), SS_PERR_NONE);
}

static void test_build_limits(void **unused)
{
    (void)unused;
    static uint8_t p[SS_PROTO_MAX_PAYLOAD + 1], w[SS_PROTO_MAX_WIRE];
    memset(p, 0xAB, sizeof p);
    assert_true(ss_proto_build(1, 0, p, SS_PROTO_MAX_PAYLOAD, w, sizeof w) > 0u);
    assert_true(ss_proto_build(1, 0, p, SS_PROTO_MAX_PAYLOAD, w, sizeof w) <= SS_PROTO_MAX_WIRE);
    assert_int_equal(ss_proto_build(1, 0, p, SS_PROTO_MAX_PAYLOAD + 1, w, sizeof w), 0);
    assert_int_equal(ss_proto_build(1, 0, p, 100, w, 50), 0); /* no room */
    assert_int_equal(ss_cobs_encode(p, 10, w, 0), 0);
    uint8_t d[4];
    const uint8_t enc[5] = {0x05, 1, 2, 3, 4};
    assert_int_equal(ss_cobs_decode(enc, 5, d, 3), -1); /* result longer than cap */
    assert_string_equal(ss_proto_error_name(SS_PERR_DUPLICATE), "duplicate");
    assert_string_equal(ss_proto_error_name((ss_proto_error_t)99), "unknown_error");
}

/* The streaming encoder gives ss_proto_build's bytes, whatever the pieces the payload comes in,
 * and never hands on a byte COBS still has to go back for: across lengths that end COBS groups
 * every way (a zero, a full 254-byte group, both at the frame's end), payloads with and without
 * zeros. */
static void test_stream_equals_build(void **unused)
{
    (void)unused;
    static const uint16_t lens[] = {0, 1, 2, 249, 250, 251, 252, 253, 254, 255, 500, 507, 508, 971, 1024};
    static uint8_t payload[SS_PROTO_MAX_PAYLOAD];
    static uint8_t built[SS_PROTO_MAX_WIRE];
    static uint8_t wire[SS_PROTO_MAX_WIRE];
    static uint8_t got[SS_PROTO_MAX_WIRE];
    unsigned seed = 12345u;
    for (int zeros = 0; zeros < 3; ++zeros) {
        for (size_t li = 0; li < sizeof lens / sizeof lens[0]; ++li) {
            const uint16_t len = lens[li];
            for (uint16_t i = 0; i < len; ++i) {
                seed = seed * 1103515245u + 12345u;
                const uint8_t r = (uint8_t)(seed >> 16);
                /* no zeros; about one in 16; the telemetry's kind (floats, small counts) */
                payload[i] = (zeros == 0) ? (uint8_t)(r | 1u) : (zeros == 1 && (r & 15u) == 0u) ? 0u : r;
            }
            const size_t n = ss_proto_build(SS_MSG_TELEMETRY, 7u, payload, len, built, sizeof built);
            assert_true(n > 0u);
            ss_proto_stream_t st;
            assert_int_equal(ss_proto_stream_begin(&st, wire, SS_MSG_TELEMETRY, 7u, len), 1);
            size_t at = 0;
            size_t have = 0;
            while (!ss_proto_stream_done(&st)) {
                seed = seed * 1103515245u + 12345u;
                const size_t piece = (seed >> 16) % 23u;
                const size_t take = (piece < (size_t)len - at) ? piece : (size_t)len - at;
                ss_proto_stream_put(&st, &payload[at], take);
                at += take;
                const uint8_t *p = NULL;
                const size_t ready = ss_proto_stream_ready(&st, &p);
                const size_t send = (ready < 17u) ? ready : 17u; /* a few at a time, as the node does */
                memcpy(&got[have], p, send);
                /* what was handed on is final: already the built frame's bytes */
                assert_memory_equal(&got[have], &built[have], send);
                have += send;
                ss_proto_stream_sent(&st, send);
            }
            assert_int_equal(have, n);
            assert_memory_equal(got, built, n);
        }
    }
    ss_proto_stream_t st;
    assert_int_equal(ss_proto_stream_begin(&st, wire, SS_MSG_TELEMETRY, 0u, SS_PROTO_MAX_PAYLOAD + 1u), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_crc_check_value),     cmocka_unit_test(test_shared_vectors),
        cmocka_unit_test(test_bad_frames),          cmocka_unit_test(test_build_limits),
        cmocka_unit_test(test_stream_equals_build),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
