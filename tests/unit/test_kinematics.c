/*
 * Kinematics (SPEC 1) against finite differences of an exact attitude path.
 * With constant body rate w, qdot = 0.5 Xi(q) w = 0.5 [w; 0] (x) q has the
 * closed-form solution q(t) = [e sin(|w| t / 2); cos(|w| t / 2)] (x) q0,
 * e = w / |w|. The path, its CRP and MRP images and their central
 * differences are evaluated here in double, independently of the library;
 * the library's derivative functions are then compared with them.
 */
#include "test_support.h"

#define D(x) ((double)(x))

/* central-difference step: truncation ~h^2 |x'''| ~ 1e-10, rounding ~1e-16 / h ~ 1e-11 */
#define FD_H 1e-5
#if defined(AOCS_REAL_IS_FLOAT)
/* inputs rounded to float (6e-8) then a handful of float operations */
#define KIN_TOL 2e-6
#else
#define KIN_TOL 1e-8
#endif

/* Shuster product q (x) p of SPEC 1 in double */
static void ref_mul(const double q[4], const double p[4], double r[4])
{
    r[0] = q[3] * p[0] + p[3] * q[0] - (q[1] * p[2] - q[2] * p[1]);
    r[1] = q[3] * p[1] + p[3] * q[1] - (q[2] * p[0] - q[0] * p[2]);
    r[2] = q[3] * p[2] + p[3] * q[2] - (q[0] * p[1] - q[1] * p[0]);
    r[3] = q[3] * p[3] - (q[0] * p[0] + q[1] * p[1] + q[2] * p[2]);
}

/* exact path q(t) for constant w (double) */
static void path(const double q0[4], const double w[3], double t, double q[4])
{
    double n = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    double s = sin(0.5 * n * t) / n;
    double dq[4] = {w[0] * s, w[1] * s, w[2] * s, cos(0.5 * n * t)};
    ref_mul(dq, q0, q);
}

static void crp_of(const double q[4], double rho[3])
{
    for (int i = 0; i < 3; ++i) {
        rho[i] = q[i] / q[3];
    }
}

/* sigma = qv / (1 + q4) with no sign choice (sign = +1 or -1 picks the set) */
static void mrp_of(const double q[4], double sign, double sig[3])
{
    for (int i = 0; i < 3; ++i) {
        sig[i] = sign * q[i] / (1.0 + sign * q[3]);
    }
}

static aocs_quat_t to_quat(const double q[4])
{
    return aocs_quat_make((real_t)q[0], (real_t)q[1], (real_t)q[2], (real_t)q[3]);
}

static aocs_vec3_t to_vec(const double v[3])
{
    return aocs_vec3_make((real_t)v[0], (real_t)v[1], (real_t)v[2]);
}

typedef struct {
    double q0[4];
    double w[3];
} kin_case_t;

static kin_case_t random_case(test_rng_t *rng)
{
    kin_case_t c;
    aocs_quat_t q = test_random_quat(rng);
    for (int i = 0; i < 4; ++i) {
        c.q0[i] = D(q.q[i]);
    }
    double n = sqrt(c.q0[0] * c.q0[0] + c.q0[1] * c.q0[1] + c.q0[2] * c.q0[2] + c.q0[3] * c.q0[3]);
    for (int i = 0; i < 4; ++i) {
        c.q0[i] /= n;
    }
    for (int i = 0; i < 3; ++i) {
        c.w[i] = test_rng_uniform(rng, -1.0, 1.0);
    }
    return c;
}

/* sanity of the reference path itself: unit norm, q(0) = q0 */
static void test_reference_path(void **state)
{
    (void)state;
    test_rng_t rng = {0xC0FFEEULL};
    kin_case_t c = random_case(&rng);
    double q[4];
    path(c.q0, c.w, 0.0, q);
    for (int i = 0; i < 4; ++i) {
        assert_close(q[i], c.q0[i], 1e-15);
    }
    path(c.q0, c.w, 3.7, q);
    assert_close(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3], 1.0, 1e-14);
}

