/*
 * orbit_lqr (SPEC 2.8): F = -K x with x = [du dv dw dx dy dz] against an
 * evaluation here, the physical sign (an offset is pushed back), a closed
 * loop on the Clohessy-Wiltshire model in Bryson's form (Landsat 8 data),
 * config and input validation.
 */
#include "law_test_support.h"

#include "aocs/control/orbit_lqr.h"

#if defined(AOCS_REAL_IS_FLOAT)
#define LAW_REL_TOL 2.0e-6 /* six products and sums in float */
#else
#define LAW_REL_TOL 1.0e-14
#endif

static aocs_orbit_input_t make_orbit_input(aocs_vec3_t vel, aocs_vec3_t pos)
{
    aocs_orbit_input_t in;
    in.vel_mps = vel;
    in.pos_m = pos;
    in.dt_s = AOCS_R(0.1);
    return in;
}

/* one step on in returns expected and overwrites a nonzero force with an exact zero */
static void assert_orbit_rejects(aocs_orbit_lqr_t *law, const aocs_orbit_input_t *in, aocs_status_t expected)
{
    aocs_vec3_t f = aocs_vec3_make(AOCS_R(7.0), AOCS_R(7.0), AOCS_R(7.0));
    assert_int_equal(aocs_orbit_lqr_step(law, in, &f), expected);
    assert_vec3_is_zero(f);
}

/* decoupled PD-like gain: kv on the velocity block, kp on the position block */
static aocs_orbit_lqr_config_t pd_config(double kv, double kp)
{
    aocs_orbit_lqr_config_t cfg;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 6; ++j) {
            cfg.k[i][j] = AOCS_R(0.0);
        }
        cfg.k[i][i] = (real_t)kv;
        cfg.k[i][3 + i] = (real_t)kp;
    }
    return cfg;
}

/* a full (coupled) random gain with a positive velocity diagonal */
static aocs_orbit_lqr_config_t coupled_config(test_rng_t *rng)
{
    aocs_orbit_lqr_config_t cfg;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 6; ++j) {
            cfg.k[i][j] = (real_t)test_rng_uniform(rng, -5.0, 5.0);
        }
        cfg.k[i][i] = (real_t)test_rng_uniform(rng, 10.0, 100.0);
    }
    return cfg;
}

static void test_force_matches_formula_random(void **state)
{
    (void)state;
    test_rng_t rng = {0xabcdefu};
    aocs_orbit_lqr_t law;
    const aocs_orbit_lqr_config_t cfg = coupled_config(&rng);
    assert_int_equal(aocs_orbit_lqr_init(&law, &cfg), AOCS_OK);
    for (int k = 0; k < 2000; ++k) {
        aocs_orbit_input_t in = make_orbit_input(test_random_vec3(&rng, 0.1), test_random_vec3(&rng, 500.0));
        double x[6];
        for (int i = 0; i < 3; ++i) {
            x[i] = (double)in.vel_mps.v[i];
            x[3 + i] = (double)in.pos_m.v[i];
        }
        aocs_vec3_t f;
        assert_int_equal(aocs_orbit_lqr_step(&law, &in, &f), AOCS_OK);
        assert_gain_product(cfg.k, x, -1.0, f, LAW_REL_TOL, 0.0, 0.0); /* F = -K x */
    }
}

static void test_sign_pushes_back(void **state)
{
    (void)state;
    aocs_orbit_lqr_t law;
    aocs_orbit_lqr_config_t cfg = pd_config(50.0, 0.5);
    assert_int_equal(aocs_orbit_lqr_init(&law, &cfg), AOCS_OK);
    aocs_vec3_t f;
    /* +10 m along-track offset: force -0.5 * 10 = -5 N along x only */
    aocs_orbit_input_t in = make_orbit_input(aocs_vec3_zero(), aocs_vec3_make(AOCS_R(10.0), AOCS_R(0.0), AOCS_R(0.0)));
    assert_int_equal(aocs_orbit_lqr_step(&law, &in, &f), AOCS_OK);
    assert_close(f.v[0], -5.0, TOL_TIGHT);
    assert_true(fabs((double)f.v[1]) <= 0.0 && fabs((double)f.v[2]) <= 0.0);
    /* velocity goes first in the state: +0.1 m/s in w (radial) gives -5 N in z */
    in = make_orbit_input(aocs_vec3_make(AOCS_R(0.0), AOCS_R(0.0), AOCS_R(0.1)), aocs_vec3_zero());
    assert_int_equal(aocs_orbit_lqr_step(&law, &in, &f), AOCS_OK);
    assert_close(f.v[2], -5.0, TOL_TIGHT);
    assert_true(fabs((double)f.v[0]) <= 0.0);
}

