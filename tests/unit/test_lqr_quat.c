/*
 * lqr_quat (SPEC 2.5): gains computed here in closed form from the ARE,
 * torque = -K [sign(qe4) qe_vec; we] against an independent evaluation,
 * sign conventions, closed loop on the nonlinear rigid body with x^T S x as
 * Lyapunov function, config and input validation.
 *
 * Closed-form ARE (derived here, not taken from the tools). With diagonal J,
 * Q = q I6 and R = r I3 the model decouples per axis i into
 *     x1' = 0.5 x2,  x2' = u / J_i,   A = [[0, 0.5], [0, 0]], B = [0; 1/J_i],
 * and A^T S + S A - S B r^-1 B^T S + q I = 0 with S = [[a, b], [b, c]] reads
 *     (1,1): q - b^2 / (r J^2)            = 0  ->  b = J sqrt(q r)   (b > 0)
 *     (1,2): 0.5 a - b c / (r J^2)        = 0  ->  a = 2 b c / (r J^2)
 *     (2,2): b - c^2 / (r J^2) + q        = 0  ->  c = J sqrt(r (b + q))
 * (A^T S + S A = [[0, 0.5 a], [0.5 a, b]], S B = [b; c] / J). Then
 *     K_i = r^-1 B^T S = [b / (r J), c / (r J)] = [sqrt(q / r), sqrt((b + q) / r)].
 * S > 0 since a c - b^2 = b^2 + 2 b q > 0. In the 3x6 layout k[i][i] = K_i1,
 * k[i][3+i] = K_i2, zero elsewhere.
 */
#include "law_test_support.h"

#include "aocs/control/lqr_quat.h"


#if defined(AOCS_REAL_IS_FLOAT)
/* float law: ~1e-7 relative per operation, a dozen operations */
#define LAW_REL_TOL 2.0e-5
#else
#define LAW_REL_TOL 1.0e-12
#endif

static const double J_DIAG[3] = {2059.5, 5954.2, 5974.3};
static const double Q_W = 200.0;
static const double R_W = 0.001;

typedef struct {
    double a, b, c;   /* S per axis */
    double k1, k2;    /* gains per axis */
} axis_are_t;

static axis_are_t axis_are(double j)
{
    axis_are_t s;
    s.b = j * sqrt(Q_W * R_W);
    s.c = j * sqrt(R_W * (s.b + Q_W));
    s.a = 2.0 * s.b * s.c / (R_W * j * j);
    s.k1 = s.b / (R_W * j);
    s.k2 = s.c / (R_W * j);
    return s;
}

static aocs_lqr_quat_config_t design_config(void)
{
    aocs_lqr_quat_config_t cfg;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 6; ++j) {
            cfg.k[i][j] = AOCS_R(0.0);
        }
        axis_are_t s = axis_are(J_DIAG[i]);
        cfg.k[i][i] = (real_t)s.k1;
        cfg.k[i][3 + i] = (real_t)s.k2;
    }
    return cfg;
}

static aocs_status_t lqr_step(void *law, const aocs_att_input_t *in, aocs_vec3_t *u_out)
{
    return aocs_lqr_quat_step((aocs_lqr_quat_t *)law, in, u_out);
}

/* quaternion reference (dq_t, Shuster product): law_test_support.h */
/* x = [sign(qe4) qe_vec; we] from the inputs, evaluated here */
static void ref_state(const aocs_att_input_t *in, double x[6])
{
    dq_t qe = dq_mul(dq_from_real(in->q_BN), dq_inv(dq_from_real(in->qd_DN)));
    double n = sqrt(qe.q[0] * qe.q[0] + qe.q[1] * qe.q[1] + qe.q[2] * qe.q[2] + qe.q[3] * qe.q[3]);
    double s = (qe.q[3] < 0.0) ? -1.0 : 1.0;
    for (int i = 0; i < 3; ++i) {
        x[i] = s * qe.q[i] / n;
        x[3 + i] = (double)in->w_BN_B.v[i] - (double)in->wd_B.v[i];
    }
}

