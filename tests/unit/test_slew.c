/*
 * Slew guidance (aocs/guidance/slew.h, docs/spec.md "Slew guidance"), against
 * an independent model written here in double (law_test_support.h: no
 * firmware math):
 *  - theta(t), thetadot(t) at random times equal the numerical integral
 *    (trapezoid, 200k steps) of the module's own thetaddot(t), for both
 *    profiles, with and without a rate limit, random inertia (off-diagonal
 *    terms), attitudes and limits (box, ball, both);
 *  - the end time equals the closed form of each profile written here from
 *    an independently computed alpha (min over axes of m u_i / (|Je|_i +
 *    theta_f |e x Je|_i), the ball's m u / max|Je +- theta_f e x Je|);
 *  - qd(t) has the attitude matrix R(e, theta(t)) A(q0) (Rodrigues'
 *    formula), wd = thetadot e, wd_dot = thetaddot e;
 *  - at t_end and after the reference is the commanded target exactly, zero rates;
 *    just before it, within the precision's tolerance;
 *  - the reference torque J wd_dot + wd x J wd never leaves margin x the
 *    envelope (dense sampling), and the jerk-limited acceleration is continuous
 *    with |jerk| <= alpha / jerk_time;
 *  - q0 -> -q0 and qf -> -qf give the same attitude path and rates;
 *  - each invalid config its own status; the feedforward formula.
 */
#include "law_test_support.h"
#include "wheel_test_support.h"

#include "aocs/guidance/slew.h"

#if defined(AOCS_REAL_IS_FLOAT)
#define TOL_PROFILE 2.0e-3 /* relative to theta_f / peak rate: float evaluation of t, sin, cos */
#define TOL_TEND 1.0e-5
#define TOL_JERK 1.0e-3 /* float time near 500 s: ulp 3e-5 s of ramp */
#define TOL_ATT 2.0e-5
#else
#define TOL_PROFILE 1.0e-7 /* plus the trapezoid error bound at the acceleration jumps, 2 alpha h (tol_rate) */
#define TOL_TEND 1.0e-9
#define TOL_JERK 1.0e-9
#define TOL_ATT 1.0e-11
#endif

#define N_INT 200000

/* exact equality without a float == (-Wfloat-equal) */
static int same(double a, double b)
{
    return (!(a < b) && !(a > b)) ? 1 : 0;
}

typedef struct {
    aocs_slew_config_t cfg;
    aocs_slew_envelope_t env;
    aocs_quat_t q0;
    aocs_quat_t qf;
} slew_case_t;

static aocs_mat3_t random_inertia(test_rng_t *r)
{
    /* a principal inertia turned by a random attitude: symmetric positive definite, off-diagonal terms */
    double d[3] = {test_rng_uniform(r, 1000.0, 6000.0), test_rng_uniform(r, 1000.0, 6000.0),
                   test_rng_uniform(r, 1000.0, 6000.0)};
    double a[3][3];
    aocs_mat3_t j;
    ref_dcm(test_random_quat(r), a);
    for (int i = 0; i < 3; ++i) {
        for (int k = 0; k < 3; ++k) {
            double s = 0.0;
            for (int m = 0; m < 3; ++m) {
                s += a[m][i] * d[m] * a[m][k];
            }
            j.m[i][k] = (real_t)s;
        }
    }
    for (int i = 0; i < 3; ++i) {
        for (int k = 0; k < i; ++k) {
            j.m[i][k] = j.m[k][i]; /* exactly symmetric after rounding */
        }
    }
    return j;
}

