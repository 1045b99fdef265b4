#include "ss_proto.h"

const char *ss_proto_error_name(ss_proto_error_t code)
{
    static const char *const names[] = {
        "none",      "bad_crc", "bad_length",  "unknown_type", "bad_payload", "out_of_range", "non_finite",
        "duplicate", "busy",    "bad_framing", "oversize",     "no_waveform", "unknown_param"};
    const unsigned i = (unsigned)code;
    return (i < sizeof names / sizeof names[0]) ? names[i] : "unknown_error";
}

/* The CRC of each 4-bit value shifted through the polynomial 0x1021: two lookups a byte instead of
 * eight conditional shifts (about 12 instructions a byte on a Cortex-M against 45; a paced run's
 * telemetry is encoded between steps, ss_proto_stream.h). */
static const uint16_t CRC_NIBBLE[16] = {0x0000u, 0x1021u, 0x2042u, 0x3063u, 0x4084u, 0x50A5u,
                                        0x60C6u, 0x70E7u, 0x8108u, 0x9129u, 0xA14Au, 0xB16Bu,
                                        0xC18Cu, 0xD1ADu, 0xE1CEu, 0xF1EFu};

uint16_t ss_crc16_ccitt_update(uint16_t crc, uint8_t byte)
{
    crc = (uint16_t)((uint16_t)(crc << 4) ^ CRC_NIBBLE[((crc >> 12) ^ (byte >> 4)) & 0xFu]);
    return (uint16_t)((uint16_t)(crc << 4) ^ CRC_NIBBLE[((crc >> 12) ^ byte) & 0xFu]);
}

uint16_t ss_crc16_ccitt(const uint8_t *data, size_t n)
{
    uint16_t crc = 0xFFFFu;
    for (size_t i = 0; i < n; ++i) {
        crc = ss_crc16_ccitt_update(crc, data[i]);
    }
    return crc;
}

size_t ss_cobs_encode(const uint8_t *src, size_t n, uint8_t *dst, size_t cap)
{
    size_t out = 1; /* dst[code_at] holds the distance to the next zero */
    size_t code_at = 0;
    uint8_t code = 1;
    if (cap == 0) {
        return 0;
    }
    for (size_t i = 0; i < n; ++i) {
        if (src[i] == 0u) {
            dst[code_at] = code;
            code_at = out++;
            code = 1;
        } else {
            if (out >= cap) {
                return 0;
            }
            dst[out++] = src[i];
            if (++code == 0xFFu) {
                dst[code_at] = code;
                code_at = out++;
                code = 1;
            }
        }
        if (out > cap) {
            return 0;
        }
    }
    if (code_at >= cap) {
        return 0;
    }
    dst[code_at] = code;
    return out;
}

int32_t ss_cobs_decode(const uint8_t *src, size_t n, uint8_t *dst, size_t cap)
{
    size_t out = 0;
    size_t i = 0;
    while (i < n) {
        const uint8_t code = src[i++];
        if (code == 0u || i + code - 1u > n) {
            return -1;
        }
        for (uint8_t k = 1; k < code; ++k) {
            if (src[i] == 0u || out >= cap) {
                return -1;
            }
            dst[out++] = src[i++];
        }
        if (code != 0xFFu && i < n) {
            if (out >= cap) {
                return -1;
            }
            dst[out++] = 0u;
        }
    }
    return (int32_t)out;
}

size_t ss_proto_build(uint8_t type, uint8_t seq, const uint8_t *payload, size_t len, uint8_t *wire,
                      size_t cap)
{
    uint8_t pkt[SS_PROTO_MAX_PACKET];
    if (len > SS_PROTO_MAX_PAYLOAD || (len > 0u && payload == 0)) {
        return 0;
    }
    pkt[0] = type;
    pkt[1] = seq;
    ss_put_u16(&pkt[2], (uint16_t)len);
    for (size_t i = 0; i < len; ++i) {
        pkt[4 + i] = payload[i];
    }
    ss_put_u16(&pkt[4 + len], ss_crc16_ccitt(pkt, 4 + len));
    const size_t n = ss_cobs_encode(pkt, len + SS_PROTO_OVERHEAD, wire, cap);
    if (n == 0u || n >= cap) {
        return 0;
    }
    wire[n] = 0u;
    return n + 1u;
}

