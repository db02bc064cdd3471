/*
 * Momentum-management stage alone (firmware/src/momentum/, aocs/momentum/momentum.h):
 * the rows and their names; the trigger's hysteresis against a hand-evaluated sequence;
 * the magnetorquer cross-product law against an independent evaluation in double
 * (dipole perpendicular to B, torque = -k dh_perp, the per-rod saturation keeping the
 * direction); the thrusters' pulse-width modulation on a canted 12-thruster layout
 * (on-times non-negative, within the period, multiples of the quantum, none below the
 * minimum pulse; the impulse they give reproduces the requested dumping torque within
 * the minimum impulse bits); configuration errors; the executive feeding the unloading
 * torque forward into the wheels' command.
 */
#include "test_support.h"

#include <string.h>

#include "aocs/executive.h"

/* ---- independent helpers, in double ---- */
static void d_cross(const double a[3], const double b[3], double c[3])
{
    c[0] = (a[1] * b[2]) - (a[2] * b[1]);
    c[1] = (a[2] * b[0]) - (a[0] * b[2]);
    c[2] = (a[0] * b[1]) - (a[1] * b[0]);
}

static double d_dot(const double a[3], const double b[3])
{
    return (a[0] * b[0]) + (a[1] * b[1]) + (a[2] * b[2]);
}

static double d_norm(const double a[3])
{
    return sqrt(d_dot(a, a));
}

static aocs_mom_input_t input(aocs_vec3_t h, aocs_vec3_t b, double dt)
{
    aocs_mom_input_t in;
    (void)memset(&in, 0, sizeof(in));
    in.h_wheels_B_Nms = h;
    in.h_valid = 1;
    in.b_B_T = b;
    in.b_valid = 1;
    in.enabled = 1;
    in.dt_s = AOCS_R(dt);
    return in;
}

static void base_config(aocs_mom_config_t *c, aocs_mom_id_t policy)
{
    aocs_exec_config_t ecfg;
    aocs_exec_config_default(&ecfg);
    *c = ecfg.momentum;
    c->policy = (uint32_t)policy;
    c->trigger = (uint32_t)AOCS_MOM_TRIGGER_CONTINUOUS;
}

static void test_rows_and_none(void **state)
{
    (void)state;
    for (int i = 0; i < (int)AOCS_MOM_COUNT; ++i) {
        const char *name = aocs_mom_name((aocs_mom_id_t)i);
        assert_true(strlen(name) > 0u);
        assert_string_not_equal(name, "unknown");
        for (int j = 0; j < i; ++j) {
            assert_string_not_equal(name, aocs_mom_name((aocs_mom_id_t)j));
        }
    }
    assert_string_equal(aocs_mom_name(AOCS_MOM_NONE), "none");
    assert_string_equal(aocs_mom_name(AOCS_MOM_MAGNETORQUERS), "magnetorquers");
    assert_string_equal(aocs_mom_name(AOCS_MOM_THRUSTERS), "thrusters");
    assert_string_equal(aocs_mom_name(AOCS_MOM_COUNT), "unknown");
    aocs_mom_t m;
    aocs_mom_config_t cfg;
    base_config(&cfg, AOCS_MOM_NONE);
    (void)memset(&m, 0x7f, sizeof(m));
    assert_int_equal(aocs_mom_init(&m, &cfg), AOCS_OK);
    aocs_mom_input_t in = input(aocs_vec3_make(AOCS_R(5.0), AOCS_R(-3.0), AOCS_R(1.0)),
                                aocs_vec3_make(AOCS_R(2e-5), AOCS_R(0.0), AOCS_R(0.0)), 0.1);
    assert_int_equal(aocs_mom_step(&m, &in), AOCS_OK);
    aocs_mom_output_t out = aocs_mom_output(&m);
    assert_vec3_close(out.dipole_Am2, aocs_vec3_zero(), 0.0);
    assert_vec3_close(out.u_unload_B_Nm, aocs_vec3_zero(), 0.0);
    assert_int_equal(out.unloading, 0);
    assert_int_equal(out.n_events, 0);
    /* the momentum it saw is reported all the same */
    assert_vec3_close(out.h_wheels_B_Nms, in.h_wheels_B_Nms, 0.0);
    /* the default configuration is NONE, threshold trigger */
    aocs_exec_config_t ecfg;
    aocs_exec_config_default(&ecfg);
    assert_int_equal(ecfg.momentum.policy, (uint32_t)AOCS_MOM_NONE);
    assert_int_equal(ecfg.momentum.trigger, (uint32_t)AOCS_MOM_TRIGGER_THRESHOLD);
}

static void test_errors_give_zero(void **state)
{
    (void)state;
    aocs_mom_t m;
    aocs_mom_config_t bad;
    base_config(&bad, AOCS_MOM_NONE);
    bad.policy = (uint32_t)AOCS_MOM_COUNT;
    (void)memset(&m, 0x7f, sizeof(m));
    assert_int_equal(aocs_mom_init(&m, &bad), AOCS_ERR_MOMENTUM_POLICY_UNKNOWN);
    aocs_mom_input_t in = input(aocs_vec3_zero(), aocs_vec3_zero(), 0.1);
    assert_int_equal(aocs_mom_step(&m, &in), AOCS_ERR_NOT_INITIALISED);
    aocs_mom_output_t out = aocs_mom_output(&m);
    assert_vec3_close(out.dipole_Am2, aocs_vec3_zero(), 0.0);
    assert_int_equal(aocs_mom_init(NULL, &bad), AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_mom_init(&m, NULL), AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_mom_step(NULL, &in), AOCS_ERR_NULL_ARG);
    out = aocs_mom_output(NULL);
    assert_vec3_close(out.u_unload_B_Nm, aocs_vec3_zero(), 0.0);
    /* threshold trigger with h_stop >= h_start: no hysteresis */
    aocs_mom_config_t c;
    base_config(&c, AOCS_MOM_MAGNETORQUERS);
    c.k_mtq_per_s = AOCS_R(0.01);
    c.mtq_max_dipole_Am2 = aocs_vec3_make(AOCS_R(1.0), AOCS_R(1.0), AOCS_R(1.0));
    assert_int_equal(aocs_mom_init(&m, &c), AOCS_OK);
    c.trigger = (uint32_t)AOCS_MOM_TRIGGER_THRESHOLD;
    c.h_start_Nms = AOCS_R(1.0);
    c.h_stop_Nms = AOCS_R(1.0);
    assert_int_equal(aocs_mom_init(&m, &c), AOCS_ERR_MOMENTUM_CONFIG_INVALID);
    c.h_stop_Nms = AOCS_R(0.5);
    assert_int_equal(aocs_mom_init(&m, &c), AOCS_OK);
    c.trigger = 7u;
    assert_int_equal(aocs_mom_init(&m, &c), AOCS_ERR_MOMENTUM_CONFIG_INVALID);
    c.trigger = (uint32_t)AOCS_MOM_TRIGGER_COUNT; /* the first value past the rows: refused too */
    assert_int_equal(aocs_mom_init(&m, &c), AOCS_ERR_MOMENTUM_CONFIG_INVALID);
    c.trigger = (uint32_t)AOCS_MOM_TRIGGER_CONTINUOUS;
    c.k_mtq_per_s = AOCS_R(0.0);
    assert_int_equal(aocs_mom_init(&m, &c), AOCS_ERR_MOMENTUM_CONFIG_INVALID);
    c.k_mtq_per_s = AOCS_R(0.01);
    c.mtq_axes.m[2][0] = AOCS_R(1.0); /* rod 2 along x too: not unit, and not spanning */
    c.mtq_axes.m[2][2] = AOCS_R(0.0);
    assert_int_equal(aocs_mom_init(&m, &c), AOCS_ERR_MOMENTUM_CONFIG_INVALID);
    c.mtq_axes = aocs_mat3_identity();
    c.mtq_max_dipole_Am2.v[1] = AOCS_R(0.0);
    assert_int_equal(aocs_mom_init(&m, &c), AOCS_ERR_MOMENTUM_CONFIG_INVALID);
    c.mtq_max_dipole_Am2.v[1] = AOCS_R(1.0);
    c.h_target_B_Nms.v[0] = AOCS_R(NAN);
    assert_int_equal(aocs_mom_init(&m, &c), AOCS_ERR_MOMENTUM_CONFIG_INVALID);
}