static slew_case_t random_case(test_rng_t *r, aocs_slew_profile_t profile, int rate_limited, int env_kind)
{
    slew_case_t c;
    c.cfg.profile = profile;
    c.cfg.margin = (real_t)test_rng_uniform(r, 0.5, 1.0);
    c.cfg.rate_limit_radps = (rate_limited != 0) ? (real_t)test_rng_uniform(r, 0.001, 0.004) : AOCS_R(0.0);
    c.cfg.jerk_time_s = (profile == AOCS_SLEW_PROFILE_JERK_LIMITED) ? (real_t)test_rng_uniform(r, 1.0, 20.0)
                                                                     : AOCS_R(0.0);
    c.cfg.inertia_kgm2 = random_inertia(r);
    c.env.u_max_axis_Nm = aocs_vec3_zero();
    c.env.u_max_norm_Nm = AOCS_R(0.0);
    c.env.wheels = NULL;
    if ((env_kind & 1) != 0) {
        c.env.u_max_axis_Nm = aocs_vec3_make((real_t)test_rng_uniform(r, 0.2, 1.0), (real_t)test_rng_uniform(r, 0.2, 1.0),
                                             (real_t)test_rng_uniform(r, 0.2, 1.0));
    }
    if ((env_kind & 2) != 0) {
        c.env.u_max_norm_Nm = (real_t)test_rng_uniform(r, 0.3, 1.5);
    }
    c.q0 = test_random_quat(r);
    c.qf = test_random_quat(r);
    return c;
}

/* eigenaxis and angle of qf (x) q0^-1, short way, in double */
static double ref_axis_angle(aocs_quat_t q0, aocs_quat_t qf, double e[3])
{
    dq_t dq = dq_mul(dq_from_real(qf), dq_inv(dq_from_real(q0)));
    double s;
    if (dq.q[3] < 0.0) {
        for (int i = 0; i < 4; ++i) {
            dq.q[i] = -dq.q[i];
        }
    }
    s = sqrt(dq.q[0] * dq.q[0] + dq.q[1] * dq.q[1] + dq.q[2] * dq.q[2]);
    for (int i = 0; i < 3; ++i) {
        e[i] = dq.q[i] / s;
    }
    return 2.0 * atan2(s, dq.q[3]);
}

/* alpha of the config written independently: margin * min over the set envelope kinds */
static double ref_alpha(const slew_case_t *c, const double e[3], double th)
{
    double je[3];
    double g[3];
    double alpha = 1e300;
    dmat_t j;
    for (int i = 0; i < 3; ++i) {
        for (int k = 0; k < 3; ++k) {
            j.m[i][k] = (double)c->cfg.inertia_kgm2.m[i][k];
        }
    }
    dm_mul_vec(&j, e, je);
    dv_cross(e, je, g);
    if ((double)c->env.u_max_axis_Nm.v[0] > 0.0) {
        for (int i = 0; i < 3; ++i) {
            double a = (double)c->env.u_max_axis_Nm.v[i] / (fabs(je[i]) + th * fabs(g[i]));
            alpha = (a < alpha) ? a : alpha;
        }
    }
    if ((double)c->env.u_max_norm_Nm > 0.0) {
        double np = 0.0;
        double nm = 0.0;
        for (int i = 0; i < 3; ++i) {
            np += (je[i] + th * g[i]) * (je[i] + th * g[i]);
            nm += (je[i] - th * g[i]) * (je[i] - th * g[i]);
        }
        np = sqrt((np > nm) ? np : nm);
        alpha = ((double)c->env.u_max_norm_Nm / np < alpha) ? (double)c->env.u_max_norm_Nm / np : alpha;
    }
    return (double)c->cfg.margin * alpha;
}

/* end time in closed form: t_end = theta_f / v + v / alpha + tj (long slew, peak acceleration alpha) */
static double ref_t_end(const slew_case_t *c, double alpha, double th)
{
    double tj = (double)c->cfg.jerk_time_s;
    double w = (double)c->cfg.rate_limit_radps;
    double v = 0.5 * alpha * (sqrt(tj * tj + 4.0 * th / alpha) - tj);
    if ((w > 0.0) && (w < v)) {
        v = w;
    }
    return th / v + v / alpha + tj;
}

static void eval_at(const aocs_slew_t *s, double t, aocs_slew_ref_t *ref)
{
    aocs_slew_eval(s, (real_t)t, ref);
}

