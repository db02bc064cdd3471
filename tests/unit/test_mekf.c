/*
 * MEKF of attitude and gyro bias (firmware/estimation/mekf.c, docs/spec.md 5.6).
 * Proves, in the build's precision (double and float):
 *  - reference_filter: the filter equals an independent double-precision 6x6
 *    MEKF written here (own quaternion algebra, Phi and Q_d by Van Loan's
 *    matrix exponential instead of the closed forms, the delayed residual
 *    formed at t_meas in that frame with H = A(M)^T [I h I] instead of carried
 *    forward, 3x3 inverse by cofactors, explicit Joseph products) on a seeded
 *    random trajectory with fast rates (series and closed-form branches),
 *    varying steps, delayed samples between step boundaries, a rotated tracker
 *    with different about-boresight noise: attitude, bias and P agree;
 *  - riccati_ode: the closed-form Phi and Q_d of one and of two propagations
 *    equal the continuous Riccati equation Pdot = F P + P F^T + G Q G^T
 *    integrated by 4000 RK4 steps;
 *  - steady_state_*: a three-axis simulation (truth attitude, gyro with ARW and
 *    RRW, star-tracker noise, seeded, 8 runs): the filter's per-axis 1-sigma
 *    within 10 % of the analytic steady state (the discrete Riccati solution of
 *    Farrenkopf's two-state per-axis model, iterated here), the measured error
 *    1-sigma within 10 % of it, the ensemble NEES (6 dof) inside its 99 %
 *    chi-square band for >= 95 % of the 10 s windows, the +-3 sigma fraction of
 *    the errors in [99 %, 99.9 %]; at 10 Hz and at 2 Hz (for two sensor sets),
 *    and at 2 Hz with a 0.25 s tracker latency (consistency);
 *  - configured_start: mekf.init_mode configured, the filter started at a q0_BN
 *    1 deg off with a 1 deg/h bias per axis it does not know: the time its 30 s
 *    rms error enters 3 times the steady state is stated from the filter's
 *    own gains (the expected rms of the two-state model, mean and noise-driven,
 *    inside 1.5 times the steady state) and every run meets it; no tracker
 *    needed to start; a reset waits for the tracker again;
 *  - convergence: from a 1 deg attitude error and a 1 deg/h unknown bias the
 *    knowledge error's 30 s RMS per axis enters 3 times the steady state
 *    within CONV_BOUND_S and stays there to the end (4 runs, 600 s);
 *  - outage: 600 s without star tracker: the error stays inside the growing
 *    +-3 sigma (>= 99 % of the outage samples of every axis, none beyond
 *    3.5 sigma: a consistent filter's error crosses 3 sigma for 0.27 % of the
 *    time), and from 60 s after the tracker returns the error is inside 3
 *    times the steady state with P within 10 % of it;
 *  - gating (1 deg step outliers rejected and counted, the state untouched),
 *    the quaternion reset (unit norm after 1 deg corrections), the
 *    positive-definiteness rule (symmetric, floored, a broken P restarts the
 *    filter), hostile inputs (NaN, Inf, non-unit, stale, future, too old, gap,
 *    rate range, time not advancing) each with its status, output zeroed on
 *    a failed step and never NaN, the state exactly that of a twin that
 *    never saw them; config validation.
 */
#include <string.h>

#include "test_support.h"
#include "aocs/estimation/mekf.h"

#define ARCSEC 4.84813681109536e-6
#define DEG 0.017453292519943295
#define NS 1000000000ull

#if defined(AOCS_REAL_IS_FLOAT)
#define REF_TOL_ANGLE 2.0e-6 /* rad */
#define REF_TOL_REL 2.0e-3   /* of the largest P element of its block */
#define ODE_TOL_REL 1.0e-4
#else
#define REF_TOL_ANGLE 1.0e-12
#define REF_TOL_REL 1.0e-9
#define ODE_TOL_REL 1.0e-10
#endif

/* ======================= independent double-precision helpers ======================= */

typedef struct {
    double q[4];
} rq_t;

/* Shuster product: A(q (x) p) = A(q) A(p) (docs/conventions.md) */
static rq_t rq_mul(rq_t a, rq_t b)
{
    rq_t r;
    r.q[0] = a.q[3] * b.q[0] + b.q[3] * a.q[0] - (a.q[1] * b.q[2] - a.q[2] * b.q[1]);
    r.q[1] = a.q[3] * b.q[1] + b.q[3] * a.q[1] - (a.q[2] * b.q[0] - a.q[0] * b.q[2]);
    r.q[2] = a.q[3] * b.q[2] + b.q[3] * a.q[2] - (a.q[0] * b.q[1] - a.q[1] * b.q[0]);
    r.q[3] = a.q[3] * b.q[3] - (a.q[0] * b.q[0] + a.q[1] * b.q[1] + a.q[2] * b.q[2]);
    return r;
}

static rq_t rq_conj(rq_t a)
{
    rq_t r = {{-a.q[0], -a.q[1], -a.q[2], a.q[3]}};
    return r;
}

static rq_t rq_norm(rq_t a)
{
    double n = sqrt(a.q[0] * a.q[0] + a.q[1] * a.q[1] + a.q[2] * a.q[2] + a.q[3] * a.q[3]);
    rq_t r = {{a.q[0] / n, a.q[1] / n, a.q[2] / n, a.q[3] / n}};
    return r;
}

/* rotation of rotation vector v (the "exp" of v/2) */
static rq_t rq_exp(const double v[3])
{
    double th = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    double k = (th > 1e-8) ? sin(0.5 * th) / th : 0.5 - th * th / 48.0;
    rq_t r = {{k * v[0], k * v[1], k * v[2], cos(0.5 * th)}};
    return r;
}

/* 2 vec(a (x) b^-1) with the sign of the scalar part fixed: the small rotation from b to a */
static void rq_err(rq_t a, rq_t b, double e[3])
{
    rq_t d = rq_mul(a, rq_conj(b));
    double s = (d.q[3] < 0.0) ? -2.0 : 2.0;
    for (int i = 0; i < 3; ++i) {
        e[i] = s * d.q[i];
    }
}

static double rq_angle(rq_t a, rq_t b)
{
    rq_t d = rq_mul(a, rq_conj(b));
    double v = sqrt(d.q[0] * d.q[0] + d.q[1] * d.q[1] + d.q[2] * d.q[2]);
    return 2.0 * atan2(v, fabs(d.q[3]));
}

static rq_t rq_from(aocs_quat_t q)
{
    rq_t r = {{(double)q.q[0], (double)q.q[1], (double)q.q[2], (double)q.q[3]}};
    return r;
}

static aocs_quat_t rq_to(rq_t q)
{
    return aocs_quat_make((real_t)q.q[0], (real_t)q.q[1], (real_t)q.q[2], (real_t)q.q[3]);
}

/* A(q) of docs/conventions.md written out in double */
static void rq_dcm(rq_t q, double a[3][3])
{
    double q1 = q.q[0], q2 = q.q[1], q3 = q.q[2], q4 = q.q[3];
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

static void rm_mul(int n, int m, int p, const double *a, const double *b, double *c)
{
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < p; ++j) {
            double s = 0.0;
            for (int k = 0; k < m; ++k) {
                s += a[i * m + k] * b[k * p + j];
            }
            c[i * p + j] = s;
        }
    }
}

static void rm_transpose(int n, int m, const double *a, double *t)
{
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < m; ++j) {
            t[j * n + i] = a[i * m + j];
        }
    }
}

/* exp(A) of an n x n matrix (n <= 12): scaling by 2^s, Taylor to order 24, squaring */
static void rm_expm(int n, const double *a, double *e)
{
    double norm = 0.0;
    int s = 0;
    double as[144], term[144], tmp[144];
    for (int i = 0; i < n * n; ++i) {
        norm = fmax(norm, fabs(a[i]));
    }
    norm *= (double)n;
    while (norm > 0.25) {
        norm *= 0.5;
        ++s;
    }
    for (int i = 0; i < n * n; ++i) {
        as[i] = ldexp(a[i], -s);
        term[i] = (i % (n + 1) == 0) ? 1.0 : 0.0;
        e[i] = term[i];
    }
    for (int k = 1; k <= 24; ++k) {
        rm_mul(n, n, n, term, as, tmp);
        for (int i = 0; i < n * n; ++i) {
            term[i] = tmp[i] / (double)k;
            e[i] += term[i];
        }
    }
    for (int k = 0; k < s; ++k) {
        rm_mul(n, n, n, e, e, tmp);
        memcpy(e, tmp, sizeof(double) * (size_t)(n * n));
    }
}

static void rm_inv3(const double a[9], double inv[9])
{
    double c00 = a[4] * a[8] - a[5] * a[7], c01 = a[5] * a[6] - a[3] * a[8], c02 = a[3] * a[7] - a[4] * a[6];
    double det = a[0] * c00 + a[1] * c01 + a[2] * c02;
    inv[0] = c00 / det;
    inv[3] = c01 / det;
    inv[6] = c02 / det;
    inv[1] = (a[2] * a[7] - a[1] * a[8]) / det;
    inv[4] = (a[0] * a[8] - a[2] * a[6]) / det;
    inv[7] = (a[1] * a[6] - a[0] * a[7]) / det;
    inv[2] = (a[1] * a[5] - a[2] * a[4]) / det;
    inv[5] = (a[2] * a[3] - a[0] * a[5]) / det;
    inv[8] = (a[0] * a[4] - a[1] * a[3]) / det;
}

/* F (6x6) of the error dynamics for the rate w: [[-[w x], -I], [0, 0]] */
static void ref_f(const double w[3], double f[36])
{
    memset(f, 0, sizeof(double) * 36);
    f[0 * 6 + 1] = w[2];
    f[0 * 6 + 2] = -w[1];
    f[1 * 6 + 0] = -w[2];
    f[1 * 6 + 2] = w[0];
    f[2 * 6 + 0] = w[1];
    f[2 * 6 + 1] = -w[0];
    for (int i = 0; i < 3; ++i) {
        f[i * 6 + i + 3] = -1.0;
    }
}

/* Van Loan (1978): exp([[-F, G Q G^T], [0, F^T]] dt) = [[., Phi^-1 Qd], [0, Phi^T]] */
static void ref_phi_qd(const double w[3], double dt, double sv, double su, double phi[36], double qd[36])
{
    double f[36], big[144], e[144], phit[36], b12[36];
    ref_f(w, f);
    memset(big, 0, sizeof(big));
    for (int i = 0; i < 6; ++i) {
        for (int j = 0; j < 6; ++j) {
            big[i * 12 + j] = -f[i * 6 + j] * dt;
            big[(i + 6) * 12 + j + 6] = f[j * 6 + i] * dt;
        }
        big[i * 12 + i + 6] = ((i < 3) ? sv * sv : su * su) * dt;
    }
    rm_expm(12, big, e);
    for (int i = 0; i < 6; ++i) {
        for (int j = 0; j < 6; ++j) {
            phit[i * 6 + j] = e[(i + 6) * 12 + j + 6];
            b12[i * 6 + j] = e[i * 12 + j + 6];
        }
    }
    rm_transpose(6, 6, phit, phi);
    rm_mul(6, 6, 6, phi, b12, qd);
}

/* ======================= the reference filter ======================= */

#define REF_HIST 64

typedef struct {
    rq_t q;
    double b[3];
    double p[36];
    double sc, sa, sv, su;
    rq_t q_sb;
    double gate;
    /* history: rate and time span of each step, newest last */
    double hw[REF_HIST][3];
    uint64_t ht0[REF_HIST], ht1[REF_HIST];
    int hn;
    uint64_t t;
    uint32_t n_upd, n_gated;
} ref_filter_t;

static void ref_start(ref_filter_t *r, rq_t q_sn, uint64_t t, double p0a, double p0b)
{
    r->q = rq_norm(rq_mul(rq_conj(r->q_sb), q_sn));
    memset(r->b, 0, sizeof(r->b));
    memset(r->p, 0, sizeof(r->p));
    for (int i = 0; i < 3; ++i) {
        r->p[i * 7] = p0a * p0a;
        r->p[(i + 3) * 7] = p0b * p0b;
    }
    r->hn = 0;
    r->t = t;
}

static void ref_propagate(ref_filter_t *r, const double wm[3], uint64_t t)
{
    double dt = (double)(t - r->t) * 1e-9;
    double w[3], v[3], phi[36], qd[36], tmp[36], phit[36];
    for (int i = 0; i < 3; ++i) {
        w[i] = wm[i] - r->b[i];
        v[i] = w[i] * dt;
    }
    ref_phi_qd(w, dt, r->sv, r->su, phi, qd);
    rm_mul(6, 6, 6, phi, r->p, tmp);
    rm_transpose(6, 6, phi, phit);
    rm_mul(6, 6, 6, tmp, phit, r->p);
    for (int i = 0; i < 36; ++i) {
        r->p[i] += qd[i];
    }
    r->q = rq_norm(rq_mul(rq_exp(v), r->q));
    if (r->hn == REF_HIST) {
        memmove(&r->hw[0], &r->hw[1], sizeof(r->hw[0]) * (REF_HIST - 1));
        memmove(&r->ht0[0], &r->ht0[1], sizeof(r->ht0[0]) * (REF_HIST - 1));
        memmove(&r->ht1[0], &r->ht1[1], sizeof(r->ht1[0]) * (REF_HIST - 1));
        r->hn--;
    }
    memcpy(r->hw[r->hn], w, sizeof(w));
    r->ht0[r->hn] = r->t;
    r->ht1[r->hn] = t;
    r->hn++;
    r->t = t;
}

