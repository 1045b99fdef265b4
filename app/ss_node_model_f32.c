/* The node's model adapter for the float32 family (ss_node_model.h). */
#include "ss_node_model.h"

ss_node_drive_t ss_node_model_drive_from_v(float v)
{
    return v;
}

float ss_node_model_dt_s(const ss_node_config_t *cfg)
{
    return cfg->dt_s;
}

uint64_t ss_node_model_dt_fs(const ss_node_config_t *cfg)
{
    return (uint64_t)(cfg->dt_s * 1e15f + 0.5f); /* dt_s is checked positive and at most 1e-3 s */
}

ss_node_config_t ss_node_model_default_config(void)
{
    return ss_actuator_config_table1_f32();
}

ss_status_t ss_node_model_config(const ss_actuator_config_f32_t *f, ss_node_config_t *out, const char **why)
{
    *out = *f;
    return ss_actuator_config_check_f32(out, why);
}

void ss_node_model_init(const ss_node_config_t *cfg, ss_node_state_t *st, ss_node_drive_t d)
{
    (void)ss_actuator_init_f32(cfg, st, d);
}

void ss_node_model_place_slider(ss_node_state_t *st, float x_m)
{
    ss_actuator_place_slider_f32(st, x_m);
}

void ss_node_model_step(const ss_node_config_t *cfg, ss_node_state_t *st, ss_node_drive_t d)
{
    (void)ss_actuator_step_f32(cfg, st, d);
}

ss_node_row_t ss_node_model_row(const ss_node_state_t *st)
{
    const ss_node_row_t r = {st->steps,         st->drive_v,       st->x_rod_m,
                             st->x_slider.hi_m, st->x_slider.lo_m, st->force_n};
    return r;
}

ss_status_t ss_node_model_wave_convert(const ss_waveform_config_f32_t *w, ss_node_wave_t *out,
                                       const char **why)
{
    (void)why;
    *out = *w;
    return SS_OK;
}

ss_status_t ss_node_model_wave_init(const ss_node_config_t *cfg, const ss_node_wave_t *w,
                                    ss_node_wave_state_t *ws)
{
    return ss_waveform_init_f32(w, cfg->dt_s, ws);
}

ss_node_drive_t ss_node_model_wave_value(const ss_node_wave_t *w, const ss_node_wave_state_t *ws)
{
    return ss_waveform_value_f32(w, ws);
}

void ss_node_model_wave_step(const ss_node_config_t *cfg, ss_node_state_t *st, const ss_node_wave_t *w,
                             ss_node_wave_state_t *ws)
{
    (void)ss_actuator_wave_step_f32(cfg, st, w, ws);
}
