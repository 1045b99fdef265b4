/* Instruction count of one fixed-point actuator step on the emulated Cortex-M, as bench_cortex_m.c
 * for the float family: under QEMU -icount shift=0 one instruction takes one ns of virtual time, so
 * elapsed virtual ns = instructions executed. Integer only, like the model it times (no printf:
 * ss_fmt.h). Prints one line per friction model and exits (bench/firmware_bench.sh). */
#include <stddef.h>
#include <stdint.h>

#include "bench_q_config.h"
#include "ss_actuator_q.h"
#include "ss_fmt.h"
#include "ss_port_cortex_m.h"

#define BENCH_STEPS 20000u

static void print(const ss_port_link_t *link, const char *line, size_t n)
{
    (void)link->write(link->ctx, (const uint8_t *)line, n);
}

/* "bench q NAME coarse N: " (or "... coarse N stick L: "), each coarse line's start */
static void put_coarse_name(char *line, size_t *n, const char *name, const ss_actuator_coarse_q_t *co)
{
    ss_fmt_put_str(line, n, "bench q ");
    ss_fmt_put_str(line, n, name);
    ss_fmt_put_str(line, n, " coarse ");
    ss_fmt_put_i64(line, n, co->n);
    if (co->stick_n != 0u) {
        ss_fmt_put_str(line, n, " stick ");
        ss_fmt_put_i64(line, n, co->stick_n);
    }
    ss_fmt_put_str(line, n, ": ");
}

/* With coarse steps where the contact sticks (LS 8 x 1.5 us, split; LuGre 8 x 1 us), 2 where it rings
 * (bench_q_config.h; docs/model.md): the same BENCH_STEPS steps of model time in fewer model steps.
 * The player advances every step of dt (a coarse step advances a copy of it n times) but is read
 * once a model step: its advances over BENCH_STEPS and its reads per model step are subtracted
 * (player_ns: advance and read, each step). */
static void coarse_bench(const ss_port_link_t *link, const char *name, const ss_actuator_config_q_t *cfg,
                         const ss_actuator_coarse_q_t *co, const ss_waveform_config_q_t *w,
                         uint64_t player_ns, uint32_t rows_every)
{
    static ss_actuator_state_q_t st;
    ss_waveform_state_q_t ws;
    int ok = ss_waveform_init_q(w, cfg->dt_q40, &ws) == SS_OK;
    const uint64_t t0 = link->time_ns(link->ctx);
    for (uint32_t i = 0; i < BENCH_STEPS; ++i) {
        ss_waveform_advance_q(&ws);
    }
    const uint64_t advance_ns = link->time_ns(link->ctx) - t0;
    ok = ok && ss_waveform_init_q(w, cfg->dt_q40, &ws) == SS_OK;
    ok = ok && ss_actuator_init_q(cfg, &st, ss_waveform_value_q(w, &ws)) == SS_OK;
    uint32_t rows = 0;
    uint32_t model_steps = 0;
    const uint64_t t1 = link->time_ns(link->ctx);
    ok = ok && ss_actuator_run_coarse_q(cfg, co, &st, w, &ws, BENCH_STEPS, rows_every, NULL, &rows,
                                        &model_steps) == SS_OK;
    const uint64_t t2 = link->time_ns(link->ctx);
    const uint64_t read_ns = (player_ns - advance_ns) * model_steps / BENCH_STEPS;
    const uint64_t model_instructions = (t2 - t1) - advance_ns - read_ns;
    const uint64_t model_ns = ((uint64_t)BENCH_STEPS * (((uint64_t)cfg->dt_q40 * 1000000000u) >> 20)) >> 20;
    char line[160];
    size_t n = 0;
    put_coarse_name(line, &n, name, co);
    ss_fmt_put_i64(line, &n, model_steps);
    ss_fmt_put_str(line, &n, " model steps for ");
    ss_fmt_put_i64(line, &n, BENCH_STEPS);
    /* where the slider ends, m at 2^-40: tests/python/test_firmware_q.py holds it to the host's */
    ss_fmt_put_str(line, &n, " steps of dt, slider at ");
    ss_fmt_put_i64(line, &n, st.x_slider_q40);
    ss_fmt_put_str(line, &n, ok ? "\n" : " (MODEL ERROR)\n");
    print(link, line, n);
    n = 0;
    put_coarse_name(line, &n, name, co);
    ss_fmt_put_i64(line, &n, (int64_t)((model_instructions * 1000u + model_ns / 2u) / model_ns));
    ss_fmt_put_str(line, &n,
                   (co->stick_n != 0u)
                       ? " instructions per microsecond of model time (coarse and stick steps)\n"
                       : " instructions per microsecond of model time (coarse steps)\n");
    print(link, line, n);
    if (!ok) {
        ss_cortex_m_exit(1);
    }
}

