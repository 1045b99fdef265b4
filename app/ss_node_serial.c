/* The node's serial front end (ss_node_serial.h): the frames of docs/protocol.md in and out. */
#include "ss_node_serial.h"

#include <math.h>
#include <stdint.h>

/* ------------------------------------------------------------------ sending */

static void tx_finish(ss_node_serial_t *n);

static void send_frame(ss_node_serial_t *n, uint8_t type, const uint8_t *payload, size_t len)
{
    tx_finish(n); /* a telemetry frame on its way goes out whole first (frames never interleave) */
    const size_t w = ss_proto_build(type, n->tx_seq, payload, len, n->wire, sizeof n->wire);
    if (w > 0u) {
        n->tx_seq++;
        (void)n->link->write(n->link->ctx, n->wire, w);
    }
}

static void send_error(ss_node_serial_t *n, ss_proto_error_t code, uint8_t ref_type, uint8_t ref_seq,
                       const char *a, const char *b)
{
    uint8_t p[3 + SS_NODE_SERIAL_MAX_REASON];
    size_t len = 0;
    p[len++] = ref_seq;
    p[len++] = (uint8_t)code;
    p[len++] = ref_type;
    const char *parts[3] = {a, (b != 0 && b[0] != '\0') ? ": " : "", b};
    for (int i = 0; i < 3; ++i) {
        for (const char *c = parts[i]; c != 0 && *c != '\0' && len < sizeof p; ++c) {
            p[len++] = (uint8_t)*c;
        }
    }
    send_frame(n, SS_MSG_ERROR, p, len);
}

/* An ERROR about the request being handled. */
static void send_err(ss_node_serial_t *n, ss_proto_error_t code, const char *a, const char *b)
{
    send_error(n, code, n->pkt.type, n->pkt.seq, a, b);
}

static void send_refusal(ss_node_serial_t *n, ss_proto_error_t code, const ss_node_refusal_t *why)
{
    send_err(n, code, why->what, why->why);
}

static void send_reply(ss_node_serial_t *n, uint8_t req_type, const uint8_t *body, size_t len)
{
    uint8_t p[SS_PROTO_MAX_PAYLOAD];
    p[0] = n->pkt.seq;
    for (size_t i = 0; i < len && i + 1u < sizeof p; ++i) {
        p[i + 1u] = body[i];
    }
    send_frame(n, (uint8_t)(req_type | SS_MSG_REPLY), p, len + 1u);
}

static void put_row(uint8_t *b, const ss_node_core_t *c)
{
    const ss_node_row_t r = ss_node_core_row(c);
    ss_put_u32(b, r.steps);
    ss_put_f32(b + 4, r.drive_v);
    ss_put_f32(b + 8, r.x_rod_m);
    ss_put_f32(b + 12, r.x_slider_hi_m);
    ss_put_f32(b + 16, r.x_slider_lo_m);
    ss_put_f32(b + 20, r.force_n);
}

/* ------------------------------------------------------------------ a free run's output */

/* A free run's TELEMETRY frame is built by the streaming encoder (ss_proto_stream.h): at once in
 * an unpaced run and at a run's end, SS_NODE_SERIAL_TX_CHUNK bytes at a time between steps in a
 * paced one. Its payload: run seq, first step, row count, the rows, the run's misses so far. */

/* Put up to max more bytes of the frame's payload: its head, its rows, the misses so far. */
static void tx_put(ss_node_serial_t *n, size_t max)
{
    const size_t rows_end = 7u + (size_t)n->tx_rows * SS_PROTO_ROW_BYTES;
    const size_t total = rows_end + 4u;
    while (max > 0u && n->tx_at < total) {
        const uint8_t *src;
        size_t avail;
        if (n->tx_at < 7u) {
            src = &n->tx_head[n->tx_at];
            avail = 7u - n->tx_at;
        } else if (n->tx_at < rows_end) {
            src = &n->rows[n->tx_buf][n->tx_at - 7u];
            avail = rows_end - n->tx_at;
        } else {
            if (n->tx_at == rows_end) {
                ss_put_u32(n->tx_tail, n->core.run_misses); /* taken once: the count when it is reached */
            }
            src = &n->tx_tail[n->tx_at - rows_end];
            avail = total - n->tx_at;
        }
        const size_t k = (avail < max) ? avail : max;
        ss_proto_stream_put(&n->tx, src, k);
        n->tx_at = (uint16_t)(n->tx_at + k);
        max -= k;
    }
}

