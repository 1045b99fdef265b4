/* The node's core (ss_node_core.h): one set of rules for every front end. */
#include "ss_node_core.h"

#include <math.h>
#include <string.h>

static const ss_node_param_def_t PARAMS[SS_NODE_N_PARAMS] = {
#define SS_NODE_PARAM(tag, name, def, min, max) {name, min, max},
#include "ss_node_params.def"
#undef SS_NODE_PARAM
};

#ifdef SS_MODEL_HEADER
/* A model compiled in (cmake -DSS_MODEL_HEADER=path, a header from `stickslip model export`):
 * its SS_MODEL_NODE_PARAMS are the node's defaults instead of Table I. */
#include SS_MODEL_HEADER
#ifndef SS_MODEL_NODE_PARAMS
#error "SS_MODEL_HEADER: no SS_MODEL_NODE_PARAMS (a GMS model: the node runs LS and LuGre)"
#endif
#if defined(SS_NODE_MODEL_Q) && !defined(SS_MODEL_CONFIG_Q)
#error "SS_MODEL_HEADER: the fixed-point node cannot run this model (an effect it does not model)"
#endif
#endif

/* Table I as the parameter table's defaults: from the library, never written out here. */
static void params_table1(ss_node_params_t *p)
{
    const ss_actuator_config_f32_t act = ss_actuator_config_table1_f32();
    const ss_friction_mu_f32_t mu = ss_friction_mu_table1_f32();
    uint32_t i = 0;
#define SS_NODE_PARAM(tag, name, def, min, max) p->value[i++] = (def);
#include "ss_node_params.def"
#undef SS_NODE_PARAM
}

static ss_actuator_config_f32_t config_from(const ss_node_params_t *p)
{
    ss_actuator_config_f32_t c = ss_actuator_config_table1_f32();
    const float *v = p->value;
    c.piezo_stiffness_n_per_m = v[SS_NODE_P_K];
    c.piezo_damping_kg_per_s = v[SS_NODE_P_C];
    c.rod_mass_kg = v[SS_NODE_P_MR];
    c.slider_mass_kg = v[SS_NODE_P_MC];
    c.piezo_gain_m_per_v = v[SS_NODE_P_GAIN];
    c.friction_model = (v[SS_NODE_P_MODEL] != 0.0f) ? SS_FRICTION_LUGRE : SS_FRICTION_LS;
    c.friction =
        ss_friction_config_from_mu_f32(v[SS_NODE_P_MUS], v[SS_NODE_P_MUD], v[SS_NODE_P_N], v[SS_NODE_P_VS],
                                       v[SS_NODE_P_S0], v[SS_NODE_P_S1], v[SS_NODE_P_S2]);
    c.friction.asymmetry = v[SS_NODE_P_ASYM];
    ss_effects_config_f32_t *e = &c.effects;
    e->hysteresis_alpha = v[SS_NODE_P_HALPHA];
    e->hysteresis_width_m = v[SS_NODE_P_HWIDTH];
    e->creep_ratio = v[SS_NODE_P_CRATIO];
    e->creep_tau_s = v[SS_NODE_P_CTAU];
    e->load_n = v[SS_NODE_P_LOAD];
    e->friction_gradient_per_m = v[SS_NODE_P_GRAD];
    e->slew_v_per_s = v[SS_NODE_P_SLEW];
    e->amp_bandwidth_hz = v[SS_NODE_P_AMPBW];
    e->thermal_coeff_per_j = v[SS_NODE_P_TCOEF];
    e->thermal_tau_s = v[SS_NODE_P_TTAU];
    e->base_mass_kg = v[SS_NODE_P_BMASS];
    e->base_freq_hz = v[SS_NODE_P_BFREQ];
    e->base_damping_ratio = v[SS_NODE_P_BDAMP];
    e->sensor_scale_error = v[SS_NODE_P_SSCALE];
    c.dt_s = v[SS_NODE_P_DT];
    return c;
}

