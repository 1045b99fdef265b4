/* The node's CAN front end (ss_node_can.h). */
#include "ss_node_can.h"

#include <math.h>

static void send_state(ss_node_can_t *n)
{
    const ss_node_row_t r = ss_node_core_row(&n->core);
    const ss_can_state_t m = {r.steps, r.drive_v, r.x_rod_m, r.force_n, r.x_slider_hi_m, r.x_slider_lo_m};
    ss_can_frame_t f[3];
    ss_can_pack_state(&m, f);
    for (int i = 0; i < 3; ++i) {
        (void)n->can->write(n->can->ctx, &f[i]);
    }
}

static void reply(ss_node_can_t *n, uint8_t cmd, uint8_t seq, ss_proto_error_t status, uint8_t index,
                  float value)
{
    const ss_can_reply_t m = {cmd, seq, (uint8_t)status, index, value};
    ss_can_frame_t f;
    ss_can_pack_reply(&m, &f);
    (void)n->can->write(n->can->ctx, &f);
}

/* The reason of a refusal, "what: why", in SS_REASON frames (before the SS_REPLY). */
static void send_reason(ss_node_can_t *n, uint8_t cmd, uint8_t seq, const ss_node_refusal_t *why)
{
    const char *parts[3] = {why->what, (why->why[0] != '\0') ? ": " : "", why->why};
    int part = 0;
    const char *c = parts[0];
    for (uint32_t k = 0; k < SS_NODE_CAN_MAX_REASON_FRAMES; ++k) {
        ss_can_reason_t m = {cmd, seq, {0}};
        size_t i = 0;
        while (i < SS_CAN_REASON_CHARS && part < 3) {
            if (*c == '\0') {
                c = (++part < 3) ? parts[part] : c;
            } else {
                m.text[i++] = *c++;
            }
        }
        if (i == 0u) {
            return;
        }
        ss_can_frame_t f;
        ss_can_pack_reason(&m, &f);
        (void)n->can->write(n->can->ctx, &f);
    }
}

/* ------------------------------------------------------------------ a free run's output */

static void run_row(void *ctx, const ss_node_core_t *c)
{
    (void)c;
    send_state(ctx);
}

/* The CAN reply has room for the steps done only; a paced run's deadline misses go over the
 * serial link (docs/protocol.md). */
static void run_end(void *ctx, uint8_t req, uint8_t ref_seq, uint32_t steps_done, uint32_t misses)
{
    (void)misses;
    reply(ctx, (req == SS_MSG_RUN) ? SS_CAN_CMD_RUN : SS_CAN_CMD_STOP, ref_seq, SS_PERR_NONE, 0,
          (float)steps_done);
}

static uint64_t run_now(void *ctx)
{
    const ss_node_can_t *n = ctx;
    return n->can->time_ns(n->can->ctx);
}

static ss_node_run_sink_t sink_of(ss_node_can_t *n)
{
    const ss_node_run_sink_t s = {n, run_row, run_end, run_now};
    return s;
}

/* ------------------------------------------------------------------ commands */

/* A whole count in a float32 value: 1, or 0 if it is not one. */
static int count_from(float v, uint32_t *count)
{
    if (!isfinite(v) || v < 0.0f || v > SS_NODE_CAN_MAX_COUNT || v != (float)(uint32_t)v) {
        return 0;
    }
    *count = (uint32_t)v;
    return 1;
}

static ss_proto_error_t refuse(ss_node_refusal_t *why, ss_proto_error_t e, const char *what,
                               const char *because)
{
    why->what = what;
    why->why = because;
    return e;
}

