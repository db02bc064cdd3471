/*
 * Conversions between quaternion, attitude matrix, CRP (Gibbs), MRP and
 * Euler 3-2-1 (SPEC 1, docs/conventions.md). Expected values are computed
 * here from the defining formulas in double, or derived by hand.
 */
#include "test_support.h"

#define D(x) ((double)(x))
#define PI 3.14159265358979323846
#define DEG (PI / 180.0)
#define N_RANDOM 2000

/* ref_dcm, A(q) of SPEC 1 in double: test_support.h */

/* passive elementary rotations multiplied in double: R1(roll) R2(pitch) R3(yaw) */
static void ref_euler_dcm(double yaw, double pitch, double roll, double a[3][3])
{
    const double r3[3][3] = {{cos(yaw), sin(yaw), 0}, {-sin(yaw), cos(yaw), 0}, {0, 0, 1}};
    const double r2[3][3] = {{cos(pitch), 0, -sin(pitch)}, {0, 1, 0}, {sin(pitch), 0, cos(pitch)}};
    const double r1[3][3] = {{1, 0, 0}, {0, cos(roll), sin(roll)}, {0, -sin(roll), cos(roll)}};
    double t[3][3];
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            t[i][j] = r2[i][0] * r3[0][j] + r2[i][1] * r3[1][j] + r2[i][2] * r3[2][j];
        }
    }
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            a[i][j] = r1[i][0] * t[0][j] + r1[i][1] * t[1][j] + r1[i][2] * t[2][j];
        }
    }
}

static void assert_dcm_equals_ref(aocs_mat3_t a, double e[3][3], double tol)
{
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            assert_close(a.m[i][j], e[i][j], tol);
        }
    }
}

/* q equal to s * e, s = +-1, where the sign is the one that makes them agree best */
static void assert_same_quat_up_to_sign(aocs_quat_t q, aocs_quat_t e, double tol)
{
    double dot = D(q.q[0]) * D(e.q[0]) + D(q.q[1]) * D(e.q[1]) + D(q.q[2]) * D(e.q[2]) + D(q.q[3]) * D(e.q[3]);
    double s = dot < 0.0 ? -1.0 : 1.0;
    for (int i = 0; i < 4; ++i) {
        assert_close(q.q[i], s * D(e.q[i]), tol);
    }
}

static aocs_quat_t quat_axis_angle(double ax, double ay, double az, double q4)
{
    double n = sqrt(ax * ax + ay * ay + az * az);
    double s = sqrt(1.0 - q4 * q4);
    return aocs_quat_make((real_t)(s * ax / n), (real_t)(s * ay / n), (real_t)(s * az / n), (real_t)q4);
}

/* ---------------- quaternion <-> attitude matrix ---------------- */

static void test_dcm_round_trip_random(void **state)
{
    (void)state;
    test_rng_t rng = {0x5EED0001ULL};
    for (int k = 0; k < N_RANDOM; ++k) {
        aocs_quat_t q = test_random_quat(&rng);
        double s = q.q[3] < 0 ? -1.0 : 1.0;
        aocs_quat_t r = aocs_dcm_to_quat(aocs_quat_to_dcm(q));
        assert_true(r.q[3] >= AOCS_R(0.0));
        for (int i = 0; i < 4; ++i) {
            assert_close(r.q[i], s * D(q.q[i]), 4.0 * TOL_TIGHT);
        }
    }
}

/* each of Shepperd's four branches, including exact 180 deg about each axis */
static void test_dcm_to_quat_branches_and_180deg(void **state)
{
    (void)state;
    const double a180x[3][3] = {{1, 0, 0}, {0, -1, 0}, {0, 0, -1}};
    const double a180y[3][3] = {{-1, 0, 0}, {0, 1, 0}, {0, 0, -1}};
    const double a180z[3][3] = {{-1, 0, 0}, {0, -1, 0}, {0, 0, 1}};
    const double (*mats[3])[3] = {a180x, a180y, a180z};
    for (int k = 0; k < 3; ++k) {
        aocs_mat3_t a;
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                a.m[i][j] = (real_t)mats[k][i][j];
            }
        }
        aocs_quat_t q = aocs_dcm_to_quat(a);
        for (int i = 0; i < 3; ++i) {
            assert_close(fabs(D(q.q[i])), (i == k) ? 1.0 : 0.0, TOL_TIGHT);
        }
        assert_close(q.q[3], 0.0, TOL_TIGHT);
    }
    /* 120 deg about (1,1,1): a cyclic permutation, every d_i equal -> q4 branch */
    const double perm[3][3] = {{0, 1, 0}, {0, 0, 1}, {1, 0, 0}};
    aocs_mat3_t a;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            a.m[i][j] = (real_t)perm[i][j];
        }
    }
    aocs_quat_t q = aocs_dcm_to_quat(a);
    double e[3][3];
    ref_dcm(q, e);
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            assert_close(e[i][j], perm[i][j], 4.0 * TOL_TIGHT);
        }
    }
    assert_close(q.q[3], 0.5, TOL_TIGHT); /* cos(60 deg) */
}

