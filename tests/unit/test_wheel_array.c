/*
 * Reaction wheel array (wheel_array.h, docs/spec.md 5.3) against computations
 * written out here in double: the minimum-norm allocation by solving
 * (Gs Gs^T) x = u_c with Gaussian elimination (u_s = -Gs^T x), the uniform
 * scale, failed wheels, speed protection, the momentum, the SPEC 5.3 body
 * envelope of the reference pyramid and every configuration status code.
 */
#include <string.h>

#include "test_support.h"
#include "wheel_test_support.h"

#include "aocs/actuation/wheel_array.h"

#define PI_D 3.14159265358979323846
#define JS TEST_WHEEL_JS_KGM2
#define UMAX TEST_WHEEL_U_MAX_NM
#define WMAX TEST_WHEEL_OMEGA_MAX_RADPS

static void pyramid(aocs_wheels_config_t *cfg)
{
    test_wheels_pyramid(cfg);
    cfg->period_s = AOCS_R(0.1);
}

/* independent minimum-norm solution in double: u_s = -Gs^T (Gs Gs^T)^-1 u_c over the healthy wheels */
static void min_norm_d(const aocs_wheels_config_t *cfg, const double uc[3], double us[AOCS_WHEELS_MAX])
{
    double a[3][4];
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) {
            a[r][c] = 0.0;
            for (uint32_t i = 0u; i < cfg->n; ++i) {
                if ((cfg->failed_mask & (1u << i)) == 0u) {
                    a[r][c] += (double)cfg->axis_B[i].v[r] * (double)cfg->axis_B[i].v[c];
                }
            }
        }
        a[r][3] = uc[r];
    }
    for (int p = 0; p < 3; ++p) { /* elimination with partial pivoting */
        int best = p;
        for (int r = p + 1; r < 3; ++r) {
            if (fabs(a[r][p]) > fabs(a[best][p])) {
                best = r;
            }
        }
        for (int c = 0; c < 4; ++c) {
            double t = a[p][c];
            a[p][c] = a[best][c];
            a[best][c] = t;
        }
        for (int r = 0; r < 3; ++r) {
            if (r != p) {
                double f = a[r][p] / a[p][p];
                for (int c = 0; c < 4; ++c) {
                    a[r][c] -= f * a[p][c];
                }
            }
        }
    }
    double x[3] = {a[0][3] / a[0][0], a[1][3] / a[1][1], a[2][3] / a[2][2]};
    for (uint32_t i = 0u; i < AOCS_WHEELS_MAX; ++i) {
        us[i] = 0.0;
        if ((i < cfg->n) && ((cfg->failed_mask & (1u << i)) == 0u)) {
            us[i] = -((double)cfg->axis_B[i].v[0] * x[0] + (double)cfg->axis_B[i].v[1] * x[1] +
                      (double)cfg->axis_B[i].v[2] * x[2]);
        }
    }
}

static double rnd(uint32_t *s)
{
    *s = *s * 1664525u + 1013904223u;
    return ((double)(*s >> 8) / 16777216.0) * 2.0 - 1.0;
}

static const real_t ZERO_SPEEDS[AOCS_WHEELS_MAX] = {0};

static void check_allocation(uint32_t failed_mask)
{
    aocs_wheels_config_t cfg;
    aocs_wheels_t wa;
    pyramid(&cfg);
    cfg.failed_mask = failed_mask;
    assert_int_equal(aocs_wheels_init(&wa, &cfg), AOCS_OK);
    uint32_t seed = 12345u + failed_mask;
    for (int k = 0; k < 200; ++k) {
        /* small commands: no scaling */
        double uc[3] = {0.05 * rnd(&seed), 0.05 * rnd(&seed), 0.05 * rnd(&seed)};
        double us[AOCS_WHEELS_MAX];
        aocs_wheels_alloc_t al;
        min_norm_d(&cfg, uc, us);
        assert_int_equal(aocs_wheels_allocate(&wa, aocs_vec3_make((real_t)uc[0], (real_t)uc[1], (real_t)uc[2]),
                                              ZERO_SPEEDS, &al), AOCS_OK);
        assert_close(al.scale, 1.0, 0.0);
        for (uint32_t i = 0u; i < AOCS_WHEELS_MAX; ++i) {
            assert_close(al.u_s_nm[i], us[i], TOL_TIGHT);
        }
        /* the motors' reaction -Gs u_s is the command */
        for (int r = 0; r < 3; ++r) {
            assert_close(al.u_body_B_nm.v[r], uc[r], TOL_TIGHT);
        }
        if (failed_mask == 0u) {
            /* minimum norm: orthogonal to the pyramid's null space [1 -1 1 -1] */
            assert_close(us[0] - us[1] + us[2] - us[3], 0.0, 1e-15);
            assert_close(al.u_s_nm[0] - al.u_s_nm[1] + al.u_s_nm[2] - al.u_s_nm[3], 0.0, TOL_TIGHT);
        }
    }
}

static void test_minimum_norm_allocation_of_the_pyramid(void **state)
{
    (void)state;
    check_allocation(0u);
}

static void test_a_failed_wheel_is_removed_and_three_still_control_every_axis(void **state)
{
    (void)state;
    for (uint32_t f = 0u; f < 4u; ++f) {
        check_allocation(1u << f);
    }
}

static void test_the_uniform_scale_keeps_the_direction(void **state)
{
    (void)state;
    aocs_wheels_config_t cfg;
    aocs_wheels_t wa;
    aocs_wheels_alloc_t al;
    pyramid(&cfg);
    assert_int_equal(aocs_wheels_init(&wa, &cfg), AOCS_OK);
    uint32_t seed = 99u;
    for (int k = 0; k < 200; ++k) {
        double uc[3] = {3.0 * rnd(&seed), 3.0 * rnd(&seed), 3.0 * rnd(&seed)};
        double us[AOCS_WHEELS_MAX];
        min_norm_d(&cfg, uc, us);
        double amax = 0.0;
        for (int i = 0; i < 4; ++i) {
            amax = fmax(amax, fabs(us[i]));
        }
        double s = amax > UMAX ? UMAX / amax : 1.0;
        assert_int_equal(aocs_wheels_allocate(&wa, aocs_vec3_make((real_t)uc[0], (real_t)uc[1], (real_t)uc[2]),
                                              ZERO_SPEEDS, &al), AOCS_OK);
        assert_close(al.scale, s, TOL_TIGHT);
        double got_max = 0.0;
        for (int i = 0; i < 4; ++i) {
            assert_close(al.u_s_nm[i], s * us[i], TOL_TIGHT);
            got_max = fmax(got_max, fabs((double)al.u_s_nm[i]));
        }
        assert_true(got_max <= UMAX * (1.0 + 4.0 * (double)AOCS_REAL_EPS));
        for (int r = 0; r < 3; ++r) {
            assert_close(al.u_body_B_nm.v[r], s * uc[r], TOL_TIGHT);
        }
        if (s < 1.0) {
            assert_true(al.torque_limited_mask != 0u && al.speed_limited_mask == 0u);
        }
    }
}

