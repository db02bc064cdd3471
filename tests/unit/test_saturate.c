/*
 * Saturation helpers (saturate.h): exact bounds, direction preservation,
 * continuity / monotonicity / slope of the scalar saturations, and the
 * documented behaviour for NaN, Inf and invalid limits.
 * Expected values come from the definitions evaluated here in double.
 */
#include "law_test_support.h"
#include "exact_norm.h"

#include "aocs/control/saturate.h"

#if defined(AOCS_REAL_IS_FLOAT)
#define REAL_EPS_D 1.1920929e-07
#define HUGE_REAL 1.0e37
#else
#define REAL_EPS_D 2.220446049250313e-16
#define HUGE_REAL 1.0e300
#endif

/* exact equality without -Wfloat-equal; SAME() casts both sides explicitly */
#define SAME(a, b) same((double)(a), (double)(b))
static int same(double a, double b)
{
    return (!(a < b) && !(a > b)) ? 1 : 0;
}

/* Euclidean norm in double (exact enough for float components; double ulp for double) */
static double norm_d(aocs_vec3_t v)
{
    double a = (double)v.v[0];
    double b = (double)v.v[1];
    double c = (double)v.v[2];
    double m = fmax(fabs(a), fmax(fabs(b), fabs(c)));
    if (!(m > 0.0)) {
        return 0.0;
    }
    a /= m;
    b /= m;
    c /= m;
    return m * sqrt(a * a + b * b + c * c);
}

/* the exact norm for the bound checks: exact_norm.h (shared with the executive tests and fuzz targets) */

static void test_clamp_per_axis_values(void **state)
{
    (void)state;
    int sat = -1;
    aocs_vec3_t lim = aocs_vec3_make(AOCS_R(1.0), AOCS_R(2.0), AOCS_R(0.5));
    aocs_vec3_t out = aocs_sat_clamp_per_axis(aocs_vec3_make(AOCS_R(3.0), AOCS_R(-2.5), AOCS_R(0.25)), lim, &sat);
    assert_true(SAME(out.v[0], 1.0));
    assert_true(SAME(out.v[1], -2.0));
    assert_true(SAME(out.v[2], 0.25));
    assert_int_equal(sat, 1);

    out = aocs_sat_clamp_per_axis(aocs_vec3_make(AOCS_R(-1.0), AOCS_R(2.0), AOCS_R(-0.5)), lim, &sat);
    assert_true(SAME(out.v[0], -1.0));
    assert_true(SAME(out.v[1], 2.0)); /* exactly at the limit: unchanged, not saturated */
    assert_true(SAME(out.v[2], -0.5));
    assert_int_equal(sat, 0);

    /* NULL flag is allowed */
    out = aocs_sat_clamp_per_axis(aocs_vec3_make(AOCS_R(5.0), AOCS_R(0.0), AOCS_R(0.0)), lim, NULL);
    assert_true(SAME(out.v[0], 1.0));
}

static void test_clamp_per_axis_nonfinite(void **state)
{
    (void)state;
    int sat = 0;
    aocs_vec3_t lim = aocs_vec3_make(AOCS_R(1.0), AOCS_R(1.0), AOCS_R(1.0));
    aocs_vec3_t out = aocs_sat_clamp_per_axis(aocs_vec3_make((real_t)NAN, (real_t)INFINITY, (real_t)-INFINITY), lim, &sat);
    assert_true(SAME(out.v[0], 0.0));
    assert_true(SAME(out.v[1], 1.0));
    assert_true(SAME(out.v[2], -1.0));
    assert_int_equal(sat, 1);

    /* limit NaN or <= 0 allows nothing; +Inf is no limit */
    lim = aocs_vec3_make((real_t)NAN, AOCS_R(-1.0), (real_t)INFINITY);
    out = aocs_sat_clamp_per_axis(aocs_vec3_make(AOCS_R(0.3), AOCS_R(0.3), AOCS_R(123.0)), lim, &sat);
    assert_true(SAME(out.v[0], 0.0));
    assert_true(SAME(out.v[1], 0.0));
    assert_true(SAME(out.v[2], 123.0));
    assert_int_equal(sat, 1);
}