/* the sample at t_meas: residual against the estimate at t_meas, H = A(M)^T [I h I], R in B at t_meas */
static int ref_update(ref_filter_t *r, rq_t q_sn, uint64_t t_meas)
{
    rq_t m = {{0.0, 0.0, 0.0, 1.0}};
    double am[3][3], asb[3][3], h[18], ht[18], rb[9], s[9], si[9], y[3], ph[18], k[18], kh[36], a[36], at[36],
        tmp[36], pj[36], kr[18], kt[18], krk[36];
    double hdel = (double)(r->t - t_meas) * 1e-9;
    double d2 = 0.0;
    for (int i = r->hn - 1; i >= 0 && t_meas < r->t; --i) {
        double span = (double)(r->ht1[i] - ((r->ht0[i] > t_meas) ? r->ht0[i] : t_meas)) * 1e-9;
        double v[3] = {r->hw[i][0] * span, r->hw[i][1] * span, r->hw[i][2] * span};
        m = rq_mul(m, rq_exp(v));
        if (r->ht0[i] <= t_meas) {
            break;
        }
    }
    {
        rq_t q_at = rq_mul(rq_conj(m), r->q); /* the estimate at t_meas */
        rq_t q_meas = rq_mul(rq_conj(r->q_sb), q_sn);
        rq_err(q_meas, q_at, y);
    }
    rq_dcm(m, am);
    rq_dcm(r->q_sb, asb);
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            h[i * 6 + j] = am[j][i];
            h[i * 6 + j + 3] = hdel * am[j][i];
            double sum = 0.0;
            for (int q = 0; q < 3; ++q) {
                double var = (q < 2) ? r->sc * r->sc : r->sa * r->sa;
                sum += asb[q][i] * var * asb[q][j];
            }
            rb[i * 3 + j] = sum;
        }
    }
    rm_transpose(3, 6, h, ht);
    rm_mul(6, 6, 3, r->p, ht, ph);
    rm_mul(3, 6, 3, h, ph, s);
    for (int i = 0; i < 9; ++i) {
        s[i] += rb[i];
    }
    rm_inv3(s, si);
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            d2 += y[i] * si[i * 3 + j] * y[j];
        }
    }
    if (!(d2 <= r->gate)) {
        r->n_gated++;
        return 0;
    }
    rm_mul(6, 3, 3, ph, si, k);
    rm_mul(6, 3, 6, k, h, kh);
    for (int i = 0; i < 36; ++i) {
        a[i] = ((i % 7) == 0 ? 1.0 : 0.0) - kh[i];
    }
    rm_transpose(6, 6, a, at);
    rm_mul(6, 6, 6, a, r->p, tmp);
    rm_mul(6, 6, 6, tmp, at, pj);
    rm_mul(6, 3, 3, k, rb, kr);
    rm_transpose(6, 3, k, kt);
    rm_mul(6, 3, 6, kr, kt, krk);
    for (int i = 0; i < 36; ++i) {
        r->p[i] = pj[i] + krk[i];
    }
    {
        double dx[6];
        for (int i = 0; i < 6; ++i) {
            dx[i] = k[i * 3] * y[0] + k[i * 3 + 1] * y[1] + k[i * 3 + 2] * y[2];
        }
        r->q = rq_norm(rq_mul(rq_exp(dx), r->q));
        for (int i = 0; i < 3; ++i) {
            r->b[i] += dx[i + 3];
        }
    }
    r->n_upd++;
    return 1;
}

/* ======================= simulation of truth and sensors ======================= */

typedef struct {
    double sc, sa;  /* tracker 1-sigma cross / about boresight, rad */
    double sv, su;  /* gyro ARW, RRW */
    double dt;      /* control period, s */
    int st_every;   /* tracker sample every this many steps */
    uint64_t latency_ns;
    rq_t q_sb;
} sim_sensors_t;

typedef struct {
    rq_t q;          /* truth q_BN */
    double b[3];     /* true gyro bias */
    double w[3];     /* true body rate */
    test_rng_t rng;
    rq_t hist_q[64]; /* truth at the last steps, for the latency */
} sim_truth_t;

static void sim_init(sim_truth_t *s, uint64_t seed, double bias_sigma)
{
    s->rng.s = seed;
    s->q = rq_from(test_random_quat(&s->rng));
    for (int i = 0; i < 3; ++i) {
        s->b[i] = bias_sigma * test_rng_normal(&s->rng);
        s->w[i] = 1.0e-3 * test_rng_uniform(&s->rng, -1.0, 1.0);
    }
    for (int i = 0; i < 64; ++i) {
        s->hist_q[i] = s->q;
    }
}

/* one step: truth advanced over dt (rate held), gyro measurement of that step (Markley & Crassidis 2014, sec. 6.4) */
static void sim_step(sim_truth_t *s, const sim_sensors_t *c, double wm[3])
{
    double v[3];
    double bnext[3];
    for (int i = 0; i < 3; ++i) {
        bnext[i] = s->b[i] + c->su * sqrt(c->dt) * test_rng_normal(&s->rng);
        wm[i] = s->w[i] + 0.5 * (s->b[i] + bnext[i]) +
                sqrt(c->sv * c->sv / c->dt + c->su * c->su * c->dt / 12.0) * test_rng_normal(&s->rng);
        s->b[i] = bnext[i];
        v[i] = s->w[i] * c->dt;
    }
    s->q = rq_norm(rq_mul(rq_exp(v), s->q));
    memmove(&s->hist_q[1], &s->hist_q[0], sizeof(s->hist_q[0]) * 63);
    s->hist_q[0] = s->q;
}

/* a tracker measurement of the truth `lag` steps ago: q_SN = exp(nu_S) (x) q_SB (x) q_BN */
static rq_t sim_tracker(sim_truth_t *s, const sim_sensors_t *c, int lag)
{
    double nu[3] = {c->sc * test_rng_normal(&s->rng), c->sc * test_rng_normal(&s->rng),
                    c->sa * test_rng_normal(&s->rng)};
    return rq_norm(rq_mul(rq_exp(nu), rq_mul(c->q_sb, s->hist_q[lag])));
}

static aocs_mekf_config_t cfg_for(const sim_sensors_t *c, double p0a, double p0b)
{
    aocs_mekf_config_t cfg;
    aocs_mekf_config_default(&cfg);
    cfg.q_SB = rq_to(c->q_sb);
    cfg.st_sigma_cross_rad = (real_t)c->sc;
    cfg.st_sigma_about_rad = (real_t)c->sa;
    cfg.gyro_arw_radpsqrts = (real_t)c->sv;
    cfg.gyro_rrw_radps1p5 = (real_t)c->su;
    cfg.p0_att_sigma_rad = (real_t)p0a;
    cfg.p0_bias_sigma_radps = (real_t)p0b;
    return cfg;
}

static aocs_mekf_input_t input_of(uint64_t t, const double wm[3], int st_valid, rq_t q_sn, uint64_t t_meas)
{
    aocs_mekf_input_t in;
    memset(&in, 0, sizeof(in));
    in.t_ns = t;
    in.w_meas_B_radps = aocs_vec3_make((real_t)wm[0], (real_t)wm[1], (real_t)wm[2]);
    in.st.valid = (uint32_t)st_valid;
    in.st.q_SN = rq_to(q_sn);
    in.st.t_meas_ns = t_meas;
    return in;
}

/* the filter's error: attitude dth (q = dq(dth) (x) q_hat) and bias (b - b_hat) */
static void est_error(const sim_truth_t *s, const aocs_mekf_output_t *o, double e[6])
{
    rq_err(s->q, rq_from(o->q_BN_hat), e);
    for (int i = 0; i < 3; ++i) {
        e[i + 3] = s->b[i] - (double)o->bias_B_hat.v[i];
    }
}

/* e^T P^-1 e (6 x 6, Cholesky in double) */
static double nees6(const aocs_mekf_output_t *o, const double e[6])
{
    double l[6][6] = {{0}};
    double z[6];
    double d2 = 0.0;
    for (int j = 0; j < 6; ++j) {
        double d = (double)o->P.m[j][j];
        for (int k = 0; k < j; ++k) {
            d -= l[j][k] * l[j][k];
        }
        l[j][j] = sqrt(d);
        for (int i = j + 1; i < 6; ++i) {
            double v = (double)o->P.m[i][j];
            for (int k = 0; k < j; ++k) {
                v -= l[i][k] * l[j][k];
            }
            l[i][j] = v / l[j][j];
        }
    }
    for (int i = 0; i < 6; ++i) {
        double v = e[i];
        for (int k = 0; k < i; ++k) {
            v -= l[i][k] * z[k];
        }
        z[i] = v / l[i][i];
        d2 += z[i] * z[i];
    }
    return d2;
}

/* chi-square quantile, Wilson-Hilferty (relative error < 1e-3 for k >= 30) */
static double chi2_quantile(double k, double z)
{
    double c = 2.0 / (9.0 * k);
    double t = 1.0 - c + z * sqrt(c);
    return k * t * t * t;
}

/*
 * Steady state of the per-axis two-state model (Farrenkopf 1978): the discrete
 * Riccati recursion of x = [angle, bias], Phi = [[1, -T], [0, 1]],
 * Q = [[sv^2 T + su^2 T^3/3, -su^2 T^2/2], [., su^2 T]], H = [1 0], R = sn^2,
 * T the period between tracker samples, iterated to convergence in long
 * double. Post-update 1-sigma of the angle and of the bias.
 */
static void farrenkopf_riccati(double sn, double sv, double su, double t, double *sig_att, double *sig_bias)
{
    long double p11 = 1e-4L, p12 = 0.0L, p22 = 1e-10L;
    long double lt = (long double)t;
    for (long it = 0; it < 4000000L; ++it) {
        /* propagate */
        long double a = p11 - 2.0L * lt * p12 + lt * lt * p22 + (long double)(sv * sv) * lt +
                        (long double)(su * su) * lt * lt * lt / 3.0L;
        long double b = p12 - lt * p22 - (long double)(su * su) * lt * lt / 2.0L;
        long double c = p22 + (long double)(su * su) * lt;
        /* update */
        long double s = a + (long double)(sn * sn);
        long double n11 = a - a * a / s, n12 = b - a * b / s, n22 = c - b * b / s;
        long double ch = fabsl(n11 - p11) / n11 + fabsl(n22 - p22) / n22;
        p11 = n11;
        p12 = n12;
        p22 = n22;
        if ((ch < 1e-15L) && (it > 1000)) {
            break;
        }
    }
    *sig_att = (double)sqrtl(p11);
    *sig_bias = (double)sqrtl(p22);
}

/* ======================= tests ======================= */

/* a started filter and its reference twin on a rotated tracker */
static void reference_run(uint64_t seed, double rate_scale, double dt_long)
{
    test_rng_t rng = {seed};
    sim_sensors_t c = {20.0 * ARCSEC, 90.0 * ARCSEC, 3e-5, 2e-7, 0.1, 1, 0u, {{0.0, 0.0, 0.0, 1.0}}};
    aocs_mekf_config_t cfg;
    aocs_mekf_t f;
    aocs_mekf_output_t o;
    ref_filter_t r;
    rq_t q_true = rq_from(test_random_quat(&rng));
    uint64_t t = 5u * NS;
    double worst_q = 0.0, worst_p = 0.0, worst_b = 0.0;
    uint64_t t_last_used = t;
    c.q_sb = rq_from(test_random_quat(&rng));
    cfg = cfg_for(&c, 0.5 * DEG, 1e-4);
    cfg.gate_chi2 = (real_t)1e12; /* no sample gated here: gating has its own test */
    assert_int_equal(aocs_mekf_init(&f, &cfg), AOCS_OK);
    memset(&r, 0, sizeof(r));
    r.sc = c.sc;
    r.sa = c.sa;
    r.sv = c.sv;
    r.su = c.su;
    r.q_sb = rq_from(cfg.q_SB);
    r.gate = 1e12;
    {
        /* first sample 0.3 deg off the truth: the first updates are large */
        double off[3] = {0.3 * DEG, -0.2 * DEG, 0.1 * DEG};
        rq_t q_sn = rq_norm(rq_mul(r.q_sb, rq_mul(rq_exp(off), q_true)));
        double wm[3] = {0.0, 0.0, 0.0};
        aocs_mekf_input_t in = input_of(t, wm, 1, q_sn, t);
        assert_int_equal(aocs_mekf_step(&f, &in, &o), AOCS_OK);
        ref_start(&r, rq_from(in.st.q_SN), t, 0.5 * DEG, 1e-4);
    }
    for (int k = 0; k < 1500; ++k) {
        double wm[3];
        double dt = ((k % 97) == 50) ? dt_long : test_rng_uniform(&rng, 0.05, 0.2);
        uint64_t dt_ns = (uint64_t)(dt * 1e9);
        double v[3];
        int with_st = ((k % 3) != 1) ? 1 : 0;
        uint64_t lag_ns = ((k % 5) == 0) ? (uint64_t)(test_rng_uniform(&rng, 0.0, 0.9) * 1e9) : 0u;
        if (t + dt_ns - lag_ns <= t_last_used) {
            with_st = 0; /* a stale sample is not a comparison (hostile_inputs tests it) */
        }
        for (int i = 0; i < 3; ++i) {
            wm[i] = rate_scale * test_rng_uniform(&rng, -1.0, 1.0);
            v[i] = wm[i] * dt;
        }
        t += dt_ns;
        q_true = rq_norm(rq_mul(rq_exp(v), q_true));
        {
            /* the sample: the reference filter's own estimate at t_meas plus noise, so residuals are sane */
            uint64_t t_meas = t - lag_ns;
            double nu[3] = {c.sc * test_rng_normal(&rng), c.sc * test_rng_normal(&rng), c.sa * test_rng_normal(&rng)};
            rq_t q_sn = rq_norm(rq_mul(rq_exp(nu), rq_mul(r.q_sb, q_true)));
            aocs_mekf_input_t in = input_of(t, wm, with_st, q_sn, t_meas);
            aocs_status_t st = aocs_mekf_step(&f, &in, &o);
            assert_int_equal(st, AOCS_OK);
            ref_propagate(&r, wm, t);
            if (with_st != 0) {
                int used = ref_update(&r, rq_from(in.st.q_SN), t_meas);
                assert_int_equal(o.st_status, used ? AOCS_OK : AOCS_ERR_MEKF_GATED);
                t_last_used = t_meas;
            }
        }
        {
            double pmax_a = 0.0, pmax_b = 0.0, pmax_c = 0.0;
            double dq = rq_angle(rq_from(o.q_BN_hat), r.q);
            for (int i = 0; i < 3; ++i) {
                for (int j = 0; j < 3; ++j) {
                    pmax_a = fmax(pmax_a, fabs(r.p[i * 6 + j]));
                    pmax_b = fmax(pmax_b, fabs(r.p[(i + 3) * 6 + j + 3]));
                    pmax_c = fmax(pmax_c, fabs(r.p[i * 6 + j + 3]));
                }
            }
            worst_q = fmax(worst_q, dq);
            assert_true(dq <= REF_TOL_ANGLE);
            for (int i = 0; i < 3; ++i) {
                double eb = fabs((double)o.bias_B_hat.v[i] - r.b[i]) / sqrt(r.p[(i + 3) * 7]);
                worst_b = fmax(worst_b, eb);
                assert_true(eb <= REF_TOL_REL * 100.0);
                for (int j = 0; j < 3; ++j) {
                    double da = fabs((double)o.P.m[i][j] - r.p[i * 6 + j]) / pmax_a;
                    double db = fabs((double)o.P.m[i + 3][j + 3] - r.p[(i + 3) * 6 + j + 3]) / pmax_b;
                    double dc = fabs((double)o.P.m[i][j + 3] - r.p[i * 6 + j + 3]) / pmax_c;
                    worst_p = fmax(worst_p, fmax(da, fmax(db, dc)));
                    assert_true(da <= REF_TOL_REL);
                    assert_true(db <= REF_TOL_REL);
                    assert_true(dc <= REF_TOL_REL);
                }
            }
        }
    }
    assert_int_equal(o.n_updates, r.n_upd);
    assert_true(o.n_updates > 700u);
    print_message("reference filter (rates %.2g rad/s, long step %.2g s): worst attitude difference %.3g rad, "
                  "bias %.3g sigma, P %.3g relative\n",
                  rate_scale, dt_long, worst_q, worst_b, worst_p);
}