/* ---- the trigger ---- */
static void test_hysteresis(void **state)
{
    (void)state;
    aocs_mom_t m;
    aocs_mom_config_t c;
    base_config(&c, AOCS_MOM_MAGNETORQUERS);
    c.trigger = (uint32_t)AOCS_MOM_TRIGGER_THRESHOLD;
    c.h_start_Nms = AOCS_R(2.0);
    c.h_stop_Nms = AOCS_R(0.5);
    c.h_target_B_Nms = aocs_vec3_make(AOCS_R(0.0), AOCS_R(1.0), AOCS_R(0.0)); /* a bias */
    c.k_mtq_per_s = AOCS_R(0.01);
    c.mtq_max_dipole_Am2 = aocs_vec3_make(AOCS_R(100.0), AOCS_R(100.0), AOCS_R(100.0));
    assert_int_equal(aocs_mom_init(&m, &c), AOCS_OK);
    /* |dh| along x (the bias is along y): start above 2, keep until below 0.5, start again above 2 */
    const double dh[] = {1.0, 1.99, 2.5, 1.5, 0.6, 0.5, 0.49, 1.5, 2.0, 2.01, 0.3};
    const int expect[] = {0, 0, 1, 1, 1, 1, 0, 0, 0, 1, 0};
    const uint32_t events[] = {0, 0, 1, 1, 1, 1, 1, 1, 1, 2, 2};
    for (size_t i = 0u; i < (sizeof(dh) / sizeof(dh[0])); ++i) {
        aocs_mom_input_t in = input(aocs_vec3_make(AOCS_R(dh[i]), AOCS_R(1.0), AOCS_R(0.0)),
                                    aocs_vec3_make(AOCS_R(0.0), AOCS_R(0.0), AOCS_R(3e-5)), 0.1);
        assert_int_equal(aocs_mom_step(&m, &in), AOCS_OK);
        assert_int_equal(m.out.unloading, expect[i]);
        assert_int_equal(m.out.n_events, events[i]);
        assert_close(m.out.dh_B_Nms.v[0], dh[i], TOL_TIGHT);
        assert_close(m.out.dh_B_Nms.v[1], 0.0, TOL_TIGHT);
        if (expect[i] == 0) {
            assert_vec3_close(m.out.dipole_Am2, aocs_vec3_zero(), 0.0);
        } else {
            assert_true(aocs_vec3_norm(m.out.dipole_Am2) > AOCS_R(0.0));
        }
    }
    /* disabled (not NOMINAL): the unload stops, nothing commanded */
    aocs_mom_input_t in = input(aocs_vec3_make(AOCS_R(3.0), AOCS_R(1.0), AOCS_R(0.0)),
                                aocs_vec3_make(AOCS_R(0.0), AOCS_R(0.0), AOCS_R(3e-5)), 0.1);
    assert_int_equal(aocs_mom_step(&m, &in), AOCS_OK);
    assert_int_equal(m.out.unloading, 1);
    in.enabled = 0;
    assert_int_equal(aocs_mom_step(&m, &in), AOCS_OK);
    assert_int_equal(m.out.unloading, 0);
    assert_vec3_close(m.out.dipole_Am2, aocs_vec3_zero(), 0.0);
    /* no wheel momentum: no unloading, and said so */
    in.enabled = 1;
    in.h_valid = 0;
    assert_int_equal(aocs_mom_step(&m, &in), AOCS_ERR_INPUT_MISSING);
    assert_int_equal(m.out.status, AOCS_ERR_INPUT_MISSING);
    assert_int_equal(m.out.unloading, 0);
    /* no field: no dipole */
    in.h_valid = 1;
    in.b_valid = 0;
    assert_int_equal(aocs_mom_step(&m, &in), AOCS_ERR_INPUT_MISSING);
    assert_vec3_close(m.out.dipole_Am2, aocs_vec3_zero(), 0.0);
    assert_vec3_close(m.out.u_unload_B_Nm, aocs_vec3_zero(), 0.0);
}

/* ---- magnetorquers ---- */

/* rod axes: x, and two unit axes in the y-z plane 10 deg off y and z (not orthogonal) */
static void canted_rods(aocs_mom_config_t *c)
{
    const double a = 10.0 * 3.14159265358979323846 / 180.0;
    c->mtq_axes = aocs_mat3_zero();
    c->mtq_axes.m[0][0] = AOCS_R(1.0);
    c->mtq_axes.m[1][1] = AOCS_R(cos(a));
    c->mtq_axes.m[1][2] = AOCS_R(sin(a));
    c->mtq_axes.m[2][1] = AOCS_R(-sin(a));
    c->mtq_axes.m[2][2] = AOCS_R(cos(a));
    c->mtq_axes.m[2][0] = AOCS_R(0.0);
}

static void mtq_case(const aocs_mom_config_t *c, test_rng_t *r, int expect_saturated)
{
    aocs_mom_t m;
    assert_int_equal(aocs_mom_init(&m, c), AOCS_OK);
    const double b_mag = test_rng_uniform(r, 1.0e-8, 5.0e-5);
    aocs_vec3_t b = test_random_vec3(r, 1.0);
    b = aocs_vec3_scale(b, AOCS_R(b_mag) / aocs_vec3_norm(b));
    const aocs_vec3_t h = test_random_vec3(r, 5.0);
    aocs_mom_input_t in = input(h, b, 0.1);
    assert_int_equal(aocs_mom_step(&m, &in), AOCS_OK);
    /* independent: dh, dh_perp, the rods' dipoles summed along their axes */
    double dh[3], bd[3], mB[3], tq[3], perp[3];
    for (int i = 0; i < 3; ++i) {
        dh[i] = (double)h.v[i] - (double)c->h_target_B_Nms.v[i];
        bd[i] = (double)b.v[i];
        mB[i] = 0.0;
    }
    for (int rod = 0; rod < 3; ++rod) {
        for (int i = 0; i < 3; ++i) {
            mB[i] += (double)m.out.dipole_Am2.v[rod] * (double)c->mtq_axes.m[rod][i];
        }
    }
    const double bn = d_norm(bd);
    const double dhb = d_dot(dh, bd) / bn;
    for (int i = 0; i < 3; ++i) {
        perp[i] = dh[i] - (dhb * bd[i] / bn);
    }
    d_cross(mB, bd, tq);
    /* the dipole is perpendicular to B */
    assert_true(fabs(d_dot(mB, bd)) <= (TOL_LOOSE * d_norm(mB) * bn) + 1e-300);
    /* its torque opposes dh_perp: tau = -s k dh_perp with 0 < s <= 1 (s = 1 when no rod saturates) */
    double s = 1.0;
    double worst = 0.0;
    for (int rod = 0; rod < 3; ++rod) {
        const double use = fabs((double)m.out.dipole_Am2.v[rod]) / (double)c->mtq_max_dipole_Am2.v[rod];
        worst = (use > worst) ? use : worst;
    }
    assert_true(worst <= 1.0 + TOL_LOOSE);
    if (expect_saturated != 0) {
        assert_close(worst, 1.0, TOL_LOOSE);
        s = -d_dot(tq, perp) / ((double)c->k_mtq_per_s * d_dot(perp, perp));
        assert_true((s > 0.0) && (s <= 1.0 + TOL_LOOSE));
    } else {
        assert_true(worst < 1.0);
    }
    for (int i = 0; i < 3; ++i) {
        assert_close(tq[i] / ((double)c->k_mtq_per_s * d_norm(perp)), -s * perp[i] / d_norm(perp), TOL_LOOSE);
    }
    /* the torque fed forward is that torque */
    for (int i = 0; i < 3; ++i) {
        assert_close((double)m.out.u_unload_B_Nm.v[i] / (d_norm(tq) + 1e-300), tq[i] / (d_norm(tq) + 1e-300), TOL_LOOSE);
    }
}

