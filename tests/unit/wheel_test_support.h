/*
 * The reference wheel array of the unit tests: the SPEC 5.3 pyramid about z
 * (cant acos(1/sqrt 3), azimuths 0, 90, 180, 270 deg from x; docs/spec.md
 * 5.3), four wheels of 0.08 kg m^2, 0.25 N m and 600 rad/s, the IRASSI
 * inertia, no friction model and no null-space management.
 */
#ifndef AOCS_WHEEL_TEST_SUPPORT_H
#define AOCS_WHEEL_TEST_SUPPORT_H

#include <math.h>

#include "aocs/actuation/wheel_array.h"

#define TEST_WHEEL_JS_KGM2 0.08
#define TEST_WHEEL_U_MAX_NM 0.25
#define TEST_WHEEL_OMEGA_MAX_RADPS 600.0

/* A tachometer reading far beyond any wheel (issue 25 item 1): 1e308 in double, the largest float in float
 * (1e308 is not a float). */
#if defined(AOCS_REAL_IS_FLOAT)
#define TEST_WHEEL_TACH_HUGE AOCS_REAL_MAX
#define TEST_NEXT_UP(x) nextafterf((x), INFINITY)
#else
#define TEST_WHEEL_TACH_HUGE 1e308
#define TEST_NEXT_UP(x) nextafter((x), INFINITY)
#endif

static inline void test_wheels_pyramid(aocs_wheels_config_t *w)
{
    const double beta = acos(1.0 / sqrt(3.0));
    aocs_wheels_config_default(w);
    w->n = 4u;
    for (uint32_t i = 0u; i < 4u; ++i) {
        const double az = 0.5 * 3.14159265358979323846 * (double)i;
        w->axis_B[i] = aocs_vec3_make((real_t)(sin(beta) * cos(az)), (real_t)(sin(beta) * sin(az)), (real_t)cos(beta));
        w->js_kgm2[i] = AOCS_R(TEST_WHEEL_JS_KGM2);
        w->u_max_nm[i] = AOCS_R(TEST_WHEEL_U_MAX_NM);
        w->omega_max_radps[i] = AOCS_R(TEST_WHEEL_OMEGA_MAX_RADPS);
    }
    w->inertia_B_kgm2 = aocs_mat3_diag(aocs_vec3_make(AOCS_R(2059.5), AOCS_R(5954.2), AOCS_R(5974.3)));
}

#endif /* AOCS_WHEEL_TEST_SUPPORT_H */