static void reference_filter(void **state)
{
    (void)state;
    reference_run(0x5eed0001ull, 0.05, 0.5);  /* theta up to ~0.04 rad per step: series branch */
    reference_run(0x5eed0002ull, 0.6, 1.0);   /* theta up to ~1 rad per step: both branches */
}

/* Pdot = F P + P F^T + G Q G^T over [0, dt] with w constant, 4000 RK4 steps */
static void riccati_rk4(double p[36], const double w[3], double dt, double sv, double su)
{
    double f[36];
    const int n = 4000;
    double h = dt / n;
    ref_f(w, f);
    for (int s = 0; s < n; ++s) {
        double k[4][36], tmp[36];
        for (int stage = 0; stage < 4; ++stage) {
            double x[36], fx[36], xf[36];
            double c = (stage == 0) ? 0.0 : ((stage == 3) ? 1.0 : 0.5);
            for (int i = 0; i < 36; ++i) {
                x[i] = p[i] + ((stage == 0) ? 0.0 : c * h * k[stage - 1][i]);
            }
            rm_mul(6, 6, 6, f, x, fx);
            rm_transpose(6, 6, fx, xf);
            for (int i = 0; i < 36; ++i) {
                k[stage][i] = fx[i] + xf[i];
            }
            for (int i = 0; i < 6; ++i) {
                k[stage][i * 7] += (i < 3) ? sv * sv : su * su;
            }
        }
        for (int i = 0; i < 36; ++i) {
            tmp[i] = p[i] + h / 6.0 * (k[0][i] + 2.0 * k[1][i] + 2.0 * k[2][i] + k[3][i]);
        }
        memcpy(p, tmp, sizeof(tmp));
    }
}

static void riccati_ode(void **state)
{
    (void)state;
    const double dts[2] = {0.1, 1.3};
    for (int variant = 0; variant < 2; ++variant) {
        sim_sensors_t c = {10.0 * ARCSEC, 10.0 * ARCSEC, 2e-4, 3e-5, 0.1, 1, 0u, {{0.0, 0.0, 0.0, 1.0}}};
        aocs_mekf_config_t cfg = cfg_for(&c, 0.01, 1e-3);
        aocs_mekf_t f;
        aocs_mekf_output_t o;
        double p[36] = {0};
        const double w1[3] = {0.3, -0.5, 0.2}, w2[3] = {-0.1, 0.4, 0.7};
        rq_t q0 = {{0.0, 0.0, 0.0, 1.0}};
        double zero[3] = {0.0, 0.0, 0.0};
        uint64_t t0 = 2u * NS;
        aocs_mekf_input_t in = input_of(t0, zero, 1, q0, t0);
        double dt = dts[variant];
        double pmax = 0.0, worst = 0.0;
        assert_int_equal(aocs_mekf_init(&f, &cfg), AOCS_OK);
        assert_int_equal(aocs_mekf_step(&f, &in, &o), AOCS_OK);
        for (int i = 0; i < 3; ++i) {
            p[i * 7] = 0.01 * 0.01;
            p[(i + 3) * 7] = 1e-3 * 1e-3;
        }
        /* two propagations with different rates: the second starts from a correlated P */
        assert_int_equal(aocs_mekf_propagate(&f, aocs_vec3_make((real_t)w1[0], (real_t)w1[1], (real_t)w1[2]),
                                             t0 + (uint64_t)(dt * 1e9)),
                         AOCS_OK);
        riccati_rk4(p, w1, dt, c.sv, c.su);
        assert_int_equal(aocs_mekf_propagate(&f, aocs_vec3_make((real_t)w2[0], (real_t)w2[1], (real_t)w2[2]),
                                             t0 + 2u * (uint64_t)(dt * 1e9)),
                         AOCS_OK);
        riccati_rk4(p, w2, dt, c.sv, c.su);
        assert_int_equal(aocs_mekf_get_output(&f, &o), AOCS_OK);
        for (int i = 0; i < 36; ++i) {
            pmax = fmax(pmax, fabs(p[i]));
        }
        for (int i = 0; i < 6; ++i) {
            for (int j = 0; j < 6; ++j) {
                double d = fabs((double)o.P.m[i][j] - p[i * 6 + j]) / pmax;
                worst = fmax(worst, d);
                assert_true(d <= ODE_TOL_REL);
            }
        }
        print_message("Riccati ODE (RK4) vs closed-form Phi, Q_d, two steps of %.2g s (theta up to %.2g rad): worst "
                      "%.3g of max |P|\n",
                      dt, dt * 0.81, worst);
    }
}

/* The coefficient functions of spec 5.6.3 (f2 = (th - sin th) / th^3, f3 = (th^2/2 - 1 + cos th) / th^4,
 * f4 = (th^3/3 - 2 th + 2 sin th) / th^5) as their power series summed in long double to 20 terms, each term
 * from its factorial (not the firmware's Horner form): f2 = sum_k>=0 (-1)^k th^2k / (2k+3)!,
 * f3 = sum (-1)^k th^2k / (2k+4)!, f4 = 2 sum (-1)^k th^2k / (2k+5)!. */
static long double series_f(int first_factorial, long double scale, long double th)
{
    long double sum = 0.0L, term = scale;
    for (int n = 1; n <= first_factorial; ++n) {
        term /= (long double)n;
    }
    for (int k = 0; k < 20; ++k) {
        sum += term;
        term *= -th * th / ((long double)(first_factorial + 2 * k + 1) * (long double)(first_factorial + 2 * k + 2));
    }
    return sum;
}

/* Q_d of one propagation from P = 0 is all of P, and with r = w dt in the x-y plane its elements isolate
 * the coefficient functions (spec 5.6.4): P11_xy = su^2 dt^3 f4 r_x r_y, P12_xy = -su^2 dt^2 f3 r_x r_y,
 * P12_xz = su^2 dt^2 f2 r_y; the same step from P = pb I on the bias adds pb Phi12 to P12 (spec 5.6.3), whose
 * xz element pb dt f1 r_y isolates f1. Checked against the series above on both sides of the series/closed-form switch
 * (0.1 rad in double, 0.5 in float): in double to 2e-14, where dropping or flipping the fifth term of a
 * series (a relative change of th^6 / 332640, 3e-12 at 0.1 rad) is seen. */
static void propagation_coefficients(void **state)
{
    (void)state;
    const double thetas[4] = {0.02, 0.0999, 0.4999, 2.0};
#if defined(AOCS_REAL_IS_FLOAT)
    const double tol = 2e-6;
#else
    const double tol = 2e-14;
#endif
    for (int n = 0; n < 4; ++n) {
        sim_sensors_t c = {10.0 * ARCSEC, 10.0 * ARCSEC, 2e-4, 3e-5, 0.1, 1, 0u, {{0.0, 0.0, 0.0, 1.0}}};
        aocs_mekf_config_t cfg = cfg_for(&c, 0.01, 1e-3);
        aocs_mekf_t f;
        aocs_mekf_output_t o;
        rq_t q0 = {{0.0, 0.0, 0.0, 1.0}};
        double zero[3] = {0.0, 0.0, 0.0};
        const uint64_t t0 = 2u * NS;
        aocs_mekf_input_t in = input_of(t0, zero, 1, q0, t0);
        if ((thetas[n] > 0.45) && (thetas[n] < 0.55) && (tol < 1e-10)) {
            continue; /* double's closed forms just above 0.1 rad lose digits to cancellation (by design) */
        }
        assert_int_equal(aocs_mekf_init(&f, &cfg), AOCS_OK);
        assert_int_equal(aocs_mekf_step(&f, &in, &o), AOCS_OK);
        memset(&f.P, 0, sizeof(f.P));
        f.bias_B_hat = aocs_vec3_zero();
        /* the same step from a bias covariance pb I alone: P12 gains pb Phi12, whose xz element is dt f1 r_y */
        aocs_mekf_t fb = f;
        const double pb = 1e-6;
        for (int i = 3; i < 6; ++i) {
            fb.P.m[i][i] = (real_t)pb;
        }
        /* |w| dt = theta along (0.6, 0.8, 0) over dt = 0.1 s */
        const aocs_vec3_t w = aocs_vec3_make((real_t)(6.0 * thetas[n]), (real_t)(8.0 * thetas[n]), AOCS_R(0.0));
        assert_int_equal(aocs_mekf_propagate(&f, w, t0 + 100000000u), AOCS_OK);
        assert_int_equal(aocs_mekf_propagate(&fb, w, t0 + 100000000u), AOCS_OK);
        const real_t dt = (real_t)100000000u * AOCS_R(1.0e-9);
        const long double rx = (long double)(w.v[0] * dt), ry = (long double)(w.v[1] * dt);
        const long double th = sqrtl(rx * rx + ry * ry);
        const long double su2 = (long double)(cfg.gyro_rrw_radps1p5 * cfg.gyro_rrw_radps1p5);
        const long double d = (long double)dt;
        const long double f2 = (long double)f.P.m[0][5] / (su2 * d * d * ry);
        const long double f3 = -(long double)f.P.m[0][4] / (su2 * d * d * rx * ry);
        const long double f4 = (long double)f.P.m[0][1] / (su2 * d * d * d * rx * ry);
        const long double f1 = ((long double)fb.P.m[0][5] - (long double)f.P.m[0][5]) / ((long double)(real_t)pb * d * ry);
        const long double e1 = series_f(2, 1.0L, th);
        const long double e2 = series_f(3, 1.0L, th), e3 = series_f(4, 1.0L, th), e4 = series_f(5, 2.0L, th);
        print_message("theta %.4g rad: f1, f2, f3, f4 relative errors %.2Lg %.2Lg %.2Lg %.2Lg\n", (double)th,
                      fabsl(f1 / e1 - 1.0L), fabsl(f2 / e2 - 1.0L), fabsl(f3 / e3 - 1.0L), fabsl(f4 / e4 - 1.0L));
        assert_true(fabsl(f1 / e1 - 1.0L) <= (long double)tol);
        assert_true(fabsl(f2 / e2 - 1.0L) <= (long double)tol);
        assert_true(fabsl(f3 / e3 - 1.0L) <= (long double)tol);
        assert_true(fabsl(f4 / e4 - 1.0L) <= (long double)tol);
    }
}

typedef struct {
    double sig_filter[3];  /* the filter's attitude 1-sigma at the end (mean over runs), rad */
    double sig_bias[3];
    double rms_err[3];     /* measured attitude error 1-sigma over the steady window, rad */
    double nees_in_band;   /* fraction of windows with the ensemble NEES in its 99 % band */
    double nees_in_band95; /* the same with the 95 % band (reported) */
    double three_sigma;    /* fraction of |e_i| <= 3 sigma_i (attitude and bias) */
    double nees_mean;
    double gated;          /* fraction of the samples rejected by the gate */
} ss_stats_t;

#define SS_RUNS 8
#define SS_MAX_WINDOWS 1024

