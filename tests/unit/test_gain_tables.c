/*
 * Generated gain tables (firmware/gains/aocs_gains.{h,c}, `aocs gains`) fed to
 * the firmware laws: the law output must be -K x (lqr_quat, orbit_lqr) or
 * +K x (hinf) with x built here independently of the law; the tables must be
 * finite; the lqr_quat tables must equal the closed-form ARE solution of the
 * decoupled SPEC 2.5 model.
 */
#include "law_test_support.h"

#include "gains/aocs_gains.h"
#include "aocs/control/lqr_quat.h"
#include "aocs/control/orbit_lqr.h"
#include "aocs/control/hinf.h"

#define N_RANDOM 200

/*
 * Law outputs are compared with sum_j K_ij x_j evaluated here in double; the
 * tolerance is relative to sum_j |K_ij x_j| (cancellation-safe). Float: the
 * inputs are float and the law renormalises qe (relative ~1e-7 per component),
 * hence a few float ulps; the Euler angle round trip of the hinf test loses
 * ~1e-7 rad absolute on angles of ~1e-2 rad, hence 1e-4 there.
 */
#if defined(AOCS_REAL_IS_FLOAT)
#define TOL_LAW 2.0e-5
#define TOL_EULER 1.0e-4
#define TOL_TABLE 1.2e-7 /* a double literal rounded to float: <= 0.5 ulp (6e-8) */
#else
#define TOL_TABLE 1.0e-9 /* ARE solved numerically: ~1e-13 relative */
#define TOL_LAW 1.0e-12
#define TOL_EULER 1.0e-9
#endif

typedef const real_t (*gain_table_t)[6];

typedef struct {
    const char *name;
    gain_table_t k;
} named_table_t;

static const named_table_t all_tables[] = {
    {"lqr_quat_ref", aocs_gains_lqr_quat_ref_K},
    {"lqr_quat_strong", aocs_gains_lqr_quat_strong_K},
    {"orbit_lqr_q1", aocs_gains_orbit_lqr_q1_K},
    {"orbit_lqr_q01", aocs_gains_orbit_lqr_q01_K},
    {"orbit_lqr_q10", aocs_gains_orbit_lqr_q10_K},
    {"hinf_min", aocs_gains_hinf_min_K},
    {"hinf_regional", aocs_gains_hinf_regional_K},
    {"hinf_bounded", aocs_gains_hinf_bounded_K},
};

/* law output against sign * K x: assert_gain_product (law_test_support.h), absolute floor 1e-300 */
static void expect_kx(gain_table_t k, const double x[6], double sign, aocs_vec3_t u, double tol)
{
    assert_gain_product(k, x, sign, u, tol, 0.0, 1e-300);
}

/* law input at attitude q and rate w towards the identity target, wd = 0 */
static aocs_att_input_t att_input(aocs_quat_t q, aocs_vec3_t w)
{
    return make_input_real(q, w, aocs_quat_identity(), aocs_vec3_zero());
}

/* the 3x9 tables (lqr_quat_i, SPEC 5.2); test_lqr_quat_i.c checks the law on them */
static const struct {
    const char *name;
    const real_t (*k)[9];
} all_tables9[] = {
    {"lqr_quat_i_ref", aocs_gains_lqr_quat_i_ref_K},
    {"lqr_quat_i_suite", aocs_gains_lqr_quat_i_suite_K},
    {"lqr_quat_i_rw_suite", aocs_gains_lqr_quat_i_rw_suite_K},
};

static void test_tables_finite(void **state)
{
    (void)state;
    assert_int_equal(AOCS_GAINS_TABLE_COUNT,
                     (int)(sizeof all_tables / sizeof all_tables[0] + sizeof all_tables9 / sizeof all_tables9[0]));
    for (size_t t = 0; t < sizeof all_tables9 / sizeof all_tables9[0]; ++t) {
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 9; ++j) {
                assert_true(AOCS_IS_FINITE(all_tables9[t].k[i][j]));
            }
            assert_true((all_tables9[t].k[i][i] > 0) && (all_tables9[t].k[i][3 + i] > 0) &&
                        (all_tables9[t].k[i][6 + i] > 0));
        }
    }
    for (size_t t = 0; t < sizeof all_tables / sizeof all_tables[0]; ++t) {
        int nonzero = 0;
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 6; ++j) {
                assert_true(AOCS_IS_FINITE(all_tables[t].k[i][j]));
                nonzero += (fabs((double)all_tables[t].k[i][j]) > 0.0) ? 1 : 0;
            }
        }
        if (nonzero < 6) {
            print_error("%s: only %d nonzero gains\n", all_tables[t].name, nonzero);
            fail();
        }
    }
}