static void test_no_torque_drives_a_wheel_beyond_its_speed_limit(void **state)
{
    (void)state;
    aocs_wheels_config_t cfg;
    aocs_wheels_t wa;
    aocs_wheels_alloc_t al;
    pyramid(&cfg);
    assert_int_equal(aocs_wheels_init(&wa, &cfg), AOCS_OK);
    /* a body torque along -g0 asks wheel 0 to speed up in +: u_s = -Gs^+ u_c */
    aocs_vec3_t uc = aocs_vec3_scale(cfg.axis_B[0], AOCS_R(-0.2));
    real_t om[AOCS_WHEELS_MAX] = {AOCS_R(599.9), 0, 0, 0, 0, 0};
    double us[AOCS_WHEELS_MAX];
    double ucd[3] = {(double)uc.v[0], (double)uc.v[1], (double)uc.v[2]};
    min_norm_d(&cfg, ucd, us);
    assert_true(us[0] > 0.1); /* 0.15 N m: more than the headroom below, within u_s,max */
    /* headroom Js (600 - 599.9) / 0.1 = 0.08 N m */
    double head = JS * (WMAX - (double)om[0]) / 0.1;
    assert_int_equal(aocs_wheels_allocate(&wa, uc, om, &al), AOCS_OK);
    assert_close(al.u_s_nm[0], head, TOL_LOOSE);
    assert_close(al.scale, head / us[0], TOL_LOOSE);
    assert_true(al.speed_limited_mask == 1u);
    /* Omega + u T / Js stays within the limit */
    assert_true((double)om[0] + (double)al.u_s_nm[0] * 0.1 / JS <= WMAX * (1.0 + 1e-6));
    /* at the limit: nothing more in that direction ... */
    om[0] = AOCS_R(WMAX);
    assert_int_equal(aocs_wheels_allocate(&wa, uc, om, &al), AOCS_OK);
    assert_close(al.scale, 0.0, 0.0);
    /* ... braking is always allowed */
    assert_int_equal(aocs_wheels_allocate(&wa, aocs_vec3_neg(uc), om, &al), AOCS_OK);
    assert_close(al.scale, 1.0, 0.0);
    assert_true(al.u_s_nm[0] < AOCS_R(0.0));
}

static void test_total_momentum_and_margin(void **state)
{
    (void)state;
    aocs_wheels_config_t cfg;
    aocs_wheels_t wa;
    aocs_wheels_momentum_t m;
    pyramid(&cfg);
    cfg.failed_mask = 1u << 2;
    assert_int_equal(aocs_wheels_init(&wa, &cfg), AOCS_OK);
    real_t om[AOCS_WHEELS_MAX] = {AOCS_R(100.0), AOCS_R(-450.0), AOCS_R(590.0), AOCS_R(20.0), 0, 0};
    aocs_vec3_t w = aocs_vec3_make(AOCS_R(1e-3), AOCS_R(-2e-3), AOCS_R(5e-4));
    assert_int_equal(aocs_wheels_momentum(&wa, w, om, &m), AOCS_OK);
    double jd[3] = {2059.5, 5954.2, 5974.3};
    double hw[3] = {0.0, 0.0, 0.0};
    for (int i = 0; i < 4; ++i) {
        for (int r = 0; r < 3; ++r) {
            hw[r] += JS * (double)om[i] * (double)cfg.axis_B[i].v[r];
        }
    }
    for (int r = 0; r < 3; ++r) {
        assert_close(m.h_total_B_Nms.v[r], jd[r] * (double)w.v[r] + hw[r], TOL_TIGHT);
    }
    assert_close(m.h_wheels_norm_Nms, sqrt(hw[0] * hw[0] + hw[1] * hw[1] + hw[2] * hw[2]), TOL_TIGHT);
    /* the failed wheel 2 (590 rad/s) is not counted: the worst healthy one is wheel 1 at 450 */
    assert_close(m.speed_margin, 1.0 - 450.0 / 600.0, TOL_TIGHT);
    assert_int_equal(m.worst_wheel, 1u);
}

static void test_the_envelope_of_the_reference_pyramid(void **state)
{
    (void)state;
    aocs_wheels_config_t cfg;
    aocs_wheels_t wa;
    pyramid(&cfg);
    assert_int_equal(aocs_wheels_init(&wa, &cfg), AOCS_OK);
    aocs_mat3_t eye = aocs_mat3_identity();
    /* SPEC 5.3: 2 * 0.25 sqrt(2/3) = 0.408 N m transverse, 4 * 0.25 / sqrt 3 = 0.577 N m on the pyramid axis */
    assert_close(aocs_wheels_alpha_max(&wa, eye, aocs_vec3_make(1, 0, 0)), 2.0 * UMAX * sqrt(2.0 / 3.0), TOL_TIGHT);
    assert_close(aocs_wheels_alpha_max(&wa, eye, aocs_vec3_make(0, 1, 0)), 2.0 * UMAX * sqrt(2.0 / 3.0), TOL_TIGHT);
    assert_close(aocs_wheels_alpha_max(&wa, eye, aocs_vec3_make(0, 0, 1)), 4.0 * UMAX / sqrt(3.0), TOL_TIGHT);
    /* with the IRASSI inertia along the large slew's axis: J a e allocated at a = alpha_max has
     * scale 1 and one wheel exactly at its limit; a little more is scaled */
    aocs_vec3_t e = aocs_vec3_make(AOCS_R(-0.297), AOCS_R(-0.799), AOCS_R(0.522));
    e = aocs_vec3_scale(e, AOCS_R(1.0) / aocs_vec3_norm(e));
    real_t a = aocs_wheels_alpha_max(&wa, cfg.inertia_B_kgm2, e);
    assert_true(a > AOCS_R(0.0));
    aocs_wheels_alloc_t al;
    aocs_vec3_t u = aocs_mat3_mul_vec(cfg.inertia_B_kgm2, aocs_vec3_scale(e, a));
    assert_int_equal(aocs_wheels_allocate(&wa, u, ZERO_SPEEDS, &al), AOCS_OK);
    assert_close(al.scale, 1.0, TOL_TIGHT);
    double amax = 0.0;
    for (int i = 0; i < 4; ++i) {
        amax = fmax(amax, fabs((double)al.u_s_nm[i]));
    }
    assert_close(amax, UMAX, TOL_TIGHT);
    assert_int_equal(aocs_wheels_allocate(&wa, aocs_vec3_scale(u, AOCS_R(1.01)), ZERO_SPEEDS, &al), AOCS_OK);
    assert_true(al.scale < AOCS_R(0.995));
    /* a failed wheel shrinks the envelope */
    cfg.failed_mask = 1u;
    assert_int_equal(aocs_wheels_init(&wa, &cfg), AOCS_OK);
    assert_true(aocs_wheels_alpha_max(&wa, cfg.inertia_B_kgm2, e) < a);
    /* total: bad inputs give 0 */
    assert_close(aocs_wheels_alpha_max(NULL, eye, e), 0.0, 0.0);
    assert_close(aocs_wheels_alpha_max(&wa, eye, aocs_vec3_make(0, 0, 0)), 0.0, 0.0);
    assert_close(aocs_wheels_alpha_max(&wa, eye, aocs_vec3_make(NAN, 0, 0)), 0.0, 0.0);
}