static void test_mtq_cross_product_law(void **state)
{
    (void)state;
    test_rng_t r = {0x5eed1234abcdULL};
    aocs_mom_config_t c;
    base_config(&c, AOCS_MOM_MAGNETORQUERS);
    c.k_mtq_per_s = AOCS_R(0.005);
    c.h_target_B_Nms = aocs_vec3_make(AOCS_R(0.2), AOCS_R(-0.1), AOCS_R(0.05));
    for (int rep = 0; rep < 200; ++rep) {
        /* limits far above any dipole of these cases: no saturation (k |dh| / |B| <= 0.005 * 10 / 1e-8) */
        c.mtq_max_dipole_Am2 = aocs_vec3_make(AOCS_R(1e9), AOCS_R(1e9), AOCS_R(1e9));
        c.mtq_axes = aocs_mat3_identity();
        mtq_case(&c, &r, 0);
        canted_rods(&c);
        mtq_case(&c, &r, 0);
        /* small limits: saturated, the direction kept */
        c.mtq_max_dipole_Am2 = aocs_vec3_make(AOCS_R(1e-3), AOCS_R(2e-3), AOCS_R(5e-4));
        mtq_case(&c, &r, 1);
        c.mtq_axes = aocs_mat3_identity();
        mtq_case(&c, &r, 1);
    }
}

/* Magnetorquers, continuous trigger, zero target, identity rods: gain k_per_s, rod limits max_Am2. */
static void mtq_config(aocs_mom_config_t *c, double k_per_s, aocs_vec3_t max_Am2)
{
    base_config(c, AOCS_MOM_MAGNETORQUERS);
    c->k_mtq_per_s = AOCS_R(k_per_s);
    c->h_target_B_Nms = aocs_vec3_zero();
    c->mtq_max_dipole_Am2 = max_Am2;
    c->mtq_axes = aocs_mat3_identity();
}

/*
 * dh along B (the fuzz finding f9a15516: h = 1e6 B, canted rods): the cross product dh x b is rounding only,
 * of order eps |dh|, in no particular direction; the dipole must still be perpendicular to B (before the
 * projection onto B's normal plane the angle's cosine was 0.08).
 */
static void test_mtq_dh_along_field(void **state)
{
    (void)state;
    aocs_mom_config_t c;
    aocs_mom_t m;
    mtq_config(&c, 0.001953125, aocs_vec3_make(AOCS_R(122.0703125), AOCS_R(122.0703125), AOCS_R(281.4453125)));
    c.mtq_axes.m[1][0] = AOCS_R(0.00049609375);
    c.mtq_axes.m[1][1] = AOCS_R(1.0000001678466797);
    c.mtq_axes.m[2][1] = AOCS_R(-0.0005);
    c.mtq_axes.m[2][2] = AOCS_R(0.9995);
    assert_int_equal(aocs_mom_init(&m, &c), AOCS_OK);
    const aocs_vec3_t b = aocs_vec3_make(AOCS_R(-2.3378906250000003e-05), AOCS_R(1.3242187499999996e-05),
                                         AOCS_R(-6.0e-05));
    aocs_mom_input_t in = input(aocs_vec3_scale(b, AOCS_R(1.0e6)), b, 0.1);
    assert_int_equal(aocs_mom_step(&m, &in), AOCS_OK);
    double mB[3] = {0.0, 0.0, 0.0};
    double bd[3];
    for (int rod = 0; rod < 3; ++rod) {
        for (int i = 0; i < 3; ++i) {
            mB[i] += (double)m.out.dipole_Am2.v[rod] * (double)c.mtq_axes.m[rod][i];
        }
    }
    for (int i = 0; i < 3; ++i) {
        bd[i] = (double)b.v[i];
    }
    /* perpendicular to B to the rounding of the rods' inverse (or zero) */
    assert_true(fabs(d_dot(mB, bd)) <= (TOL_LOOSE * d_norm(mB) * d_norm(bd)));
    /* and negligible: below eps |dh| k / |B| */
    assert_true(d_norm(mB) <= (1e-3 * (double)c.k_mtq_per_s * 1e6));
}

/* A magnetorquer stage of gain 0.005 1/s with identity rods of 100 A m^2 (continuous trigger, zero target). */
static void mtq_stage(aocs_mom_t *m)
{
    aocs_mom_config_t c;
    mtq_config(&c, 0.005, aocs_vec3_make(AOCS_R(100.0), AOCS_R(100.0), AOCS_R(100.0)));
    assert_int_equal(aocs_mom_init(m, &c), AOCS_OK);
}

/* The field the law divides by: [B_MIN, B_MAX] in every component's magnitude, else no dipole (the fuzz
 * finding 58377915: a field of 1e80 T made the dipole subnormal, of no direction). */
static void test_mtq_field_range(void **state)
{
    (void)state;
    aocs_mom_t m;
    mtq_stage(&m);
    const aocs_vec3_t h = aocs_vec3_make(AOCS_R(0.5), AOCS_R(0.0), AOCS_R(0.0));
    aocs_mom_input_t in = input(h, aocs_vec3_make(AOCS_R(0.0), AOCS_R(0.0), AOCS_MOM_B_MAX_T), 0.1);
    assert_int_equal(aocs_mom_step(&m, &in), AOCS_OK); /* at the limit: used */
    assert_true(m.out.dipole_Am2.v[1] < AOCS_R(0.0)); /* k (dh x B) / |B|^2 along -y */
    const double beyond[3] = {(double)AOCS_MOM_B_MAX_T * 1.001, 1e80, -0.5};
    for (int i = 0; i < 3; ++i) {
        in.b_B_T = aocs_vec3_make(AOCS_R(1e-5), AOCS_R(beyond[i]), AOCS_R(0.0));
        assert_int_equal(aocs_mom_step(&m, &in), AOCS_ERR_INPUT_MISSING);
        assert_vec3_close(m.out.dipole_Am2, aocs_vec3_zero(), 0.0);
        assert_vec3_close(m.out.u_unload_B_Nm, aocs_vec3_zero(), 0.0);
    }
    /* below B_MIN: noise only */
    in.b_B_T = aocs_vec3_make(AOCS_R(5e-13), AOCS_R(5e-13), AOCS_R(0.0));
    assert_int_equal(aocs_mom_step(&m, &in), AOCS_ERR_INPUT_MISSING);
    in.b_B_T = aocs_vec3_make(AOCS_R(1e-12), AOCS_R(1e-12), AOCS_R(0.0));
    assert_int_equal(aocs_mom_step(&m, &in), AOCS_OK);
    assert_true(aocs_vec3_norm_inf(m.out.dipole_Am2) > AOCS_R(0.0));
}

/* mtq_stage in a field of 3e-5 T along z: h_zero gives no dipole and no torque (status OK, still unloading);
 * then h_axis gives a vector (the dipole, or with torque != 0 the torque fed forward) of `expected` along
 * `axis` and exactly zero along the other two. */