static void test_scale_to_norm_random(void **state)
{
    (void)state;
    test_rng_t rng = {0x5a7u};
    int n_scaled = 0;
    for (int k = 0; k < 20000; ++k) {
        double mag = pow(10.0, test_rng_uniform(&rng, -3.0, 4.0));
        aocs_vec3_t u = test_random_vec3(&rng, mag);
        real_t max_norm = (real_t)pow(10.0, test_rng_uniform(&rng, -2.0, 2.0));
        int sat = -1;
        aocs_vec3_t out = aocs_sat_scale_to_norm(u, max_norm, &sat);
        double nu = norm_d(u);
        double no = norm_d(out);
        /* exact bound, whatever the rounding: the true norm of the result never exceeds the limit */
        assert_true(exact_norm(out) <= (long double)max_norm);
        if (nu > (double)max_norm * (1.0 + 4.0 * REAL_EPS_D)) {
            ++n_scaled;
            assert_int_equal(sat, 1);
            /* on the bound: below it by at most the 8 eps margin and the pull-back steps */
            assert_true(no >= (double)max_norm * (1.0 - 24.0 * REAL_EPS_D));
            /* direction kept: cross product ~0 and same sense */
            double ud[3];
            double od[3];
            for (int i = 0; i < 3; ++i) {
                ud[i] = (double)u.v[i];
                od[i] = (double)out.v[i];
            }
            double cx = ud[1] * od[2] - ud[2] * od[1];
            double cy = ud[2] * od[0] - ud[0] * od[2];
            double cz = ud[0] * od[1] - ud[1] * od[0];
            double cn = sqrt(cx * cx + cy * cy + cz * cz);
            assert_true(cn <= 8.0 * REAL_EPS_D * nu * no);
            double dot = ud[0] * od[0] + ud[1] * od[1] + ud[2] * od[2];
            assert_true(dot > 0.0);
        } else if (nu < (double)max_norm * (1.0 - 16.0 * REAL_EPS_D)) {
            assert_int_equal(sat, 0);
            for (int i = 0; i < 3; ++i) {
                assert_true(SAME(out.v[i], u.v[i]));
            }
        } else {
            /* within the margin of the bound: scaled or not, the exact bound above holds */
        }
    }
    assert_true(n_scaled > 1000); /* the branch under test was exercised */
}

/* 10^e for e uniform in [lo, hi), as real_t */
static real_t pow10_real(test_rng_t *rng, double lo, double hi)
{
    return (real_t)pow(10.0, test_rng_uniform(rng, lo, hi));
}

#if defined(AOCS_REAL_IS_FLOAT)
#define EXP_RANGE 37.0  /* |x| from 1e-37 to 1e37: normal floats */
#define LIMIT_EXP 30.0
#else
#define EXP_RANGE 300.0
#define LIMIT_EXP 250.0
#endif

/*
 * Exactness at every scale: components of unrelated magnitudes (one 1e300,
 * one 1e-300 in double; 1e37 / 1e-37 in float) against limits from 1e-250 to
 * 1e250 (float 1e-30 .. 1e30): the exact norm of the result never exceeds
 * the limit. Before the scale-aware computation, rounding let it exceed by
 * an ulp or more.
 */
static void test_scale_to_norm_exact_at_every_scale(void **state)
{
    (void)state;
    test_rng_t rng = {0xa11ced5u};
    for (int k = 0; k < 200000; ++k) {
        aocs_vec3_t u;
        for (int i = 0; i < 3; ++i) {
            real_t mag = pow10_real(&rng, -EXP_RANGE, EXP_RANGE);
            u.v[i] = (test_rng_uniform(&rng, 0.0, 1.0) < 0.5) ? -mag : mag;
        }
        if ((k % 3) == 0) {
            /* two equal components near the limit: the rounding of the scaling matters most */
            u.v[1] = u.v[0];
        }
        real_t max_norm = pow10_real(&rng, -LIMIT_EXP, LIMIT_EXP);
        if ((k % 5) == 0) {
            max_norm = (real_t)(norm_d(u) * (1.0 - test_rng_uniform(&rng, 0.0, 64.0) * REAL_EPS_D));
            if (!(max_norm > AOCS_R(0.0)) || !(isfinite(max_norm) != 0)) {
                continue;
            }
        }
        int sat = -1;
        aocs_vec3_t out = aocs_sat_scale_to_norm(u, max_norm, &sat);
        if (!(exact_norm(out) <= (long double)max_norm)) {
            print_error("k=%d u=(%.17g %.17g %.17g) max_norm=%.17g: |out| = %.21Lg\n", k, (double)u.v[0],
                        (double)u.v[1], (double)u.v[2], (double)max_norm, exact_norm(out));
            fail();
        }
        assert_int_equal(aocs_sat_norm_above(out, max_norm), 0);
    }
}