/* Hand up to max of the frame's final bytes to the link; the frame is done when all are sent. */
static void tx_send(ss_node_serial_t *n, size_t max)
{
    const uint8_t *p = 0;
    size_t k = ss_proto_stream_ready(&n->tx, &p);
    k = (k < max) ? k : max;
    if (k > 0u) {
        (void)n->link->write(n->link->ctx, p, k);
        ss_proto_stream_sent(&n->tx, k);
    }
    if (ss_proto_stream_done(&n->tx)) {
        n->tx_active = 0;
    }
}

static void tx_finish(ss_node_serial_t *n)
{
    if (n->tx_active) {
        tx_put(n, SIZE_MAX);
        tx_send(n, SIZE_MAX);
    }
}

/* rows[fill]'s frame starts on its way and the other buffer fills. If the last frame is still
 * going (the steps left no time for it), it goes out whole now: its buffer is needed. */
static void tx_start(ss_node_serial_t *n)
{
    tx_finish(n);
    const uint16_t rows = (uint16_t)n->n_rows;
    n->tx_head[0] = n->core.run_seq;
    ss_put_u32(&n->tx_head[1], n->first_row_step);
    ss_put_u16(&n->tx_head[5], rows);
    n->tx_buf = n->fill;
    n->tx_rows = rows;
    n->tx_at = 0;
    (void)ss_proto_stream_begin(&n->tx, n->wire, SS_MSG_TELEMETRY, n->tx_seq++,
                                (uint16_t)(7u + rows * SS_PROTO_ROW_BYTES + 4u));
    n->tx_active = 1;
    n->fill ^= 1u;
    n->n_rows = 0;
}

/* The rows gathered so far, sent now (a frame, if there are any). */
static void flush_rows(ss_node_serial_t *n)
{
    if (n->n_rows > 0u) {
        tx_start(n);
        tx_finish(n);
    }
}

/* Between steps: the frame's next piece, while the next step is not due before the longest piece
 * measured so far could end (before the first is measured: half a slot must be free). */
static void tx_background(ss_node_serial_t *n)
{
    while (n->tx_active) {
        const uint64_t t0 = n->link->time_ns(n->link->ctx);
        const uint64_t need_fs = (n->chunk_fs != 0u) ? n->chunk_fs : n->core.run_dt_fs / 2u;
        if (ss_node_core_idle_fs(&n->core, t0) < need_fs) {
            return;
        }
        tx_put(n, SS_NODE_SERIAL_TX_CHUNK);
        tx_send(n, SS_NODE_SERIAL_TX_CHUNK);
        const uint64_t took_fs = (n->link->time_ns(n->link->ctx) - t0) * 1000000u;
        n->chunk_fs = (took_fs > n->chunk_fs) ? took_fs : n->chunk_fs;
    }
}

static void run_row(void *ctx, const ss_node_core_t *c)
{
    ss_node_serial_t *n = ctx;
    if (n->n_rows == 0u) {
        n->first_row_step = c->st.steps;
    }
    put_row(&n->rows[n->fill][(size_t)SS_PROTO_ROW_BYTES * n->n_rows++], c);
    if (n->n_rows == SS_PROTO_MAX_ROWS) {
        tx_start(n);
        if (!c->paced) {
            tx_finish(n);
        }
    }
}

static void run_end(void *ctx, uint8_t req, uint8_t ref_seq, uint32_t steps_done, uint32_t misses)
{
    ss_node_serial_t *n = ctx;
    flush_rows(n);
    uint8_t p[9];
    p[0] = ref_seq;
    ss_put_u32(&p[1], steps_done);
    ss_put_u32(&p[5], misses);
    send_frame(n, (uint8_t)(req | SS_MSG_REPLY), p, sizeof p);
}

static uint64_t run_now(void *ctx)
{
    const ss_node_serial_t *n = ctx;
    return n->link->time_ns(n->link->ctx);
}

static ss_node_run_sink_t sink_of(ss_node_serial_t *n)
{
    const ss_node_run_sink_t s = {n, run_row, run_end, run_now};
    return s;
}

/* ------------------------------------------------------------------ requests */

static void handle_hello(ss_node_serial_t *n)
{
    uint8_t b[8 + sizeof SS_NODE_VERSION];
    b[0] = (uint8_t)SS_PROTO_VERSION;
    b[1] = (uint8_t)n->core.cfg.friction_model;
    b[2] = (uint8_t)SS_NODE_VARIANT;
    b[3] = (uint8_t)SS_NODE_N_PARAMS;
    ss_put_f32(&b[4], ss_node_model_dt_s(&n->core.cfg));
    size_t len = 8;
    for (const char *c = SS_NODE_VERSION; *c != '\0'; ++c) {
        b[len++] = (uint8_t)*c;
    }
    send_reply(n, SS_MSG_HELLO, b, len);
}