static void mtq_zero_then_axis(aocs_vec3_t h_zero, aocs_vec3_t h_axis, int torque, int axis, double expected)
{
    aocs_mom_t m;
    mtq_stage(&m);
    aocs_mom_input_t in = input(h_zero, aocs_vec3_make(AOCS_R(0.0), AOCS_R(0.0), AOCS_R(3e-5)), 0.1);
    assert_int_equal(aocs_mom_step(&m, &in), AOCS_OK);
    assert_int_equal(m.out.unloading, 1);
    assert_vec3_close(m.out.dipole_Am2, aocs_vec3_zero(), 0.0);
    assert_vec3_close(m.out.u_unload_B_Nm, aocs_vec3_zero(), 0.0);
    in.h_wheels_B_Nms = h_axis;
    assert_int_equal(aocs_mom_step(&m, &in), AOCS_OK);
    const aocs_vec3_t v = (torque != 0) ? m.out.u_unload_B_Nm : m.out.dipole_Am2;
    for (int i = 0; i < 3; ++i) {
        if (i == axis) {
            assert_close((double)v.v[i], expected, TOL_LOOSE * fabs(expected));
        } else {
            assert_true(fabs((double)v.v[i]) <= 0.0);
        }
    }
}

/* A dipole below AOCS_MOM_DIPOLE_MIN_AM2 is commanded as zero: k |dh| / |B| = 0.005 * 1e-16 / 3e-5 =
 * 1.7e-14 A m^2; at dh = 1e-12 N m s the dipole is m = k (dh x B) / |B|^2 = (0, -k 1e-12 / 3e-5, 0). */
static void test_mtq_tiny_dipole_is_zero(void **state)
{
    (void)state;
    mtq_zero_then_axis(aocs_vec3_make(AOCS_R(1e-16), AOCS_R(0.0), AOCS_R(0.0)),
                       aocs_vec3_make(AOCS_R(1e-12), AOCS_R(0.0), AOCS_R(0.0)), 0, 1, -0.005 * 1e-12 / 3e-5);
}

/* dh within AOCS_MOM_PARALLEL_SIN of the field (s = 0.5e-6 in dh = (s, 0, 1) N m s, B along z): nothing to
 * unload, zero dipole; at s = 1e-5 the torque is -k dh_perp = (-k s, 0, 0). */
static void test_mtq_parallel_deadband(void **state)
{
    (void)state;
    mtq_zero_then_axis(aocs_vec3_make(AOCS_R(0.5e-6), AOCS_R(0.0), AOCS_R(1.0)),
                       aocs_vec3_make(AOCS_R(1e-5), AOCS_R(0.0), AOCS_R(1.0)), 1, 0, -0.005 * 1e-5);
}

/* ---- thrusters ---- */

#define N_THR 12

/*
 * A canted L2 layout: for each body axis k and sign, two thrusters 1.2 m either side of the centre of mass
 * along axis j firing in opposite directions along axis l (a couple about s e_k), each direction canted by
 * 8 deg towards axis k, so every thruster also pushes along k and no torque is purely about one axis.
 */
static void l2_thrusters(aocs_mom_config_t *c, double pos[N_THR][3], double dir[N_THR][3])
{
    const double cant = 8.0 * 3.14159265358979323846 / 180.0;
    int i = 0;
    for (int k = 0; k < 3; ++k) {
        const int j = (k + 1) % 3;
        const int l = (k + 2) % 3;
        for (int s = 0; s < 2; ++s) {
            const double sg = (s == 0) ? 1.0 : -1.0;
            for (int side = 0; side < 2; ++side) {
                const double sd = (side == 0) ? 1.0 : -1.0;
                for (int a = 0; a < 3; ++a) {
                    pos[i][a] = 0.0;
                    dir[i][a] = 0.0;
                }
                pos[i][j] = 1.2 * sd;
                pos[i][k] = 0.3 * sd;
                /* e_j x e_l = e_k: r = sd e_j, d = sg sd e_l gives sg e_k */
                dir[i][l] = sg * sd * cos(cant);
                dir[i][k] = sin(cant);
                double t[3];
                d_cross(pos[i], dir[i], t);
                c->thr_arm_x_m[i] = AOCS_R(t[0]);
                c->thr_arm_y_m[i] = AOCS_R(t[1]);
                c->thr_arm_z_m[i] = AOCS_R(t[2]);
                ++i;
            }
        }
    }
    c->thr_count = N_THR;
}

static void thr_config(aocs_mom_config_t *c, double pos[N_THR][3], double dir[N_THR][3])
{
    base_config(c, AOCS_MOM_THRUSTERS);
    l2_thrusters(c, pos, dir);
    c->thr_thrust_N = AOCS_R(1.0);
    c->dump_torque_Nm = AOCS_R(0.5);
    c->thr_min_on_s = AOCS_R(0.02);
    c->thr_quantum_s = AOCS_R(0.001);
}

/* The impulse of the on-times (independent: F sum_i t_i (r_i x d_i)) against the requested torque's. */
static void thr_check_step(aocs_mom_t *mp, const aocs_mom_config_t *c, double pos[N_THR][3], double dir[N_THR][3],
                           aocs_vec3_t h, double dt, uint32_t excluded)
{
    aocs_mom_t m = *mp;
    aocs_mom_input_t in = input(h, aocs_vec3_zero(), dt);
    in.b_valid = 0; /* thrusters need no field */
    assert_int_equal(aocs_mom_step(&m, &in), AOCS_OK);
    double dh[3], want[3], got[3] = {0.0, 0.0, 0.0}, slack = 0.0;
    for (int a = 0; a < 3; ++a) {
        dh[a] = (double)h.v[a] - (double)c->h_target_B_Nms.v[a];
    }
    const double dhn = d_norm(dh);
    const double mag = ((double)c->dump_torque_Nm < dhn / dt) ? (double)c->dump_torque_Nm : dhn / dt;
    const double F = (double)c->thr_thrust_N;
    const double q = (double)c->thr_quantum_s;
    const double tmin = (double)c->thr_min_on_s;
    for (int a = 0; a < 3; ++a) {
        want[a] = -mag * dh[a] / dhn * dt; /* the dumping impulse, N m s */
    }
    for (int i = 0; i < N_THR; ++i) {
        const double t = (double)m.out.thruster_on_s[i];
        double arm[3];
        d_cross(pos[i], dir[i], arm);
        if (((excluded >> i) & 1u) != 0u) {
            assert_true(!(t > 0.0) && !(t < 0.0)); /* taken out: never fired */
        }
        /* non-negative, within the period, a whole number of quanta, not below the minimum pulse */
        assert_true((t >= 0.0) && (t <= dt * (1.0 + TOL_TIGHT)));
        if (t > 0.0) {
            assert_true(t >= tmin * (1.0 - TOL_TIGHT));
            if (q > 0.0) {
                assert_close(t / q, floor((t / q) + 0.5), TOL_LOOSE);
            }
        }
        for (int a = 0; a < 3; ++a) {
            got[a] += F * t * arm[a];
        }
        /* what a thruster may be off by: a dropped pulse (t_min), half a quantum */
        slack += F * d_norm(arm) * ((tmin > (q / 2.0)) ? tmin : (q / 2.0));
    }
    double err[3];
    for (int a = 0; a < 3; ++a) {
        err[a] = got[a] - want[a];
        /* the torque fed forward is that of the on-times */
        assert_close((double)m.out.u_unload_B_Nm.v[a] * dt, got[a], TOL_LOOSE);
    }
    assert_true(d_norm(err) <= slack + (TOL_LOOSE * d_norm(want)));
    /* the impulse opposes dh */
    if (d_norm(want) > slack) {
        assert_true(d_dot(got, dh) < 0.0);
    }
}

static void thr_check_case_without(const aocs_mom_config_t *c, double pos[N_THR][3], double dir[N_THR][3],
                                   aocs_vec3_t h, double dt, uint32_t excluded)
{
    aocs_mom_t m;
    assert_int_equal(aocs_mom_init(&m, c), AOCS_OK);
    for (uint32_t i = 0u; i < N_THR; ++i) {
        if (((excluded >> i) & 1u) != 0u) {
            assert_int_equal(aocs_mom_thr_exclude(&m, i), AOCS_OK);
        }
    }
    assert_int_equal(m.thr_excluded_mask, excluded);
    thr_check_step(&m, c, pos, dir, h, dt, excluded);
}