/* SS_RUNS seeded runs of `steps`; statistics after `settle` steps; the tracker's sigma equal on both axes here */
static void steady_state_sim(const sim_sensors_t *c, int steps, int settle, uint64_t seed, ss_stats_t *out)
{
    static double win_nees[SS_MAX_WINDOWS];
    const int win_steps = (int)(10.0 / c->dt + 0.5); /* 10 s windows, NEES sampled at each window's end */
    const int lag_steps = (int)(c->latency_ns / (uint64_t)(c->dt * 1e9));
    int n_win = 0;
    double sum_e2[3] = {0}, sum_sig[3] = {0}, sum_sigb[3] = {0};
    long n_e = 0, n_in3 = 0, n_3 = 0;
    double nees_sum = 0.0;
    long nees_n = 0;
    long n_samples = 0, n_gated = 0;
    memset(win_nees, 0, sizeof(win_nees));
    for (int run = 0; run < SS_RUNS; ++run) {
        sim_truth_t s;
        aocs_mekf_t f;
        aocs_mekf_output_t o;
        aocs_mekf_config_t cfg = cfg_for(c, 1e-3, 1e-6);
        uint64_t t = 1u * NS;
        uint64_t dt_ns = (uint64_t)(c->dt * 1e9 + 0.5);
        int w = 0;
        sim_init(&s, seed + (uint64_t)run * 7919u, 1e-6);
        assert_int_equal(aocs_mekf_init(&f, &cfg), AOCS_OK);
        {
            double wm[3] = {0.0, 0.0, 0.0};
            aocs_mekf_input_t in = input_of(t, wm, 1, sim_tracker(&s, c, 0), t);
            assert_int_equal(aocs_mekf_step(&f, &in, &o), AOCS_OK);
        }
        for (int k = 1; k <= steps; ++k) {
            double wm[3];
            int st = ((k % c->st_every) == 0) ? 1 : 0;
            sim_step(&s, c, wm);
            t += dt_ns;
            {
                rq_t q_sn = st ? sim_tracker(&s, c, lag_steps) : s.q;
                aocs_mekf_input_t in = input_of(t, wm, st, q_sn, t - c->latency_ns);
                assert_int_equal(aocs_mekf_step(&f, &in, &o), AOCS_OK);
                if (st != 0) {
                    /* a good sample beyond the 99.9 % gate is rejected 0.1 % of the time, by design */
                    assert_true(o.st_status == AOCS_OK || o.st_status == AOCS_ERR_MEKF_GATED);
                    n_samples++;
                }
            }
            if (k > settle) {
                double e[6];
                est_error(&s, &o, e);
                for (int i = 0; i < 6; ++i) {
                    n_3++;
                    if (fabs(e[i]) <= 3.0 * (double)o.sigma[i]) {
                        n_in3++;
                    }
                }
                for (int i = 0; i < 3; ++i) {
                    sum_e2[i] += e[i] * e[i];
                }
                n_e++;
                if (((k - settle) % win_steps) == 0) {
                    double d2 = nees6(&o, e);
                    assert_true(w < SS_MAX_WINDOWS);
                    win_nees[w++] += d2 / SS_RUNS;
                    nees_sum += d2;
                    nees_n++;
                }
            }
        }
        n_gated += (long)o.n_gated;
        for (int i = 0; i < 3; ++i) {
            sum_sig[i] += (double)o.sigma[i] / SS_RUNS;
            sum_sigb[i] += (double)o.sigma[i + 3] / SS_RUNS;
            /* never NaN, unit q */
            assert_true(fabs((double)aocs_quat_norm(o.q_BN_hat) - 1.0) <= 10.0 * (double)AOCS_REAL_EPS);
        }
        n_win = w;
    }
    {
        /* ensemble average of SS_RUNS independent NEES (6 dof): chi2(6 SS_RUNS) / SS_RUNS */
        const double k = 6.0 * SS_RUNS;
        const double lo99 = chi2_quantile(k, -2.5758293035489) / SS_RUNS, hi99 = chi2_quantile(k, 2.5758293035489) / SS_RUNS;
        const double lo95 = chi2_quantile(k, -1.959963984540) / SS_RUNS, hi95 = chi2_quantile(k, 1.959963984540) / SS_RUNS;
        int in99 = 0, in95 = 0;
        for (int i = 0; i < n_win; ++i) {
            in99 += (win_nees[i] >= lo99 && win_nees[i] <= hi99) ? 1 : 0;
            in95 += (win_nees[i] >= lo95 && win_nees[i] <= hi95) ? 1 : 0;
        }
        out->nees_in_band = (double)in99 / n_win;
        out->nees_in_band95 = (double)in95 / n_win;
    }
    for (int i = 0; i < 3; ++i) {
        out->sig_filter[i] = sum_sig[i];
        out->sig_bias[i] = sum_sigb[i];
        out->rms_err[i] = sqrt(sum_e2[i] / (double)n_e);
    }
    out->three_sigma = (double)n_in3 / (double)n_3;
    out->gated = (double)n_gated / (double)n_samples;
    out->nees_mean = nees_sum / (double)nees_n;
}

static void check_steady_state(const char *name, const sim_sensors_t *c, int steps, int settle, uint64_t seed,
                               int compare_analytic)
{
    ss_stats_t s;
    double sa = 0.0, sb = 0.0;
    farrenkopf_riccati(c->sc, c->sv, c->su, c->dt * c->st_every, &sa, &sb);
    steady_state_sim(c, steps, settle, seed, &s);
    print_message("%s: analytic 1-sigma %.4g arcsec (bias %.4g rad/s); filter %.4g %.4g %.4g arcsec (ratio %.4f), "
                  "measured %.4g %.4g %.4g arcsec (ratio %.4f); NEES mean %.3f (6 dof), in 99%% band %.1f %%, in 95%% "
                  "band %.1f %%; 3-sigma fraction %.3f %%; gated %.3f %%\n",
                  name, sa / ARCSEC, sb, s.sig_filter[0] / ARCSEC, s.sig_filter[1] / ARCSEC, s.sig_filter[2] / ARCSEC,
                  s.sig_filter[0] / sa, s.rms_err[0] / ARCSEC, s.rms_err[1] / ARCSEC, s.rms_err[2] / ARCSEC,
                  (s.rms_err[0] + s.rms_err[1] + s.rms_err[2]) / (3.0 * sa), s.nees_mean, 100.0 * s.nees_in_band,
                  100.0 * s.nees_in_band95, 100.0 * s.three_sigma, 100.0 * s.gated);
    for (int i = 0; i < 3; ++i) {
        if (compare_analytic != 0) {
            /* the filter's P against Farrenkopf's steady state, and the bias 1-sigma too */
            assert_true(fabs(s.sig_filter[i] / sa - 1.0) <= 0.10);
            assert_true(fabs(s.sig_bias[i] / sb - 1.0) <= 0.10);
            assert_true(fabs(s.rms_err[i] / sa - 1.0) <= 0.10);
        }
        /* the measured error against the filter's own 1-sigma */
        assert_true(fabs(s.rms_err[i] / s.sig_filter[i] - 1.0) <= 0.10);
    }
    assert_true(s.nees_in_band >= 0.95);
    assert_true(s.gated <= 0.003); /* 0.1 % expected of a consistent filter */
    assert_true(s.three_sigma >= 0.99);
    assert_true(s.three_sigma <= 0.999);
}

/* 10 Hz, 1 arcsec tracker, navigation-grade gyro (ARW 1e-7 rad/s^0.5 ~ 0.02 deg/h^0.5, RRW 1e-10 rad/s^1.5) */
static void steady_state_10hz_nav(void **state)
{
    (void)state;
    sim_sensors_t c = {1.0 * ARCSEC, 1.0 * ARCSEC, 1e-7, 1e-10, 0.1, 1, 0u, {{0.0, 0.0, 0.0, 1.0}}};
    check_steady_state("steady state 10 Hz, 1 arcsec, navigation gyro", &c, 40000, 10000, 0xabc001ull, 1);
}

/* 2 Hz tracker (a lower rate than the 10 Hz control), 5 arcsec, tactical gyro (ARW 3e-6, RRW 3e-9) */
static void steady_state_2hz_tactical(void **state)
{
    (void)state;
    sim_sensors_t c = {5.0 * ARCSEC, 5.0 * ARCSEC, 3e-6, 3e-9, 0.1, 5, 0u, {{0.0, 0.0, 0.0, 1.0}}};
    check_steady_state("steady state 2 Hz, 5 arcsec, tactical gyro", &c, 40000, 10000, 0xabc002ull, 1);
}

/* 10 Hz, 5 arcsec, navigation gyro */
static void steady_state_10hz_5as(void **state)
{
    (void)state;
    sim_sensors_t c = {5.0 * ARCSEC, 5.0 * ARCSEC, 1e-7, 1e-10, 0.1, 1, 0u, {{0.0, 0.0, 0.0, 1.0}}};
    check_steady_state("steady state 10 Hz, 5 arcsec, navigation gyro", &c, 40000, 10000, 0xabc003ull, 1);
}

/* 2 Hz with a 0.3 s latency (3 steps back through the history), a rotated tracker with 8x
 * about-boresight noise: consistency only (the analytic per-axis model has neither) */
static void steady_state_latency(void **state)
{
    (void)state;
    sim_sensors_t c = {2.0 * ARCSEC, 16.0 * ARCSEC, 5e-7, 5e-10, 0.1, 5, 300000000u, {{0.0, 0.0, 0.0, 1.0}}};
    test_rng_t rng = {77u};
    c.q_sb = rq_from(test_random_quat(&rng));
    check_steady_state("steady state 2 Hz, 0.3 s latency, 2/16 arcsec rotated tracker", &c, 40000, 10000,
                       0xabc004ull, 0);
}

/* the convergence time bound of the test below, s (measured: see the message it prints) */
#define CONV_BOUND_S 300.0

static void convergence(void **state)
{
    (void)state;
    sim_sensors_t c = {1.0 * ARCSEC, 1.0 * ARCSEC, 1e-7, 1e-10, 0.1, 1, 0u, {{0.0, 0.0, 0.0, 1.0}}};
    double sa = 0.0, sb = 0.0;
    double worst_t = 0.0;
    farrenkopf_riccati(c.sc, c.sv, c.su, c.dt, &sa, &sb);
    for (int run = 0; run < 4; ++run) {
        sim_truth_t s;
        aocs_mekf_t f;
        aocs_mekf_output_t o;
        aocs_mekf_config_t cfg = cfg_for(&c, 1.0 * DEG, 1.0 * DEG / 3600.0);
        uint64_t t = NS;
        double last_out = 0.0;
        const int steps = 6000;
        static double e2_ring[300][3]; /* the last 30 s of squared errors, per axis */
        double e2_sum[3] = {0.0, 0.0, 0.0};
        memset(e2_ring, 0, sizeof(e2_ring));
        sim_init(&s, (uint64_t)0xc0c0u + (uint64_t)(unsigned)run, 0.0);
        for (int i = 0; i < 3; ++i) {
            s.b[i] = ((i == run % 3) ? 1.0 : 0.3) * DEG / 3600.0; /* >= 1 deg/h, unknown (prior 0) */
        }
        assert_int_equal(aocs_mekf_init(&f, &cfg), AOCS_OK);
        {
            /* the first sample 1 deg off the truth: the filter starts with a 1 deg attitude error */
            double off[3] = {0.0, 0.0, 0.0};
            off[run % 3] = 1.0 * DEG;
            rq_t q_sn = rq_norm(rq_mul(c.q_sb, rq_mul(rq_exp(off), s.q)));
            double wm[3] = {0.0, 0.0, 0.0};
            aocs_mekf_input_t in = input_of(t, wm, 1, q_sn, t);
            assert_int_equal(aocs_mekf_step(&f, &in, &o), AOCS_OK);
            assert_true(rq_angle(s.q, rq_from(o.q_BN_hat)) > 0.99 * DEG);
        }
        for (int k = 1; k <= steps; ++k) {
            double wm[3], e[6];
            sim_step(&s, &c, wm);
            t += 100000000u;
            aocs_mekf_input_t in = input_of(t, wm, 1, sim_tracker(&s, &c, 0), t);
            assert_int_equal(aocs_mekf_step(&f, &in, &o), AOCS_OK);
            if (k <= 10) {
                assert_int_equal(o.st_status, AOCS_OK); /* the 1 deg start is inside the gate (P0 = 1 deg) */
            }
            /* the correction's reset keeps the quaternion unit */
            assert_true(fabs((double)aocs_quat_norm(o.q_BN_hat) - 1.0) <= 10.0 * (double)AOCS_REAL_EPS);
            est_error(&s, &o, e);
            /* the knowledge error's 1-sigma: RMS over a sliding 30 s window (ending at the time reported), per axis */
            for (int i = 0; i < 3; ++i) {
                e2_sum[i] += e[i] * e[i] - e2_ring[k % 300][i];
                e2_ring[k % 300][i] = e[i] * e[i];
                if ((k < 300) || (sqrt(fmax(e2_sum[i], 0.0) / 300.0) > 3.0 * sa)) {
                    last_out = k * c.dt;
                }
            }
        }
        assert_true(last_out < steps * c.dt - 100.0); /* settled well before the end */
        worst_t = fmax(worst_t, last_out);
        assert_true(last_out <= CONV_BOUND_S);
        /* the bias was learnt */
        for (int i = 0; i < 3; ++i) {
            assert_true(fabs(s.b[i] - (double)o.bias_B_hat.v[i]) <= 4.0 * sb);
        }
    }
    print_message("convergence from 1 deg and >= 1 deg/h: 30 s RMS error inside 3 x %.3g arcsec (steady state) for good "
                  "after %.1f s "
                  "(worst of 4 runs; bound %.0f s)\n",
                  sa / ARCSEC, worst_t, CONV_BOUND_S);
}

/*
 * The expected squared angle error of one axis at steps 0 .. n-1 of the two-state per-axis model (Farrenkopf's,
 * Phi = [[1, -T], [0, 1]], Q as farrenkopf_riccati's, H = [1 0], R = sn^2) started at P0 = diag(pa0^2, pb0^2) with
 * the deterministic error (ea0, eb0): the gain of every step from the Riccati recursion of P, the mean error
 * m <- (I - K H) Phi m, the noise-driven covariance N <- (I - K H)(Phi N Phi^T + Q)(I - K H)^T + K R K^T, N0 = 0;
 * E[e^2] = m_a^2 + N_aa. An update at step 0 and at every step (the tracker at the control rate).
 */
