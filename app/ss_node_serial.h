/* The node on a byte link (docs/protocol.md): COBS/CRC frames in, replies, errors and telemetry
 * out, the rules and the model in the core (ss_node_core.h). The framing buffers (some 4 KB) are
 * this front end's: a CAN-only node (ss_node_can.h) does not carry them. */
#ifndef SS_NODE_SERIAL_H
#define SS_NODE_SERIAL_H

#include <stdint.h>

#include "ss_node_core.h"
#include "ss_port.h"
#include "ss_proto.h"
#include "ss_proto_stream.h"

/* Bytes read from the link per poll. */
#define SS_NODE_SERIAL_READ_CHUNK 256u
/* Longest reason text in an ERROR frame. */
#define SS_NODE_SERIAL_MAX_REASON 96u
/* A paced run's telemetry goes out between steps, this many bytes (encoded, then sent) at a time. */
#define SS_NODE_SERIAL_TX_CHUNK 16u

typedef struct {
    ss_node_core_t core;
    const ss_port_link_t *link;
    ss_proto_rx_t rx;
    ss_proto_packet_t pkt;
    uint8_t tx_seq; /* the node's frame counter */
    /* a free run's telemetry, a frame of SS_PROTO_MAX_ROWS rows at a time: rows[fill] fills (n_rows,
     * from step first_row_step); in a paced run a full buffer's frame is encoded and sent in the
     * time between steps (tx, from rows[tx_buf] into wire) while the other fills, so that no step
     * waits for a whole frame (some 20 000 instructions) */
    uint8_t rows[2][SS_PROTO_MAX_ROWS * SS_PROTO_ROW_BYTES];
    uint32_t n_rows, first_row_step;
    uint8_t fill;
    uint8_t tx_active, tx_buf;
    uint8_t tx_head[7], tx_tail[4]; /* the frame's run seq, first step, row count; its misses */
    uint16_t tx_at, tx_rows;        /* payload bytes put; rows in the frame */
    uint64_t chunk_fs;              /* the longest piece of that work this run (0: none yet) */
    ss_proto_stream_t tx;
    uint8_t wire[SS_PROTO_MAX_WIRE];
} ss_node_serial_t;

/* Table I parameters, LS friction, at rest (the q node: ss_actuator_config_table1_q()). */
void ss_node_serial_init(ss_node_serial_t *node, const ss_port_link_t *link);

/* Read what the link has, answer it, and advance a free run. Returns -1 when the link reported
 * the peer gone (the session is reset; the node stays usable), else 0. */
int ss_node_serial_poll(ss_node_serial_t *node);

/* Forget the session (decoder, sequence numbers, a run in progress); keep model and waveform. */
void ss_node_serial_session_reset(ss_node_serial_t *node);

#endif /* SS_NODE_SERIAL_H */
