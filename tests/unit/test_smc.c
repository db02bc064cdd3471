/*
 * smc (SPEC 2.4, Crassidis-Vadali-Markley 2000):
 *   s = we + Lambda sign(qe4) qe_vec,
 *   u = J (-Lambda sign(qe4) d/dt(qe_vec) + wd_dot) + w x (J w) - J G sat(s, eps).
 * Proves: the torque equals the SPEC formula evaluated independently in
 * double (own Shuster product, own cross products) outside the layer
 * (IRASSI data), inside the layer (full symmetric inertia, per-axis gains,
 * precondition asserted), with qe4 < 0, plus two states worked by hand; a
 * positive error about +x with zero rate gives u_x < 0; q and -q (and qd,
 * -qd) give the same torque; along closed-loop RK4 runs (IRASSI inertia and
 * the full gao_mrp inertia) V = 0.5 s^T s decreases with
 * Vdot = -sum G_i s_i sat(s_i) (outside the layer -sum G_i |s_i|); every
 * invalid config (inertia codes, gains, boundary layer), every non-finite
 * input field, a non-unit quaternion, a bad dt, an overflowing torque and a
 * step before init are rejected with their own status and a zero torque.
 */
#include "law_test_support.h"
#include "aocs/control/smc.h"

/* ---- law-specific reference ---- */
/* gao_mrp inertia (SPEC 4) */
static const dmat_t J_GAO = {{{42.0, 1.8, -1.5}, {1.8, 25.0, -1.2}, {-1.5, -1.2, 61.8}}};

typedef struct {
    dmat_t j;
    double lambda[3];
    double g[3];
    double eps[3];
} smc_ref_cfg_t;

static const smc_ref_cfg_t CFG_IRASSI = {{{{2059.5, 0.0, 0.0}, {0.0, 5954.2, 0.0}, {0.0, 0.0, 5974.3}}},
                                         {1.0, 1.0, 1.0},
                                         {0.05, 0.05, 0.05},
                                         {0.02, 0.02, 0.02}};
static const smc_ref_cfg_t CFG_GAO = {{{{42.0, 1.8, -1.5}, {1.8, 25.0, -1.2}, {-1.5, -1.2, 61.8}}},
                                      {1.0, 0.5, 2.0},
                                      {0.05, 0.1, 0.02},
                                      {0.02, 0.05, 0.03}};

static aocs_smc_config_t to_config(const smc_ref_cfg_t *r)
{
    aocs_smc_config_t c;
    for (int i = 0; i < 3; ++i) {
        for (int k = 0; k < 3; ++k) {
            c.inertia.m[i][k] = (real_t)r->j.m[i][k];
        }
    }
    c.lambda = dv_to_real(r->lambda);
    c.g = dv_to_real(r->g);
    c.eps = dv_to_real(r->eps);
    return c;
}

/* reference config as the firmware sees it (rounded to real_t) */
static smc_ref_cfg_t seen_by_firmware(const smc_ref_cfg_t *r)
{
    aocs_smc_config_t c = to_config(r);
    smc_ref_cfg_t out;
    for (int i = 0; i < 3; ++i) {
        for (int k = 0; k < 3; ++k) {
            out.j.m[i][k] = (double)c.inertia.m[i][k];
        }
    }
    dv_from_real(c.lambda, out.lambda);
    dv_from_real(c.g, out.g);
    dv_from_real(c.eps, out.eps);
    return out;
}

static double ref_sat(double s, double eps)
{
    double r;
    if (fabs(s) <= eps) {
        r = s / eps;
    } else {
        r = (s > 0.0) ? 1.0 : -1.0;
    }
    return r;
}

/* surface s = we + Lambda sign(qe4) qe_vec */
static void ref_surface(const smc_ref_cfg_t *c, dq_t qe, const double we[3], double s[3])
{
    double sgn = (qe.q[3] >= 0.0) ? 1.0 : -1.0;
    for (int i = 0; i < 3; ++i) {
        s[i] = we[i] + c->lambda[i] * sgn * qe.q[i];
    }
}

