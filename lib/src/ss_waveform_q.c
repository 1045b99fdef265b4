#include "ss_waveform_q.h"

#include <stddef.h>

#include "ss_fixed_ops.h"

ss_waveform_config_q_t ss_waveform_sawtooth_q(uint32_t frequency_mhz, int32_t amplitude_q16,
                                              int32_t offset_q16, uint32_t rise_q32, int32_t direction,
                                              uint32_t cycles)
{
    ss_waveform_config_q_t cfg;
    cfg.frequency_mhz = frequency_mhz;
    cfg.amplitude_q16 = amplitude_q16;
    cfg.offset_q16 = offset_q16;
    cfg.rise_q32 = rise_q32;
    cfg.direction = direction;
    cfg.cycles = cycles;
    return cfg;
}

ss_waveform_config_q_t ss_waveform_paper_q(void)
{
    return ss_waveform_sawtooth_q(500000u, 100 * 65536, 0, 4080218880u, 1, 20u);
}

/* 1/d as a reciprocal mantissa m and shift sh (1/d ~ m 2^-sh, sh >= 32 for d >= 2;
 * ss_reciprocal_mantissa_q, d halved to fit it where d >= 2^31); m = 0 for d = 1. */
static uint32_t recip_u32(uint32_t d, int *sh)
{
    *sh = 0;
    if (d <= 1u) {
        return 0u;
    }
    const int halved = d > (uint32_t)INT32_MAX;
    const uint32_t m = (uint32_t)ss_reciprocal_mantissa_q(halved ? d >> 1 : d, sh);
    *sh += halved;
    return m;
}

/* floor(n / d), exact, for n < 2^63 + 2^32 and 0 < d < 2^32 whose quotient is below 2^32, from
 * d's reciprocal (recip_u32: m, sh). The estimate (m's relative error below 2^-30.8, and 2^-31
 * more for a d halved to fit it) comes within 7 of the quotient, and the remainder brings it there
 * exactly: no division instruction or libgcc division in a step on any target. */
static uint32_t div_by_recip(uint64_t n, uint32_t d, uint32_t m, int sh)
{
    if (m == 0u) {
        return (uint32_t)n; /* d = 1 */
    }
    /* n m / 2^sh in two 32 x 32 -> 64 products (n m needs 95 bits) */
    const uint64_t t = ss_mul_u32_u64((uint32_t)(n >> 32), m) + (ss_mul_u32_u64((uint32_t)n, m) >> 32);
    uint64_t q = t >> (sh - 32);
    /* the remainder n - q d, within (-8 d, 8 d): q d < 2^64 (q below 2^32 + 8) */
    int64_t rem = (int64_t)(n - ss_mul_u64_u32(q, d));
    while (rem < 0) {
        q--;
        rem += d;
    }
    while (rem >= (int64_t)d) {
        q++;
        rem -= d;
    }
    return (uint32_t)q;
}

/* The sawtooth at phase p: round(|A| p / r) on the rise, round(|A| (1 - p) / (1 - r)) on the fall
 * (ties up; at most 2^31: |A| p / r < |A|), by the divisor's reciprocal (m, sh; recip_u32). */
static int32_t sawtooth_q(const ss_waveform_config_q_t *cfg, uint32_t phase_q32, uint32_t m_rise, int sh_rise,
                          uint32_t m_fall, int sh_fall)
{
    const uint64_t one = (uint64_t)1 << 32;
    const uint64_t r = cfg->rise_q32;
    /* direction -1 plays the period reversed in time */
    const uint64_t p = (cfg->direction < 0) ? one - phase_q32 : phase_q32;
    const uint64_t a = (uint64_t)ss_abs64(cfg->amplitude_q16); /* |A| p < 2^63 */
    const int rise = p < r;
    const uint64_t num = ss_mul_u64_u32(a, (uint32_t)(rise ? p : one - p));
    const uint64_t den = rise ? r : one - r; /* 2^32 only for a rise of 0, which init refuses */
    const int64_t mag = (den == one)
                            ? (int64_t)((num + (one >> 1)) >> 32)
                            : (int64_t)div_by_recip(num + den / 2u, (uint32_t)den, rise ? m_rise : m_fall,
                                                    rise ? sh_rise : sh_fall);
    return ss_sat32((int64_t)cfg->offset_q16 + ((cfg->amplitude_q16 < 0) ? -mag : mag));
}

ss_status_t ss_waveform_init_q(const ss_waveform_config_q_t *cfg, int32_t dt_q40, ss_waveform_state_q_t *st)
{
    if (cfg == NULL || st == NULL) {
        return SS_ERR_NULL;
    }
    if (dt_q40 <= 0 || cfg->frequency_mhz == 0u || cfg->rise_q32 == 0u ||
        (cfg->direction != 1 && cfg->direction != -1)) {
        return SS_ERR_RANGE;
    }
    /* f dt 2^64 = (f_mHz dt_q40 / 1000) 2^24; f_mHz dt_q40 < 2^63 */
    const uint64_t x = (uint64_t)cfg->frequency_mhz * (uint64_t)dt_q40;
    const uint64_t whole = x / 1000u;
    if (whole >= ((uint64_t)1 << 40)) {
        return SS_ERR_RANGE; /* f dt >= 1: a period no longer than a step */
    }
    st->step_q64 = (whole << 24) + (((x % 1000u) << 24) + 500u) / 1000u;
    st->phase_q64 = 0u;
    st->index = 0u;
    int sh = 0;
    st->rise_recip = recip_u32(cfg->rise_q32, &sh);
    st->rise_shift = (uint8_t)sh;
    st->fall_recip = recip_u32((uint32_t)(((uint64_t)1 << 32) - cfg->rise_q32), &sh);
    st->fall_shift = (uint8_t)sh;
    st->pad = 0u;
    return SS_OK;
}

