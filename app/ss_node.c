#include "ss_node.h"

#include <math.h>

#ifdef SS_NODE_MODEL_Q
#include "ss_convert_q.h" /* float32 and SI at the node's edges */
#endif

/* Parameter table of docs/protocol.md: names (stick-slip-dataset/1), defaults (Table I) and the
 * ranges reported by PARAM_INFO. The library's own check has the last word on a SET_PARAM. */
typedef struct {
    const char *name;
    float def, min, max;
} param_def_t;

enum { P_K, P_C, P_MR, P_MC, P_GAIN, P_MUS, P_MUD, P_N, P_VS, P_S0, P_S1, P_S2, P_MODEL };

static const param_def_t PARAMS[SS_NODE_N_PARAMS] = {
    {"piezo_stiffness_n_per_m", 2.08e8f, 1.0f, 1e12f},
    {"piezo_damping_kg_per_s", 6.2f, 0.0f, 1e6f},
    {"rod_mass_kg", 1.1e-3f, 1e-9f, 1e3f},
    {"slider_mass_kg", 1.38e-2f, 1e-9f, 1e3f},
    {"piezo_gain_m_per_v", 4.4e-8f, -1e-3f, 1e-3f},
    {"mu_s", 0.36f, 0.0f, 10.0f},
    {"mu_d", 0.30f, 0.0f, 10.0f},
    {"normal_force_n", 10.0f, 0.0f, 1e4f},
    {"stribeck_velocity_m_per_s", 4.0e-4f, 1e-9f, 10.0f},
    {"sigma0_n_per_m", 1.0e7f, 1.0f, 1e12f},
    {"sigma1_ns_per_m", 80.0f, 0.0f, 1e6f},
    {"sigma2_ns_per_m", 8.0f, 0.0f, 1e6f},
    {"friction_model", 0.0f, 0.0f, 1.0f},
};

const char *ss_node_param_name(uint32_t id)
{
    return (id < SS_NODE_N_PARAMS) ? PARAMS[id].name : 0;
}

static ss_actuator_config_f32_t config_from(const ss_node_params_t *p)
{
    ss_actuator_config_f32_t c = ss_actuator_config_table1_f32();
    c.piezo_stiffness_n_per_m = p->value[P_K];
    c.piezo_damping_kg_per_s = p->value[P_C];
    c.rod_mass_kg = p->value[P_MR];
    c.slider_mass_kg = p->value[P_MC];
    c.piezo_gain_m_per_v = p->value[P_GAIN];
    c.friction_model = (p->value[P_MODEL] != 0.0f) ? SS_FRICTION_LUGRE : SS_FRICTION_LS;
    c.friction =
        ss_friction_config_from_mu_f32(p->value[P_MUS], p->value[P_MUD], p->value[P_N], p->value[P_VS],
                                       p->value[P_S0], p->value[P_S1], p->value[P_S2]);
    return c;
}

/* ------------------------------------------------------------------ sending */

static void send_frame(ss_node_t *n, uint8_t type, const uint8_t *payload, size_t len)
{
    const size_t w = ss_proto_build(type, n->tx_seq, payload, len, n->wire, sizeof n->wire);
    if (w > 0u) {
        n->tx_seq++;
        (void)n->link->write(n->link->ctx, n->wire, w);
    }
}

