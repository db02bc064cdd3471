/*
 * The MEKF's gyroless model (firmware/estimation/mekf.c, docs/spec.md 5.6.12): after fault management
 * excludes the gyro, the filter propagates on the rigid-body dynamics J dw/dt = tau - w x (J w + h_w) with
 * the commanded torque and takes the star tracker. Proves, in the build's precision:
 *  - propagation: without tracker samples and without noise, the filter's rate and attitude follow an
 *    independent truth written here (Euler's equations by RK4 on 1 ms substeps, the attitude turned by the
 *    substep's mean rate) through a tumble with gyroscopic coupling (non-diagonal J, wheel momentum): a wrong
 *    sign of either term of the dynamics, or a rate not carried, is off by orders of magnitude;
 *  - steady_state: on one axis decoupled (diagonal J, no wheel momentum, a slow rate), the filter's attitude
 *    and rate 1-sigma equal the discrete Riccati solution of the per-axis double integrator with white
 *    torque noise, iterated here, within 5 %;
 *  - consistency: a truth driven by a known torque plus white torque noise of the configured spectral
 *    density and a tracker with its configured noise, 8 seeded runs of 300 s: the ensemble NEES (6 dof) of
 *    the attitude and rate errors against the filter's P is within the 99 % band of its chi-square mean,
 *    with tracker samples on time and 0.2 s late (the sign of H = [I -h I] against the rate error: the
 *    bias model's +h makes the late case inconsistent);
 *  - switch: the API's refusals (NULL, not initialised, no gyroless model configured, a non-inertia), the
 *    state at the switch (rate from the caller, P = diag(p0_att^2, p0_rate^2)), the gyro's reading ignored
 *    afterwards (a NaN rate is no error), the bias re-inflation a no-op, a restart started again from the
 *    tracker with the rate prior.
 */
#include <math.h>
#include <string.h>

#include "test_support.h"
#include "aocs/estimation/mekf.h"

#define ARCSEC 4.84813681109536e-6
#define NS UINT64_C(1000000000)
#define DT_S 0.1
#define SUBSTEPS 100

/* ======================= the truth, independent of the filter ======================= */

typedef struct {
    double j[3][3];
    double jinv[3][3];
    double h[3];      /* wheel momentum, N m s, B */
    double q[4];      /* q_BN, Shuster, scalar last */
    double w[3];      /* rad/s, B */
} truth_t;

static void m3v(double a[3][3], const double x[3], double y[3])
{
    for (int i = 0; i < 3; ++i) {
        y[i] = a[i][0] * x[0] + a[i][1] * x[1] + a[i][2] * x[2];
    }
}

