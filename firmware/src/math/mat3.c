/*
 * 3x3 matrices (math3.h), row-major m[row][col].
 *
 * Singularity rule (docs/conventions.md "Matrix inverse"): the rows are first
 * scaled by their largest element (so the test does not depend on units and
 * cannot overflow), then the matrix is declared singular when
 *     |det(As)| <= AOCS_MAT3_SINGULAR_RTOL * |r1| |r2| |r3|
 * where r_i are the scaled rows. By Hadamard's inequality the ratio
 * |det| / prod |r_i| lies in [0, 1] (1 for orthogonal rows), so the threshold
 * is a dimensionless measure of how close the rows are to linear dependence.
 */
#include <stddef.h>

#include "aocs/math3.h"

/* 1e3 machine epsilons: 2.2e-13 in double, 1.2e-4 in float */
#define AOCS_MAT3_SINGULAR_RTOL (AOCS_R(1.0e3) * AOCS_REAL_EPS)

/*
 * Symmetry tolerance of an inertia matrix, relative to its largest element
 * (docs/conventions.md "Inertia check"); the same in both precisions, about
 * 8 float ulps, far above rounding of a symmetric matrix typed in decimal.
 */
#define AOCS_INERTIA_SYM_RTOL AOCS_R(1.0e-6)

aocs_mat3_t aocs_mat3_zero(void)
{
    aocs_mat3_t r;
    int i;
    int j;
    for (i = 0; i < 3; ++i) {
        for (j = 0; j < 3; ++j) {
            r.m[i][j] = AOCS_R(0.0);
        }
    }
    return r;
}

aocs_mat3_t aocs_mat3_identity(void)
{
    aocs_mat3_t r = aocs_mat3_zero();
    r.m[0][0] = AOCS_R(1.0);
    r.m[1][1] = AOCS_R(1.0);
    r.m[2][2] = AOCS_R(1.0);
    return r;
}

aocs_mat3_t aocs_mat3_diag(aocs_vec3_t d)
{
    aocs_mat3_t r = aocs_mat3_zero();
    r.m[0][0] = d.v[0];
    r.m[1][1] = d.v[1];
    r.m[2][2] = d.v[2];
    return r;
}

aocs_mat3_t aocs_mat3_add(aocs_mat3_t a, aocs_mat3_t b)
{
    aocs_mat3_t r;
    int i;
    int j;
    for (i = 0; i < 3; ++i) {
        for (j = 0; j < 3; ++j) {
            r.m[i][j] = a.m[i][j] + b.m[i][j];
        }
    }
    return r;
}

aocs_mat3_t aocs_mat3_scale(aocs_mat3_t a, real_t s)
{
    aocs_mat3_t r;
    int i;
    int j;
    for (i = 0; i < 3; ++i) {
        for (j = 0; j < 3; ++j) {
            r.m[i][j] = a.m[i][j] * s;
        }
    }
    return r;
}

aocs_mat3_t aocs_mat3_mul(aocs_mat3_t a, aocs_mat3_t b)
{
    aocs_mat3_t r;
    int i;
    int j;
    for (i = 0; i < 3; ++i) {
        for (j = 0; j < 3; ++j) {
            r.m[i][j] = (a.m[i][0] * b.m[0][j]) + (a.m[i][1] * b.m[1][j]) + (a.m[i][2] * b.m[2][j]);
        }
    }
    return r;
}

aocs_mat3_t aocs_mat3_transpose(aocs_mat3_t a)
{
    aocs_mat3_t r;
    int i;
    int j;
    for (i = 0; i < 3; ++i) {
        for (j = 0; j < 3; ++j) {
            r.m[i][j] = a.m[j][i];
        }
    }
    return r;
}

aocs_vec3_t aocs_mat3_mul_vec(aocs_mat3_t a, aocs_vec3_t x)
{
    aocs_vec3_t r;
    int i;
    for (i = 0; i < 3; ++i) {
        r.v[i] = (a.m[i][0] * x.v[0]) + (a.m[i][1] * x.v[1]) + (a.m[i][2] * x.v[2]);
    }
    return r;
}

aocs_vec3_t aocs_mat3_tmul_vec(aocs_mat3_t a, aocs_vec3_t x)
{
    aocs_vec3_t r;
    int j;
    for (j = 0; j < 3; ++j) {
        r.v[j] = (a.m[0][j] * x.v[0]) + (a.m[1][j] * x.v[1]) + (a.m[2][j] * x.v[2]);
    }
    return r;
}