const ss_node_param_def_t *ss_node_core_param_def(uint32_t id)
{
    return (id < SS_NODE_N_PARAMS) ? &PARAMS[id] : 0;
}

int ss_node_core_param_id(const uint8_t *name, size_t len, uint32_t *id)
{
    for (uint32_t i = 0; i < SS_NODE_N_PARAMS; ++i) {
        const char *s = PARAMS[i].name;
        size_t k = 0;
        while (k < len && s[k] != '\0' && (uint8_t)s[k] == name[k]) {
            ++k;
        }
        if (k == len && s[k] == '\0') {
            *id = i;
            return 1;
        }
    }
    return 0;
}

static ss_proto_error_t refuse(ss_node_refusal_t *why, ss_proto_error_t e, const char *what,
                               const char *because)
{
    why->what = what;
    why->why = because;
    return e;
}

static ss_proto_error_t from_status(ss_status_t st)
{
    return (st == SS_ERR_NONFINITE) ? SS_PERR_NON_FINITE : SS_PERR_OUT_OF_RANGE;
}

/* ------------------------------------------------------------------ the model at rest */

static void rest(ss_node_core_t *c, ss_node_drive_t drive0)
{
    ss_node_model_init(&c->cfg, &c->st, drive0);
    if (c->wave_loaded) {
        (void)ss_node_model_wave_init(&c->cfg, &c->wave, &c->wst);
    }
}

/* At rest where the next RUN starts: the loaded waveform at t = 0 (0 V without one). */
static void rest_at_wave_start(ss_node_core_t *c)
{
    if (c->wave_loaded) {
        (void)ss_node_model_wave_init(&c->cfg, &c->wave, &c->wst);
        ss_node_model_init(&c->cfg, &c->st, ss_node_model_wave_value(&c->wave, &c->wst));
    } else {
        ss_node_model_init(&c->cfg, &c->st, ss_node_model_drive_from_v(0.0f));
    }
}

void ss_node_core_session_reset(ss_node_core_t *c)
{
    c->have_last = 0;
    c->running = 0;
}

void ss_node_core_init(ss_node_core_t *c)
{
#ifdef SS_MODEL_NODE_PARAMS
    static const float model[SS_NODE_N_PARAMS] = SS_MODEL_NODE_PARAMS;
    memcpy(c->params.value, model, sizeof model);
    const ss_actuator_config_f32_t f = config_from(&c->params);
    const char *field = "";
    if (ss_node_model_config(&f, &c->cfg, &field) != SS_OK) {
        /* not reached: the export checked the model with this library, and the #errors above
         * keep a model the family cannot run out of the build */
        params_table1(&c->params);
        c->cfg = ss_node_model_default_config();
    }
#else
    params_table1(&c->params);
    c->cfg = ss_node_model_default_config(); /* what config_from(the defaults) gives */
#endif
    c->wave_loaded = 0;
    rest(c, ss_node_model_drive_from_v(0.0f));
    ss_node_core_session_reset(c);
}

/* ------------------------------------------------------------------ the session */

void ss_node_core_hello(ss_node_core_t *c, uint8_t seq)
{
    c->running = 0; /* a new session stops whatever the last one left running */
    c->have_last = 1;
    c->last_seq = seq;
}

ss_proto_error_t ss_node_core_admit(ss_node_core_t *c, uint8_t seq, int is_stop, ss_node_refusal_t *why)
{
    if (c->have_last && seq == c->last_seq) {
        return refuse(why, SS_PERR_DUPLICATE, "same seq as the last request, not executed again", "");
    }
    c->have_last = 1;
    c->last_seq = seq;
    if (c->running && !is_stop) {
        return refuse(why, SS_PERR_BUSY, "a run is in progress: STOP or HELLO first", "");
    }
    return SS_PERR_NONE;
}

/* ------------------------------------------------------------------ requests */