static void test_dcm_to_quat_near_180deg(void **state)
{
    (void)state;
    test_rng_t rng = {0x5EED0002ULL};
    const double q4s[5] = {1e-6, -1e-6, 1e-9, 0.0, -3e-7};
    for (int k = 0; k < 200; ++k) {
        aocs_vec3_t ax = test_random_vec3(&rng, 1.0);
        aocs_quat_t q = quat_axis_angle(D(ax.v[0]), D(ax.v[1]), D(ax.v[2]), q4s[k % 5]);
        aocs_quat_t r = aocs_dcm_to_quat(aocs_quat_to_dcm(q));
        assert_true(r.q[3] >= AOCS_R(0.0));
        assert_same_quat_up_to_sign(r, q, 4.0 * TOL_TIGHT);
        double e[3][3];
        ref_dcm(q, e);
        assert_dcm_equals_ref(aocs_quat_to_dcm(r), e, 8.0 * TOL_TIGHT);
    }
}

/* ---------------- CRP (Gibbs) ---------------- */

static void test_crp_round_trip(void **state)
{
    (void)state;
    test_rng_t rng = {0x5EED0003ULL};
    int n = 0;
    while (n < N_RANDOM) {
        aocs_quat_t q = test_random_quat(&rng);
        if (fabs(D(q.q[3])) < 0.1) {
            continue; /* |rho| <= 10 keeps the float comparison meaningful */
        }
        ++n;
        /* short-rotation representative: rho = s qv / (s q4), s = sign(q4), i.e. qv / q4 */
        double r0 = D(q.q[0]) / D(q.q[3]), r1 = D(q.q[1]) / D(q.q[3]), r2 = D(q.q[2]) / D(q.q[3]);
        aocs_vec3_t rho = aocs_vec3_make(99, 99, 99);
        assert_int_equal(aocs_quat_to_crp(q, &rho), AOCS_OK);
        double scale = 1.0 / fabs(D(q.q[3]));
        assert_close(rho.v[0], r0, 4.0 * TOL_TIGHT * scale);
        assert_close(rho.v[1], r1, 4.0 * TOL_TIGHT * scale);
        assert_close(rho.v[2], r2, 4.0 * TOL_TIGHT * scale);
        aocs_quat_t back = aocs_crp_to_quat(rho);
        double s = q.q[3] < 0 ? -1.0 : 1.0;
        assert_true(back.q[3] > AOCS_R(0.0));
        for (int i = 0; i < 4; ++i) {
            assert_close(back.q[i], s * D(q.q[i]), 4.0 * TOL_TIGHT);
        }
    }
}

static void test_crp_flips_to_short_rotation(void **state)
{
    (void)state;
    /* q4 = -0.6: 254 deg the long way is 106 deg the short way, rho = -qv / 0.6 */
    aocs_quat_t q = aocs_quat_make(0, AOCS_R(0.8), 0, AOCS_R(-0.6));
    aocs_vec3_t rho;
    assert_int_equal(aocs_quat_to_crp(q, &rho), AOCS_OK);
    assert_vec3_close(rho, aocs_vec3_make(0, AOCS_R(-0.8 / 0.6), 0), TOL_TIGHT);
    aocs_quat_t back = aocs_crp_to_quat(rho);
    assert_close(back.q[1], -0.8, TOL_TIGHT);
    assert_close(back.q[3], 0.6, TOL_TIGHT);
}