/* a^x = [[0,-a3,a2],[a3,0,-a1],[-a2,a1,0]] (SPEC 1) */
aocs_mat3_t aocs_mat3_skew(aocs_vec3_t a)
{
    aocs_mat3_t r = aocs_mat3_zero();
    r.m[0][1] = -a.v[2];
    r.m[0][2] = a.v[1];
    r.m[1][0] = a.v[2];
    r.m[1][2] = -a.v[0];
    r.m[2][0] = -a.v[1];
    r.m[2][1] = a.v[0];
    return r;
}

aocs_mat3_t aocs_mat3_outer(aocs_vec3_t a, aocs_vec3_t b)
{
    aocs_mat3_t r;
    int i;
    int j;
    for (i = 0; i < 3; ++i) {
        for (j = 0; j < 3; ++j) {
            r.m[i][j] = a.v[i] * b.v[j];
        }
    }
    return r;
}

/* cofactor expansion along the first row */
real_t aocs_mat3_det(aocs_mat3_t a)
{
    real_t c0 = (a.m[1][1] * a.m[2][2]) - (a.m[1][2] * a.m[2][1]);
    real_t c1 = (a.m[1][2] * a.m[2][0]) - (a.m[1][0] * a.m[2][2]);
    real_t c2 = (a.m[1][0] * a.m[2][1]) - (a.m[1][1] * a.m[2][0]);
    return (a.m[0][0] * c0) + (a.m[0][1] * c1) + (a.m[0][2] * c2);
}

int aocs_mat3_is_finite(aocs_mat3_t a)
{
    int ok = 1;
    int i;
    int j;
    for (i = 0; i < 3; ++i) {
        for (j = 0; j < 3; ++j) {
            if (!AOCS_IS_FINITE(a.m[i][j])) {
                ok = 0;
            }
        }
    }
    return ok;
}

/* adjugate (transposed cofactor matrix) */
static aocs_mat3_t mat3_adjugate(aocs_mat3_t a)
{
    aocs_mat3_t r;
    r.m[0][0] = (a.m[1][1] * a.m[2][2]) - (a.m[1][2] * a.m[2][1]);
    r.m[0][1] = (a.m[0][2] * a.m[2][1]) - (a.m[0][1] * a.m[2][2]);
    r.m[0][2] = (a.m[0][1] * a.m[1][2]) - (a.m[0][2] * a.m[1][1]);
    r.m[1][0] = (a.m[1][2] * a.m[2][0]) - (a.m[1][0] * a.m[2][2]);
    r.m[1][1] = (a.m[0][0] * a.m[2][2]) - (a.m[0][2] * a.m[2][0]);
    r.m[1][2] = (a.m[0][2] * a.m[1][0]) - (a.m[0][0] * a.m[1][2]);
    r.m[2][0] = (a.m[1][0] * a.m[2][1]) - (a.m[1][1] * a.m[2][0]);
    r.m[2][1] = (a.m[0][1] * a.m[2][0]) - (a.m[0][0] * a.m[2][1]);
    r.m[2][2] = (a.m[0][0] * a.m[1][1]) - (a.m[0][1] * a.m[1][0]);
    return r;
}

/*
 * A = D As with D = diag(row max |a_ij|), so A^-1 = As^-1 D^-1, i.e. column j
 * of As^-1 divided by d_j. Non-finite input gives AOCS_ERR_PARAM_NOT_FINITE.
 */
aocs_status_t aocs_mat3_inverse(aocs_mat3_t a, aocs_mat3_t *out)
{
    aocs_status_t st = AOCS_OK;
    aocs_mat3_t as;
    aocs_mat3_t inv;
    real_t d[3];
    real_t row_norm_prod = AOCS_R(1.0);
    real_t det_s;
    int i;
    int j;

    if (out == NULL) {
        st = AOCS_ERR_NULL_ARG;
    } else if (aocs_mat3_is_finite(a) == 0) {
        st = AOCS_ERR_PARAM_NOT_FINITE;
    } else {
        for (i = 0; i < 3; ++i) {
            d[i] = aocs_vec3_norm_inf(aocs_vec3_make(a.m[i][0], a.m[i][1], a.m[i][2]));
            if (!(d[i] > AOCS_R(0.0))) {
                st = AOCS_ERR_INERTIA_SINGULAR; /* a zero row */
            }
        }
        if (st == AOCS_OK) {
            for (i = 0; i < 3; ++i) {
                for (j = 0; j < 3; ++j) {
                    as.m[i][j] = a.m[i][j] / d[i];
                }
                row_norm_prod *= aocs_vec3_norm(aocs_vec3_make(as.m[i][0], as.m[i][1], as.m[i][2]));
            }
            det_s = aocs_mat3_det(as);
            if (!(AOCS_FABS(det_s) > (AOCS_MAT3_SINGULAR_RTOL * row_norm_prod))) {
                st = AOCS_ERR_INERTIA_SINGULAR;
            }
        }
        if (st == AOCS_OK) {
            inv = mat3_adjugate(as);
            for (i = 0; i < 3; ++i) {
                for (j = 0; j < 3; ++j) {
                    inv.m[i][j] = (inv.m[i][j] / det_s) / d[j];
                }
            }
            /* overflow when a row is tiny compared with the others */
            if (aocs_mat3_is_finite(inv) == 0) {
                st = AOCS_ERR_INERTIA_SINGULAR;
            } else {
                *out = inv;
            }
        }
    }
    return st;
}

