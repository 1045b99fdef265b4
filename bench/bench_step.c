/* Host speed of the actuator step: median ns per step over repeated runs of the paper's drive.
 * Usage: bench_step [repeats] [cycles]   (see bench/run_benchmarks.py) */
#include <stdio.h>
#include <stdlib.h>

#include "bench_timing.h"
#include "ss_actuator.h"
#include "ss_actuator_q.h"

int main(int argc, char **argv)
{
    int repeats;
    unsigned cycles;
    if (!bench_args(argc, argv, "bench_step", &repeats, &cycles)) {
        return 2;
    }
    double *t = malloc(sizeof(double) * (size_t)repeats);
    if (t == NULL) {
        return 1;
    }
    const char *names[2] = {"ls", "lugre"};
    for (int m = 0; m < 2; ++m) {
        ss_actuator_config_f32_t cfg = ss_actuator_config_table1_f32();
        cfg.friction_model = m;
        ss_waveform_config_f32_t w = ss_waveform_sawtooth_f32(500.0f, 100.0f, 0.0f, 0.95f, 1, cycles);
        uint32_t steps = 0;
        float sink = 0.0f;
        for (int r = 0; r < repeats; ++r) {
            steps = (uint32_t)((double)cycles / 500.0 / (double)cfg.dt_s + 0.5);
            float x = 0.0f;
            t[r] = bench_time_run_f32(&cfg, &w, steps, &x);
            sink += x;
        }
        qsort(t, (size_t)repeats, sizeof(double), bench_cmp_double);
        const double med = t[repeats / 2];
        printf(
            "{\"model\": \"%s\", \"steps\": %u, \"repeats\": %d, \"median_s\": %.6g, \"ns_per_step\": %.4g, "
            "\"sim_s_per_wall_s\": %.4g, \"dt_s\": %g, \"check\": %.6g}\n",
            names[m], steps, repeats, med, 1e9 * med / (double)steps, (double)steps * (double)cfg.dt_s / med,
            (double)cfg.dt_s, (double)sink / repeats);
    }
    /* two simulations (sigma0 1 % apart) one after the other, then as one batch of two, which
     * interleaves them step by step (ss_actuator_run_many_f32): same bits, measured ns per step */
    for (int m = 0; m < 2; ++m) {
        ss_actuator_config_f32_t cfg[2] = {ss_actuator_config_table1_f32(), ss_actuator_config_table1_f32()};
        cfg[0].friction_model = cfg[1].friction_model = m;
        cfg[1].friction.sigma0_n_per_m *= 1.01f;
        ss_waveform_config_f32_t w = ss_waveform_sawtooth_f32(500.0f, 100.0f, 0.0f, 0.95f, 1, cycles);
        const uint32_t steps = (uint32_t)((double)cycles / 500.0 / (double)cfg[0].dt_s + 0.5);
        double *tb = malloc(sizeof(double) * (size_t)repeats);
        if (tb == NULL) {
            free(t);
            return 1;
        }
        int same = 1;
        for (int r = 0; r < repeats; ++r) {
            ss_waveform_state_f32_t ws[2][2];
            ss_actuator_state_f32_t st[2][2];
            for (int k = 0; k < 2; ++k) {
                for (int b = 0; b < 2; ++b) {
                    ss_waveform_init_f32(&w, cfg[k].dt_s, &ws[b][k]);
                    ss_actuator_init_f32(&cfg[k], &st[b][k], 0.0f);
                }
            }
            uint32_t rows = 0;
            double t0 = bench_now_s();
            for (int k = 0; k < 2; ++k) {
                ss_actuator_run_f32(&cfg[k], &st[0][k], &w, &ws[0][k], steps, 1u, NULL, &rows);
            }
            t[r] = bench_now_s() - t0;
            ss_actuator_run_job_f32_t jobs[2];
            for (int k = 0; k < 2; ++k) {
                jobs[k] = (ss_actuator_run_job_f32_t){&cfg[k], &st[1][k], &w, &ws[1][k], steps,
                                                      1u,      NULL,      0u, SS_OK};
            }
            t0 = bench_now_s();
            ss_actuator_run_many_f32(jobs, 2u);
            tb[r] = bench_now_s() - t0;
            for (int k = 0; k < 2; ++k) {
                same &= ss_position_value_f32(st[0][k].x_slider) == ss_position_value_f32(st[1][k].x_slider);
            }
        }
        qsort(t, (size_t)repeats, sizeof(double), bench_cmp_double);
        qsort(tb, (size_t)repeats, sizeof(double), bench_cmp_double);
        printf("{\"model\": \"%s_pair\", \"steps\": %u, \"repeats\": %d, \"ns_per_step_alone\": %.4g, "
               "\"ns_per_step_batch\": %.4g, \"speedup\": %.3g, \"same_bits\": %s}\n",
               names[m], 2u * steps, repeats, 1e9 * t[repeats / 2] / (2.0 * steps),
               1e9 * tb[repeats / 2] / (2.0 * steps), t[repeats / 2] / tb[repeats / 2],
               same ? "true" : "false");
        free(tb);
    }
    /* the fixed-point family on the same drive (Table I q constants, 100 V = 100 << 16) */
    for (int m = 0; m < 2; ++m) {
        ss_actuator_config_q_t cfg = ss_actuator_config_table1_q();
        cfg.friction_model = m;
        const ss_waveform_config_q_t w =
            ss_waveform_sawtooth_q(500000u, 100 << 16, 0, 4080218931u, 1, cycles);
        const uint32_t steps = (uint32_t)((double)cycles / 500.0 / 1e-6 + 0.5);
        double sink = 0.0;
        for (int r = 0; r < repeats; ++r) {
            ss_waveform_state_q_t ws;
            ss_actuator_state_q_t st;
            ss_waveform_init_q(&w, cfg.dt_q40, &ws);
            ss_actuator_init_q(&cfg, &st, 0);
            uint32_t rows = 0;
            const double t0 = bench_now_s();
            ss_actuator_run_q(&cfg, &st, &w, &ws, steps, 1u, NULL, &rows);
            t[r] = bench_now_s() - t0;
            sink += (double)st.x_slider_q40 / 1099511627776.0;
        }
        qsort(t, (size_t)repeats, sizeof(double), bench_cmp_double);
        const double med = t[repeats / 2];
        printf("{\"model\": \"%s_q\", \"steps\": %u, \"repeats\": %d, \"median_s\": %.6g, \"ns_per_step\": "
               "%.4g, "
               "\"sim_s_per_wall_s\": %.4g, \"dt_s\": %g, \"check\": %.6g}\n",
               names[m], steps, repeats, med, 1e9 * med / (double)steps, (double)steps * 1e-6 / med, 1e-6,
               sink / repeats);
    }
    free(t);
    return 0;
}