static void handle_param_info(ss_node_serial_t *n)
{
    const ss_proto_packet_t *pk = &n->pkt;
    if (pk->len != 1u) {
        send_err(n, SS_PERR_BAD_PAYLOAD, "PARAM_INFO takes 1 byte", "");
        return;
    }
    const uint32_t id = pk->payload[0];
    float value = 0.0f;
    ss_node_refusal_t why;
    const ss_proto_error_t e = ss_node_core_get_param(&n->core, id, &value, &why);
    if (e != SS_PERR_NONE) {
        send_refusal(n, e, &why);
        return;
    }
    const ss_node_param_def_t *d = ss_node_core_param_def(id);
    uint8_t b[13 + 32];
    b[0] = (uint8_t)id;
    ss_put_f32(&b[1], value);
    ss_put_f32(&b[5], d->min);
    ss_put_f32(&b[9], d->max);
    size_t len = 13;
    for (const char *c = d->name; *c != '\0' && len < sizeof b; ++c) {
        b[len++] = (uint8_t)*c;
    }
    send_reply(n, SS_MSG_PARAM_INFO, b, len);
}

/* The parameter a GET_PARAM or SET_PARAM names: an id in byte 0, or 0xFF and a name from
 * name_at; 0 (and an ERROR sent) if there is no such name. */
static int named_param(ss_node_serial_t *n, size_t name_at, uint32_t *id)
{
    const ss_proto_packet_t *pk = &n->pkt;
    if (pk->payload[0] != 0xFFu) {
        *id = pk->payload[0];
        return 1;
    }
    if (!ss_node_core_param_id(&pk->payload[name_at], pk->len - name_at, id)) {
        send_err(n, SS_PERR_UNKNOWN_PARAM, "no parameter with that name", "");
        return 0;
    }
    return 1;
}

static void handle_get_param(ss_node_serial_t *n)
{
    const ss_proto_packet_t *pk = &n->pkt;
    uint32_t id = 0;
    if (!((pk->len == 1u && pk->payload[0] != 0xFFu) || (pk->len >= 2u && pk->payload[0] == 0xFFu))) {
        send_err(n, SS_PERR_BAD_PAYLOAD, "GET_PARAM takes an id or 0xFF + name", "");
        return;
    }
    if (!named_param(n, 1, &id)) {
        return;
    }
    float value = 0.0f;
    ss_node_refusal_t why;
    const ss_proto_error_t e = ss_node_core_get_param(&n->core, id, &value, &why);
    if (e != SS_PERR_NONE) {
        send_refusal(n, e, &why);
        return;
    }
    uint8_t b[5];
    b[0] = (uint8_t)id;
    ss_put_f32(&b[1], value);
    send_reply(n, SS_MSG_GET_PARAM, b, sizeof b);
}

static void handle_set_param(ss_node_serial_t *n)
{
    const ss_proto_packet_t *pk = &n->pkt;
    uint32_t id = 0;
    if (!((pk->len == 5u && pk->payload[0] != 0xFFu) || (pk->len >= 6u && pk->payload[0] == 0xFFu))) {
        send_err(n, SS_PERR_BAD_PAYLOAD, "SET_PARAM takes id + f32 or 0xFF + f32 + name", "");
        return;
    }
    const float v = ss_get_f32(&pk->payload[1]);
    if (!named_param(n, 5, &id)) {
        return;
    }
    ss_node_refusal_t why;
    const ss_proto_error_t e = ss_node_core_set_param(&n->core, id, v, &why);
    if (e != SS_PERR_NONE) {
        send_refusal(n, e, &why);
        return;
    }
    uint8_t b[5];
    b[0] = (uint8_t)id;
    ss_put_f32(&b[1], v);
    send_reply(n, SS_MSG_SET_PARAM, b, sizeof b);
}

