/* Instruction count of one actuator step on the emulated Cortex-M. Run under QEMU with
 * -icount shift=0: one instruction per nanosecond of virtual time, and SysTick on the 25 MHz
 * MPS2 clock, so elapsed virtual ns = instructions executed. Prints one line per model on the
 * UART and exits through semihosting (bench/firmware_bench.sh). */
#include <stdio.h>

#include "ss_actuator.h"
#include "ss_port_cortex_m.h"

#define BENCH_STEPS 20000u

static void print(const ss_port_link_t *link, const char *s)
{
    size_t n = 0;
    while (s[n] != '\0') {
        ++n;
    }
    (void)link->write(link->ctx, (const uint8_t *)s, n);
}

int main(void)
{
    const ss_port_link_t *link = ss_cortex_m_init();
    static const char *const names[2] = {"ls", "lugre"};
    /* each law at the longest step at which it holds issue 17's 0.1 % a cycle over the drive matrix
     * (bench/step_study.py, docs/model.md): LS 1.5 us, LuGre 1 us */
    static const float step_s[2] = {1.5e-6f, 1.0e-6f};
    for (int m = 0; m < 2; ++m) {
        ss_actuator_config_f32_t cfg = ss_actuator_config_table1_f32();
        cfg.friction_model = m;
        cfg.dt_s = step_s[m];
        ss_waveform_config_f32_t w = ss_waveform_paper_f32();
        w.cycles = 1000u;
        ss_waveform_state_f32_t ws;
        static ss_actuator_state_f32_t st;
        (void)ss_waveform_init_f32(&w, cfg.dt_s, &ws);
        (void)ss_actuator_init_f32(&cfg, &st, 0.0f);
        uint32_t rows = 0;
        /* the loop alone (waveform player), to subtract */
        const uint64_t t0 = link->time_ns(link->ctx);
        for (uint32_t i = 0; i < BENCH_STEPS; ++i) {
            ss_waveform_advance_f32(&ws);
            (void)ss_waveform_value_f32(&w, &ws);
        }
        const uint64_t t1 = link->time_ns(link->ctx);
        (void)ss_waveform_init_f32(&w, cfg.dt_s, &ws);
        (void)ss_actuator_run_f32(&cfg, &st, &w, &ws, BENCH_STEPS, 1u, NULL, &rows);
        const uint64_t t2 = link->time_ns(link->ctx);
        char line[160];
        (void)snprintf(line, sizeof line,
                       "bench %s: %lu steps, %lu instructions per step with the waveform, %lu for the "
                       "waveform alone\n",
                       names[m], (unsigned long)BENCH_STEPS, (unsigned long)((t2 - t1) / BENCH_STEPS),
                       (unsigned long)((t1 - t0) / BENCH_STEPS));
        print(link, line);
        /* issue 17's figure of merit: the model alone (the waveform is the drive's, not the
         * model's), per microsecond of model time at the step it runs */
        const double model_instructions = (double)((t2 - t1) - (t1 - t0)); /* shift=0: one a ns */
        const double model_us = (double)BENCH_STEPS * (double)cfg.dt_s * 1e6;
        (void)snprintf(line, sizeof line,
                       "bench %s: %lu instructions per microsecond of model time at a step of %lu ns\n",
                       names[m], (unsigned long)(model_instructions / model_us + 0.5),
                       (unsigned long)((double)cfg.dt_s * 1e9 + 0.5));
        print(link, line);
    }
    ss_cortex_m_exit(0);
    return 0;
}