static void test_norm_above(void **state)
{
    (void)state;
    /* (3, 4, 0): norm 5 */
    aocs_vec3_t v = aocs_vec3_make(AOCS_R(3.0), AOCS_R(-4.0), AOCS_R(0.0));
    assert_int_equal(aocs_sat_norm_above(v, AOCS_R(4.9)), 1);
    assert_int_equal(aocs_sat_norm_above(v, AOCS_R(5.1)), 0);
    assert_int_equal(aocs_sat_norm_above(v, (real_t)INFINITY), 0);
    assert_int_equal(aocs_sat_norm_above(v, (real_t)NAN), 1);
    assert_int_equal(aocs_sat_norm_above(aocs_vec3_zero(), AOCS_R(0.0)), 0);
    assert_int_equal(aocs_sat_norm_above(aocs_vec3_make((real_t)INFINITY, AOCS_R(0.0), AOCS_R(0.0)), AOCS_R(1.0)), 1);
    /* no overflow of |v|^2: huge components are compared, not squared */
    v = aocs_vec3_make((real_t)HUGE_REAL, (real_t)HUGE_REAL, AOCS_R(0.0));
    assert_int_equal(aocs_sat_norm_above(v, (real_t)HUGE_REAL), 1);
    assert_int_equal(aocs_sat_norm_above(v, (real_t)(2.0 * HUGE_REAL)), 0);
    /* no underflow of |v|^2 either: 1e-30 (float) / 1e-200 (double) components */
#if defined(AOCS_REAL_IS_FLOAT)
    const real_t tiny = AOCS_R(1e-30);
#else
    const real_t tiny = AOCS_R(1e-200);
#endif
    v = aocs_vec3_make(tiny, tiny, tiny); /* norm sqrt(3) tiny */
    assert_int_equal(aocs_sat_norm_above(v, tiny * AOCS_R(1.7)), 1);
    assert_int_equal(aocs_sat_norm_above(v, tiny * AOCS_R(1.75)), 0);
}

static void test_scale_to_norm_hand_value(void **state)
{
    (void)state;
    int sat = 0;
    /* (3, 4, 0) has norm 5; to norm 1 gives (0.6, 0.8, 0) */
    aocs_vec3_t out = aocs_sat_scale_to_norm(aocs_vec3_make(AOCS_R(3.0), AOCS_R(-4.0), AOCS_R(0.0)), AOCS_R(1.0), &sat);
    assert_close(out.v[0], 0.6, TOL_TIGHT);
    assert_close(out.v[1], -0.8, TOL_TIGHT);
    assert_true(SAME(out.v[2], 0.0));
    assert_int_equal(sat, 1);
}

static void test_scale_to_norm_huge_and_nonfinite(void **state)
{
    (void)state;
    int sat = 0;
    /* |u|^2 overflows real_t: still scaled along its direction */
    aocs_vec3_t out = aocs_sat_scale_to_norm(
        aocs_vec3_make((real_t)HUGE_REAL, (real_t)-HUGE_REAL, (real_t)HUGE_REAL), AOCS_R(2.0), &sat);
    double c = 2.0 / sqrt(3.0);
    assert_close(out.v[0], c, TOL_TIGHT);
    assert_close(out.v[1], -c, TOL_TIGHT);
    assert_close(out.v[2], c, TOL_TIGHT);
    assert_int_equal(sat, 1);

    /* Inf components give the direction of the infinite ones */
    out = aocs_sat_scale_to_norm(aocs_vec3_make((real_t)INFINITY, AOCS_R(1.0), (real_t)-INFINITY), AOCS_R(1.0), &sat);
    assert_close(out.v[0], 1.0 / sqrt(2.0), TOL_TIGHT);
    assert_true(SAME(out.v[1], 0.0));
    assert_close(out.v[2], -1.0 / sqrt(2.0), TOL_TIGHT);
    assert_int_equal(sat, 1);

    /* NaN anywhere: zero command */
    out = aocs_sat_scale_to_norm(aocs_vec3_make(AOCS_R(0.1), (real_t)NAN, AOCS_R(0.0)), AOCS_R(1.0), &sat);
    for (int i = 0; i < 3; ++i) {
        assert_true(SAME(out.v[i], 0.0));
    }
    assert_int_equal(sat, 1);

    /* invalid max_norm: zero command; NaN max_norm too */
    out = aocs_sat_scale_to_norm(aocs_vec3_make(AOCS_R(0.1), AOCS_R(0.0), AOCS_R(0.0)), AOCS_R(-1.0), &sat);
    assert_true(SAME(out.v[0], 0.0));
    assert_int_equal(sat, 1);
    out = aocs_sat_scale_to_norm(aocs_vec3_make(AOCS_R(0.1), AOCS_R(0.0), AOCS_R(0.0)), (real_t)NAN, &sat);
    assert_true(SAME(out.v[0], 0.0));

    /* +Inf max_norm: no limit */
    out = aocs_sat_scale_to_norm(aocs_vec3_make(AOCS_R(1e6), AOCS_R(0.0), AOCS_R(0.0)), (real_t)INFINITY, &sat);
    assert_true(SAME(out.v[0], 1e6));
    assert_int_equal(sat, 0);
}

