/* Firmware for the fixed-point core: plays the paper's drive (Table I, 500 Hz sawtooth, 100 V, rise
 * 0.95) in a fixed-step loop, one ss_actuator_step_q per tick as an MCU's control interrupt would,
 * and sends the slider's staircase over UART0 as text lines; then exits (semihosting) with 0, or 1
 * on a model error. tests/python/test_firmware_q.py checks the lines bit for bit against the host.
 * No float anywhere in the image (the build checks its symbols). */
#include <stddef.h>
#include <stdint.h>

#include "ss_actuator_q.h"
#include "ss_fmt.h"
#include "ss_port_cortex_m.h"

#define Q_FW_CYCLES 6u
#define Q_FW_STEPS_PER_CYCLE 2000u /* the paper's 500 Hz at dt = 1 us */
#define Q_FW_EVERY 100u            /* a line every 100 steps: 20 per cycle, 121 lines in all */
#define Q_FW_LINE 192u             /* longest line (the header) with room to spare */

static void send(const ss_port_link_t *link, const char *line, size_t len)
{
    (void)link->write(link->ctx, (const uint8_t *)line, len);
}

static void send_row(const ss_port_link_t *link, uint32_t step, int64_t x_slider_q40)
{
    char line[Q_FW_LINE];
    size_t n = 0;
    ss_fmt_put_i64(line, &n, step);
    ss_fmt_put_str(line, &n, ",");
    ss_fmt_put_i64(line, &n, x_slider_q40);
    ss_fmt_put_str(line, &n, "\n");
    send(link, line, n);
}

/* "name=value " into line */
static void put_field(char *line, size_t *n, const char *name, int64_t v)
{
    ss_fmt_put_str(line, n, " ");
    ss_fmt_put_str(line, n, name);
    ss_fmt_put_str(line, n, "=");
    ss_fmt_put_i64(line, n, v);
}

int main(void)
{
    const ss_port_link_t *link = ss_cortex_m_init();
    const ss_actuator_config_q_t cfg = ss_actuator_config_table1_q();
    ss_waveform_config_q_t w = ss_waveform_paper_q(); /* the paper's drive, in integer constants */
    w.cycles = Q_FW_CYCLES;
    const uint32_t n_steps = Q_FW_CYCLES * Q_FW_STEPS_PER_CYCLE;
    ss_waveform_state_q_t ws;
    static ss_actuator_state_q_t st; /* 328 bytes: in .bss, not on the stack */

    /* the run's parameters first, so the receiver can check it plays the same drive */
    char line[Q_FW_LINE];
    size_t n = 0;
    ss_fmt_put_str(line, &n, "# stickslip q staircase:");
    put_field(line, &n, "dt_q40", cfg.dt_q40);
    put_field(line, &n, "frequency_mhz", w.frequency_mhz);
    put_field(line, &n, "amplitude_q16", w.amplitude_q16);
    put_field(line, &n, "offset_q16", w.offset_q16);
    put_field(line, &n, "rise_q32", w.rise_q32);
    put_field(line, &n, "direction", w.direction);
    put_field(line, &n, "cycles", w.cycles);
    put_field(line, &n, "steps", n_steps);
    put_field(line, &n, "every", Q_FW_EVERY);
    ss_fmt_put_str(line, &n, "\nstep,x_slider_q40\n");
    send(link, line, n);

    ss_status_t status = ss_waveform_init_q(&w, cfg.dt_q40, &ws);
    if (status == SS_OK) {
        status = ss_actuator_init_q(&cfg, &st, ss_waveform_value_q(&w, &ws));
    }
    if (status == SS_OK) {
        send_row(link, st.steps, st.x_slider_q40);
    }
    /* the fixed-step loop: the drive's next sample, then one step of the model */
    for (uint32_t i = 1u; i <= n_steps && status == SS_OK; ++i) {
        status = ss_actuator_wave_step_q(&cfg, &st, &w, &ws);
        if (status == SS_OK && i % Q_FW_EVERY == 0u) {
            send_row(link, st.steps, st.x_slider_q40);
        }
    }
    n = 0;
    ss_fmt_put_str(line, &n, "# end");
    put_field(line, &n, "status", (int64_t)status);
    ss_fmt_put_str(line, &n, " ");
    ss_fmt_put_str(line, &n, ss_status_str(status));
    ss_fmt_put_str(line, &n, "\n");
    send(link, line, n);
    ss_cortex_m_exit(status == SS_OK ? 0 : 1);
    return 0;
}
