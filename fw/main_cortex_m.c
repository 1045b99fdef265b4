/* Firmware: the stage-model node on a serial link (app/, the same application as the host's
 * stickslip_node) on the Cortex-M port (port/cortex_m); linked with stickslip_app_q
 * (SS_NODE_MODEL_Q) it is stickslip_fw_q.elf, the fixed-point node (as stickslip_node_q). */
#include "ss_node_serial.h"
#include "ss_port_cortex_m.h"

static ss_node_serial_t node; /* the firmware's one instance, in .bss */

int main(void)
{
    const ss_port_link_t *link = ss_cortex_m_init();
    ss_node_serial_init(&node, link);
    /* a banner for people, ended by a frame delimiter so a framing receiver drops it */
#ifdef SS_NODE_MODEL_Q
    const char hello[] = "stickslip firmware " SS_NODE_VERSION " (fixed-point model)\n";
#else
    const char hello[] = "stickslip firmware " SS_NODE_VERSION "\n";
#endif
    (void)link->write(link->ctx, (const uint8_t *)hello, sizeof hello); /* with its NUL */
    for (;;) {
        (void)ss_node_serial_poll(&node);
    }
}