static void test_the_guidance_envelope_with_the_gyroscopic_allowance(void **state)
{
    (void)state;
    aocs_wheels_config_t cfg;
    aocs_wheels_t wa;
    pyramid(&cfg);
    cfg.failed_mask = 1u << 2;
    assert_int_equal(aocs_wheels_init(&wa, &cfg), AOCS_OK);
    aocs_vec3_t a = aocs_vec3_make(AOCS_R(-600.0), AOCS_R(-4700.0), AOCS_R(3100.0));
    aocs_vec3_t b = aocs_vec3_make(AOCS_R(30.0), AOCS_R(-5.0), AOCS_R(12.0));
    /* independent: min_i umax / (|(P a)_i| + |(P b)_i|) with P from the elimination in double (unit columns) */
    double best = 1e300;
    for (int i = 0; i < 4; ++i) {
        if (i == 2) {
            continue;
        }
        double pa[AOCS_WHEELS_MAX];
        double pb[AOCS_WHEELS_MAX];
        double ad[3] = {(double)a.v[0], (double)a.v[1], (double)a.v[2]};
        double bd[3] = {(double)b.v[0], (double)b.v[1], (double)b.v[2]};
        min_norm_d(&cfg, ad, pa); /* -P a */
        min_norm_d(&cfg, bd, pb);
        best = fmin(best, UMAX / (fabs(pa[i]) + fabs(pb[i])));
    }
    assert_close(aocs_wheels_alpha_envelope(&wa, a, b), best, TOL_TIGHT);
    /* b = 0 is aocs_wheels_alpha_max */
    aocs_mat3_t eye = aocs_mat3_identity();
    assert_close(aocs_wheels_alpha_envelope(&wa, a, aocs_vec3_zero()), aocs_wheels_alpha_max(&wa, eye, a), TOL_TIGHT);
    /* the wheels' momentum for the feedforward */
    real_t om[AOCS_WHEELS_MAX] = {AOCS_R(10.0), AOCS_R(-20.0), AOCS_R(30.0), AOCS_R(-40.0), 0, 0};
    aocs_vec3_t h = aocs_wheels_h_B(&wa, om);
    for (int r = 0; r < 3; ++r) {
        double x = 0.0;
        for (int i = 0; i < 4; ++i) {
            x += JS * (double)om[i] * (double)cfg.axis_B[i].v[r];
        }
        assert_close(h.v[r], x, TOL_TIGHT);
    }
    om[0] = NAN;
    assert_vec3_close(aocs_wheels_h_B(&wa, om), aocs_vec3_zero(), 0.0);
    assert_vec3_close(aocs_wheels_h_B(NULL, om), aocs_vec3_zero(), 0.0);
}

static void expect_init(aocs_wheels_config_t *cfg, aocs_status_t st)
{
    aocs_wheels_t wa;
    wa.initialised = 1;
    assert_int_equal(aocs_wheels_init(&wa, cfg), st);
    assert_int_equal(wa.initialised, 0);
    aocs_wheels_alloc_t al;
    assert_int_equal(aocs_wheels_allocate(&wa, aocs_vec3_make(1, 0, 0), ZERO_SPEEDS, &al), AOCS_ERR_NOT_INITIALISED);
    assert_close(al.scale, 0.0, 0.0);
}

static void test_every_configuration_error_has_its_code(void **state)
{
    (void)state;
    aocs_wheels_config_t cfg;
    aocs_wheels_t wa;
    pyramid(&cfg);
    assert_int_equal(aocs_wheels_init(NULL, &cfg), AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_wheels_init(&wa, NULL), AOCS_ERR_NULL_ARG);
    cfg.n = 2u;
    expect_init(&cfg, AOCS_ERR_WHEEL_COUNT);
    cfg.n = 7u;
    expect_init(&cfg, AOCS_ERR_WHEEL_COUNT);
    pyramid(&cfg);
    cfg.failed_mask = 1u << 4;
    expect_init(&cfg, AOCS_ERR_WHEEL_FAILED_MASK);
    pyramid(&cfg);
    cfg.axis_B[1] = aocs_vec3_make(AOCS_R(1.1), 0, 0);
    expect_init(&cfg, AOCS_ERR_WHEEL_AXIS_NOT_UNIT);
    cfg.axis_B[1] = aocs_vec3_make(NAN, 0, 0);
    expect_init(&cfg, AOCS_ERR_WHEEL_AXIS_NOT_UNIT);
    pyramid(&cfg);
    cfg.js_kgm2[3] = AOCS_R(0.0);
    expect_init(&cfg, AOCS_ERR_WHEEL_INERTIA_NOT_POSITIVE);
    pyramid(&cfg);
    cfg.u_max_nm[0] = AOCS_R(-0.25);
    expect_init(&cfg, AOCS_ERR_WHEEL_LIMIT_NOT_POSITIVE);
    pyramid(&cfg);
    cfg.omega_max_radps[2] = INFINITY;
    expect_init(&cfg, AOCS_ERR_WHEEL_LIMIT_NOT_POSITIVE);
    pyramid(&cfg);
    cfg.period_s = AOCS_R(0.0);
    expect_init(&cfg, AOCS_ERR_DT_INVALID);
    pyramid(&cfg);
    cfg.inertia_B_kgm2.m[0][1] = AOCS_R(5.0);
    expect_init(&cfg, AOCS_ERR_INERTIA_NOT_SYMMETRIC);
    /* two failed wheels of four: the two left do not span */
    pyramid(&cfg);
    cfg.failed_mask = 0x5u;
    expect_init(&cfg, AOCS_ERR_WHEELS_NOT_SPANNING);
    /* three coplanar axes */
    pyramid(&cfg);
    cfg.n = 3u;
    cfg.axis_B[0] = aocs_vec3_make(1, 0, 0);
    cfg.axis_B[1] = aocs_vec3_make(0, 1, 0);
    cfg.axis_B[2] = aocs_vec3_make(AOCS_R(0.6), AOCS_R(0.8), 0);
    expect_init(&cfg, AOCS_ERR_WHEELS_NOT_SPANNING);
}

static void test_bad_inputs_give_a_zero_command(void **state)
{
    (void)state;
    aocs_wheels_config_t cfg;
    aocs_wheels_t wa;
    aocs_wheels_alloc_t al;
    aocs_wheels_momentum_t m;
    pyramid(&cfg);
    assert_int_equal(aocs_wheels_init(&wa, &cfg), AOCS_OK);
    real_t om[AOCS_WHEELS_MAX] = {0, NAN, 0, 0, 0, 0};
    assert_int_equal(aocs_wheels_allocate(&wa, aocs_vec3_make(AOCS_R(0.1), 0, 0), om, &al), AOCS_ERR_INPUT_NOT_FINITE);
    for (int i = 0; i < 6; ++i) {
        assert_close(al.u_s_nm[i], 0.0, 0.0);
    }
    assert_int_equal(aocs_wheels_allocate(&wa, aocs_vec3_make(INFINITY, 0, 0), ZERO_SPEEDS, &al),
                     AOCS_ERR_INPUT_NOT_FINITE);
    assert_int_equal(aocs_wheels_allocate(&wa, aocs_vec3_make(0, 0, 0), NULL, &al), AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_wheels_allocate(&wa, aocs_vec3_make(0, 0, 0), ZERO_SPEEDS, NULL), AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_wheels_momentum(&wa, aocs_vec3_make(0, 0, 0), om, &m), AOCS_ERR_INPUT_NOT_FINITE);
    assert_close(m.h_wheels_norm_Nms, 0.0, 0.0);
    assert_int_equal(aocs_wheels_momentum(NULL, aocs_vec3_make(0, 0, 0), om, &m), AOCS_ERR_NULL_ARG);
    /* a huge but finite command is scaled, never beyond the limit */
    assert_int_equal(aocs_wheels_allocate(&wa, aocs_vec3_make(AOCS_R(1e30), AOCS_R(-1e30), AOCS_R(1e29)),
                                          ZERO_SPEEDS, &al), AOCS_OK);
    for (int i = 0; i < 4; ++i) {
        assert_true(AOCS_FABS(al.u_s_nm[i]) <= AOCS_R(UMAX) * (AOCS_R(1.0) + AOCS_R(4.0) * AOCS_REAL_EPS));
    }
}

/* ---- friction feedforward and null-space management (docs/spec.md 5.3.2) ---- */

#define FB 1.0e-4   /* b, N m s/rad: 0.06 N m at 600 rad/s */
#define FC 0.02     /* c, N m */
#define FEPS 0.5    /* Omega_eps, rad/s */

static void with_friction(aocs_wheels_config_t *cfg)
{
    for (uint32_t i = 0u; i < cfg->n; ++i) {
        cfg->viscous_nms[i] = AOCS_R(FB);
        cfg->coulomb_nm[i] = AOCS_R(FC);
        cfg->coulomb_width_radps[i] = AOCS_R(FEPS);
    }
}

/* the reference pyramid with the reference friction, initialised */
static void friction_array(aocs_wheels_config_t *cfg, aocs_wheels_t *wa)
{
    pyramid(cfg);
    with_friction(cfg);
    assert_int_equal(aocs_wheels_init(wa, cfg), AOCS_OK);
}

