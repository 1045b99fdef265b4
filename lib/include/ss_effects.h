/* Optional physical extensions of the actuator model: the cause catalog of the diagnosis
 * (stick-slip-diagnosis/1). Every field is neutral at zero, so a zeroed config is the base model
 * and costs nothing. Equations and parameter ranges: docs/effects.md. Asymmetric friction lives in
 * the friction config (ss_friction.h, field asymmetry), since it shapes the Stribeck curve. */
#ifndef SS_EFFECTS_H
#define SS_EFFECTS_H

#include "ss_status.h"

typedef struct {
    /* piezo_hysteresis, Bouc-Wen on the ideal strain u: dh = alpha du - |du| h / width, x_p = u - h */
    float hysteresis_alpha;   /* [0, 0.9], 0 = off */
    float hysteresis_width_m; /* (0, 1e-3] when alpha > 0 */
    /* piezo_creep: u = gain (V + ratio w), tau dw/dt = V - w (strain keeps growing after a step) */
    float creep_ratio; /* [0, 1], 0 = off */
    float creep_tau_s; /* [1e-5, 1e4] when ratio > 0 */
    /* external_load: a constant force on the slider, + in the direction of +x */
    float load_n; /* [-1e3, 1e3] */
    /* position_dependent_friction: Fs and Fc times 1 + gradient x_slider (clamped to >= 0.1) */
    float friction_gradient_per_m; /* [-1e5, 1e5] */
    /* amplifier_slew_limit: the piezo voltage follows the command at most this fast */
    float slew_v_per_s; /* 0 = off, else [1e2, 1e12] */
    /* ... and its small-signal bandwidth: behind the slew limit the voltage lags the command with
     * time constant tau = 1 / (2 pi f), dV/dt = clamp((V_cmd - V) / tau, -slew, +slew) */
    float amp_bandwidth_hz; /* 0 = unlimited, else [1e3, 1e10] with a slew limit on */
    /* thermal_drift: Fs and Fc times 1 - coeff q (clamped to >= 0.1), q the stored frictional heat:
     * dq/dt = |F v_rel| - q / tau */
    float thermal_coeff_per_j; /* [-1e6, 1e6], 0 = off */
    float thermal_tau_s;       /* [1e-4, 1e6] when coeff != 0 */
    /* base_compliance: the piezo pushes against a base of this mass on a spring to ground */
    float base_mass_kg;       /* 0 = off, else [1e-4, 1e3] */
    float base_freq_hz;       /* [10, 1e5] when mass > 0: base on its spring, piezo held */
    float base_damping_ratio; /* [0, 2] */
    /* sensor_scale_error: the sensor reports (1 + error) x_slider */
    float sensor_scale_error; /* [-0.5, 0.5] */
} ss_effects_config_f32_t;

typedef struct {
    float amp_v;          /* voltage on the piezo (the slew-limited command) */
    float amp_cmd_v;      /* the command at the end of the last step (its ramp drives the lag) */
    float creep_v;        /* creep state w, V */
    float hysteresis_m;   /* Bouc-Wen hysteretic strain h, m */
    float strain_m;       /* ideal strain u before hysteresis, m */
    float heat_j;         /* stored frictional heat q, J */
    float x_base_m;       /* base displacement */
    float v_base_m_per_s; /* base velocity */
} ss_effects_state_f32_t;

/* All off. */
ss_effects_config_f32_t ss_effects_config_none_f32(void);

/* SS_OK or the first problem; *bad_field (not NULL) names it, prefixed "effects.". */
ss_status_t ss_effects_config_check_f32(const ss_effects_config_f32_t *cfg, const char **bad_field);

/* At rest under drive v0_v: the piezo voltage settled (creep too), virgin hysteresis, no heat. */
void ss_effects_init_f32(const ss_effects_config_f32_t *cfg, ss_effects_state_f32_t *st, float gain_m_per_v,
                         float v0_v);

/* Advance the drive chain (amplifier, creep, hysteresis) over dt_s towards the commanded
 * voltage; returns the piezo strain x_p in m at the end of the step. */
float ss_effects_drive_f32(const ss_effects_config_f32_t *cfg, ss_effects_state_f32_t *st, float gain_m_per_v,
                           float command_v, float dt_s);

/* Factor on Fs and Fc from the slider position and the stored heat. 1 when both are off. */
float ss_effects_friction_scale_f32(const ss_effects_config_f32_t *cfg, const ss_effects_state_f32_t *st,
                                    float x_slider_m);

/* Add the work friction did over a step of dt_s (energy_j, signed: elastic energy given back
 * counts negative) to the stored heat and lose q / tau of it; q never falls below 0. */
void ss_effects_heat_f32(const ss_effects_config_f32_t *cfg, ss_effects_state_f32_t *st, float energy_j,
                         float dt_s);

/* What the position sensor reports for a true slider position. */
float ss_effects_sensor_f32(const ss_effects_config_f32_t *cfg, float x_slider_m);

#endif /* SS_EFFECTS_H */