ss_proto_error_t ss_node_core_get_param(const ss_node_core_t *c, uint32_t id, float *value,
                                        ss_node_refusal_t *why)
{
    if (id >= SS_NODE_N_PARAMS) {
        return refuse(why, SS_PERR_UNKNOWN_PARAM, "no parameter with that id", "");
    }
    *value = c->params.value[id];
    return SS_PERR_NONE;
}

/* A parameter in its own range can still make the library's config invalid through a product
 * (Fs = mu_s N, Fc = mu_d N); say which rule, not only the library's field name. */
static const char *combined_reason(const char *field)
{
    if (strcmp(field, "friction.fs_n") == 0) {
        return "Fs = mu_s N: in [1e-6, 1e4] N";
    }
    if (strcmp(field, "friction.fc_n") == 0) {
        return "Fc = mu_d N: in [1e-6, 1e4] N, <= Fs";
    }
    return field;
}

/* One value against its row of the table (the library judges the whole set afterwards). */
static ss_proto_error_t check_param(uint32_t id, float v, ss_node_refusal_t *why)
{
    if (id >= SS_NODE_N_PARAMS) {
        return refuse(why, SS_PERR_UNKNOWN_PARAM, "no parameter with that id", "");
    }
    if (!isfinite(v)) {
        return refuse(why, SS_PERR_NON_FINITE, PARAMS[id].name, "not a finite number");
    }
    if (v < PARAMS[id].min || v > PARAMS[id].max || (id == SS_NODE_P_MODEL && v != 0.0f && v != 1.0f)) {
        return refuse(why, SS_PERR_OUT_OF_RANGE, PARAMS[id].name, "outside its range (PARAM_INFO)");
    }
    return SS_PERR_NONE;
}

/* The library's check of a whole parameter set; on success it is in force, the model at rest. */
static ss_proto_error_t apply_params(ss_node_core_t *c, const ss_node_params_t *next, const char *what,
                                     ss_node_refusal_t *why)
{
    const ss_actuator_config_f32_t f = config_from(next);
    ss_node_config_t cfg;
    const char *field = "";
    const ss_status_t st = ss_node_model_config(&f, &cfg, &field);
    if (st != SS_OK) {
        return refuse(why, from_status(st), what, combined_reason(field));
    }
    c->params = *next;
    c->cfg = cfg;
    rest_at_wave_start(c); /* a new parameter set starts a new experiment */
    return SS_PERR_NONE;
}

ss_proto_error_t ss_node_core_set_param(ss_node_core_t *c, uint32_t id, float v, ss_node_refusal_t *why)
{
    const ss_proto_error_t e = check_param(id, v, why);
    if (e != SS_PERR_NONE) {
        return e;
    }
    ss_node_params_t next = c->params;
    next.value[id] = v;
    return apply_params(c, &next, PARAMS[id].name, why);
}

ss_proto_error_t ss_node_core_set_params(ss_node_core_t *c, const uint8_t *ids, const float *values,
                                         uint32_t n, ss_node_refusal_t *why)
{
    if (n == 0u) {
        return refuse(why, SS_PERR_BAD_PAYLOAD, "SET_MODEL takes 1 or more id + f32 pairs", "");
    }
    ss_node_params_t next = c->params;
    for (uint32_t i = 0; i < n; ++i) {
        const ss_proto_error_t e = check_param(ids[i], values[i], why);
        if (e != SS_PERR_NONE) {
            return e;
        }
        next.value[ids[i]] = values[i];
    }
    /* a rule between fields is the set's, not one field's: the library's field names it */
    return apply_params(c, &next, "model", why);
}