static void test_crp_singular_detection(void **state)
{
    (void)state;
    const double q4_min = (double)AOCS_CRP_Q4_MIN; /* 1e-8 double, 1e-6 float */
    const double q4s[5] = {0.0, 1e-12, -1e-12, q4_min, -q4_min};
    for (int k = 0; k < 5; ++k) {
        aocs_quat_t q = quat_axis_angle(1, 2, -2, q4s[k]);
        aocs_vec3_t rho = aocs_vec3_make(7, 8, 9);
        assert_int_equal(aocs_quat_to_crp(q, &rho), AOCS_ERR_CRP_SINGULAR);
        assert_vec3_close(rho, aocs_vec3_make(7, 8, 9), 0.0); /* untouched */
    }
    /* just above the threshold: representable, |rho| = sqrt(1 - q4^2) / q4 ~ 0.5 / q4_min */
    aocs_quat_t q = quat_axis_angle(0, 0, 1, 2.0 * q4_min);
    aocs_vec3_t rho;
    assert_int_equal(aocs_quat_to_crp(q, &rho), AOCS_OK);
    assert_close(rho.v[2], 1.0 / D(q.q[3]), 4.0 * TOL_TIGHT);
    /* non-finite input and NULL output */
    aocs_vec3_t keep = aocs_vec3_make(7, 8, 9);
    assert_int_equal(aocs_quat_to_crp(aocs_quat_make((real_t)NAN, 0, 0, 1), &keep), AOCS_ERR_INPUT_NOT_FINITE);
    assert_int_equal(aocs_quat_to_crp(aocs_quat_make(0, 0, 0, (real_t)INFINITY), &keep),
                     AOCS_ERR_INPUT_NOT_FINITE);
    assert_vec3_close(keep, aocs_vec3_make(7, 8, 9), 0.0);
    assert_int_equal(aocs_quat_to_crp(aocs_quat_identity(), NULL), AOCS_ERR_NULL_ARG);
}

static void test_crp_to_quat_huge_rho(void **state)
{
    (void)state;
#if defined(AOCS_REAL_IS_FLOAT)
    const real_t big = AOCS_R(1.0e30); /* |rho|^2 would overflow float */
#else
    const real_t big = AOCS_R(1.0e200); /* |rho|^2 would overflow double */
#endif
    aocs_quat_t q = aocs_crp_to_quat(aocs_vec3_make(big, 0, big));
    assert_int_equal(aocs_quat_is_finite(q), 1);
    assert_close(q.q[0], 1.0 / sqrt(2.0), TOL_TIGHT);
    assert_close(q.q[2], 1.0 / sqrt(2.0), TOL_TIGHT);
    assert_close(q.q[1], 0.0, 0.0);
    assert_true(q.q[3] >= AOCS_R(0.0) && D(q.q[3]) < 1e-29);
    /* scenario rtc_ex1a: q0 = [rho0; 1] / sqrt(1 + |rho0|^2), |rho0|^2 = 550 (SPEC 4) */
    aocs_quat_t r = aocs_crp_to_quat(aocs_vec3_make(-10, 15, 15));
    const double n = sqrt(551.0);
    assert_close(r.q[0], -10.0 / n, TOL_TIGHT);
    assert_close(r.q[1], 15.0 / n, TOL_TIGHT);
    assert_close(r.q[2], 15.0 / n, TOL_TIGHT);
    assert_close(r.q[3], 1.0 / n, TOL_TIGHT);
}

/* ---------------- MRP ---------------- */

static void test_mrp_round_trip(void **state)
{
    (void)state;
    test_rng_t rng = {0x5EED0004ULL};
    for (int k = 0; k < N_RANDOM; ++k) {
        aocs_quat_t q = test_random_quat(&rng);
        double s = q.q[3] < 0 ? -1.0 : 1.0;
        aocs_vec3_t sig = aocs_quat_to_mrp(q);
        for (int i = 0; i < 3; ++i) {
            assert_close(sig.v[i], s * D(q.q[i]) / (1.0 + s * D(q.q[3])), 4.0 * TOL_TIGHT);
        }
        assert_true(D(aocs_vec3_norm(sig)) <= 1.0 + 4.0 * TOL_TIGHT);
        aocs_quat_t back = aocs_mrp_to_quat(sig);
        for (int i = 0; i < 4; ++i) {
            assert_close(back.q[i], s * D(q.q[i]), 8.0 * TOL_TIGHT);
        }
    }
}