/* the plant's bearing friction, written out (sil/aocs_plant/effectors/reaction_wheels.py) */
static double friction_d(double omega)
{
    double w = fmax(-WMAX, fmin(WMAX, omega));
    return FB * w + FC * tanh(w / FEPS);
}

/* the largest s in [0, 1] with |s tau_i + f_i| <= UMAX for every wheel (no speed bound binding) */
static double scale_d(const double tau[AOCS_WHEELS_MAX], const double f[AOCS_WHEELS_MAX], uint32_t n)
{
    double s = 1.0;
    for (uint32_t i = 0u; i < n; ++i) {
        if (tau[i] > 0.0) {
            s = fmin(s, (UMAX - f[i]) / tau[i]);
        } else if (tau[i] < 0.0) {
            s = fmin(s, (UMAX + f[i]) / -tau[i]);
        }
    }
    return s;
}

static void test_the_friction_feedforward_delivers_the_net_torque(void **state)
{
    (void)state;
    aocs_wheels_config_t cfg;
    aocs_wheels_t wa;
    friction_array(&cfg, &wa);
    uint32_t seed = 4242u;
    int n_scaled = 0;
    for (int k = 0; k < 400; ++k) {
        /* speeds across zero (the tanh) and far from it; commands small and far beyond the envelope */
        double spread = (k % 2 == 0) ? 2.0 : 400.0;
        double mag = (k % 3 == 0) ? 3.0 : 0.05;
        real_t om[AOCS_WHEELS_MAX] = {0};
        double f[AOCS_WHEELS_MAX] = {0};
        for (int i = 0; i < 4; ++i) {
            om[i] = (real_t)(spread * rnd(&seed));
            f[i] = friction_d((double)om[i]);
        }
        double uc[3] = {mag * rnd(&seed), mag * rnd(&seed), mag * rnd(&seed)};
        double tau[AOCS_WHEELS_MAX];
        min_norm_d(&cfg, uc, tau);
        double s = scale_d(tau, f, 4u);
        aocs_wheels_alloc_t al;
        assert_int_equal(aocs_wheels_allocate(&wa, aocs_vec3_make((real_t)uc[0], (real_t)uc[1], (real_t)uc[2]), om,
                                              &al), AOCS_OK);
        assert_close(al.scale, s, TOL_LOOSE);
        n_scaled += (s < 1.0) ? 1 : 0;
        for (int i = 0; i < 4; ++i) {
            /* the motor overcomes the bearing: u_s = s tau + f(Omega), so u_s - f(Omega) = s tau reaches the wheel */
            assert_close(al.friction_nm[i], f[i], TOL_TIGHT);
            assert_close(al.u_s_nm[i], s * tau[i] + f[i], TOL_LOOSE * UMAX);
            assert_close(al.null_nm[i], 0.0, 0.0);
            /* the compensated command never beyond the motor limit */
            assert_true(fabs((double)al.u_s_nm[i]) <= UMAX * (1.0 + 8.0 * (double)AOCS_REAL_EPS));
        }
        /* the body receives -Gs (u_s - f) = s u_c: the law's direction */
        double body[3] = {0.0, 0.0, 0.0};
        for (int i = 0; i < 4; ++i) {
            for (int r = 0; r < 3; ++r) {
                body[r] -= (double)cfg.axis_B[i].v[r] * ((double)al.u_s_nm[i] - f[i]);
            }
        }
        for (int r = 0; r < 3; ++r) {
            assert_close(body[r], s * uc[r], TOL_LOOSE * mag);
            assert_close(al.u_body_B_nm.v[r], s * uc[r], TOL_LOOSE * mag);
        }
        if (s < 1.0) {
            /* beyond the envelope a wheel sits exactly at its limit with the compensation included */
            double amax = 0.0;
            for (int i = 0; i < 4; ++i) {
                amax = fmax(amax, fabs((double)al.u_s_nm[i]));
            }
            assert_close(amax, UMAX, TOL_LOOSE);
            assert_true(al.torque_limited_mask != 0u);
        }
    }
    assert_true(n_scaled > 50); /* both cases were exercised */
}

static void test_the_friction_model_is_clamped_at_the_speed_limit(void **state)
{
    (void)state;
    aocs_wheels_config_t cfg;
    aocs_wheels_t wa;
    friction_array(&cfg, &wa);
    assert_close(aocs_wheels_friction(&wa, 1u, AOCS_R(0.25)), FB * 0.25 + FC * tanh(0.5), TOL_TIGHT);
    assert_close(aocs_wheels_friction(&wa, 1u, AOCS_R(-300.0)), -(FB * 300.0 + FC * tanh(600.0)), TOL_TIGHT);
    /* a tachometer beyond the limit (one step of overshoot) reads as the limit: |f^| < u_s,max always */
    assert_close(aocs_wheels_friction(&wa, 2u, AOCS_R(700.0)), FB * WMAX + FC, TOL_TIGHT);
    assert_close(aocs_wheels_friction(&wa, 2u, AOCS_R(-1e30)), -(FB * WMAX + FC), TOL_TIGHT);
    /* total */
    assert_close(aocs_wheels_friction(&wa, 4u, AOCS_R(10.0)), 0.0, 0.0);
    assert_close(aocs_wheels_friction(&wa, 0u, AOCS_R(NAN)), 0.0, 0.0);
    assert_close(aocs_wheels_friction(NULL, 0u, AOCS_R(10.0)), 0.0, 0.0);
    /* a failed wheel gets no motor torque, so no compensation either */
    cfg.failed_mask = 1u << 1;
    assert_int_equal(aocs_wheels_init(&wa, &cfg), AOCS_OK);
    real_t om[AOCS_WHEELS_MAX] = {AOCS_R(100.0), AOCS_R(100.0), AOCS_R(-50.0), AOCS_R(3.0), 0, 0};
    aocs_wheels_alloc_t al;
    assert_int_equal(aocs_wheels_allocate(&wa, aocs_vec3_make(AOCS_R(0.01), 0, 0), om, &al), AOCS_OK);
    assert_close(al.u_s_nm[1], 0.0, 0.0);
    assert_close(al.friction_nm[1], 0.0, 0.0);
    assert_close(al.friction_nm[2], friction_d(-50.0), TOL_TIGHT);
}