ss_proto_error_t ss_node_core_reset(ss_node_core_t *c, float drive0_v, float x0_m, ss_node_refusal_t *why)
{
    if (!isfinite(drive0_v)) {
        return refuse(why, SS_PERR_NON_FINITE, "drive0_v", "not a finite number");
    }
    if (fabsf(drive0_v) > SS_NODE_MAX_DRIVE_V) {
        return refuse(why, SS_PERR_OUT_OF_RANGE, "drive0_v", "outside " SS_NODE_MAX_DRIVE_V_TEXT);
    }
    if (!isfinite(x0_m)) {
        return refuse(why, SS_PERR_NON_FINITE, "x0_m", "not a finite number");
    }
    if (fabsf(x0_m) > 1.0f) {
        return refuse(why, SS_PERR_OUT_OF_RANGE, "x0_m", "outside [-1, 1] m");
    }
    rest(c, ss_node_model_drive_from_v(drive0_v));
    ss_node_model_place_slider(&c->st, x0_m);
    return SS_PERR_NONE;
}

/* The sawtooth's fields as LOAD_WAVEFORM (and CAN SET_WAVE) name them, with the library's ranges
 * (ss_waveform.h), so that a refusal names the field at fault and what it accepts. */
static const char *const WAVE_FIELDS[5] = {"frequency_hz", "amplitude_v", "offset_v", "rise_fraction",
                                           "direction"};

static ss_proto_error_t check_wave(const ss_waveform_config_f32_t *w, ss_node_refusal_t *why)
{
    const float v[4] = {w->frequency_hz, w->amplitude_v, w->offset_v, w->rise_fraction};
    const char *const range[4] = {"outside [1e-6, 1e6] Hz", "outside " SS_NODE_MAX_DRIVE_V_TEXT,
                                  "outside " SS_NODE_MAX_DRIVE_V_TEXT, "outside (0, 1)"};
    const int ok[4] = {v[0] >= 1e-6f && v[0] <= 1e6f, fabsf(v[1]) <= SS_NODE_MAX_DRIVE_V,
                       fabsf(v[2]) <= SS_NODE_MAX_DRIVE_V, v[3] > 0.0f && v[3] < 1.0f};
    for (int i = 0; i < 4; ++i) {
        if (!isfinite(v[i])) {
            return refuse(why, SS_PERR_NON_FINITE, WAVE_FIELDS[i], "not a finite number");
        }
        if (!ok[i]) {
            return refuse(why, SS_PERR_OUT_OF_RANGE, WAVE_FIELDS[i], range[i]);
        }
    }
    if (w->direction != 1 && w->direction != -1) {
        return refuse(why, SS_PERR_OUT_OF_RANGE, WAVE_FIELDS[4], "+1 or -1");
    }
    return SS_PERR_NONE;
}

ss_proto_error_t ss_node_core_load_waveform(ss_node_core_t *c, const ss_waveform_config_f32_t *w,
                                            ss_node_refusal_t *why)
{
    const ss_proto_error_t e = check_wave(w, why);
    if (e != SS_PERR_NONE) {
        return e;
    }
    ss_node_wave_t wm;
    ss_node_wave_state_t ws;
    const char *reason = "";
    ss_status_t st = ss_node_model_wave_convert(w, &wm, &reason);
    if (st == SS_OK) {
        st = ss_node_model_wave_init(&c->cfg, &wm, &ws);
        reason = ss_status_str(st);
    }
    if (st != SS_OK) {
        return refuse(why, from_status(st), "waveform", reason);
    }
    c->wave = wm;
    c->wave_loaded = 1;
    rest_at_wave_start(c);
    return SS_PERR_NONE;
}

ss_proto_error_t ss_node_core_drive(ss_node_core_t *c, float drive_v)
{
    if (!isfinite(drive_v)) {
        return SS_PERR_NON_FINITE;
    }
    if (fabsf(drive_v) > SS_NODE_MAX_DRIVE_V) { /* 1e38 V made the state inf, then NaN for good */
        return SS_PERR_OUT_OF_RANGE;
    }
    ss_node_model_step(&c->cfg, &c->st, ss_node_model_drive_from_v(drive_v));
    return SS_PERR_NONE;
}

ss_node_row_t ss_node_core_row(const ss_node_core_t *c)
{
    return ss_node_model_row(&c->st);
}

/* ------------------------------------------------------------------ the free run */