static void predicted_sq_error(double sn, double sv, double su, double t, double pa0, double pb0, double ea0, double eb0,
                               int n, double *out)
{
    double p[2][2] = {{pa0 * pa0, 0.0}, {0.0, pb0 * pb0}};
    double nn[2][2] = {{0.0, 0.0}, {0.0, 0.0}};
    double m[2] = {ea0, eb0};
    const double q11 = sv * sv * t + su * su * t * t * t / 3.0, q12 = -su * su * t * t / 2.0, q22 = su * su * t;
    for (int k = 0; k < n; ++k) {
        if (k > 0) {
            /* propagation of P, N (Phi X Phi^T + Q) and m (Phi m) */
            double (*xs[2])[2] = {p, nn};
            for (int j = 0; j < 2; ++j) {
                double (*x)[2] = xs[j];
                double a = x[0][0] - 2.0 * t * x[0][1] + t * t * x[1][1] + q11;
                double b = x[0][1] - t * x[1][1] + q12;
                double c = x[1][1] + q22;
                x[0][0] = a;
                x[0][1] = b;
                x[1][0] = b;
                x[1][1] = c;
            }
            m[0] -= t * m[1];
        }
        {
            /* update: K = P H^T / (P11 + R), A = I - K H; Joseph form for N, A m for the mean */
            const double s = p[0][0] + sn * sn;
            const double k0 = p[0][0] / s, k1 = p[1][0] / s;
            double (*xs[2])[2] = {p, nn};
            for (int j = 0; j < 2; ++j) {
                double (*x)[2] = xs[j];
                /* A X A^T + K R K^T with A = [[1 - k0, 0], [-k1, 1]] */
                double a = (1.0 - k0) * (1.0 - k0) * x[0][0] + k0 * k0 * sn * sn;
                double b = (1.0 - k0) * (x[0][1] - k1 * x[0][0]) + k0 * k1 * sn * sn;
                double c = x[1][1] - 2.0 * k1 * x[0][1] + k1 * k1 * x[0][0] + k1 * k1 * sn * sn;
                x[0][0] = a;
                x[0][1] = b;
                x[1][0] = b;
                x[1][1] = c;
            }
            m[1] -= k1 * m[0];
            m[0] *= (1.0 - k0);
        }
        out[k] = m[0] * m[0] + nn[0][0];
    }
}

/* the trailing window of the convergence rule: 30 s of 0.1 s steps (the about-boresight error's correlation
 * time is about 9 s: a shorter window's rms scatters too much to say "for good") */
#define CONV_WIN 300
#define CONV_STEPS 1200
/* the stated time: the predicted (expected) rms inside CONV_PRED_K times the steady state, half the 3 x of the
 * rule: a factor 2 for the scatter of one run's 30 s rms about its expectation */
#define CONV_PRED_K 1.5

/*
 * Configured start (mekf.init_mode configured, spec 5.6.10): the filter starts at q0_BN, 1 deg off the truth,
 * with a 1 deg/h bias per axis it does not know (prior 0), P0 = 1 deg and 1 deg/h per axis, on the IRASSI hold's
 * sensors (1 / 8 arcsec tracker at 10 Hz, ARW 1.45e-6, RRW 1e-10). The rule: the knowledge error's trailing
 * 30 s rms per axis inside 3 times the steady state for good. The stated time is PREDICTED here from the
 * filter's own gains (predicted_sq_error): when the expected rms is inside CONV_PRED_K = 1.5 times the steady
 * state; every run (8 seeds, each axis of the error in turn) must meet the rule by then. The start needs no
 * tracker sample; a reset falls back to waiting for one.
 */
static void configured_start(void **state)
{
    (void)state;
    sim_sensors_t c = {1.0 * ARCSEC, 8.0 * ARCSEC, 1.45e-6, 1e-10, 0.1, 1, 0u, {{0.0, 0.0, 0.0, 1.0}}};
    const double sn[3] = {c.sc, c.sc, c.sa};
    double bound[3], sb = 0.0;
    double t_pred = 0.0, worst = 0.0;
    static double pred_sq[3][CONV_STEPS];
    for (int i = 0; i < 3; ++i) {
        farrenkopf_riccati(sn[i], c.sv, c.su, c.dt, &bound[i], &sb);
    }
    for (int run = 0; run < 8; ++run) {
        sim_truth_t s;
        aocs_mekf_t f;
        aocs_mekf_output_t o;
        aocs_mekf_config_t cfg = cfg_for(&c, 1.0 * DEG, 1.0 * DEG / 3600.0);
        double off[3] = {0.0, 0.0, 0.0};
        double e2[3][CONV_STEPS];
        double last_out = 0.0, last_pred = 0.0;
        uint64_t t = NS;
        sim_init(&s, (uint64_t)0xc0f1u + (uint64_t)(unsigned)run, 0.0);
        for (int i = 0; i < 3; ++i) {
            s.b[i] = ((run & (1 << i)) ? -1.0 : 1.0) * DEG / 3600.0;
        }
        off[run % 3] = ((run < 4) ? 1.0 : -1.0) * DEG;
        cfg.init_mode = AOCS_MEKF_INIT_CONFIGURED;
        cfg.q0_BN = rq_to(rq_norm(rq_mul(rq_exp((double[3]){-off[0], -off[1], -off[2]}), s.q)));
        assert_int_equal(aocs_mekf_init(&f, &cfg), AOCS_OK);
        {
            /* the first step, no tracker sample: the estimate is q0_BN at this step's time, 1 deg off */
            double wm[3] = {s.w[0] + s.b[0], s.w[1] + s.b[1], s.w[2] + s.b[2]};
            aocs_mekf_input_t in = input_of(t, wm, 0, s.q, t);
            assert_int_equal(aocs_mekf_step(&f, &in, &o), AOCS_OK);
            assert_int_equal(o.n_updates, 0u);
            assert_true(fabs(rq_angle(s.q, rq_from(o.q_BN_hat)) - 1.0 * DEG) < 1e-6 * DEG + 1e3 * (double)AOCS_REAL_EPS);
        }
        /* the prediction from the errors the filter starts with (the hold: S = B) */
        for (int i = 0; i < 3; ++i) {
            predicted_sq_error(sn[i], c.sv, c.su, c.dt, 1.0 * DEG, 1.0 * DEG / 3600.0, off[i], s.b[i], CONV_STEPS,
                               pred_sq[i]);
        }
        for (int k = 0; k < CONV_STEPS; ++k) {
            double wm[3], e[6];
            sim_step(&s, &c, wm);
            t += 100000000u;
            aocs_mekf_input_t in = input_of(t, wm, 1, sim_tracker(&s, &c, 0), t);
            assert_int_equal(aocs_mekf_step(&f, &in, &o), AOCS_OK);
            if (k < 10) {
                assert_int_equal(o.st_status, AOCS_OK); /* the 1 deg start is inside the gate (P0 = 1 deg) */
            }
            est_error(&s, &o, e);
            for (int i = 0; i < 3; ++i) {
                double se = 0.0, sp = 0.0;
                const int lo = (k + 1 > CONV_WIN) ? (k + 1 - CONV_WIN) : 0;
                e2[i][k] = e[i] * e[i];
                for (int j = lo; j <= k; ++j) {
                    se += e2[i][j];
                    sp += pred_sq[i][j];
                }
                if (sqrt(se / (double)(k + 1 - lo)) > 3.0 * bound[i]) {
                    last_out = (k + 1) * c.dt;
                }
                if (sqrt(sp / (double)(k + 1 - lo)) > CONV_PRED_K * bound[i]) {
                    last_pred = (k + 1) * c.dt;
                }
            }
        }
        t_pred = fmax(t_pred, last_pred);
        worst = fmax(worst, last_out);
        assert_true(last_pred < 0.5 * CONV_STEPS * c.dt); /* the prediction enters well within the run */
        assert_true(last_out <= last_pred);
        /* the bias is being learnt: its error has shrunk from 1 deg/h on every axis */
        for (int i = 0; i < 3; ++i) {
            assert_true(fabs(s.b[i] - (double)o.bias_B_hat.v[i]) < 0.5 * DEG / 3600.0);
        }
        /* a reset: back to waiting for the tracker (the configured start is the first one only) */
        assert_int_equal(aocs_mekf_reset(&f), AOCS_OK);
        {
            double wm[3] = {0.0, 0.0, 0.0};
            aocs_mekf_input_t in = input_of(t + 100000000u, wm, 0, s.q, t);
            assert_int_equal(aocs_mekf_step(&f, &in, &o), AOCS_ERR_MEKF_NO_ATTITUDE);
        }
    }
    print_message("configured start, 1 deg and 1 deg/h per axis: 30 s rms inside 3 x steady state (%.3g %.3g %.3g "
                  "arcsec) for good after %.1f s at most (8 runs); stated time (expected rms inside 1.5 x) %.1f s\n",
                  bound[0] / ARCSEC, bound[1] / ARCSEC, bound[2] / ARCSEC, worst, t_pred);
}

/*
 * The configured start's first sample (mekf.h, aocs_mekf_step: "a rejected star-tracker sample does not make
 * the step fail: its verdict is out->st_status"): the filter starts at q0_BN whatever the sample; one 10 deg
 * off q0 with P0 = 1 deg (d^2 about 100, gate 16.3) is gated, one measured after the step's time is hostile,
 * one 0.01 deg off is used: each step is AOCS_OK with the estimate usable and the verdict in st_status.
 */
static void configured_start_with_a_rejected_first_sample(void **state)
{
    (void)state;
    sim_sensors_t c = {10.0 * ARCSEC, 10.0 * ARCSEC, 1.45e-6, 1e-10, 0.1, 1, 0u, {{0.0, 0.0, 0.0, 1.0}}};
    const rq_t q0 = rq_norm(rq_exp((double[3]){0.1, -0.2, 0.3}));
    const double wm[3] = {0.0, 0.0, 0.0};
    const uint64_t t = 5u * NS;
    struct {
        double off_deg;      /* the sample: q0 turned by this about x */
        uint64_t t_meas;
        aocs_status_t verdict;
        uint32_t n_updates, n_gated, n_hostile;
    } cases[3] = {
        {10.0, t, AOCS_ERR_MEKF_GATED, 0u, 1u, 0u},
        {0.01, t + 1u, AOCS_ERR_MEKF_MEAS_FUTURE, 0u, 0u, 1u},
        {0.01, t, AOCS_OK, 1u, 0u, 0u},
    };
    for (int k = 0; k < 3; ++k) {
        aocs_mekf_t f;
        aocs_mekf_output_t o;
        aocs_mekf_config_t cfg = cfg_for(&c, 1.0 * DEG, 1.0 * DEG / 3600.0);
        cfg.init_mode = AOCS_MEKF_INIT_CONFIGURED;
        cfg.q0_BN = rq_to(q0);
        assert_int_equal(aocs_mekf_init(&f, &cfg), AOCS_OK);
        const rq_t q_sn = rq_norm(rq_mul(rq_exp((double[3]){cases[k].off_deg * DEG, 0.0, 0.0}), q0));
        aocs_mekf_input_t in = input_of(t, wm, 1, q_sn, cases[k].t_meas);
        assert_int_equal(aocs_mekf_step(&f, &in, &o), AOCS_OK);
        assert_int_equal(o.st_status, cases[k].verdict);
        assert_int_equal(o.n_updates, cases[k].n_updates);
        assert_int_equal(o.n_gated, cases[k].n_gated);
        assert_int_equal(o.n_hostile, cases[k].n_hostile);
        /* rejected: the estimate is q0_BN; used: it moved to the sample (P0 = 1 deg against a 10 arcsec tracker) */
        const double moved = rq_angle(q0, rq_from(o.q_BN_hat));
        if (cases[k].verdict == AOCS_OK) {
            assert_true(moved > 0.5 * cases[k].off_deg * DEG);
            assert_true(moved < 1.5 * cases[k].off_deg * DEG);
        } else {
            assert_true(moved < 1e3 * (double)AOCS_REAL_EPS);
        }
    }
}

static void outage(void **state)
{
    (void)state;
    sim_sensors_t c = {1.0 * ARCSEC, 1.0 * ARCSEC, 1e-7, 1e-10, 0.1, 1, 0u, {{0.0, 0.0, 0.0, 1.0}}};
    double sa = 0.0, sb = 0.0;
    farrenkopf_riccati(c.sc, c.sv, c.su, c.dt, &sa, &sb);
    for (int run = 0; run < 3; ++run) {
        sim_truth_t s;
        aocs_mekf_t f;
        aocs_mekf_output_t o;
        aocs_mekf_config_t cfg = cfg_for(&c, 1e-4, 1e-7);
        uint64_t t = NS;
        const int t_out0 = 10000, t_out1 = 16000, t_end = 16600; /* 600 s outage after 1000 s */
        double worst_ratio = 0.0, sig_end = 0.0, err_back = 0.0;
        long n_out = 0, n_out_in[3] = {0, 0, 0};
        sim_init(&s, (uint64_t)0x0a7a6eu + (uint64_t)(unsigned)run, 1e-7);
        assert_int_equal(aocs_mekf_init(&f, &cfg), AOCS_OK);
        {
            double wm[3] = {0.0, 0.0, 0.0};
            aocs_mekf_input_t in = input_of(t, wm, 1, sim_tracker(&s, &c, 0), t);
            assert_int_equal(aocs_mekf_step(&f, &in, &o), AOCS_OK);
        }
        for (int k = 1; k <= t_end; ++k) {
            double wm[3], e[6];
            int st = (k <= t_out0 || k > t_out1) ? 1 : 0;
            sim_step(&s, &c, wm);
            t += 100000000u;
            aocs_mekf_input_t in = input_of(t, wm, st, st ? sim_tracker(&s, &c, 0) : s.q, t);
            assert_int_equal(aocs_mekf_step(&f, &in, &o), AOCS_OK);
            est_error(&s, &o, e);
            if (k > t_out0 && k <= t_out1) {
                n_out++;
                for (int i = 0; i < 3; ++i) {
                    n_out_in[i] += (fabs(e[i]) <= 3.0 * (double)o.sigma[i]) ? 1 : 0;
                    worst_ratio = fmax(worst_ratio, fabs(e[i]) / (double)o.sigma[i]);
                }
                sig_end = (double)o.sigma[0];
            }
            if (k == t_out1 + 1) {
                assert_int_equal(o.st_status, AOCS_OK); /* the returning tracker is not gated */
            }
            if (k >= t_out1 + 600) { /* 60 s after the return */
                for (int i = 0; i < 3; ++i) {
                    assert_true(fabs(e[i]) <= 3.0 * sa);
                    assert_true((double)o.sigma[i] <= 1.10 * sa);
                    err_back = fmax(err_back, fabs(e[i]));
                }
            }
        }
        assert_true(sig_end > 5.0 * sa); /* the outage did grow P */
        assert_true(worst_ratio <= 3.5);
        for (int i = 0; i < 3; ++i) {
            assert_true((double)n_out_in[i] >= 0.99 * (double)n_out);
        }
        print_message("outage run %d: 3-sigma grew to %.3g arcsec, worst |e|/sigma %.2f, inside 3 sigma %.2f %.2f %.2f %%; "
                      "from 60 s after the return |e| <= %.3g arcsec (3 x steady %.3g)\n",
                      run, 3.0 * sig_end / ARCSEC, worst_ratio, 100.0 * (double)n_out_in[0] / (double)n_out,
                      100.0 * (double)n_out_in[1] / (double)n_out, 100.0 * (double)n_out_in[2] / (double)n_out,
                      err_back / ARCSEC, 3.0 * sa / ARCSEC);
    }
}

