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
 * (root in [1, sqrt 3] when amax > 0).
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
        real_t dir[3];
        real_t amax = AOCS_R(0.0);
        real_t root = AOCS_R(0.0);
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
        sat_norm_parts(dir, &amax, &root);
        /* |u| > max_norm  <=>  root > max_norm / amax (no overflow of |u|) */
        if ((has_inf != 0) || ((amax > AOCS_R(0.0)) && (root > (max_norm / amax)))) {
            real_t f = max_norm / root;
            real_t amax2 = AOCS_R(0.0);
            real_t root2 = AOCS_R(0.0);
            for (int i = 0; i < 3; ++i) {
                out.v[i] = (dir[i] / amax) * f;
            }
            /* rounding may land a few ulps above max_norm: pull it back */
            sat_norm_parts(out.v, &amax2, &root2);
            if (root2 > (max_norm / amax2)) {
                real_t shrink = AOCS_R(1.0) - (AOCS_R(4.0) * AOCS_REAL_EPS);
                for (int i = 0; i < 3; ++i) {
                    out.v[i] *= shrink;
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