static void test_quat_derivative_vs_finite_difference(void **state)
{
    (void)state;
    test_rng_t rng = {0xC0FFEE01ULL};
    for (int k = 0; k < 200; ++k) {
        kin_case_t c = random_case(&rng);
        double t = test_rng_uniform(&rng, 0.0, 10.0);
        double qp[4], qm[4], q[4];
        path(c.q0, c.w, t + FD_H, qp);
        path(c.q0, c.w, t - FD_H, qm);
        path(c.q0, c.w, t, q);
        aocs_quat_t qd = aocs_quat_derivative(to_quat(q), to_vec(c.w));
        for (int i = 0; i < 4; ++i) {
            assert_close(qd.q[i], (qp[i] - qm[i]) / (2.0 * FD_H), KIN_TOL);
        }
    }
}

/* RK4 with the library's derivative reproduces the exact path */
static void test_quat_derivative_integrates_to_exact_path(void **state)
{
    (void)state;
    test_rng_t rng = {0xC0FFEE02ULL};
    for (int k = 0; k < 10; ++k) {
        kin_case_t c = random_case(&rng);
        const double dt = 1e-2;
        const int steps = 200; /* 2 s, up to ~3.5 rad of rotation */
        aocs_quat_t q = to_quat(c.q0);
        aocs_vec3_t w = to_vec(c.w);
        for (int s = 0; s < steps; ++s) {
            aocs_quat_t k1 = aocs_quat_derivative(q, w);
            aocs_quat_t y2, y3, y4;
            for (int i = 0; i < 4; ++i) {
                y2.q[i] = q.q[i] + (real_t)(0.5 * dt) * k1.q[i];
            }
            aocs_quat_t k2 = aocs_quat_derivative(y2, w);
            for (int i = 0; i < 4; ++i) {
                y3.q[i] = q.q[i] + (real_t)(0.5 * dt) * k2.q[i];
            }
            aocs_quat_t k3 = aocs_quat_derivative(y3, w);
            for (int i = 0; i < 4; ++i) {
                y4.q[i] = q.q[i] + (real_t)dt * k3.q[i];
            }
            aocs_quat_t k4 = aocs_quat_derivative(y4, w);
            for (int i = 0; i < 4; ++i) {
                q.q[i] += (real_t)(dt / 6.0) * (k1.q[i] + AOCS_R(2.0) * k2.q[i] + AOCS_R(2.0) * k3.q[i] + k4.q[i]);
            }
        }
        double e[4];
        path(c.q0, c.w, dt * steps, e);
        /* RK4 global error ~ (|w| dt)^4 t ~ 1e-9 in double; float accumulates ~200 roundings */
        for (int i = 0; i < 4; ++i) {
            assert_close(q.q[i], e[i], 100.0 * KIN_TOL);
        }
    }
}

static void test_crp_derivative_vs_finite_difference(void **state)
{
    (void)state;
    test_rng_t rng = {0xC0FFEE03ULL};
    int n = 0;
    while (n < 200) {
        kin_case_t c = random_case(&rng);
        double t = test_rng_uniform(&rng, 0.0, 10.0);
        double q[4], qp[4], qm[4];
        path(c.q0, c.w, t, q);
        if (fabs(q[3]) < 0.3) {
            continue; /* |rho| < 3.2: the difference quotient stays accurate */
        }
        ++n;
        path(c.q0, c.w, t + FD_H, qp);
        path(c.q0, c.w, t - FD_H, qm);
        double rho[3], rp[3], rm[3];
        crp_of(q, rho);
        crp_of(qp, rp);
        crp_of(qm, rm);
        aocs_vec3_t rd = aocs_crp_derivative(to_vec(rho), to_vec(c.w));
        double mag = 1.0 + rho[0] * rho[0] + rho[1] * rho[1] + rho[2] * rho[2];
        for (int i = 0; i < 3; ++i) {
            assert_close(rd.v[i], (rp[i] - rm[i]) / (2.0 * FD_H), mag * KIN_TOL);
        }
        /* identity of the crp_linear Lyapunov proof: rho . rhodot = 0.5 (1 + |rho|^2) rho . w */
        double lhs = D(aocs_vec3_dot(to_vec(rho), rd));
        double rhs = 0.5 * mag * (rho[0] * c.w[0] + rho[1] * c.w[1] + rho[2] * c.w[2]);
        assert_close(lhs, rhs, mag * mag * KIN_TOL);
    }
}

