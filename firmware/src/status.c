/* Names of the status codes of types.h: "AOCS_<ID>" of every aocs/status.def row, in enum order. */
#include "aocs/types.h"

#define STATUS_NAME_ROW(ID, MEANING) "AOCS_" #ID,

const char *aocs_status_name(aocs_status_t status)
{
    static const char *const status_names[AOCS_STATUS_COUNT] = {AOCS_STATUS_ROWS(STATUS_NAME_ROW)};
    const char *name = "AOCS_STATUS_UNKNOWN";
    if (((int)status >= 0) && (status < AOCS_STATUS_COUNT)) {
        name = status_names[status];
    }
    return name;
}
