/*
 * Shared reference helpers of the control-law unit tests (test_crp_linear,
 * test_quat_pd, test_quat_nlpd, test_smc, test_lqr_quat, test_hinf,
 * test_mrp_sat, test_orbit_lqr, test_gain_tables, test_saturate,
 * test_law_io): an independent double-precision model of SPEC 1 that uses no
 * firmware math (Shuster product, axis-angle and 3-2-1 quaternions, 3x3
 * inverse), conversions to and from real_t, the law input builders and
 * reference states, the input field accessors, a closed-loop RK4 rigid body
 * (J wdot = -w x Jw + u, qdot = 0.5 Xi(q) w), the Lyapunov checker, the K x
 * reference of the table-driven laws, the linear saturation in double, and
 * the checks of the law_io.h contract that every attitude law must pass
 * (rejections, q / -q, restoring sign), run through a step function pointer
 * so each law's test keeps one line per check and its own assertions.
 * Header-only (static inline) so each test stays one .c file.
 */
#ifndef AOCS_LAW_TEST_SUPPORT_H
#define AOCS_LAW_TEST_SUPPORT_H

#include <string.h>

#include "test_support.h"
#include "aocs/control/law_io.h"

/* ---- constants shared by the law tests ---- */
static const double ZERO3[3] = {0.0, 0.0, 0.0};
static const double PI = 3.14159265358979323846;

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
    in.u_max_axis = aocs_vec3_zero();
    in.u_max_norm = AOCS_R(0.0);
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
    in.u_max_axis = aocs_vec3_zero();
    in.u_max_norm = AOCS_R(0.0);
    return in;
}

/*
 * The reference states of the PD-type laws (quat_pd, quat_nlpd), dt = 0.1 s:
 * [0] the IRASSI large-slew geometry (14/14/14 deg to a 30/-20/1 deg target)
 *     with nonzero w and wd;
 * [1] an error of 250 deg from the same target with rates: qe4 < -0.5
 *     (asserted), so sign(qe4) = -1 is exercised;
 * [2] exactly 180 deg about x from the identity target, w = [0 0 0.5]:
 *     qe4 = 0, sign(0) = +1.
 */
#define N_PD_REFERENCE_STATES 3
static inline void pd_reference_states(aocs_att_input_t in[N_PD_REFERENCE_STATES])
{
    const double w1[3] = {0.01, -0.02, 0.03};
    const double wd1[3] = {0.001, 0.0, -0.002};
    const dq_t qd = dq_euler321_deg(30.0, -20.0, 1.0);
    in[0] = make_input(dq_euler321_deg(14.0, 14.0, 14.0), w1, qd, wd1, ZERO3, 0.1);

    const dq_t q2 = dq_mul(dq_axis_angle(1.0, -2.0, 0.5, 250.0 * PI / 180.0), qd);
    assert_true(dq_mul(q2, dq_inv(qd)).q[3] < -0.5);
    const double w2[3] = {-0.1, 0.05, 0.2};
    in[1] = make_input(q2, w2, qd, ZERO3, ZERO3, 0.1);

    const dq_t q3 = {{1.0, 0.0, 0.0, 0.0}};
    const dq_t id = {{0.0, 0.0, 0.0, 1.0}};
    const double w3[3] = {0.0, 0.0, 0.5};
    in[2] = make_input(q3, w3, id, ZERO3, ZERO3, 0.1);
}

