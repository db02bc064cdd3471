/*
 * Shared saturation helpers (saturate.h). All functions are total; the
 * handling of NaN / Inf / invalid limits is documented in the header.
 */
#include <stddef.h>

#include "aocs/control/saturate.h"

/* +1 for x > 0, -1 for x < 0, 0 for 0 and NaN */
static real_t sat_sign(real_t x)
{
    real_t s = AOCS_R(0.0);
    if (x > AOCS_R(0.0)) {
        s = AOCS_R(1.0);
    } else if (x < AOCS_R(0.0)) {
        s = AOCS_R(-1.0);
    } else {
        s = AOCS_R(0.0);
    }
    return s;
}

/* x clamped to [-lim, lim] for lim >= 0 (lim may be +Inf); NaN x gives 0 */
static real_t sat_clamp(real_t x, real_t lim, int *changed)
{
    real_t y = AOCS_R(0.0);
    *changed = 1;
    if (isnan(x) != 0) {
        y = AOCS_R(0.0);
    } else if (x > lim) {
        y = lim;
    } else if (x < -lim) {
        y = -lim;
    } else {
        y = x;
        *changed = 0;
    }
    return y;
}

aocs_vec3_t aocs_sat_clamp_per_axis(aocs_vec3_t u, aocs_vec3_t limit, int *saturated)
{
    aocs_vec3_t out;
    int any = 0;
    for (int i = 0; i < 3; ++i) {
        int changed = 0;
        /* a limit that is NaN or <= 0 allows nothing on that axis */
        real_t lim = (limit.v[i] > AOCS_R(0.0)) ? limit.v[i] : AOCS_R(0.0);
        out.v[i] = sat_clamp(u.v[i], lim, &changed);
        if (changed != 0) {
            any = 1;
        }
    }
    if (saturated != NULL) {
        *saturated = any;
    }
    return out;
}

/*
 * |v|_2 of a finite vector without overflow or underflow: amax * sqrt(sum
 * (v_i / amax)^2). Returns amax in *amax_out and the root in *root_out
 * (root in [1, sqrt 3] when amax > 0). A quotient v_i / amax that underflows
 * belongs to a component below amax * REAL_MIN: its error is far below one
 * ulp of the norm.
 */
static void sat_norm_parts(const real_t v[3], real_t *amax_out, real_t *root_out)
{
    real_t amax = AOCS_R(0.0);
    real_t sum = AOCS_R(0.0);
    for (int i = 0; i < 3; ++i) {
        real_t a = AOCS_FABS(v[i]);
        if (a > amax) {
            amax = a;
        }
    }
    if (amax > AOCS_R(0.0)) {
        for (int i = 0; i < 3; ++i) {
            real_t r = v[i] / amax;
            sum += r * r;
        }
    }
    *amax_out = amax;
    *root_out = AOCS_SQRT(sum);
}

/*
 * 1 when the norm of the finite vector v, computed as amax * root, exceeds
 * lim (compared as root > lim / amax: no overflow of the norm itself; the
 * quotient underflows to 0 only when amax is far above lim). The computed
 * root is within 3 eps (relative) of the exact one.
 */
static int sat_norm_above(const real_t v[3], real_t lim)
{
    real_t amax = AOCS_R(0.0);
    real_t root = AOCS_R(0.0);
    sat_norm_parts(v, &amax, &root);
    return ((amax > AOCS_R(0.0)) && (root > (lim / amax))) ? 1 : 0;
}

int aocs_sat_norm_above(aocs_vec3_t v, real_t limit)
{
    int above = 1;
    if ((aocs_vec3_is_finite(v) != 0) && (isnan(limit) == 0)) {
        above = (isinf(limit) != 0) ? 0 : sat_norm_above(v.v, limit);
    }
    return above;
}

/*
 * Norm margin: the computed norm of the result is at most
 * max_norm (1 - SAT_NORM_MARGIN); its error is below 3 eps (sat_norm_above),
 * so the exact norm stays below max_norm with room to spare, whoever
 * evaluates it and in whichever precision.
 */
#define SAT_NORM_MARGIN (AOCS_R(8.0) * AOCS_REAL_EPS)
/* shrink steps of the final pull-back: a few of (1 - 4 eps), then halvings (subnormal results) */
#define SAT_SHRINK_FINE_STEPS 4
#define SAT_SHRINK_MAX_STEPS 64

