/* What the host benches share: a monotonic clock, a comparison for qsort of doubles, and the
 * [repeats] [cycles] arguments (defaults 11 and 100). Header-only; needs _POSIX_C_SOURCE. */
#ifndef SS_BENCH_TIMING_H
#define SS_BENCH_TIMING_H

#include <stdio.h>
#include <stdlib.h>
#include <time.h>

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

#endif