/* Design inputs quoted in the header are the SPEC values. */
static void test_header_inputs(void **state)
{
    (void)state;
    assert_close(AOCS_GAINS_IRASSI_J11_KGM2, 2059.5, TOL_TIGHT);
    assert_close(AOCS_GAINS_IRASSI_J22_KGM2, 5954.2, TOL_TIGHT);
    assert_close(AOCS_GAINS_IRASSI_J33_KGM2, 5974.3, TOL_TIGHT);
    assert_close(AOCS_GAINS_LANDSAT8_MASS_KG, 2623.0, TOL_TIGHT);
    /* n = sqrt(mu / R^3), SPEC 2.8; scaled to O(1) so the relative tolerance applies */
    assert_close((double)AOCS_GAINS_LANDSAT8_N_RADPS * 1e3,
                 sqrt(3.986004418e14 / (7080.0e3 * 7080.0e3 * 7080.0e3)) * 1e3, TOL_TIGHT);
    assert_close(AOCS_GAINS_GEO_IX_KGM2, 1030.17, TOL_TIGHT);
    assert_close(AOCS_GAINS_GEO_IY_KGM2, 3015.65, TOL_TIGHT);
    assert_close(AOCS_GAINS_GEO_IZ_KGM2, 3030.43, TOL_TIGHT);
    assert_close((double)AOCS_GAINS_GEO_W0_RADPS * 1e5, 7.292115, TOL_TIGHT);
}

/*
 * SPEC 2.5 with Q = q I6, R = r I3 decouples into per-axis
 * x = [qe_i, w_i], A = [[0, 0.5], [0, 0]], B = [0; 1/J_i]; solving the 2x2
 * ARE by hand: S12 = J sqrt(q r), K = [sqrt(q / r), sqrt((J sqrt(q r) + q) / r)],
 * all couplings zero.
 */
static void check_lqr_closed_form(gain_table_t k, double q, double r)
{
    const double j[3] = {2059.5, 5954.2, 5974.3};
    for (int i = 0; i < 3; ++i) {
        for (int c = 0; c < 6; ++c) {
            double expected = 0.0;
            if (c == i) {
                expected = sqrt(q / r);
            } else if (c == i + 3) {
                expected = sqrt((j[i] * sqrt(q * r) + q) / r);
            }
            if (!(fabs((double)k[i][c] - expected) <= TOL_TABLE * fabs((double)k[i][i + 3]))) {
                print_error("K[%d][%d] = %.17g, closed form %.17g\n", i, c, (double)k[i][c], expected);
                fail();
            }
        }
    }
}

static void test_lqr_quat_closed_form(void **state)
{
    (void)state;
    check_lqr_closed_form(aocs_gains_lqr_quat_ref_K, 200.0, 0.001);
    check_lqr_closed_form(aocs_gains_lqr_quat_strong_K, 2000.0, 1e-5);
}

static aocs_lqr_quat_config_t lqr_cfg(gain_table_t k)
{
    aocs_lqr_quat_config_t cfg;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 6; ++j) {
            cfg.k[i][j] = k[i][j];
        }
    }
    return cfg;
}

/* u = -K [sign(qe4) qe_vec; we] with qd = identity, so qe = q. */
static void check_lqr_quat(gain_table_t k)
{
    aocs_lqr_quat_config_t cfg = lqr_cfg(k);
    aocs_lqr_quat_t law;
    test_rng_t rng = {0x9E3779B97F4A7C15ULL};
    assert_int_equal(aocs_lqr_quat_init(&law, &cfg), AOCS_OK);
    for (int n = 0; n < N_RANDOM; ++n) {
        aocs_quat_t q = (n < N_RANDOM / 4) ? aocs_quat_identity() : test_random_quat(&rng);
        aocs_vec3_t w = test_random_vec3(&rng, 0.05);
        aocs_att_input_t in = att_input(q, w);
        aocs_vec3_t u;
        double s = ((double)q.q[3] < 0.0) ? -1.0 : 1.0;
        double x[6] = {s * (double)q.q[0], s * (double)q.q[1], s * (double)q.q[2],
                       (double)w.v[0], (double)w.v[1], (double)w.v[2]};
        assert_int_equal(aocs_lqr_quat_step(&law, &in, &u), AOCS_OK);
        expect_kx(k, x, -1.0, u, TOL_LAW);
    }
}