static void test_closed_form_are_residual(void **state)
{
    (void)state;
    for (int i = 0; i < 3; ++i) {
        double j = J_DIAG[i];
        axis_are_t s = axis_are(j);
        double rj2 = R_W * j * j;
        /* residual of A^T S + S A - S B R^-1 B^T S + Q, entry by entry */
        double r11 = Q_W - s.b * s.b / rj2;
        double r12 = 0.5 * s.a - s.b * s.c / rj2;
        double r22 = s.b - s.c * s.c / rj2 + Q_W;
        assert_true(fabs(r11) <= 1e-9 * Q_W);
        assert_true(fabs(r12) <= 1e-9 * Q_W);
        assert_true(fabs(r22) <= 1e-9 * Q_W);
        /* S > 0 */
        assert_true(s.a > 0.0);
        assert_true(s.a * s.c - s.b * s.b > 0.0);
        /* closed loop A - B K Hurwitz: s^2 + (k2/J) s + 0.5 k1 / J */
        assert_true(s.k2 / j > 0.0);
        assert_true(0.5 * s.k1 / j > 0.0);
        /* K1 = sqrt(q/r) independent of J, by hand: sqrt(2e5) */
        assert_close(s.k1, 447.21359549995793, 1e-12);
    }
    /* one hand value: axis 1, b = 2059.5 sqrt(0.2), K2 = sqrt((b + 200) / 0.001) */
    assert_close(axis_are(2059.5).k2, sqrt((2059.5 * sqrt(0.2) + 200.0) / 0.001), 1e-12);
}

static void test_torque_matches_formula_random(void **state)
{
    (void)state;
    aocs_lqr_quat_t law;
    const aocs_lqr_quat_config_t cfg = design_config();
    assert_int_equal(aocs_lqr_quat_init(&law, &cfg), AOCS_OK);
    test_rng_t rng = {0x1234567u};
    int n_neg_q4 = 0;
    for (int k = 0; k < 2000; ++k) {
        aocs_att_input_t in = make_input_real(test_random_quat(&rng), test_random_vec3(&rng, 0.1),
                                         test_random_quat(&rng), test_random_vec3(&rng, 0.05));
        aocs_vec3_t u;
        assert_int_equal(aocs_lqr_quat_step(&law, &in, &u), AOCS_OK);
        double x[6];
        ref_state(&in, x);
        dq_t qe = dq_mul(dq_from_real(in.q_BN), dq_inv(dq_from_real(in.qd_DN)));
        if (qe.q[3] < 0.0) {
            ++n_neg_q4;
        }
        assert_gain_product(cfg.k, x, -1.0, u, LAW_REL_TOL, 0.0, 1e-300); /* u = -K x */
    }
    assert_true(n_neg_q4 > 500); /* the anti-unwinding branch was exercised */
}

