#include "ss_port_cortex_m.h"

#include <stdint.h>

/* CMSDK APB UART0 */
#define UART0_BASE 0x40004000u
#define UART_DATA (*(volatile uint32_t *)(UART0_BASE + 0x00u))
#define UART_STATE (*(volatile uint32_t *)(UART0_BASE + 0x04u))
#define UART_CTRL (*(volatile uint32_t *)(UART0_BASE + 0x08u))
#define UART_BAUDDIV (*(volatile uint32_t *)(UART0_BASE + 0x10u))
#define UART_STATE_TXFULL 1u
#define UART_STATE_RXFULL 2u

/* SysTick */
#define SYST_CSR (*(volatile uint32_t *)0xE000E010u)
#define SYST_RVR (*(volatile uint32_t *)0xE000E014u)
#define SYST_CVR (*(volatile uint32_t *)0xE000E018u)
#define TICKS_PER_MS (SS_MPS2_CPU_HZ / 1000u)

/* The port's only mutable state: the millisecond count the SysTick interrupt advances. */
static volatile uint32_t ms_ticks;

void SysTick_Handler(void);
void SysTick_Handler(void)
{
    ms_ticks++;
}

static int32_t uart_read(void *ctx, uint8_t *buf, size_t max)
{
    (void)ctx;
    size_t n = 0;
    while (n < max && (UART_STATE & UART_STATE_RXFULL) != 0u) {
        buf[n++] = (uint8_t)UART_DATA;
    }
    return (int32_t)n;
}

static int32_t uart_write(void *ctx, const uint8_t *buf, size_t n)
{
    (void)ctx;
    for (size_t i = 0; i < n; ++i) {
        while ((UART_STATE & UART_STATE_TXFULL) != 0u) {
        }
        UART_DATA = buf[i];
    }
    return (int32_t)n;
}

/* The clock in ns to the SysTick's resolution (40 ns at 25 MHz: a paced run's deadlines are judged
 * to a few instructions, not to a microsecond); a whole number of ns a tick keeps it exact. */
#define NS_PER_TICK (1000000000u / SS_MPS2_CPU_HZ)
typedef char ss_ns_per_tick_is_whole[(NS_PER_TICK * SS_MPS2_CPU_HZ == 1000000000u) ? 1 : -1];

static uint64_t systick_ns(void *ctx)
{
    (void)ctx;
    uint32_t ms;
    uint32_t cvr;
    do { /* a consistent pair across a tick */
        ms = ms_ticks;
        cvr = SYST_CVR;
    } while (ms != ms_ticks);
    return (uint64_t)ms * 1000000u + (uint64_t)((TICKS_PER_MS - 1u - cvr) * NS_PER_TICK);
}

static const ss_port_link_t LINK = {0, uart_read, uart_write, systick_ns};

const ss_port_link_t *ss_cortex_m_init(void)
{
    UART_BAUDDIV = SS_MPS2_CPU_HZ / 115200u;
    UART_CTRL = 3u; /* TX and RX enabled */
    SYST_RVR = TICKS_PER_MS - 1u;
    SYST_CVR = 0u;
    SYST_CSR = 7u; /* core clock, interrupt, enabled */
    return &LINK;
}

void ss_cortex_m_exit(int code)
{
    /* SYS_EXIT_EXTENDED with ADP_Stopped_ApplicationExit and the code */
    volatile uint32_t block[2] = {0x20026u, (uint32_t)code};
    register uint32_t r0 __asm("r0") = 0x20u;
    register volatile uint32_t *r1 __asm("r1") = block;
    __asm volatile("bkpt 0xab" : : "r"(r0), "r"(r1) : "memory");
}