static void thr_check_case(const aocs_mom_config_t *c, double pos[N_THR][3], double dir[N_THR][3],
                           aocs_vec3_t h, double dt)
{
    thr_check_case_without(c, pos, dir, h, dt, 0u);
}

/* A thruster taken out (fault management, docs/spec.md 5.15.8): for each one of the twelve, the dump of any
 * momentum is still the requested impulse (the same independent check as with all twelve) and the thruster
 * never fires; its torque is the configured one. Taking more out until some signed axis has no torque left is
 * refused and leaves the allocation as it was; a second exclusion of the same thruster, a thruster out of
 * range or another policy are refused too. */
static void test_thr_exclude_reallocates_over_the_rest(void **state)
{
    (void)state;
    double pos[N_THR][3], dir[N_THR][3];
    aocs_mom_config_t c;
    test_rng_t r = {0x5eed0fa11ULL};
    thr_config(&c, pos, dir);
    for (uint32_t i = 0u; i < N_THR; ++i) {
        aocs_mom_t m;
        double arm[3];
        d_cross(pos[i], dir[i], arm);
        assert_int_equal(aocs_mom_init(&m, &c), AOCS_OK);
        for (int a = 0; a < 3; ++a) {
            assert_close(aocs_mom_thr_torque_B(&m, i).v[a], (double)c.thr_thrust_N * arm[a], TOL_TIGHT);
        }
        for (int rep = 0; rep < 40; ++rep) {
            thr_check_case_without(&c, pos, dir, test_random_vec3(&r, 20.0), 1.0, 1u << i);
        }
    }
    {
        aocs_mom_t m;
        aocs_mom_t before;
        aocs_status_t st = AOCS_OK;
        uint32_t k = 0u;
        assert_int_equal(aocs_mom_init(&m, &c), AOCS_OK);
        assert_int_equal(aocs_mom_thr_exclude(&m, N_THR), AOCS_ERR_MOMENTUM_CONFIG_INVALID);
        assert_int_equal(aocs_mom_thr_exclude(&m, 3u), AOCS_OK);
        assert_int_equal(aocs_mom_thr_exclude(&m, 3u), AOCS_ERR_MOMENTUM_CONFIG_INVALID);
        /* both thrusters of every couple about -x, +y, ... in turn: at some point an axis is left bare */
        while ((st == AOCS_OK) && (k < N_THR)) {
            if (k != 3u) {
                before = m;
                st = aocs_mom_thr_exclude(&m, k);
            }
            ++k;
        }
        assert_int_equal(st, AOCS_ERR_MOMENTUM_THRUSTERS_NOT_SPANNING);
        assert_true(memcmp(&m, &before, sizeof(m)) == 0);
        assert_int_equal(aocs_mom_thr_exclude(NULL, 0u), AOCS_ERR_NULL_ARG);
        assert_close(aocs_vec3_norm(aocs_mom_thr_torque_B(NULL, 0u)), 0.0, 0.0);
        assert_close(aocs_vec3_norm(aocs_mom_thr_torque_B(&m, N_THR)), 0.0, 0.0);
    }
    {
        aocs_mom_t m;
        aocs_mom_config_t none;
        base_config(&none, AOCS_MOM_NONE);
        assert_int_equal(aocs_mom_init(&m, &none), AOCS_OK);
        assert_int_equal(aocs_mom_thr_exclude(&m, 0u), AOCS_ERR_MOMENTUM_CONFIG_INVALID);
        assert_close(aocs_vec3_norm(aocs_mom_thr_torque_B(&m, 0u)), 0.0, 0.0);
    }
}

/* Six couples without cant or offset (irassi_day's): thruster 2k and 2k + 1 give the same torque. Taking one
 * out moves its duty to its twin on every signed axis (the allocation otherwise unchanged, bit for bit: no
 * search), and the dump is still the requested impulse (the independent check). */
static void couples_config(aocs_mom_config_t *c, double pos[N_THR][3], double dir[N_THR][3])
{
    thr_config(c, pos, dir);
    for (int i = 0; i < N_THR; ++i) {
        const int k = i / 4;           /* axis of the couple's torque */
        const int j = (k + 1) % 3;
        const int l = (k + 2) % 3;
        const double sg = ((i / 2) % 2 == 0) ? 1.0 : -1.0;
        const double sd = (i % 2 == 0) ? 1.0 : -1.0;
        double t[3];
        pos[i][0] = pos[i][1] = pos[i][2] = 0.0;
        dir[i][0] = dir[i][1] = dir[i][2] = 0.0;
        pos[i][j] = 1.2 * sd;
        dir[i][l] = sg * sd;
        d_cross(pos[i], dir[i], t);
        c->thr_arm_x_m[i] = AOCS_R(t[0]);
        c->thr_arm_y_m[i] = AOCS_R(t[1]);
        c->thr_arm_z_m[i] = AOCS_R(t[2]);
    }
}

static void test_thr_exclude_moves_the_duty_to_a_twin(void **state)
{
    (void)state;
    double pos[N_THR][3] = {{0}};
    double dir[N_THR][3] = {{0}};
    aocs_mom_config_t c;
    test_rng_t r = {0x7717ULL};
    couples_config(&c, pos, dir);
    for (uint32_t i = 0u; i < N_THR; ++i) {
        aocs_mom_t m;
        aocs_mom_t before;
        assert_int_equal(aocs_mom_init(&m, &c), AOCS_OK);
        before = m;
        assert_int_equal(aocs_mom_thr_exclude(&m, i), AOCS_OK);
        for (uint32_t s = 0u; s < AOCS_MOM_AXES_SIGNED; ++s) {
            for (uint32_t n = 0u; n < N_THR; ++n) {
                const real_t want = (n == i) ? AOCS_R(0.0)
                                   : ((n == (i ^ 1u)) ? (before.thr_alloc[s][n] + before.thr_alloc[s][i])
                                                      : before.thr_alloc[s][n]);
                assert_true(!(m.thr_alloc[s][n] < want) && !(m.thr_alloc[s][n] > want));
            }
        }
        for (int rep = 0; rep < 20; ++rep) {
            thr_check_case_without(&c, pos, dir, test_random_vec3(&r, 20.0), 1.0, 1u << i);
        }
    }
}

/* Latch-valve branches (docs/spec.md 5.15.8) on the couples: thruster 2k on branch A, 2k + 1 on B
 * (mom.thr_latch_b_mask 0xAAA). Closing A moves every even thruster's duty to its twin (bit for bit, as an
 * exclusion does), zeroes the on-times A had been given this step, and the dump is still the requested impulse
 * on B alone (the independent check); reopening gives back the allocation over all twelve, bit for bit.
 * Closing B as well would leave nothing: refused, m unchanged. A branch that is not one, another policy, NULL
 * and a stage not initialised are refused; the branch of each thruster is its bit. */