size_t ss_proto_build_error(uint8_t seq, uint8_t ref_seq, ss_proto_error_t code, uint8_t ref_type,
                            const char *reason, uint8_t *wire, size_t cap)
{
    uint8_t p[3u + SS_PROTO_MAX_REASON];
    size_t len = 0;
    p[len++] = ref_seq;
    p[len++] = (uint8_t)code;
    p[len++] = ref_type;
    for (const char *c = reason; c != 0 && *c != '\0' && len < sizeof p; ++c) {
        p[len++] = (uint8_t)*c;
    }
    return ss_proto_build((uint8_t)SS_MSG_ERROR, seq, p, len, wire, cap);
}

void ss_proto_rx_init(ss_proto_rx_t *rx)
{
    rx->n = 0;
    rx->overflow = 0;
    rx->last_type = 0;
    rx->last_seq = 0;
}

ss_proto_error_t ss_proto_rx_push(ss_proto_rx_t *rx, uint8_t byte, ss_proto_packet_t *pkt, int *complete)
{
    *complete = 0;
    if (byte != 0u) {
        if (rx->n < sizeof rx->buf) {
            rx->buf[rx->n++] = byte;
        } else {
            rx->overflow = 1;
        }
        return SS_PERR_NONE;
    }
    /* delimiter: judge the frame */
    const size_t n = rx->n;
    const uint8_t overflow = rx->overflow;
    rx->n = 0;
    rx->overflow = 0;
    rx->last_type = 0;
    rx->last_seq = 0;
    if (overflow) {
        return SS_PERR_OVERSIZE;
    }
    if (n == 0u) {
        return SS_PERR_NONE; /* back-to-back delimiters: idle line, not an error */
    }
    uint8_t raw[SS_PROTO_MAX_PACKET];
    const int32_t m = ss_cobs_decode(rx->buf, n, raw, sizeof raw);
    if (m < 0) {
        return SS_PERR_BAD_FRAMING;
    }
    if (m < (int32_t)SS_PROTO_OVERHEAD) {
        return SS_PERR_BAD_LENGTH;
    }
    rx->last_type = raw[0];
    rx->last_seq = raw[1];
    const uint16_t len = ss_get_u16(&raw[2]);
    if ((int32_t)len + (int32_t)SS_PROTO_OVERHEAD != m) {
        return SS_PERR_BAD_LENGTH;
    }
    if (ss_get_u16(&raw[4 + len]) != ss_crc16_ccitt(raw, 4u + len)) {
        return SS_PERR_BAD_CRC;
    }
    pkt->type = raw[0];
    pkt->seq = raw[1];
    pkt->len = len;
    for (uint16_t i = 0; i < len; ++i) {
        pkt->payload[i] = raw[4 + i];
    }
    *complete = 1;
    return SS_PERR_NONE;
}

void ss_put_u16(uint8_t *p, uint16_t v)
{
    p[0] = (uint8_t)(v & 0xFFu);
    p[1] = (uint8_t)(v >> 8);
}

void ss_put_u32(uint8_t *p, uint32_t v)
{
    for (int i = 0; i < 4; ++i) {
        p[i] = (uint8_t)((v >> (8 * i)) & 0xFFu);
    }
}

void ss_put_f32(uint8_t *p, float v)
{
    union {
        float f;
        uint32_t u;
    } c;
    c.f = v;
    ss_put_u32(p, c.u);
}

uint16_t ss_get_u16(const uint8_t *p)
{
    return (uint16_t)((uint16_t)p[0] | (uint16_t)((uint16_t)p[1] << 8));
}

uint32_t ss_get_u32(const uint8_t *p)
{
    return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) | ((uint32_t)p[3] << 24);
}

float ss_get_f32(const uint8_t *p)
{
    union {
        float f;
        uint32_t u;
    } c;
    c.u = ss_get_u32(p);
    return c.f;
}
