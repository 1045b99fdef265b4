/* A frame built a few bytes at a time: the same bytes as ss_proto_build, so that a paced run's
 * telemetry can be encoded and handed to the link in the time between two steps instead of in one
 * piece that holds a step up (app/ss_node_serial.c). The frame is written into the caller's
 * buffer; a byte becomes ready to send once COBS no longer needs to go back for it (the open
 * group's code byte is written when the group closes: up to 254 bytes later). */
#ifndef SS_PROTO_STREAM_H
#define SS_PROTO_STREAM_H

#include <stddef.h>
#include <stdint.h>

typedef struct {
    uint8_t *wire;    /* the caller's, at least SS_PROTO_MAX_WIRE bytes */
    size_t out;       /* bytes written (the open group's code byte at code_at still to come) */
    size_t code_at;   /* where the open COBS group's code byte goes */
    size_t sent;      /* bytes handed on (ss_proto_stream_sent) */
    uint16_t left;    /* payload bytes still to put */
    uint16_t crc;     /* CRC-16/CCITT-FALSE of the header and the payload so far */
    uint8_t code;     /* the open group's length + 1 */
    uint8_t complete; /* CRC and delimiter written: every byte is final */
} ss_proto_stream_t;

/* Start a frame of len payload bytes (len <= SS_PROTO_MAX_PAYLOAD: else 0 and nothing started)
 * in wire; returns 1. */
int ss_proto_stream_begin(ss_proto_stream_t *s, uint8_t *wire, uint8_t type, uint8_t seq, uint16_t len);

/* Put the next n payload bytes (at most what is left: the rest is ignored); after the last, the
 * CRC and the delimiter follow at once. */
void ss_proto_stream_put(ss_proto_stream_t *s, const uint8_t *p, size_t n);

/* The bytes that are final and not yet sent: their count, *p at the first. */
size_t ss_proto_stream_ready(const ss_proto_stream_t *s, const uint8_t **p);

/* n of the ready bytes were sent. */
void ss_proto_stream_sent(ss_proto_stream_t *s, size_t n);

/* Every byte of the frame written and sent. */
int ss_proto_stream_done(const ss_proto_stream_t *s);

#endif /* SS_PROTO_STREAM_H */
