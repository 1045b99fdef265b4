/* Coarse steps as a prototype (docs/model.md, "Coarse steps while the contact sticks"): the tests
 * that ss_actuator_coarse_step_f32 makes, and two it does not, tried on any law by swapping the
 * state's rod flow between a fine and a coarse config before each step (the library refuses LS and
 * GMS). Unlike the library's run it lets a coarse step start at any fine step, not only on a row.
 * Prints each drive's worst per-cycle error against the law's own run at 0.125 us and the model
 * steps per microsecond, over step_study.py's drive matrix.
 *
 *   build/host/bench/coarse_prototype LAW STEP_US N V_REL_MAX [BRISTLE_MAX [RING_MAX]]
 *     LAW 0 LS, 1 LuGre; V_REL_MAX and RING_MAX in m/s; BRISTLE_MAX: LuGre's sigma0 |z| / Fc
 *   e.g. build/host/bench/coarse_prototype 0 1.5 2 1e-3 1e9 1e-4 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ss_actuator.h"

typedef struct {
    double period_s;
    double first; /* share of the period of the first (rising) piece */
    int cycles;
} drive_t;

/* the sawtooth of stick-slip-dataset/1, 0 to 100 V, held at 0 after the last period */
static double volts(const drive_t *d, double t)
{
    if (t >= d->cycles * d->period_s) {
        return 0.0;
    }
    const double u = fmod(t, d->period_s);
    const double t1 = d->first * d->period_s;
    return u < t1 ? 100.0 * u / t1 : 100.0 * (1.0 - (u - t1) / (d->period_s - t1));
}

static double slope(const drive_t *d, double t)
{
    if (t >= d->cycles * d->period_s) {
        return 0.0;
    }
    const double t1 = d->first * d->period_s;
    return fmod(t, d->period_s) < t1 ? 100.0 / t1 : -100.0 / (d->period_s - t1);
}

/* the first corner strictly inside (t0, t1), or -1 */
static double corner_in(const drive_t *d, double t0, double t1)
{
    const double k = floor(t0 / d->period_s);
    for (int j = 0; j < 3; ++j) {
        const double c1 = (k + j + d->first) * d->period_s;
        const double c2 = (k + j + 1) * d->period_s;
        if (c1 > t0 + 1e-13 && c1 < t1 - 1e-13) {
            return c1;
        }
        if (c2 > t0 + 1e-13 && c2 < t1 - 1e-13) {
            return c2;
        }
    }
    return -1.0;
}

typedef struct {
    int law;
    double fine_s;
    int n;
    double v_rel_max, bristle_max, ring_max;
} scheme_t;

typedef struct {
    double *t, *x;
    long rows;
    long steps;
} record_t;

static void run(const drive_t *d, const scheme_t *s, record_t *r)
{
    ss_actuator_config_f32_t fine = ss_actuator_config_table1_f32();
    fine.friction_model = s->law;
    fine.dt_s = (float)s->fine_s;
    ss_actuator_config_f32_t coarse = fine;
    coarse.dt_s = (float)(s->fine_s * s->n);
    ss_actuator_state_f32_t st, scratch;
    ss_actuator_init_f32(&fine, &st, 0.0f);
    ss_actuator_init_f32(&coarse, &scratch, 0.0f);
    float phi_fine[4], phi_coarse[4];
    memcpy(phi_fine, st.phi, sizeof phi_fine);
    memcpy(phi_coarse, scratch.phi, sizeof phi_coarse);
    const long n_fine = lround((d->cycles * d->period_s + s->fine_s) / s->fine_s);
    r->rows = 1;
    r->steps = 0;
    r->t[0] = 0.0;
    r->x[0] = 0.0;
    for (long i = 0; i < n_fine;) {
        const double t = i * s->fine_s;
        int big = 0;
        if (s->n > 1 && i + s->n <= n_fine) {
            const double v_rel = st.v_rod_m_per_s - st.v_slider_m_per_s;
            const double bristle =
                (s->law == SS_FRICTION_LUGRE)
                    ? fabs(st.fr.lugre.z_m) * fine.friction.sigma0_n_per_m / fine.friction.fc_n
                    : 0.0;
            const double ring = fabs(st.v_rod_m_per_s - fine.piezo_gain_m_per_v * slope(d, t));
            big = fabs(v_rel) < s->v_rel_max && bristle < s->bristle_max && ring < s->ring_max &&
                  corner_in(d, t - 1e-12, t + (s->n + 1) * s->fine_s) < 0.0;
        }
        const int k = big ? s->n : 1;
        memcpy(st.phi, big ? phi_coarse : phi_fine, sizeof phi_fine);
        const ss_actuator_config_f32_t *c = big ? &coarse : &fine;
        const double t1 = (i + k) * s->fine_s;
        const double corner = corner_in(d, t, t1);
        if (corner > 0.0) {
            ss_actuator_step_corner_f32(c, &st, (float)volts(d, t1), (float)((corner - t) / (t1 - t)),
                                        (float)volts(d, corner));
        } else {
            ss_actuator_step_f32(c, &st, (float)volts(d, t1));
        }
        i += k;
        r->steps++;
        r->t[r->rows] = t1;
        r->x[r->rows++] = ss_position_value_f32(st.x_slider);
    }
}