int32_t ss_sawtooth_at_phase_q(const ss_waveform_config_q_t *cfg, uint32_t phase_q32)
{
    int sh_rise = 0;
    int sh_fall = 0;
    const uint32_t m_rise = recip_u32(cfg->rise_q32, &sh_rise);
    const uint32_t m_fall = recip_u32((uint32_t)(((uint64_t)1 << 32) - cfg->rise_q32), &sh_fall);
    return sawtooth_q(cfg, phase_q32, m_rise, sh_rise, m_fall, sh_fall);
}

int32_t ss_waveform_value_q(const ss_waveform_config_q_t *cfg, const ss_waveform_state_q_t *st)
{
    if (st->index >= cfg->cycles) {
        return cfg->offset_q16;
    }
    return sawtooth_q(cfg, (uint32_t)(st->phase_q64 >> 32), st->rise_recip, st->rise_shift, st->fall_recip,
                      st->fall_shift);
}

void ss_waveform_advance_q(ss_waveform_state_q_t *st)
{
    const uint64_t before = st->phase_q64;
    st->phase_q64 += st->step_q64; /* unsigned: wraps modulo 2^64, which is the period boundary */
    if (st->phase_q64 < before && st->index < UINT32_MAX) {
        st->index++;
    }
}

void ss_waveform_advance_by_q(ss_waveform_state_q_t *st, uint32_t n)
{
    uint64_t sn = 0u;
    if (n > 4u && !ss_mul_u64_u32_overflows(st->step_q64, n, &sn)) {
        /* n steps within 2^64 (a period): the sum wraps at most once */
        const uint64_t before = st->phase_q64;
        st->phase_q64 += sn;
        if (st->phase_q64 < before && st->index < UINT32_MAX) {
            st->index++;
        }
        return;
    }
    for (uint32_t k = 0; k < n; ++k) { /* a few steps: as cheap as the product on the M0+ */
        ss_waveform_advance_q(st);
    }
}

int ss_waveform_corner_q(const ss_waveform_config_q_t *cfg, const ss_waveform_state_q_t *st,
                         int32_t *frac_q30, int32_t *v_q16)
{
    if (st->index >= cfg->cycles) {
        return 0; /* holding */
    }
    /* the next corner not yet passed, as a phase at 2^-64: the peak, or the period's end (2^64,
     * which is 0 mod 2^64: d is then 2^64 - phase, the unsigned difference) */
    const uint64_t r = (uint64_t)cfg->rise_q32 << 32;
    const uint64_t peak = (cfg->direction < 0) ? (uint64_t)0 - r : r;
    const uint64_t p = st->phase_q64;
    const uint64_t s = st->step_q64;
    const uint64_t end = p + s; /* below p where the step passes the period's end */
    if (end > p && (p >= peak || end <= peak)) {
        return 0; /* most steps: neither the peak nor the period's end inside */
    }
    const int at_peak = p < peak;
    const uint64_t d = (at_peak ? peak : 0u) - p;
    const uint64_t margin = s >> 10;
    if (d <= margin || d >= s - margin) {
        return 0; /* on the step's start, on its end or beyond it */
    }
    /* d / s in Q30 by s's reciprocal, both cut to s's top 31 bits (the phase's low bits are far
     * below a step's 2^-30) */
    int k = 0;
    while ((s >> k) > (uint64_t)INT32_MAX) {
        ++k;
    }
    int sh = 0;
    const int32_t m = ss_reciprocal_mantissa_q((uint32_t)(s >> k), &sh);
    *frac_q30 = (int32_t)ss_mul_recip_q((int32_t)(d >> k), m, sh - 30);
    *v_q16 = ss_sat32((int64_t)cfg->offset_q16 + (at_peak ? cfg->amplitude_q16 : 0));
    return 1;
}

int ss_waveform_straight_q(const ss_waveform_config_q_t *cfg, const ss_waveform_state_q_t *st, uint32_t n)
{
    if (st->index >= cfg->cycles || n == 0u) {
        return 1; /* holding */
    }
    const uint64_t s = st->step_q64;
    uint64_t sn = 0u;
    if (ss_mul_u64_u32_overflows(s, n, &sn)) {
        return 0; /* more than a period */
    }
    /* the next corner as ss_waveform_corner_q finds it, d ahead of the phase */
    const uint64_t r = (uint64_t)cfg->rise_q32 << 32;
    const uint64_t peak = (cfg->direction < 0) ? (uint64_t)0 - r : r;
    const uint64_t p = st->phase_q64;
    const uint64_t d = ((p < peak) ? peak : 0u) - p;
    return sn - (s >> 10) <= d;
}

ss_status_t ss_waveform_fill_q(const ss_waveform_config_q_t *cfg, ss_waveform_state_q_t *st, int32_t *out_q16,
                               uint32_t n)
{
    if (cfg == NULL || st == NULL || (n > 0u && out_q16 == NULL)) {
        return SS_ERR_NULL;
    }
    for (uint32_t i = 0; i < n; ++i) {
        ss_waveform_advance_q(st);
        out_q16[i] = ss_waveform_value_q(cfg, st);
    }
    return SS_OK;
}