/* ---- a small harness for the unit checks: a started filter at 10 Hz ---- */
typedef struct {
    aocs_mekf_t f;
    sim_truth_t s;
    sim_sensors_t c;
    uint64_t t;
} bench_t;

static void harness_start(bench_t *b, int settle_steps)
{
    aocs_mekf_output_t o;
    aocs_mekf_config_t cfg;
    sim_sensors_t c = {2.0 * ARCSEC, 2.0 * ARCSEC, 1e-7, 1e-10, 0.1, 1, 0u, {{0.0, 0.0, 0.0, 1.0}}};
    b->c = c;
    cfg = cfg_for(&c, 1e-4, 1e-7);
    sim_init(&b->s, 0x1234ull, 1e-7);
    b->t = 10u * NS;
    assert_int_equal(aocs_mekf_init(&b->f, &cfg), AOCS_OK);
    {
        double wm[3] = {0.0, 0.0, 0.0};
        aocs_mekf_input_t in = input_of(b->t, wm, 1, sim_tracker(&b->s, &c, 0), b->t);
        assert_int_equal(aocs_mekf_step(&b->f, &in, &o), AOCS_OK);
    }
    for (int k = 0; k < settle_steps; ++k) {
        double wm[3];
        sim_step(&b->s, &b->c, wm);
        b->t += 100000000u;
        aocs_mekf_input_t in = input_of(b->t, wm, 1, sim_tracker(&b->s, &b->c, 0), b->t);
        assert_int_equal(aocs_mekf_step(&b->f, &in, &o), AOCS_OK);
    }
}

static void assert_output_zero(const aocs_mekf_output_t *o)
{
    const real_t *q = o->q_BN_hat.q;
    assert_int_equal(o->valid, 0u);
    for (int i = 0; i < 4; ++i) {
        assert_true(!(q[i] > AOCS_R(0.0)) && !(q[i] < AOCS_R(0.0)));
    }
    for (int i = 0; i < 6; ++i) {
        assert_true(!(o->sigma[i] > AOCS_R(0.0)) && !(o->sigma[i] < AOCS_R(0.0)));
        for (int j = 0; j < 6; ++j) {
            assert_true(!(o->P.m[i][j] > AOCS_R(0.0)) && !(o->P.m[i][j] < AOCS_R(0.0)));
        }
    }
    for (int i = 0; i < 3; ++i) {
        assert_true(!(o->w_BN_B_hat.v[i] > AOCS_R(0.0)) && !(o->w_BN_B_hat.v[i] < AOCS_R(0.0)));
        assert_true(!(o->bias_B_hat.v[i] > AOCS_R(0.0)) && !(o->bias_B_hat.v[i] < AOCS_R(0.0)));
    }
}

static void assert_output_sane(const aocs_mekf_output_t *o)
{
    assert_int_equal(o->valid, 1u);
    assert_true(aocs_quat_is_finite(o->q_BN_hat) != 0);
    assert_true(fabs((double)aocs_quat_norm(o->q_BN_hat) - 1.0) <= 10.0 * (double)AOCS_REAL_EPS);
    for (int i = 0; i < 6; ++i) {
        assert_true(AOCS_IS_FINITE(o->sigma[i]) && o->sigma[i] > AOCS_R(0.0));
        for (int j = 0; j < 6; ++j) {
            assert_true(AOCS_IS_FINITE(o->P.m[i][j]));
            assert_true(o->P.m[i][j] <= o->P.m[j][i] && o->P.m[i][j] >= o->P.m[j][i]); /* exactly symmetric */
        }
    }
}

static void gating(void **state)
{
    (void)state;
    bench_t b, twin;
    aocs_mekf_output_t o, ot;
    harness_start(&b, 3000);
    twin = b;
    for (int k = 0; k < 5; ++k) {
        double wm[3];
        const double step[3] = {1.0 * DEG, 0.0, 0.0}; /* a 1 deg bias step of the tracker */
        sim_step(&b.s, &b.c, wm);
        b.t += 100000000u;
        {
            rq_t q_bad = rq_norm(rq_mul(rq_exp(step), sim_tracker(&b.s, &b.c, 0)));
            aocs_mekf_input_t in = input_of(b.t, wm, 1, q_bad, b.t);
            aocs_mekf_input_t in_twin = input_of(b.t, wm, 0, q_bad, b.t);
            assert_int_equal(aocs_mekf_step(&b.f, &in, &o), AOCS_OK);
            assert_int_equal(o.st_status, AOCS_ERR_MEKF_GATED);
            assert_int_equal(o.n_gated, twin.f.n_gated + (uint32_t)(k + 1));
            assert_true((double)o.innovation_chi2 > (double)AOCS_MEKF_GATE_CHI2_3DOF_999);
            assert_true(fabs((double)o.innovation_B_rad.v[0] - 1.0 * DEG) <= 0.01 * DEG);
            assert_int_equal(aocs_mekf_step(&twin.f, &in_twin, &ot), AOCS_OK);
            /* a gated sample leaves the state exactly as propagation alone */
            assert_memory_equal(&o.q_BN_hat, &ot.q_BN_hat, sizeof(o.q_BN_hat));
            assert_memory_equal(&o.P, &ot.P, sizeof(o.P));
            assert_output_sane(&o);
        }
    }
    {
        /* a good sample is used again, and passes the gate */
        double wm[3];
        sim_step(&b.s, &b.c, wm);
        b.t += 100000000u;
        aocs_mekf_input_t in = input_of(b.t, wm, 1, sim_tracker(&b.s, &b.c, 0), b.t);
        assert_int_equal(aocs_mekf_step(&b.f, &in, &o), AOCS_OK);
        assert_int_equal(o.st_status, AOCS_OK);
        assert_int_equal(o.n_gated, twin.f.n_gated + 5u);
        assert_true((double)o.innovation_chi2 < (double)AOCS_MEKF_GATE_CHI2_3DOF_999);
    }
    {
        /* the gate is the configured threshold: a 0.2 deg outlier passes a gate of 1e12 and is used */
        aocs_mekf_config_t cfg = b.f.cfg;
        aocs_mekf_t g = b.f;
        double wm[3];
        const double step[3] = {0.0, 0.2 * DEG, 0.0};
        cfg.gate_chi2 = AOCS_R(1e12);
        g.cfg.gate_chi2 = cfg.gate_chi2; /* same state, wider gate */
        sim_step(&b.s, &b.c, wm);
        b.t += 100000000u;
        {
            rq_t q_bad = rq_norm(rq_mul(rq_exp(step), sim_tracker(&b.s, &b.c, 0)));
            aocs_mekf_input_t in = input_of(b.t, wm, 1, q_bad, b.t);
            assert_int_equal(aocs_mekf_step(&b.f, &in, &o), AOCS_OK);
            assert_int_equal(o.st_status, AOCS_ERR_MEKF_GATED);
            assert_int_equal(aocs_mekf_step(&g, &in, &o), AOCS_OK);
            assert_int_equal(o.st_status, AOCS_OK);
        }
    }
}

static void quaternion_reset(void **state)
{
    (void)state;
    /* 200 corrections of ~1 deg each (sample 1 deg away each step, gate wide, P0 large): q stays unit,
     * and the estimate moves to the sample */
    aocs_mekf_config_t cfg;
    aocs_mekf_t f;
    aocs_mekf_output_t o;
    test_rng_t rng = {99u};
    rq_t q = rq_from(test_random_quat(&rng));
    uint64_t t = NS;
    double zero[3] = {0.0, 0.0, 0.0};
    aocs_mekf_config_default(&cfg);
    cfg.p0_att_sigma_rad = AOCS_R(10.0 * DEG);
    cfg.gyro_arw_radpsqrts = AOCS_R(0.05); /* P grows back between samples: every correction is large */
    cfg.gate_chi2 = AOCS_R(1e9);
    assert_int_equal(aocs_mekf_init(&f, &cfg), AOCS_OK);
    {
        aocs_mekf_input_t in = input_of(t, zero, 1, q, t);
        assert_int_equal(aocs_mekf_step(&f, &in, &o), AOCS_OK);
    }
    for (int k = 0; k < 200; ++k) {
        double off[3] = {0.0, 0.0, 0.0};
        off[k % 3] = ((k % 2) ? 1.0 : -1.0) * DEG;
        q = rq_norm(rq_mul(rq_exp(off), q));
        t += 100000000u;
        aocs_mekf_input_t in = input_of(t, zero, 1, q, t);
        assert_int_equal(aocs_mekf_step(&f, &in, &o), AOCS_OK);
        assert_int_equal(o.st_status, AOCS_OK);
        assert_true(fabs((double)aocs_quat_norm(o.q_BN_hat) - 1.0) <= 4.0 * (double)AOCS_REAL_EPS);
        assert_true(o.q_BN_hat.q[3] >= AOCS_R(0.0));
        /* a good part of the 1 deg jump is taken in one update (R tiny next to P) */
        assert_true(rq_angle(q, rq_from(o.q_BN_hat)) < 0.1 * DEG);
    }
}

/* Fault management's re-inflation (docs/spec.md 5.15.4): the bias block of P back to p0_bias^2 I, the
 * attitude-bias cross covariance zero, the attitude block and the estimates untouched; a no-op before the
 * start. Then, after a bias jump of 5 prior sigma (5e-7 rad/s), the re-inflated filter's bias error after
 * 60 s is under a fifth of the one left alone on the same samples (measured: a tenth) */
static int same_real(real_t a, real_t b)
{
    return (a <= b) && (a >= b);
}

static void bias_reinflation(void **state)
{
    (void)state;
    bench_t a;
    bench_t *b = (bench_t *)test_malloc(sizeof(bench_t));
    aocs_mekf_output_t o0;
    aocs_mekf_output_t o1;
    aocs_mekf_t idle;
    aocs_mekf_config_t cfg;
    harness_start(&a, 3000);
    assert_int_equal(aocs_mekf_get_output(&a.f, &o0), AOCS_OK);
    *b = a;
    aocs_mekf_reinflate_bias(&b->f);
    assert_int_equal(aocs_mekf_get_output(&b->f, &o1), AOCS_OK);
    assert_output_sane(&o1);
    for (int i = 0; i < 6; ++i) {
        for (int j = 0; j < 6; ++j) {
            if ((i < 3) && (j < 3)) {
                assert_true(same_real(o1.P.m[i][j], o0.P.m[i][j]));
            } else if (i == j) {
                assert_close(o1.P.m[i][j], 1e-7 * 1e-7, 1e-6 * 1e-14);
            } else {
                assert_true(!(o1.P.m[i][j] > AOCS_R(0.0)) && !(o1.P.m[i][j] < AOCS_R(0.0)));
            }
        }
    }
    for (int i = 0; i < 4; ++i) {
        assert_true(same_real(o1.q_BN_hat.q[i], o0.q_BN_hat.q[i]));
    }
    for (int i = 0; i < 3; ++i) {
        assert_true(same_real(o1.bias_B_hat.v[i], o0.bias_B_hat.v[i]));
        /* the jump: both filters see the same truth and samples from here */
        a.s.b[i] += 5e-7;
    }
    b->s = a.s;
    for (int k = 0; k < 600; ++k) {
        double wm[3];
        rq_t q_sn;
        sim_step(&a.s, &a.c, wm);
        q_sn = sim_tracker(&a.s, &a.c, 0);
        a.t += 100000000u;
        b->t = a.t;
        {
            aocs_mekf_input_t in = input_of(a.t, wm, 1, q_sn, a.t);
            assert_int_equal(aocs_mekf_step(&a.f, &in, &o0), AOCS_OK);
            assert_int_equal(aocs_mekf_step(&b->f, &in, &o1), AOCS_OK);
        }
    }
    {
        double ea = 0.0;
        double eb = 0.0;
        for (int i = 0; i < 3; ++i) {
            ea = fmax(ea, fabs((double)o0.bias_B_hat.v[i] - a.s.b[i]));
            eb = fmax(eb, fabs((double)o1.bias_B_hat.v[i] - a.s.b[i]));
        }
        print_message("bias error 60 s after a 5e-7 rad/s jump: left alone %.3g, re-inflated %.3g rad/s\n", ea, eb);
        assert_true(eb < 0.2 * ea);
    }
    test_free(b);
    /* before the start, and on NULL: nothing */
    aocs_mekf_config_default(&cfg);
    assert_int_equal(aocs_mekf_init(&idle, &cfg), AOCS_OK);
    aocs_mekf_reinflate_bias(&idle);
    for (int i = 0; i < 6; ++i) {
        assert_true(!(idle.P.m[i][i] > AOCS_R(0.0)) && !(idle.P.m[i][i] < AOCS_R(0.0)));
    }
    aocs_mekf_reinflate_bias(NULL);
    /* a started filter's copy whose init mark is not init's (memory not set by aocs_mekf_init): nothing, as
     * every other entry point refuses it */
    {
        bench_t c;
        harness_start(&c, 20);
        const real_t p33 = c.f.P.m[3][3];
        c.f.initialised = 1;
        aocs_mekf_reinflate_bias(&c.f);
        assert_true(same_real(c.f.P.m[3][3], p33));
        assert_int_equal(aocs_mekf_get_output(&c.f, &o0), AOCS_ERR_NOT_INITIALISED);
    }
}