int main(void)
{
    const ss_port_link_t *link = ss_cortex_m_init();
    static const char *const names[2] = {"ls", "lugre"};
    /* each law at the longest step at which it holds issue 17's 0.1 % a cycle over the drive matrix
     * (bench/step_study.py --variant q, docs/fixed-point.md): LS 1.5 us (a config the host made,
     * bench_q_config.h), LuGre Table I's 1 us */
    static const ss_actuator_config_q_t ls_cfg = SS_BENCH_Q_LS_CONFIG;
    static const ss_actuator_coarse_q_t coarse[2] = {SS_BENCH_Q_LS_COARSE, SS_BENCH_Q_LUGRE_COARSE};
    uint64_t player_15_ns = 0;
    for (int32_t m = 0; m < 2; ++m) {
        ss_actuator_config_q_t cfg = (m == SS_FRICTION_Q_LS) ? ls_cfg : ss_actuator_config_table1_q();
        cfg.friction_model = m;
        ss_waveform_config_q_t w = ss_waveform_paper_q();
        w.cycles = 1000u;
        ss_waveform_state_q_t ws;
        static ss_actuator_state_q_t st;
        int ok = ss_waveform_init_q(&w, cfg.dt_q40, &ws) == SS_OK;
        ok = ok && ss_actuator_init_q(&cfg, &st, ss_waveform_value_q(&w, &ws)) == SS_OK;
        uint32_t rows = 0;
        /* the loop alone (waveform player), to subtract */
        volatile int32_t sink = 0;
        const uint64_t t0 = link->time_ns(link->ctx);
        for (uint32_t i = 0; i < BENCH_STEPS; ++i) {
            ss_waveform_advance_q(&ws);
            sink = ss_waveform_value_q(&w, &ws);
        }
        const uint64_t t1 = link->time_ns(link->ctx);
        ok = ok && ss_waveform_init_q(&w, cfg.dt_q40, &ws) == SS_OK;
        ok = ok && ss_actuator_run_q(&cfg, &st, &w, &ws, BENCH_STEPS, 1u, NULL, &rows) == SS_OK;
        const uint64_t t2 = link->time_ns(link->ctx);
        (void)sink;
        char line[160];
        size_t n = 0;
        ss_fmt_put_str(line, &n, "bench q ");
        ss_fmt_put_str(line, &n, names[m]);
        ss_fmt_put_str(line, &n, ": ");
        ss_fmt_put_i64(line, &n, BENCH_STEPS);
        ss_fmt_put_str(line, &n, " steps, ");
        ss_fmt_put_i64(line, &n, (int64_t)((t2 - t1) / BENCH_STEPS));
        ss_fmt_put_str(line, &n, " instructions per step with the waveform, ");
        ss_fmt_put_i64(line, &n, (int64_t)((t1 - t0) / BENCH_STEPS));
        ss_fmt_put_str(line, &n,
                       ok ? " for the waveform alone\n" : " for the waveform alone (MODEL ERROR)\n");
        print(link, line, n);
        /* issue 17's figure of merit: the model alone (the waveform is the drive's, not the
         * model's), per microsecond of model time at the step it runs */
        const uint64_t model_instructions = (t2 - t1) - (t1 - t0);                 /* shift=0: one a ns */
        const uint64_t step_ns_x2p20 = ((uint64_t)cfg.dt_q40 * 1000000000u) >> 20; /* the step, ns x 2^20 */
        const uint64_t model_ns = ((uint64_t)BENCH_STEPS * step_ns_x2p20) >> 20;
        n = 0;
        ss_fmt_put_str(line, &n, "bench q ");
        ss_fmt_put_str(line, &n, names[m]);
        ss_fmt_put_str(line, &n, ": ");
        ss_fmt_put_i64(line, &n, (int64_t)((model_instructions * 1000u + model_ns / 2u) / model_ns));
        ss_fmt_put_str(line, &n, " instructions per microsecond of model time at a step of ");
        ss_fmt_put_i64(line, &n, (int64_t)((step_ns_x2p20 + (1u << 19)) >> 20));
        ss_fmt_put_str(line, &n, " ns\n");
        print(link, line, n);
        if (!ok) {
            ss_cortex_m_exit(1);
        }
        coarse_bench(link, names[m], &cfg, &coarse[m], &w, t1 - t0, coarse[m].n);
        if (m == SS_FRICTION_Q_LS) {
            player_15_ns = t1 - t0; /* the player at 1.5 us */
        }
    }
    /* LuGre with stick steps once the contact has stopped ringing and its fine steps on a fast edge
     * in parts, at LS's 1.5 us with coarse steps of 4, rows every stick_n steps (bench_q_config.h) */
    static const ss_actuator_coarse_q_t stick = SS_BENCH_Q_LUGRE_STICK;
    ss_actuator_config_q_t lugre_15 = ls_cfg;
    lugre_15.friction_model = SS_FRICTION_Q_LUGRE;
    ss_waveform_config_q_t w = ss_waveform_paper_q();
    w.cycles = 1000u;
    coarse_bench(link, names[SS_FRICTION_Q_LUGRE], &lugre_15, &stick, &w, player_15_ns, stick.stick_n);
    /* ... and on a 15 us fall at 1 kHz, whose fine steps on the fall are taken in parts (the
     * player's cost measured again: its own waveform) */
    static const ss_waveform_config_q_t fast = SS_BENCH_Q_FAST_EDGE_WAVE;
    ss_waveform_state_q_t ws;
    volatile int32_t sink = 0;
    int ok = ss_waveform_init_q(&fast, lugre_15.dt_q40, &ws) == SS_OK;
    const uint64_t t0 = link->time_ns(link->ctx);
    for (uint32_t i = 0; i < BENCH_STEPS; ++i) {
        ss_waveform_advance_q(&ws);
        sink = ss_waveform_value_q(&fast, &ws);
    }
    const uint64_t t1 = link->time_ns(link->ctx);
    (void)sink;
    if (!ok) {
        ss_cortex_m_exit(1);
    }
    coarse_bench(link, "lugre fall 15", &lugre_15, &stick, &fast, t1 - t0, stick.stick_n);
    ss_cortex_m_exit(0);
    return 0;
}
