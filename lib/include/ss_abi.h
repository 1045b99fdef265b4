/* Sizes of the public structs, so that a binding (hil/stickslip/_native.py) can check its
 * mirrors of them at load time instead of trusting a copy of the layout; and the Q format of each
 * fixed-point signal (ss_qformat.h), so that it scales the q family's integers without a copy. */
#ifndef SS_ABI_H
#define SS_ABI_H

#include <stdint.h>

typedef enum {
    SS_ABI_FRICTION_CONFIG_F32 = 0,
    SS_ABI_ACTUATOR_CONFIG_F32 = 1,
    SS_ABI_ACTUATOR_STATE_F32 = 2,
    SS_ABI_WAVEFORM_CONFIG_F32 = 3,
    SS_ABI_WAVEFORM_STATE_F32 = 4,
    SS_ABI_LS_STATE_F32 = 5,
    SS_ABI_LUGRE_STATE_F32 = 6,
    SS_ABI_ACTUATOR_TRACE_F32 = 7,
    SS_ABI_FRICTION_CONFIG_Q = 8,
    SS_ABI_ACTUATOR_CONFIG_Q = 9,
    SS_ABI_ACTUATOR_STATE_Q = 10,
    SS_ABI_WAVEFORM_CONFIG_Q = 11,
    SS_ABI_WAVEFORM_STATE_Q = 12,
    SS_ABI_LS_STATE_Q = 13,
    SS_ABI_LUGRE_STATE_Q = 14,
    SS_ABI_ACTUATOR_TRACE_Q = 15,
    SS_ABI_ACTUATOR_SI = 16,
    SS_ABI_EFFECTS_CONFIG_F32 = 20,
    SS_ABI_GMS_STATE_F32 = 21,
    SS_ABI_FRICTION_MU_F32 = 22,
    SS_ABI_ACTUATOR_RUN_JOB_F32 = 23,
    SS_ABI_ACTUATOR_COARSE_F32 = 24,
    SS_ABI_ACTUATOR_COARSE_Q = 25
} ss_abi_struct_t;

/* sizeof the struct, or 0 for an unknown id. */
uint32_t ss_abi_sizeof(int32_t which);

/* Entry i of the table of the q family's signals, named as their struct fields (trace columns and
 * state fields, "ls." / "lugre." for the friction states, config fields): the shift n of its Q
 * format (SI value = integer * 2^-n) and its name in *name; -1 (and *name NULL) past the end. */
int32_t ss_abi_qformat(uint32_t i, const char **name);

#endif /* SS_ABI_H */
