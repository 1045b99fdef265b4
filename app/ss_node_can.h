/* The node on a CAN link (docs/protocol.md, the CAN link; hil/stickslip/hil/stickslip.dbc): SS_CMD
 * and SS_DRIVE frames in, SS_REPLY and SS_STATE frames out, the rules and the model in the core
 * (ss_node_core.h). No serial framing buffers. */
#ifndef SS_NODE_CAN_H
#define SS_NODE_CAN_H

#include <stdint.h>

#include "ss_can_msg.h"
#include "ss_node_core.h"
#include "ss_port.h"

/* Frames read from the bus per poll before a free run advances. */
#define SS_NODE_CAN_FRAMES_PER_POLL 64
/* A count carried in a float32 value (SET_WAVE cycles, RUN steps): whole, and at most this. */
#define SS_NODE_CAN_MAX_COUNT 4e9f
/* A refusal's reason ("what: why", as the serial link's ERROR says it) in at most this many
 * SS_REASON frames of SS_CAN_REASON_CHARS characters, before the SS_REPLY that refuses. */
#define SS_NODE_CAN_MAX_REASON_FRAMES 8u

typedef struct {
    ss_node_core_t core;
    const ss_port_can_t *can;
    ss_waveform_config_f32_t wave_pending; /* SET_WAVE fields until LOAD_WAVE */
    uint8_t drive_seq, have_drive_seq;     /* last lock-step drive frame */
    /* SET_PARAM with flags bit 0 stages a value; APPLY_MODEL applies the set (SET_MODEL's rules) */
    uint8_t staged_ids[SS_NODE_N_PARAMS];
    float staged_values[SS_NODE_N_PARAMS];
    uint32_t n_staged;
} ss_node_can_t;

/* Table I parameters, LS friction, at rest; SET_WAVE starts from the paper's drive. */
void ss_node_can_init(ss_node_can_t *node, const ss_port_can_t *can);

/* Read what the bus has (at most SS_NODE_CAN_FRAMES_PER_POLL frames), answer it, and advance a
 * free run. Returns -1 when the link reported the peer gone (the session is reset; the node stays
 * usable), else 0. */
int ss_node_can_poll(ss_node_can_t *node);

#endif /* SS_NODE_CAN_H */
