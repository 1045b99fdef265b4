/* An in-memory link and a fake clock for the node tests (test_node.c, test_node_q.c): what the
 * test pushes into `in` the node reads; what the node writes lands in `out`. */
#ifndef SS_FAKE_LINK_H
#define SS_FAKE_LINK_H

#include <stdint.h>
#include <string.h>

#include "ss_port.h"

typedef struct {
    uint8_t in[8192];
    size_t in_n, in_at;
    uint8_t out[1 << 16];
    size_t out_n;
    uint64_t now_ns;
    uint64_t tick_ns; /* what each reading of the clock costs (a node that is slow to step) */
    int gone;         /* next read reports the peer gone */
} fake_t;

static int32_t fake_read(void *ctx, uint8_t *buf, size_t max)
{
    fake_t *f = ctx;
    if (f->gone) {
        f->gone = 0;
        return -1;
    }
    size_t n = f->in_n - f->in_at;
    n = n < max ? n : max;
    memcpy(buf, f->in + f->in_at, n);
    f->in_at += n;
    return (int32_t)n;
}

static int32_t fake_write(void *ctx, const uint8_t *buf, size_t n)
{
    fake_t *f = ctx;
    if (f->out_n + n > sizeof f->out) {
        return -1;
    }
    memcpy(f->out + f->out_n, buf, n);
    f->out_n += n;
    return (int32_t)n;
}

static uint64_t fake_time(void *ctx)
{
    fake_t *f = ctx;
    const uint64_t t = f->now_ns;
    f->now_ns += f->tick_ns;
    return t;
}

#endif /* SS_FAKE_LINK_H */