static void end_run(ss_node_core_t *c, uint8_t req, uint8_t ref_seq, const ss_node_run_sink_t *sink)
{
    c->running = 0;
    sink->end(sink->ctx, req, ref_seq, c->run_done, c->run_misses);
}

ss_proto_error_t ss_node_core_run(ss_node_core_t *c, uint8_t seq, uint32_t steps, uint32_t decimation,
                                  uint8_t paced, uint64_t now_ns, const ss_node_run_sink_t *sink,
                                  ss_node_refusal_t *why)
{
    if (!c->wave_loaded) {
        return refuse(why, SS_PERR_NO_WAVEFORM, "RUN needs LOAD_WAVEFORM first", "");
    }
    if (decimation == 0u) {
        return refuse(why, SS_PERR_OUT_OF_RANGE, "decimation >= 1", "");
    }
    c->running = 1;
    c->run_seq = seq;
    c->run_left = steps;
    c->run_decimation = decimation;
    c->paced = paced;
    c->run_done = 0;
    c->run_misses = 0;
    c->run_t0_ns = now_ns;
    c->run_dt_fs = ss_node_model_dt_fs(&c->cfg) * (paced > 1u ? paced : 1u); /* <= 1e12 fs x 255 */
    c->run_next_fs = c->run_dt_fs;
    if (c->run_left == 0u) {
        end_run(c, SS_MSG_RUN, c->run_seq, sink);
    }
    return SS_PERR_NONE;
}

#define FS_PER_NS 1000000u

/* Time since the run's start in integer femtoseconds (a float deadline lost microseconds after
 * 2^24 us, about 16 s). 2^64 fs is 5.1 hours: later than that, everything is due. */
static uint64_t elapsed_fs(const ss_node_core_t *c, uint64_t now_ns)
{
    const uint64_t elapsed_ns = now_ns - c->run_t0_ns;
    return (elapsed_ns > UINT64_MAX / FS_PER_NS) ? UINT64_MAX : elapsed_ns * FS_PER_NS;
}

uint64_t ss_node_core_idle_fs(const ss_node_core_t *c, uint64_t now_ns)
{
    if (!c->running || !c->paced) {
        return 0;
    }
    const uint64_t t = elapsed_fs(c, now_ns);
    return (t < c->run_next_fs) ? c->run_next_fs - t : 0u;
}

void ss_node_core_run_poll(ss_node_core_t *c, uint64_t now_ns, const ss_node_run_sink_t *sink)
{
    if (!c->running) {
        return;
    }
    /* Paced: step k is due when k slots <= the time since the start. */
    const uint64_t due_fs = elapsed_fs(c, now_ns);
    uint32_t todo = (c->run_left < SS_NODE_MAX_STEPS_PER_POLL) ? c->run_left : SS_NODE_MAX_STEPS_PER_POLL;
    for (; todo > 0u && (!c->paced || c->run_next_fs <= due_fs); --todo) {
        ss_node_model_wave_step(&c->cfg, &c->st, &c->wave, &c->wst);
        c->run_done++;
        c->run_left--;
        c->run_next_fs =
            (c->run_next_fs > UINT64_MAX - c->run_dt_fs) ? UINT64_MAX : c->run_next_fs + c->run_dt_fs;
        /* the step's deadline is the next one's due time: ended later, it missed it */
        if (c->paced && elapsed_fs(c, sink->now_ns(sink->ctx)) > c->run_next_fs) {
            c->run_misses++;
        }
        if (c->run_done % c->run_decimation == 0u) {
            sink->row(sink->ctx, c);
        }
    }
    if (c->run_left == 0u) {
        end_run(c, SS_MSG_RUN, c->run_seq, sink);
    }
}

int ss_node_core_stop(ss_node_core_t *c, uint8_t seq, const ss_node_run_sink_t *sink)
{
    if (!c->running) {
        return 0;
    }
    end_run(c, SS_MSG_STOP, seq, sink);
    return 1;
}