static void test_mrp_near_180deg(void **state)
{
    (void)state;
    const double q4s[4] = {1e-6, -1e-6, 0.0, 1e-12};
    for (int k = 0; k < 4; ++k) {
        aocs_quat_t q = quat_axis_angle(2, -1, 2, q4s[k]);
        aocs_vec3_t sig = aocs_quat_to_mrp(q);
        assert_int_equal(aocs_vec3_is_finite(sig), 1);
        /* |sigma| = |qv| / (1 + |q4|) -> 1 from below */
        assert_true(D(aocs_vec3_norm(sig)) <= 1.0 + TOL_TIGHT);
        assert_close(aocs_vec3_norm(sig), sqrt(1.0 - q4s[k] * q4s[k]) / (1.0 + fabs(q4s[k])), 4.0 * TOL_TIGHT);
        double e[3][3];
        ref_dcm(q, e);
        assert_dcm_equals_ref(aocs_quat_to_dcm(aocs_mrp_to_quat(sig)), e, 8.0 * TOL_TIGHT);
    }
}

static void test_mrp_shadow_set(void **state)
{
    (void)state;
    /* sigma = (0,0,2): s2 = 4, q = [0,0,4/5,-3/5]; shadow (0,0,-1/2): q = [0,0,-4/5,3/5] */
    aocs_vec3_t sig = aocs_vec3_make(0, 0, 2);
    aocs_vec3_t sh = aocs_mrp_shadow_if_needed(sig);
    assert_vec3_close(sh, aocs_vec3_make(0, 0, -0.5), TOL_TIGHT);
    aocs_quat_t q = aocs_mrp_to_quat(sig);
    aocs_quat_t qs = aocs_mrp_to_quat(sh);
    assert_close(q.q[2], 0.8, TOL_TIGHT);
    assert_close(q.q[3], -0.6, TOL_TIGHT);
    assert_close(qs.q[2], -0.8, TOL_TIGHT);
    assert_close(qs.q[3], 0.6, TOL_TIGHT);
    /* |sigma| <= 1 is kept as is, including the boundary |sigma| = 1 */
    assert_vec3_close(aocs_mrp_shadow_if_needed(aocs_vec3_make(AOCS_R(0.6), 0, AOCS_R(-0.8))), aocs_vec3_make(AOCS_R(0.6), 0, AOCS_R(-0.8)), 0.0);
    assert_vec3_close(aocs_mrp_shadow_if_needed(aocs_vec3_make(AOCS_R(0.1), AOCS_R(0.2), AOCS_R(0.3))), aocs_vec3_make(AOCS_R(0.1), AOCS_R(0.2), AOCS_R(0.3)), 0.0);

    test_rng_t rng = {0x5EED0005ULL};
    for (int k = 0; k < N_RANDOM; ++k) {
        aocs_vec3_t s = test_random_vec3(&rng, 6.0);
        double s2 = D(s.v[0]) * D(s.v[0]) + D(s.v[1]) * D(s.v[1]) + D(s.v[2]) * D(s.v[2]);
        if (s2 <= 1.0 + 1e-3) {
            continue;
        }
        aocs_vec3_t t = aocs_mrp_shadow_if_needed(s);
        for (int i = 0; i < 3; ++i) {
            assert_close(t.v[i], -D(s.v[i]) / s2, 4.0 * TOL_TIGHT);
        }
        assert_true(D(aocs_vec3_norm(t)) < 1.0);
        /* same attitude: both quaternions give the same matrix */
        double e1[3][3], e2[3][3];
        ref_dcm(aocs_mrp_to_quat(s), e1);
        ref_dcm(aocs_mrp_to_quat(t), e2);
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                assert_close(e1[i][j], e2[i][j], 8.0 * TOL_TIGHT);
            }
        }
        /* standard inverse: q4 = (1 - s2) / (1 + s2) < 0 for the long set */
        aocs_quat_t ql = aocs_mrp_to_quat(s);
        assert_close(ql.q[3], (1.0 - s2) / (1.0 + s2), 4.0 * TOL_TIGHT);
        assert_close(ql.q[0], 2.0 * D(s.v[0]) / (1.0 + s2), 4.0 * TOL_TIGHT);
    }
}

