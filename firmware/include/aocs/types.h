/*
 * AOCS firmware: basic types, status codes and the real_t switch.
 *
 * real_t is double by default; configure with -DAOCS_REAL_FLOAT=ON (CMake
 * preset host-float or cortex-m4f) to build every module in single precision.
 * All math goes through the AOCS_* wrappers below so that a float build never
 * promotes to double (-Wdouble-promotion is an error on every build).
 */
#ifndef AOCS_TYPES_H
#define AOCS_TYPES_H

#include <stdint.h>
#include <math.h>

#include "aocs/status.def"

#if defined(AOCS_REAL_IS_FLOAT)
typedef float real_t;
#define AOCS_R(x) ((real_t)(x))
#define AOCS_SQRT(x) sqrtf(x)
#define AOCS_FABS(x) fabsf(x)
#define AOCS_SIN(x) sinf(x)
#define AOCS_COS(x) cosf(x)
#define AOCS_TAN(x) tanf(x)
#define AOCS_ASIN(x) asinf(x)
#define AOCS_ACOS(x) acosf(x)
#define AOCS_ATAN(x) atanf(x)
#define AOCS_ATAN2(y, x) atan2f((y), (x))
#define AOCS_TANH(x) tanhf(x)
#define AOCS_LOG(x) logf(x)
#define AOCS_LOG1P(x) log1pf(x)
#define AOCS_REAL_EPS AOCS_R(1.1920929e-07)
#define AOCS_REAL_MAX AOCS_R(3.40282347e+38)
#else
typedef double real_t;
#define AOCS_R(x) ((real_t)(x))
#define AOCS_SQRT(x) sqrt(x)
#define AOCS_FABS(x) fabs(x)
#define AOCS_SIN(x) sin(x)
#define AOCS_COS(x) cos(x)
#define AOCS_TAN(x) tan(x)
#define AOCS_ASIN(x) asin(x)
#define AOCS_ACOS(x) acos(x)
#define AOCS_ATAN(x) atan(x)
#define AOCS_ATAN2(y, x) atan2((y), (x))
#define AOCS_TANH(x) tanh(x)
#define AOCS_LOG(x) log(x)
#define AOCS_LOG1P(x) log1p(x)
#define AOCS_REAL_EPS AOCS_R(2.220446049250313e-16)
#define AOCS_REAL_MAX AOCS_R(1.7976931348623157e+308)
#endif

/* true when x is neither NaN nor +-Inf */
#define AOCS_IS_FINITE(x) (isfinite(x) != 0)

/*
 * Status codes. Every init/step function returns one; every invalid
 * configuration value has its own code so a test (and a user) can tell
 * exactly which check failed. aocs_status_name() gives the text. The codes
 * and their meanings are the rows of aocs/status.def (AOCS_OK = 0, then in
 * row order), then AOCS_STATUS_COUNT (number of codes, keep last).
 */
#define AOCS_STATUS_ENUM_ROW(ID, MEANING) AOCS_##ID,
typedef enum {
    AOCS_STATUS_ROWS(AOCS_STATUS_ENUM_ROW)
    AOCS_STATUS_COUNT
} aocs_status_t;

/* Human-readable name of a status code ("AOCS_ERR_GAIN_NOT_POSITIVE"). */
const char *aocs_status_name(aocs_status_t status);

#endif /* AOCS_TYPES_H */
