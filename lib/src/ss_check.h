/* Private helpers for parameter validation (not part of the public API). */
#ifndef SS_CHECK_H
#define SS_CHECK_H

#include <math.h>
#include <stddef.h>
#include "ss_status.h"

/* SS_ERR_NONFINITE for NaN/inf, SS_ERR_RANGE outside [lo, hi], else SS_OK. */
static inline ss_status_t ss_check_range_f32(float v, float lo, float hi)
{
    if (!isfinite(v)) {
        return SS_ERR_NONFINITE;
    }
    return (v >= lo && v <= hi) ? SS_OK : SS_ERR_RANGE;
}

typedef struct {
    const char *name;
    float value;
    float lo, hi;
} ss_range_f32_t;

/* First failing range check of a table; *bad_field gets its name. */
static inline ss_status_t ss_check_ranges_f32(const ss_range_f32_t *r, size_t n, const char **bad_field)
{
    for (size_t i = 0; i < n; ++i) {
        const ss_status_t st = ss_check_range_f32(r[i].value, r[i].lo, r[i].hi);
        if (st != SS_OK) {
            *bad_field = r[i].name;
            return st;
        }
    }
    return SS_OK;
}

#define SS_FRICTION_N_FIELDS 9
static inline float ss_sign_f32(float v)
{
    return (v > 0.0f) ? 1.0f : ((v < 0.0f) ? -1.0f : 0.0f);
}

#endif /* SS_CHECK_H */