static void check_case(const slew_case_t *c, test_rng_t *r)
{
    aocs_slew_t s;
    aocs_slew_ref_t ref;
    double e[3];
    double th = ref_axis_angle(c->q0, c->qf, e);
    double alpha = ref_alpha(c, e, th);
    static double theta_num[N_INT + 1];
    static double rate_num[N_INT + 1];
    double t_end;
    double h;
    double acc_prev;
    double v_peak = 0.0;
    double tol_rate;
    double tol_theta;

    assert_int_equal(aocs_slew_plan(&s, &c->cfg, &c->env, c->q0, c->qf), AOCS_OK);
    assert_close(s.theta_f_rad, th, TOL_ATT * 10.0);
    for (int i = 0; i < 3; ++i) {
        assert_close(s.e.v[i], e[i], TOL_ATT * 1e3);
    }
    /* the long-slew closed form applies when the peak acceleration is reached */
    if ((double)s.accel_radps2 >= alpha * (1.0 - 1e-6)) {
        assert_close(s.t_end_s, ref_t_end(c, alpha, th), TOL_TEND);
    }
    assert_true((double)s.accel_radps2 <= alpha * (1.0 + 1e-5));
    t_end = (double)s.t_end_s;
    assert_true(t_end > 0.0);

    /* numerical integral of the module's own acceleration */
    h = t_end / (double)N_INT;
    theta_num[0] = 0.0;
    rate_num[0] = 0.0;
    eval_at(&s, 0.0, &ref);
    acc_prev = (double)ref.theta_ddot_radps2;
    for (int k = 1; k <= N_INT; ++k) {
        double acc;
        eval_at(&s, (k == N_INT) ? t_end * (1.0 - 1e-12) : h * (double)k, &ref);
        acc = (double)ref.theta_ddot_radps2;
        rate_num[k] = rate_num[k - 1] + 0.5 * h * (acc + acc_prev);
        theta_num[k] = theta_num[k - 1] + 0.5 * h * (rate_num[k] + rate_num[k - 1]);
        v_peak = (rate_num[k] > v_peak) ? rate_num[k] : v_peak;
        if (c->cfg.profile == AOCS_SLEW_PROFILE_JERK_LIMITED) {
            /* continuous acceleration, |jerk| <= alpha / tj (tiny slack for rounding) */
            assert_true(fabs(acc - acc_prev) <= h * alpha / (double)c->cfg.jerk_time_s * 1.001 + TOL_JERK * alpha);
        }
        acc_prev = acc;
    }
    /* a jump of the acceleration between two grid points costs the trapezoid up to alpha h / 2 of rate */
    tol_rate = TOL_PROFILE * v_peak + 2.0 * alpha * h;
    tol_theta = TOL_PROFILE * th + 2.0 * alpha * h * t_end;
    if (c->cfg.rate_limit_radps > AOCS_R(0.0)) {
        assert_true(v_peak <= (double)c->cfg.rate_limit_radps + tol_rate);
        assert_true((double)s.rate_radps <= (double)c->cfg.rate_limit_radps);
    }
    assert_true(fabs(rate_num[N_INT]) <= tol_rate);
    assert_true(fabs(theta_num[N_INT] - th) <= tol_theta);

    for (int n = 0; n < 200; ++n) {
        int k = (int)test_rng_uniform(r, 1.0, (double)N_INT);
        double t = h * (double)k;
        double a_n[3][3];
        double a_r[3][3];
        double a0[3][3];
        double ct;
        double st;
        eval_at(&s, t, &ref);
        assert_true(fabs((double)ref.theta_rad - theta_num[k]) <= tol_theta);
        assert_true(fabs((double)ref.theta_dot_radps - rate_num[k]) <= tol_rate);
        /* attitude: A(qd) = R(e, theta) A(q0), R(e, th) = cos I + (1 - cos) e e^T - sin [e x] (passive) */
        ct = cos((double)ref.theta_rad);
        st = sin((double)ref.theta_rad);
        ref_dcm(c->q0, a0);
        for (int i = 0; i < 3; ++i) {
            for (int m = 0; m < 3; ++m) {
                double skew[3][3] = {{0.0, -e[2], e[1]}, {e[2], 0.0, -e[0]}, {-e[1], e[0], 0.0}};
                a_r[i][m] = ((i == m) ? ct : 0.0) + (1.0 - ct) * e[i] * e[m] - st * skew[i][m];
            }
        }
        ref_dcm(ref.qd_DN, a_n);
        for (int i = 0; i < 3; ++i) {
            for (int m = 0; m < 3; ++m) {
                double p = 0.0;
                for (int l = 0; l < 3; ++l) {
                    p += a_r[i][l] * a0[l][m];
                }
                assert_true(fabs(a_n[i][m] - p) <= TOL_ATT * 10.0);
            }
        }
        for (int i = 0; i < 3; ++i) {
            assert_close(ref.wd_D.v[i], (double)ref.theta_dot_radps * e[i], TOL_ATT * 1e3);
            assert_close(ref.wd_dot_D.v[i], (double)ref.theta_ddot_radps2 * e[i], TOL_ATT * 1e3);
        }
    }

    /* end: exactly the target, at rest */
    eval_at(&s, t_end, &ref);
    for (int i = 0; i < 4; ++i) {
        assert_true(same((double)(ref.qd_DN.q[i]), (double)(c->qf.q[i])));
    }
    assert_true(same((double)(aocs_vec3_norm_inf(ref.wd_D)), (double)(AOCS_R(0.0))));
    assert_true(same((double)(aocs_vec3_norm_inf(ref.wd_dot_D)), (double)(AOCS_R(0.0))));
    aocs_slew_eval(&s, s.t_end_s + AOCS_R(100.0), &ref);
    assert_true(same((double)(ref.qd_DN.q[3]), (double)(c->qf.q[3])));
    /* just before the end: dq_e(theta) (x) q0 is the target (up to sign) */
    eval_at(&s, t_end * (1.0 - 1e-9), &ref);
    {
        dq_t a = dq_from_real(ref.qd_DN);
        dq_t b = dq_from_real(c->qf);
        double dot = 0.0;
        for (int i = 0; i < 4; ++i) {
            dot += a.q[i] * b.q[i];
        }
        assert_true(fabs(fabs(dot) - 1.0) <= TOL_ATT * 100.0);
    }
}

