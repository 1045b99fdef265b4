#include "ss_waveform.h"

#include <math.h>
#include <stddef.h>

#include "ss_check.h"

ss_waveform_config_f32_t ss_waveform_sawtooth_f32(float frequency_hz, float amplitude_v, float offset_v,
                                                  float rise_fraction, int32_t direction, uint32_t cycles)
{
    ss_waveform_config_f32_t cfg;
    cfg.kind = SS_WAVE_SAWTOOTH;
    cfg.frequency_hz = frequency_hz;
    cfg.amplitude_v = amplitude_v;
    cfg.offset_v = offset_v;
    cfg.rise_fraction = rise_fraction;
    cfg.direction = direction;
    cfg.cycles = cycles;
    cfg.samples_v = NULL;
    cfg.n_samples = 0u;
    cfg.sample_interval_s = 0.0f;
    return cfg;
}

ss_waveform_config_f32_t ss_waveform_paper_f32(void)
{
    return ss_waveform_sawtooth_f32(500.0f, 100.0f, 0.0f, 0.95f, 1, 20);
}

static ss_status_t check_sawtooth(const ss_waveform_config_f32_t *cfg)
{
    ss_status_t st = ss_check_range_f32(cfg->frequency_hz, 1e-6f, 1e6f);
    if (st == SS_OK) {
        st = ss_check_range_f32(cfg->amplitude_v, -1e5f, 1e5f);
    }
    if (st == SS_OK) {
        st = ss_check_range_f32(cfg->offset_v, -1e5f, 1e5f);
    }
    if (st == SS_OK) {
        st = ss_check_range_f32(cfg->rise_fraction, 0.0f, 1.0f);
        /* both edges need a finite duration */
        if (st == SS_OK && (cfg->rise_fraction <= 0.0f || cfg->rise_fraction >= 1.0f)) {
            st = SS_ERR_RANGE;
        }
    }
    if (st == SS_OK && cfg->direction != 1 && cfg->direction != -1) {
        st = SS_ERR_RANGE;
    }
    return st;
}

static ss_status_t check_sampled(const ss_waveform_config_f32_t *cfg)
{
    if (cfg->samples_v == NULL) {
        return SS_ERR_NULL;
    }
    if (cfg->n_samples == 0u) {
        return SS_ERR_RANGE;
    }
    ss_status_t st = ss_check_range_f32(cfg->sample_interval_s, 1e-12f, 1e3f);
    for (uint32_t i = 0; st == SS_OK && i < cfg->n_samples; ++i) {
        st = ss_check_range_f32(cfg->samples_v[i], -1e5f, 1e5f);
    }
    return st;
}

ss_status_t ss_waveform_init_f32(const ss_waveform_config_f32_t *cfg, float dt_s, ss_waveform_state_f32_t *st)
{
    if (cfg == NULL || st == NULL) {
        return SS_ERR_NULL;
    }
    ss_status_t status = ss_check_range_f32(dt_s, 1e-12f, 1.0f);
    if (status != SS_OK) {
        return status;
    }
    if (cfg->kind == SS_WAVE_SAWTOOTH) {
        status = check_sawtooth(cfg);
        st->period_s = 1.0f / cfg->frequency_hz;
    } else if (cfg->kind == SS_WAVE_SAMPLED) {
        status = check_sampled(cfg);
        st->period_s = cfg->sample_interval_s;
    } else {
        status = SS_ERR_RANGE;
    }
    if (status != SS_OK) {
        return status;
    }
    st->dt_s = dt_s;
    st->tau0_s = 0.0f;
    st->index = 0u;
    st->j = 0u;
    st->peak_s = st->period_s;
    if (cfg->kind == SS_WAVE_SAWTOOTH) {
        st->peak_s = ((cfg->direction < 0) ? 1.0f - cfg->rise_fraction : cfg->rise_fraction) * st->period_s;
    }
    st->corner_s = st->peak_s;
    return SS_OK;
}

float ss_sawtooth_at_phase_f32(const ss_waveform_config_f32_t *cfg, float phase)
{
    const float r = cfg->rise_fraction;
    /* direction -1 plays the period reversed in time */
    const float p = (cfg->direction < 0) ? 1.0f - phase : phase;
    const float shape = (p < r) ? p / r : (1.0f - p) / (1.0f - r);
    return cfg->offset_v + cfg->amplitude_v * shape;
}

