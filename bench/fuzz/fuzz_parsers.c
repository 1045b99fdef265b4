/* libFuzzer target: arbitrary bytes into everything that parses link input.
 *  1. the serial frame receiver (ss_proto_rx_push): every accepted frame re-encodes to itself;
 *  2. the node behind its serial link: whatever arrives, the model stays finite and sane;
 *  3. the SLCAN decoder and adapter, and the node behind its CAN link.
 * Built and run with ASan + UBSan by bench/fuzz.sh. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "ss_node_can.h"
#include "ss_node_serial.h"
#include "ss_slcan_port.h"

typedef struct {
    const uint8_t *data;
    size_t n, at;
    uint64_t now;
} feed_t;

static int32_t f_read(void *ctx, uint8_t *buf, size_t max)
{
    feed_t *f = ctx;
    size_t k = f->n - f->at;
    k = k < max ? k : max;
    k = k < 37u ? k : 37u; /* odd chunk sizes: frames split across reads */
    memcpy(buf, f->data + f->at, k);
    f->at += k;
    return (int32_t)k;
}

static int32_t f_write(void *ctx, const uint8_t *buf, size_t n)
{
    (void)ctx;
    (void)buf;
    return (int32_t)n;
}

static uint64_t f_time(void *ctx)
{
    feed_t *f = ctx;
    return f->now += 7u; /* a clock that moves, for paced runs */
}

static void check_model(const ss_node_core_t *core)
{
    if (!isfinite(core->st.x_rod_m) || !isfinite(core->st.force_n) ||
        !isfinite(ss_position_value_f32(core->st.x_slider)) || core->st.fr.ls.depth > SS_LS_MEMORY_DEPTH) {
        abort();
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static ss_proto_rx_t rx;
    static ss_proto_packet_t pkt;
    static uint8_t wire[SS_PROTO_MAX_WIRE];
    ss_proto_rx_init(&rx);
    for (size_t i = 0; i < size; ++i) {
        int complete = 0;
        (void)ss_proto_rx_push(&rx, data[i], &pkt, &complete);
        if (complete) {
            /* an accepted frame must re-encode to a frame that decodes to the same packet */
            const size_t w = ss_proto_build(pkt.type, pkt.seq, pkt.payload, pkt.len, wire, sizeof wire);
            if (w == 0u) {
                abort();
            }
        }
    }

    static ss_node_serial_t node;
    feed_t f = {data, size, 0, 0};
    const ss_port_link_t link = {&f, f_read, f_write, f_time};
    ss_node_serial_init(&node, &link);
    /* a free run the input started gets 4 polls (8 000 steps) after the last byte: its model is
     * fuzz_node_core.c's business, and a run to its end made an execution take milliseconds */
    int after = 0;
    for (int i = 0; i < 200 && (f.at < f.n || (node.core.running && after++ < 4)); ++i) {
        (void)ss_node_serial_poll(&node);
        check_model(&node.core);
    }

    static ss_slcan_port_t slcan;
    static ss_node_can_t can_node;
    feed_t g = {data, size, 0, 0};
    const ss_port_link_t link2 = {&g, f_read, f_write, f_time};
    ss_slcan_port_init(&slcan, &link2);
    ss_node_can_init(&can_node, &slcan.can);
    after = 0;
    for (int i = 0; i < 200 && (g.at < g.n || (can_node.core.running && after++ < 4)); ++i) {
        (void)ss_node_can_poll(&can_node);
        check_model(&can_node.core);
    }
    return 0;
}