static void profile_matches_independent_model(void **state)
{
    (void)state;
    test_rng_t r = {0x5eed5eedULL};
    for (int env = 1; env <= 3; ++env) {
        for (int rl = 0; rl <= 1; ++rl) {
            for (int p = 0; p < (int)AOCS_SLEW_PROFILE_COUNT; ++p) {
                for (int n = 0; n < 3; ++n) {
                    slew_case_t c = random_case(&r, (aocs_slew_profile_t)p, rl, env);
                    check_case(&c, &r);
                }
            }
        }
    }
}

/* the IRASSI slew of SPEC 5.1: bound 2 sqrt(theta_f / alpha), m = 1 */
static void irassi_bound(void **state)
{
    (void)state;
        slew_case_t c;
    aocs_slew_t s;
    const double lim[3] = {1.0, 0.5, 0.2};
    const double bound[3] = {114.3, 161.6, 255.6};
    c.cfg.profile = AOCS_SLEW_PROFILE_BANG_COAST_BANG;
    c.cfg.margin = AOCS_R(1.0);
    c.cfg.rate_limit_radps = AOCS_R(0.0);
    c.cfg.jerk_time_s = AOCS_R(0.0);
    c.cfg.inertia_kgm2 = aocs_mat3_diag(aocs_vec3_make(AOCS_R(2059.5), AOCS_R(5954.2), AOCS_R(5974.3)));
    c.q0 = dq_to_real(dq_euler321_deg(14.0, 14.0, 14.0));
    c.qf = dq_to_real(dq_euler321_deg(30.0, -20.0, 1.0));
    c.env.u_max_norm_Nm = AOCS_R(0.0);
    c.env.wheels = NULL;
    for (int i = 0; i < 3; ++i) {
        c.env.u_max_axis_Nm = aocs_vec3_make((real_t)lim[i], (real_t)lim[i], (real_t)lim[i]);
        assert_int_equal(aocs_slew_plan(&s, &c.cfg, &c.env, c.q0, c.qf), AOCS_OK);
        /* theta_f = 39.31 deg; the gyroscopic allowance (slew.h) makes the m = 1 slew 4.3 % longer than
         * the bound 2 sqrt(theta_f / alpha), alpha = min_i u_i / (J_ii |e_i|) (SPEC 5.1) */
        assert_close(s.theta_f_rad, 39.31 * PI / 180.0, 1e-4);
        assert_true((double)s.t_end_s >= bound[i]);
        assert_true((double)s.t_end_s <= 1.05 * bound[i]);
    }
}