float ss_waveform_value_f32(const ss_waveform_config_f32_t *cfg, const ss_waveform_state_f32_t *st)
{
    const float tau = st->tau0_s + (float)st->j * st->dt_s;
    float frac = tau / st->period_s;
    if (frac > 1.0f) {
        frac = 1.0f;
    }
    if (cfg->kind == SS_WAVE_SAWTOOTH) {
        if (st->index >= cfg->cycles) {
            return cfg->offset_v;
        }
        return ss_sawtooth_at_phase_f32(cfg, frac);
    }
    if (st->index + 1u >= cfg->n_samples) {
        return cfg->samples_v[cfg->n_samples - 1u];
    }
    const float a = cfg->samples_v[st->index];
    const float b = cfg->samples_v[st->index + 1u];
    return a + (b - a) * frac;
}

void ss_waveform_advance_f32(ss_waveform_state_f32_t *st)
{
    st->j++;
    float tau = st->tau0_s + (float)st->j * st->dt_s;
    while (tau >= st->period_s) {
        tau -= st->period_s;
        st->tau0_s = tau;
        st->j = 0u;
        st->corner_s = st->peak_s;
        if (st->index < UINT32_MAX) {
            st->index++;
        }
    }
    if (tau >= st->corner_s) {
        st->corner_s = st->period_s; /* past the peak: the period's end is next */
    }
}

int ss_waveform_corner_f32(const ss_waveform_config_f32_t *cfg, const ss_waveform_state_f32_t *st,
                           float *frac_out, float *v_out)
{
    /* every step asks: one multiply-add and a compare while the next corner is beyond this step */
    const float tau = st->tau0_s + (float)st->j * st->dt_s;
    const float d = st->corner_s - tau;
    if (d >= (1.0f - SS_WAVEFORM_CORNER_MIN_FRAC) * st->dt_s || d <= SS_WAVEFORM_CORNER_MIN_FRAC * st->dt_s) {
        return 0; /* beyond the step, or on its start (on the grid) */
    }
    if (cfg->kind == SS_WAVE_SAWTOOTH) {
        if (st->index >= cfg->cycles) {
            return 0; /* holding */
        }
        /* the peak, or the period's end where the drive is back at offset */
        *v_out = cfg->offset_v + ((st->corner_s < st->period_s) ? cfg->amplitude_v : 0.0f);
    } else {
        if (st->index + 1u >= cfg->n_samples) {
            return 0; /* holding the last sample */
        }
        *v_out = cfg->samples_v[st->index + 1u];
    }
    *frac_out = d / st->dt_s;
    return 1;
}

int ss_waveform_straight_f32(const ss_waveform_config_f32_t *cfg, const ss_waveform_state_f32_t *st,
                             uint32_t n)
{
    const int holding =
        (cfg->kind == SS_WAVE_SAWTOOTH) ? st->index >= cfg->cycles : st->index + 1u >= cfg->n_samples;
    if (holding) {
        return 1;
    }
    /* the corner the player would find inside one of the steps, as ss_waveform_corner_f32 asks */
    const float tau = st->tau0_s + (float)st->j * st->dt_s;
    return st->corner_s - tau >= ((float)n - SS_WAVEFORM_CORNER_MIN_FRAC) * st->dt_s;
}

float ss_waveform_slope_f32(const ss_waveform_config_f32_t *cfg, const ss_waveform_state_f32_t *st)
{
    if (cfg->kind == SS_WAVE_SAWTOOTH) {
        if (st->index >= cfg->cycles) {
            return 0.0f;
        }
        /* both directions rise from offset to the peak, then fall back (ss_sawtooth_at_phase_f32) */
        return (st->corner_s < st->period_s) ? cfg->amplitude_v / st->peak_s
                                             : -cfg->amplitude_v / (st->period_s - st->peak_s);
    }
    if (st->index + 1u >= cfg->n_samples) {
        return 0.0f;
    }
    return (cfg->samples_v[st->index + 1u] - cfg->samples_v[st->index]) / st->period_s;
}

ss_status_t ss_waveform_fill_f32(const ss_waveform_config_f32_t *cfg, ss_waveform_state_f32_t *st, float *out,
                                 uint32_t n)
{
    if (cfg == NULL || st == NULL || (n > 0u && out == NULL)) {
        return SS_ERR_NULL;
    }
    for (uint32_t i = 0; i < n; ++i) {
        ss_waveform_advance_f32(st);
        out[i] = ss_waveform_value_f32(cfg, st);
    }
    return SS_OK;
}
