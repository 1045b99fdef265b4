/* The driver interface a port implements (as CANopenNode's CO_driver.h): a byte link, a CAN link
 * and a clock. The protocol (proto/) and the node application (app/) know nothing else of the
 * platform; a port (port/posix, port/cortex_m) fills these structs and knows no frame layout.
 * Callbacks and a context pointer, as littlefs's block device: no globals in the application. */
#ifndef SS_PORT_H
#define SS_PORT_H

#include <stddef.h>
#include <stdint.h>

#include "ss_can.h"

typedef struct {
    void *ctx;
    /* Non-blocking read of up to max bytes: the count read (0 if none), or -1 when the peer is
     * gone (the node then forgets the session and waits for the next). */
    int32_t (*read)(void *ctx, uint8_t *buf, size_t max);
    /* Write all n bytes as one piece (one TCP segment where it matters): n, or -1 on failure. */
    int32_t (*write)(void *ctx, const uint8_t *buf, size_t n);
    /* Monotonic nanoseconds (as fine as the platform's clock: a paced run's deadlines are judged
     * on it). */
    uint64_t (*time_ns)(void *ctx);
} ss_port_link_t;

/* A CAN link: SocketCAN, a CAN controller, or SLCAN over a byte link (ss_slcan_port.h). */
typedef struct {
    void *ctx;
    /* Non-blocking: 1 with *frame filled, 0 if none, -1 when the peer is gone. */
    int32_t (*read)(void *ctx, ss_can_frame_t *frame);
    /* Queue one frame: 1, or -1 on failure. */
    int32_t (*write)(void *ctx, const ss_can_frame_t *frame);
    uint64_t (*time_ns)(void *ctx); /* as the byte link's */
} ss_port_can_t;

#endif /* SS_PORT_H */