/* the wheel kind of envelope (slew.h env.wheels): an initialised array bounds the acceleration by its
   aocs_wheels_alpha_envelope (tested against its own reference in test_wheel_array.c) times the margin;
   an array that is not initialised is no envelope at all (the body limits alone) */
static void test_the_wheel_envelope_bounds_the_slew(void **state)
{
    (void)state;
    aocs_wheels_config_t wc;
    aocs_wheels_t wa;
    test_wheels_pyramid(&wc);
    wc.period_s = AOCS_R(0.1);
    assert_int_equal(aocs_wheels_init(&wa, &wc), AOCS_OK);
    test_rng_t r = {0x3a3aULL};
    slew_case_t c = random_case(&r, AOCS_SLEW_PROFILE_BANG_COAST_BANG, 0, 0);
    c.env.wheels = &wa;
    aocs_slew_t s;
    assert_int_equal(aocs_slew_plan(&s, &c.cfg, &c.env, c.q0, c.qf), AOCS_OK);
    double e[3];
    const double th = ref_axis_angle(c.q0, c.qf, e);
    const aocs_vec3_t ev = aocs_vec3_make((real_t)e[0], (real_t)e[1], (real_t)e[2]);
    const aocs_vec3_t a = aocs_mat3_mul_vec(c.cfg.inertia_kgm2, ev);
    const aocs_vec3_t b = aocs_vec3_scale(aocs_vec3_cross(ev, a), (real_t)th);
    const double alpha_w = (double)c.cfg.margin * (double)aocs_wheels_alpha_envelope(&wa, a, b);
    assert_true(alpha_w > 0.0);
    assert_close(s.accel_radps2, alpha_w, 1e-4 * alpha_w);
    /* the same array not initialised, with body axis limits: those alone, as with no array */
    c = random_case(&r, AOCS_SLEW_PROFILE_BANG_COAST_BANG, 0, 1);
    aocs_slew_t s_none;
    c.env.wheels = NULL;
    assert_int_equal(aocs_slew_plan(&s_none, &c.cfg, &c.env, c.q0, c.qf), AOCS_OK);
    wa.initialised = 0;
    c.env.wheels = &wa;
    assert_int_equal(aocs_slew_plan(&s, &c.cfg, &c.env, c.q0, c.qf), AOCS_OK);
    assert_close(s.accel_radps2, s_none.accel_radps2, 0.0);
    assert_close(s.t_end_s, s_none.t_end_s, 0.0);
}

