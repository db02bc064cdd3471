/*
 * Shared reference helpers of the attitude-law unit tests (test_crp_linear,
 * test_quat_pd, test_quat_nlpd, test_smc, and the quaternion / rigid-body
 * parts of test_lqr_quat, test_hinf, test_mrp_sat): an independent
 * double-precision model of SPEC 1 that uses no firmware math (Shuster
 * product, axis-angle and 3-2-1 quaternions, 3x3 inverse), conversions to
 * and from real_t, the law input builder, a closed-loop RK4 rigid body
 * (J wdot = -w x Jw + u, qdot = 0.5 Xi(q) w) and the Lyapunov checker.
 * Header-only (static inline) so each test stays one .c file.
 */
#ifndef AOCS_LAW_TEST_SUPPORT_H
#define AOCS_LAW_TEST_SUPPORT_H

#include <string.h>

#include "test_support.h"
#include "aocs/control/law_io.h"

/* ---- independent double-precision reference (SPEC 1), no firmware math ---- */
typedef struct {
    double q[4]; /* scalar last */
} dq_t;

/* Shuster product (Markley & Crassidis eq. 2.82): A(q (x) p) = A(q) A(p) */
static inline dq_t dq_mul(dq_t q, dq_t p)
{
    dq_t r;
    r.q[0] = p.q[3] * q.q[0] + q.q[3] * p.q[0] - (q.q[1] * p.q[2] - q.q[2] * p.q[1]);
    r.q[1] = p.q[3] * q.q[1] + q.q[3] * p.q[1] - (q.q[2] * p.q[0] - q.q[0] * p.q[2]);
    r.q[2] = p.q[3] * q.q[2] + q.q[3] * p.q[2] - (q.q[0] * p.q[1] - q.q[1] * p.q[0]);
    r.q[3] = q.q[3] * p.q[3] - (q.q[0] * p.q[0] + q.q[1] * p.q[1] + q.q[2] * p.q[2]);
    return r;
}

static inline dq_t dq_inv(dq_t q)
{
    dq_t r = {{-q.q[0], -q.q[1], -q.q[2], q.q[3]}};
    return r;
}

static inline dq_t dq_normalize(dq_t q)
{
    double n = sqrt(q.q[0] * q.q[0] + q.q[1] * q.q[1] + q.q[2] * q.q[2] + q.q[3] * q.q[3]);
    dq_t r = {{q.q[0] / n, q.q[1] / n, q.q[2] / n, q.q[3] / n}};
    return r;
}

/* rotation by angle_rad about the axis (ax, ay, az), normalised here */
static inline dq_t dq_axis_angle(double ax, double ay, double az, double angle_rad)
{
    double n = sqrt(ax * ax + ay * ay + az * az);
    double s = sin(0.5 * angle_rad) / n;
    dq_t r = {{ax * s, ay * s, az * s, cos(0.5 * angle_rad)}};
    return r;
}

/* 3-2-1 in rad: A = R1(roll) R2(pitch) R3(yaw), so q = q_x (x) q_y (x) q_z */
static inline dq_t dq_euler321(double yaw, double pitch, double roll)
{
    return dq_mul(dq_axis_angle(1, 0, 0, roll), dq_mul(dq_axis_angle(0, 1, 0, pitch), dq_axis_angle(0, 0, 1, yaw)));
}

/* the same in degrees (scenario files) */
static inline dq_t dq_euler321_deg(double yaw, double pitch, double roll)
{
    const double d2r = 3.14159265358979323846 / 180.0;
    return dq_euler321(yaw * d2r, pitch * d2r, roll * d2r);
}

/* the value the firmware actually sees, back in double */
static inline dq_t dq_from_real(aocs_quat_t q)
{
    dq_t r = {{(double)q.q[0], (double)q.q[1], (double)q.q[2], (double)q.q[3]}};
    return r;
}

static inline aocs_quat_t dq_to_real(dq_t q)
{
    return aocs_quat_make((real_t)q.q[0], (real_t)q.q[1], (real_t)q.q[2], (real_t)q.q[3]);
}

static inline aocs_vec3_t dv_to_real(const double v[3])
{
    return aocs_vec3_make((real_t)v[0], (real_t)v[1], (real_t)v[2]);
}

static inline void dv_from_real(aocs_vec3_t a, double v[3])
{
    for (int i = 0; i < 3; ++i) {
        v[i] = (double)a.v[i];
    }
}

