/* POSIX port: CAN over Linux SocketCAN (vcan0, can0). */
#ifndef SS_PORT_SOCKETCAN_H
#define SS_PORT_SOCKETCAN_H

#include "ss_port.h"

typedef struct {
    int fd;
    ss_port_can_t can;
} ss_socketcan_t;

/* Bind a raw CAN socket to the interface; 0 on success, -1 (errno) when there is none. */
int ss_socketcan_open(ss_socketcan_t *s, const char *ifname);

#endif /* SS_PORT_SOCKETCAN_H */