static void handle_set_model(ss_node_serial_t *n)
{
    const ss_proto_packet_t *pk = &n->pkt;
    uint8_t ids[SS_NODE_N_PARAMS];
    float values[SS_NODE_N_PARAMS];
    const uint32_t count = pk->len / 5u;
    if (pk->len == 0u || pk->len % 5u != 0u || count > SS_NODE_N_PARAMS) {
        send_err(n, SS_PERR_BAD_PAYLOAD, "SET_MODEL takes 1 to " SS_NODE_N_PARAMS_TEXT " id + f32 pairs", "");
        return;
    }
    for (size_t i = 0; i < count; ++i) {
        ids[i] = pk->payload[5u * i];
        values[i] = ss_get_f32(&pk->payload[5u * i + 1u]);
    }
    ss_node_refusal_t why;
    const ss_proto_error_t e = ss_node_core_set_params(&n->core, ids, values, count, &why);
    if (e != SS_PERR_NONE) {
        send_refusal(n, e, &why);
        return;
    }
    const uint8_t b[1] = {(uint8_t)count};
    send_reply(n, SS_MSG_SET_MODEL, b, sizeof b);
}

static void handle_reset(ss_node_serial_t *n)
{
    const ss_proto_packet_t *pk = &n->pkt;
    if (pk->len != 4u && pk->len != 8u) {
        send_err(n, SS_PERR_BAD_PAYLOAD, "RESET takes f32 drive0_v [, f32 x0_m]", "");
        return;
    }
    ss_node_refusal_t why;
    const float x0_m = (pk->len == 8u) ? ss_get_f32(pk->payload + 4) : 0.0f;
    const ss_proto_error_t e = ss_node_core_reset(&n->core, ss_get_f32(pk->payload), x0_m, &why);
    if (e != SS_PERR_NONE) {
        send_refusal(n, e, &why);
        return;
    }
    send_reply(n, SS_MSG_RESET, 0, 0);
}

static void handle_load_waveform(ss_node_serial_t *n)
{
    const ss_proto_packet_t *pk = &n->pkt;
    if (pk->len != 21u) {
        send_err(n, SS_PERR_BAD_PAYLOAD, "LOAD_WAVEFORM takes 21 bytes", "");
        return;
    }
    const uint8_t *p = pk->payload;
    const ss_waveform_config_f32_t w =
        ss_waveform_sawtooth_f32(ss_get_f32(p), ss_get_f32(p + 4), ss_get_f32(p + 8), ss_get_f32(p + 12),
                                 (int32_t)(int8_t)p[16], ss_get_u32(p + 17));
    ss_node_refusal_t why;
    const ss_proto_error_t e = ss_node_core_load_waveform(&n->core, &w, &why);
    if (e != SS_PERR_NONE) {
        send_refusal(n, e, &why);
        return;
    }
    send_reply(n, SS_MSG_LOAD_WAVEFORM, 0, 0);
}

#define SS_STR_(x) #x
#define SS_STR(x) SS_STR_(x)

static void handle_drive_block(ss_node_serial_t *n)
{
    const ss_proto_packet_t *pk = &n->pkt;
    if (pk->len < 6u || (pk->len - 2u) % 4u != 0u || (pk->len - 2u) / 4u > 255u) {
        send_err(n, SS_PERR_BAD_PAYLOAD, "DRIVE_BLOCK takes u16 + 1..255 f32", "");
        return;
    }
    const uint32_t dec = ss_get_u16(pk->payload);
    const uint32_t count = (pk->len - 2u) / 4u;
    if (dec == 0u || count / dec > SS_PROTO_MAX_ROWS) {
        send_err(n, SS_PERR_OUT_OF_RANGE, "decimation",
                 "must be >= 1 and give <= " SS_STR(SS_PROTO_MAX_ROWS) " rows");
        return;
    }
    for (uint32_t i = 0; i < count; ++i) { /* check all before touching the state */
        const float v = ss_get_f32(&pk->payload[2u + 4u * i]);
        if (!isfinite(v)) {
            send_err(n, SS_PERR_NON_FINITE, "drive sample", "not a finite number");
            return;
        }
        if (fabsf(v) > SS_NODE_MAX_DRIVE_V) {
            send_err(n, SS_PERR_OUT_OF_RANGE, "drive sample", "outside " SS_NODE_MAX_DRIVE_V_TEXT);
            return;
        }
    }
    uint8_t b[6 + SS_PROTO_MAX_ROWS * SS_PROTO_ROW_BYTES];
    uint32_t rows = 0;
    ss_put_u32(b, n->core.st.steps + dec);
    for (uint32_t i = 0; i < count; ++i) {
        (void)ss_node_core_drive(&n->core, ss_get_f32(&pk->payload[2u + 4u * i]));
        if ((i + 1u) % dec == 0u) {
            put_row(&b[6u + (size_t)SS_PROTO_ROW_BYTES * rows++], &n->core);
        }
    }
    ss_put_u16(&b[4], (uint16_t)rows);
    send_reply(n, SS_MSG_DRIVE_BLOCK, b, 6u + (size_t)SS_PROTO_ROW_BYTES * rows);
}