static void test_thr_latch_branches(void **state)
{
    (void)state;
    double pos[N_THR][3] = {{0}};
    double dir[N_THR][3] = {{0}};
    aocs_mom_config_t c;
    aocs_mom_t m;
    aocs_mom_t before;
    test_rng_t r = {0x1a7c4ULL};
    couples_config(&c, pos, dir);
    c.thr_latch_b_mask = 0xAAAu;
    assert_int_equal(aocs_mom_init(&m, &c), AOCS_OK);
    for (uint32_t i = 0u; i < N_THR; ++i) {
        assert_int_equal(aocs_mom_thr_branch(&m, i), i % 2u);
    }
    assert_int_equal(aocs_mom_thr_branch(NULL, 1u), 0u);
    assert_int_equal(aocs_mom_thr_branch(&m, 40u), 0u);
    /* on each branch, a thruster itself or its couple's twin (no other thruster has its torque) */
    for (uint32_t i = 0u; i < N_THR; ++i) {
        assert_int_equal(aocs_mom_thr_like_on_branch(&m, i % 2u, i), i);
        assert_int_equal(aocs_mom_thr_like_on_branch(&m, 1u - (i % 2u), i), i ^ 1u);
    }
    assert_int_equal(aocs_mom_thr_like_on_branch(NULL, 0u, 1u), AOCS_MOM_THRUSTERS_MAX);
    assert_int_equal(aocs_mom_thr_like_on_branch(&m, 0u, N_THR), AOCS_MOM_THRUSTERS_MAX);
    {
        /* a step that fires thrusters of both branches, then A closes */
        aocs_mom_input_t in = input(aocs_vec3_make(AOCS_R(8.0), AOCS_R(-5.0), AOCS_R(3.0)), aocs_vec3_zero(), 1.0);
        uint32_t fired_a = 0u;
        assert_int_equal(aocs_mom_step(&m, &in), AOCS_OK);
        for (uint32_t i = 0u; i < N_THR; i += 2u) {
            fired_a += (m.out.thruster_on_s[i] > AOCS_R(0.0)) ? 1u : 0u;
        }
        assert_true(fired_a > 0u);
    }
    before = m;
    assert_int_equal(aocs_mom_latch_set(&m, 0u, 1), AOCS_OK);
    assert_int_equal(m.out.latch_closed_mask, 1u);
    assert_int_equal(m.thr_excluded_mask, 0u);
    for (uint32_t i = 0u; i < N_THR; ++i) {
        const real_t want_on = ((i % 2u) == 0u) ? AOCS_R(0.0) : before.out.thruster_on_s[i];
        assert_true(!(m.out.thruster_on_s[i] < want_on) && !(m.out.thruster_on_s[i] > want_on));
    }
    for (uint32_t s = 0u; s < AOCS_MOM_AXES_SIGNED; ++s) {
        for (uint32_t n = 0u; n < N_THR; ++n) {
            const real_t want = ((n % 2u) == 0u) ? AOCS_R(0.0) : (before.thr_alloc[s][n] + before.thr_alloc[s][n - 1u]);
            assert_true(!(m.thr_alloc[s][n] < want) && !(m.thr_alloc[s][n] > want));
        }
    }
    for (int rep = 0; rep < 40; ++rep) {
        thr_check_step(&m, &c, pos, dir, test_random_vec3(&r, 20.0), 1.0, 0x555u);
    }
    /* B too: nothing would be left */
    before = m;
    assert_int_equal(aocs_mom_latch_set(&m, 1u, 1), AOCS_ERR_MOMENTUM_THRUSTERS_NOT_SPANNING);
    assert_true(memcmp(&m, &before, sizeof(m)) == 0);
    /* reopened: the allocation over all twelve again */
    assert_int_equal(aocs_mom_latch_set(&m, 0u, 0), AOCS_OK);
    assert_int_equal(m.out.latch_closed_mask, 0u);
    assert_true(memcmp(m.thr_alloc, m.thr_alloc_full, sizeof(m.thr_alloc)) == 0);
    /* B closed with thruster 0 excluded: A's 0 gone and B's 1 shut, the +x couple is empty */
    assert_int_equal(aocs_mom_thr_exclude(&m, 0u), AOCS_OK);
    assert_int_equal(aocs_mom_thr_like_on_branch(&m, 0u, 1u), AOCS_MOM_THRUSTERS_MAX); /* excluded: none */
    assert_int_equal(aocs_mom_latch_set(&m, 1u, 1), AOCS_ERR_MOMENTUM_THRUSTERS_NOT_SPANNING);
    assert_int_equal(m.out.latch_closed_mask, 0u);
    assert_int_equal(aocs_mom_latch_set(&m, 2u, 1), AOCS_ERR_MOMENTUM_CONFIG_INVALID);
    assert_int_equal(aocs_mom_latch_set(NULL, 0u, 1), AOCS_ERR_NULL_ARG);
    {
        aocs_mom_t blank;
        aocs_mom_config_t none;
        (void)memset(&blank, 0, sizeof(blank));
        assert_int_equal(aocs_mom_latch_set(&blank, 0u, 1), AOCS_ERR_NOT_INITIALISED);
        base_config(&none, AOCS_MOM_NONE);
        assert_int_equal(aocs_mom_init(&blank, &none), AOCS_OK);
        assert_int_equal(aocs_mom_latch_set(&blank, 0u, 1), AOCS_ERR_MOMENTUM_CONFIG_INVALID);
    }
}

static void test_thr_pwm(void **state)
{
    (void)state;
    double pos[N_THR][3], dir[N_THR][3];
    aocs_mom_config_t c;
    test_rng_t r = {0xfeedbeef1234ULL};
    thr_config(&c, pos, dir);
    for (int rep = 0; rep < 300; ++rep) {
        const aocs_vec3_t h = test_random_vec3(&r, 20.0);
        thr_check_case(&c, pos, dir, h, 0.1);
        thr_check_case(&c, pos, dir, h, 1.0);
        /* small dh: the dump is limited to dh in one period */
        thr_check_case(&c, pos, dir, test_random_vec3(&r, 0.05), 0.5);
    }
    /* without quantum and minimum pulse the impulse is the requested one to rounding */
    c.thr_min_on_s = AOCS_R(0.0);
    c.thr_quantum_s = AOCS_R(0.0);
    for (int rep = 0; rep < 100; ++rep) {
        thr_check_case(&c, pos, dir, test_random_vec3(&r, 20.0), 0.1);
    }
    {
        /* any momentum to dump is dumped, well below 1 N m s too: |dh| = 0.5 N m s in a 1 s period at the
         * 0.5 N m dump torque fires, and the torque fed forward is -dh / T */
        aocs_mom_t m;
        const aocs_vec3_t h = aocs_vec3_make(AOCS_R(0.3), AOCS_R(-0.4), AOCS_R(0.0));
        aocs_mom_input_t in = input(h, aocs_vec3_zero(), 1.0);
        in.b_valid = 0;
        assert_int_equal(aocs_mom_init(&m, &c), AOCS_OK);
        assert_int_equal(aocs_mom_step(&m, &in), AOCS_OK);
        assert_vec3_close(m.out.u_unload_B_Nm, aocs_vec3_scale(h, AOCS_R(-1.0)), TOL_LOOSE);
    }
    /* a dump torque beyond what the thrusters give in a period: the duties scaled by the largest, the
     * direction kept; for the momentum along each signed axis, the diagonals and one oblique, and with the
     * thrusters numbered otherwise (0 and 1 swapped: then thruster 0 carries the -x dump): the on-times are
     * the same ones, renumbered (to one quantum) */
    c.dump_torque_Nm = AOCS_R(100.0);
    aocs_mom_config_t swapped = c;
    swapped.thr_arm_x_m[0] = c.thr_arm_x_m[1];
    swapped.thr_arm_y_m[0] = c.thr_arm_y_m[1];
    swapped.thr_arm_z_m[0] = c.thr_arm_z_m[1];
    swapped.thr_arm_x_m[1] = c.thr_arm_x_m[0];
    swapped.thr_arm_y_m[1] = c.thr_arm_y_m[0];
    swapped.thr_arm_z_m[1] = c.thr_arm_z_m[0];
    for (int k = 0; k < 28; ++k) {
        /* h = 30 (a, b, c), a, b, c in {-1, 0, 1}, not all 0; and (30, -10, 5) */
        const int a3[3] = {(k % 3) - 1, ((k / 3) % 3) - 1, (k / 9) - 1};
        const aocs_vec3_t h = (k == 27) ? aocs_vec3_make(AOCS_R(30.0), AOCS_R(-10.0), AOCS_R(5.0))
                                        : aocs_vec3_make((real_t)(30 * a3[0]), (real_t)(30 * a3[1]), (real_t)(30 * a3[2]));
        if ((k != 27) && (a3[0] == 0) && (a3[1] == 0) && (a3[2] == 0)) {
            continue;
        }
        aocs_mom_t m;
        aocs_mom_t m2;
        aocs_mom_input_t in = input(h, aocs_vec3_zero(), 0.1);
        assert_int_equal(aocs_mom_init(&m, &c), AOCS_OK);
        assert_int_equal(aocs_mom_step(&m, &in), AOCS_OK);
        assert_int_equal(aocs_mom_init(&m2, &swapped), AOCS_OK);
        assert_int_equal(aocs_mom_step(&m2, &in), AOCS_OK);
        real_t tmax = AOCS_R(0.0);
        for (int i = 0; i < N_THR; ++i) {
            const int j = (i < 2) ? (1 - i) : i;
            tmax = (m.out.thruster_on_s[i] > tmax) ? m.out.thruster_on_s[i] : tmax;
            assert_true(fabs((double)m2.out.thruster_on_s[j] - (double)m.out.thruster_on_s[i]) <=
                        (double)c.thr_quantum_s + 1e-6);
        }
        assert_close(tmax, 0.1, TOL_TIGHT);
        const aocs_vec3_t u = m.out.u_unload_B_Nm;
        for (int a = 0; a < 3; ++a) {
            assert_close(u.v[a] / aocs_vec3_norm(u), -in.h_wheels_B_Nms.v[a] / aocs_vec3_norm(in.h_wheels_B_Nms),
                         TOL_LOOSE);
        }
    }
}

