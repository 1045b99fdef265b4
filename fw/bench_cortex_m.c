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

/* The loop alone (the waveform player) over BENCH_STEPS steps, ns: advancing, and advancing and
 * reading the value (the runs' own player work, subtracted from their figures). */
static void player_cost(const ss_port_link_t *link, const ss_waveform_config_f32_t *w, float dt_s,
                        uint64_t *advance_ns, uint64_t *advance_value_ns)
{
    ss_waveform_state_f32_t ws;
    (void)ss_waveform_init_f32(w, dt_s, &ws);
    const uint64_t t0 = link->time_ns(link->ctx);
    for (uint32_t i = 0; i < BENCH_STEPS; ++i) {
        ss_waveform_advance_f32(&ws);
    }
    const uint64_t t1 = link->time_ns(link->ctx);
    (void)ss_waveform_init_f32(w, dt_s, &ws);
    for (uint32_t i = 0; i < BENCH_STEPS; ++i) {
        ss_waveform_advance_f32(&ws);
        (void)ss_waveform_value_f32(w, &ws);
    }
    *advance_ns = t1 - t0;
    *advance_value_ns = link->time_ns(link->ctx) - t1;
}

/* issue 17's figure of merit: the model alone (the waveform is the drive's, not the model's), per
 * microsecond of model time at the step it runs */
static void print_merit(const ss_port_link_t *link, const char *name, double model_instructions, float dt_s,
                        const char *how)
{
    char line[160];
    const double model_us = (double)BENCH_STEPS * (double)dt_s * 1e6;
    (void)snprintf(line, sizeof line,
                   "bench %s: %lu instructions per microsecond of model time at a step of %lu ns%s\n", name,
                   (unsigned long)(model_instructions / model_us + 0.5),
                   (unsigned long)((double)dt_s * 1e9 + 0.5), how);
    print(link, line);
}

/* LuGre's stick steps (bench/step_study.py --models lugre --steps-us 1.5 --coarse 4 --stick 40) */
#define STICK_N 40u
#define STICK_COARSE_N 4u
#define STICK_DT_S 1.5e-6f

/* A coarse run of BENCH_STEPS steps of dt with rows every `rows`: the same model time in fewer
 * model steps; the player advanced every step of dt but read once a model step (advance_ns,
 * player_ns: player_cost's) */
static void coarse_run(const ss_port_link_t *link, const char *name, const ss_actuator_config_f32_t *cfg,
                       const ss_actuator_coarse_f32_t *co, const ss_waveform_config_f32_t *w,
                       uint32_t rows_every, uint64_t advance_ns, uint64_t player_ns, const char *what)
{
    static ss_actuator_state_f32_t st;
    ss_waveform_state_f32_t ws;
    char line[160];
    (void)ss_waveform_init_f32(w, cfg->dt_s, &ws);
    (void)ss_actuator_init_f32(cfg, &st, 0.0f);
    uint32_t rows = 0;
    uint32_t model_steps = 0;
    const uint64_t t3 = link->time_ns(link->ctx);
    (void)ss_actuator_run_coarse_f32(cfg, co, &st, w, &ws, BENCH_STEPS, rows_every, NULL, &rows,
                                     &model_steps);
    const uint64_t t4 = link->time_ns(link->ctx);
    const double value_ns = (double)(player_ns - advance_ns) / BENCH_STEPS;
    (void)snprintf(line, sizeof line, "bench %s: %lu model steps for %lu steps of dt\n", name,
                   (unsigned long)model_steps, (unsigned long)BENCH_STEPS);
    print(link, line);
    print_merit(link, name, (double)(t4 - t3) - (double)advance_ns - value_ns * model_steps, cfg->dt_s, what);
}