/* the same at negative speeds: a wheel near -Omega_max is never driven past -Omega_max */
static void test_no_torque_drives_a_wheel_beyond_its_negative_speed_limit(void **state)
{
    (void)state;
    aocs_wheels_config_t cfg;
    aocs_wheels_t wa;
    aocs_wheels_alloc_t al;
    pyramid(&cfg);
    assert_int_equal(aocs_wheels_init(&wa, &cfg), AOCS_OK);
    /* a body torque along +g0 asks wheel 0 to speed up in -: u_s = -Gs^+ u_c */
    aocs_vec3_t uc = aocs_vec3_scale(cfg.axis_B[0], AOCS_R(0.2));
    real_t om[AOCS_WHEELS_MAX] = {AOCS_R(-599.9), 0, 0, 0, 0, 0};
    double us[AOCS_WHEELS_MAX];
    double ucd[3] = {(double)uc.v[0], (double)uc.v[1], (double)uc.v[2]};
    min_norm_d(&cfg, ucd, us);
    assert_true(us[0] < -0.1); /* -0.15 N m: more than the headroom below, within u_s,max */
    double head = JS * (WMAX - 599.9) / 0.1; /* 0.08 N m */
    assert_int_equal(aocs_wheels_allocate(&wa, uc, om, &al), AOCS_OK);
    assert_close(al.u_s_nm[0], -head, TOL_LOOSE);
    assert_close(al.scale, head / -us[0], TOL_LOOSE);
    assert_true(al.speed_limited_mask == 1u);
    assert_true((double)om[0] + (double)al.u_s_nm[0] * 0.1 / JS >= -WMAX * (1.0 + 1e-6));
    /* at -Omega_max: nothing more in that direction ... */
    om[0] = AOCS_R(-WMAX);
    assert_int_equal(aocs_wheels_allocate(&wa, uc, om, &al), AOCS_OK);
    assert_close(al.scale, 0.0, 0.0);
    assert_true(al.speed_limited_mask == 1u);
    /* ... braking (toward 0) is always allowed */
    assert_int_equal(aocs_wheels_allocate(&wa, aocs_vec3_neg(uc), om, &al), AOCS_OK);
    assert_close(al.scale, 1.0, 0.0);
    assert_true(al.u_s_nm[0] > AOCS_R(0.0));
    /* from rest the headroom bounds either direction: a 384 s step leaves Js Omega_max / T = 0.125 N m */
    cfg.period_s = AOCS_R(384.0);
    assert_int_equal(aocs_wheels_init(&wa, &cfg), AOCS_OK);
    om[0] = AOCS_R(0.0);
    const double head_rest = JS * WMAX / 384.0;
    assert_int_equal(aocs_wheels_allocate(&wa, uc, om, &al), AOCS_OK);
    assert_close(al.u_s_nm[0], -head_rest, TOL_LOOSE);
    assert_true(al.speed_limited_mask == 1u);
    assert_int_equal(aocs_wheels_allocate(&wa, aocs_vec3_neg(uc), om, &al), AOCS_OK);
    assert_close(al.u_s_nm[0], head_rest, TOL_LOOSE);
    assert_true(al.speed_limited_mask == 1u);
    /* with the bearing: the net torque (motor minus friction) gets the headroom */
    friction_array(&cfg, &wa);
    om[0] = AOCS_R(-599.9);
    double tau[AOCS_WHEELS_MAX];
    min_norm_d(&cfg, ucd, tau);
    assert_int_equal(aocs_wheels_allocate(&wa, uc, om, &al), AOCS_OK);
    assert_close(al.scale, head / -tau[0], TOL_LOOSE);
    assert_close((double)al.u_s_nm[0] - friction_d(-599.9), -head, TOL_LOOSE);
    assert_true(al.speed_limited_mask == 1u);
}

/* the last guard of aocs_wheels_allocate (unreachable from accepted inputs): a non-finite motor command, here
   from a corrupted Gs^+ after init, is no command: every output zero and AOCS_ERR_WHEEL_CMD_INVALID */
static void test_a_corrupted_allocation_gives_no_command_and_says_so(void **state)
{
    (void)state;
    aocs_wheels_config_t cfg;
    aocs_wheels_t wa;
    aocs_wheels_alloc_t al;
    pyramid(&cfg);
    assert_int_equal(aocs_wheels_init(&wa, &cfg), AOCS_OK);
    wa.pinv[0][0] = (real_t)INFINITY;
    assert_int_equal(aocs_wheels_allocate(&wa, aocs_vec3_make(AOCS_R(0.1), AOCS_R(0.0), AOCS_R(0.0)), ZERO_SPEEDS, &al),
                     AOCS_ERR_WHEEL_CMD_INVALID);
    for (uint32_t i = 0u; i < AOCS_WHEELS_MAX; ++i) {
        assert_close(al.u_s_nm[i], 0.0, 0.0);
    }
    assert_close(al.scale, 0.0, 0.0);
    assert_close(aocs_vec3_norm(al.u_body_B_nm), 0.0, 0.0);
}

static void test_the_speed_headroom_bounds_the_net_torque(void **state)
{
    (void)state;
    aocs_wheels_config_t cfg;
    aocs_wheels_t wa;
    aocs_wheels_alloc_t al;
    friction_array(&cfg, &wa);
    aocs_vec3_t uc = aocs_vec3_scale(cfg.axis_B[0], AOCS_R(-0.2)); /* speeds wheel 0 up in + */
    real_t om[AOCS_WHEELS_MAX] = {AOCS_R(599.9), 0, 0, 0, 0, 0};
    double ucd[3] = {(double)uc.v[0], (double)uc.v[1], (double)uc.v[2]};
    double tau[AOCS_WHEELS_MAX];
    min_norm_d(&cfg, ucd, tau);
    double head = JS * (WMAX - 599.9) / 0.1; /* 0.08 N m of net torque */
    assert_int_equal(aocs_wheels_allocate(&wa, uc, om, &al), AOCS_OK);
    /* the net torque (motor minus bearing) is what changes the speed: it gets the headroom, the motor the
     * headroom plus the friction it must overcome */
    assert_close(al.scale, head / tau[0], TOL_LOOSE);
    assert_close((double)al.u_s_nm[0] - friction_d(599.9), head, TOL_LOOSE);
    assert_true(al.speed_limited_mask == 1u);
}

/* the pyramid's null space is spanned by n = [1 -1 1 -1] / 2 (its azimuths 0, 90, 180, 270 deg) */
static const double NULL_N[4] = {0.5, -0.5, 0.5, -0.5};

static void test_the_null_space_management_gives_no_body_torque(void **state)
{
    (void)state;
    aocs_wheels_config_t cfg;
    aocs_wheels_t wa;
    pyramid(&cfg);
    with_friction(&cfg);
    const double kn = 0.005; /* u_n below 0.06 N m here: within half the room left, so r = 1 */
    const double target[4] = {50.0, -50.0, 50.0, -50.0};
    cfg.null_gain_per_s = AOCS_R(kn);
    for (int i = 0; i < 4; ++i) {
        cfg.null_speed_radps[i] = AOCS_R(target[i]);
    }
    assert_int_equal(aocs_wheels_init(&wa, &cfg), AOCS_OK);
    uint32_t seed = 777u;
    for (int k = 0; k < 200; ++k) {
        real_t om[AOCS_WHEELS_MAX] = {0};
        double f[AOCS_WHEELS_MAX] = {0};
        double e_n = 0.0; /* n . Js (Omega* - Omega) */
        for (int i = 0; i < 4; ++i) {
            om[i] = (real_t)(100.0 * rnd(&seed));
            f[i] = friction_d((double)om[i]);
            e_n += NULL_N[i] * JS * (target[i] - (double)om[i]);
        }
        double uc[3] = {0.01 * rnd(&seed), 0.01 * rnd(&seed), 0.01 * rnd(&seed)};
        double tau[AOCS_WHEELS_MAX];
        min_norm_d(&cfg, uc, tau);
        aocs_wheels_alloc_t al;
        assert_int_equal(aocs_wheels_allocate(&wa, aocs_vec3_make((real_t)uc[0], (real_t)uc[1], (real_t)uc[2]), om,
                                              &al), AOCS_OK);
        /* small command and small null torque: neither is scaled */
        assert_close(al.scale, 1.0, 0.0);
        assert_close(al.null_scale, 1.0, 0.0);
        for (int i = 0; i < 4; ++i) {
            /* u_n = k_n P_N Js (Omega* - Omega), P_N = n n^T */
            assert_close(al.null_nm[i], kn * NULL_N[i] * e_n, TOL_LOOSE * 0.01);
            assert_close(al.u_s_nm[i], tau[i] + kn * NULL_N[i] * e_n + f[i], TOL_LOOSE * 0.01);
        }
        /* -Gs u_n = 0: the body torque is the command alone */
        double body[3] = {0.0, 0.0, 0.0};
        for (int i = 0; i < 4; ++i) {
            for (int r = 0; r < 3; ++r) {
                body[r] -= (double)cfg.axis_B[i].v[r] * ((double)al.u_s_nm[i] - f[i]);
            }
        }
        for (int r = 0; r < 3; ++r) {
            assert_close(body[r], uc[r], TOL_LOOSE * 0.01);
        }
    }
    /* the null-space part of the momenta relaxes to the targets': one period of u_n, e+ = (1 - k_n T) e */
    real_t om[AOCS_WHEELS_MAX] = {AOCS_R(3.0), AOCS_R(2.0), AOCS_R(-1.0), AOCS_R(0.5), 0, 0};
    aocs_wheels_alloc_t al;
    assert_int_equal(aocs_wheels_allocate(&wa, aocs_vec3_zero(), om, &al), AOCS_OK);
    double e0 = 0.0;
    double e1 = 0.0;
    for (int i = 0; i < 4; ++i) {
        double next = (double)om[i] + (double)al.null_nm[i] * 0.1 / JS; /* the net torque is u_n */
        e0 += NULL_N[i] * (target[i] - (double)om[i]);
        e1 += NULL_N[i] * (target[i] - next);
    }
    assert_true(e0 > 50.0);
    assert_close(e1, (1.0 - kn * 0.1) * e0, TOL_LOOSE * 100.0);
}

