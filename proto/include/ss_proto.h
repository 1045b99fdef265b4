/* The node's serial protocol (docs/protocol.md): COBS framing with a 0x00 delimiter, a 6-byte
 * header/trailer (type, seq, len, CRC-16/CCITT-FALSE) and little-endian payloads. Pure functions
 * and a byte-at-a-time receiver; no platform code, no allocation. */
#ifndef SS_PROTO_H
#define SS_PROTO_H

#include <stddef.h>
#include <stdint.h>

#define SS_PROTO_VERSION 1u
#define SS_PROTO_MAX_PAYLOAD 1024u
#define SS_PROTO_OVERHEAD 6u                                           /* type, seq, len(2), crc(2) */
#define SS_PROTO_MAX_PACKET (SS_PROTO_MAX_PAYLOAD + SS_PROTO_OVERHEAD) /* 1030 */
/* COBS adds one byte per 254 and a leading code byte; plus the delimiter: 1036 */
#define SS_PROTO_MAX_WIRE (SS_PROTO_MAX_PACKET + SS_PROTO_MAX_PACKET / 254u + 2u)

typedef enum {
    SS_MSG_HELLO = 0x01,
    SS_MSG_PARAM_INFO = 0x02,
    SS_MSG_GET_PARAM = 0x03,
    SS_MSG_SET_PARAM = 0x04,
    SS_MSG_RESET = 0x05,
    SS_MSG_LOAD_WAVEFORM = 0x06,
    SS_MSG_DRIVE_BLOCK = 0x07,
    SS_MSG_RUN = 0x08,
    SS_MSG_STOP = 0x09,
    SS_MSG_SET_MODEL = 0x0A,
    SS_MSG_TELEMETRY = 0x10,
    SS_MSG_ERROR = 0x7F,
    SS_MSG_REPLY = 0x80 /* or-ed into a request's type */
} ss_msg_type_t;

typedef enum {
    SS_PERR_NONE = 0,
    SS_PERR_BAD_CRC = 1,
    SS_PERR_BAD_LENGTH = 2,
    SS_PERR_UNKNOWN_TYPE = 3,
    SS_PERR_BAD_PAYLOAD = 4,
    SS_PERR_OUT_OF_RANGE = 5,
    SS_PERR_NON_FINITE = 6,
    SS_PERR_DUPLICATE = 7,
    SS_PERR_BUSY = 8,
    SS_PERR_BAD_FRAMING = 9,
    SS_PERR_OVERSIZE = 10,
    SS_PERR_NO_WAVEFORM = 11,
    SS_PERR_UNKNOWN_PARAM = 12
} ss_proto_error_t;

#define SS_PROTO_ROW_BYTES 24u
#define SS_PROTO_MAX_ROWS 40 /* unsuffixed: ss_node_serial.c quotes it in a reason text */

/* Short name of an error code ("bad_crc", ...), never NULL. */
const char *ss_proto_error_name(ss_proto_error_t code);

uint16_t ss_crc16_ccitt(const uint8_t *data, size_t n);
/* The CRC after one more byte (start from 0xFFFF). */
uint16_t ss_crc16_ccitt_update(uint16_t crc, uint8_t byte);

/* COBS-encode n bytes into dst (no delimiter); returns the encoded size, 0 if cap is too small. */
size_t ss_cobs_encode(const uint8_t *src, size_t n, uint8_t *dst, size_t cap);

/* Decode n COBS bytes (no delimiter) into dst; returns the decoded size, or -1 for invalid COBS
 * or a result longer than cap. */
int32_t ss_cobs_decode(const uint8_t *src, size_t n, uint8_t *dst, size_t cap);

/* Build a wire frame (COBS packet + 0x00) into wire; returns its size, 0 if it does not fit or
 * len exceeds SS_PROTO_MAX_PAYLOAD. */
size_t ss_proto_build(uint8_t type, uint8_t seq, const uint8_t *payload, size_t len, uint8_t *wire,
                      size_t cap);

/* Longest reason an ERROR frame built by ss_proto_build_error carries (longer ones are cut). */
#define SS_PROTO_MAX_REASON 96u

/* Build an ERROR frame (ref_seq, code, ref_type, ASCII reason without its NUL) with the sender's
 * counter seq into wire; returns its size, 0 if it does not fit. */
size_t ss_proto_build_error(uint8_t seq, uint8_t ref_seq, ss_proto_error_t code, uint8_t ref_type,
                            const char *reason, uint8_t *wire, size_t cap);

/* A decoded, checked packet. */
typedef struct {
    uint8_t type;
    uint8_t seq;
    uint16_t len;
    uint8_t payload[SS_PROTO_MAX_PAYLOAD];
} ss_proto_packet_t;

/* Byte-at-a-time receiver. */
typedef struct {
    uint8_t buf[SS_PROTO_MAX_WIRE];
    size_t n;
    uint8_t overflow;            /* discarding up to the next delimiter */
    uint8_t last_type, last_seq; /* of the last rejected frame, when its header could be read */
} ss_proto_rx_t;

void ss_proto_rx_init(ss_proto_rx_t *rx);

/* Feed one byte. Returns SS_PERR_NONE while a frame is incomplete (with *complete = 0), or on a
 * good frame (with *complete = 1 and pkt filled); a rejection code when a frame ended bad (then
 * rx->last_type/last_seq say what it claimed to be, 0 when unreadable). */
ss_proto_error_t ss_proto_rx_push(ss_proto_rx_t *rx, uint8_t byte, ss_proto_packet_t *pkt, int *complete);

/* Little-endian field access. */
void ss_put_u16(uint8_t *p, uint16_t v);
void ss_put_u32(uint8_t *p, uint32_t v);
void ss_put_f32(uint8_t *p, float v);
uint16_t ss_get_u16(const uint8_t *p);
uint32_t ss_get_u32(const uint8_t *p);
float ss_get_f32(const uint8_t *p);

#endif /* SS_PROTO_H */
