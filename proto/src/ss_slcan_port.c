#include "ss_slcan_port.h"

static void reply(ss_slcan_port_t *p, const char *s)
{
    size_t n = 0;
    while (s[n] != '\0') {
        ++n;
    }
    (void)p->link->write(p->link->ctx, (const uint8_t *)s, n);
}

static void command(ss_slcan_port_t *p, const char *cmd)
{
    switch (cmd[0]) {
    case 'O':
    case 'L':
        p->open = 1;
        reply(p, "\r");
        break;
    case 'C':
        p->open = 0;
        reply(p, "\r");
        break;
    case 'S':
        /* S0..S8: 10 kbit/s .. 1 Mbit/s; only the number is checked, the link has no bit time */
        reply(p, (cmd[1] >= '0' && cmd[1] <= '8' && cmd[2] == '\0') ? "\r" : "\a");
        break;
    case 's':
    case 'Z':
    case 'M':
    case 'm': reply(p, "\r"); break;
    case 'V': reply(p, "V1013\r"); break;
    case 'v': reply(p, "v1013\r"); break;
    case 'N': reply(p, "NSS01\r"); break;
    case 'F': reply(p, "F00\r"); break;
    default:
        p->bad_lines++;
        reply(p, "\a");
        break;
    }
}

static int32_t slcan_read(void *ctx, ss_can_frame_t *frame)
{
    ss_slcan_port_t *p = ctx;
    for (;;) {
        if (p->at == p->n) {
            const int32_t got = p->link->read(p->link->ctx, p->buf, sizeof p->buf);
            if (got < 0) {
                ss_slcan_rx_init(&p->rx);
                p->open = 0;
                p->n = p->at = 0;
                return -1;
            }
            if (got == 0) {
                return 0;
            }
            p->n = (size_t)got;
            p->at = 0;
        }
        char cmd[SS_SLCAN_MAX_LINE + 1u];
        const ss_slcan_event_t ev = ss_slcan_push(&p->rx, p->buf[p->at++], frame, cmd);
        if (ev == SS_SLCAN_FRAME) {
            if (p->open) {
                reply(p, frame->ext ? "Z\r" : "z\r"); /* Lawicel: transmit acknowledged */
                return 1;
            }
            reply(p, "\a"); /* channel closed */
        } else if (ev == SS_SLCAN_COMMAND) {
            command(p, cmd);
        } else if (ev == SS_SLCAN_BAD) {
            p->bad_lines++;
            reply(p, "\a");
        }
    }
}

static int32_t slcan_write(void *ctx, const ss_can_frame_t *frame)
{
    ss_slcan_port_t *p = ctx;
    char line[SS_SLCAN_MAX_LINE];
    const size_t n = ss_slcan_format(frame, line, sizeof line);
    if (n == 0u || !p->open) {
        return -1;
    }
    return (p->link->write(p->link->ctx, (const uint8_t *)line, n) < 0) ? -1 : 1;
}

static uint64_t slcan_time(void *ctx)
{
    ss_slcan_port_t *p = ctx;
    return p->link->time_ns(p->link->ctx);
}

void ss_slcan_port_init(ss_slcan_port_t *p, const ss_port_link_t *link)
{
    p->link = link;
    ss_slcan_rx_init(&p->rx);
    p->n = p->at = 0;
    p->open = 0;
    p->bad_lines = 0;
    p->can.ctx = p;
    p->can.read = slcan_read;
    p->can.write = slcan_write;
    p->can.time_ns = slcan_time;
}