/* independent evaluation of the documented linear saturation, in double: ref_linear_sat (law_test_support.h) */

static void test_linear_plain_clamp_when_l_equals_m(void **state)
{
    (void)state;
    const real_t m = AOCS_R(0.05);
    assert_true(SAME(aocs_sat_linear(AOCS_R(0.03), m, m), (double)AOCS_R(0.03)));
    assert_true(SAME(aocs_sat_linear(AOCS_R(0.2), m, m), (double)m));
    assert_true(SAME(aocs_sat_linear(AOCS_R(-7.0), m, m), -(double)m));
    assert_true(SAME(aocs_sat_linear((real_t)INFINITY, m, m), (double)m));
}

static void test_linear_values_continuity_monotonic(void **state)
{
    (void)state;
    const real_t l = AOCS_R(0.04);
    const real_t m = AOCS_R(0.06);
    /* formula values */
    const double xs[] = {0.0, 0.01, -0.039, 0.05, -0.05, 0.07, 0.2, -3.0};
    for (size_t i = 0; i < sizeof(xs) / sizeof(xs[0]); ++i) {
        assert_close(aocs_sat_linear((real_t)xs[i], l, m), ref_linear_sat((double)(real_t)xs[i], (double)l, (double)m),
                     TOL_TIGHT);
    }
    /* continuity and unit slope at l from both sides */
    const double h = 1e-4;
    double at_l = (double)aocs_sat_linear(l, l, m);
    double above = (double)aocs_sat_linear((real_t)((double)l + h), l, m);
    double below = (double)aocs_sat_linear((real_t)((double)l - h), l, m);
    assert_close(at_l, (double)l, TOL_TIGHT);
    assert_close((above - at_l) / h, 1.0, 1e-2);
    assert_close((at_l - below) / h, 1.0, 1e-2);
    /* monotone (non-decreasing) and bounded on a fine grid, odd */
    double prev = -1e300;
    for (int k = -20000; k <= 20000; ++k) {
        real_t x = (real_t)(1e-5 * (double)k);
        double y = (double)aocs_sat_linear(x, l, m);
        assert_true(y >= prev);
        assert_true(fabs(y) <= (double)m);
        assert_true(SAME(y, -(double)aocs_sat_linear(-x, l, m)));
        prev = y;
    }
    /* strictly increasing just above l (not a clamp) */
    assert_true(aocs_sat_linear(AOCS_R(0.05), l, m) < aocs_sat_linear(AOCS_R(0.06), l, m));
    /* bounded for huge and infinite arguments */
    assert_true(fabs((double)aocs_sat_linear((real_t)HUGE_REAL, l, m)) <= (double)m);
    assert_true(SAME(aocs_sat_linear((real_t)INFINITY, l, m), (double)m));
    assert_true(SAME(aocs_sat_linear((real_t)-INFINITY, l, m), -(double)m));
}

static void test_linear_invalid_params(void **state)
{
    (void)state;
    assert_true(SAME(aocs_sat_linear((real_t)NAN, AOCS_R(1.0), AOCS_R(2.0)), 0.0));
    assert_true(SAME(aocs_sat_linear(AOCS_R(1.0), AOCS_R(1.0), AOCS_R(0.0)), 0.0));
    assert_true(SAME(aocs_sat_linear(AOCS_R(1.0), AOCS_R(1.0), (real_t)NAN), 0.0));
    /* l NaN or < 0 taken as 0: m tanh(x / m) */
    assert_close(aocs_sat_linear(AOCS_R(0.5), (real_t)NAN, AOCS_R(1.0)), tanh(0.5), TOL_TIGHT);
    assert_close(aocs_sat_linear(AOCS_R(0.5), AOCS_R(-1.0), AOCS_R(1.0)), tanh(0.5), TOL_TIGHT);
    /* m = +Inf: identity */
    assert_true(SAME(aocs_sat_linear(AOCS_R(1e6), AOCS_R(1.0), (real_t)INFINITY), 1e6));
}