/* SPEC 2.4 in double on the values the firmware sees; returns the term scale, s out */
static double smc_expected(const aocs_smc_config_t *cfg, const aocs_att_input_t *in, double u[3], double s[3])
{
    smc_ref_cfg_t tmp;
    for (int i = 0; i < 3; ++i) {
        for (int k = 0; k < 3; ++k) {
            tmp.j.m[i][k] = (double)cfg->inertia.m[i][k];
        }
    }
    dv_from_real(cfg->lambda, tmp.lambda);
    dv_from_real(cfg->g, tmp.g);
    dv_from_real(cfg->eps, tmp.eps);
    const smc_ref_cfg_t *c = &tmp;

    dq_t qe = dq_mul(dq_from_real(in->q_BN), dq_inv(dq_from_real(in->qd_DN)));
    double sgn = (qe.q[3] >= 0.0) ? 1.0 : -1.0;
    double w[3];
    double wd[3];
    double wd_dot[3];
    dv_from_real(in->w_BN_B, w);
    dv_from_real(in->wd_B, wd);
    dv_from_real(in->wd_dot_B, wd_dot);
    double we[3] = {w[0] - wd[0], w[1] - wd[1], w[2] - wd[2]};
    ref_surface(c, qe, we, s);
    double qv[3] = {qe.q[0], qe.q[1], qe.q[2]};
    double qv_x_we[3];
    dv_cross(qv, we, qv_x_we);
    double a[3];
    for (int i = 0; i < 3; ++i) {
        double qdot_i = 0.5 * (qe.q[3] * we[i] + qv_x_we[i]);
        a[i] = -c->lambda[i] * sgn * qdot_i + wd_dot[i] - c->g[i] * ref_sat(s[i], c->eps[i]);
    }
    double ja[3];
    double h[3];
    double wxh[3];
    dm_mul_vec(&c->j, a, ja);
    dm_mul_vec(&c->j, w, h);
    dv_cross(w, h, wxh);
    double scale = 1.0;
    for (int i = 0; i < 3; ++i) {
        u[i] = ja[i] + wxh[i];
        double t = fabs(w[(i + 1) % 3] * h[(i + 2) % 3]) + fabs(w[(i + 2) % 3] * h[(i + 1) % 3]);
        for (int k = 0; k < 3; ++k) {
            t += fabs(c->j.m[i][k] * a[k]);
        }
        scale = (t > scale) ? t : scale;
    }
    return scale;
}

static aocs_smc_t make_law(const smc_ref_cfg_t *r)
{
    aocs_smc_t law;
    aocs_smc_config_t cfg = to_config(r);
    memset(&law, 0, sizeof law);
    assert_int_equal(aocs_smc_init(&law, &cfg), AOCS_OK);
    return law;
}

static aocs_status_t smc_step(void *law, const aocs_att_input_t *in, aocs_vec3_t *u_out)
{
    return aocs_smc_step((aocs_smc_t *)law, in, u_out);
}

/* returns the surface of the state so callers can assert where it lies */
static void check_state(const smc_ref_cfg_t *r, aocs_att_input_t in, double s[3])
{
    aocs_smc_t law = make_law(r);
    aocs_smc_config_t cfg = to_config(r);
    aocs_vec3_t u = aocs_vec3_make(AOCS_R(123.0), AOCS_R(123.0), AOCS_R(123.0));
    double expected[3];
    double scale = smc_expected(&cfg, &in, expected, s);
    assert_int_equal(aocs_smc_step(&law, &in, &u), AOCS_OK);
    assert_vec3_close_scaled(u, expected, TOL_TIGHT, scale);
}

static void test_known_states(void **state)
{
    (void)state;
    double s[3];
    dq_t qd = dq_euler321_deg(30.0, -20.0, 1.0);
    /* IRASSI geometry, all three components outside the layer */
    const double w1[3] = {0.01, -0.02, 0.03};
    const double wd1[3] = {0.001, 0.0, -0.002};
    const double wdd1[3] = {1e-4, -2e-4, 0.0};
    check_state(&CFG_IRASSI, make_input(dq_euler321_deg(14.0, 14.0, 14.0), w1, qd, wd1, wdd1, 0.1), s);
    for (int i = 0; i < 3; ++i) {
        assert_true(fabs(s[i]) > CFG_IRASSI.eps[i]);
    }

    /* inside the layer on every axis: 0.4 deg error, small rates, full inertia */
    dq_t q2 = dq_mul(dq_axis_angle(1.0, 2.0, -1.5, 0.4 * PI / 180.0), qd);
    const double w2[3] = {0.002, -0.001, 0.003};
    const double wd2[3] = {0.001, 0.0005, 0.0};
    const double wdd2[3] = {0.0, 1e-4, -1e-4};
    check_state(&CFG_GAO, make_input(q2, w2, qd, wd2, wdd2, 0.1), s);
    for (int i = 0; i < 3; ++i) {
        assert_true(fabs(s[i]) < CFG_GAO.eps[i]);
    }

    /* qe4 < 0 (250 deg) with rates: mixed inside / outside, full inertia */
    dq_t q3 = dq_mul(dq_axis_angle(1.0, -2.0, 0.5, 250.0 * PI / 180.0), qd);
    assert_true(dq_mul(q3, dq_inv(qd)).q[3] < -0.5);
    const double w3[3] = {0.3, -0.51, 0.2};
    check_state(&CFG_GAO, make_input(q3, w3, qd, ZERO3, ZERO3, 0.1), s);
}

