/* Names of the status codes of types.h, in enum order. */
#include "aocs/types.h"

const char *aocs_status_name(aocs_status_t status)
{
    static const char *const status_names[AOCS_STATUS_COUNT] = {
        "AOCS_OK",
        "AOCS_ERR_NULL_ARG",
        "AOCS_ERR_PARAM_NOT_FINITE",
        "AOCS_ERR_GAIN_NOT_POSITIVE",
        "AOCS_ERR_INERTIA_NOT_SYMMETRIC",
        "AOCS_ERR_INERTIA_NOT_POS_DEF",
        "AOCS_ERR_INERTIA_SINGULAR",
        "AOCS_ERR_SAT_L1_NOT_EQUAL_M1",
        "AOCS_ERR_SAT_M1_NOT_BELOW_L2",
        "AOCS_ERR_SAT_L2_ABOVE_M2",
        "AOCS_ERR_SAT_M2_ABOVE_UMAX",
        "AOCS_ERR_SAT_LIMIT_NOT_POSITIVE",
        "AOCS_ERR_BOUNDARY_LAYER_NOT_POSITIVE",
        "AOCS_ERR_MASS_NOT_POSITIVE",
        "AOCS_ERR_ORBIT_RATE_NOT_POSITIVE",
        "AOCS_ERR_GAIN_TABLE_INVALID",
        "AOCS_ERR_DT_INVALID",
        "AOCS_ERR_INPUT_NOT_FINITE",
        "AOCS_ERR_QUAT_NOT_UNIT",
        "AOCS_ERR_CRP_SINGULAR",
        "AOCS_ERR_NOT_INITIALISED",
        "AOCS_ERR_UNKNOWN_LAW",
        "AOCS_ERR_MODE_INVALID",
        "AOCS_ERR_TARGET_INVALID",
        "AOCS_ERR_INPUT_STALE",
        "AOCS_ERR_INPUT_MISSING",
        "AOCS_ERR_RATE_INVALID",
        "AOCS_ERR_INPUT_INVALID",
        "AOCS_ERR_OUTPUT_NOT_FINITE",
        "AOCS_ERR_GAIN_TABLE_UNKNOWN",
        "AOCS_ERR_GAIN_TABLE_WRONG_LAW",
    };
    const char *name = "AOCS_STATUS_UNKNOWN";
    if (((int)status >= 0) && (status < AOCS_STATUS_COUNT)) {
        name = status_names[status];
    }
    return name;
}