static void test_the_null_space_torque_gets_half_the_room_left(void **state)
{
    (void)state;
    aocs_wheels_config_t cfg;
    aocs_wheels_t wa;
    pyramid(&cfg);
    cfg.null_gain_per_s = AOCS_R(10.0); /* k_n T = 1: asks for far more than the motors have */
    for (int i = 0; i < 4; ++i) {
        cfg.null_speed_radps[i] = AOCS_R((i % 2 == 0) ? 500.0 : -500.0);
    }
    assert_int_equal(aocs_wheels_init(&wa, &cfg), AOCS_OK);
    aocs_vec3_t uc = aocs_vec3_make(AOCS_R(0.05), AOCS_R(-0.1), AOCS_R(0.02));
    double ucd[3] = {0.05, -0.1, 0.02};
    double tau[AOCS_WHEELS_MAX];
    min_norm_d(&cfg, ucd, tau);
    aocs_wheels_alloc_t al;
    assert_int_equal(aocs_wheels_allocate(&wa, uc, ZERO_SPEEDS, &al), AOCS_OK);
    /* the body torque first and whole */
    assert_close(al.scale, 1.0, 0.0);
    assert_vec3_close(al.u_body_B_nm, uc, TOL_TIGHT);
    /* r: the largest scale with every |tau_i + r u_n,i| within tau_i + half of (+-UMAX - tau_i) */
    double un = 10.0 * JS * 1000.0; /* u_n,i = k_n Js (n . Omega*) n_i with n . Omega* = 1000 rad/s */
    double r = 1.0;
    for (int i = 0; i < 4; ++i) {
        double d = un * NULL_N[i];
        double bound = (d > 0.0) ? 0.5 * (UMAX - tau[i]) : 0.5 * (-UMAX - tau[i]);
        r = fmin(r, bound / d);
    }
    assert_true(r < 0.1);
    assert_close(al.null_scale, r, TOL_LOOSE);
    double amax = 0.0;
    for (int i = 0; i < 4; ++i) {
        assert_close(al.null_nm[i], r * un * NULL_N[i], TOL_LOOSE);
        amax = fmax(amax, fabs((double)al.u_s_nm[i]));
    }
    /* no wheel reaches its limit through the momentum management */
    assert_true(amax < UMAX * 0.99);
    /* with three healthy wheels there is no null space: nothing */
    cfg.failed_mask = 1u;
    assert_int_equal(aocs_wheels_init(&wa, &cfg), AOCS_OK);
    assert_int_equal(aocs_wheels_allocate(&wa, uc, ZERO_SPEEDS, &al), AOCS_OK);
    for (int i = 0; i < 4; ++i) {
        assert_close(al.null_nm[i], 0.0, 0.0);
    }
}

/* the defaults (wheel_array.h: "no null-space management (k_n = 0, Omega* = 0)"): with only a gain set, the
   null-space management relaxes the wheels toward rest. The 3 + 1 array (x, y, z and a skew wheel on
   (1 1 1) / sqrt 3) has the null vector n = [1 1 1 -sqrt 3] / sqrt 6, which is not orthogonal to a target
   speed common to every wheel (the pyramid's [1 -1 1 -1] / 2 is: there any common Omega* would pass unseen) */
static void test_the_default_null_space_target_is_rest(void **state)
{
    (void)state;
    aocs_wheels_config_t cfg;
    aocs_wheels_t wa;
    aocs_wheels_alloc_t al;
    const double s3 = sqrt(3.0);
    const double nv[4] = {1.0 / sqrt(6.0), 1.0 / sqrt(6.0), 1.0 / sqrt(6.0), -s3 / sqrt(6.0)};
    aocs_wheels_config_default(&cfg);
    cfg.n = 4u;
    cfg.axis_B[0] = aocs_vec3_make(AOCS_R(1.0), AOCS_R(0.0), AOCS_R(0.0));
    cfg.axis_B[1] = aocs_vec3_make(AOCS_R(0.0), AOCS_R(1.0), AOCS_R(0.0));
    cfg.axis_B[2] = aocs_vec3_make(AOCS_R(0.0), AOCS_R(0.0), AOCS_R(1.0));
    cfg.axis_B[3] = aocs_vec3_make((real_t)(1.0 / s3), (real_t)(1.0 / s3), (real_t)(1.0 / s3));
    for (uint32_t i = 0u; i < 4u; ++i) {
        cfg.js_kgm2[i] = AOCS_R(JS);
        cfg.u_max_nm[i] = AOCS_R(UMAX);
        cfg.omega_max_radps[i] = AOCS_R(WMAX);
    }
    /* the defaults alone manage nothing */
    real_t om[AOCS_WHEELS_MAX] = {AOCS_R(10.0), AOCS_R(20.0), AOCS_R(-5.0), AOCS_R(7.0), 0, 0};
    assert_int_equal(aocs_wheels_init(&wa, &cfg), AOCS_OK);
    assert_int_equal(aocs_wheels_allocate(&wa, aocs_vec3_zero(), om, &al), AOCS_OK);
    for (uint32_t i = 0u; i < 4u; ++i) {
        assert_close(al.null_nm[i], 0.0, 0.0);
    }
    /* a gain: u_n = k_n n (n . Js (0 - Omega)), small enough to be unscaled (|u_n| < 0.02 N m) */
    const double kn = 0.1;
    cfg.null_gain_per_s = AOCS_R(kn);
    assert_int_equal(aocs_wheels_init(&wa, &cfg), AOCS_OK);
    assert_int_equal(aocs_wheels_allocate(&wa, aocs_vec3_zero(), om, &al), AOCS_OK);
    double e_n = 0.0;
    for (int i = 0; i < 4; ++i) {
        e_n += nv[i] * JS * (0.0 - (double)om[i]);
    }
    assert_close(al.null_scale, 1.0, 0.0);
    for (int i = 0; i < 4; ++i) {
        assert_close(al.null_nm[i], kn * nv[i] * e_n, TOL_LOOSE * 0.01);
    }
    /* at rest there is nothing to manage */
    assert_int_equal(aocs_wheels_allocate(&wa, aocs_vec3_zero(), ZERO_SPEEDS, &al), AOCS_OK);
    for (uint32_t i = 0u; i < 4u; ++i) {
        assert_close(al.null_nm[i], 0.0, TOL_TIGHT);
    }
}

/* AOCS_WHEELS_MAX wheels (the pyramid, one on x and one on (0 0.6 0.8)): a three-dimensional null space. The
   null-space torque is u_n = k_n P_N Js (Omega* - Omega) with P_N = I - Gs^T (Gs Gs^T)^-1 Gs written out here:
   P_N e = e + min_norm_d(Gs e) */