static void test_by_hand(void **state)
{
    (void)state;
    /* J = diag(2 3 4), Lambda = I, G = 0.5 I, eps = 0.1; qe = [0.5 0 0 cos 30]
       (a) w = 0: s = [0.5 0 0], sat = [1 0 0], u = -J G sat = [-1 0 0]
       (b) w = [0.05 0 0]: qedot_x = 0.5 cos30 0.05 = 0.0216506351, w x Jw = 0,
           u_x = 2 (-0.0216506351 - 0.5) = -1.0433012702 */
    const smc_ref_cfg_t c = {{{{2.0, 0.0, 0.0}, {0.0, 3.0, 0.0}, {0.0, 0.0, 4.0}}},
                             {1.0, 1.0, 1.0},
                             {0.5, 0.5, 0.5},
                             {0.1, 0.1, 0.1}};
    aocs_smc_t law = make_law(&c);
    aocs_att_input_t in = make_input_60deg_about_x(0.0);
    aocs_vec3_t u;
    assert_int_equal(aocs_smc_step(&law, &in, &u), AOCS_OK);
    const double ua[3] = {-1.0, 0.0, 0.0};
    assert_vec3_close_scaled(u, ua, TOL_TIGHT, 1.0);
    in = make_input_60deg_about_x(0.05);
    assert_int_equal(aocs_smc_step(&law, &in, &u), AOCS_OK);
    const double ub[3] = {-1.0433012701892219, 0.0, 0.0};
    assert_vec3_close_scaled(u, ub, TOL_TIGHT, 1.1);
}

static void test_sign_convention(void **state)
{
    (void)state;
    aocs_smc_t law = make_law(&CFG_IRASSI);
    check_restoring_torque_about_x(smc_step, &law);
}

static void test_q_and_minus_q_same_torque(void **state)
{
    (void)state;
    aocs_smc_t law = make_law(&CFG_GAO);
    const sign_sweep_t sweep = {.w_scale = 0.1, .wd_scale = 0.01, .wd_dot_scale = 0.001, .tol = TOL_TIGHT * 100.0};
    assert_int_equal(check_q_sign_invariance(smc_step, &law, &sweep), 200);
}

/* ---- Lyapunov ---- */
typedef struct {
    aocs_smc_t law;
    smc_ref_cfg_t ref; /* as seen by the firmware */
    dq_t qd;
    int outside; /* steps with every |s_i| > eps_i */
} smc_ctx_t;

static aocs_status_t smc_torque(void *vctx, dq_t q, const double w[3], double u[3])
{
    smc_ctx_t *c = (smc_ctx_t *)vctx;
    return law_torque(smc_step, &c->law, q, w, c->qd, u);
}

/* SPEC 2.4: closed loop sdot_i = -G_i sat(s_i), so V = 0.5 s^T s, Vdot = -sum G_i s_i sat(s_i) */
static void smc_lyap(void *vctx, dq_t q, const double w[3], double *v, double *vdot)
{
    smc_ctx_t *c = (smc_ctx_t *)vctx;
    dq_t qe = dq_mul(q, dq_inv(c->qd));
    double s[3];
    ref_surface(&c->ref, qe, w, s);
    *v = 0.5 * dv_dot(s, s);
    *vdot = 0.0;
    int out = 1;
    for (int i = 0; i < 3; ++i) {
        *vdot -= c->ref.g[i] * s[i] * ref_sat(s[i], c->ref.eps[i]);
        out = out && (fabs(s[i]) > c->ref.eps[i]);
    }
    c->outside += out;
}

static void test_lyapunov(void **state)
{
    (void)state;
    static smc_ctx_t ctx;
    plant_t plant;
    const double w0[3] = {0.01, -0.02, 0.015};

    /* IRASSI large slew, 3 s: starts outside the layer on every axis */
    plant_init(&plant, &J_IRASSI);
    ctx.law = make_law(&CFG_IRASSI);
    ctx.ref = seen_by_firmware(&CFG_IRASSI);
    ctx.qd = dq_euler321_deg(30.0, -20.0, 1.0);
    ctx.outside = 0;
    double ratio = check_lyapunov(&plant, smc_torque, smc_lyap, &ctx, dq_euler321_deg(14.0, 14.0, 14.0), w0, 0.01,
                                  300, 2e-3);
    assert_true(ratio < 0.7);
    assert_true(ctx.outside > 100);

    /* full inertia, 40 deg error with rates, 8 s: crosses into the layer; stops while
       V / V0 > 1e-6 so float rounding of qe (~6e-8) stays well below |s| */
    plant_init(&plant, &J_GAO);
    ctx.law = make_law(&CFG_GAO);
    ctx.ref = seen_by_firmware(&CFG_GAO);
    ctx.qd = dq_euler321_deg(-10.0, 5.0, 20.0);
    ctx.outside = 0;
    dq_t q0 = dq_mul(dq_axis_angle(0.3, 1.0, -0.2, 40.0 * PI / 180.0), ctx.qd);
    const double w1[3] = {0.05, -0.02, 0.03};
    ratio = check_lyapunov(&plant, smc_torque, smc_lyap, &ctx, q0, w1, 0.01, 800, 2e-3);
    assert_true(ratio < 0.01);
    assert_true(ctx.outside > 10);
}