static double torque_ratio(const slew_case_t *c, const aocs_slew_ref_t *ref)
{
    /* u = J wd_dot + wd x J wd in double, its largest use of the envelope */
    double wd[3];
    double wdd[3];
    double jw[3];
    double jwd[3];
    double cr[3];
    double u[3];
    double worst = 0.0;
    dmat_t j;
    for (int i = 0; i < 3; ++i) {
        for (int k = 0; k < 3; ++k) {
            j.m[i][k] = (double)c->cfg.inertia_kgm2.m[i][k];
        }
    }
    dv_from_real(ref->wd_D, wd);
    dv_from_real(ref->wd_dot_D, wdd);
    dm_mul_vec(&j, wd, jw);
    dm_mul_vec(&j, wdd, jwd);
    dv_cross(wd, jw, cr);
    for (int i = 0; i < 3; ++i) {
        u[i] = jwd[i] + cr[i];
    }
    if ((double)c->env.u_max_axis_Nm.v[0] > 0.0) {
        for (int i = 0; i < 3; ++i) {
            double q = fabs(u[i]) / (double)c->env.u_max_axis_Nm.v[i];
            worst = (q > worst) ? q : worst;
        }
    }
    if ((double)c->env.u_max_norm_Nm > 0.0) {
        double q = sqrt(dv_dot(u, u)) / (double)c->env.u_max_norm_Nm;
        worst = (q > worst) ? q : worst;
    }
    return worst;
}

static void never_exceeds_envelope(void **state)
{
    (void)state;
    test_rng_t r = {0xabcdef12ULL};
    for (int n = 0; n < 60; ++n) {
        slew_case_t c = random_case(&r, (aocs_slew_profile_t)(n % 2), (n / 2) % 2, 1 + (n % 3));
        aocs_slew_t s;
        aocs_slew_ref_t ref;
        double worst = 0.0;
        assert_int_equal(aocs_slew_plan(&s, &c.cfg, &c.env, c.q0, c.qf), AOCS_OK);
        for (int k = 0; k <= 4000; ++k) {
            eval_at(&s, (double)s.t_end_s * (double)k / 4000.0, &ref);
            double q = torque_ratio(&c, &ref);
            worst = (q > worst) ? q : worst;
        }
        assert_true(worst <= (double)c.cfg.margin * (1.0 + 1e-5));
        if ((c.cfg.profile == AOCS_SLEW_PROFILE_BANG_COAST_BANG) && (c.cfg.rate_limit_radps < AOCS_R(1e-12))) {
            /* bang-bang reaches the vertex a + b just before the midpoint: the bound is tight */
            assert_true(worst >= 0.99 * (double)c.cfg.margin);
        } else {
            assert_true(worst > 0.0);
        }
    }
}

static void sign_invariance(void **state)
{
    (void)state;
    test_rng_t r = {0x77ULL};
    for (int n = 0; n < 20; ++n) {
        slew_case_t c = random_case(&r, (aocs_slew_profile_t)(n % 2), n % 2, 1);
        aocs_slew_t s[4];
        const aocs_quat_t q0[2] = {c.q0, aocs_quat_make(-c.q0.q[0], -c.q0.q[1], -c.q0.q[2], -c.q0.q[3])};
        const aocs_quat_t qf[2] = {c.qf, aocs_quat_make(-c.qf.q[0], -c.qf.q[1], -c.qf.q[2], -c.qf.q[3])};
        for (int k = 0; k < 4; ++k) {
            assert_int_equal(aocs_slew_plan(&s[k], &c.cfg, &c.env, q0[k / 2], qf[k % 2]), AOCS_OK);
            assert_close(s[k].t_end_s, s[0].t_end_s, TOL_TIGHT);
        }
        for (int m = 0; m < 20; ++m) {
            double t = test_rng_uniform(&r, 0.0, (double)s[0].t_end_s);
            aocs_slew_ref_t a;
            aocs_slew_ref_t b;
            eval_at(&s[0], t, &a);
            for (int k = 1; k < 4; ++k) {
                double dot = 0.0;
                eval_at(&s[k], t, &b);
                for (int i = 0; i < 4; ++i) {
                    dot += (double)a.qd_DN.q[i] * (double)b.qd_DN.q[i];
                }
                assert_true(fabs(fabs(dot) - 1.0) <= TOL_ATT * 10.0);
                assert_vec3_close(b.wd_D, a.wd_D, TOL_TIGHT);
                assert_vec3_close(b.wd_dot_D, a.wd_dot_D, TOL_TIGHT);
            }
        }
    }
}