static double at(const record_t *r, double t)
{
    long lo = 0;
    long hi = r->rows - 1;
    while (hi - lo > 1) {
        const long m = (lo + hi) / 2;
        if (r->t[m] <= t) {
            lo = m;
        } else {
            hi = m;
        }
    }
    return r->x[lo] + (t - r->t[lo]) / (r->t[hi] - r->t[lo]) * (r->x[hi] - r->x[lo]);
}

int main(int argc, char **argv)
{
    if (argc < 5) {
        fprintf(stderr, "usage: %s LAW STEP_US N V_REL_MAX [BRISTLE_MAX [RING_MAX]]\n", argv[0]);
        return 2;
    }
    const scheme_t s = {atoi(argv[1]), atof(argv[2]) * 1e-6,           atoi(argv[3]),
                        atof(argv[4]), argc > 5 ? atof(argv[5]) : 1e9, argc > 6 ? atof(argv[6]) : 1e9};
    const scheme_t ref = {s.law, 0.125e-6, 1, 0.0, 0.0, 0.0};
    /* step_study.py's matrix: (frequency, fall, cycles) */
    static const double f_hz[6] = {100, 300, 500, 1000, 2000, 500};
    static const double fall_us[6] = {15, 15, 15, 15, 15, 100};
    static const int cycles[6] = {4, 6, 8, 10, 12, 8};
    double worst = 0.0, steps = 0.0, us = 0.0;
    for (int k = 0; k < 6; ++k) {
        for (int dir = 1; dir >= -1; dir -= 2) {
            const double period = 1.0 / f_hz[k];
            const double fall = fall_us[k] * 1e-6 / period;
            const drive_t d = {period, dir > 0 ? 1.0 - fall : fall, cycles[k]};
            const long cap = (long)(cycles[k] * period / ref.fine_s) + 16;
            record_t a = {malloc(cap * sizeof(double)), malloc(cap * sizeof(double)), 0, 0};
            record_t b = {malloc(cap * sizeof(double)), malloc(cap * sizeof(double)), 0, 0};
            if (!a.t || !a.x || !b.t || !b.x) {
                return 1;
            }
            run(&d, &ref, &a);
            run(&d, &s, &b);
            double w = 0.0; /* the first cycle, from rest, left out */
            for (int c = 1; c < cycles[k]; ++c) {
                const double s_ref = at(&a, (c + 1) * period) - at(&a, c * period);
                const double s_run = at(&b, (c + 1) * period) - at(&b, c * period);
                w = fmax(w, 100.0 * fabs(s_run - s_ref) / fabs(s_ref));
            }
            worst = fmax(worst, w);
            steps += (double)b.steps;
            us += cycles[k] * period * 1e6;
            printf("%5.0f Hz %s %3.0f us fall: %.3f %%, %.3f model steps per us\n", f_hz[k],
                   dir > 0 ? "fwd" : "rev", fall_us[k], w, b.steps / (cycles[k] * period * 1e6));
            free(a.t);
            free(a.x);
            free(b.t);
            free(b.x);
        }
    }
    printf("worst %.3f %%, %.3f model steps per us over the matrix\n", worst, steps / us);
    return 0;
}