/* A torque below the minimum impulse bit per period: nothing fires at first, the carried on-time fires
 * later, and over many periods the impulse follows the requested one within one minimum pulse per thruster. */
static void test_thr_small_torque_carried(void **state)
{
    (void)state;
    double pos[N_THR][3], dir[N_THR][3];
    aocs_mom_config_t c;
    thr_config(&c, pos, dir);
    c.dump_torque_Nm = AOCS_R(0.05); /* duties ~0.02-0.04: 2-4 ms a period, below the 20 ms pulse */
    aocs_mom_t m;
    assert_int_equal(aocs_mom_init(&m, &c), AOCS_OK);
    const aocs_vec3_t h = aocs_vec3_make(AOCS_R(3.0), AOCS_R(-2.0), AOCS_R(1.0));
    aocs_mom_input_t in = input(h, aocs_vec3_zero(), 0.1);
    double got[3] = {0.0, 0.0, 0.0}, want[3], slack = 0.0, fired = 0.0;
    const double hn = (double)aocs_vec3_norm(h);
    const int steps = 2000;
    assert_int_equal(aocs_mom_step(&m, &in), AOCS_OK);
    for (int i = 0; i < N_THR; ++i) {
        assert_true(!(m.out.thruster_on_s[i] > AOCS_R(0.0))); /* first period: all below the pulse */
    }
    for (int k = 0; k < steps; ++k) {
        if (k > 0) {
            assert_int_equal(aocs_mom_step(&m, &in), AOCS_OK);
        }
        for (int i = 0; i < N_THR; ++i) {
            double arm[3];
            d_cross(pos[i], dir[i], arm);
            const double t = (double)m.out.thruster_on_s[i];
            fired += t;
            for (int a = 0; a < 3; ++a) {
                got[a] += (double)c.thr_thrust_N * t * arm[a];
            }
        }
    }
    for (int i = 0; i < N_THR; ++i) {
        double arm[3];
        d_cross(pos[i], dir[i], arm);
        slack += (double)c.thr_thrust_N * d_norm(arm) * ((double)c.thr_min_on_s + (double)c.thr_quantum_s);
    }
    double err[3];
    for (int a = 0; a < 3; ++a) {
        want[a] = -0.05 * (double)h.v[a] / hn * 0.1 * steps;
        err[a] = got[a] - want[a];
    }
    assert_true(fired > 0.0);
    assert_true(d_norm(err) <= slack);
    assert_true(d_norm(want) > 10.0 * slack); /* so the bound says something */
}

/* An unload that ends owes nothing: the on-time carried below the minimum pulse (every thruster's, the first
 * one's too) is dropped when the stage stops unloading, so the next unload starts from none. */
static void test_thr_an_ended_unload_carries_nothing(void **state)
{
    (void)state;
    double pos[N_THR][3], dir[N_THR][3];
    aocs_mom_config_t c;
    thr_config(&c, pos, dir);
    c.dump_torque_Nm = AOCS_R(0.05); /* duties below the 20 ms pulse: carried */
    int found = 0;
    for (int k = 0; (k < 8) && (found == 0); ++k) {
        aocs_mom_t m;
        const aocs_vec3_t h = aocs_vec3_make((real_t)(((k & 1) != 0) ? -3.0 : 3.0),
                                             (real_t)(((k & 2) != 0) ? 2.0 : -2.0),
                                             (real_t)(((k & 4) != 0) ? -1.0 : 1.0));
        aocs_mom_input_t in = input(h, aocs_vec3_zero(), 0.1);
        in.b_valid = 0;
        assert_int_equal(aocs_mom_init(&m, &c), AOCS_OK);
        assert_int_equal(aocs_mom_step(&m, &in), AOCS_OK);
        if (m.thr_residual_s[0] > AOCS_R(0.0)) {
            found = 1;
            in.enabled = 0; /* the unload ends */
            assert_int_equal(aocs_mom_step(&m, &in), AOCS_OK);
            assert_int_equal(m.out.unloading, 0);
            for (int i = 0; i < N_THR; ++i) {
                assert_true(!(m.thr_residual_s[i] > AOCS_R(0.0)) && !(m.thr_residual_s[i] < AOCS_R(0.0)));
            }
        }
    }
    assert_int_equal(found, 1); /* some dump direction leaves thruster 0 an on-time to carry */
}

static void test_thr_config_errors(void **state)
{
    (void)state;
    double pos[N_THR][3], dir[N_THR][3];
    aocs_mom_config_t c;
    aocs_mom_t m;
    thr_config(&c, pos, dir);
    assert_int_equal(aocs_mom_init(&m, &c), AOCS_OK);
    /* three thrusters giving +x, +y, +z: nothing gives -x */
    aocs_mom_config_t half = c;
    for (int i = 0; i < N_THR; ++i) {
        half.thr_arm_x_m[i] = AOCS_R((i == 0) ? 1.0 : 0.0);
        half.thr_arm_y_m[i] = AOCS_R((i == 1) ? 1.0 : 0.0);
        half.thr_arm_z_m[i] = AOCS_R((i == 2) ? 1.0 : 0.0);
    }
    half.thr_count = 3u;
    assert_int_equal(aocs_mom_init(&m, &half), AOCS_ERR_MOMENTUM_THRUSTERS_NOT_SPANNING);
    half.thr_arm_x_m[3] = AOCS_R(-1.0);
    half.thr_arm_y_m[3] = AOCS_R(-1.0);
    half.thr_arm_z_m[3] = AOCS_R(-1.0);
    half.thr_count = 4u; /* a fourth against the diagonal: every signed axis (a simplex) */
    assert_int_equal(aocs_mom_init(&m, &half), AOCS_OK);
    aocs_mom_config_t bad = c;
    bad.thr_count = 13u;
    assert_int_equal(aocs_mom_init(&m, &bad), AOCS_ERR_MOMENTUM_CONFIG_INVALID);
    /* thrusters that give no torque at all (every arm zero): a configuration error, not a set that fails to
     * span (the allocation's scale, the largest torque, would be 0) */
    bad = c;
    for (int i = 0; i < N_THR; ++i) {
        bad.thr_arm_x_m[i] = AOCS_R(0.0);
        bad.thr_arm_y_m[i] = AOCS_R(0.0);
        bad.thr_arm_z_m[i] = AOCS_R(0.0);
    }
    assert_int_equal(aocs_mom_init(&m, &bad), AOCS_ERR_MOMENTUM_CONFIG_INVALID);
    bad = c;
    bad.thr_thrust_N = AOCS_R(0.0);
    assert_int_equal(aocs_mom_init(&m, &bad), AOCS_ERR_MOMENTUM_CONFIG_INVALID);
    bad = c;
    bad.dump_torque_Nm = AOCS_R(-1.0);
    assert_int_equal(aocs_mom_init(&m, &bad), AOCS_ERR_MOMENTUM_CONFIG_INVALID);
    bad = c;
    bad.thr_arm_y_m[3] = AOCS_R(INFINITY);
    assert_int_equal(aocs_mom_init(&m, &bad), AOCS_ERR_MOMENTUM_CONFIG_INVALID);
    bad = c;
    bad.thr_quantum_s = AOCS_R(NAN);
    assert_int_equal(aocs_mom_init(&m, &bad), AOCS_ERR_MOMENTUM_CONFIG_INVALID);
    /* a latch-valve bit for a thruster that is not there */
    bad = c;
    bad.thr_latch_b_mask = 1u << N_THR;
    assert_int_equal(aocs_mom_init(&m, &bad), AOCS_ERR_MOMENTUM_CONFIG_INVALID);
    bad.thr_latch_b_mask = (1u << N_THR) - 1u; /* every one on B: valid */
    assert_int_equal(aocs_mom_init(&m, &bad), AOCS_OK);
}

