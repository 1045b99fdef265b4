#include "ss_can_msg.h"

#include <stddef.h>

#include "ss_proto.h" /* little-endian helpers */

static void frame(ss_can_frame_t *f, uint32_t id, uint8_t dlc)
{
    f->id = id;
    f->dlc = dlc;
    f->ext = 0;
    f->rtr = 0;
    for (int i = 0; i < 8; ++i) {
        f->data[i] = 0;
    }
}

static int is(const ss_can_frame_t *f, uint32_t id, uint8_t dlc)
{
    return f->id == id && !f->ext && !f->rtr && f->dlc == dlc;
}

void ss_can_pack_cmd(const ss_can_cmd_t *m, ss_can_frame_t *f)
{
    frame(f, SS_CAN_ID_CMD, 8);
    f->data[0] = m->cmd;
    f->data[1] = m->seq;
    f->data[2] = m->index;
    f->data[3] = m->flags;
    ss_put_f32(&f->data[4], m->value);
}

int ss_can_unpack_cmd(const ss_can_frame_t *f, ss_can_cmd_t *m)
{
    if (!is(f, SS_CAN_ID_CMD, 8)) {
        return 0;
    }
    m->cmd = f->data[0];
    m->seq = f->data[1];
    m->index = f->data[2];
    m->flags = f->data[3];
    m->value = ss_get_f32(&f->data[4]);
    return 1;
}

void ss_can_pack_reply(const ss_can_reply_t *m, ss_can_frame_t *f)
{
    frame(f, SS_CAN_ID_REPLY, 8);
    f->data[0] = m->cmd;
    f->data[1] = m->seq;
    f->data[2] = m->status;
    f->data[3] = m->index;
    ss_put_f32(&f->data[4], m->value);
}

int ss_can_unpack_reply(const ss_can_frame_t *f, ss_can_reply_t *m)
{
    if (!is(f, SS_CAN_ID_REPLY, 8)) {
        return 0;
    }
    m->cmd = f->data[0];
    m->seq = f->data[1];
    m->status = f->data[2];
    m->index = f->data[3];
    m->value = ss_get_f32(&f->data[4]);
    return 1;
}

void ss_can_pack_reason(const ss_can_reason_t *m, ss_can_frame_t *f)
{
    frame(f, SS_CAN_ID_REASON, 8);
    f->data[0] = m->cmd;
    f->data[1] = m->seq;
    for (size_t i = 0; i < SS_CAN_REASON_CHARS; ++i) {
        f->data[2 + i] = (uint8_t)m->text[i];
    }
}

int ss_can_unpack_reason(const ss_can_frame_t *f, ss_can_reason_t *m)
{
    if (!is(f, SS_CAN_ID_REASON, 8)) {
        return 0;
    }
    m->cmd = f->data[0];
    m->seq = f->data[1];
    for (size_t i = 0; i < SS_CAN_REASON_CHARS; ++i) {
        m->text[i] = (char)f->data[2 + i];
    }
    return 1;
}

void ss_can_pack_drive(const ss_can_drive_t *m, ss_can_frame_t *f)
{
    frame(f, SS_CAN_ID_DRIVE, 6);
    ss_put_f32(&f->data[0], m->drive_v);
    f->data[4] = m->seq;
    f->data[5] = (uint8_t)(m->report & 1u);
}

int ss_can_unpack_drive(const ss_can_frame_t *f, ss_can_drive_t *m)
{
    if (!is(f, SS_CAN_ID_DRIVE, 6)) {
        return 0;
    }
    m->drive_v = ss_get_f32(&f->data[0]);
    m->seq = f->data[4];
    m->report = (uint8_t)(f->data[5] & 1u);
    return 1;
}

void ss_can_pack_state(const ss_can_state_t *m, ss_can_frame_t f[3])
{
    frame(&f[0], SS_CAN_ID_STATE_A, 8);
    ss_put_u32(&f[0].data[0], m->step);
    ss_put_f32(&f[0].data[4], m->drive_v);
    frame(&f[1], SS_CAN_ID_STATE_B, 8);
    ss_put_f32(&f[1].data[0], m->x_rod_m);
    ss_put_f32(&f[1].data[4], m->friction_n);
    frame(&f[2], SS_CAN_ID_STATE_C, 8);
    ss_put_f32(&f[2].data[0], m->x_slider_hi_m);
    ss_put_f32(&f[2].data[4], m->x_slider_lo_m);
}
