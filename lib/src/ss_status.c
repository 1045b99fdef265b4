#include "ss_status.h"

const char *ss_status_str(ss_status_t status)
{
    switch (status) {
    case SS_OK: return "ok";
    case SS_ERR_NULL: return "null pointer";
    case SS_ERR_RANGE: return "parameter out of range";
    case SS_ERR_NONFINITE: return "non-finite value (NaN or infinity)";
    case SS_ERR_STATE: return "invalid state for this call";
    default: return "unknown status";
    }
}