static void test_the_null_space_management_of_the_largest_array(void **state)
{
    (void)state;
    aocs_wheels_config_t cfg;
    aocs_wheels_t wa;
    aocs_wheels_alloc_t al;
    pyramid(&cfg);
    cfg.n = AOCS_WHEELS_MAX;
    cfg.axis_B[4] = aocs_vec3_make(AOCS_R(1.0), AOCS_R(0.0), AOCS_R(0.0));
    cfg.axis_B[5] = aocs_vec3_make(AOCS_R(0.0), AOCS_R(0.6), AOCS_R(0.8));
    for (uint32_t i = 4u; i < AOCS_WHEELS_MAX; ++i) {
        cfg.js_kgm2[i] = AOCS_R(JS);
        cfg.u_max_nm[i] = AOCS_R(UMAX);
        cfg.omega_max_radps[i] = AOCS_R(WMAX);
    }
    const double kn = 0.01;
    const double target[AOCS_WHEELS_MAX] = {40.0, -30.0, 20.0, 0.0, -50.0, 60.0};
    const real_t om[AOCS_WHEELS_MAX] = {AOCS_R(10.0), AOCS_R(20.0), AOCS_R(-35.0), AOCS_R(70.0), AOCS_R(-5.0),
                                        AOCS_R(15.0)};
    cfg.null_gain_per_s = AOCS_R(kn);
    for (uint32_t i = 0u; i < AOCS_WHEELS_MAX; ++i) {
        cfg.null_speed_radps[i] = (real_t)target[i];
    }
    assert_int_equal(aocs_wheels_init(&wa, &cfg), AOCS_OK);
    double e[AOCS_WHEELS_MAX];
    double ge[3] = {0.0, 0.0, 0.0};
    for (uint32_t i = 0u; i < AOCS_WHEELS_MAX; ++i) {
        e[i] = JS * (target[i] - (double)om[i]);
        for (int r = 0; r < 3; ++r) {
            ge[r] += (double)cfg.axis_B[i].v[r] * e[i];
        }
    }
    double back[AOCS_WHEELS_MAX];
    min_norm_d(&cfg, ge, back);
    assert_int_equal(aocs_wheels_allocate(&wa, aocs_vec3_zero(), om, &al), AOCS_OK);
    assert_close(al.null_scale, 1.0, 0.0); /* |u_n| < 0.05 N m: within half the room */
    double body[3] = {0.0, 0.0, 0.0};
    double largest = 0.0;
    for (uint32_t i = 0u; i < AOCS_WHEELS_MAX; ++i) {
        const double un = kn * (e[i] + back[i]);
        largest = fmax(largest, fabs(un));
        assert_close(al.null_nm[i], un, TOL_LOOSE * 0.01);
        assert_close(al.u_s_nm[i], un, TOL_LOOSE * 0.01);
        for (int r = 0; r < 3; ++r) {
            body[r] -= (double)cfg.axis_B[i].v[r] * (double)al.u_s_nm[i];
        }
    }
    assert_true(largest > 0.01);
    for (int r = 0; r < 3; ++r) {
        assert_close(body[r], 0.0, TOL_LOOSE * 0.01);
    }
}

static void test_every_friction_and_null_space_error_has_its_code(void **state)
{
    (void)state;
    aocs_wheels_config_t cfg;
    pyramid(&cfg);
    with_friction(&cfg);
    cfg.viscous_nms[2] = AOCS_R(-1e-6);
    expect_init(&cfg, AOCS_ERR_WHEEL_FRICTION_NEGATIVE);
    with_friction(&cfg);
    cfg.coulomb_nm[0] = AOCS_R(NAN);
    expect_init(&cfg, AOCS_ERR_WHEEL_FRICTION_NEGATIVE);
    with_friction(&cfg);
    cfg.coulomb_width_radps[3] = AOCS_R(0.0);
    expect_init(&cfg, AOCS_ERR_WHEEL_FRICTION_WIDTH_NOT_POSITIVE);
    with_friction(&cfg);
    cfg.coulomb_width_radps[3] = AOCS_R(INFINITY);
    expect_init(&cfg, AOCS_ERR_WHEEL_FRICTION_WIDTH_NOT_POSITIVE);
    /* b Omega_max + c = 0.25 = u_s,max: nothing left for the attitude loop at the speed limit */
    with_friction(&cfg);
    cfg.viscous_nms[1] = AOCS_R((UMAX - FC) / WMAX);
    expect_init(&cfg, AOCS_ERR_WHEEL_FRICTION_EXCEEDS_LIMIT);
    with_friction(&cfg);
    cfg.viscous_nms[1] = AOCS_R(0.99 * (UMAX - FC) / WMAX);
    aocs_wheels_t wa;
    assert_int_equal(aocs_wheels_init(&wa, &cfg), AOCS_OK);
    with_friction(&cfg);
    cfg.null_gain_per_s = AOCS_R(-0.1);
    expect_init(&cfg, AOCS_ERR_WHEEL_NULL_GAIN_INVALID);
    cfg.null_gain_per_s = AOCS_R(10.5); /* k_n T = 1.05 */
    expect_init(&cfg, AOCS_ERR_WHEEL_NULL_GAIN_INVALID);
    cfg.null_gain_per_s = AOCS_R(NAN);
    expect_init(&cfg, AOCS_ERR_WHEEL_NULL_GAIN_INVALID);
    cfg.null_gain_per_s = AOCS_R(10.0);
    assert_int_equal(aocs_wheels_init(&wa, &cfg), AOCS_OK);
    cfg.null_speed_radps[2] = AOCS_R(-WMAX);
    expect_init(&cfg, AOCS_ERR_WHEEL_NULL_SPEED_INVALID);
    cfg.null_speed_radps[2] = AOCS_R(INFINITY);
    expect_init(&cfg, AOCS_ERR_WHEEL_NULL_SPEED_INVALID);
}

/* issue 25 item 1: Js = 10 and one tachometer reading of 1e308 overflowed the null-space term into NaN
 * commands reported as OK. A speed beyond AOCS_WHEEL_SPEED_RANGE_FACTOR Omega_max is rejected. */
static void test_a_tachometer_far_beyond_its_range_is_rejected(void **state)
{
    (void)state;
    aocs_wheels_config_t cfg;
    aocs_wheels_t wa;
    pyramid(&cfg);
    with_friction(&cfg);
    for (int i = 0; i < 4; ++i) {
        cfg.js_kgm2[i] = AOCS_R(10.0);
    }
    cfg.null_gain_per_s = AOCS_R(1.0);
    assert_int_equal(aocs_wheels_init(&wa, &cfg), AOCS_OK);
    const aocs_vec3_t uc = aocs_vec3_make(AOCS_R(0.01), AOCS_R(-0.02), AOCS_R(0.03));
    const real_t bad[3] = {TEST_WHEEL_TACH_HUGE, -AOCS_REAL_MAX, AOCS_R(2.0 * WMAX) * AOCS_R(1.0001)};
    for (int b = 0; b < 3; ++b) {
        real_t om[AOCS_WHEELS_MAX] = {AOCS_R(10.0), AOCS_R(-20.0), AOCS_R(30.0), AOCS_R(0.0), 0, 0};
        om[b] = bad[b];
        aocs_wheels_alloc_t al;
        assert_int_equal(aocs_wheels_allocate(&wa, uc, om, &al), AOCS_ERR_WHEEL_SPEED_RANGE);
        for (uint32_t i = 0u; i < AOCS_WHEELS_MAX; ++i) {
            assert_true(isfinite((double)al.u_s_nm[i]));
            assert_close(al.u_s_nm[i], 0.0, 0.0);
        }
        assert_true(aocs_vec3_is_finite(al.u_body_B_nm) != 0);
        aocs_wheels_momentum_t mom;
        assert_int_equal(aocs_wheels_momentum(&wa, aocs_vec3_zero(), om, &mom), AOCS_ERR_WHEEL_SPEED_RANGE);
        assert_true(aocs_vec3_is_finite(mom.h_total_B_Nms) != 0);
    }
    /* exactly twice the limit is still a reading */
    real_t om[AOCS_WHEELS_MAX] = {AOCS_R(2.0 * WMAX), AOCS_R(-2.0 * WMAX), 0, 0, 0, 0};
    aocs_wheels_alloc_t al;
    assert_int_equal(aocs_wheels_allocate(&wa, uc, om, &al), AOCS_OK);
    for (int i = 0; i < 4; ++i) {
        assert_true(AOCS_FABS(al.u_s_nm[i]) <= cfg.u_max_nm[i]);
    }
}

