/* The node's CAN messages, packed and unpacked as hil/stickslip/hil/stickslip.dbc defines them
 * (the DBC is the contract; tests/c/test_can.c checks these against cantools' encoding, frame by
 * frame, from tests/vectors/can_frames.csv). All signals little-endian; floats IEEE-754. */
#ifndef SS_CAN_MSG_H
#define SS_CAN_MSG_H

#include <stdint.h>

#include "ss_can.h"

#define SS_CAN_ID_CMD 0x100u
#define SS_CAN_ID_REPLY 0x101u
#define SS_CAN_ID_REASON 0x102u
#define SS_CAN_ID_DRIVE 0x110u
#define SS_CAN_ID_STATE_A 0x120u
#define SS_CAN_ID_STATE_B 0x121u
#define SS_CAN_ID_STATE_C 0x122u

enum {
    SS_CAN_CMD_HELLO = 1,
    SS_CAN_CMD_GET_PARAM = 2,
    SS_CAN_CMD_SET_PARAM = 3,
    SS_CAN_CMD_RESET = 4,
    SS_CAN_CMD_SET_WAVE = 5,
    SS_CAN_CMD_LOAD_WAVE = 6,
    SS_CAN_CMD_RUN = 7,
    SS_CAN_CMD_STOP = 8,
    SS_CAN_CMD_APPLY_MODEL = 9, /* apply the parameters staged by SET_PARAM with flags bit 0 */
    SS_CAN_CMD_DRIVE = 0x10     /* not a command: the cmd of an SS_REPLY refusing an SS_DRIVE frame */
};

typedef struct {
    uint8_t cmd, seq, index, flags;
    float value;
} ss_can_cmd_t;

typedef struct {
    uint8_t cmd, seq, status, index;
    float value;
} ss_can_reply_t;

/* Why a command was refused: 6 bytes of ASCII text a frame, NUL-padded. */
#define SS_CAN_REASON_CHARS 6u
typedef struct {
    uint8_t cmd, seq;
    char text[SS_CAN_REASON_CHARS];
} ss_can_reason_t;

typedef struct {
    float drive_v;
    uint8_t seq, report;
} ss_can_drive_t;

typedef struct {
    uint32_t step;
    float drive_v, x_rod_m, friction_n, x_slider_hi_m, x_slider_lo_m;
} ss_can_state_t;

void ss_can_pack_cmd(const ss_can_cmd_t *m, ss_can_frame_t *f);
int ss_can_unpack_cmd(const ss_can_frame_t *f, ss_can_cmd_t *m); /* 0 if not SS_CMD of 8 bytes */
void ss_can_pack_reply(const ss_can_reply_t *m, ss_can_frame_t *f);
int ss_can_unpack_reply(const ss_can_frame_t *f, ss_can_reply_t *m);
void ss_can_pack_reason(const ss_can_reason_t *m, ss_can_frame_t *f);
int ss_can_unpack_reason(const ss_can_frame_t *f, ss_can_reason_t *m);
void ss_can_pack_drive(const ss_can_drive_t *m, ss_can_frame_t *f);
int ss_can_unpack_drive(const ss_can_frame_t *f, ss_can_drive_t *m);
/* The three state frames A, B, C. */
void ss_can_pack_state(const ss_can_state_t *m, ss_can_frame_t f[3]);

#endif /* SS_CAN_MSG_H */