static inline double dv_dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static inline void dv_cross(const double a[3], const double b[3], double out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

typedef struct {
    double m[3][3];
} dmat_t;

static inline void dm_mul_vec(const dmat_t *a, const double x[3], double out[3])
{
    for (int i = 0; i < 3; ++i) {
        out[i] = a->m[i][0] * x[0] + a->m[i][1] * x[1] + a->m[i][2] * x[2];
    }
}

/* inverse by adjugate (test inertias are well conditioned) */
static inline dmat_t dm_inv(const dmat_t *a)
{
    const double(*m)[3] = a->m;
    dmat_t r;
    double c[3][3];
    c[0][0] = m[1][1] * m[2][2] - m[1][2] * m[2][1];
    c[0][1] = m[1][2] * m[2][0] - m[1][0] * m[2][2];
    c[0][2] = m[1][0] * m[2][1] - m[1][1] * m[2][0];
    c[1][0] = m[0][2] * m[2][1] - m[0][1] * m[2][2];
    c[1][1] = m[0][0] * m[2][2] - m[0][2] * m[2][0];
    c[1][2] = m[0][1] * m[2][0] - m[0][0] * m[2][1];
    c[2][0] = m[0][1] * m[1][2] - m[0][2] * m[1][1];
    c[2][1] = m[0][2] * m[1][0] - m[0][0] * m[1][2];
    c[2][2] = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    double det = m[0][0] * c[0][0] + m[0][1] * c[0][1] + m[0][2] * c[0][2];
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            r.m[i][j] = c[j][i] / det;
        }
    }
    return r;
}

static inline aocs_att_input_t make_input(dq_t q, const double w[3], dq_t qd, const double wd[3],
                                   const double wd_dot[3], double dt)
{
    aocs_att_input_t in;
    in.q_BN = dq_to_real(q);
    in.w_BN_B = dv_to_real(w);
    in.qd_DN = dq_to_real(qd);
    in.wd_B = dv_to_real(wd);
    in.wd_dot_B = dv_to_real(wd_dot);
    in.dt_s = (real_t)dt;
    return in;
}

/* law input from firmware-typed values; wd_dot = 0, dt = 0.1 s (the 10 Hz control period) */
static inline aocs_att_input_t make_input_real(aocs_quat_t q, aocs_vec3_t w, aocs_quat_t qd, aocs_vec3_t wd)
{
    aocs_att_input_t in;
    in.q_BN = q;
    in.w_BN_B = w;
    in.qd_DN = qd;
    in.wd_B = wd;
    in.wd_dot_B = aocs_vec3_zero();
    in.dt_s = AOCS_R(0.1);
    return in;
}

/* k-th scalar field of the input in declaration order (18 fields, dt last) */
#define N_INPUT_FIELDS 18
static inline real_t *input_field(aocs_att_input_t *in, int k)
{
    real_t *p = NULL;
    if (k < 4) {
        p = &in->q_BN.q[k];
    } else if (k < 7) {
        p = &in->w_BN_B.v[k - 4];
    } else if (k < 11) {
        p = &in->qd_DN.q[k - 7];
    } else if (k < 14) {
        p = &in->wd_B.v[k - 11];
    } else if (k < 17) {
        p = &in->wd_dot_B.v[k - 14];
    } else {
        p = &in->dt_s;
    }
    return p;
}

/* every component exactly zero (and finite) */
static inline void assert_vec3_is_zero(aocs_vec3_t u)
{
    for (int i = 0; i < 3; ++i) {
        assert_true(isfinite((double)u.v[i]) && !(fabs((double)u.v[i]) > 0.0));
    }
}

/* |a_i - b_i| <= tol * scale for each i: scale is the size of the terms summed */
static inline void assert_vec3_close_scaled(aocs_vec3_t a, const double b[3], double tol, double scale)
{
    for (int i = 0; i < 3; ++i) {
        if (!(fabs((double)a.v[i] - b[i]) <= tol * scale)) {
            print_error("component %d: got %.17g expected %.17g (tol %.3g scale %.3g)\n", i,
                        (double)a.v[i], b[i], tol, scale);
            fail();
        }
    }
}

/* ---- closed loop: J wdot = -w x Jw + u, qdot = 0.5 Xi(q) w (SPEC 1), RK4 ---- */
typedef aocs_status_t (*torque_fn_t)(void *ctx, dq_t q, const double w[3], double u[3]);

typedef struct {
    dmat_t j;
    dmat_t jinv;
} plant_t;

static inline void plant_init(plant_t *p, const dmat_t *j)
{
    p->j = *j;
    p->jinv = dm_inv(j);
}

/* state derivative with the law evaluated on the stage state (continuous feedback) */
static inline void plant_deriv(const plant_t *p, torque_fn_t law, void *ctx, dq_t q, const double w[3],
                        dq_t *qdot, double wdot[3])
{
    double u[3];
    double h[3];
    double wxh[3];
    double rhs[3];
    assert_int_equal(law(ctx, dq_normalize(q), w, u), AOCS_OK);
    dm_mul_vec(&p->j, w, h);
    dv_cross(w, h, wxh);
    for (int i = 0; i < 3; ++i) {
        rhs[i] = -wxh[i] + u[i];
    }
    dm_mul_vec(&p->jinv, rhs, wdot);
    /* Xi(q) w = [q4 w + q_vec x w; -q_vec . w] */
    double qv[3] = {q.q[0], q.q[1], q.q[2]};
    double qxw[3];
    dv_cross(qv, w, qxw);
    for (int i = 0; i < 3; ++i) {
        qdot->q[i] = 0.5 * (q.q[3] * w[i] + qxw[i]);
    }
    qdot->q[3] = -0.5 * dv_dot(qv, w);
}

