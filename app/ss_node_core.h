/* The node's core (docs/protocol.md): the parameters, the session's rules (duplicate, busy), and
 * what a request does to the model (set and get a parameter, reset, load a waveform, a lock-step
 * drive, a free run). It knows no link: it returns protocol errors with a reason, and a run hands
 * its rows and its end to the front end (ss_node_serial.h, ss_node_can.h) that formats them. */
#ifndef SS_NODE_CORE_H
#define SS_NODE_CORE_H

#include <stddef.h>
#include <stdint.h>

#include "ss_node_model.h"
#include "ss_proto.h" /* ss_proto_error_t, the request types a run ends with */

#define SS_NODE_VERSION "0.1.0"

/* Parameter ids: the position in ss_node_params.def. */
enum {
#define SS_NODE_PARAM(tag, name, def, min, max) SS_NODE_P_##tag,
#include "ss_node_params.def"
#undef SS_NODE_PARAM
    SS_NODE_P_COUNT
};
#define SS_NODE_N_PARAMS ((uint32_t)SS_NODE_P_COUNT)
#define SS_NODE_N_PARAMS_TEXT "29" /* in reason texts; a static assertion keeps it true */
typedef char ss_node_n_params_text_check[(SS_NODE_P_COUNT == 29) ? 1 : -1];

/* Steps a free run may take in one poll before the front end reads its link again. */
#define SS_NODE_MAX_STEPS_PER_POLL 2000u
/* RESET's drive0_v range in V, the library's for a drive (ss_actuator_init_f32, ss_waveform.h). */
#define SS_NODE_MAX_DRIVE_V 1e5f
#define SS_NODE_MAX_DRIVE_V_TEXT "[-1e5, 1e5] V"

/* One row of the parameter table. */
typedef struct {
    const char *name;
    float min, max;
} ss_node_param_def_t;

/* The user-facing parameters (stick-slip-dataset/1 names); the library config is built from them. */
typedef struct {
    float value[SS_NODE_N_PARAMS];
} ss_node_params_t;

/* Why a request was refused: what (a parameter or field, or the whole reason) and why (may be
 * ""); the serial link sends "what: why", the CAN link its own frames. */
typedef struct {
    const char *what, *why;
} ss_node_refusal_t;

typedef struct {
    ss_node_params_t params;
    ss_node_config_t cfg;
    ss_node_state_t st;
    ss_node_wave_t wave;
    ss_node_wave_state_t wst;
    uint8_t wave_loaded;
    uint8_t last_seq;  /* seq of the last accepted request */
    uint8_t have_last; /* a request was accepted in this session */
    /* free run */
    uint8_t running, paced, run_seq;
    uint32_t run_left, run_done, run_decimation;
    uint32_t run_misses; /* paced steps that ended after their deadline */
    uint64_t run_t0_ns;
    uint64_t run_dt_fs;   /* a step's slot of real time, fs (paced runs): paced x the model's step */
    uint64_t run_next_fs; /* when the next step is due, fs after run_t0_ns */
} ss_node_core_t;

/* Where a run's output goes: the front end's. row: the state after every decimation-th step;
 * end: the run is over (req SS_MSG_RUN: all steps done; SS_MSG_STOP: stopped), answer ref_seq,
 * with the paced run's deadline misses; now_ns: the port's clock, read after every paced step. */
typedef struct {
    void *ctx;
    void (*row)(void *ctx, const ss_node_core_t *core);
    void (*end)(void *ctx, uint8_t req, uint8_t ref_seq, uint32_t steps_done, uint32_t misses);
    uint64_t (*now_ns)(void *ctx);
} ss_node_run_sink_t;

/* Table I parameters (the library's), LS friction, the paper's drive pending, at rest at 0 V. */
void ss_node_core_init(ss_node_core_t *core);

/* The table's row for id, or NULL; the id of a name (len bytes, not terminated): 1, or 0. */
const ss_node_param_def_t *ss_node_core_param_def(uint32_t id);
int ss_node_core_param_id(const uint8_t *name, size_t len, uint32_t *id);