static void invalid_configs(void **state)
{
    (void)state;
    test_rng_t r = {0x99ULL};
    slew_case_t good = random_case(&r, AOCS_SLEW_PROFILE_JERK_LIMITED, 1, 1);
    slew_case_t c;
    aocs_slew_t s;
    const real_t nan = (real_t)NAN;
    assert_int_equal(aocs_slew_config_check(&good.cfg), AOCS_OK);
    assert_int_equal(aocs_slew_config_check(NULL), AOCS_ERR_NULL_ARG);
    c = good; c.cfg.profile = AOCS_SLEW_PROFILE_COUNT;
    assert_int_equal(aocs_slew_config_check(&c.cfg), AOCS_ERR_GUIDANCE_PROFILE_INVALID);
    c = good; c.cfg.margin = AOCS_R(0.0);
    assert_int_equal(aocs_slew_config_check(&c.cfg), AOCS_ERR_GUIDANCE_MARGIN_INVALID);
    c = good; c.cfg.margin = AOCS_R(1.01);
    assert_int_equal(aocs_slew_config_check(&c.cfg), AOCS_ERR_GUIDANCE_MARGIN_INVALID);
    c = good; c.cfg.margin = nan;
    assert_int_equal(aocs_slew_config_check(&c.cfg), AOCS_ERR_GUIDANCE_MARGIN_INVALID);
    c = good; c.cfg.rate_limit_radps = AOCS_R(-1e-3);
    assert_int_equal(aocs_slew_config_check(&c.cfg), AOCS_ERR_GUIDANCE_RATE_LIMIT_INVALID);
    c = good; c.cfg.rate_limit_radps = nan;
    assert_int_equal(aocs_slew_config_check(&c.cfg), AOCS_ERR_GUIDANCE_RATE_LIMIT_INVALID);
    c = good; c.cfg.jerk_time_s = AOCS_R(0.0);
    assert_int_equal(aocs_slew_config_check(&c.cfg), AOCS_ERR_GUIDANCE_JERK_TIME_INVALID);
    c = good; c.cfg.jerk_time_s = AOCS_R(-1.0);
    assert_int_equal(aocs_slew_config_check(&c.cfg), AOCS_ERR_GUIDANCE_JERK_TIME_INVALID);
    c = good; c.cfg.jerk_time_s = AOCS_R(2000.0);
    assert_int_equal(aocs_slew_config_check(&c.cfg), AOCS_ERR_GUIDANCE_JERK_TIME_INVALID);
    c = good; c.cfg.profile = AOCS_SLEW_PROFILE_BANG_COAST_BANG; /* jerk time > 0 with bang-coast-bang */
    assert_int_equal(aocs_slew_config_check(&c.cfg), AOCS_ERR_GUIDANCE_JERK_TIME_INVALID);
    c = good; c.cfg.inertia_kgm2.m[0][1] = AOCS_R(7.0);
    assert_int_equal(aocs_slew_config_check(&c.cfg), AOCS_ERR_INERTIA_NOT_SYMMETRIC);
    c = good; c.cfg.inertia_kgm2 = aocs_mat3_zero();
    assert_true(aocs_slew_config_check(&c.cfg) != AOCS_OK);
    /* plan: no envelope, bad quaternions, NULL */
    c = good; c.env.u_max_axis_Nm = aocs_vec3_zero();
    assert_int_equal(aocs_slew_plan(&s, &c.cfg, &c.env, c.q0, c.qf), AOCS_ERR_GUIDANCE_ENVELOPE_INVALID);
    assert_true(same((double)s.t_end_s, 0.0)); /* a zero-length slew at the target */
    c = good;
    assert_int_equal(aocs_slew_plan(&s, &c.cfg, &c.env, aocs_quat_make(AOCS_R(2.0), 0, 0, 0), c.qf),
                     AOCS_ERR_QUAT_NOT_UNIT);
    assert_int_equal(aocs_slew_plan(NULL, &c.cfg, &c.env, c.q0, c.qf), AOCS_ERR_NULL_ARG);
    /* NaN in the envelope functions gives 0, never NaN */
    assert_true(same((double)aocs_slew_alpha_box(aocs_vec3_make(nan, AOCS_R(1.0), AOCS_R(1.0)),
                                                 aocs_vec3_make(1, 1, 1), aocs_vec3_zero()),
                     0.0));
    assert_true(same((double)(aocs_slew_alpha_norm(AOCS_R(1.0), aocs_vec3_make(nan, 1, 1), aocs_vec3_zero())), (double)(AOCS_R(0.0))));
}