/* ---- in the executive: the unloading torque is taken off the wheels' command ---- */
static void exec_with_wheels(aocs_exec_config_t *cfg)
{
    aocs_exec_config_default(cfg);
    cfg->law = AOCS_LAW_QUAT_PD;
    cfg->period_s = AOCS_R(0.1);
    cfg->laws.quat_pd.kp = AOCS_R(1.0);
    cfg->laws.quat_pd.kd = AOCS_R(10.0);
    cfg->u_max_axis = aocs_vec3_make(AOCS_R(5.0), AOCS_R(5.0), AOCS_R(5.0));
    cfg->wheels.n = 3u;
    for (uint32_t i = 0u; i < 3u; ++i) {
        cfg->wheels.axis_B[i] = aocs_vec3_zero();
        cfg->wheels.axis_B[i].v[i] = AOCS_R(1.0);
        cfg->wheels.js_kgm2[i] = AOCS_R(0.1);
        cfg->wheels.u_max_nm[i] = AOCS_R(5.0);
        cfg->wheels.omega_max_radps[i] = AOCS_R(600.0);
    }
    cfg->wheels.inertia_B_kgm2 = aocs_mat3_identity();
}

static void test_exec_feeds_unloading_forward(void **state)
{
    (void)state;
    double pos[N_THR][3], dir[N_THR][3];
    aocs_exec_config_t cfg;
    exec_with_wheels(&cfg);
    thr_config(&cfg.momentum, pos, dir);
    cfg.momentum.dump_torque_Nm = AOCS_R(1.0);
    cfg.momentum.trigger = (uint32_t)AOCS_MOM_TRIGGER_THRESHOLD;
    cfg.momentum.h_start_Nms = AOCS_R(5.0);
    cfg.momentum.h_stop_Nms = AOCS_R(1.0);
    aocs_exec_t exec;
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    aocs_exec_input_t in;
    aocs_exec_output_t out;
    aocs_mom_output_t mom;
    (void)memset(&in, 0, sizeof(in));
    in.valid = AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE;
    in.q_BN = aocs_quat_identity();
    /* wheels at 100, -50, 30 rad/s: h = 0.1 * those = (10, -5, 3) N m s, above h_start */
    in.wheel_speed_radps[0] = AOCS_R(100.0);
    in.wheel_speed_radps[1] = AOCS_R(-50.0);
    in.wheel_speed_radps[2] = AOCS_R(30.0);
    for (uint32_t k = 1u; k <= 3u; ++k) {
        in.tick = k;
        in.t_sensor_ns = (uint64_t)k * 100000000u;
        assert_int_equal(aocs_quat_normalize(aocs_quat_make(AOCS_R(0.001), AOCS_R(-0.002), AOCS_R(0.0005), AOCS_R(1.0)),
                                             &in.q_BN), AOCS_OK);
        assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
        mom = aocs_exec_momentum(&exec);
        assert_int_equal(out.mode, AOCS_EXEC_MODE_NOMINAL);
        assert_int_equal(mom.unloading, 1);
        assert_int_equal(mom.n_events, 1u);
        assert_vec3_close(mom.h_wheels_B_Nms, aocs_vec3_make(AOCS_R(10.0), AOCS_R(-5.0), AOCS_R(3.0)), TOL_TIGHT);
        assert_true(aocs_vec3_norm(mom.u_unload_B_Nm) > AOCS_R(0.1));
        /* the wheels deliver the law's torque minus the unloading torque: the body sees the law's */
        assert_vec3_close(aocs_vec3_add(out.u_cmd, mom.u_unload_B_Nm), out.u_unsat, TOL_TIGHT);
        /* and the unloading torque opposes h */
        assert_true(aocs_vec3_dot(mom.u_unload_B_Nm, mom.h_wheels_B_Nms) < AOCS_R(0.0));
    }
    /* a period without a sample while unloading: no momentum measured, the unload stops, nothing fires */
    {
        aocs_exec_t held = exec;
        assert_int_equal(aocs_exec_step_no_input(&held, &out), AOCS_OK);
        mom = aocs_exec_momentum(&held);
        assert_int_equal(mom.status, AOCS_ERR_INPUT_MISSING); /* the stage was given no momentum, not a zero one */
        assert_close(aocs_vec3_norm(mom.h_wheels_B_Nms), 0.0, 0.0);
        assert_int_equal(mom.unloading, 0);
        assert_close(aocs_vec3_norm(mom.u_unload_B_Nm), 0.0, 0.0);
        for (uint32_t i = 0u; i < AOCS_MOM_THRUSTERS_MAX; ++i) {
            assert_true(!(mom.thruster_on_s[i] > AOCS_R(0.0)));
        }
    }
    /* STANDBY: nothing fires */
    assert_int_equal(aocs_exec_select(&exec, AOCS_LAW_NONE, NULL), AOCS_OK);
    in.tick = 4u;
    in.t_sensor_ns = 400000000u;
    assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
    mom = aocs_exec_momentum(&exec);
    assert_int_equal(mom.unloading, 0);
    for (uint32_t i = 0u; i < AOCS_MOM_THRUSTERS_MAX; ++i) {
        assert_true(!(mom.thruster_on_s[i] > AOCS_R(0.0)));
    }
    /* the accessor is total */
    mom = aocs_exec_momentum(NULL);
    assert_int_equal(mom.n_events, 0u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rows_and_none),
        cmocka_unit_test(test_errors_give_zero),
        cmocka_unit_test(test_hysteresis),
        cmocka_unit_test(test_mtq_cross_product_law),
        cmocka_unit_test(test_mtq_dh_along_field),
        cmocka_unit_test(test_mtq_field_range),
        cmocka_unit_test(test_mtq_tiny_dipole_is_zero),
        cmocka_unit_test(test_mtq_parallel_deadband),
        cmocka_unit_test(test_thr_pwm),
        cmocka_unit_test(test_thr_exclude_reallocates_over_the_rest),
        cmocka_unit_test(test_thr_exclude_moves_the_duty_to_a_twin),
        cmocka_unit_test(test_thr_latch_branches),
        cmocka_unit_test(test_thr_small_torque_carried),
        cmocka_unit_test(test_thr_an_ended_unload_carries_nothing),
        cmocka_unit_test(test_thr_config_errors),
        cmocka_unit_test(test_exec_feeds_unloading_forward),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