static void send_error(ss_node_t *n, ss_proto_error_t code, uint8_t ref_type, uint8_t ref_seq, const char *a,
                       const char *b)
{
    uint8_t p[3 + 96];
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

static void send_reply(ss_node_t *n, uint8_t req_type, const uint8_t *body, size_t len)
{
    uint8_t p[SS_PROTO_MAX_PAYLOAD];
    p[0] = n->pkt.seq;
    for (size_t i = 0; i < len && i + 1u < sizeof p; ++i) {
        p[i + 1u] = body[i];
    }
    send_frame(n, (uint8_t)(req_type | SS_MSG_REPLY), p, len + 1u);
}

/* ------------------------------------------------------------------ model */

/* The one place that knows which family the node runs (SS_NODE_MODEL_Q, ss_node.h): the rest of
 * the application speaks float32 volts and SI telemetry, as the protocol does. */

/* The state as a telemetry row sends it (docs/protocol.md): float32, SI. */
typedef struct {
    uint32_t steps;
    float drive_v, x_rod_m, x_slider_hi_m, x_slider_lo_m, force_n;
} si_row_t;

#ifdef SS_NODE_MODEL_Q
/* The q node may use float at its edges (protocol fields are float32, set_param converts through
 * the host converter ss_convert_q): the no-float check applies to the q library and the q-only
 * images, not to this application. Every conversion below gives the same bits on every target. */
typedef int32_t drive_t; /* V in Q16.16 */

/* float32 volts to Q16.16: floor(v 2^16 + 1/2) in double, saturated (ss_volts_to_q16, the
 * converter's rule for amplitude and offset). v 2^16 and the + 1/2 are exact in double for every
 * float32 v, and floor is exact, so the host and a soft-float target agree. */
static drive_t drive_from_v(float v)
{
    return ss_volts_to_q16((double)v);
}

static float model_dt_s(const ss_node_t *n)
{
    return (float)n->cfg.dt_q40 * 0x1p-40f;
}

/* The config a parameter set gives: through the host converter (double and libm), so a target
 * matches the host to the bit only where both round the same (docs/fixed-point.md). */
static ss_status_t model_config(const ss_node_params_t *p, ss_node_config_t *out, const char **why)
{
    const ss_actuator_config_f32_t f = config_from(p);
    return ss_actuator_config_to_q(&f, out, why);
}

static void model_init(ss_node_t *n, drive_t d)
{
    (void)ss_actuator_init_q(&n->cfg, &n->st, d);
}

static void model_step(ss_node_t *n, drive_t d)
{
    (void)ss_actuator_step_q(&n->cfg, &n->st, d);
}

static ss_status_t wave_convert(const ss_waveform_config_f32_t *w, ss_node_wave_t *out, const char **why)
{
    return ss_waveform_config_to_q(w, out, why);
}

static ss_status_t wave_init(const ss_node_t *n, const ss_node_wave_t *w, ss_node_wave_state_t *ws)
{
    return ss_waveform_init_q(w, n->cfg.dt_q40, ws);
}

static drive_t wave_value(const ss_node_wave_t *w, const ss_node_wave_state_t *ws)
{
    return ss_waveform_value_q(w, ws);
}

static void wave_advance(ss_node_wave_state_t *ws)
{
    ss_waveform_advance_q(ws);
}

/* Integer to float32 (round to nearest, ties to even: one rounding), then times a power of two
 * (exact): the same bits on the host's SSE and a target's soft float. The slider is split into
 * hi = float32(x) and lo = float32(x - hi), both times 2^-40, so hi + lo in double is x exactly
 * while |x| < 2^48 (256 m). */
static si_row_t model_row(const ss_node_t *n)
{
    const ss_actuator_state_q_t *st = &n->st;
    const float hi = (float)st->x_slider_q40;
    int64_t rest = 0;
    const float two62 = 4611686018427387904.0f; /* 2^62 */
    if (hi > -two62 && hi < two62) {            /* always, in practice; keeps the cast defined */
        rest = st->x_slider_q40 - (int64_t)hi;
    }
    const si_row_t r = {st->steps,     (float)st->drive_q16 * 0x1p-16f, (float)st->x_rod_q40 * 0x1p-40f,
                        hi * 0x1p-40f, (float)rest * 0x1p-40f,          (float)st->force_q24 * 0x1p-24f};
    return r;
}

static ss_node_config_t model_default_config(void)
{
    return ss_actuator_config_table1_q(); /* integer constants: the same on every target */
}
#else
typedef float drive_t; /* V */

static drive_t drive_from_v(float v)
{
    return v;
}

static float model_dt_s(const ss_node_t *n)
{
    return n->cfg.dt_s;
}

static ss_status_t model_config(const ss_node_params_t *p, ss_node_config_t *out, const char **why)
{
    *out = config_from(p);
    return ss_actuator_config_check_f32(out, why);
}

static void model_init(ss_node_t *n, drive_t d)
{
    (void)ss_actuator_init_f32(&n->cfg, &n->st, d);
}

static void model_step(ss_node_t *n, drive_t d)
{
    (void)ss_actuator_step_f32(&n->cfg, &n->st, d);
}

static ss_status_t wave_convert(const ss_waveform_config_f32_t *w, ss_node_wave_t *out, const char **why)
{
    (void)why;
    *out = *w;
    return SS_OK;
}

static ss_status_t wave_init(const ss_node_t *n, const ss_node_wave_t *w, ss_node_wave_state_t *ws)
{
    return ss_waveform_init_f32(w, n->cfg.dt_s, ws);
}

static drive_t wave_value(const ss_node_wave_t *w, const ss_node_wave_state_t *ws)
{
    return ss_waveform_value_f32(w, ws);
}

static void wave_advance(ss_node_wave_state_t *ws)
{
    ss_waveform_advance_f32(ws);
}

static si_row_t model_row(const ss_node_t *n)
{
    const ss_actuator_state_f32_t *st = &n->st;
    const si_row_t r = {st->steps,         st->drive_v,       st->x_rod_m,
                        st->x_slider.hi_m, st->x_slider.lo_m, st->force_n};
    return r;
}

static ss_node_config_t model_default_config(void)
{
    return ss_actuator_config_table1_f32();
}
#endif

static void put_row(uint8_t *b, const ss_node_t *n)
{
    const si_row_t r = model_row(n);
    ss_put_u32(b, r.steps);
    ss_put_f32(b + 4, r.drive_v);
    ss_put_f32(b + 8, r.x_rod_m);
    ss_put_f32(b + 12, r.x_slider_hi_m);
    ss_put_f32(b + 16, r.x_slider_lo_m);
    ss_put_f32(b + 20, r.force_n);
}

static void model_rest(ss_node_t *n, drive_t drive0)
{
    model_init(n, drive0);
    if (n->wave_loaded) {
        (void)wave_init(n, &n->wave, &n->wst);
    }
}

void ss_node_session_reset(ss_node_t *n)
{
    ss_proto_rx_init(&n->rx);
    n->have_last = 0;
    n->running = 0;
    n->n_rows = 0;
}

void ss_node_init(ss_node_t *n, const ss_port_link_t *link)
{
    n->link = link;
    n->can = 0;
    n->wave_pending = ss_waveform_sawtooth_f32(500.0f, 100.0f, 0.0f, 0.95f, 1, 20);
    n->have_drive_seq = 0;
    for (uint32_t i = 0; i < SS_NODE_N_PARAMS; ++i) {
        n->params.value[i] = PARAMS[i].def;
    }
    n->cfg = model_default_config(); /* what config_from(PARAMS defaults) gives */
    n->wave_loaded = 0;
    n->tx_seq = 0;
    model_rest(n, drive_from_v(0.0f));
    ss_node_session_reset(n);
}

/* ------------------------------------------------------------------ requests */

/* Check and apply one parameter; on refusal *why says what (the library's field name). */
static ss_proto_error_t set_param(ss_node_t *n, uint32_t id, float v, const char **why)
{
    if (!isfinite(v)) {
        *why = "not a finite number";
        return SS_PERR_NON_FINITE;
    }
    if (v < PARAMS[id].min || v > PARAMS[id].max || (id == P_MODEL && v != 0.0f && v != 1.0f)) {
        *why = "outside its range";
        return SS_PERR_OUT_OF_RANGE;
    }
    ss_node_params_t next = n->params;
    next.value[id] = v;
    ss_node_config_t cfg;
    const ss_status_t st = model_config(&next, &cfg, why);
    if (st != SS_OK) {
        return (st == SS_ERR_NONFINITE) ? SS_PERR_NON_FINITE : SS_PERR_OUT_OF_RANGE;
    }
    n->params = next;
    n->cfg = cfg;
    model_rest(n, n->wave_loaded ? wave_value(&n->wave, &n->wst) : drive_from_v(0.0f));
    return SS_PERR_NONE;
}

/* Check and load a sawtooth; the model goes to rest at its start. */
static ss_proto_error_t load_waveform(ss_node_t *n, const ss_waveform_config_f32_t *w, const char **why)
{
    ss_node_wave_t wm;
    ss_node_wave_state_t ws;
    ss_status_t st = wave_convert(w, &wm, why);
    if (st == SS_OK) {
        st = wave_init(n, &wm, &ws);
        *why = ss_status_str(st);
    }
    if (st != SS_OK) {
        return (st == SS_ERR_NONFINITE) ? SS_PERR_NON_FINITE : SS_PERR_OUT_OF_RANGE;
    }
    n->wave = wm;
    n->wave_loaded = 1;
    model_rest(n, wave_value(&n->wave, &ws));
    return SS_PERR_NONE;
}

static int find_param(const ss_proto_packet_t *pk, size_t name_at, uint32_t *id)
{
    const size_t n = pk->len - name_at;
    for (uint32_t i = 0; i < SS_NODE_N_PARAMS; ++i) {
        const char *s = PARAMS[i].name;
        size_t k = 0;
        while (k < n && s[k] != '\0' && (uint8_t)s[k] == pk->payload[name_at + k]) {
            ++k;
        }
        if (k == n && s[k] == '\0') {
            *id = i;
            return 1;
        }
    }
    return 0;
}

static void handle_hello(ss_node_t *n)
{
    uint8_t b[8 + sizeof SS_NODE_VERSION];
    b[0] = (uint8_t)SS_PROTO_VERSION;
    b[1] = (uint8_t)n->cfg.friction_model;
    b[2] = (uint8_t)SS_NODE_VARIANT;
    b[3] = (uint8_t)SS_NODE_N_PARAMS;
    ss_put_f32(&b[4], model_dt_s(n));
    size_t len = 8;
    for (const char *c = SS_NODE_VERSION; *c != '\0'; ++c) {
        b[len++] = (uint8_t)*c;
    }
    send_reply(n, SS_MSG_HELLO, b, len);
}

static void handle_param_info(ss_node_t *n)
{
    const ss_proto_packet_t *pk = &n->pkt;
    if (pk->len != 1u) {
        send_error(n, SS_PERR_BAD_PAYLOAD, pk->type, pk->seq, "PARAM_INFO takes 1 byte", "");
        return;
    }
    const uint32_t id = pk->payload[0];
    if (id >= SS_NODE_N_PARAMS) {
        send_error(n, SS_PERR_UNKNOWN_PARAM, pk->type, pk->seq, "no parameter with that id", "");
        return;
    }
    uint8_t b[13 + 32];
    b[0] = (uint8_t)id;
    ss_put_f32(&b[1], n->params.value[id]);
    ss_put_f32(&b[5], PARAMS[id].min);
    ss_put_f32(&b[9], PARAMS[id].max);
    size_t len = 13;
    for (const char *c = PARAMS[id].name; *c != '\0' && len < sizeof b; ++c) {
        b[len++] = (uint8_t)*c;
    }
    send_reply(n, SS_MSG_PARAM_INFO, b, len);
}

static void handle_get_param(ss_node_t *n)
{
    const ss_proto_packet_t *pk = &n->pkt;
    uint32_t id = 0;
    if (pk->len == 1u && pk->payload[0] != 0xFFu) {
        id = pk->payload[0];
    } else if (pk->len >= 2u && pk->payload[0] == 0xFFu) {
        if (!find_param(pk, 1, &id)) {
            send_error(n, SS_PERR_UNKNOWN_PARAM, pk->type, pk->seq, "no parameter with that name", "");
            return;
        }
    } else {
        send_error(n, SS_PERR_BAD_PAYLOAD, pk->type, pk->seq, "GET_PARAM takes an id or 0xFF + name", "");
        return;
    }
    if (id >= SS_NODE_N_PARAMS) {
        send_error(n, SS_PERR_UNKNOWN_PARAM, pk->type, pk->seq, "no parameter with that id", "");
        return;
    }
    uint8_t b[5];
    b[0] = (uint8_t)id;
    ss_put_f32(&b[1], n->params.value[id]);
    send_reply(n, SS_MSG_GET_PARAM, b, sizeof b);
}

static void handle_set_param(ss_node_t *n)
{
    const ss_proto_packet_t *pk = &n->pkt;
    uint32_t id = 0;
    float v;
    if (pk->len == 5u && pk->payload[0] != 0xFFu) {
        id = pk->payload[0];
        v = ss_get_f32(&pk->payload[1]);
    } else if (pk->len >= 6u && pk->payload[0] == 0xFFu) {
        v = ss_get_f32(&pk->payload[1]);
        if (!find_param(pk, 5, &id)) {
            send_error(n, SS_PERR_UNKNOWN_PARAM, pk->type, pk->seq, "no parameter with that name", "");
            return;
        }
    } else {
        send_error(n, SS_PERR_BAD_PAYLOAD, pk->type, pk->seq, "SET_PARAM takes id + f32 or 0xFF + f32 + name",
                   "");
        return;
    }
    if (id >= SS_NODE_N_PARAMS) {
        send_error(n, SS_PERR_UNKNOWN_PARAM, pk->type, pk->seq, "no parameter with that id", "");
        return;
    }
    const char *why = "";
    const ss_proto_error_t e = set_param(n, id, v, &why);
    if (e != SS_PERR_NONE) {
        send_error(n, e, pk->type, pk->seq, PARAMS[id].name, why);
        return;
    }
    uint8_t b[5];
    b[0] = (uint8_t)id;
    ss_put_f32(&b[1], v);
    send_reply(n, SS_MSG_SET_PARAM, b, sizeof b);
}

static void handle_reset(ss_node_t *n)
{
    const ss_proto_packet_t *pk = &n->pkt;
    if (pk->len != 4u) {
        send_error(n, SS_PERR_BAD_PAYLOAD, pk->type, pk->seq, "RESET takes f32 drive0_v", "");
        return;
    }
    const float v = ss_get_f32(pk->payload);
    if (!isfinite(v)) {
        send_error(n, SS_PERR_NON_FINITE, pk->type, pk->seq, "drive0_v", "not a finite number");
        return;
    }
    if (fabsf(v) > 1e5f) {
        send_error(n, SS_PERR_OUT_OF_RANGE, pk->type, pk->seq, "drive0_v", "outside [-1e5, 1e5] V");
        return;
    }
    model_rest(n, drive_from_v(v));
    send_reply(n, SS_MSG_RESET, 0, 0);
}

static void handle_load_waveform(ss_node_t *n)
{
    const ss_proto_packet_t *pk = &n->pkt;
    if (pk->len != 21u) {
        send_error(n, SS_PERR_BAD_PAYLOAD, pk->type, pk->seq, "LOAD_WAVEFORM takes 21 bytes", "");
        return;
    }
    const uint8_t *p = pk->payload;
    ss_waveform_config_f32_t w =
        ss_waveform_sawtooth_f32(ss_get_f32(p), ss_get_f32(p + 4), ss_get_f32(p + 8), ss_get_f32(p + 12),
                                 (int32_t)(int8_t)p[16], ss_get_u32(p + 17));
    const char *why = "";
    const ss_proto_error_t e = load_waveform(n, &w, &why);
    if (e != SS_PERR_NONE) {
        send_error(n, e, pk->type, pk->seq, "waveform", why);
        return;
    }
    send_reply(n, SS_MSG_LOAD_WAVEFORM, 0, 0);
}

static void handle_drive_block(ss_node_t *n)
{
    const ss_proto_packet_t *pk = &n->pkt;
    if (pk->len < 6u || (pk->len - 2u) % 4u != 0u || (pk->len - 2u) / 4u > 255u) {
        send_error(n, SS_PERR_BAD_PAYLOAD, pk->type, pk->seq, "DRIVE_BLOCK takes u16 + 1..255 f32", "");
        return;
    }
    const uint32_t dec = ss_get_u16(pk->payload);
    const uint32_t count = (pk->len - 2u) / 4u;
    if (dec == 0u || count / dec > SS_PROTO_MAX_ROWS) {
        send_error(n, SS_PERR_OUT_OF_RANGE, pk->type, pk->seq, "decimation",
                   "must be >= 1 and give <= 40 rows");
        return;
    }
    for (uint32_t i = 0; i < count; ++i) { /* check all before touching the state */
        if (!isfinite(ss_get_f32(&pk->payload[2u + 4u * i]))) {
            send_error(n, SS_PERR_NON_FINITE, pk->type, pk->seq, "drive sample", "not a finite number");
            return;
        }
    }
    uint8_t b[6 + SS_PROTO_MAX_ROWS * SS_PROTO_ROW_BYTES];
    uint32_t rows = 0;
    ss_put_u32(b, n->st.steps + dec);
    for (uint32_t i = 0; i < count; ++i) {
        model_step(n, drive_from_v(ss_get_f32(&pk->payload[2u + 4u * i])));
        if ((i + 1u) % dec == 0u) {
            put_row(&b[6u + (size_t)SS_PROTO_ROW_BYTES * rows++], n);
        }
    }
    ss_put_u16(&b[4], (uint16_t)rows);
    send_reply(n, SS_MSG_DRIVE_BLOCK, b, 6u + (size_t)SS_PROTO_ROW_BYTES * rows);
}

static uint64_t now_us(const ss_node_t *n)
{
    return (n->can != 0) ? n->can->time_us(n->can->ctx) : n->link->time_us(n->link->ctx);
}

static void can_send_state(ss_node_t *n)
{
    const si_row_t r = model_row(n);
    const ss_can_state_t m = {r.steps, r.drive_v, r.x_rod_m, r.force_n, r.x_slider_hi_m, r.x_slider_lo_m};
    ss_can_frame_t f[3];
    ss_can_pack_state(&m, f);
    for (int i = 0; i < 3; ++i) {
        (void)n->can->write(n->can->ctx, &f[i]);
    }
}

static void can_reply(ss_node_t *n, uint8_t cmd, uint8_t seq, ss_proto_error_t status, uint8_t index,
                      float value)
{
    const ss_can_reply_t m = {cmd, seq, (uint8_t)status, index, value};
    ss_can_frame_t f;
    ss_can_pack_reply(&m, &f);
    (void)n->can->write(n->can->ctx, &f);
}

static void flush_rows(ss_node_t *n)
{
    if (n->n_rows == 0u) {
        return;
    }
    uint8_t p[7 + SS_PROTO_MAX_ROWS * SS_PROTO_ROW_BYTES];
    p[0] = n->run_seq;
    ss_put_u32(&p[1], n->first_row_step);
    ss_put_u16(&p[5], (uint16_t)n->n_rows);
    for (size_t i = 0; i < (size_t)n->n_rows * SS_PROTO_ROW_BYTES; ++i) {
        p[7 + i] = n->rows[i];
    }
    send_frame(n, SS_MSG_TELEMETRY, p, 7u + (size_t)n->n_rows * SS_PROTO_ROW_BYTES);
    n->n_rows = 0;
}

static void end_run(ss_node_t *n, uint8_t reply_type, uint8_t ref_seq)
{
    n->running = 0;
    if (n->can != 0) {
        can_reply(n, (reply_type == SS_MSG_RUN) ? SS_CAN_CMD_RUN : SS_CAN_CMD_STOP, ref_seq, SS_PERR_NONE, 0,
                  (float)n->run_done);
        return;
    }
    flush_rows(n);
    uint8_t p[5];
    p[0] = ref_seq;
    ss_put_u32(&p[1], n->run_done);
    send_frame(n, (uint8_t)(reply_type | SS_MSG_REPLY), p, sizeof p);
}

static void handle_run(ss_node_t *n)
{
    const ss_proto_packet_t *pk = &n->pkt;
    if (pk->len != 7u) {
        send_error(n, SS_PERR_BAD_PAYLOAD, pk->type, pk->seq, "RUN takes u32 + u16 + u8", "");
        return;
    }
    if (!n->wave_loaded) {
        send_error(n, SS_PERR_NO_WAVEFORM, pk->type, pk->seq, "RUN needs LOAD_WAVEFORM first", "");
        return;
    }
    const uint32_t dec = ss_get_u16(&pk->payload[4]);
    if (dec == 0u || pk->payload[6] > 1u) {
        send_error(n, SS_PERR_OUT_OF_RANGE, pk->type, pk->seq, "decimation >= 1, paced 0 or 1", "");
        return;
    }
    n->running = 1;
    n->run_seq = pk->seq;
    n->run_left = ss_get_u32(pk->payload);
    n->run_decimation = dec;
    n->paced = pk->payload[6];
    n->run_done = 0;
    n->n_rows = 0;
    n->run_t0_us = now_us(n);
    if (n->run_left == 0u) {
        end_run(n, SS_MSG_RUN, n->run_seq);
    }
}

static void advance_run(ss_node_t *n)
{
    uint32_t todo = n->run_left;
    if (n->paced) {
        const uint64_t now = now_us(n);
        const uint64_t due = (uint64_t)((float)(now - n->run_t0_us) / (model_dt_s(n) * 1e6f));
        const uint64_t behind = (due > n->run_done) ? due - n->run_done : 0u;
        if (behind < todo) {
            todo = (uint32_t)behind;
        }
    }
    if (todo > SS_NODE_MAX_STEPS_PER_POLL) {
        todo = SS_NODE_MAX_STEPS_PER_POLL;
    }
    for (uint32_t i = 0; i < todo; ++i) {
        wave_advance(&n->wst);
        model_step(n, wave_value(&n->wave, &n->wst));
        n->run_done++;
        n->run_left--;
        if (n->run_done % n->run_decimation == 0u && n->can != 0) {
            can_send_state(n);
        } else if (n->run_done % n->run_decimation == 0u) {
            if (n->n_rows == 0u) {
                n->first_row_step = n->st.steps;
            }
            put_row(&n->rows[(size_t)SS_PROTO_ROW_BYTES * n->n_rows++], n);
            if (n->n_rows == SS_PROTO_MAX_ROWS) {
                flush_rows(n);
            }
        }
    }
    if (n->run_left == 0u) {
        end_run(n, SS_MSG_RUN, n->run_seq);
    }
}

static void handle_packet(ss_node_t *n)
{
    const ss_proto_packet_t *pk = &n->pkt;
    if (pk->type == SS_MSG_HELLO) {
        n->running = 0; /* a new session stops whatever the last one left running */
        n->n_rows = 0;
        n->have_last = 1;
        n->last_seq = pk->seq;
        handle_hello(n);
        return;
    }
    if (n->have_last && pk->seq == n->last_seq) {
        send_error(n, SS_PERR_DUPLICATE, pk->type, pk->seq,
                   "same seq as the last request, not executed again", "");
        return;
    }
    n->have_last = 1;
    n->last_seq = pk->seq;
    if (n->running && pk->type != SS_MSG_STOP) {
        send_error(n, SS_PERR_BUSY, pk->type, pk->seq, "a run is in progress: STOP or HELLO first", "");
        return;
    }
    switch (pk->type) {
    case SS_MSG_PARAM_INFO: handle_param_info(n); break;
    case SS_MSG_GET_PARAM: handle_get_param(n); break;
    case SS_MSG_SET_PARAM: handle_set_param(n); break;
    case SS_MSG_RESET: handle_reset(n); break;
    case SS_MSG_LOAD_WAVEFORM: handle_load_waveform(n); break;
    case SS_MSG_DRIVE_BLOCK: handle_drive_block(n); break;
    case SS_MSG_RUN: handle_run(n); break;
    case SS_MSG_STOP:
        if (n->running) {
            end_run(n, SS_MSG_STOP, pk->seq);
        } else {
            uint8_t b[4];
            ss_put_u32(b, 0u);
            send_reply(n, SS_MSG_STOP, b, sizeof b);
        }
        break;
    default: send_error(n, SS_PERR_UNKNOWN_TYPE, pk->type, pk->seq, "unknown request type", ""); break;
    }
}

int ss_node_poll(ss_node_t *n)
{
    uint8_t buf[256];
    const int32_t got = n->link->read(n->link->ctx, buf, sizeof buf);
    if (got < 0) {
        ss_node_session_reset(n);
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
    if (n->running) {
        advance_run(n);
    }
    return 0;
}

/* ------------------------------------------------------------------ CAN front end */

void ss_node_init_can(ss_node_t *n, const ss_port_can_t *can)
{
    ss_node_init(n, 0);
    n->can = can;
}

static ss_proto_error_t can_set_wave(ss_node_t *n, uint8_t field, float v)
{
    ss_waveform_config_f32_t *w = &n->wave_pending;
    if (!isfinite(v)) {
        return SS_PERR_NON_FINITE;
    }
    switch (field) {
    case 0: w->frequency_hz = v; break;
    case 1: w->amplitude_v = v; break;
    case 2: w->offset_v = v; break;
    case 3: w->rise_fraction = v; break;
    case 4:
        if (v != 1.0f && v != -1.0f) {
            return SS_PERR_OUT_OF_RANGE;
        }
        w->direction = (int32_t)v;
        break;
    case 5:
        if (v < 0.0f || v > 4e9f || v != (float)(uint32_t)v) {
            return SS_PERR_OUT_OF_RANGE;
        }
        w->cycles = (uint32_t)v;
        break;
    default: return SS_PERR_OUT_OF_RANGE;
    }
    return SS_PERR_NONE;
}

static void can_command(ss_node_t *n, const ss_can_cmd_t *c)
{
    const char *why = "";
    ss_proto_error_t e = SS_PERR_NONE;
    float value = 0.0f;
    uint8_t index = c->index;
    if (c->cmd == SS_CAN_CMD_HELLO) {
        n->running = 0;
        n->have_last = 1;
        n->last_seq = c->seq;
        n->have_drive_seq = 0;
        /* index: model + 16 x variant (a float node answers as before) */
        const uint8_t id = (uint8_t)((uint32_t)n->cfg.friction_model + 16u * SS_NODE_VARIANT);
        can_reply(n, c->cmd, c->seq, SS_PERR_NONE, id, model_dt_s(n));
        return;
    }
    if (n->have_last && c->seq == n->last_seq) {
        can_reply(n, c->cmd, c->seq, SS_PERR_DUPLICATE, index, 0.0f);
        return;
    }
    n->have_last = 1;
    n->last_seq = c->seq;
    if (n->running && c->cmd != SS_CAN_CMD_STOP) {
        can_reply(n, c->cmd, c->seq, SS_PERR_BUSY, index, 0.0f);
        return;
    }
    switch (c->cmd) {
    case SS_CAN_CMD_GET_PARAM:
    case SS_CAN_CMD_SET_PARAM:
        if (c->index >= SS_NODE_N_PARAMS) {
            e = SS_PERR_UNKNOWN_PARAM;
        } else if (c->cmd == SS_CAN_CMD_SET_PARAM) {
            e = set_param(n, c->index, c->value, &why);
        }
        value = (e == SS_PERR_NONE) ? n->params.value[c->index] : 0.0f;
        break;
    case SS_CAN_CMD_RESET:
        if (!isfinite(c->value)) {
            e = SS_PERR_NON_FINITE;
        } else if (fabsf(c->value) > 1e5f) {
            e = SS_PERR_OUT_OF_RANGE;
        } else {
            model_rest(n, drive_from_v(c->value));
        }
        break;
    case SS_CAN_CMD_SET_WAVE: e = can_set_wave(n, c->index, c->value); break;
    case SS_CAN_CMD_LOAD_WAVE: e = load_waveform(n, &n->wave_pending, &why); break;
    case SS_CAN_CMD_RUN:
        if (!n->wave_loaded) {
            e = SS_PERR_NO_WAVEFORM;
        } else if (c->index == 0u || c->flags > 1u || !isfinite(c->value) || c->value < 0.0f ||
                   c->value > 4e9f || c->value != (float)(uint32_t)c->value) {
            e = SS_PERR_OUT_OF_RANGE;
        } else {
            n->running = 1;
            n->run_seq = c->seq;
            n->run_left = (uint32_t)c->value;
            n->run_decimation = c->index;
            n->paced = c->flags;
            n->run_done = 0;
            n->run_t0_us = now_us(n);
            if (n->run_left == 0u) {
                end_run(n, SS_MSG_RUN, n->run_seq);
            }
            return; /* the reply comes when the run ends */
        }
        break;
    case SS_CAN_CMD_STOP:
        if (n->running) {
            end_run(n, SS_MSG_STOP, c->seq);
            return;
        }
        break;
    default: e = SS_PERR_UNKNOWN_TYPE; break;
    }
    (void)why;
    can_reply(n, c->cmd, c->seq, e, index, value);
}

static void can_drive(ss_node_t *n, const ss_can_drive_t *d)
{
    const uint8_t drive_cmd = 0x10; /* replies about drive frames carry this cmd */
    if (n->have_drive_seq && d->seq == n->drive_seq) {
        can_reply(n, drive_cmd, d->seq, SS_PERR_DUPLICATE, 0, 0.0f);
        return;
    }
    if (n->running) {
        can_reply(n, drive_cmd, d->seq, SS_PERR_BUSY, 0, 0.0f);
        return;
    }
    if (!isfinite(d->drive_v)) {
        can_reply(n, drive_cmd, d->seq, SS_PERR_NON_FINITE, 0, 0.0f);
        return;
    }
    n->have_drive_seq = 1;
    n->drive_seq = d->seq;
    model_step(n, drive_from_v(d->drive_v));
    if (d->report) {
        can_send_state(n);
    }
}

int ss_node_poll_can(ss_node_t *n)
{
    for (int i = 0; i < 64; ++i) {
        ss_can_frame_t f;
        const int32_t got = n->can->read(n->can->ctx, &f);
        if (got < 0) {
            n->running = 0;
            n->have_last = 0;
            n->have_drive_seq = 0;
            return -1;
        }
        if (got == 0) {
            break;
        }
        ss_can_cmd_t c;
        ss_can_drive_t d;
        if (ss_can_unpack_cmd(&f, &c)) {
            can_command(n, &c);
        } else if (ss_can_unpack_drive(&f, &d)) {
            can_drive(n, &d);
        } /* other traffic on the bus is not for this node */
    }
    if (n->running) {
        advance_run(n);
    }
    return 0;
}