static void test_mrp_to_quat_huge_sigma(void **state)
{
    (void)state;
#if defined(AOCS_REAL_IS_FLOAT)
    const real_t big = AOCS_R(1.0e30);
#else
    const real_t big = AOCS_R(1.0e200);
#endif
    /* sigma = tan(phi/4) e -> infinity is phi -> 360 deg: q -> [0; -1] */
    aocs_quat_t q = aocs_mrp_to_quat(aocs_vec3_make(big, -big, 0));
    assert_int_equal(aocs_quat_is_finite(q), 1);
    assert_close(q.q[3], -1.0, TOL_TIGHT);
    assert_close(q.q[0], 0.0, TOL_TIGHT);
    /* sigma = 0 is the identity */
    aocs_quat_t i = aocs_mrp_to_quat(aocs_vec3_zero());
    assert_close(i.q[3], 1.0, 0.0);
}

/* ---------------- Euler 3-2-1 ---------------- */

static void test_euler_known_values(void **state)
{
    (void)state;
    const double h = 0.70710678118654752;
    /* yaw alone: 90 deg about z */
    aocs_euler321_t e = {(real_t)(90.0 * DEG), 0, 0};
    aocs_quat_t q = aocs_euler321_to_quat(e);
    assert_close(q.q[0], 0.0, TOL_TIGHT);
    assert_close(q.q[1], 0.0, TOL_TIGHT);
    assert_close(q.q[2], h, TOL_TIGHT);
    assert_close(q.q[3], h, TOL_TIGHT);
    /* pitch alone: about y */
    aocs_euler321_t ep = {0, (real_t)(90.0 * DEG), 0};
    q = aocs_euler321_to_quat(ep);
    assert_close(q.q[1], h, TOL_TIGHT);
    assert_close(q.q[3], h, TOL_TIGHT);
    /* sequence order: yaw 90 then pitch 90 (about the new y, which is N's -x) */
    aocs_euler321_t eyp = {(real_t)(90.0 * DEG), (real_t)(90.0 * DEG), 0};
    aocs_mat3_t a = aocs_euler321_to_dcm(eyp);
    /* R2(90) R3(90) = [[0,0,-1],[0,1,0],[1,0,0]] [[0,1,0],[-1,0,0],[0,0,1]] */
    const double ex[3][3] = {{0, 0, -1}, {-1, 0, 0}, {0, 1, 0}};
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            assert_close(a.m[i][j], ex[i][j], TOL_TIGHT);
        }
    }
}

static void test_euler_round_trip_and_dcm(void **state)
{
    (void)state;
    test_rng_t rng = {0x5EED0006ULL};
    for (int k = 0; k < N_RANDOM; ++k) {
        double yaw = test_rng_uniform(&rng, -PI, PI);
        double pitch = test_rng_uniform(&rng, -85.0 * DEG, 85.0 * DEG);
        double roll = test_rng_uniform(&rng, -PI, PI);
        aocs_euler321_t e = {(real_t)yaw, (real_t)pitch, (real_t)roll};
        double ref[3][3];
        ref_euler_dcm(D(e.yaw), D(e.pitch), D(e.roll), ref);
        /* Euler -> dcm against the product of elementary rotations */
        assert_dcm_equals_ref(aocs_euler321_to_dcm(e), ref, 4.0 * TOL_TIGHT);
        /* Euler -> quat -> dcm against the same */
        aocs_quat_t q = aocs_euler321_to_quat(e);
        assert_close(aocs_quat_norm(q), 1.0, 4.0 * TOL_TIGHT);
        assert_dcm_equals_ref(aocs_quat_to_dcm(q), ref, 8.0 * TOL_TIGHT);
        /* quat -> Euler recovers the angles; wrap the difference for yaw/roll near +-pi */
        aocs_euler321_t b = aocs_quat_to_euler321(q);
        /* rounding amplified by up to 1/(sqrt2 cos(87.5 deg)) ~ 16 at pitch 85 deg */
        const double tol = 100.0 * TOL_TIGHT;
        assert_close(remainder(D(b.yaw) - D(e.yaw), 2.0 * PI), 0.0, tol);
        assert_close(D(b.pitch) - D(e.pitch), 0.0, tol);
        assert_close(remainder(D(b.roll) - D(e.roll), 2.0 * PI), 0.0, tol);
        assert_true(D(b.pitch) >= -PI / 2.0 && D(b.pitch) <= PI / 2.0);
    }
}