static ss_proto_error_t set_wave(ss_node_can_t *n, uint8_t field, float v, ss_node_refusal_t *why)
{
    ss_waveform_config_f32_t *w = &n->wave_pending;
    if (!isfinite(v)) {
        return refuse(why, SS_PERR_NON_FINITE, "SET_WAVE value", "not a finite number");
    }
    switch (field) {
    case 0: w->frequency_hz = v; break;
    case 1: w->amplitude_v = v; break;
    case 2: w->offset_v = v; break;
    case 3: w->rise_fraction = v; break;
    case 4:
        if (v != 1.0f && v != -1.0f) {
            return refuse(why, SS_PERR_OUT_OF_RANGE, "direction", "+1 or -1");
        }
        w->direction = (int32_t)v;
        break;
    case 5:
        if (!count_from(v, &w->cycles)) {
            return refuse(why, SS_PERR_OUT_OF_RANGE, "cycles", "a whole number, at most 4e9");
        }
        break;
    default: return refuse(why, SS_PERR_OUT_OF_RANGE, "SET_WAVE field", "0..5");
    }
    return SS_PERR_NONE;
}

/* Keep one value for APPLY_MODEL (a repeated id replaces its value); checked against its row. */
static ss_proto_error_t stage_param(ss_node_can_t *n, uint8_t id, float v, ss_node_refusal_t *why)
{
    const ss_node_param_def_t *def = ss_node_core_param_def(id);
    if (def == NULL) {
        return refuse(why, SS_PERR_UNKNOWN_PARAM, "no parameter with that id", "");
    }
    if (!isfinite(v)) {
        return refuse(why, SS_PERR_NON_FINITE, def->name, "not a finite number");
    }
    uint32_t i = 0;
    while (i < n->n_staged && n->staged_ids[i] != id) {
        ++i;
    }
    n->staged_ids[i] = id; /* i < SS_NODE_N_PARAMS: one slot per id */
    n->staged_values[i] = v;
    n->n_staged = (i == n->n_staged) ? n->n_staged + 1u : n->n_staged;
    return SS_PERR_NONE;
}

static void command(ss_node_can_t *n, const ss_can_cmd_t *c)
{
    ss_node_refusal_t why = {"", ""};
    ss_proto_error_t e = SS_PERR_NONE;
    float value = 0.0f;
    if (c->cmd == SS_CAN_CMD_HELLO) {
        ss_node_core_hello(&n->core, c->seq);
        n->have_drive_seq = 0;
        n->n_staged = 0u;
        /* index: model + 16 x variant (a float node answers as before) */
        const uint8_t id = (uint8_t)((uint32_t)n->core.cfg.friction_model + 16u * SS_NODE_VARIANT);
        reply(n, c->cmd, c->seq, SS_PERR_NONE, id, ss_node_model_dt_s(&n->core.cfg));
        return;
    }
    e = ss_node_core_admit(&n->core, c->seq, c->cmd == SS_CAN_CMD_STOP, &why);
    if (e != SS_PERR_NONE) {
        send_reason(n, c->cmd, c->seq, &why);
        reply(n, c->cmd, c->seq, e, c->index, 0.0f);
        return;
    }
    const ss_node_run_sink_t sink = sink_of(n);
    uint32_t steps = 0;
    switch (c->cmd) {
    case SS_CAN_CMD_GET_PARAM: e = ss_node_core_get_param(&n->core, c->index, &value, &why); break;
    case SS_CAN_CMD_SET_PARAM:
        if ((c->flags & 1u) != 0u) {
            e = stage_param(n, c->index, c->value, &why);
            value = c->value;
            break;
        }
        e = ss_node_core_set_param(&n->core, c->index, c->value, &why);
        if (e == SS_PERR_NONE) {
            (void)ss_node_core_get_param(&n->core, c->index, &value, &why);
        }
        break;
    case SS_CAN_CMD_APPLY_MODEL:
        e = ss_node_core_set_params(&n->core, n->staged_ids, n->staged_values, n->n_staged, &why);
        value = (float)n->n_staged;
        n->n_staged = 0u; /* applied or refused: the next model is staged afresh */
        break;
    case SS_CAN_CMD_RESET: e = ss_node_core_reset(&n->core, c->value, 0.0f, &why); break;
    case SS_CAN_CMD_SET_WAVE: e = set_wave(n, c->index, c->value, &why); break;
    case SS_CAN_CMD_LOAD_WAVE: e = ss_node_core_load_waveform(&n->core, &n->wave_pending, &why); break;
    case SS_CAN_CMD_RUN:
        if (!n->core.wave_loaded) {
            e = refuse(&why, SS_PERR_NO_WAVEFORM, "RUN needs LOAD_WAVE first", "");
        } else if (!count_from(c->value, &steps)) {
            e = refuse(&why, SS_PERR_OUT_OF_RANGE, "steps", "a whole number, at most 4e9");
        } else {
            e = ss_node_core_run(&n->core, c->seq, steps, c->index, c->flags, n->can->time_ns(n->can->ctx),
                                 &sink, &why);
            if (e == SS_PERR_NONE) {
                return; /* the reply comes when the run ends */
            }
        }
        break;
    case SS_CAN_CMD_STOP:
        if (ss_node_core_stop(&n->core, c->seq, &sink)) {
            return;
        }
        break;
    default: e = refuse(&why, SS_PERR_UNKNOWN_TYPE, "unknown command", ""); break;
    }
    if (e != SS_PERR_NONE) {
        send_reason(n, c->cmd, c->seq, &why);
    }
    reply(n, c->cmd, c->seq, e, c->index, (e == SS_PERR_NONE) ? value : 0.0f);
}

