/* Status codes shared by every stickslip module.
 * Errors are negative, as in littlefs; SS_OK is zero so `if (st)` tests for failure. */
#ifndef SS_STATUS_H
#define SS_STATUS_H

typedef enum {
    SS_OK = 0,
    SS_ERR_NULL = -1,      /* a required pointer was NULL */
    SS_ERR_RANGE = -2,     /* a parameter is outside its documented range */
    SS_ERR_NONFINITE = -3, /* a parameter or input is NaN or infinite */
    SS_ERR_STATE = -4      /* the call does not fit the object's state (e.g. not initialised) */
} ss_status_t;

/* Short, static, human-readable message for a status (never NULL). */
const char *ss_status_str(ss_status_t status);

#endif /* SS_STATUS_H */