static void covariance_rule(void **state)
{
    (void)state;
    bench_t b;
    aocs_mekf_output_t o;
    harness_start(&b, 50);
    assert_int_equal(aocs_mekf_get_output(&b.f, &o), AOCS_OK);
    assert_output_sane(&o);
    /* the floor: a diagonal element driven negative by rounding (row and column zero) comes back at exactly
     * p_floor (raised here above the step's Q so that it binds) */
    b.f.p_floor[4] = AOCS_R(1e-12);
    b.f.P.m[4][4] = AOCS_R(-1e-30);
    for (int j = 0; j < 6; ++j) {
        if (j != 4) {
            b.f.P.m[4][j] = AOCS_R(0.0);
            b.f.P.m[j][4] = AOCS_R(0.0);
        }
    }
    b.t += 100000000u;
    assert_int_equal(aocs_mekf_propagate(&b.f, aocs_vec3_zero(), b.t), AOCS_OK);
    assert_true(!(b.f.P.m[4][4] > b.f.p_floor[4]) && !(b.f.P.m[4][4] < b.f.p_floor[4]));
    assert_true(b.f.p_floor[4] > AOCS_R(0.0));
    /* an asymmetric P comes out exactly symmetric */
    b.f.P.m[0][1] *= AOCS_R(1.5);
    b.t += 100000000u;
    assert_int_equal(aocs_mekf_propagate(&b.f, aocs_vec3_make(AOCS_R(0.01), AOCS_R(0.02), AOCS_R(-0.01)), b.t),
                     AOCS_OK);
    assert_int_equal(aocs_mekf_get_output(&b.f, &o), AOCS_OK);
    assert_output_sane(&o);
    /* an indefinite P (correlation > 1): the filter restarts, status and zeroed output */
    b.f.P.m[0][3] = AOCS_R(10.0) * AOCS_SQRT(b.f.P.m[0][0] * b.f.P.m[3][3]);
    b.f.P.m[3][0] = b.f.P.m[0][3];
    b.t += 100000000u;
    {
        double wm[3] = {0.0, 0.0, 0.0};
        aocs_mekf_input_t in = input_of(b.t, wm, 0, b.s.q, b.t);
        assert_int_equal(aocs_mekf_step(&b.f, &in, &o), AOCS_ERR_MEKF_COV_INVALID);
        assert_output_zero(&o);
        assert_int_equal(o.n_restarts, 1u);
        b.t += 100000000u;
        in = input_of(b.t, wm, 0, b.s.q, b.t);
        assert_int_equal(aocs_mekf_step(&b.f, &in, &o), AOCS_ERR_MEKF_NO_ATTITUDE);
        assert_output_zero(&o);
        /* the next valid sample starts it again */
        b.t += 100000000u;
        in = input_of(b.t, wm, 1, sim_tracker(&b.s, &b.c, 0), b.t);
        assert_int_equal(aocs_mekf_step(&b.f, &in, &o), AOCS_OK);
        assert_output_sane(&o);
        /* indefinite in the last pivot of the factorisation (attitude z with bias z): found as well */
        b.f.P.m[2][5] = AOCS_R(10.0) * AOCS_SQRT(b.f.P.m[2][2] * b.f.P.m[5][5]);
        b.f.P.m[5][2] = b.f.P.m[2][5];
        b.t += 100000000u;
        in = input_of(b.t, wm, 0, b.s.q, b.t);
        assert_int_equal(aocs_mekf_step(&b.f, &in, &o), AOCS_ERR_MEKF_COV_INVALID);
        assert_output_zero(&o);
        assert_int_equal(o.n_restarts, 2u);
    }
}

/* A valid star-tracker sample of the bench's truth taken at the estimate's time (h = 0), given to the update. */
static aocs_status_t update_at_estimate_time(bench_t *b)
{
    aocs_mekf_st_sample_t smp;
    memset(&smp, 0, sizeof(smp));
    smp.valid = 1u;
    smp.q_SN = rq_to(sim_tracker(&b->s, &b->c, 0));
    smp.t_meas_ns = b->t;
    return aocs_mekf_update(&b->f, &smp);
}

/* S = H P H^T + R must be positive definite: a zero pivot of its factorisation is refused as an invalid
 * covariance and restarts the filter, like a negative one; it is never used as a divisor (d^2 would be inf or
 * NaN and the sample would count as gated). Here the last pivot, S_22 - L_20^2 - L_21^2 = P_22 + R_22 = 0
 * exactly: a sample at the estimate's time (h = 0) with q_SB = identity, so that R = diag(r_S), and P_22's
 * row decoupled from the attitude x and y errors (a zero pivot earlier would make the next one non-finite) */
static void innovation_covariance_zero_pivot(void **state)
{
    (void)state;
    bench_t b;
    aocs_mekf_output_t o;
    harness_start(&b, 20);
    const uint32_t restarts = b.f.n_restarts;
    const uint32_t gated = b.f.n_gated;
    b.t += 100000000u;
    assert_int_equal(aocs_mekf_propagate(&b.f, aocs_vec3_zero(), b.t), AOCS_OK);
    for (int j = 0; j < 2; ++j) {
        b.f.P.m[2][j] = AOCS_R(0.0);
        b.f.P.m[j][2] = AOCS_R(0.0);
    }
    b.f.P.m[2][2] = -b.f.r_S[2];
    assert_int_equal(update_at_estimate_time(&b), AOCS_ERR_MEKF_COV_INVALID);
    assert_int_equal(b.f.n_restarts, restarts + 1u);
    assert_int_equal(b.f.n_gated, gated);
    assert_int_equal(aocs_mekf_get_output(&b.f, &o), AOCS_ERR_MEKF_NO_ATTITUDE);
    assert_output_zero(&o);
}

/* P after an update must be positive definite: a zero last pivot of its factorisation (a singular P, the bias
 * z error a copy of the bias x error: P_33 = 4, P_35 = 2, P_55 = 1, so that P_55 - L_53^2 = 1 - (2/2)^2 = 0
 * exactly, in both precisions) is refused like a negative one and restarts the filter. The update is at the
 * estimate's time (h = 0) with the bias decoupled from the attitude, so the bias block comes out of the Joseph
 * form unchanged. The restart count saturates at UINT32_MAX rather than wrap to 0. */
static void updated_covariance_zero_last_pivot(void **state)
{
    (void)state;
    bench_t b;
    harness_start(&b, 20);
    b.t += 100000000u;
    assert_int_equal(aocs_mekf_propagate(&b.f, aocs_vec3_zero(), b.t), AOCS_OK);
    for (int i = 0; i < 3; ++i) {
        for (int j = 3; j < 6; ++j) {
            b.f.P.m[i][j] = AOCS_R(0.0);
            b.f.P.m[j][i] = AOCS_R(0.0);
        }
    }
    for (int i = 3; i < 6; ++i) {
        for (int j = 3; j < 6; ++j) {
            b.f.P.m[i][j] = AOCS_R(0.0);
        }
    }
    b.f.P.m[3][3] = AOCS_R(4.0);
    b.f.P.m[4][4] = AOCS_R(1.0);
    b.f.P.m[5][5] = AOCS_R(1.0);
    b.f.P.m[3][5] = AOCS_R(2.0);
    b.f.P.m[5][3] = AOCS_R(2.0);
    for (int i = 3; i < 6; ++i) {
        assert_true(b.f.P.m[i][i] > b.f.p_floor[i]); /* the floor leaves the diagonal as it is */
    }
    b.f.n_restarts = UINT32_MAX;
    assert_int_equal(update_at_estimate_time(&b), AOCS_ERR_MEKF_COV_INVALID);
    assert_int_equal(b.f.n_restarts, UINT32_MAX);
    assert_int_equal(b.f.started, 0u);
}

static void hostile_inputs(void **state)
{
    (void)state;
    bench_t b, twin;
    aocs_mekf_output_t o, ot;
    double wm[3];
    harness_start(&b, 100);
    twin = b;
    sim_step(&b.s, &b.c, wm);
    b.t += 100000000u;
    {
        /* the same step for both: the twin never sees the bad samples */
        rq_t good = sim_tracker(&b.s, &b.c, 0);
        aocs_mekf_input_t in = input_of(b.t, wm, 0, good, b.t);
        assert_int_equal(aocs_mekf_step(&b.f, &in, &o), AOCS_OK);
        assert_int_equal(o.st_status, AOCS_ERR_INPUT_MISSING);
        assert_int_equal(aocs_mekf_step(&twin.f, &in, &ot), AOCS_OK);
        {
            const uint64_t tl = b.f.t_last_meas_ns;
            struct {
                aocs_quat_t q;
                uint64_t t;
                aocs_status_t want;
            } cases[] = {
                {aocs_quat_make(AOCS_R(NAN), AOCS_R(0.0), AOCS_R(0.0), AOCS_R(1.0)), b.t, AOCS_ERR_INPUT_NOT_FINITE},
                {aocs_quat_make(AOCS_R(0.0), AOCS_R(INFINITY), AOCS_R(0.0), AOCS_R(1.0)), b.t, AOCS_ERR_INPUT_NOT_FINITE},
                {aocs_quat_make((real_t)(good.q[0] * 1.01), (real_t)(good.q[1] * 1.01), (real_t)(good.q[2] * 1.01),
                                (real_t)(good.q[3] * 1.01)),
                 b.t, AOCS_ERR_QUAT_NOT_UNIT},
                {aocs_quat_make(AOCS_R(0.0), AOCS_R(0.0), AOCS_R(0.0), AOCS_R(0.0)), b.t, AOCS_ERR_QUAT_NOT_UNIT},
                {rq_to(good), b.t + 1u, AOCS_ERR_MEKF_MEAS_FUTURE},
                {rq_to(good), UINT64_MAX, AOCS_ERR_MEKF_MEAS_FUTURE},
                {rq_to(good), tl, AOCS_ERR_INPUT_STALE},
                {rq_to(good), tl - 1u, AOCS_ERR_INPUT_STALE},
                {rq_to(good), 0u, AOCS_ERR_INPUT_STALE},
            };
            for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); ++i) {
                aocs_mekf_st_sample_t smp = {cases[i].q, cases[i].t, 1u};
                assert_int_equal(aocs_mekf_update(&b.f, &smp), cases[i].want);
                assert_int_equal(aocs_mekf_get_output(&b.f, &o), AOCS_OK);
                assert_output_sane(&o);
                assert_int_equal(o.n_hostile, (uint32_t)(i + 1));
            }
            /* the state is exactly the twin's */
            assert_memory_equal(&b.f.q_BN_hat, &twin.f.q_BN_hat, sizeof(b.f.q_BN_hat));
            assert_memory_equal(&b.f.P, &twin.f.P, sizeof(b.f.P));
            assert_memory_equal(&b.f.bias_B_hat, &twin.f.bias_B_hat, sizeof(b.f.bias_B_hat));
        }
        {
            /* within the unit tolerance: used (normalised) */
            real_t k = AOCS_R(1.0) + AOCS_R(0.5) * AOCS_MEKF_QUAT_UNIT_TOL;
            aocs_mekf_st_sample_t smp = {aocs_quat_make(AOCS_R(good.q[0]) * k, AOCS_R(good.q[1]) * k,
                                                        AOCS_R(good.q[2]) * k, AOCS_R(good.q[3]) * k),
                                         b.t, 1u};
            assert_int_equal(aocs_mekf_update(&b.f, &smp), AOCS_OK);
        }
    }
    {
        /* too old: before the 32-step history (but not stale: after the last used sample) */
        uint64_t t_old;
        for (int k = 0; k < 40; ++k) {
            sim_step(&b.s, &b.c, wm);
            b.t += 100000000u;
            assert_int_equal(aocs_mekf_propagate(&b.f, aocs_vec3_make((real_t)wm[0], (real_t)wm[1], (real_t)wm[2]), b.t),
                             AOCS_OK);
        }
        t_old = b.t - (uint64_t)(AOCS_MEKF_HISTORY_LEN + 1u) * 100000000u;
        {
            aocs_mekf_st_sample_t smp = {rq_to(b.s.q), t_old, 1u};
            uint32_t h0 = b.f.n_hostile;
            assert_int_equal(aocs_mekf_update(&b.f, &smp), AOCS_ERR_MEKF_MEAS_TOO_OLD);
            assert_int_equal(b.f.n_hostile, h0 + 1u);
            /* the oldest instant the history covers is accepted */
            smp.t_meas_ns = b.t - (uint64_t)AOCS_MEKF_HISTORY_LEN * 100000000u;
            smp.q_SN = rq_to(sim_tracker(&b.s, &b.c, (int)AOCS_MEKF_HISTORY_LEN)); /* the truth at that time */
            assert_int_equal(aocs_mekf_update(&b.f, &smp), AOCS_OK);
        }
    }
    {
        /* gyro: NaN, Inf, out of range, time not advancing: the step fails with a zeroed output, the state kept */
        aocs_mekf_t keep = b.f;
        const double nanv[3] = {NAN, 0.0, 0.0}, infv[3] = {0.0, -INFINITY, 0.0}, big[3] = {0.0, 0.0, 1000.0};
        aocs_mekf_input_t in = input_of(b.t + 100000000u, nanv, 1, b.s.q, b.t + 100000000u);
        assert_int_equal(aocs_mekf_step(&b.f, &in, &o), AOCS_ERR_INPUT_NOT_FINITE);
        assert_output_zero(&o);
        in = input_of(b.t + 100000000u, infv, 1, b.s.q, b.t + 100000000u);
        assert_int_equal(aocs_mekf_step(&b.f, &in, &o), AOCS_ERR_INPUT_NOT_FINITE);
        assert_output_zero(&o);
        in = input_of(b.t + 100000000u, big, 1, b.s.q, b.t + 100000000u);
        assert_int_equal(aocs_mekf_step(&b.f, &in, &o), AOCS_ERR_MEKF_RATE_RANGE);
        assert_output_zero(&o);
        in = input_of(b.t, wm, 0, b.s.q, b.t);
        assert_int_equal(aocs_mekf_step(&b.f, &in, &o), AOCS_ERR_INPUT_STALE);
        assert_output_zero(&o);
        in = input_of(b.t - 1u, wm, 0, b.s.q, b.t);
        assert_int_equal(aocs_mekf_step(&b.f, &in, &o), AOCS_ERR_INPUT_STALE);
        assert_output_zero(&o);
        assert_memory_equal(&keep.q_BN_hat, &b.f.q_BN_hat, sizeof(keep.q_BN_hat));
        assert_memory_equal(&keep.P, &b.f.P, sizeof(keep.P));
    }
    {
        /* a gap beyond max_gap_s (10 s): restart, and this step's sample starts the filter again */
        uint64_t t2 = b.t + 11u * NS;
        aocs_mekf_input_t in = input_of(t2, wm, 0, b.s.q, t2);
        uint32_t r0 = b.f.n_restarts;
        assert_int_equal(aocs_mekf_step(&b.f, &in, &o), AOCS_ERR_MEKF_NO_ATTITUDE);
        assert_output_zero(&o);
        assert_int_equal(o.n_restarts, r0 + 1u);
        t2 += 100000000u;
        in = input_of(t2, wm, 1, rq_from(aocs_quat_make(AOCS_R(NAN), AOCS_R(0), AOCS_R(0), AOCS_R(1))), t2);
        assert_int_equal(aocs_mekf_step(&b.f, &in, &o), AOCS_ERR_MEKF_NO_ATTITUDE); /* a NaN sample does not start it */
        assert_int_equal(o.st_status, AOCS_ERR_INPUT_NOT_FINITE);
        assert_output_zero(&o);
        in = input_of(t2, wm, 1, b.s.q, t2 - 20u * NS);
        assert_int_equal(aocs_mekf_step(&b.f, &in, &o), AOCS_ERR_MEKF_NO_ATTITUDE); /* older than max_gap_s */
        assert_int_equal(o.st_status, AOCS_ERR_MEKF_MEAS_TOO_OLD);
        in = input_of(t2, wm, 1, b.s.q, t2 - 50000000u);
        assert_int_equal(aocs_mekf_step(&b.f, &in, &o), AOCS_OK); /* started at t_meas, propagated to t */
        assert_output_sane(&o);
        assert_int_equal(o.t_ns, t2);
    }
    {
        /* before the first sample, and the API's NULL / not-initialised cases */
        aocs_mekf_t g;
        aocs_mekf_config_t cfg;
        aocs_mekf_st_sample_t smp = {aocs_quat_identity(), 0u, 1u};
        memset(&g, 0, sizeof(g));
        aocs_mekf_input_t in = input_of(NS, wm, 0, b.s.q, NS);
        assert_int_equal(aocs_mekf_step(&g, &in, &o), AOCS_ERR_NOT_INITIALISED);
        assert_output_zero(&o);
        assert_int_equal(aocs_mekf_propagate(&g, aocs_vec3_zero(), NS), AOCS_ERR_NOT_INITIALISED);
        assert_int_equal(aocs_mekf_reset(&g), AOCS_ERR_NOT_INITIALISED);
        aocs_mekf_config_default(&cfg);
        assert_int_equal(aocs_mekf_init(&g, &cfg), AOCS_OK);
        assert_int_equal(aocs_mekf_step(&g, &in, &o), AOCS_ERR_MEKF_NO_ATTITUDE);
        assert_output_zero(&o);
        assert_int_equal(aocs_mekf_propagate(&g, aocs_vec3_zero(), NS), AOCS_ERR_MEKF_NO_ATTITUDE);
        assert_int_equal(aocs_mekf_update(&g, &smp), AOCS_ERR_MEKF_NO_ATTITUDE);
        assert_int_equal(aocs_mekf_get_output(&g, &o), AOCS_ERR_MEKF_NO_ATTITUDE);
        assert_output_zero(&o);
        assert_int_equal(aocs_mekf_step(NULL, &in, &o), AOCS_ERR_NULL_ARG);
        assert_output_zero(&o);
        assert_int_equal(aocs_mekf_step(&g, NULL, &o), AOCS_ERR_NULL_ARG);
        assert_int_equal(aocs_mekf_step(&g, &in, NULL), AOCS_ERR_NULL_ARG);
        assert_int_equal(aocs_mekf_update(&g, NULL), AOCS_ERR_NULL_ARG);
        assert_int_equal(aocs_mekf_get_output(NULL, &o), AOCS_ERR_NULL_ARG);
        assert_int_equal(aocs_mekf_init(NULL, &cfg), AOCS_ERR_NULL_ARG);
        assert_int_equal(aocs_mekf_init(&g, NULL), AOCS_ERR_NULL_ARG);
        assert_int_equal(aocs_mekf_reset(NULL), AOCS_ERR_NULL_ARG);
        aocs_mekf_config_default(NULL); /* total */
    }
    {
        /* explicit reset: back to waiting, counters cleared */
        assert_int_equal(aocs_mekf_reset(&b.f), AOCS_OK);
        assert_int_equal(aocs_mekf_get_output(&b.f, &o), AOCS_ERR_MEKF_NO_ATTITUDE);
        assert_output_zero(&o);
        assert_int_equal(o.n_hostile, 0u);
        assert_int_equal(o.n_updates, 0u);
        assert_int_equal(o.n_gated, 0u);
        assert_int_equal(o.n_restarts, 0u); /* the filter's own count starts again (the stage counts resets) */
    }
}

