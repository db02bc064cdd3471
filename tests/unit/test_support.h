/*
 * Shared helpers for the cmocka unit tests: tolerances that follow real_t,
 * the SPEC 1 attitude matrix in double, a seeded random generator
 * (repeatable on every machine), random attitudes.
 */
#ifndef AOCS_TEST_SUPPORT_H
#define AOCS_TEST_SUPPORT_H

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <math.h>
#include <stdio.h>
#include <cmocka.h>

#include "aocs/types.h"
#include "aocs/math3.h"
#include "aocs/attitude.h"

#if defined(AOCS_REAL_IS_FLOAT)
#define TOL_TIGHT 2.0e-5 /* a few float ulps after a handful of operations */
#define TOL_LOOSE 2.0e-3
#else
#define TOL_TIGHT 1.0e-12
#define TOL_LOOSE 1.0e-7
#endif

/* assert |a - b| <= tol * max(1, |b|), printing both values on failure */
#define assert_close(a, b, tol) assert_close_impl((double)(a), (double)(b), (tol), #a, __FILE__, __LINE__)

static inline void assert_close_impl(double a, double b, double tol, const char *what,
                                     const char *file, int line)
{
    double scale = fabs(b) > 1.0 ? fabs(b) : 1.0;
    if (!(fabs(a - b) <= tol * scale)) {
        print_error("%s:%d: %s = %.17g, expected %.17g (tol %.3g)\n", file, line, what, a, b, tol);
        fail();
    }
}

#define assert_vec3_close(a, b, tol)                                   \
    do {                                                               \
        aocs_vec3_t a_ = (a);                                          \
        aocs_vec3_t b_ = (b);                                          \
        for (int i_ = 0; i_ < 3; ++i_) {                               \
            assert_close(a_.v[i_], b_.v[i_], (tol));                   \
        }                                                              \
    } while (0)

/* A(q) of SPEC 1 written out element by element, in double (never the firmware's aocs_quat_to_dcm) */
static inline void ref_dcm(aocs_quat_t qr, double a[3][3])
{
    double q1 = (double)qr.q[0], q2 = (double)qr.q[1], q3 = (double)qr.q[2], q4 = (double)qr.q[3];
    a[0][0] = q1 * q1 - q2 * q2 - q3 * q3 + q4 * q4;
    a[0][1] = 2.0 * (q1 * q2 + q3 * q4);
    a[0][2] = 2.0 * (q1 * q3 - q2 * q4);
    a[1][0] = 2.0 * (q1 * q2 - q3 * q4);
    a[1][1] = -q1 * q1 + q2 * q2 - q3 * q3 + q4 * q4;
    a[1][2] = 2.0 * (q2 * q3 + q1 * q4);
    a[2][0] = 2.0 * (q1 * q3 + q2 * q4);
    a[2][1] = 2.0 * (q2 * q3 - q1 * q4);
    a[2][2] = -q1 * q1 - q2 * q2 + q3 * q3 + q4 * q4;
}

/* xorshift64*: deterministic, no libc state */
typedef struct {
    uint64_t s;
} test_rng_t;

static inline uint64_t test_rng_next(test_rng_t *r)
{
    r->s ^= r->s >> 12;
    r->s ^= r->s << 25;
    r->s ^= r->s >> 27;
    return r->s * 2685821657736338717ULL;
}

/* uniform in [lo, hi) */
static inline double test_rng_uniform(test_rng_t *r, double lo, double hi)
{
    double u = (double)(test_rng_next(r) >> 11) * (1.0 / 9007199254740992.0);
    return lo + (hi - lo) * u;
}

/* standard normal by Box-Muller */
static inline double test_rng_normal(test_rng_t *r)
{
    double u1 = test_rng_uniform(r, 1e-300, 1.0);
    double u2 = test_rng_uniform(r, 0.0, 1.0);
    return sqrt(-2.0 * log(u1)) * cos(6.283185307179586 * u2);
}

/* uniformly distributed unit quaternion (normalised 4-D Gaussian) */
static inline aocs_quat_t test_random_quat(test_rng_t *r)
{
    double g[4];
    double n = 0.0;
    for (int i = 0; i < 4; ++i) {
        g[i] = test_rng_normal(r);
        n += g[i] * g[i];
    }
    n = sqrt(n);
    return aocs_quat_make((real_t)(g[0] / n), (real_t)(g[1] / n), (real_t)(g[2] / n), (real_t)(g[3] / n));
}

static inline aocs_vec3_t test_random_vec3(test_rng_t *r, double scale)
{
    return aocs_vec3_make((real_t)(scale * test_rng_uniform(r, -1.0, 1.0)),
                          (real_t)(scale * test_rng_uniform(r, -1.0, 1.0)),
                          (real_t)(scale * test_rng_uniform(r, -1.0, 1.0)));
}

#endif /* AOCS_TEST_SUPPORT_H */
