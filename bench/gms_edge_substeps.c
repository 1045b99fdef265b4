/* Where GMS's step error comes from (BENCHMARKS.md, "GMS's step error lies in the fast edge"): the
 * actuator with GMS friction and micro-damping at a 1 us step, and the same with some steps taken
 * as N sub-steps (the state's rod flow swapped for the sub-step's, as coarse_prototype.c does),
 * each against the run at 1/8 us throughout. Steps sub-stepped: those of the sawtooth's fast edge
 * (from 2 us before it), or those in which an element's damping switched (tried, then redone).
 * Prints per drive the slider's drift per cycle against the reference and its largest deviation.
 *
 *   build/host/bench/gms_edge_substeps SIGMA1 DECAY N MODE      MODE 0: fast edge, 1: switches
 *   e.g. build/host/bench/gms_edge_substeps 104 4.3 2 0          (seed 131's calibration) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ss_actuator.h"

typedef struct {
    double period_s;
    double rise; /* share of the period of the slow (rising) edge */
} drive_t;

/* the sawtooth of stick-slip-dataset/1, 0 to 100 V */
static double volts(const drive_t *d, double t)
{
    const double u = fmod(t, d->period_s), up = d->rise * d->period_s;
    return u < up ? 100.0 * u / up : 100.0 * (d->period_s - u) / (d->period_s - up);
}

/* one step over [t, t + dt], with the drive's corner when one lies inside it */
static void step(const ss_actuator_config_f32_t *cfg, ss_actuator_state_f32_t *st, const drive_t *d, double t,
                 double dt)
{
    const double k = floor(t / d->period_s);
    const double corners[3] = {(k + d->rise) * d->period_s, (k + 1.0) * d->period_s,
                               (k + 1.0 + d->rise) * d->period_s};
    for (int i = 0; i < 3; ++i) {
        if (corners[i] > t + 1e-12 && corners[i] < t + dt - 1e-12) {
            (void)ss_actuator_step_corner_f32(cfg, st, (float)volts(d, t + dt),
                                              (float)((corners[i] - t) / dt), (float)volts(d, corners[i]));
            return;
        }
    }
    (void)ss_actuator_step_f32(cfg, st, (float)volts(d, t + dt));
}

/* did an element's damping switch in the step just taken: damped at its start and at its level
 * now, or slipping at its start and below its level now */
static int switched(const ss_gms_state_f32_t *g)
{
    for (int i = 0; i < SS_GMS_ELEMENTS; ++i) {
        const int at_level = fabsf(g->f_n[i]) >= g->share[i] * g->level_n;
        if ((((g->damped_start >> i) & 1u) != 0u) == at_level) {
            return 1;
        }
    }
    return 0;
}

/* slider positions every us over `cycles` periods; sub > 1 with mode: the steps sub-stepped */
static long run(ss_actuator_config_f32_t cfg, const drive_t *d, int cycles, double dt, int sub, int mode,
                double *x)
{
    ss_actuator_config_f32_t fine = cfg;
    cfg.dt_s = (float)dt;
    fine.dt_s = (float)(dt / sub);
    ss_actuator_state_f32_t st, saved;
    (void)ss_actuator_init_f32(&fine, &st, 0.0f);
    float phi_fine[4], phi[4];
    memcpy(phi_fine, st.phi, sizeof phi);
    (void)ss_actuator_init_f32(&cfg, &st, 0.0f);
    memcpy(phi, st.phi, sizeof phi);
    const int per_us = (int)lround(1e-6 / dt);
    const long n_us = lround(cycles * d->period_s * 1e6);
    long k = 0, used = 0;
    for (long i = 0; i < n_us; ++i) {
        x[i] = (double)st.x_slider.hi_m + (double)st.x_slider.lo_m;
        for (int s = 0; s < per_us; ++s, ++k) {
            const double t = (double)k * dt;
            int redo = 0;
            if (sub > 1 && mode == 0) {
                redo = fmod(t, d->period_s) > d->rise * d->period_s - 2e-6;
            } else if (sub > 1) {
                saved = st;
                step(&cfg, &st, d, t, dt);
                redo = switched(&st.fr.gms);
                if (redo) {
                    st = saved;
                }
            }
            if (!redo) {
                if (sub == 1 || mode == 0) {
                    step(&cfg, &st, d, t, dt);
                }
                continue;
            }
            ++used;
            memcpy(st.phi, phi_fine, sizeof phi);
            for (int j = 0; j < sub; ++j) {
                step(&fine, &st, d, t + j * dt / sub, dt / sub);
            }
            memcpy(st.phi, phi, sizeof phi);
        }
    }
    return used;
}

int main(int argc, char **argv)
{
    if (argc != 5) {
        fprintf(stderr, "usage: %s SIGMA1 DECAY N MODE\n", argv[0]);
        return 2;
    }
    ss_actuator_config_f32_t cfg = ss_actuator_config_table1_f32();
    cfg.friction_model = SS_FRICTION_GMS;
    cfg.friction.sigma1_ns_per_m = (float)atof(argv[1]);
    cfg.friction.gms_decay = (float)atof(argv[2]);
    const int sub = atoi(argv[3]), mode = atoi(argv[4]), cycles = 6;
    const double hz[5] = {100.0, 300.0, 1000.0, 2000.0, 500.0};
    for (int q = 0; q < 5; ++q) {
        const drive_t d = {1.0 / hz[q], q == 4 ? 0.95 : 1.0 - 15e-6 * hz[q]};
        const long n = lround(cycles * d.period_s * 1e6), T = lround(d.period_s * 1e6);
        double *a = malloc(sizeof(double) * (size_t)n), *b = malloc(sizeof(double) * (size_t)n);
        double *r = malloc(sizeof(double) * (size_t)n);
        if (a == NULL || b == NULL || r == NULL) {
            return 1;
        }
        (void)run(cfg, &d, cycles, 1e-6, 1, 0, a);
        const long used = run(cfg, &d, cycles, 1e-6, sub, mode, b);
        (void)run(cfg, &d, cycles, 0.125e-6, 1, 0, r);
        double max_a = 0.0, max_b = 0.0;
        for (long i = 0; i < n; ++i) {
            max_a = fmax(max_a, fabs(a[i] - r[i]));
            max_b = fmax(max_b, fabs(b[i] - r[i]));
        }
        const double per = 1e9 / (cycles - 1);
        printf("%5.0f Hz, fall %3.0f us: 1 us %6.2f nm/cycle (max %5.2f nm); %d sub-steps on %ld of %ld "
               "steps %6.2f "
               "nm/cycle (max %5.2f nm)\n",
               hz[q], (1.0 - d.rise) * d.period_s * 1e6, ((a[n - 1] - r[n - 1]) - (a[T] - r[T])) * per,
               max_a * 1e9, sub, used, n, ((b[n - 1] - r[n - 1]) - (b[T] - r[T])) * per, max_b * 1e9);
        free(a);
        free(b);
        free(r);
    }
    return 0;
}