/*
 * Definiteness of a symmetric matrix with a positive diagonal, by Sylvester's
 * leading minors of S = D^-1/2 J D^-1/2 (unit diagonal, D = diag(J)), so the
 * thresholds are dimensionless: a minor below -AOCS_MAT3_SINGULAR_RTOL means
 * a negative eigenvalue (NOT_POS_DEF); a minor within +-AOCS_MAT3_SINGULAR_RTOL
 * of zero means a (numerically) zero eigenvalue (SINGULAR).
 */
static aocs_status_t inertia_definiteness(aocs_mat3_t j)
{
    aocs_status_t st;
    aocs_mat3_t s;
    real_t sq[3];
    real_t minor2;
    real_t minor3;
    int r;
    int c;

    for (r = 0; r < 3; ++r) {
        sq[r] = AOCS_SQRT(j.m[r][r]);
    }
    for (r = 0; r < 3; ++r) {
        for (c = 0; c < 3; ++c) {
            /* symmetric part, so the small tolerated asymmetry cannot bias the minors */
            s.m[r][c] = ((AOCS_R(0.5) * (j.m[r][c] + j.m[c][r])) / sq[r]) / sq[c];
        }
    }
    minor2 = (s.m[0][0] * s.m[1][1]) - (s.m[0][1] * s.m[1][0]);
    minor3 = aocs_mat3_det(s);
    if ((minor2 < -AOCS_MAT3_SINGULAR_RTOL) || (minor3 < -AOCS_MAT3_SINGULAR_RTOL)) {
        st = AOCS_ERR_INERTIA_NOT_POS_DEF;
    } else if ((minor2 <= AOCS_MAT3_SINGULAR_RTOL) || (minor3 <= AOCS_MAT3_SINGULAR_RTOL)) {
        st = AOCS_ERR_INERTIA_SINGULAR;
    } else {
        st = AOCS_OK;
    }
    return st;
}

/*
 * Inertia check (docs/conventions.md "Inertia check"): finite, symmetric to
 * AOCS_INERTIA_SYM_RTOL of the largest element, positive diagonal (first
 * leading minor), then inertia_definiteness(), then the same singularity
 * test as aocs_mat3_inverse, so a checked inertia always inverts.
 */
aocs_status_t aocs_mat3_check_inertia(aocs_mat3_t j)
{
    aocs_status_t st = AOCS_OK;
    aocs_mat3_t inv;
    real_t max_abs = AOCS_R(0.0);
    int r;

    if (aocs_mat3_is_finite(j) == 0) {
        st = AOCS_ERR_PARAM_NOT_FINITE;
    } else {
        int c;
        for (r = 0; r < 3; ++r) {
            for (c = 0; c < 3; ++c) {
                if (AOCS_FABS(j.m[r][c]) > max_abs) {
                    max_abs = AOCS_FABS(j.m[r][c]);
                }
            }
        }
        for (r = 0; r < 3; ++r) {
            for (c = r + 1; c < 3; ++c) {
                if (AOCS_FABS(j.m[r][c] - j.m[c][r]) > (AOCS_INERTIA_SYM_RTOL * max_abs)) {
                    st = AOCS_ERR_INERTIA_NOT_SYMMETRIC;
                }
            }
        }
    }
    if (st == AOCS_OK) {
        for (r = 0; r < 3; ++r) {
            if (!(j.m[r][r] > AOCS_R(0.0))) {
                st = AOCS_ERR_INERTIA_NOT_POS_DEF;
            }
        }
    }
    if (st == AOCS_OK) {
        st = inertia_definiteness(j);
    }
    if ((st == AOCS_OK) && (aocs_mat3_inverse(j, &inv) != AOCS_OK)) {
        st = AOCS_ERR_INERTIA_SINGULAR;
    }
    return st;
}