static void test_sign_conventions(void **state)
{
    (void)state;
    aocs_lqr_quat_t law;
    aocs_lqr_quat_config_t cfg = design_config();
    assert_int_equal(aocs_lqr_quat_init(&law, &cfg), AOCS_OK);
    const double half = 0.05; /* 0.1 rad about x */
    aocs_quat_t q = aocs_quat_make((real_t)sin(half), AOCS_R(0.0), AOCS_R(0.0), (real_t)cos(half));
    aocs_quat_t qneg = aocs_quat_make((real_t)-sin(half), AOCS_R(0.0), AOCS_R(0.0), (real_t)-cos(half));
    aocs_att_input_t in = make_input_real(q, aocs_vec3_zero(), aocs_quat_identity(), aocs_vec3_zero());
    aocs_vec3_t u;
    aocs_vec3_t u2;
    assert_int_equal(aocs_lqr_quat_step(&law, &in, &u), AOCS_OK);
    /* positive roll error: restoring (negative) torque about x, -K1 sin(0.05) */
    assert_true(u.v[0] < AOCS_R(0.0));
    assert_close(u.v[0], -(double)cfg.k[0][0] * sin(half), LAW_REL_TOL * 10.0);
    assert_true(fabs((double)u.v[1]) <= 1e-30 && fabs((double)u.v[2]) <= 1e-30);
    /* q and -q are the same attitude: same torque (sign(qe4) anti-unwinding) */
    in.q_BN = qneg;
    assert_int_equal(aocs_lqr_quat_step(&law, &in, &u2), AOCS_OK);
    assert_vec3_close(u2, u, TOL_TIGHT);
    /* positive rate error about y: negative torque about y, -K2 * 0.01 */
    in = make_input_real(aocs_quat_identity(), aocs_vec3_make(AOCS_R(0.0), AOCS_R(0.01), AOCS_R(0.0)),
                    aocs_quat_identity(), aocs_vec3_zero());
    assert_int_equal(aocs_lqr_quat_step(&law, &in, &u), AOCS_OK);
    assert_close(u.v[1], -(double)cfg.k[1][4] * 0.01, LAW_REL_TOL * 10.0);
    /* we = w - wd: equal rates give zero torque */
    in.wd_B = in.w_BN_B;
    assert_int_equal(aocs_lqr_quat_step(&law, &in, &u), AOCS_OK);
    assert_true(aocs_vec3_norm_inf(u) <= AOCS_R(0.0));
    /* qe4 = 0 exactly (180 deg about z): sign(0) = +1, x = [0 0 1 ...] */
    in = make_input_real(aocs_quat_make(AOCS_R(0.0), AOCS_R(0.0), AOCS_R(1.0), AOCS_R(0.0)), aocs_vec3_zero(),
                    aocs_quat_identity(), aocs_vec3_zero());
    assert_int_equal(aocs_lqr_quat_step(&law, &in, &u), AOCS_OK);
    assert_close(u.v[2], -(double)cfg.k[2][2], TOL_TIGHT);
}

/* ---- closed loop: nonlinear rigid body, RK4 in double, ZOH torque (law_test_support.h) ---- */
/* V = x^T S x with the per-axis ARE solution S (the LQR Lyapunov function) */
static double lyapunov(const double x[6])
{
    double v = 0.0;
    for (int i = 0; i < 3; ++i) {
        axis_are_t s = axis_are(J_DIAG[i]);
        v += s.a * x[i] * x[i] + 2.0 * s.b * x[i] * x[3 + i] + s.c * x[3 + i] * x[3 + i];
    }
    return v;
}

static void test_closed_loop_lyapunov_decreases(void **state)
{
    (void)state;
    aocs_lqr_quat_t law;
    aocs_lqr_quat_config_t cfg = design_config();
    assert_int_equal(aocs_lqr_quat_init(&law, &cfg), AOCS_OK);

    /* target: 20 deg about (1, -1, 2)/sqrt 6; start 3 deg about (1, 2, -1)/sqrt 6 from it */
    const dq_t qd = dq_axis_angle(1.0, -1.0, 2.0, 20.0 * PI / 180.0);
    const dq_t qerr = dq_axis_angle(1.0, 2.0, -1.0, 3.0 * PI / 180.0);
    dq_t q = dq_mul(qerr, qd);
    double w[3] = {1e-3, -2e-3, 5e-4};
    const dmat_t j_diag = {{{J_DIAG[0], 0.0, 0.0}, {0.0, J_DIAG[1], 0.0}, {0.0, 0.0, J_DIAG[2]}}};
    plant_t plant;
    plant_init(&plant, &j_diag);

    const double dt = 0.1;
    const int substeps = 4;
    double v0 = -1.0;
    double v_prev = -1.0;
    for (int k = 0; k <= 200; ++k) { /* 20 s at 10 Hz */
        aocs_att_input_t in = make_input_real(dq_to_real(q), dv_to_real(w), dq_to_real(qd), aocs_vec3_zero());
        double x[6];
        ref_state(&in, x);
        double v = lyapunov(x);
        if (k == 0) {
            v0 = v;
        } else {
            /* monotone decrease at every sample (Vdot = -x'(Q + K'RK)x < 0 near 0) */
            assert_true(v < v_prev);
        }
        v_prev = v;
        if (k == 200) {
            break;
        }
        aocs_vec3_t u;
        assert_int_equal(aocs_lqr_quat_step(&law, &in, &u), AOCS_OK);
        double ud[3];
        dv_from_real(u, ud);
        for (int j = 0; j < substeps; ++j) {
            plant_rk4(&plant, plant_zoh_torque, ud, &q, w, dt / substeps);
        }
    }
    /* slowest closed-loop pole has real part ~ -0.14 1/s: V(20 s) well below 1 % of V(0) */
    print_message("lqr_quat closed loop: V(0) = %.6g, V(20 s) = %.6g, ratio %.3g\n", v0, v_prev, v_prev / v0);
    assert_true(v_prev < 1e-2 * v0);
}