static void zero_and_half_turn(void **state)
{
    (void)state;
    test_rng_t r = {0x1234ULL};
    slew_case_t c = random_case(&r, AOCS_SLEW_PROFILE_BANG_COAST_BANG, 0, 1);
    aocs_slew_t s;
    aocs_slew_ref_t ref;
    /* no rotation: a zero-length slew, the target at once */
    assert_int_equal(aocs_slew_plan(&s, &c.cfg, &c.env, c.q0, c.q0), AOCS_OK);
    assert_true(same((double)(s.t_end_s), (double)(AOCS_R(0.0))));
    /* its eigenaxis is still a unit vector (the fault management's replan reads the envelope along it) */
    assert_close(aocs_vec3_norm(s.e), 1.0, TOL_TIGHT);
    aocs_slew_eval(&s, AOCS_R(0.0), &ref);
    assert_true(same((double)(ref.qd_DN.q[3]), (double)(c.q0.q[3])));
    /* 180 deg about z: dq4 = 0, a finite profile */
    assert_int_equal(aocs_slew_plan(&s, &c.cfg, &c.env, aocs_quat_identity(), aocs_quat_make(0, 0, 1, 0)), AOCS_OK);
    assert_close(s.theta_f_rad, PI, TOL_TIGHT);
    assert_true(AOCS_IS_FINITE(s.t_end_s) && (s.t_end_s > AOCS_R(0.0)));
    /* NaN time: the start */
    aocs_slew_eval(&s, (real_t)NAN, &ref);
    assert_true(same((double)(ref.theta_rad), (double)(AOCS_R(0.0))));
}

static void feedforward_formula(void **state)
{
    (void)state;
    aocs_mat3_t j = aocs_mat3_diag(aocs_vec3_make(AOCS_R(2.0), AOCS_R(3.0), AOCS_R(5.0)));
    aocs_vec3_t wd = aocs_vec3_make(AOCS_R(0.1), AOCS_R(-0.2), AOCS_R(0.3));
    aocs_vec3_t wdd = aocs_vec3_make(AOCS_R(0.01), AOCS_R(0.02), AOCS_R(-0.03));
    aocs_vec3_t h = aocs_vec3_make(AOCS_R(1.0), AOCS_R(0.0), AOCS_R(-1.0));
    aocs_vec3_t u = aocs_slew_feedforward(j, wd, wdd, h);
    /* by hand: J wdd = (0.02, 0.06, -0.15); J wd + h = (1.2, -0.6, 0.5);
     * wd x (J wd + h) = (-0.2*0.5 - 0.3*-0.6, 0.3*1.2 - 0.1*0.5, 0.1*-0.6 - (-0.2)*1.2) = (0.08, 0.31, 0.18) */
    assert_vec3_close(u, aocs_vec3_make(AOCS_R(0.10), AOCS_R(0.37), AOCS_R(0.03)), TOL_TIGHT);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(profile_matches_independent_model),
        cmocka_unit_test(irassi_bound),
        cmocka_unit_test(test_the_wheel_envelope_bounds_the_slew),
        cmocka_unit_test(never_exceeds_envelope),
        cmocka_unit_test(sign_invariance),
        cmocka_unit_test(invalid_configs),
        cmocka_unit_test(zero_and_half_turn),
        cmocka_unit_test(feedforward_formula),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