aocs_vec3_t aocs_sat_scale_to_norm(aocs_vec3_t u, real_t max_norm, int *saturated)
{
    aocs_vec3_t out = u;
    int sat = 0;
    int has_nan = 0;
    int has_inf = 0;
    int nonzero = 0;

    for (int i = 0; i < 3; ++i) {
        if (isnan(u.v[i]) != 0) {
            has_nan = 1;
        } else if (isinf(u.v[i]) != 0) {
            has_inf = 1;
        } else {
            /* finite */
        }
        if (!(AOCS_FABS(u.v[i]) <= AOCS_R(0.0))) {
            nonzero = 1; /* also true for NaN */
        }
    }

    if ((!(max_norm > AOCS_R(0.0))) || (has_nan != 0)) {
        for (int i = 0; i < 3; ++i) {
            out.v[i] = AOCS_R(0.0);
        }
        sat = nonzero;
    } else if (isinf(max_norm) != 0) {
        /* no limit: out = u */
    } else {
        const real_t thr = max_norm * (AOCS_R(1.0) - SAT_NORM_MARGIN);
        real_t dir[3];
        if (has_inf != 0) {
            /* direction of the infinite components only (their limit ratio) */
            for (int i = 0; i < 3; ++i) {
                dir[i] = (isinf(u.v[i]) != 0) ? sat_sign(u.v[i]) : AOCS_R(0.0);
            }
        } else {
            for (int i = 0; i < 3; ++i) {
                dir[i] = u.v[i];
            }
        }
        if ((has_inf != 0) || (sat_norm_above(dir, thr) != 0)) {
            real_t amax = AOCS_R(0.0);
            real_t root = AOCS_R(0.0);
            real_t f;
            int k = 0;
            sat_norm_parts(dir, &amax, &root);
            /*
             * out = (u / amax) (max_norm / root): each factor is scale-free
             * (|u_i / amax| <= 1, root in [1, sqrt 3]), so nothing overflows
             * or underflows whatever the magnitude of u and of the limit;
             * forming max_norm / |u| first would underflow for a huge u.
             */
            f = max_norm / root;
            for (int i = 0; i < 3; ++i) {
                out.v[i] = (dir[i] / amax) * f;
            }
            /* roundings land within a few eps of max_norm: pull back below the margin */
            while ((k < SAT_SHRINK_MAX_STEPS) && (sat_norm_above(out.v, thr) != 0)) {
                const real_t shrink = (k < SAT_SHRINK_FINE_STEPS) ? (AOCS_R(1.0) - (AOCS_R(4.0) * AOCS_REAL_EPS))
                                                                  : AOCS_R(0.5);
                for (int i = 0; i < 3; ++i) {
                    out.v[i] *= shrink;
                }
                ++k;
            }
            if (sat_norm_above(out.v, thr) != 0) {
                for (int i = 0; i < 3; ++i) {
                    out.v[i] = AOCS_R(0.0); /* not reachable for a normal max_norm; zero is within any limit */
                }
            }
            sat = 1;
        }
    }
    if (saturated != NULL) {
        *saturated = sat;
    }
    return out;
}

real_t aocs_sat_linear(real_t x, real_t l, real_t m)
{
    real_t y = AOCS_R(0.0);
    if ((!(m > AOCS_R(0.0))) || (isnan(x) != 0)) {
        y = AOCS_R(0.0);
    } else if (isinf(m) != 0) {
        y = x; /* limit m -> Inf of the formula: identity */
    } else {
        real_t lv = (l > AOCS_R(0.0)) ? l : AOCS_R(0.0);
        real_t ax = AOCS_FABS(x);
        if (lv >= m) {
            /* plain clamp (l = m) */
            y = (ax > m) ? (sat_sign(x) * m) : x;
        } else if (ax <= lv) {
            y = x;
        } else {
            /* Gao, Lu, Wang 2010 linear saturation, smooth tail (saturate.h) */
            real_t span = m - lv;
            real_t mag = lv + (span * AOCS_TANH((ax - lv) / span));
            if (mag > m) {
                mag = m; /* rounding of lv + span */
            }
            y = sat_sign(x) * mag;
        }
    }
    return y;
}

real_t aocs_sat_tanh(real_t x, real_t m)
{
    real_t y = AOCS_R(0.0);
    if ((!(m > AOCS_R(0.0))) || (isnan(x) != 0)) {
        y = AOCS_R(0.0);
    } else if (isinf(m) != 0) {
        y = x;
    } else {
        /* SPEC 2.7 generalised saturation; |tanh| <= 1 so |y| <= m exactly */
        y = m * AOCS_TANH(x / m);
    }
    return y;
}

real_t aocs_sat_boundary_layer(real_t s, real_t eps)
{
    real_t y = AOCS_R(0.0);
    if (isnan(s) != 0) {
        y = AOCS_R(0.0);
    } else if (!(eps > AOCS_R(0.0))) {
        y = sat_sign(s);
    } else if (s > eps) {
        y = AOCS_R(1.0);
    } else if (s < -eps) {
        y = AOCS_R(-1.0);
    } else if (isinf(eps) != 0) {
        y = AOCS_R(0.0);
    } else {
        /* SPEC 2.4: |s| <= eps, so |s / eps| <= 1 after correct rounding */
        y = s / eps;
    }
    return y;
}
