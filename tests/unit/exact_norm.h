/*
 * Reference norm for the saturation checks (unit tests and fuzz targets):
 * |v|_2 in long double with max-abs scaling, so it neither overflows nor
 * underflows for any finite double components, and rounds far below one ulp
 * of a double: a check "exact_norm(u) <= max_norm" is then a real bound, not
 * "within an ulp". Test code only (long double, math library).
 */
#ifndef AOCS_TESTS_EXACT_NORM_H
#define AOCS_TESTS_EXACT_NORM_H

#include <math.h>

#include "aocs/math3.h"

static inline long double exact_norm(aocs_vec3_t v)
{
    long double m = 0.0L;
    long double s = 0.0L;
    for (int i = 0; i < 3; ++i) {
        long double a = fabsl((long double)v.v[i]);
        if (a > m) {
            m = a;
        }
    }
    if (!(m > 0.0L)) {
        return 0.0L;
    }
    for (int i = 0; i < 3; ++i) {
        long double r = (long double)v.v[i] / m;
        s += r * r;
    }
    return m * sqrtl(s);
}

#endif /* AOCS_TESTS_EXACT_NORM_H */