/* issue 25 item 6: with one failed wheel the scaled command plus the friction feedforward could land 1 ulp
 * above u_s,max. 10^6 random commands and speeds: never above the limit, compared exactly. */
static void test_no_motor_command_exceeds_its_limit_even_by_one_ulp(void **state)
{
    (void)state;
    aocs_wheels_config_t cfg;
    aocs_wheels_t wa;
    pyramid(&cfg);
    with_friction(&cfg);
    cfg.failed_mask = 1u;
    assert_int_equal(aocs_wheels_init(&wa, &cfg), AOCS_OK);
    uint32_t seed = 20251u;
    for (long k = 0; k < 1000000L; ++k) {
        real_t om[AOCS_WHEELS_MAX] = {0};
        for (int i = 0; i < 4; ++i) {
            om[i] = (real_t)(1.2 * WMAX * rnd(&seed));
        }
        const double mag = (k % 2 == 0) ? 1.0 : 0.3;
        const aocs_vec3_t uc =
            aocs_vec3_make((real_t)(mag * rnd(&seed)), (real_t)(mag * rnd(&seed)), (real_t)(mag * rnd(&seed)));
        aocs_wheels_alloc_t al;
        assert_int_equal(aocs_wheels_allocate(&wa, uc, om, &al), AOCS_OK);
        for (int i = 0; i < 4; ++i) {
            if (!(isfinite((double)al.u_s_nm[i]) && (al.u_s_nm[i] <= cfg.u_max_nm[i]) &&
                  (al.u_s_nm[i] >= -cfg.u_max_nm[i]))) {
                fail_msg("allocation %ld wheel %d: %.17g against %.17g", k, i, (double)al.u_s_nm[i],
                         (double)cfg.u_max_nm[i]);
            }
        }
    }
}

static int same(real_t a, real_t b)
{
    return (!(a < b) && !(a > b)) ? 1 : 0;
}

static void test_the_final_clamp_is_exact(void **state)
{
    (void)state;
    const real_t lim = AOCS_R(0.25);
    assert_true(same(aocs_wheels_clamp_cmd(TEST_NEXT_UP(lim), lim), lim));
    assert_true(same(aocs_wheels_clamp_cmd(-TEST_NEXT_UP(lim), lim), -lim));
    assert_true(same(aocs_wheels_clamp_cmd(AOCS_R(0.1), lim), AOCS_R(0.1)));
    assert_true(same(aocs_wheels_clamp_cmd(AOCS_R(INFINITY), lim), lim));
    assert_true(same(aocs_wheels_clamp_cmd(AOCS_R(NAN), lim), AOCS_R(0.0)));
}

/* The friction model replaced in place (fault management's friction test): the new model is the one the
 * allocation compensates (its feedforward at a speed, by hand: b w + c tanh(w / eps)), Gs^+ and the null projector
 * are untouched (bit for bit), and a model beyond the motor's limit or negative is refused with the array as it
 * was. */
static void test_the_friction_model_is_replaced_in_place_and_checked(void **state)
{
    (void)state;
    aocs_wheels_config_t c;
    aocs_wheels_t wa;
    aocs_wheels_t before;
    test_wheels_pyramid(&c);
    c.coulomb_width_radps[2] = AOCS_R(0.5);
    assert_int_equal(aocs_wheels_init(&wa, &c), AOCS_OK);
    before = wa;
    assert_int_equal(aocs_wheels_set_friction(&wa, 2u, AOCS_R(5.0e-5), AOCS_R(0.01)), AOCS_OK);
    assert_close(aocs_wheels_friction(&wa, 2u, AOCS_R(100.0)), (5.0e-5 * 100.0) + (0.01 * tanh(100.0 / 0.5)),
                 TOL_TIGHT);
    assert_close(aocs_wheels_friction(&wa, 1u, AOCS_R(100.0)), aocs_wheels_friction(&before, 1u, AOCS_R(100.0)),
                 0.0);
    assert_true(memcmp(wa.pinv, before.pinv, sizeof(wa.pinv)) == 0);
    assert_true(memcmp(wa.null_proj, before.null_proj, sizeof(wa.null_proj)) == 0);
    before = wa;
    /* b Omega_max + c at the motor's limit, a negative term, a NaN, a wheel beyond n, NULL */
    assert_int_equal(aocs_wheels_set_friction(&wa, 2u, AOCS_R(0.0), c.u_max_nm[2]), AOCS_ERR_WHEEL_FRICTION_EXCEEDS_LIMIT);
    assert_int_equal(aocs_wheels_set_friction(&wa, 2u, AOCS_R(-1.0e-6), AOCS_R(0.0)), AOCS_ERR_WHEEL_FRICTION_NEGATIVE);
    assert_int_equal(aocs_wheels_set_friction(&wa, 2u, (real_t)NAN, AOCS_R(0.0)), AOCS_ERR_WHEEL_FRICTION_NEGATIVE);
    assert_int_equal(aocs_wheels_set_friction(&wa, c.n, AOCS_R(0.0), AOCS_R(0.0)), AOCS_ERR_NOT_INITIALISED);
    assert_int_equal(aocs_wheels_set_friction(NULL, 0u, AOCS_R(0.0), AOCS_R(0.0)), AOCS_ERR_NULL_ARG);
    assert_true(memcmp(&wa, &before, sizeof(wa)) == 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_minimum_norm_allocation_of_the_pyramid),
        cmocka_unit_test(test_a_tachometer_far_beyond_its_range_is_rejected),
        cmocka_unit_test(test_no_motor_command_exceeds_its_limit_even_by_one_ulp),
        cmocka_unit_test(test_the_final_clamp_is_exact),
        cmocka_unit_test(test_a_failed_wheel_is_removed_and_three_still_control_every_axis),
        cmocka_unit_test(test_the_uniform_scale_keeps_the_direction),
        cmocka_unit_test(test_no_torque_drives_a_wheel_beyond_its_speed_limit),
        cmocka_unit_test(test_total_momentum_and_margin),
        cmocka_unit_test(test_the_envelope_of_the_reference_pyramid),
        cmocka_unit_test(test_the_guidance_envelope_with_the_gyroscopic_allowance),
        cmocka_unit_test(test_every_configuration_error_has_its_code),
        cmocka_unit_test(test_bad_inputs_give_a_zero_command),
        cmocka_unit_test(test_the_friction_feedforward_delivers_the_net_torque),
        cmocka_unit_test(test_the_friction_model_is_clamped_at_the_speed_limit),
        cmocka_unit_test(test_the_speed_headroom_bounds_the_net_torque),
        cmocka_unit_test(test_a_corrupted_allocation_gives_no_command_and_says_so),
        cmocka_unit_test(test_no_torque_drives_a_wheel_beyond_its_negative_speed_limit),
        cmocka_unit_test(test_the_null_space_management_gives_no_body_torque),
        cmocka_unit_test(test_the_null_space_torque_gets_half_the_room_left),
        cmocka_unit_test(test_every_friction_and_null_space_error_has_its_code),
        cmocka_unit_test(test_the_friction_model_is_replaced_in_place_and_checked),
        cmocka_unit_test(test_the_default_null_space_target_is_rest),
        cmocka_unit_test(test_the_null_space_management_of_the_largest_array),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
