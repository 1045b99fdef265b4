/* The stage-model node: the actuator of lib/ served over the protocol of proto/ (docs/protocol.md).
 * Shared by the host node (host_sim/ on port/posix) and the firmware (fw/ on port/cortex_m). The
 * model family is chosen by the build: the float32 model by default, the fixed-point (_q) model
 * when compiled with SS_NODE_MODEL_Q (stickslip_app_q: stickslip_node_q, stickslip_fw_q.elf); the
 * protocol is the same. */
#ifndef SS_NODE_H
#define SS_NODE_H

#include <stdint.h>

#include "ss_actuator.h"
#include "ss_actuator_q.h"
#include "ss_can_msg.h"
#include "ss_port.h"
#include "ss_proto.h"

#define SS_NODE_VERSION "0.1.0"
#define SS_NODE_N_PARAMS 13u
/* Steps a free run may take in one poll before it reads the link again. */
#define SS_NODE_MAX_STEPS_PER_POLL 2000u

/* The model the node runs, fixed at build time; HELLO reports SS_NODE_VARIANT (0 float32, 1 fixed
 * point). The q node's conversions at its float32 edges are in docs/protocol.md. */
#ifdef SS_NODE_MODEL_Q
#define SS_NODE_VARIANT 1u
typedef ss_actuator_config_q_t ss_node_config_t;
typedef ss_actuator_state_q_t ss_node_state_t;
typedef ss_waveform_config_q_t ss_node_wave_t;
typedef ss_waveform_state_q_t ss_node_wave_state_t;
#else
#define SS_NODE_VARIANT 0u
typedef ss_actuator_config_f32_t ss_node_config_t;
typedef ss_actuator_state_f32_t ss_node_state_t;
typedef ss_waveform_config_f32_t ss_node_wave_t;
typedef ss_waveform_state_f32_t ss_node_wave_state_t;
#endif

/* The user-facing parameters (stick-slip-dataset/1 names); the library config is built from them. */
typedef struct {
    float value[SS_NODE_N_PARAMS];
} ss_node_params_t;

typedef struct {
    const ss_port_link_t *link;            /* serial front end, or NULL */
    const ss_port_can_t *can;              /* CAN front end, or NULL */
    ss_waveform_config_f32_t wave_pending; /* CAN: SET_WAVE fields until LOAD_WAVE */
    uint8_t drive_seq, have_drive_seq;     /* CAN: last lock-step drive frame */
    ss_node_params_t params;
    ss_node_config_t cfg;
    ss_node_state_t st;
    ss_node_wave_t wave;
    ss_node_wave_state_t wst;
    uint8_t wave_loaded;
    ss_proto_rx_t rx;
    ss_proto_packet_t pkt;
    uint8_t tx_seq;    /* the node's frame counter */
    uint8_t last_seq;  /* seq of the last accepted request */
    uint8_t have_last; /* a request was accepted in this session */
    /* free run */
    uint8_t running, paced, run_seq;
    uint32_t run_left, run_done, run_decimation;
    uint64_t run_t0_us;
    uint8_t rows[SS_PROTO_MAX_ROWS * SS_PROTO_ROW_BYTES];
    uint32_t n_rows, first_row_step;
    uint8_t wire[SS_PROTO_MAX_WIRE];
} ss_node_t;

/* Table I parameters, LS friction, at rest (the q node: ss_actuator_config_table1_q()). */
void ss_node_init(ss_node_t *node, const ss_port_link_t *link);

/* The same node on a CAN link (docs/protocol.md, CAN). */
void ss_node_init_can(ss_node_t *node, const ss_port_can_t *can);

/* Read what the link has, answer it, and advance a free run. Returns -1 when the link reported
 * the peer gone (the session is reset; the node stays usable), else 0. */
int ss_node_poll(ss_node_t *node);

/* As ss_node_poll, for a node made with ss_node_init_can. */
int ss_node_poll_can(ss_node_t *node);

/* Forget the session (decoder, sequence numbers, a run in progress); keep model and waveform. */
void ss_node_session_reset(ss_node_t *node);

/* Name of parameter id, or NULL. */
const char *ss_node_param_name(uint32_t id);

#endif /* SS_NODE_H */