/* ---- rejection paths (law_test_support.h) ---- */
static void expect_init_fails(aocs_smc_config_t cfg, aocs_status_t expected)
{
    aocs_smc_t law = make_law(&CFG_GAO);
    assert_int_equal(aocs_smc_init(&law, &cfg), expected);
    /* a failed init leaves the law unusable even after a good one */
    assert_step_not_initialised(smc_step, &law);
}

static void test_invalid_config(void **state)
{
    (void)state;
    const double bad_nf[3] = {NAN, INFINITY, -INFINITY};
    const double bad_np[3] = {0.0, -0.0, -0.5};
    for (int i = 0; i < 3; ++i) {
        for (int b = 0; b < 3; ++b) {
            aocs_smc_config_t cfg = to_config(&CFG_GAO);
            cfg.lambda.v[i] = (real_t)bad_nf[b];
            expect_init_fails(cfg, AOCS_ERR_PARAM_NOT_FINITE);
            cfg = to_config(&CFG_GAO);
            cfg.g.v[i] = (real_t)bad_nf[b];
            expect_init_fails(cfg, AOCS_ERR_PARAM_NOT_FINITE);
            cfg = to_config(&CFG_GAO);
            cfg.eps.v[i] = (real_t)bad_nf[b];
            expect_init_fails(cfg, AOCS_ERR_PARAM_NOT_FINITE);
            cfg = to_config(&CFG_GAO);
            cfg.inertia.m[i][(i + b) % 3] = (real_t)bad_nf[b];
            expect_init_fails(cfg, AOCS_ERR_PARAM_NOT_FINITE);

            cfg = to_config(&CFG_GAO);
            cfg.lambda.v[i] = (real_t)bad_np[b];
            expect_init_fails(cfg, AOCS_ERR_GAIN_NOT_POSITIVE);
            cfg = to_config(&CFG_GAO);
            cfg.g.v[i] = (real_t)bad_np[b];
            expect_init_fails(cfg, AOCS_ERR_GAIN_NOT_POSITIVE);
            cfg = to_config(&CFG_GAO);
            cfg.eps.v[i] = (real_t)bad_np[b];
            expect_init_fails(cfg, AOCS_ERR_BOUNDARY_LAYER_NOT_POSITIVE);
        }
    }
    /* inertia codes come from aocs_mat3_check_inertia */
    aocs_smc_config_t cfg = to_config(&CFG_GAO);
    cfg.inertia.m[0][1] = AOCS_R(5.0); /* m[1][0] stays 1.8 */
    expect_init_fails(cfg, AOCS_ERR_INERTIA_NOT_SYMMETRIC);
    cfg = to_config(&CFG_GAO);
    cfg.inertia.m[1][1] = AOCS_R(-25.0);
    expect_init_fails(cfg, AOCS_ERR_INERTIA_NOT_POS_DEF);
    cfg = to_config(&CFG_GAO);
    cfg.inertia = aocs_mat3_zero();
    aocs_status_t zero_code = aocs_mat3_check_inertia(cfg.inertia);
    assert_int_not_equal(zero_code, AOCS_OK);
    expect_init_fails(cfg, zero_code);

    aocs_smc_t law;
    cfg = to_config(&CFG_GAO);
    assert_int_equal(aocs_smc_init(NULL, &cfg), AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_smc_init(&law, NULL), AOCS_ERR_NULL_ARG);
}

static void test_step_rejections(void **state)
{
    (void)state;
    aocs_smc_t law;
    check_step_before_init(smc_step, &law, sizeof law);
    law = make_law(&CFG_IRASSI);
    aocs_att_input_t good = law_test_input();
    check_step_rejections(smc_step, &law, &good);
    /* also finite rates whose gyroscopic term w x Jw overflows */
    aocs_att_input_t in = good;
    in.w_BN_B = aocs_vec3_make(AOCS_SQRT(AOCS_REAL_MAX), AOCS_SQRT(AOCS_REAL_MAX), AOCS_R(0.0));
    assert_step_rejects(smc_step, &law, &in, AOCS_ERR_OUTPUT_NOT_FINITE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_known_states),
        cmocka_unit_test(test_by_hand),
        cmocka_unit_test(test_sign_convention),
        cmocka_unit_test(test_q_and_minus_q_same_torque),
        cmocka_unit_test(test_lyapunov),
        cmocka_unit_test(test_invalid_config),
        cmocka_unit_test(test_step_rejections),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
