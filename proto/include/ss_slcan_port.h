/* CAN over SLCAN (Lawicel) on any byte link (pty, TCP, UART): the adapter a port uses where no
 * CAN controller or kernel CAN is at hand. Answers the SLCAN commands python-can's slcan
 * interface sends (O, C, L, S0-S8, V, v, N, F, Z) and carries frames while the channel is open. */
#ifndef SS_SLCAN_PORT_H
#define SS_SLCAN_PORT_H

#include "ss_can.h"
#include "ss_port.h"

typedef struct {
    const ss_port_link_t *link;
    ss_slcan_rx_t rx;
    uint8_t buf[256];
    size_t n, at;
    uint8_t open;
    uint32_t bad_lines; /* malformed lines answered with BEL */
    ss_port_can_t can;
} ss_slcan_port_t;

/* Wrap a byte link; the CAN link is then &p->can. */
void ss_slcan_port_init(ss_slcan_port_t *p, const ss_port_link_t *link);

#endif /* SS_SLCAN_PORT_H */
