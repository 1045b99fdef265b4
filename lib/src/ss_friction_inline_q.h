/* The q family's friction helpers that the laws share inline (internal). */
#ifndef SS_FRICTION_INLINE_Q_H
#define SS_FRICTION_INLINE_Q_H

#include "ss_fixed_ops.h"
#include "ss_friction_q.h"
#include "ss_inline.h"

/* 1/g = m 2^-*shift for a Stribeck level g (N at 2^-24, in (0, 2^31)), as ss_reciprocal_mantissa_q
 * gives it: Fc's from the config where g is Fc (gross sliding: the exponential's excess is 0), the
 * same bits as computing it, which costs 45 instructions on the Cortex-M3 and 220 on the M0+. */
SS_FORCE_INLINE int32_t ss_stribeck_recip_q(const ss_friction_config_q_t *cfg, int64_t g, int *shift)
{
    if (g == cfg->fc_q24) {
        *shift = cfg->fc_recip_shift;
        return cfg->fc_recip_mantissa;
    }
    return ss_reciprocal_mantissa_q((uint32_t)g, shift);
}

#endif /* SS_FRICTION_INLINE_Q_H */