static void test_lqr_quat_ref_law(void **state)
{
    (void)state;
    check_lqr_quat(aocs_gains_lqr_quat_ref_K);
}

static void test_lqr_quat_strong_law(void **state)
{
    (void)state;
    check_lqr_quat(aocs_gains_lqr_quat_strong_K);
}

/* F = -K [du dv dw dx dy dz] */
static void check_orbit(gain_table_t k)
{
    aocs_orbit_lqr_config_t cfg;
    aocs_orbit_lqr_t law;
    test_rng_t rng = {0xD1B54A32D192ED03ULL};
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 6; ++j) {
            cfg.k[i][j] = k[i][j];
        }
    }
    assert_int_equal(aocs_orbit_lqr_init(&law, &cfg), AOCS_OK);
    for (int n = 0; n < N_RANDOM; ++n) {
        aocs_orbit_input_t in;
        aocs_vec3_t f;
        in.vel_mps = test_random_vec3(&rng, 10.0);
        in.pos_m = test_random_vec3(&rng, 500.0);
        in.dt_s = AOCS_R(0.1);
        double x[6] = {(double)in.vel_mps.v[0], (double)in.vel_mps.v[1], (double)in.vel_mps.v[2],
                       (double)in.pos_m.v[0], (double)in.pos_m.v[1], (double)in.pos_m.v[2]};
        assert_int_equal(aocs_orbit_lqr_step(&law, &in, &f), AOCS_OK);
        expect_kx(k, x, -1.0, f, TOL_LAW);
    }
}

static void test_orbit_lqr_laws(void **state)
{
    (void)state;
    check_orbit(aocs_gains_orbit_lqr_q1_K);
    check_orbit(aocs_gains_orbit_lqr_q01_K);
    check_orbit(aocs_gains_orbit_lqr_q10_K);
}

/*
 * u = +K x, x = [phi theta psi phidot thetadot psidot] (SPEC 2.6).
 * (a) identity attitude, body rate we: 3-2-1 rates equal we exactly, x = [0 0 0 we].
 * (b) zero rate, attitude A = R1(phi) R2(theta) R3(psi), so q = q_x (x) q_y (x) q_z
 *     (A(q (x) p) = A(q) A(p); dq_euler321 of law_test_support.h, own Shuster
 *     product), x = [phi theta psi 0 0 0].
 */
static void check_hinf(gain_table_t k)
{
    aocs_hinf_config_t cfg;
    aocs_hinf_t law;
    test_rng_t rng = {0x2545F4914F6CDD1DULL};
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 6; ++j) {
            cfg.k[i][j] = k[i][j];
        }
    }
    assert_int_equal(aocs_hinf_init(&law, &cfg), AOCS_OK);
    for (int n = 0; n < N_RANDOM; ++n) {
        aocs_vec3_t w = test_random_vec3(&rng, 1e-3);
        aocs_att_input_t in = att_input(aocs_quat_identity(), w);
        aocs_vec3_t u;
        double x[6] = {0.0, 0.0, 0.0, (double)w.v[0], (double)w.v[1], (double)w.v[2]};
        assert_int_equal(aocs_hinf_step(&law, &in, &u), AOCS_OK);
        expect_kx(k, x, 1.0, u, TOL_LAW);
    }
    for (int n = 0; n < N_RANDOM; ++n) {
        double phi = test_rng_uniform(&rng, -0.01, 0.01);
        double theta = test_rng_uniform(&rng, -0.01, 0.01);
        double psi = test_rng_uniform(&rng, -0.01, 0.01);
        aocs_att_input_t in = att_input(dq_to_real(dq_euler321(psi, theta, phi)), aocs_vec3_zero());
        aocs_vec3_t u;
        double x[6] = {phi, theta, psi, 0.0, 0.0, 0.0};
        assert_int_equal(aocs_hinf_step(&law, &in, &u), AOCS_OK);
        expect_kx(k, x, 1.0, u, TOL_EULER);
    }
}

static void test_hinf_laws(void **state)
{
    (void)state;
    check_hinf(aocs_gains_hinf_min_K);
    check_hinf(aocs_gains_hinf_regional_K);
    check_hinf(aocs_gains_hinf_bounded_K);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tables_finite),
        cmocka_unit_test(test_header_inputs),
        cmocka_unit_test(test_lqr_quat_closed_form),
        cmocka_unit_test(test_lqr_quat_ref_law),
        cmocka_unit_test(test_lqr_quat_strong_law),
        cmocka_unit_test(test_orbit_lqr_laws),
        cmocka_unit_test(test_hinf_laws),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