/* 60 deg about x (qe = [0.5 0 0 cos 30]) from the identity target, rate w_x about x: the by-hand states */
static inline aocs_att_input_t make_input_60deg_about_x(double w_x)
{
    return make_input_real(aocs_quat_make(AOCS_R(0.5), AOCS_R(0.0), AOCS_R(0.0), AOCS_R(0.86602540378443865)),
                           aocs_vec3_make((real_t)w_x, AOCS_R(0.0), AOCS_R(0.0)), aocs_quat_identity(),
                           aocs_vec3_zero());
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

/* k-th scalar field of the orbit input in declaration order (7 fields, dt last) */
#define N_ORBIT_INPUT_FIELDS 7
static inline real_t *orbit_input_field(aocs_orbit_input_t *in, int k)
{
    real_t *p = NULL;
    if (k < 3) {
        p = &in->vel_mps.v[k];
    } else if (k < 6) {
        p = &in->pos_m.v[k - 3];
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

/*
 * SPEC 2.3 Lyapunov function of the PD-type laws (quat_pd, quat_nlpd), with
 * |qe4| (anti-unwinding), qe = q (x) qd^-1:
 * V = 0.25 w^T J w + 0.5 kp qe_v.qe_v + 0.5 kp (1 - |qe4|)^2 (= 0.25 w^T J w + kp (1 - |qe4|)).
 * The 0.25 on the kinetic term makes it consistent with the gains of these laws.
 */
static inline double pd_lyapunov_v(const dmat_t *j, double kp, dq_t qd, dq_t q, const double w[3])
{
    dq_t qe = dq_mul(q, dq_inv(qd));
    double qv[3] = {qe.q[0], qe.q[1], qe.q[2]};
    double h[3];
    dm_mul_vec(j, w, h);
    double a = 1.0 - fabs(qe.q[3]);
    return 0.25 * dv_dot(w, h) + 0.5 * kp * dv_dot(qv, qv) + 0.5 * kp * a * a;
}

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

/* ---- K x reference of the table-driven laws (lqr_quat, hinf, orbit_lqr) ---- */
/*
 * Asserts u_i = sign * sum_j k[i][j] x[j], evaluated here in double, for each
 * row within rel_tol * sum_j |k[i][j]| (|x[j]| + x_abs_tol) + abs_tol: the
 * scale is the size of the terms summed (cancellation-safe); x_abs_tol is
 * the absolute error the law may make in its own x (hinf's Euler angles).
 */
static inline void assert_gain_product(const real_t k[3][6], const double x[6], double sign, aocs_vec3_t u,
                                       double rel_tol, double x_abs_tol, double abs_tol)
{
    for (int i = 0; i < 3; ++i) {
        double ref = 0.0;
        double scale = 0.0;
        for (int j = 0; j < 6; ++j) {
            ref += (double)k[i][j] * x[j];
            scale += fabs((double)k[i][j]) * (fabs(x[j]) + x_abs_tol);
        }
        ref *= sign;
        int ok = fabs((double)u.v[i] - ref) <= rel_tol * scale + abs_tol;
        if (!ok) {
            print_error("row %d: law %.17g, expected %.17g (sum |K||x| %.3g, tol %.3g)\n", i, (double)u.v[i], ref,
                        scale, rel_tol);
        }
        assert_true(ok);
    }
}

/* ---- the documented linear saturation (saturate.h), in double ---- */
static inline double ref_linear_sat(double x, double l, double m)
{
    double ax = fabs(x);
    double s = (x > 0.0) ? 1.0 : ((x < 0.0) ? -1.0 : 0.0);
    if (l >= m) {
        return (ax > m) ? s * m : x;
    }
    if (ax <= l) {
        return x;
    }
    return s * (l + (m - l) * tanh((ax - l) / (m - l)));
}

/* ---- the law_io.h contract, checked the same way for every attitude law ---- */
/* a law's step behind one signature; each test wraps its aocs_<law>_step in one of these */
typedef aocs_status_t (*law_step_fn_t)(void *law, const aocs_att_input_t *in, aocs_vec3_t *u_out);

/* the state the rejection checks start from: a 14/14/14 deg attitude, a 30/-20/1 deg target, 0.1 s period */
static inline aocs_att_input_t law_test_input(void)
{
    const double w[3] = {0.01, 0.02, 0.03};
    return make_input(dq_euler321_deg(14.0, 14.0, 14.0), w, dq_euler321_deg(30.0, -20.0, 1.0), ZERO3, ZERO3, 0.1);
}

/* one step on in must return expected and overwrite a nonzero u with an exact zero */
static inline void assert_step_rejects(law_step_fn_t step, void *law, const aocs_att_input_t *in,
                                       aocs_status_t expected)
{
    aocs_vec3_t u = aocs_vec3_make(AOCS_R(5.0), AOCS_R(5.0), AOCS_R(5.0));
    assert_int_equal(step(law, in, &u), expected);
    assert_vec3_is_zero(u);
}

/* a law whose init failed (or never ran) refuses to step: AOCS_ERR_NOT_INITIALISED, zero torque */
static inline void assert_step_not_initialised(law_step_fn_t step, void *law)
{
    aocs_att_input_t in = law_test_input();
    assert_step_rejects(step, law, &in, AOCS_ERR_NOT_INITIALISED);
}

/* before any init: a zeroed and a garbage (0xA5 bytes) law struct of law_size bytes both refuse to step */
static inline void check_step_before_init(law_step_fn_t step, void *law, size_t law_size)
{
    memset(law, 0, law_size);
    assert_step_not_initialised(step, law);
    memset(law, 0xA5, law_size);
    assert_step_not_initialised(step, law);
}

/*
 * Every input rejection of the law_io.h contract on an initialised law, each
 * with its own status and a zero torque: NULL law, input or output; NaN, +Inf
 * and -Inf in each of the 18 input fields (AOCS_ERR_DT_INVALID for dt,
 * AOCS_ERR_INPUT_NOT_FINITE elsewhere); q with q4 scaled by 1.1 and a zero
 * qd (AOCS_ERR_QUAT_NOT_UNIT); dt = 0 and dt < 0.
 */
static inline void check_input_rejections(law_step_fn_t step, void *law, const aocs_att_input_t *good)
{
    aocs_vec3_t u;
    assert_int_equal(step(NULL, good, &u), AOCS_ERR_NULL_ARG);
    assert_step_rejects(step, law, NULL, AOCS_ERR_NULL_ARG);
    assert_int_equal(step(law, good, NULL), AOCS_ERR_NULL_ARG);

    const double bad[3] = {NAN, INFINITY, -INFINITY};
    for (int k = 0; k < N_INPUT_FIELDS; ++k) {
        for (int b = 0; b < 3; ++b) {
            aocs_att_input_t in = *good;
            *input_field(&in, k) = (real_t)bad[b];
            assert_step_rejects(step, law, &in,
                                (k == N_INPUT_FIELDS - 1) ? AOCS_ERR_DT_INVALID : AOCS_ERR_INPUT_NOT_FINITE);
        }
    }
    aocs_att_input_t in = *good;
    in.q_BN.q[3] *= AOCS_R(1.1);
    assert_step_rejects(step, law, &in, AOCS_ERR_QUAT_NOT_UNIT);
    in = *good;
    in.qd_DN = aocs_quat_make(AOCS_R(0.0), AOCS_R(0.0), AOCS_R(0.0), AOCS_R(0.0));
    assert_step_rejects(step, law, &in, AOCS_ERR_QUAT_NOT_UNIT);
    in = *good;
    in.dt_s = AOCS_R(0.0);
    assert_step_rejects(step, law, &in, AOCS_ERR_DT_INVALID);
    in.dt_s = AOCS_R(-0.1);
    assert_step_rejects(step, law, &in, AOCS_ERR_DT_INVALID);
}

/*
 * check_input_rejections, then finite rates whose torque overflows
 * (w_x = REAL_MAX / 2: AOCS_ERR_OUTPUT_NOT_FINITE and a zero torque, never
 * Inf); afterwards the law still gives a finite torque on good (no sticky
 * state). For every law whose torque grows with the rate (all but mrp_sat).
 */
static inline void check_step_rejections(law_step_fn_t step, void *law, const aocs_att_input_t *good)
{
    check_input_rejections(step, law, good);
    aocs_att_input_t in = *good;
    in.w_BN_B = aocs_vec3_make(AOCS_REAL_MAX / AOCS_R(2.0), AOCS_R(0.0), AOCS_R(0.0));
    assert_step_rejects(step, law, &in, AOCS_ERR_OUTPUT_NOT_FINITE);
    aocs_vec3_t u;
    assert_int_equal(step(law, good, &u), AOCS_OK);
    assert_true(aocs_vec3_is_finite(u) != 0);
}

/* a law's init behind one signature, for the laws configured by two scalar gains */
typedef aocs_status_t (*gain_pair_init_fn_t)(void *law, real_t g1, real_t g2);

/*
 * Each of the two gains in turn set to NaN, +Inf, -Inf (AOCS_ERR_PARAM_NOT_FINITE)
 * and to 0, -0, -1 (AOCS_ERR_GAIN_NOT_POSITIVE), the other one at its valid
 * value (g1_ok, g2_ok): init returns that status, and a law that was
 * initialised (gains 1, 1) just before is left unusable.
 */
static inline void check_gain_pair_rejections(gain_pair_init_fn_t init, law_step_fn_t step, void *law, double g1_ok,
                                              double g2_ok)
{
    const double bad_nf[3] = {NAN, INFINITY, -INFINITY};
    const double bad_np[3] = {0.0, -0.0, -1.0};
    for (int which = 0; which < 2; ++which) {
        for (int b = 0; b < 3; ++b) {
            for (int kind = 0; kind < 2; ++kind) {
                const double bad = (kind == 0) ? bad_nf[b] : bad_np[b];
                const real_t g1 = (which == 0) ? (real_t)bad : (real_t)g1_ok;
                const real_t g2 = (which == 1) ? (real_t)bad : (real_t)g2_ok;
                assert_int_equal(init(law, AOCS_R(1.0), AOCS_R(1.0)), AOCS_OK);
                assert_int_equal(init(law, g1, g2), (kind == 0) ? AOCS_ERR_PARAM_NOT_FINITE : AOCS_ERR_GAIN_NOT_POSITIVE);
                assert_step_not_initialised(step, law);
            }
        }
    }
}

/*
 * A positive rotation about +x from a non-trivial target (0.1, 10 and
 * 170 deg, zero rates) gives a restoring torque: u_x < 0, |u_y| and |u_z| at
 * most 1e-3 |u_x|.
 */
static inline void check_restoring_torque_about_x(law_step_fn_t step, void *law)
{
    dq_t qd = dq_euler321_deg(30.0, -20.0, 1.0);
    const double angles_deg[3] = {0.1, 10.0, 170.0};
    for (int k = 0; k < 3; ++k) {
        dq_t q = dq_mul(dq_axis_angle(1.0, 0.0, 0.0, angles_deg[k] * PI / 180.0), qd);
        aocs_att_input_t in = make_input(q, ZERO3, qd, ZERO3, ZERO3, 0.1);
        aocs_vec3_t u;
        assert_int_equal(step(law, &in, &u), AOCS_OK);
        assert_true(u.v[0] < AOCS_R(0.0));
        assert_true(fabs((double)u.v[1]) <= 1e-3 * fabs((double)u.v[0]));
        assert_true(fabs((double)u.v[2]) <= 1e-3 * fabs((double)u.v[0]));
    }
}

/* the random states of check_q_sign_invariance */
typedef struct {
    double w_scale;      /* each w_i uniform in (-w_scale, w_scale), rad/s */
    double wd_scale;     /* the same for wd */
    double wd_dot_scale; /* the same for wd_dot; 0: wd_dot = 0 */
    double tol;          /* assert_vec3_close tolerance between the torques */
    double min_abs_qe4;  /* states with |qe4| below this are skipped (0: none) */
} sign_sweep_t;

/*
 * q and -q (and qd and -qd) are the same attitude: on 200 seeded random
 * states, each of the three sign flips gives the torque of the unflipped
 * input. Returns the number of states tested.
 */
static inline int check_q_sign_invariance(law_step_fn_t step, void *law, const sign_sweep_t *sw)
{
    test_rng_t rng = {0x9E3779B97F4A7C15ULL};
    int tested = 0;
    for (int k = 0; k < 200; ++k) {
        aocs_att_input_t in;
        in.q_BN = test_random_quat(&rng);
        in.qd_DN = test_random_quat(&rng);
        in.w_BN_B = test_random_vec3(&rng, sw->w_scale);
        in.wd_B = test_random_vec3(&rng, sw->wd_scale);
        in.wd_dot_B = (sw->wd_dot_scale > 0.0) ? test_random_vec3(&rng, sw->wd_dot_scale) : aocs_vec3_zero();
        in.dt_s = AOCS_R(0.1);
        in.u_max_axis = aocs_vec3_zero();
        in.u_max_norm = AOCS_R(0.0);
        if (fabs(dq_mul(dq_from_real(in.q_BN), dq_inv(dq_from_real(in.qd_DN))).q[3]) < sw->min_abs_qe4) {
            continue;
        }
        ++tested;
        aocs_vec3_t u_ref;
        assert_int_equal(step(law, &in, &u_ref), AOCS_OK);
        for (int flip = 1; flip < 4; ++flip) {
            aocs_att_input_t in2 = in;
            for (int i = 0; i < 4; ++i) {
                if ((flip & 1) != 0) {
                    in2.q_BN.q[i] = -in.q_BN.q[i];
                }
                if ((flip & 2) != 0) {
                    in2.qd_DN.q[i] = -in.qd_DN.q[i];
                }
            }
            aocs_vec3_t u2;
            assert_int_equal(step(law, &in2, &u2), AOCS_OK);
            assert_vec3_close(u2, u_ref, sw->tol);
        }
    }
    return tested;
}

/* torque_fn_t body: the law's torque at (q, w) towards the fixed target qd (wd = wd_dot = 0, dt = 0.01 s) */
static inline aocs_status_t law_torque(law_step_fn_t step, void *law, dq_t q, const double w[3], dq_t qd, double u[3])
{
    aocs_att_input_t in = make_input(q, w, qd, ZERO3, ZERO3, 0.01);
    aocs_vec3_t uv;
    aocs_status_t st = step(law, &in, &uv);
    dv_from_real(uv, u);
    return st;
}

/* ---- closed loop with an actuator limit and a disturbance (the integral laws, SPEC 5.2): rigid body
 * (SPEC 1), the law once per 0.1 s period, its torque held, clamped per axis, plus the disturbance ---- */
typedef struct {
    double overshoot_rad;  /* largest excursion past the target, along the slew axis */
    double final_err_rad;  /* true angle at the end */
    double max_late_rad;   /* largest true angle over the last tenth of the run */
} sat_loop_result_t;

static inline double sat_loop_err_angle_rad(dq_t q, dq_t qd)
{
    dq_t qe = dq_mul(q, dq_inv(qd));
    double v = sqrt(qe.q[0] * qe.q[0] + qe.q[1] * qe.q[1] + qe.q[2] * qe.q[2]);
    return 2.0 * atan2(v, fabs(qe.q[3]));
}

/*
 * Runs steps periods of 0.1 s from q0 at rest towards qd. lim > 0: the actuator clamps each axis
 * to lim (N m); tell_law: the law's input carries that limit (anti-windup on) or not (0: the law
 * integrates as if unlimited). d: constant disturbance torque (N m). axis: unit slew axis (B).
 */
static inline sat_loop_result_t run_saturated_loop(law_step_fn_t step, void *law, const dmat_t *j, dq_t q0, dq_t qd,
                                               double lim, int tell_law, const double d[3], const double axis[3],
                                               int steps)
{
    plant_t p;
    dq_t q = q0;
    double w[3] = {0.0, 0.0, 0.0};
    sat_loop_result_t r = {0.0, 0.0, 0.0};
    plant_init(&p, j);
    for (int k = 0; k < steps; ++k) {
        aocs_att_input_t in = make_input(q, w, qd, ZERO3, ZERO3, 0.1);
        aocs_vec3_t u;
        double held[3];
        if ((lim > 0.0) && (tell_law != 0)) {
            in.u_max_axis = aocs_vec3_make((real_t)lim, (real_t)lim, (real_t)lim);
        }
        assert_int_equal(step(law, &in, &u), AOCS_OK);
        for (int i = 0; i < 3; ++i) {
            double ui = (double)u.v[i];
            if (lim > 0.0) {
                ui = (ui > lim) ? lim : ((ui < -lim) ? -lim : ui);
            }
            held[i] = ui + d[i];
        }
        plant_rk4(&p, plant_zoh_torque, held, &q, w, 0.1);
        /* past the target: the error along the slew axis changes sign (qe = q qd^-1, started at -axis) */
        dq_t qe = dq_mul(q, dq_inv(qd));
        double s = (qe.q[3] >= 0.0) ? 1.0 : -1.0;
        double along = 2.0 * s * (qe.q[0] * axis[0] + qe.q[1] * axis[1] + qe.q[2] * axis[2]);
        r.overshoot_rad = (along > r.overshoot_rad) ? along : r.overshoot_rad;
        double a = sat_loop_err_angle_rad(q, qd);
        if (k >= steps - steps / 10) {
            r.max_late_rad = (a > r.max_late_rad) ? a : r.max_late_rad;
        }
        r.final_err_rad = a;
    }
    return r;
}

#endif /* AOCS_LAW_TEST_SUPPORT_H */