static void test_tanh(void **state)
{
    (void)state;
    const real_t m = AOCS_R(0.05);
    /* unit slope at 0 (central difference) */
    const double h = 1e-4;
    double slope = ((double)aocs_sat_tanh((real_t)h, m) - (double)aocs_sat_tanh((real_t)-h, m)) / (2.0 * h);
    assert_close(slope, 1.0, 1e-4);
    /* values against m tanh(x/m) evaluated here */
    const double xs[] = {-1.0, -0.03, 0.0, 0.01, 0.05, 0.3};
    for (size_t i = 0; i < sizeof(xs) / sizeof(xs[0]); ++i) {
        double x = (double)(real_t)xs[i];
        assert_close(aocs_sat_tanh((real_t)x, m), (double)m * tanh(x / (double)m), TOL_TIGHT);
    }
    /* bound, huge and infinite */
    assert_true(fabs((double)aocs_sat_tanh((real_t)HUGE_REAL, m)) <= (double)m);
    assert_true(SAME(aocs_sat_tanh((real_t)INFINITY, m), (double)m));
    assert_true(SAME(aocs_sat_tanh((real_t)-INFINITY, m), -(double)m));
    /* invalid */
    assert_true(SAME(aocs_sat_tanh((real_t)NAN, m), 0.0));
    assert_true(SAME(aocs_sat_tanh(AOCS_R(1.0), AOCS_R(0.0)), 0.0));
    assert_true(SAME(aocs_sat_tanh(AOCS_R(1.0), (real_t)NAN), 0.0));
    assert_true(SAME(aocs_sat_tanh(AOCS_R(3.0), (real_t)INFINITY), 3.0));
}

static void test_boundary_layer(void **state)
{
    (void)state;
    const real_t eps = AOCS_R(0.02);
    assert_close(aocs_sat_boundary_layer(AOCS_R(0.01), eps), 0.5, TOL_TIGHT);
    assert_close(aocs_sat_boundary_layer(AOCS_R(-0.005), eps), -0.25, TOL_TIGHT);
    assert_true(SAME(aocs_sat_boundary_layer(eps, eps), 1.0));
    assert_true(SAME(aocs_sat_boundary_layer(-eps, eps), -1.0));
    assert_true(SAME(aocs_sat_boundary_layer(AOCS_R(0.5), eps), 1.0));
    assert_true(SAME(aocs_sat_boundary_layer(AOCS_R(-3.0), eps), -1.0));
    assert_true(SAME(aocs_sat_boundary_layer((real_t)INFINITY, eps), 1.0));
    assert_true(SAME(aocs_sat_boundary_layer(AOCS_R(0.0), eps), 0.0));
    /* invalid eps: sign(s); NaN s: 0 */
    assert_true(SAME(aocs_sat_boundary_layer(AOCS_R(0.001), AOCS_R(0.0)), 1.0));
    assert_true(SAME(aocs_sat_boundary_layer(AOCS_R(-0.001), (real_t)NAN), -1.0));
    assert_true(SAME(aocs_sat_boundary_layer((real_t)NAN, eps), 0.0));
    /* bounded by 1 on a grid through the layer edges */
    for (int k = -1000; k <= 1000; ++k) {
        real_t s = (real_t)(1e-4 * (double)k);
        assert_true(fabs((double)aocs_sat_boundary_layer(s, eps)) <= 1.0);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_clamp_per_axis_values),
        cmocka_unit_test(test_clamp_per_axis_nonfinite),
        cmocka_unit_test(test_scale_to_norm_random),
        cmocka_unit_test(test_scale_to_norm_exact_at_every_scale),
        cmocka_unit_test(test_norm_above),
        cmocka_unit_test(test_scale_to_norm_hand_value),
        cmocka_unit_test(test_scale_to_norm_huge_and_nonfinite),
        cmocka_unit_test(test_linear_plain_clamp_when_l_equals_m),
        cmocka_unit_test(test_linear_values_continuity_monotonic),
        cmocka_unit_test(test_linear_invalid_params),
        cmocka_unit_test(test_tanh),
        cmocka_unit_test(test_boundary_layer),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