static void config_validation(void **state)
{
    (void)state;
    aocs_mekf_t f;
    aocs_mekf_config_t base, c;
    aocs_mekf_config_default(&base);
    assert_int_equal(aocs_mekf_init(&f, &base), AOCS_OK);
#define EXPECT_CFG(member, value, status)                      \
    do {                                                       \
        c = base;                                              \
        c.member = (value);                                    \
        assert_int_equal(aocs_mekf_init(&f, &c), (status));    \
        assert_int_not_equal(f.initialised, 0x4D454B46);       \
    } while (0)
    EXPECT_CFG(st_sigma_cross_rad, AOCS_R(NAN), AOCS_ERR_PARAM_NOT_FINITE);
    EXPECT_CFG(gyro_arw_radpsqrts, AOCS_R(INFINITY), AOCS_ERR_PARAM_NOT_FINITE);
    EXPECT_CFG(max_gap_s, AOCS_R(NAN), AOCS_ERR_PARAM_NOT_FINITE);
    EXPECT_CFG(bias0_B_radps.v[1], AOCS_R(NAN), AOCS_ERR_PARAM_NOT_FINITE);
    EXPECT_CFG(q_SB.q[3], AOCS_R(NAN), AOCS_ERR_PARAM_NOT_FINITE);
    EXPECT_CFG(q_SB.q[3], AOCS_R(0.9), AOCS_ERR_QUAT_NOT_UNIT);
    EXPECT_CFG(st_sigma_cross_rad, AOCS_R(0.0), AOCS_ERR_MEKF_NOISE_NOT_POSITIVE);
    EXPECT_CFG(st_sigma_about_rad, AOCS_R(-1e-6), AOCS_ERR_MEKF_NOISE_NOT_POSITIVE);
    EXPECT_CFG(gyro_arw_radpsqrts, AOCS_R(0.0), AOCS_ERR_MEKF_NOISE_NOT_POSITIVE);
    EXPECT_CFG(gyro_rrw_radps1p5, AOCS_R(0.0), AOCS_ERR_MEKF_NOISE_NOT_POSITIVE);
    EXPECT_CFG(p0_att_sigma_rad, AOCS_R(0.0), AOCS_ERR_MEKF_NOISE_NOT_POSITIVE);
    EXPECT_CFG(p0_bias_sigma_radps, AOCS_R(-1.0), AOCS_ERR_MEKF_NOISE_NOT_POSITIVE);
    EXPECT_CFG(gate_chi2, AOCS_R(0.0), AOCS_ERR_MEKF_GATE_INVALID);
    EXPECT_CFG(max_gap_s, AOCS_R(0.0), AOCS_ERR_DT_INVALID);
    EXPECT_CFG(max_gap_s, AOCS_R(3601.0), AOCS_ERR_DT_INVALID);
    EXPECT_CFG(q0_BN.q[0], AOCS_R(NAN), AOCS_ERR_PARAM_NOT_FINITE);
    EXPECT_CFG(q0_BN.q[3], AOCS_R(1.1), AOCS_ERR_QUAT_NOT_UNIT);
    EXPECT_CFG(init_mode, AOCS_MEKF_INIT_COUNT, AOCS_ERR_MEKF_INIT_MODE_INVALID);
    EXPECT_CFG(init_mode, 0xFFFFFFFFu, AOCS_ERR_MEKF_INIT_MODE_INVALID);
#undef EXPECT_CFG
    {
        /* the default gate is the 99.9 % point of chi2(3): 1 - CDF(x) = 1 - erf(sqrt(x/2)) + sqrt(2x/pi) exp(-x/2) */
        double x = (double)AOCS_MEKF_GATE_CHI2_3DOF_999;
        double tail = 1.0 - erf(sqrt(0.5 * x)) + sqrt(2.0 * x / 3.141592653589793) * exp(-0.5 * x);
        assert_true(fabs(tail - 1e-3) <= 1e-9);
    }
}

/* spec 5.15.3: the tracker's noise scale and the whitened innovation. Two filters fed the same samples, one with
 * its tracker noise variances scaled by 100: on a sample 20 arcsec off, d^2 falls by about the scale (S is
 * mostly R once converged); |z|^2 = d^2; a scale below 1 or not finite is 1 (the twin stays identical). */
static void tracker_noise_scale(void **state)
{
    (void)state;
    aocs_mekf_config_t cfg;
    aocs_mekf_t a;
    aocs_mekf_t b;
    aocs_mekf_t c;
    aocs_mekf_t d;
    aocs_mekf_input_t in;
    aocs_mekf_output_t oa;
    aocs_mekf_output_t ob;
    aocs_mekf_output_t oc;
    aocs_mekf_output_t od;
    aocs_mekf_config_default(&cfg);
    assert_int_equal(aocs_mekf_init(&a, &cfg), AOCS_OK);
    assert_int_equal(aocs_mekf_init(&b, &cfg), AOCS_OK);
    assert_int_equal(aocs_mekf_init(&c, &cfg), AOCS_OK);
    assert_int_equal(aocs_mekf_init(&d, &cfg), AOCS_OK);
    aocs_mekf_set_st_noise_scale(&c, AOCS_R(0.5));
    aocs_mekf_set_st_noise_scale(&d, (real_t)NAN);
    memset(&in, 0, sizeof(in));
    in.st.valid = 1u;
    for (uint64_t k = 0u; k < 600u; ++k) { /* 60 s at rest, the tracker exact */
        in.t_ns = k * (NS / 10u);
        in.st.q_SN = aocs_quat_identity();
        in.st.t_meas_ns = in.t_ns;
        if (k == 599u) {
            aocs_mekf_set_st_noise_scale(&b, AOCS_R(100.0));
            in.st.q_SN = aocs_quat_make(AOCS_R(10.0 * ARCSEC), AOCS_R(0.0), AOCS_R(0.0), AOCS_R(1.0));
        }
        (void)aocs_mekf_step(&a, &in, &oa);
        (void)aocs_mekf_step(&b, &in, &ob);
        (void)aocs_mekf_step(&c, &in, &oc);
        (void)aocs_mekf_step(&d, &in, &od);
    }
    assert_true((double)oa.innovation_chi2 > 16.0); /* 20 arcsec against a 1 arcsec tracker: gated */
    assert_close(aocs_vec3_norm_sq(oa.innovation_white), oa.innovation_chi2, 1e-4 * (double)oa.innovation_chi2);
    assert_close(aocs_vec3_norm_sq(ob.innovation_white), ob.innovation_chi2, 1e-4 * (double)ob.innovation_chi2);
    {
        const double ratio = (double)oa.innovation_chi2 / (double)ob.innovation_chi2;
        assert_true((ratio > 60.0) && (ratio < 101.0));
    }
    assert_int_equal(ob.st_status, AOCS_OK); /* within the gate once the noise is scaled */
    assert_memory_equal(&oa.q_BN_hat, &oc.q_BN_hat, sizeof(oa.q_BN_hat));
    assert_close(oa.innovation_chi2, oc.innovation_chi2, 0.0);
    assert_memory_equal(&oa.q_BN_hat, &od.q_BN_hat, sizeof(oa.q_BN_hat));
    assert_close(oa.innovation_chi2, od.innovation_chi2, 0.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(config_validation),
        cmocka_unit_test(riccati_ode),
        cmocka_unit_test(reference_filter),
        cmocka_unit_test(configured_start),
        cmocka_unit_test(configured_start_with_a_rejected_first_sample),
        cmocka_unit_test(quaternion_reset),
        cmocka_unit_test(propagation_coefficients),
        cmocka_unit_test(covariance_rule),
        cmocka_unit_test(bias_reinflation),
        cmocka_unit_test(innovation_covariance_zero_pivot),
        cmocka_unit_test(updated_covariance_zero_last_pivot),
        cmocka_unit_test(gating),
        cmocka_unit_test(tracker_noise_scale),
        cmocka_unit_test(hostile_inputs),
        cmocka_unit_test(convergence),
        cmocka_unit_test(outage),
        cmocka_unit_test(steady_state_10hz_nav),
        cmocka_unit_test(steady_state_10hz_5as),
        cmocka_unit_test(steady_state_2hz_tactical),
        cmocka_unit_test(steady_state_latency),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