/* quat -> Euler from random quaternions: the angles must rebuild the same matrix */
static void test_quat_to_euler_random_quats(void **state)
{
    (void)state;
    test_rng_t rng = {0x5EED0007ULL};
    for (int k = 0; k < N_RANDOM; ++k) {
        aocs_quat_t q = test_random_quat(&rng);
        aocs_euler321_t b = aocs_quat_to_euler321(q);
        double a[3][3], ref[3][3];
        ref_dcm(q, a);
        ref_euler_dcm(D(b.yaw), D(b.pitch), D(b.roll), ref);
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                assert_close(ref[i][j], a[i][j], 16.0 * TOL_TIGHT);
            }
        }
    }
}

static void test_euler_gimbal_lock(void **state)
{
    (void)state;
    /* pitch exactly and nearly +-90 deg, yaw 30, roll 20: no NaN, same attitude */
    const double offs[6] = {0.0, 1e-12, 1e-9, 1e-7, 1e-5, 1e-3};
    for (int sgn = -1; sgn <= 1; sgn += 2) {
        for (int k = 0; k < 6; ++k) {
            double pitch = sgn * (PI / 2.0 - offs[k]);
            aocs_euler321_t e = {(real_t)(30.0 * DEG), (real_t)pitch, (real_t)(20.0 * DEG)};
            aocs_quat_t q = aocs_euler321_to_quat(e);
            aocs_euler321_t b = aocs_quat_to_euler321(q);
            assert_true(isfinite(b.yaw) && isfinite(b.pitch) && isfinite(b.roll));
            assert_true(fabs(D(b.pitch)) <= PI / 2.0 + 1e-6);
            assert_close(D(b.pitch), pitch, 16.0 * TOL_TIGHT);
            double a[3][3], ref[3][3];
            ref_dcm(q, a);
            ref_euler_dcm(D(b.yaw), D(b.pitch), D(b.roll), ref);
            for (int i = 0; i < 3; ++i) {
                for (int j = 0; j < 3; ++j) {
                    assert_close(ref[i][j], a[i][j], 16.0 * TOL_TIGHT);
                }
            }
        }
    }
    /* at the exact lock only yaw - roll (pitch +90) is defined: roll = 0, yaw = 30 - 20 */
    aocs_euler321_t e = {(real_t)(30.0 * DEG), (real_t)(PI / 2.0), (real_t)(20.0 * DEG)};
    aocs_euler321_t b = aocs_quat_to_euler321(aocs_euler321_to_quat(e));
    assert_close(b.roll, 0.0, 0.0);
    assert_close(b.yaw, 10.0 * DEG, 16.0 * TOL_TIGHT);
    /* pitch -90: yaw + roll defined, 30 + 20 */
    e.pitch = (real_t)(-PI / 2.0);
    b = aocs_quat_to_euler321(aocs_euler321_to_quat(e));
    assert_close(b.roll, 0.0, 0.0);
    assert_close(b.yaw, 50.0 * DEG, 16.0 * TOL_TIGHT);
    /* a slightly non-unit quaternion at the lock, where |A13| > 1: asin would be NaN */
    aocs_quat_t q = aocs_euler321_to_quat(e);
    q = aocs_quat_make(q.q[0] * AOCS_R(1.001), q.q[1] * AOCS_R(1.001), q.q[2] * AOCS_R(1.001),
                       q.q[3] * AOCS_R(1.001));
    assert_true(fabs(D(aocs_quat_to_dcm(q).m[0][2])) > 1.0);
    b = aocs_quat_to_euler321(q);
    assert_true(isfinite(b.yaw) && isfinite(b.pitch) && isfinite(b.roll));
    assert_close(b.pitch, -PI / 2.0, 16.0 * TOL_TIGHT);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_dcm_round_trip_random),
        cmocka_unit_test(test_dcm_to_quat_branches_and_180deg),
        cmocka_unit_test(test_dcm_to_quat_near_180deg),
        cmocka_unit_test(test_crp_round_trip),
        cmocka_unit_test(test_crp_flips_to_short_rotation),
        cmocka_unit_test(test_crp_singular_detection),
        cmocka_unit_test(test_crp_to_quat_huge_rho),
        cmocka_unit_test(test_mrp_round_trip),
        cmocka_unit_test(test_mrp_near_180deg),
        cmocka_unit_test(test_mrp_shadow_set),
        cmocka_unit_test(test_mrp_to_quat_huge_sigma),
        cmocka_unit_test(test_euler_known_values),
        cmocka_unit_test(test_euler_round_trip_and_dcm),
        cmocka_unit_test(test_quat_to_euler_random_quats),
        cmocka_unit_test(test_euler_gimbal_lock),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