/* MRP kinematics on both sets: the short one (|sigma| <= 1) and its shadow */
static void test_mrp_derivative_vs_finite_difference(void **state)
{
    (void)state;
    test_rng_t rng = {0xC0FFEE04ULL};
    int n = 0;
    while (n < 400) {
        kin_case_t c = random_case(&rng);
        double t = test_rng_uniform(&rng, 0.0, 10.0);
        double q[4], qp[4], qm[4];
        path(c.q0, c.w, t, q);
        /* keep 1 + sign*q4 >= 0.3 on the stencil for whichever set is tested */
        double sign = (n % 2 == 0) ? 1.0 : -1.0;
        if (1.0 + sign * q[3] < 0.3) {
            continue;
        }
        ++n;
        path(c.q0, c.w, t + FD_H, qp);
        path(c.q0, c.w, t - FD_H, qm);
        double s[3], sp[3], sm[3];
        mrp_of(q, sign, s);
        mrp_of(qp, sign, sp);
        mrp_of(qm, sign, sm);
        aocs_vec3_t sd = aocs_mrp_derivative(to_vec(s), to_vec(c.w));
        double mag = 1.0 + s[0] * s[0] + s[1] * s[1] + s[2] * s[2];
        for (int i = 0; i < 3; ++i) {
            assert_close(sd.v[i], (sp[i] - sm[i]) / (2.0 * FD_H), mag * KIN_TOL);
        }
    }
}

static void test_mrp_b_matrix_structure(void **state)
{
    (void)state;
    /* sigma = (1, 2, 3), s.s = 14: 0.25 * ((1-14) I + 2 [s x] + 2 s s^T) by hand */
    const double e[3][3] = {{0.25 * (-13 + 2), 0.25 * (-6 + 4), 0.25 * (4 + 6)},
                            {0.25 * (6 + 4), 0.25 * (-13 + 8), 0.25 * (-2 + 12)},
                            {0.25 * (-4 + 6), 0.25 * (2 + 12), 0.25 * (-13 + 18)}};
    aocs_mat3_t g = aocs_mrp_b_matrix(aocs_vec3_make(1, 2, 3));
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            assert_close(g.m[i][j], e[i][j], TOL_TIGHT);
        }
    }
    /* G G^T = ((1 + s.s) / 4)^2 I for every sigma */
    test_rng_t rng = {0xC0FFEE05ULL};
    for (int k = 0; k < 500; ++k) {
        aocs_vec3_t s = test_random_vec3(&rng, 1.0);
        aocs_mat3_t b = aocs_mrp_b_matrix(s);
        aocs_mat3_t bbt = aocs_mat3_mul(b, aocs_mat3_transpose(b));
        double s2 = D(s.v[0]) * D(s.v[0]) + D(s.v[1]) * D(s.v[1]) + D(s.v[2]) * D(s.v[2]);
        double f = 0.25 * (1.0 + s2);
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                assert_close(bbt.m[i][j], (i == j) ? f * f : 0.0, 4.0 * TOL_TIGHT);
            }
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_reference_path),
        cmocka_unit_test(test_quat_derivative_vs_finite_difference),
        cmocka_unit_test(test_quat_derivative_integrates_to_exact_path),
        cmocka_unit_test(test_crp_derivative_vs_finite_difference),
        cmocka_unit_test(test_mrp_derivative_vs_finite_difference),
        cmocka_unit_test(test_mrp_b_matrix_structure),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
