/* Cortex-M port for QEMU's MPS2 boards: CMSDK UART0 as the node's byte link, SysTick as its clock
 * (25 MHz core clock), semihosting exit. */
#ifndef SS_PORT_CORTEX_M_H
#define SS_PORT_CORTEX_M_H

#include "ss_port.h"

#define SS_MPS2_CPU_HZ 25000000u

/* UART0 at 115200 baud (QEMU ignores the rate) and SysTick at 1 kHz; returns the link. */
const ss_port_link_t *ss_cortex_m_init(void);

/* End the emulation with an exit code (semihosting SYS_EXIT_EXTENDED). */
void ss_cortex_m_exit(int code);

#endif /* SS_PORT_CORTEX_M_H */
