/* The Q format of every signal of the fixed-point (_q) family, in one place: the number of
 * fraction bits n, so that the SI value is the integer times 2^-n. Integer only (no float), so the
 * q-only firmware library includes it too; the host converter (ss_convert_q.h) and the Python
 * binding (ss_abi_qformat, ss_abi.h) read the shifts here. Ranges: docs/fixed-point.md. */
#ifndef SS_QFORMAT_H
#define SS_QFORMAT_H

/* Quantities: a signal's suffix (_q40, _q28, ...) repeats its quantity's shift. */
#define SS_QF_LENGTH 40   /* m at 2^-40 (_q40): positions, strain, bristle deflection */
#define SS_QF_TIME 40     /* s at 2^-40 (dt_q40) */
#define SS_QF_VELOCITY 28 /* m/s at 2^-28 (_q28) */
#define SS_QF_FORCE 24    /* N at 2^-24 (_q24) */
#define SS_QF_VOLTAGE 16  /* V in Q16.16 (drive_q16, amplitude_q16, offset_q16) */
#define SS_QF_DAMPING 16  /* N s/m in Q16.16 (sigma1_q16, sigma2_q16, dF/dv) */
#define SS_QF_GAIN 48     /* m/V at 2^-48 (piezo_gain_q48) */
#define SS_QF_KICK 40     /* (m/s)/N at 2^-40 (kick_rod_q40, kick_slider_q40) */
#define SS_QF_LAG 24      /* c / (k dt), Q8.24 (lag_q24) */
#define SS_QF_FLOW 28     /* rod flow matrix, Q4.28 (phi_q28) */
#define SS_QF_RATIO 30    /* ratios and exp(-x), Q1.30 (_q30) */
#define SS_QF_FRACTION 32 /* fraction of a period at 2^-32 (rise_q32, phase) */

/* A velocity from a length over a time: (dx_q40 << SS_QF_DXDT) / dt_q40 is at 2^-28 m/s. */
#define SS_QF_DXDT (SS_QF_VELOCITY + SS_QF_TIME - SS_QF_LENGTH)

/* A length from a force over a stiffness in whole N/m: (f_q24 << SS_QF_F_OVER_K) / sigma0 is at
 * 2^-40 m. */
#define SS_QF_F_OVER_K (SS_QF_LENGTH - SS_QF_FORCE)

#endif /* SS_QFORMAT_H */