/* SPEC 2.8 Bryson/CW model: xdot = A x + B F */
static void cw_deriv(const double x[6], const double f[3], double n, double m, double d[6])
{
    const double du = x[0], dv = x[1], dw = x[2], dx = x[3], dy = x[4], dz = x[5];
    d[0] = n * dw - n * n * dx + f[0] / m;
    d[1] = -n * n * dy + f[1] / m;
    d[2] = -n * du + 2.0 * n * n * dz + f[2] / m;
    d[3] = du + n * dz;
    d[4] = dv;
    d[5] = dw - n * dx;
}

static void test_closed_loop_cw_landsat(void **state)
{
    (void)state;
    const double mu = 3.986004418e14;
    const double r = 7080.0e3;
    const double n = sqrt(mu / (r * r * r));
    const double m = 2623.0;
    aocs_orbit_lqr_t law;
    /* wn = sqrt(kp/m) ~ 0.02 rad/s >> n, damping ~ 1 */
    aocs_orbit_lqr_config_t cfg = pd_config(100.0, 1.0);
    assert_int_equal(aocs_orbit_lqr_init(&law, &cfg), AOCS_OK);
    double x[6] = {1.0, -1.0, -6.0, 50.0, -100.0, 350.0}; /* landsat8_* x0 */
    double x0n = 0.0;
    for (int i = 0; i < 6; ++i) {
        x0n += x[i] * x[i];
    }
    x0n = sqrt(x0n);
    const double dt = 0.1;
    for (int k = 0; k < 30000; ++k) { /* 3000 s at 10 Hz, force held over dt (RK4) */
        aocs_orbit_input_t in = make_orbit_input(aocs_vec3_make((real_t)x[0], (real_t)x[1], (real_t)x[2]),
                                           aocs_vec3_make((real_t)x[3], (real_t)x[4], (real_t)x[5]));
        aocs_vec3_t f;
        assert_int_equal(aocs_orbit_lqr_step(&law, &in, &f), AOCS_OK);
        double fd[3] = {(double)f.v[0], (double)f.v[1], (double)f.v[2]};
        double k1[6], k2[6], k3[6], k4[6], t[6];
        cw_deriv(x, fd, n, m, k1);
        for (int i = 0; i < 6; ++i) t[i] = x[i] + 0.5 * dt * k1[i];
        cw_deriv(t, fd, n, m, k2);
        for (int i = 0; i < 6; ++i) t[i] = x[i] + 0.5 * dt * k2[i];
        cw_deriv(t, fd, n, m, k3);
        for (int i = 0; i < 6; ++i) t[i] = x[i] + dt * k3[i];
        cw_deriv(t, fd, n, m, k4);
        for (int i = 0; i < 6; ++i) {
            x[i] += dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
    }
    double xn = 0.0;
    for (int i = 0; i < 6; ++i) {
        xn += x[i] * x[i];
    }
    xn = sqrt(xn);
    print_message("orbit_lqr CW closed loop: |x(0)| = %.4g, |x(3000 s)| = %.4g\n", x0n, xn);
    /* the SPEC settle criterion: positions < 0.1 m, velocities < 0.01 m/s */
    for (int i = 0; i < 3; ++i) {
        assert_true(fabs(x[i]) < 0.01);
        assert_true(fabs(x[3 + i]) < 0.1);
    }
}

static void test_config_validation(void **state)
{
    (void)state;
    aocs_orbit_lqr_t law;
    aocs_orbit_lqr_config_t good = pd_config(10.0, 1.0);
    aocs_orbit_lqr_config_t cfg;
    assert_int_equal(aocs_orbit_lqr_init(NULL, &good), AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_orbit_lqr_init(&law, NULL), AOCS_ERR_NULL_ARG);
    cfg = good;
    cfg.k[2][4] = (real_t)NAN;
    assert_int_equal(aocs_orbit_lqr_init(&law, &cfg), AOCS_ERR_PARAM_NOT_FINITE);
    cfg = good;
    cfg.k[0][0] = (real_t)-INFINITY;
    assert_int_equal(aocs_orbit_lqr_init(&law, &cfg), AOCS_ERR_PARAM_NOT_FINITE);
    cfg = good;
    cfg.k[1][1] = AOCS_R(0.0);
    assert_int_equal(aocs_orbit_lqr_init(&law, &cfg), AOCS_ERR_GAIN_TABLE_INVALID);
    cfg = good;
    cfg.k[2][2] = AOCS_R(-10.0);
    assert_int_equal(aocs_orbit_lqr_init(&law, &cfg), AOCS_ERR_GAIN_TABLE_INVALID);
    aocs_orbit_input_t in = make_orbit_input(aocs_vec3_zero(), aocs_vec3_make(AOCS_R(1.0), AOCS_R(0.0), AOCS_R(0.0)));
    assert_orbit_rejects(&law, &in, AOCS_ERR_NOT_INITIALISED);
    /* never initialised: a zeroed and a garbage struct refuse to step */
    memset(&law, 0, sizeof law);
    assert_orbit_rejects(&law, &in, AOCS_ERR_NOT_INITIALISED);
    memset(&law, 0xA5, sizeof law);
    assert_orbit_rejects(&law, &in, AOCS_ERR_NOT_INITIALISED);
}

static void test_invalid_inputs_zero_output(void **state)
{
    (void)state;
    aocs_orbit_lqr_t law;
    aocs_orbit_lqr_config_t cfg = pd_config(10.0, 1.0);
    assert_int_equal(aocs_orbit_lqr_init(&law, &cfg), AOCS_OK);
    aocs_orbit_input_t good = make_orbit_input(aocs_vec3_zero(), aocs_vec3_make(AOCS_R(1.0), AOCS_R(0.0), AOCS_R(0.0)));
    aocs_orbit_input_t in;
    aocs_vec3_t f;
    /* NaN / +Inf / -Inf in every field (dt: AOCS_ERR_DT_INVALID) */
    const real_t bad_values[3] = {(real_t)NAN, (real_t)INFINITY, (real_t)-INFINITY};
    for (int k = 0; k < N_ORBIT_INPUT_FIELDS; ++k) {
        for (int b = 0; b < 3; ++b) {
            in = good;
            *orbit_input_field(&in, k) = bad_values[b];
            assert_orbit_rejects(&law, &in, (k == N_ORBIT_INPUT_FIELDS - 1) ? AOCS_ERR_DT_INVALID : AOCS_ERR_INPUT_NOT_FINITE);
        }
    }
    in = good;
    in.dt_s = AOCS_R(-0.1);
    assert_orbit_rejects(&law, &in, AOCS_ERR_DT_INVALID);
    in.dt_s = AOCS_R(0.0);
    assert_orbit_rejects(&law, &in, AOCS_ERR_DT_INVALID);
    in = good;
    in.vel_mps.v[1] = AOCS_REAL_MAX; /* finite, but 10 * REAL_MAX overflows */
    assert_orbit_rejects(&law, &in, AOCS_ERR_OUTPUT_NOT_FINITE);
    assert_orbit_rejects(&law, NULL, AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_orbit_lqr_step(NULL, &good, &f), AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_orbit_lqr_step(&law, &good, NULL), AOCS_ERR_NULL_ARG);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_force_matches_formula_random),
        cmocka_unit_test(test_sign_pushes_back),
        cmocka_unit_test(test_closed_loop_cw_landsat),
        cmocka_unit_test(test_config_validation),
        cmocka_unit_test(test_invalid_inputs_zero_output),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