static void drive(ss_node_can_t *n, const ss_can_drive_t *d)
{
    if (n->have_drive_seq && d->seq == n->drive_seq) {
        reply(n, SS_CAN_CMD_DRIVE, d->seq, SS_PERR_DUPLICATE, 0, 0.0f);
        return;
    }
    if (n->core.running) {
        reply(n, SS_CAN_CMD_DRIVE, d->seq, SS_PERR_BUSY, 0, 0.0f);
        return;
    }
    if (!isfinite(d->drive_v)) {
        reply(n, SS_CAN_CMD_DRIVE, d->seq, SS_PERR_NON_FINITE, 0, 0.0f);
        return;
    }
    if (fabsf(d->drive_v) > SS_NODE_MAX_DRIVE_V) {
        const ss_node_refusal_t why = {"drive_v", "outside " SS_NODE_MAX_DRIVE_V_TEXT};
        send_reason(n, SS_CAN_CMD_DRIVE, d->seq, &why);
        reply(n, SS_CAN_CMD_DRIVE, d->seq, SS_PERR_OUT_OF_RANGE, 0, 0.0f);
        return;
    }
    n->have_drive_seq = 1;
    n->drive_seq = d->seq;
    (void)ss_node_core_drive(&n->core, d->drive_v);
    if (d->report) {
        send_state(n);
    }
}

/* ------------------------------------------------------------------ the node */

void ss_node_can_init(ss_node_can_t *n, const ss_port_can_t *can)
{
    n->can = can;
    n->wave_pending = ss_waveform_paper_f32();
    n->have_drive_seq = 0;
    n->n_staged = 0u;
    ss_node_core_init(&n->core);
}

int ss_node_can_poll(ss_node_can_t *n)
{
    for (int i = 0; i < SS_NODE_CAN_FRAMES_PER_POLL; ++i) {
        ss_can_frame_t f;
        const int32_t got = n->can->read(n->can->ctx, &f);
        if (got < 0) {
            ss_node_core_session_reset(&n->core);
            n->have_drive_seq = 0;
            return -1;
        }
        if (got == 0) {
            break;
        }
        ss_can_cmd_t c;
        ss_can_drive_t d;
        if (ss_can_unpack_cmd(&f, &c)) {
            command(n, &c);
        } else if (ss_can_unpack_drive(&f, &d)) {
            drive(n, &d);
        } /* other traffic on the bus is not for this node */
    }
    if (n->core.running) {
        const ss_node_run_sink_t sink = sink_of(n);
        ss_node_core_run_poll(&n->core, n->can->time_ns(n->can->ctx), &sink);
    }
    return 0;
}