static void handle_run(ss_node_serial_t *n)
{
    const ss_proto_packet_t *pk = &n->pkt;
    if (pk->len != 7u) {
        send_err(n, SS_PERR_BAD_PAYLOAD, "RUN takes u32 + u16 + u8", "");
        return;
    }
    n->n_rows = 0;
    n->fill = 0;
    n->chunk_fs = 0;
    const ss_node_run_sink_t sink = sink_of(n);
    ss_node_refusal_t why;
    const ss_proto_error_t e =
        ss_node_core_run(&n->core, pk->seq, ss_get_u32(pk->payload), ss_get_u16(&pk->payload[4]),
                         pk->payload[6], n->link->time_ns(n->link->ctx), &sink, &why);
    if (e != SS_PERR_NONE) {
        send_refusal(n, e, &why);
    }
}

static void handle_stop(ss_node_serial_t *n)
{
    const ss_node_run_sink_t sink = sink_of(n);
    if (!ss_node_core_stop(&n->core, n->pkt.seq, &sink)) {
        uint8_t b[8];
        ss_put_u32(b, 0u);
        ss_put_u32(&b[4], 0u);
        send_reply(n, SS_MSG_STOP, b, sizeof b);
    }
}

static void handle_packet(ss_node_serial_t *n)
{
    const ss_proto_packet_t *pk = &n->pkt;
    if (pk->type == SS_MSG_HELLO) {
        ss_node_core_hello(&n->core, pk->seq);
        n->n_rows = 0;
        handle_hello(n);
        return;
    }
    ss_node_refusal_t why;
    const ss_proto_error_t e = ss_node_core_admit(&n->core, pk->seq, pk->type == SS_MSG_STOP, &why);
    if (e != SS_PERR_NONE) {
        send_refusal(n, e, &why);
        return;
    }
    switch (pk->type) {
    case SS_MSG_PARAM_INFO: handle_param_info(n); break;
    case SS_MSG_GET_PARAM: handle_get_param(n); break;
    case SS_MSG_SET_PARAM: handle_set_param(n); break;
    case SS_MSG_SET_MODEL: handle_set_model(n); break;
    case SS_MSG_RESET: handle_reset(n); break;
    case SS_MSG_LOAD_WAVEFORM: handle_load_waveform(n); break;
    case SS_MSG_DRIVE_BLOCK: handle_drive_block(n); break;
    case SS_MSG_RUN: handle_run(n); break;
    case SS_MSG_STOP: handle_stop(n); break;
    default: send_err(n, SS_PERR_UNKNOWN_TYPE, "unknown request type", ""); break;
    }
}

/* ------------------------------------------------------------------ the node */

void ss_node_serial_session_reset(ss_node_serial_t *n)
{
    ss_proto_rx_init(&n->rx);
    ss_node_core_session_reset(&n->core);
    n->n_rows = 0;
    if (n->tx_active && n->tx.sent > 0u) {
        const uint8_t delimiter = 0u; /* ends the frame cut short: the next peer sees a bad frame */
        (void)n->link->write(n->link->ctx, &delimiter, 1u);
    }
    n->tx_active = 0;
}

void ss_node_serial_init(ss_node_serial_t *n, const ss_port_link_t *link)
{
    n->link = link;
    n->tx_seq = 0;
    n->tx_active = 0;
    n->fill = 0;
    ss_node_core_init(&n->core);
    ss_node_serial_session_reset(n);
}

int ss_node_serial_poll(ss_node_serial_t *n)
{
    uint8_t buf[SS_NODE_SERIAL_READ_CHUNK];
    const int32_t got = n->link->read(n->link->ctx, buf, sizeof buf);
    if (got < 0) {
        ss_node_serial_session_reset(n);
        return -1;
    }
    for (int32_t i = 0; i < got; ++i) {
        int complete = 0;
        const ss_proto_error_t e = ss_proto_rx_push(&n->rx, buf[i], &n->pkt, &complete);
        if (e != SS_PERR_NONE) {
            send_error(n, e, n->rx.last_type, n->rx.last_seq, "frame rejected", ss_proto_error_name(e));
        } else if (complete) {
            handle_packet(n);
        }
    }
    if (n->core.running) {
        const ss_node_run_sink_t sink = sink_of(n);
        ss_node_core_run_poll(&n->core, n->link->time_ns(n->link->ctx), &sink);
        tx_background(n);
    }
    return 0;
}