static void test_config_validation(void **state)
{
    (void)state;
    aocs_lqr_quat_t law;
    aocs_lqr_quat_config_t good = design_config();
    aocs_lqr_quat_config_t cfg;

    assert_int_equal(aocs_lqr_quat_init(NULL, &good), AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_lqr_quat_init(&law, NULL), AOCS_ERR_NULL_ARG);

    cfg = good;
    cfg.k[1][4] = (real_t)NAN;
    assert_int_equal(aocs_lqr_quat_init(&law, &cfg), AOCS_ERR_PARAM_NOT_FINITE);
    cfg = good;
    cfg.k[0][5] = (real_t)INFINITY; /* off-diagonal entries are checked too */
    assert_int_equal(aocs_lqr_quat_init(&law, &cfg), AOCS_ERR_PARAM_NOT_FINITE);

    cfg = good;
    cfg.k[1][1] = AOCS_R(0.0);
    assert_int_equal(aocs_lqr_quat_init(&law, &cfg), AOCS_ERR_GAIN_TABLE_INVALID);
    cfg = good;
    cfg.k[2][5] = AOCS_R(-1.0);
    assert_int_equal(aocs_lqr_quat_init(&law, &cfg), AOCS_ERR_GAIN_TABLE_INVALID);

    /* a failed init leaves the law unusable, output zeroed */
    assert_step_not_initialised(lqr_step, &law);

    /* off-diagonal negative entries are allowed (coupled designs) */
    cfg = good;
    cfg.k[0][1] = AOCS_R(-3.0);
    assert_int_equal(aocs_lqr_quat_init(&law, &cfg), AOCS_OK);
}

static void test_invalid_inputs_zero_output(void **state)
{
    (void)state;
    aocs_lqr_quat_t law;
    check_step_before_init(lqr_step, &law, sizeof law);
    aocs_lqr_quat_config_t cfg = design_config();
    assert_int_equal(aocs_lqr_quat_init(&law, &cfg), AOCS_OK);
    aocs_att_input_t good = make_input_real(aocs_quat_identity(), aocs_vec3_make(AOCS_R(0.1), AOCS_R(0.0), AOCS_R(0.0)),
                                       aocs_quat_identity(), aocs_vec3_zero());
    /* every rejection of the law_io.h contract (law_test_support.h) */
    check_step_rejections(lqr_step, &law, &good);
    /* the largest finite rate: K x overflows, reported, never Inf/NaN */
    aocs_att_input_t in = good;
    in.w_BN_B.v[0] = AOCS_REAL_MAX;
    assert_step_rejects(lqr_step, &law, &in, AOCS_ERR_OUTPUT_NOT_FINITE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_closed_form_are_residual),
        cmocka_unit_test(test_torque_matches_formula_random),
        cmocka_unit_test(test_sign_conventions),
        cmocka_unit_test(test_closed_loop_lyapunov_decreases),
        cmocka_unit_test(test_config_validation),
        cmocka_unit_test(test_invalid_inputs_zero_output),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