/* The session: HELLO starts one (it stops a run, without an answer for it, and is never a
 * duplicate); every other request passes ss_node_core_admit first: the same seq as the last
 * accepted request is refused (SS_PERR_DUPLICATE, not executed), and during a run only a STOP is
 * accepted (SS_PERR_BUSY). session_reset forgets the session (the peer went away). */
void ss_node_core_hello(ss_node_core_t *core, uint8_t seq);
ss_proto_error_t ss_node_core_admit(ss_node_core_t *core, uint8_t seq, int is_stop, ss_node_refusal_t *why);
void ss_node_core_session_reset(ss_node_core_t *core);

/* The requests; each returns SS_PERR_NONE or the refusal, and a refused request changes nothing. */
ss_proto_error_t ss_node_core_get_param(const ss_node_core_t *core, uint32_t id, float *value,
                                        ss_node_refusal_t *why);
/* Checks and applies one parameter; the model goes to rest where the next RUN starts: at the
 * loaded waveform's value at t = 0, the waveform restarted (0 V without a waveform). */
ss_proto_error_t ss_node_core_set_param(ss_node_core_t *core, uint32_t id, float v, ss_node_refusal_t *why);
/* SET_MODEL: n parameters (ids, values) at once, every one checked against the table and the whole
 * set by the library; all are applied or none (the refusal names the field). The model goes to
 * rest as after SET_PARAM. */
ss_proto_error_t ss_node_core_set_params(ss_node_core_t *core, const uint8_t *ids, const float *values,
                                         uint32_t n, ss_node_refusal_t *why);
/* The model at rest at drive0_v with the slider at x0_m (|x0_m| <= 1 m); the waveform restarts at t = 0. */
ss_proto_error_t ss_node_core_reset(ss_node_core_t *core, float drive0_v, float x0_m, ss_node_refusal_t *why);
/* Checks and loads a sawtooth; the model goes to rest at its start. A field out of range is
 * refused with the field's name as why->what ("frequency_hz") and its range as why->why. */
ss_proto_error_t ss_node_core_load_waveform(ss_node_core_t *core, const ss_waveform_config_f32_t *w,
                                            ss_node_refusal_t *why);
/* One lock-step step to drive_v (refused if not finite or outside SS_NODE_MAX_DRIVE_V). */
ss_proto_error_t ss_node_core_drive(ss_node_core_t *core, float drive_v);
ss_node_row_t ss_node_core_row(const ss_node_core_t *core);

/* A free run of steps steps of the loaded waveform, a row every decimation steps; now_ns is the
 * port's clock (ns). paced 0: as fast as it goes. paced p >= 1: step k (from 1) is due p k dt after the
 * start (p = 1 real time, p > 1 slowed p times), and its deadline is the next step's due time:
 * a step that ends later counts as a deadline miss (the port's clock, read after the step, past
 * the deadline: judged to the clock's resolution, 40 ns on the MPS2 port). A run of 0 steps ends
 * at once. */
ss_proto_error_t ss_node_core_run(ss_node_core_t *core, uint8_t seq, uint32_t steps, uint32_t decimation,
                                  uint8_t paced, uint64_t now_ns, const ss_node_run_sink_t *sink,
                                  ss_node_refusal_t *why);
/* A paced run's time until its next step is due, fs (0: due, or no paced run): what a front end
 * may spend on other work without holding that step up. */
uint64_t ss_node_core_idle_fs(const ss_node_core_t *core, uint64_t now_ns);
/* Advance a run in progress by what is due (at most SS_NODE_MAX_STEPS_PER_POLL steps). */
void ss_node_core_run_poll(ss_node_core_t *core, uint64_t now_ns, const ss_node_run_sink_t *sink);
/* STOP: ends a run in progress (sink->end, SS_MSG_STOP) and returns 1; 0 when there was none. */
int ss_node_core_stop(ss_node_core_t *core, uint8_t seq, const ss_node_run_sink_t *sink);

#endif /* SS_NODE_CORE_H */
