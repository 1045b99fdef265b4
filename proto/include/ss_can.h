/* Classic CAN frames and the SLCAN (Lawicel) serial line protocol that carries them over a
 * UART, a pseudo-terminal or TCP: "t<id:3 hex><dlc><data hex>\r", "T<id:8 hex>...", commands
 * such as "O\r" (open) and "C\r" (close). Portable: a byte-at-a-time decoder and a formatter. */
#ifndef SS_CAN_H
#define SS_CAN_H

#include <stddef.h>
#include <stdint.h>

typedef struct {
    uint32_t id; /* 11-bit, or 29-bit when ext */
    uint8_t dlc; /* 0..8 */
    uint8_t ext; /* extended (29-bit) identifier */
    uint8_t rtr; /* remote frame */
    uint8_t data[8];
} ss_can_frame_t;

#define SS_SLCAN_MAX_LINE 30u /* "T" + 8 + 1 + 16 + "\r", with room */

typedef enum {
    SS_SLCAN_NONE = 0,    /* line not complete */
    SS_SLCAN_FRAME = 1,   /* a frame line: *frame filled */
    SS_SLCAN_COMMAND = 2, /* a command line (O, C, S6, V, ...): *cmd holds it, NUL-terminated */
    SS_SLCAN_BAD = 3      /* a malformed line (bad hex, wrong length, too long): answer "\a" */
} ss_slcan_event_t;

typedef struct {
    char line[SS_SLCAN_MAX_LINE + 1u];
    size_t n;
    uint8_t overflow;
} ss_slcan_rx_t;

void ss_slcan_rx_init(ss_slcan_rx_t *rx);

/* Feed one byte; a line ends at '\r' (or '\n'). cmd must hold SS_SLCAN_MAX_LINE + 1 chars. */
ss_slcan_event_t ss_slcan_push(ss_slcan_rx_t *rx, uint8_t byte, ss_can_frame_t *frame, char *cmd);

/* Format a frame as an SLCAN line with its '\r'; returns its length, 0 if it does not fit or the
 * frame is invalid (dlc > 8, id out of range). */
size_t ss_slcan_format(const ss_can_frame_t *frame, char *out, size_t cap);

#endif /* SS_CAN_H */
