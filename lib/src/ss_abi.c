#include "ss_abi.h"

#include <stddef.h>

#include "ss_actuator.h"
#include "ss_convert_q.h"
#include "ss_qformat.h"

uint32_t ss_abi_sizeof(int32_t which)
{
    switch (which) {
    case SS_ABI_FRICTION_CONFIG_F32: return (uint32_t)sizeof(ss_friction_config_f32_t);
    case SS_ABI_ACTUATOR_CONFIG_F32: return (uint32_t)sizeof(ss_actuator_config_f32_t);
    case SS_ABI_ACTUATOR_STATE_F32: return (uint32_t)sizeof(ss_actuator_state_f32_t);
    case SS_ABI_WAVEFORM_CONFIG_F32: return (uint32_t)sizeof(ss_waveform_config_f32_t);
    case SS_ABI_WAVEFORM_STATE_F32: return (uint32_t)sizeof(ss_waveform_state_f32_t);
    case SS_ABI_LS_STATE_F32: return (uint32_t)sizeof(ss_ls_state_f32_t);
    case SS_ABI_LUGRE_STATE_F32: return (uint32_t)sizeof(ss_lugre_state_f32_t);
    case SS_ABI_ACTUATOR_TRACE_F32: return (uint32_t)sizeof(ss_actuator_trace_f32_t);
    case SS_ABI_FRICTION_CONFIG_Q: return (uint32_t)sizeof(ss_friction_config_q_t);
    case SS_ABI_ACTUATOR_CONFIG_Q: return (uint32_t)sizeof(ss_actuator_config_q_t);
    case SS_ABI_ACTUATOR_STATE_Q: return (uint32_t)sizeof(ss_actuator_state_q_t);
    case SS_ABI_WAVEFORM_CONFIG_Q: return (uint32_t)sizeof(ss_waveform_config_q_t);
    case SS_ABI_WAVEFORM_STATE_Q: return (uint32_t)sizeof(ss_waveform_state_q_t);
    case SS_ABI_LS_STATE_Q: return (uint32_t)sizeof(ss_ls_state_q_t);
    case SS_ABI_LUGRE_STATE_Q: return (uint32_t)sizeof(ss_lugre_state_q_t);
    case SS_ABI_ACTUATOR_TRACE_Q: return (uint32_t)sizeof(ss_actuator_trace_q_t);
    case SS_ABI_ACTUATOR_SI: return (uint32_t)sizeof(ss_actuator_si_t);
    case SS_ABI_EFFECTS_CONFIG_F32: return (uint32_t)sizeof(ss_effects_config_f32_t);
    case SS_ABI_GMS_STATE_F32: return (uint32_t)sizeof(ss_gms_state_f32_t);
    case SS_ABI_FRICTION_MU_F32: return (uint32_t)sizeof(ss_friction_mu_f32_t);
    case SS_ABI_ACTUATOR_RUN_JOB_F32: return (uint32_t)sizeof(ss_actuator_run_job_f32_t);
    case SS_ABI_ACTUATOR_COARSE_F32: return (uint32_t)sizeof(ss_actuator_coarse_f32_t);
    case SS_ABI_ACTUATOR_COARSE_Q: return (uint32_t)sizeof(ss_actuator_coarse_q_t);
    default: return 0u;
    }
}

typedef struct {
    const char *name;
    int32_t shift;
} qformat_entry_t;

static const qformat_entry_t QFORMATS[] = {
    /* the actuator's state and trace (ss_actuator_q.h) */
    {"drive_q16", SS_QF_VOLTAGE},
    {"x_p_q40", SS_QF_LENGTH},
    {"x_rod_q40", SS_QF_LENGTH},
    {"x_slider_q40", SS_QF_LENGTH},
    {"x_meas_q40", SS_QF_LENGTH},
    {"v_rod_q28", SS_QF_VELOCITY},
    {"v_slider_q28", SS_QF_VELOCITY},
    {"force_q24", SS_QF_FORCE},
    /* the friction states, state_a and state_b of the trace */
    {"ls.level_q24", SS_QF_FORCE},
    {"ls.fm_q24", SS_QF_FORCE},
    {"lugre.z_q40", SS_QF_LENGTH},
    {"lugre.zdot_q28", SS_QF_VELOCITY},
    /* configs (ss_actuator_q.h, ss_friction_q.h, ss_waveform_q.h) */
    {"dt_q40", SS_QF_TIME},
    {"piezo_gain_q48", SS_QF_GAIN},
    {"lag_q24", SS_QF_LAG},
    {"kick_rod_q40", SS_QF_KICK},
    {"kick_slider_q40", SS_QF_KICK},
    {"contact_lag_q30", SS_QF_RATIO},
    {"rod_w2dt2_q28", SS_QF_FLOW},
    {"phi_q28", SS_QF_FLOW},
    {"fs_q24", SS_QF_FORCE},
    {"fc_q24", SS_QF_FORCE},
    {"vs_q28", SS_QF_VELOCITY},
    {"sigma1_q16", SS_QF_DAMPING},
    {"sigma2_q16", SS_QF_DAMPING},
    {"amplitude_q16", SS_QF_VOLTAGE},
    {"offset_q16", SS_QF_VOLTAGE},
    {"rise_q32", SS_QF_FRACTION},
};

int32_t ss_abi_qformat(uint32_t i, const char **name)
{
    if (i >= (uint32_t)(sizeof QFORMATS / sizeof QFORMATS[0])) {
        if (name != NULL) {
            *name = NULL;
        }
        return -1;
    }
    if (name != NULL) {
        *name = QFORMATS[i].name;
    }
    return QFORMATS[i].shift;
}