static inline void plant_rk4(const plant_t *p, torque_fn_t law, void *ctx, dq_t *q, double w[3], double h)
{
    dq_t kq[4];
    double kw[4][3];
    dq_t qs = *q;
    double ws[3] = {w[0], w[1], w[2]};
    const double c[4] = {0.0, 0.5, 0.5, 1.0};
    for (int s = 0; s < 4; ++s) {
        if (s > 0) {
            for (int i = 0; i < 4; ++i) {
                qs.q[i] = q->q[i] + c[s] * h * kq[s - 1].q[i];
            }
            for (int i = 0; i < 3; ++i) {
                ws[i] = w[i] + c[s] * h * kw[s - 1][i];
            }
        }
        plant_deriv(p, law, ctx, qs, ws, &kq[s], kw[s]);
    }
    for (int i = 0; i < 4; ++i) {
        q->q[i] += h / 6.0 * (kq[0].q[i] + 2.0 * kq[1].q[i] + 2.0 * kq[2].q[i] + kq[3].q[i]);
    }
    for (int i = 0; i < 3; ++i) {
        w[i] += h / 6.0 * (kw[0][i] + 2.0 * kw[1][i] + 2.0 * kw[2][i] + kw[3][i]);
    }
    *q = dq_normalize(*q);
}

/*
 * Zero-order hold: ctx points to the double[3] torque held over the step
 * (the law ran once per control period on the sampled state).
 */
static inline aocs_status_t plant_zoh_torque(void *ctx, dq_t q, const double w[3], double u[3])
{
    const double *held = (const double *)ctx;
    (void)q;
    (void)w;
    for (int i = 0; i < 3; ++i) {
        u[i] = held[i];
    }
    return AOCS_OK;
}

/* IRASSI inertia (SPEC 4) */
static const dmat_t J_IRASSI = {{{2059.5, 0.0, 0.0}, {0.0, 5954.2, 0.0}, {0.0, 0.0, 5974.3}}};

/* ---- Lyapunov check along a closed-loop run ---- */
typedef void (*lyap_fn_t)(void *ctx, dq_t q, const double w[3], double *v, double *vdot_expected);

#define LYAP_MAX_STEPS 4000

/*
 * Integrates n_steps of size h from (q0, w0); asserts V strictly decreasing
 * at every step and the central difference of V equal to the analytic Vdot
 * within rtol of the largest |Vdot| of the run. Returns the final V / V(0).
 */
static inline double check_lyapunov(const plant_t *p, torque_fn_t law, lyap_fn_t lyap, void *ctx, dq_t q0,
                             const double w0[3], double h, int n_steps, double rtol)
{
    /* static: 64 KB, too large for a test thread's stack; one copy per test binary */
    static double lyap_v[LYAP_MAX_STEPS + 1];
    static double lyap_vdot[LYAP_MAX_STEPS + 1];
    dq_t q = q0;
    double w[3] = {w0[0], w0[1], w0[2]};
    double vdot_max = 0.0;
    assert_true(n_steps <= LYAP_MAX_STEPS);
    lyap(ctx, q, w, &lyap_v[0], &lyap_vdot[0]);
    for (int n = 1; n <= n_steps; ++n) {
        plant_rk4(p, law, ctx, &q, w, h);
        lyap(ctx, q, w, &lyap_v[n], &lyap_vdot[n]);
        if (!(lyap_v[n] < lyap_v[n - 1])) {
            print_error("V did not decrease at step %d: %.17g -> %.17g\n", n, lyap_v[n - 1], lyap_v[n]);
            fail();
        }
        assert_true(lyap_vdot[n] <= 0.0);
        if (fabs(lyap_vdot[n]) > vdot_max) {
            vdot_max = fabs(lyap_vdot[n]);
        }
    }
    double err_max = 0.0;
    for (int n = 1; n < n_steps; ++n) {
        double num = (lyap_v[n + 1] - lyap_v[n - 1]) / (2.0 * h);
        double err = fabs(num - lyap_vdot[n]);
        if (err > err_max) {
            err_max = err;
        }
        if (!(err <= rtol * vdot_max)) {
            print_error("Vdot mismatch at step %d: numeric %.10g analytic %.10g (max |Vdot| %.3g)\n", n, num,
                        lyap_vdot[n], vdot_max);
            fail();
        }
    }
    print_message("  Lyapunov: V %.6g -> %.6g, max |Vdot| %.4g, max Vdot error %.3g (%.2g relative)\n",
                  lyap_v[0], lyap_v[n_steps], vdot_max, err_max, err_max / vdot_max);
    return lyap_v[n_steps] / lyap_v[0];
}

/* ---- constants shared by the law tests ---- */
static const double ZERO3[3] = {0.0, 0.0, 0.0};
static const double PI = 3.14159265358979323846;

#endif /* AOCS_LAW_TEST_SUPPORT_H */
