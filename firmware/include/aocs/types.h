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
 * exactly which check failed. aocs_status_name() gives the text.
 */
typedef enum {
    AOCS_OK = 0,
    AOCS_ERR_NULL_ARG,             /* a required pointer was NULL */
    AOCS_ERR_PARAM_NOT_FINITE,     /* NaN or Inf in a configuration value */
    AOCS_ERR_GAIN_NOT_POSITIVE,    /* a gain that must be > 0 is <= 0 */
    AOCS_ERR_INERTIA_NOT_SYMMETRIC,
    AOCS_ERR_INERTIA_NOT_POS_DEF,  /* inertia has a non-positive eigenvalue */
    AOCS_ERR_INERTIA_SINGULAR,     /* inverse would divide by ~0 */
    AOCS_ERR_SAT_L1_NOT_EQUAL_M1,  /* mrp_sat: L1 = M1 violated */
    AOCS_ERR_SAT_M1_NOT_BELOW_L2,  /* mrp_sat: M1 < L2 violated */
    AOCS_ERR_SAT_L2_ABOVE_M2,      /* mrp_sat: L2 <= M2 violated */
    AOCS_ERR_SAT_M2_ABOVE_UMAX,    /* mrp_sat: M2 <= (2/sqrt 3) uM violated */
    AOCS_ERR_SAT_LIMIT_NOT_POSITIVE, /* a saturation level or torque limit <= 0 */
    AOCS_ERR_BOUNDARY_LAYER_NOT_POSITIVE, /* smc: eps_i <= 0 */
    AOCS_ERR_MASS_NOT_POSITIVE,    /* orbit_lqr: m <= 0 */
    AOCS_ERR_ORBIT_RATE_NOT_POSITIVE,
    AOCS_ERR_GAIN_TABLE_INVALID,   /* LQR / H-inf table not finite or wrong sign */
    AOCS_ERR_DT_INVALID,           /* time step not finite or <= 0 */
    AOCS_ERR_INPUT_NOT_FINITE,     /* NaN or Inf in a step input */
    AOCS_ERR_QUAT_NOT_UNIT,        /* attitude quaternion norm far from 1 */
    AOCS_ERR_CRP_SINGULAR,         /* Gibbs vector not representable (180 deg) */
    AOCS_ERR_NOT_INITIALISED,      /* step called before a successful init */
    AOCS_ERR_UNKNOWN_LAW,
    AOCS_ERR_MODE_INVALID,
    AOCS_ERR_TARGET_INVALID,
    AOCS_ERR_INPUT_STALE,
    AOCS_ERR_INPUT_MISSING,
    AOCS_ERR_RATE_INVALID,         /* executive: control rate not usable */
    AOCS_ERR_INPUT_INVALID,        /* a sensor validity flag is off */
    AOCS_ERR_OUTPUT_NOT_FINITE,    /* finite inputs made the law's output overflow */
    AOCS_ERR_GAIN_TABLE_UNKNOWN,   /* no compiled gain table of that name / id */
    AOCS_ERR_GAIN_TABLE_WRONG_LAW, /* the gain table was designed for another law */
    AOCS_STATUS_COUNT              /* number of codes, keep last */
} aocs_status_t;

/* Human-readable name of a status code ("AOCS_ERR_GAIN_NOT_POSITIVE"). */
const char *aocs_status_name(aocs_status_t status);

#endif /* AOCS_TYPES_H */
