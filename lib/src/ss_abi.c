#include "ss_abi.h"

#include "ss_actuator.h"
#include "ss_convert_q.h"

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
    default: return 0u;
    }
}
