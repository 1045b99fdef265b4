#include "ss_can.h"

void ss_slcan_rx_init(ss_slcan_rx_t *rx)
{
    rx->n = 0;
    rx->overflow = 0;
}

static int hexval(char c)
{
    if (c >= '0' && c <= '9') {
        return c - '0';
    }
    if (c >= 'A' && c <= 'F') {
        return c - 'A' + 10;
    }
    if (c >= 'a' && c <= 'f') {
        return c - 'a' + 10;
    }
    return -1;
}

/* n hex digits at s into *v; 0 on a bad digit */
static int parse_hex(const char *s, size_t n, uint32_t *v)
{
    uint32_t x = 0;
    for (size_t i = 0; i < n; ++i) {
        const int h = hexval(s[i]);
        if (h < 0) {
            return 0;
        }
        x = (x << 4) | (uint32_t)h;
    }
    *v = x;
    return 1;
}

static ss_slcan_event_t parse_line(const char *l, size_t n, ss_can_frame_t *f, char *cmd)
{
    const char k = l[0];
    const int ext = (k == 'T' || k == 'R');
    if (k == 't' || k == 'T' || k == 'r' || k == 'R') {
        const size_t id_len = ext ? 8u : 3u;
        uint32_t id = 0;
        uint32_t dlc = 0;
        if (n < 2u + id_len || !parse_hex(&l[1], id_len, &id) || !parse_hex(&l[1 + id_len], 1, &dlc) ||
            dlc > 8u || id > (ext ? 0x1FFFFFFFu : 0x7FFu)) {
            return SS_SLCAN_BAD;
        }
        const int rtr = (k == 'r' || k == 'R');
        const size_t want = 2u + id_len + (rtr ? 0u : 2u * dlc);
        if (n != want) {
            return SS_SLCAN_BAD;
        }
        f->id = id;
        f->dlc = (uint8_t)dlc;
        f->ext = (uint8_t)ext;
        f->rtr = (uint8_t)rtr;
        for (uint32_t i = 0; i < 8u; ++i) {
            uint32_t b = 0;
            if (!rtr && i < dlc && !parse_hex(&l[2u + id_len + (size_t)2u * i], 2, &b)) {
                return SS_SLCAN_BAD;
            }
            f->data[i] = (uint8_t)((!rtr && i < dlc) ? b : 0u);
        }
        return SS_SLCAN_FRAME;
    }
    for (size_t i = 0; i < n; ++i) {
        cmd[i] = l[i];
    }
    cmd[n] = '\0';
    return SS_SLCAN_COMMAND;
}

ss_slcan_event_t ss_slcan_push(ss_slcan_rx_t *rx, uint8_t byte, ss_can_frame_t *frame, char *cmd)
{
    if (byte != '\r' && byte != '\n') {
        if (rx->n < SS_SLCAN_MAX_LINE) {
            rx->line[rx->n++] = (char)byte;
        } else {
            rx->overflow = 1;
        }
        return SS_SLCAN_NONE;
    }
    const size_t n = rx->n;
    const uint8_t overflow = rx->overflow;
    rx->n = 0;
    rx->overflow = 0;
    if (overflow) {
        return SS_SLCAN_BAD;
    }
    if (n == 0u) {
        return SS_SLCAN_NONE; /* empty line (e.g. "\r\n"): nothing */
    }
    return parse_line(rx->line, n, frame, cmd);
}

size_t ss_slcan_format(const ss_can_frame_t *f, char *out, size_t cap)
{
    static const char hx[] = "0123456789ABCDEF";
    const size_t id_len = f->ext ? 8u : 3u;
    const size_t len = 2u + id_len + (f->rtr ? 0u : 2u * f->dlc) + 1u;
    if (f->dlc > 8u || f->id > (f->ext ? 0x1FFFFFFFu : 0x7FFu) || len > cap) {
        return 0;
    }
    size_t k = 0;
    static const char kinds[2][2] = {{'t', 'T'}, {'r', 'R'}}; /* [rtr][ext] */
    out[k++] = kinds[f->rtr ? 1 : 0][f->ext ? 1 : 0];
    for (size_t i = 0; i < id_len; ++i) {
        out[k++] = hx[(f->id >> (4u * (id_len - 1u - i))) & 0xFu];
    }
    out[k++] = hx[f->dlc];
    for (uint8_t i = 0; !f->rtr && i < f->dlc; ++i) {
        out[k++] = hx[f->data[i] >> 4];
        out[k++] = hx[f->data[i] & 0xFu];
    }
    out[k++] = '\r';
    return k;
}
