/* What the fast edge's sub-steps cost on the host (BENCHMARKS.md, "The fast edge in sub-steps
 * for a micro-damped GMS"): median ns per actuator step of a micro-damped GMS (seed 131's
 * calibration: sigma1 104 N s/m, gms_decay 4.3) under sawtooths with 15 us falls, 100 Hz to
 * 2 kHz, and the paper's drive (500 Hz, 100 us fall: no step fast enough to be sub-stepped).
 * Built twice: gms_edge_cost against the library, gms_edge_cost_whole against the same library
 * built with SS_GMS_EDGE_SUBSTEPS=1 (every step whole; lib/CMakeLists.txt, stickslip_whole_steps,
 * built on request). Run them alternately (BENCHMARKS.md has the command); compare the medians.
 *
 *   build/host/bench/gms_edge_cost [repeats] [cycles] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "bench_timing.h"
#include "ss_actuator.h"

int main(int argc, char **argv)
{
    int repeats;
    unsigned cycles;
    if (!bench_args(argc, argv, "gms_edge_cost", &repeats, &cycles)) {
        return 2;
    }
    double *t = malloc(sizeof(double) * (size_t)repeats);
    if (t == NULL) {
        return 1;
    }
    ss_actuator_config_f32_t cfg = ss_actuator_config_table1_f32();
    cfg.friction_model = SS_FRICTION_GMS;
    cfg.friction.sigma1_ns_per_m = 104.0f;
    cfg.friction.gms_decay = 4.3f;
    const float hz[5] = {100.0f, 300.0f, 1000.0f, 2000.0f, 500.0f};
    for (int q = 0; q < 5; ++q) {
        const float rise = (q == 4) ? 0.95f : 1.0f - 15e-6f * hz[q];
        const ss_waveform_config_f32_t w = ss_waveform_sawtooth_f32(hz[q], 100.0f, 0.0f, rise, 1, cycles);
        const uint32_t steps = (uint32_t)lround((double)cycles / (double)hz[q] / (double)cfg.dt_s);
        double x_end = 0.0;
        for (int r = 0; r < repeats; ++r) {
            float x = 0.0f;
            t[r] = bench_time_run_f32(&cfg, &w, steps, &x);
            x_end = (double)x;
        }
        qsort(t, (size_t)repeats, sizeof(double), bench_cmp_double);
        printf("{\"hz\": %.0f, \"fall_us\": %.0f, \"steps\": %u, \"repeats\": %d, \"ns_per_step\": %.4g, "
               "\"x_end_um\": %.6g}\n",
               (double)hz[q], (1.0 - (double)rise) / (double)hz[q] * 1e6, steps, repeats,
               1e9 * t[repeats / 2] / (double)steps, x_end * 1e6);
    }
    free(t);
    return 0;
}