int main(void)
{
    const ss_port_link_t *link = ss_cortex_m_init();
    static const char *const names[2] = {"ls", "lugre"};
    /* each law at the longest step at which it holds issue 17's 0.1 % a cycle over the drive matrix
     * (bench/step_study.py, docs/model.md): LS 1.5 us, LuGre 1 us */
    static const float step_s[2] = {1.5e-6f, 1.0e-6f};
    /* and the coarse steps' longest at which each holds it (bench/step_study.py --coarse N): LS 8
     * in split steps (0.071 %, --edge), LuGre 8 (0.065 %) */
    static const uint32_t coarse_n[2] = {8u, 8u};
    static ss_actuator_state_f32_t st;
    char line[160];
    for (int m = 0; m < 2; ++m) {
        ss_actuator_config_f32_t cfg = ss_actuator_config_table1_f32();
        cfg.friction_model = m;
        cfg.dt_s = step_s[m];
        ss_waveform_config_f32_t w = ss_waveform_paper_f32();
        w.cycles = 1000u;
        ss_waveform_state_f32_t ws;
        uint64_t advance_ns;
        uint64_t player_ns;
        player_cost(link, &w, cfg.dt_s, &advance_ns, &player_ns);
        (void)ss_waveform_init_f32(&w, cfg.dt_s, &ws);
        (void)ss_actuator_init_f32(&cfg, &st, 0.0f);
        uint32_t rows = 0;
        const uint64_t t1 = link->time_ns(link->ctx);
        (void)ss_actuator_run_f32(&cfg, &st, &w, &ws, BENCH_STEPS, 1u, NULL, &rows);
        const uint64_t t2 = link->time_ns(link->ctx);
        (void)snprintf(line, sizeof line,
                       "bench %s: %lu steps, %lu instructions per step with the waveform, %lu for the "
                       "waveform alone\n",
                       names[m], (unsigned long)BENCH_STEPS, (unsigned long)((t2 - t1) / BENCH_STEPS),
                       (unsigned long)(player_ns / BENCH_STEPS));
        print(link, line);
        print_merit(link, names[m], (double)((t2 - t1) - player_ns), cfg.dt_s, ""); /* shift=0: one a ns */
        /* with coarse steps of up to coarse_n[m] where the contact sticks, 2 where it rings
         * (docs/model.md): the same BENCH_STEPS steps of model time in fewer model steps; the
         * player advanced every step of dt but read once a model step */
        ss_actuator_coarse_f32_t co;
        (void)ss_actuator_coarse_init_f32(&cfg, coarse_n[m], &co, NULL);
        char name[48];
        (void)snprintf(name, sizeof name, "%s coarse %lu", names[m], (unsigned long)coarse_n[m]);
        coarse_run(link, name, &cfg, &co, &w, coarse_n[m], advance_ns, player_ns, " (coarse steps)");
    }
    /* LuGre with stick steps of STICK_N once the contact has stopped ringing, and its fine steps on
     * a fast edge in parts (docs/model.md): at LS's 1.5 us with coarse steps of 4, rows every
     * STICK_N steps */
    ss_actuator_config_f32_t cfg = ss_actuator_config_table1_f32();
    cfg.friction_model = SS_FRICTION_LUGRE;
    cfg.dt_s = STICK_DT_S;
    ss_waveform_config_f32_t w = ss_waveform_paper_f32();
    w.cycles = 1000u;
    uint64_t advance_ns;
    uint64_t player_ns;
    player_cost(link, &w, cfg.dt_s, &advance_ns, &player_ns);
    ss_actuator_coarse_f32_t co;
    (void)ss_actuator_coarse_init_f32(&cfg, STICK_COARSE_N, &co, NULL);
    (void)ss_actuator_coarse_stick_f32(&cfg, STICK_N, &co, NULL);
    char name[48];
    (void)snprintf(name, sizeof name, "lugre coarse %lu stick %lu", (unsigned long)STICK_COARSE_N,
                   (unsigned long)STICK_N);
    coarse_run(link, name, &cfg, &co, &w, STICK_N, advance_ns, player_ns, " (coarse and stick steps)");
    ss_cortex_m_exit(0);
    return 0;
}