static void cross3(const double a[3], const double b[3], double c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

/* inverse of a 3x3 by cofactors */
static void inv3(double a[3][3], double r[3][3])
{
    const double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
                       a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                       a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    for (int i = 0; i < 3; ++i) {
        for (int k = 0; k < 3; ++k) {
            const int i1 = (k + 1) % 3, i2 = (k + 2) % 3, j1 = (i + 1) % 3, j2 = (i + 2) % 3;
            r[i][k] = (a[i1][j1] * a[i2][j2] - a[i1][j2] * a[i2][j1]) / det;
        }
    }
}

/* Euler: J^-1 (tau - w x (J w + h)) */
static void wdot(truth_t *s, const double w[3], const double tau[3], double out[3])
{
    double jw[3], c[3], rhs[3];
    m3v(s->j, w, jw);
    for (int i = 0; i < 3; ++i) {
        jw[i] += s->h[i];
    }
    cross3(w, jw, c);
    for (int i = 0; i < 3; ++i) {
        rhs[i] = tau[i] - c[i];
    }
    m3v(s->jinv, rhs, out);
}

/* q <- dq(r) (x) q, Shuster product (A(q (x) p) = A(q) A(p)) */
static void turn(double q[4], const double r[3])
{
    const double th = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    const double s = (th > 1e-12) ? sin(0.5 * th) / th : 0.5;
    const double a[4] = {s * r[0], s * r[1], s * r[2], cos(0.5 * th)};
    double o[4];
    o[0] = a[3] * q[0] + q[3] * a[0] - (a[1] * q[2] - a[2] * q[1]);
    o[1] = a[3] * q[1] + q[3] * a[1] - (a[2] * q[0] - a[0] * q[2]);
    o[2] = a[3] * q[2] + q[3] * a[2] - (a[0] * q[1] - a[1] * q[0]);
    o[3] = a[3] * q[3] - (a[0] * q[0] + a[1] * q[1] + a[2] * q[2]);
    const double n = sqrt(o[0] * o[0] + o[1] * o[1] + o[2] * o[2] + o[3] * o[3]);
    for (int i = 0; i < 4; ++i) {
        q[i] = o[i] / n;
    }
}

/* one RK4 substep of dt with torque tau held; the attitude turned by the substep's mean rate */
static void truth_substep(truth_t *s, const double tau[3], double dt)
{
    double k1[3], k2[3], k3[3], k4[3], x[3], w0[3], r[3];
    memcpy(w0, s->w, sizeof(w0));
    wdot(s, w0, tau, k1);
    for (int i = 0; i < 3; ++i) x[i] = w0[i] + 0.5 * dt * k1[i];
    wdot(s, x, tau, k2);
    for (int i = 0; i < 3; ++i) x[i] = w0[i] + 0.5 * dt * k2[i];
    wdot(s, x, tau, k3);
    for (int i = 0; i < 3; ++i) x[i] = w0[i] + dt * k3[i];
    wdot(s, x, tau, k4);
    for (int i = 0; i < 3; ++i) {
        s->w[i] = w0[i] + dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        r[i] = 0.5 * (w0[i] + s->w[i]) * dt;
    }
    turn(s->q, r);
}

static void truth_init(truth_t *s, const double j[3][3], const double h[3], const double w0[3], aocs_quat_t q0)
{
    memset(s, 0, sizeof(*s));
    memcpy(s->j, j, sizeof(s->j));
    inv3(s->j, s->jinv);
    memcpy(s->h, h, sizeof(s->h));
    memcpy(s->w, w0, sizeof(s->w));
    for (int i = 0; i < 4; ++i) {
        s->q[i] = (double)q0.q[i];
    }
}

/* the attitude error dth with q_true = dq(dth) (x) q_hat: 2 vec(q_true (x) q_hat^-1), scalar made >= 0 */
static void att_error(const double qt[4], aocs_quat_t qh, double dth[3])
{
    const double b[4] = {-(double)qh.q[0], -(double)qh.q[1], -(double)qh.q[2], (double)qh.q[3]};
    double o[4];
    o[0] = qt[3] * b[0] + b[3] * qt[0] - (qt[1] * b[2] - qt[2] * b[1]);
    o[1] = qt[3] * b[1] + b[3] * qt[1] - (qt[2] * b[0] - qt[0] * b[2]);
    o[2] = qt[3] * b[2] + b[3] * qt[2] - (qt[0] * b[1] - qt[1] * b[0]);
    o[3] = qt[3] * b[3] - (qt[0] * b[0] + qt[1] * b[1] + qt[2] * b[2]);
    const double sg = (o[3] < 0.0) ? -2.0 : 2.0;
    for (int i = 0; i < 3; ++i) {
        dth[i] = sg * o[i];
    }
}

static aocs_mat3_t to_mat3(const double j[3][3])
{
    aocs_mat3_t m;
    for (int i = 0; i < 3; ++i) {
        for (int k = 0; k < 3; ++k) {
            m.m[i][k] = (real_t)j[i][k];
        }
    }
    return m;
}

/* the tracker's sample of the truth: q_SN = dq(nu) (x) q_BN (q_SB identity), nu ~ N(0, sigma^2 I) */
static aocs_quat_t tracker(const truth_t *s, test_rng_t *rng, double sigma)
{
    double q[4];
    double nu[3];
    memcpy(q, s->q, sizeof(q));
    for (int i = 0; i < 3; ++i) {
        nu[i] = sigma * test_rng_normal(rng);
    }
    turn(q, nu);
    return aocs_quat_make((real_t)q[0], (real_t)q[1], (real_t)q[2], (real_t)q[3]);
}

static const double J_TUMBLE[3][3] = {{2000.0, 30.0, -20.0}, {30.0, 3000.0, 10.0}, {-20.0, 10.0, 2500.0}};
static const double H_TUMBLE[3] = {5.0, -3.0, 2.0};

/* the known torque the executive would command: slow sines, N m */
static void known_torque(double t, double tau[3])
{
    tau[0] = 0.05 * sin(0.05 * t);
    tau[1] = 0.03 * sin(0.031 * t + 1.0);
    tau[2] = -0.04 * cos(0.023 * t);
}

static void filter_config(aocs_mekf_config_t *cfg, double st_sigma, double tau_sigma)
{
    aocs_mekf_config_default(cfg);
    cfg->st_sigma_cross_rad = (real_t)st_sigma;
    cfg->st_sigma_about_rad = (real_t)st_sigma;
    cfg->gyroless_torque_sigma_nm = (real_t)tau_sigma;
    cfg->gyroless_p0_rate_sigma_radps = (real_t)1.0e-3;
    cfg->max_gap_s = (real_t)1000.0;
}

/* the filter started from a tracker sample at t = 0 (in gyro mode, rate w_meas) and switched to gyroless */
static void start_gyroless(aocs_mekf_t *f, const aocs_mekf_config_t *cfg, const truth_t *s, aocs_quat_t q_st,
                           const double j[3][3], aocs_vec3_t w_switch)
{
    aocs_mekf_input_t in;
    aocs_mekf_output_t out;
    const aocs_mat3_t jm = to_mat3(j);
    assert_int_equal(aocs_mekf_init(f, cfg), AOCS_OK);
    memset(&in, 0, sizeof(in));
    in.t_ns = 0u;
    in.w_meas_B_radps = aocs_vec3_make((real_t)s->w[0], (real_t)s->w[1], (real_t)s->w[2]);
    in.st.q_SN = q_st;
    in.st.t_meas_ns = 0u;
    in.st.valid = 1u;
    assert_int_equal(aocs_mekf_step(f, &in, &out), AOCS_OK);
    assert_int_equal(aocs_mekf_set_gyroless(f, &jm, w_switch), AOCS_OK);
}

/* ======================= the tests ======================= */

static void propagation(void **state)
{
    (void)state;
    truth_t s;
    aocs_mekf_t f;
    aocs_mekf_config_t cfg;
    aocs_mekf_output_t out;
    const double w0[3] = {0.02, -0.015, 0.01};
    const aocs_quat_t q0 = aocs_quat_make(AOCS_R(0.1), AOCS_R(-0.2), AOCS_R(0.3), AOCS_R(0.9273618495495704));
    double max_w = 0.0, max_att = 0.0;
    truth_init(&s, J_TUMBLE, H_TUMBLE, w0, q0);
    filter_config(&cfg, ARCSEC, 1.0e-3);
    start_gyroless(&f, &cfg, &s, q0, J_TUMBLE, aocs_vec3_make((real_t)w0[0], (real_t)w0[1], (real_t)w0[2]));
    for (int k = 1; k <= 1000; ++k) { /* 100 s */
        double tau[3];
        aocs_mekf_input_t in;
        known_torque((k - 1) * DT_S, tau);
        aocs_mekf_set_torque(&f, aocs_vec3_make((real_t)tau[0], (real_t)tau[1], (real_t)tau[2]),
                             aocs_vec3_make((real_t)H_TUMBLE[0], (real_t)H_TUMBLE[1], (real_t)H_TUMBLE[2]));
        for (int j = 0; j < SUBSTEPS; ++j) {
            truth_substep(&s, tau, DT_S / SUBSTEPS);
        }
        memset(&in, 0, sizeof(in));
        in.t_ns = (uint64_t)k * (NS / 10u);
        in.w_meas_B_radps = aocs_vec3_make((real_t)NAN, (real_t)NAN, (real_t)NAN); /* the excluded gyro: never read */
        assert_int_equal(aocs_mekf_step(&f, &in, &out), AOCS_OK);
        for (int i = 0; i < 3; ++i) {
            const double e = fabs((double)out.w_BN_B_hat.v[i] - s.w[i]);
            max_w = (e > max_w) ? e : max_w;
        }
        {
            double dth[3];
            att_error(s.q, out.q_BN_hat, dth);
            const double a = sqrt(dth[0] * dth[0] + dth[1] * dth[1] + dth[2] * dth[2]);
            max_att = (a > max_att) ? a : max_att;
        }
    }
    /* Heun's rule on 0.1 s steps against RK4 on 1 ms: rates of 2e-2 rad/s turned by gyroscopic terms of
     * order |w| |J w + h| / J ~ 1e-4 rad/s^2: the step's local error (dt^3 / 12 times the third derivative)
     * stays below 1e-10 rad/s, so 1e-8 rad/s over 1000 steps; the body turns 1.5 rad meanwhile */
#if defined(AOCS_REAL_IS_FLOAT)
    assert_true(max_w < 2.0e-7);
    assert_true(max_att < 2.0e-5);
#else
    assert_true(max_w < 1.0e-8);
    assert_true(max_att < 0.1 * ARCSEC);
#endif
}

/* the discrete Riccati solution of one axis: x = [th; w], Phi = [1 dt; 0 1], Q = q [dt^3/3 dt^2/2; dt^2/2 dt],
 * H = [1 0], R = r: the a-posteriori variances of th and w */
static void riccati_axis(double q, double r, double *p_th, double *p_w)
{
    double p[2][2] = {{1.0e-6, 0.0}, {0.0, 1.0e-6}};
    for (int it = 0; it < 200000; ++it) {
        double m[2][2];
        const double dt = DT_S;
        m[0][0] = p[0][0] + dt * (p[1][0] + p[0][1]) + dt * dt * p[1][1] + q * dt * dt * dt / 3.0;
        m[0][1] = p[0][1] + dt * p[1][1] + q * dt * dt / 2.0;
        m[1][0] = m[0][1];
        m[1][1] = p[1][1] + q * dt;
        {
            const double s = m[0][0] + r;
            const double k0 = m[0][0] / s, k1 = m[1][0] / s;
            p[0][0] = (1.0 - k0) * m[0][0];
            p[0][1] = (1.0 - k0) * m[0][1];
            p[1][0] = p[0][1];
            p[1][1] = m[1][1] - k1 * m[0][1];
        }
    }
    *p_th = p[0][0];
    *p_w = p[1][1];
}

static void steady_state(void **state)
{
    (void)state;
    const double j[3][3] = {{2000.0, 0.0, 0.0}, {0.0, 6000.0, 0.0}, {0.0, 0.0, 4000.0}};
    const double h0[3] = {0.0, 0.0, 0.0};
    const double w0[3] = {0.0, 0.0, 0.0};
    const double st = 5.0 * ARCSEC, tau_sigma = 1.0e-2;
    truth_t s;
    aocs_mekf_t f;
    aocs_mekf_config_t cfg;
    aocs_mekf_output_t out;
    test_rng_t rng = {12345u};
    truth_init(&s, j, h0, w0, aocs_quat_identity());
    filter_config(&cfg, st, tau_sigma);
    start_gyroless(&f, &cfg, &s, tracker(&s, &rng, st), j, aocs_vec3_zero());
    for (int k = 1; k <= 3000; ++k) {
        aocs_mekf_input_t in;
        memset(&in, 0, sizeof(in));
        in.t_ns = (uint64_t)k * (NS / 10u);
        in.st.q_SN = tracker(&s, &rng, st);
        in.st.t_meas_ns = in.t_ns;
        in.st.valid = 1u;
        assert_int_equal(aocs_mekf_step(&f, &in, &out), AOCS_OK);
    }
    for (int i = 0; i < 3; ++i) {
        double p_th = 0.0, p_w = 0.0;
        const double qa = (tau_sigma / j[i][i]) * (tau_sigma / j[i][i]);
        riccati_axis(qa, st * st, &p_th, &p_w);
        assert_true(fabs((double)out.sigma[i] / sqrt(p_th) - 1.0) < 0.05);
        assert_true(fabs((double)out.sigma[i + 3] / sqrt(p_w) - 1.0) < 0.05);
    }
}

/* ensemble NEES of [dth; dw] against P over 8 runs of 300 s (from 30 s on), tracker late by latency_s */
static double nees_mean(double latency_s, double *count)
{
    const double st = 3.0 * ARCSEC, tau_sigma = 5.0e-3;
    const uint64_t lat_ns = (uint64_t)(latency_s * 1e9 + 0.5);
    double sum = 0.0;
    double n = 0.0;
    for (uint32_t run = 0u; run < 8u; ++run) {
        truth_t s;
        aocs_mekf_t f;
        aocs_mekf_config_t cfg;
        aocs_mekf_output_t out;
        test_rng_t rng = {1000u + run};
        const double w0[3] = {1e-3 * test_rng_uniform(&rng, -1.0, 1.0), 1e-3 * test_rng_uniform(&rng, -1.0, 1.0),
                              1e-3 * test_rng_uniform(&rng, -1.0, 1.0)};
        /* the tracker's samples: the truth's attitude latency_s ago (a ring of the last 10 steps) */
        aocs_quat_t ring[10];
        truth_init(&s, J_TUMBLE, H_TUMBLE, w0, test_random_quat(&rng));
        filter_config(&cfg, st, tau_sigma);
        ring[0] = tracker(&s, &rng, st);
        start_gyroless(&f, &cfg, &s, ring[0], J_TUMBLE, aocs_vec3_zero());
        for (int k = 1; k <= 3000; ++k) {
            double tau[3];
            double tau_true[3];
            aocs_mekf_input_t in;
            known_torque((k - 1) * DT_S, tau);
            aocs_mekf_set_torque(&f, aocs_vec3_make((real_t)tau[0], (real_t)tau[1], (real_t)tau[2]),
                                 aocs_vec3_make((real_t)H_TUMBLE[0], (real_t)H_TUMBLE[1], (real_t)H_TUMBLE[2]));
            for (int j = 0; j < SUBSTEPS; ++j) {
                /* white torque noise of spectral density tau_sigma^2: variance tau_sigma^2 / dt per substep */
                const double sd = tau_sigma / sqrt(DT_S / SUBSTEPS);
                for (int i = 0; i < 3; ++i) {
                    tau_true[i] = tau[i] + sd * test_rng_normal(&rng);
                }
                truth_substep(&s, tau_true, DT_S / SUBSTEPS);
            }
            ring[k % 10] = tracker(&s, &rng, st);
            memset(&in, 0, sizeof(in));
            in.t_ns = (uint64_t)k * (NS / 10u);
            if (in.t_ns >= lat_ns) {
                const int lag = (int)(lat_ns / (NS / 10u));
                in.st.q_SN = ring[(k - lag) % 10];
                in.st.t_meas_ns = in.t_ns - lat_ns;
                in.st.valid = (k > lag) ? 1u : 0u;
            }
            assert_int_equal(aocs_mekf_step(&f, &in, &out), AOCS_OK);
            if (k >= 300) {
                double e[6];
                double l[6][6];
                double z[6];
                double d2 = 0.0;
                att_error(s.q, out.q_BN_hat, e);
                for (int i = 0; i < 3; ++i) {
                    e[i + 3] = s.w[i] - (double)out.w_BN_B_hat.v[i];
                }
                /* d2 = e^T P^-1 e by Cholesky of P */
                memset(l, 0, sizeof(l));
                for (int c = 0; c < 6; ++c) {
                    double d = (double)out.P.m[c][c];
                    for (int m = 0; m < c; ++m) d -= l[c][m] * l[c][m];
                    l[c][c] = sqrt(d);
                    for (int r = c + 1; r < 6; ++r) {
                        double v = (double)out.P.m[r][c];
                        for (int m = 0; m < c; ++m) v -= l[r][m] * l[c][m];
                        l[r][c] = v / l[c][c];
                    }
                }
                for (int r = 0; r < 6; ++r) {
                    double v = e[r];
                    for (int m = 0; m < r; ++m) v -= l[r][m] * z[m];
                    z[r] = v / l[r][r];
                    d2 += z[r] * z[r];
                }
                sum += d2;
                n += 1.0;
            }
        }
    }
    *count = n;
    return sum / n;
}

static void consistency(void **state)
{
    (void)state;
    const double lat[2] = {0.0, 0.2};
    for (int c = 0; c < 2; ++c) {
        double n = 0.0;
        const double m = nees_mean(lat[c], &n);
        /* the mean of 6-dof chi-square samples is 6; the samples of one run are correlated over the filter's
         * time constants (some seconds), so the band is that of about n / 100 independent samples at 99 %:
         * 6 +- 2.58 sqrt(12 / (n / 100)) */
        const double half = 2.58 * sqrt(12.0 / (n / 100.0));
        print_message("gyroless NEES, tracker %.2f s late: %.3f (band 6 +- %.3f)\n", lat[c], m, half);
        assert_true(fabs(m - 6.0) < half);
    }
}

static void switch_rules(void **state)
{
    (void)state;
    aocs_mekf_t f;
    aocs_mekf_config_t cfg;
    aocs_mekf_output_t out;
    aocs_mekf_input_t in;
    truth_t s;
    const double w0[3] = {0.0, 0.0, 0.0};
    const aocs_mat3_t jm = to_mat3(J_TUMBLE);
    aocs_mat3_t bad = to_mat3(J_TUMBLE);
    filter_config(&cfg, ARCSEC, 1.0e-3);
    /* refusals */
    assert_int_equal(aocs_mekf_set_gyroless(NULL, &jm, aocs_vec3_zero()), AOCS_ERR_NULL_ARG);
    memset(&f, 0, sizeof(f));
    assert_int_equal(aocs_mekf_set_gyroless(&f, &jm, aocs_vec3_zero()), AOCS_ERR_NOT_INITIALISED);
    assert_int_equal(aocs_mekf_init(&f, &cfg), AOCS_OK);
    assert_int_equal(aocs_mekf_set_gyroless(&f, NULL, aocs_vec3_zero()), AOCS_ERR_NULL_ARG);
    bad.m[0][1] = (real_t)300.0; /* not symmetric */
    assert_int_equal(aocs_mekf_set_gyroless(&f, &bad, aocs_vec3_zero()), AOCS_ERR_INERTIA_NOT_SYMMETRIC);
    bad = to_mat3(J_TUMBLE);
    bad.m[2][2] = (real_t)-1.0;
    assert_int_equal(aocs_mekf_set_gyroless(&f, &bad, aocs_vec3_zero()), AOCS_ERR_INERTIA_NOT_POS_DEF);
    assert_int_equal(aocs_mekf_is_gyroless(&f), 0u);
    cfg.gyroless_torque_sigma_nm = (real_t)0.0; /* no model configured: valid, but no switch */
    assert_int_equal(aocs_mekf_init(&f, &cfg), AOCS_OK);
    assert_int_equal(aocs_mekf_set_gyroless(&f, &jm, aocs_vec3_zero()), AOCS_ERR_MEKF_NOISE_NOT_POSITIVE);
    cfg.gyroless_torque_sigma_nm = (real_t)-1.0e-3;
    assert_int_equal(aocs_mekf_init(&f, &cfg), AOCS_ERR_MEKF_NOISE_NOT_POSITIVE);
    cfg.gyroless_torque_sigma_nm = (real_t)1.0e-3;
    cfg.gyroless_rate_sigma_radps = (real_t)0.0;
    assert_int_equal(aocs_mekf_init(&f, &cfg), AOCS_ERR_MEKF_NOISE_NOT_POSITIVE);
    cfg.gyroless_rate_sigma_radps = (real_t)1.0e-5;
    cfg.gyroless_p0_rate_sigma_radps = (real_t)NAN;
    assert_int_equal(aocs_mekf_init(&f, &cfg), AOCS_ERR_PARAM_NOT_FINITE);
    assert_int_equal(aocs_mekf_is_gyroless(NULL), 0u);

    /* the switch: rate from the caller (a non-finite one taken as zero), P block-diagonal at the priors */
    filter_config(&cfg, ARCSEC, 1.0e-3);
    truth_init(&s, J_TUMBLE, H_TUMBLE, w0, aocs_quat_identity());
    start_gyroless(&f, &cfg, &s, aocs_quat_identity(), J_TUMBLE, aocs_vec3_make(AOCS_R(1e-3), AOCS_R(-2e-3), AOCS_R(3e-3)));
    assert_int_equal(aocs_mekf_is_gyroless(&f), 1u);
    assert_int_equal(aocs_mekf_get_output(&f, &out), AOCS_OK);
    assert_vec3_close(out.w_BN_B_hat, aocs_vec3_make(AOCS_R(1e-3), AOCS_R(-2e-3), AOCS_R(3e-3)), 0.0);
    for (int i = 0; i < 6; ++i) {
        for (int k = 0; k < 6; ++k) {
            double want = 0.0;
            if (i == k) {
                want = (i < 3) ? (double)(cfg.p0_att_sigma_rad * cfg.p0_att_sigma_rad)
                               : (double)(cfg.gyroless_p0_rate_sigma_radps * cfg.gyroless_p0_rate_sigma_radps);
            }
            assert_close(out.P.m[i][k], want, 1e-6 * want + 1e-30);
        }
    }
    assert_int_equal(aocs_mekf_set_gyroless(&f, &jm, aocs_vec3_make((real_t)NAN, AOCS_R(0.0), AOCS_R(0.0))), AOCS_OK);
    assert_int_equal(aocs_mekf_get_output(&f, &out), AOCS_OK);
    assert_vec3_close(out.w_BN_B_hat, aocs_vec3_zero(), 0.0);
    /* the bias re-inflation does not touch the rate block */
    aocs_mekf_reinflate_bias(&f);
    assert_int_equal(aocs_mekf_get_output(&f, &out), AOCS_OK);
    assert_close(out.P.m[3][3], (double)(cfg.gyroless_p0_rate_sigma_radps * cfg.gyroless_p0_rate_sigma_radps), 1e-12);
    /* a non-finite torque is taken as none: the rate holds (no wheel momentum, zero rate) */
    aocs_mekf_set_torque(&f, aocs_vec3_make((real_t)INFINITY, AOCS_R(0.0), AOCS_R(0.0)), aocs_vec3_make(AOCS_R(0.0), (real_t)NAN, AOCS_R(0.0)));
    memset(&in, 0, sizeof(in));
    in.t_ns = NS / 10u;
    in.w_meas_B_radps = aocs_vec3_make(AOCS_R(1.0e9), (real_t)NAN, AOCS_R(0.0)); /* beyond the range and NaN: not read */
    assert_int_equal(aocs_mekf_step(&f, &in, &out), AOCS_OK);
    assert_vec3_close(out.w_BN_B_hat, aocs_vec3_zero(), 0.0);
    /* a gap restarts the filter; it starts again from the tracker, gyroless, rate zero at its prior */
    in.t_ns = 2000u * NS;
    assert_int_equal(aocs_mekf_step(&f, &in, &out), AOCS_ERR_MEKF_NO_ATTITUDE); /* the gap restarted it */
    assert_int_equal(aocs_mekf_is_gyroless(&f), 1u);
    in.t_ns += NS / 10u;
    in.st.q_SN = aocs_quat_identity();
    in.st.t_meas_ns = in.t_ns;
    in.st.valid = 1u;
    assert_int_equal(aocs_mekf_step(&f, &in, &out), AOCS_OK);
    assert_close(out.sigma[3], cfg.gyroless_p0_rate_sigma_radps, 1e-3 * (double)cfg.gyroless_p0_rate_sigma_radps);
    /* init clears the mode */
    assert_int_equal(aocs_mekf_init(&f, &cfg), AOCS_OK);
    assert_int_equal(aocs_mekf_is_gyroless(&f), 0u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(switch_rules),
        cmocka_unit_test(propagation),
        cmocka_unit_test(steady_state),
        cmocka_unit_test(consistency),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
