/* Streaming frame encoder (ss_proto_stream.h): ss_proto_build's CRC and COBS, one byte at a time. */
#include "ss_proto_stream.h"

#include "ss_proto.h"

static void cobs_put(ss_proto_stream_t *s, uint8_t b)
{
    if (b == 0u) {
        s->wire[s->code_at] = s->code;
        s->code_at = s->out++;
        s->code = 1u;
        return;
    }
    s->wire[s->out++] = b;
    if (++s->code == 0xFFu) { /* a full group of 254: closed without a zero */
        s->wire[s->code_at] = s->code;
        s->code_at = s->out++;
        s->code = 1u;
    }
}

static void put_checked(ss_proto_stream_t *s, uint8_t b)
{
    s->crc = ss_crc16_ccitt_update(s->crc, b);
    cobs_put(s, b);
}

int ss_proto_stream_begin(ss_proto_stream_t *s, uint8_t *wire, uint8_t type, uint8_t seq, uint16_t len)
{
    if (len > SS_PROTO_MAX_PAYLOAD) {
        return 0;
    }
    s->wire = wire;
    s->out = 1u;
    s->code_at = 0u;
    s->sent = 0u;
    s->code = 1u;
    s->complete = 0u;
    s->crc = 0xFFFFu;
    s->left = 0u;
    const uint8_t header[4] = {type, seq, (uint8_t)(len & 0xFFu), (uint8_t)(len >> 8)};
    for (int i = 0; i < 4; ++i) {
        put_checked(s, header[i]);
    }
    s->left = len;
    if (len == 0u) {
        ss_proto_stream_put(s, 0, 0);
    }
    return 1;
}

void ss_proto_stream_put(ss_proto_stream_t *s, const uint8_t *p, size_t n)
{
    if (s->complete) {
        return;
    }
    const size_t take = (n < s->left) ? n : s->left;
    for (size_t i = 0; i < take; ++i) {
        put_checked(s, p[i]);
    }
    s->left = (uint16_t)(s->left - take);
    if (s->left == 0u) {
        const uint16_t crc = s->crc;
        cobs_put(s, (uint8_t)(crc & 0xFFu));
        cobs_put(s, (uint8_t)(crc >> 8));
        s->wire[s->code_at] = s->code;
        s->wire[s->out++] = 0u; /* the delimiter */
        s->complete = 1u;
    }
}

size_t ss_proto_stream_ready(const ss_proto_stream_t *s, const uint8_t **p)
{
    const size_t final_end = s->complete ? s->out : s->code_at;
    *p = s->wire + s->sent;
    return final_end - s->sent;
}

void ss_proto_stream_sent(ss_proto_stream_t *s, size_t n)
{
    s->sent += n;
}

int ss_proto_stream_done(const ss_proto_stream_t *s)
{
    return s->complete && s->sent == s->out;
}
