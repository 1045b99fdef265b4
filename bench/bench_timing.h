/* What the host benches share: a monotonic clock, a comparison for qsort of doubles, the
 * [repeats] [cycles] arguments (defaults 11 and 100), and one timed run of the float actuator.
 * Header-only; needs _POSIX_C_SOURCE. */
#ifndef SS_BENCH_TIMING_H
#define SS_BENCH_TIMING_H

#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "ss_actuator.h"

static inline double bench_now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static inline int bench_cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* argv's repeats in [1, 1000] and cycles in [1, 100000]; 0 after a message naming the bench if
 * either is out of range */
static inline int bench_args(int argc, char **argv, const char *name, int *repeats, unsigned *cycles)
{
    *repeats = argc > 1 ? atoi(argv[1]) : 11;
    *cycles = argc > 2 ? (unsigned)atoi(argv[2]) : 100u;
    if (*repeats < 1 || *repeats > 1000 || *cycles < 1u || *cycles > 100000u) {
        fprintf(stderr, "%s: repeats in [1, 1000], cycles in [1, 100000]\n", name);
        return 0;
    }
    return 1;
}

/* Seconds of wall time for steps of the actuator under w, from a fresh state (the set-up not
 * timed); the slider's position at the end in *x_end_m, for the bench's check. */
static inline double bench_time_run_f32(const ss_actuator_config_f32_t *cfg,
                                        const ss_waveform_config_f32_t *w, uint32_t steps, float *x_end_m)
{
    ss_waveform_state_f32_t ws;
    ss_actuator_state_f32_t st;
    ss_waveform_init_f32(w, cfg->dt_s, &ws);
    ss_actuator_init_f32(cfg, &st, 0.0f);
    uint32_t rows = 0;
    const double t0 = bench_now_s();
    ss_actuator_run_f32(cfg, &st, w, &ws, steps, 1u, NULL, &rows);
    const double t = bench_now_s() - t0;
    *x_end_m = ss_position_value_f32(st.x_slider);
    return t;
}

#endif
