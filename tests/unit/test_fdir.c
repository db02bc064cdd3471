/*
 * Fault management (aocs/fdir/fdir.h, aocs/fdir/event_log.h; docs/spec.md 5.15): the event table and log,
 * and each monitor against a model written here: a wheel integrated by the test (its own friction, substeps)
 * that loses its motor, a tracker innovation sequence, a frozen tracker, a stuck gyro axis, missing samples
 * and mode changes; then the executive end to end (a wheel dies under the allocation, is isolated, the array
 * flies on three).
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <string.h>

#include <cmocka.h>

#include "aocs/executive.h"
#include "aocs/fdir/fdir.h"
#include "test_support.h"
#include "wheel_test_support.h"

#define PERIOD_S 0.1
#define PERIOD_NS 100000000ull

/* ---- the table: ids are wire values, pinned here by hand ---- */
static void test_event_ids_names_severities_are_the_wire_values(void **state)
{
    (void)state;
    static const struct {
        aocs_evt_id_t id;
        unsigned value;
        const char *name;
        const char *severity;
        const char *unit_kind;
    } rows[] = {
        {AOCS_EVT_ST_INNOVATION_HIGH, 1u, "st_innovation_high", "warning", "star_tracker"},
        {AOCS_EVT_GYRO_ST_INCONSISTENT, 2u, "gyro_st_inconsistent", "warning", "gyro"},
        {AOCS_EVT_WHEEL_RESIDUAL_HIGH, 3u, "wheel_residual_high", "warning", "wheel"},
        {AOCS_EVT_MOMENTUM_INCONSISTENT, 4u, "momentum_inconsistent", "warning", "none"},
        {AOCS_EVT_THRUSTER_INEFFECTIVE, 5u, "thruster_ineffective", "warning", "thruster"},
        {AOCS_EVT_LINK_LOST, 6u, "link_lost", "warning", "link"},
        {AOCS_EVT_ST_EXCLUDED, 7u, "st_excluded", "error", "star_tracker"},
        {AOCS_EVT_ST_RESTORED, 8u, "st_restored", "info", "star_tracker"},
        {AOCS_EVT_GYRO_EXCLUDED, 9u, "gyro_excluded", "critical", "gyro"},
        {AOCS_EVT_WHEEL_ISOLATED, 10u, "wheel_isolated", "error", "wheel"},
        {AOCS_EVT_UNLOAD_ACTUATOR_SWITCHED, 11u, "unload_actuator_switched", "error", "thruster"},
        {AOCS_EVT_SAFE_ENTERED, 12u, "safe_entered", "error", "none"},
        {AOCS_EVT_SAFE_LEFT, 13u, "safe_left", "info", "none"},
        {AOCS_EVT_LINK_RESTORED, 14u, "link_restored", "info", "link"},
        {AOCS_EVT_ST_FROZEN, 15u, "st_frozen", "warning", "star_tracker"},
        {AOCS_EVT_GYRO_STUCK, 16u, "gyro_stuck", "warning", "gyro"},
        {AOCS_EVT_GYRO_SATURATED, 17u, "gyro_saturated", "warning", "gyro"},
        {AOCS_EVT_WHEEL_ISOLATION_REFUSED, 18u, "wheel_isolation_refused", "critical", "wheel"},
        {AOCS_EVT_WHEEL_FRICTION_HIGH, 19u, "wheel_friction_high", "warning", "wheel"},
        {AOCS_EVT_ESTIMATOR_GYROLESS, 20u, "estimator_gyroless", "error", "none"},
        {AOCS_EVT_ST_NOISE_RESCALED, 21u, "st_noise_rescaled", "warning", "star_tracker"},
        {AOCS_EVT_THRUSTER_STUCK_OPEN, 22u, "thruster_stuck_open", "error", "thruster"},
        {AOCS_EVT_THRUSTER_BRANCH_CLOSED, 23u, "thruster_branch_closed", "warning", "thruster"},
        {AOCS_EVT_THRUSTER_BRANCH_REOPENED, 24u, "thruster_branch_reopened", "warning", "thruster"},
        {AOCS_EVT_THRUSTER_ISOLATED, 25u, "thruster_isolated", "error", "thruster"},
    };
    assert_int_equal(AOCS_EVT_COUNT, sizeof(rows) / sizeof(rows[0]));
    for (size_t i = 0u; i < (sizeof(rows) / sizeof(rows[0])); ++i) {
        assert_int_equal((unsigned)rows[i].id, rows[i].value);
        assert_string_equal(aocs_evt_name(rows[i].id), rows[i].name);
        assert_string_equal(aocs_evt_severity_name(aocs_evt_severity(rows[i].id)), rows[i].severity);
        assert_string_equal(aocs_evt_unit_kind_name(aocs_evt_unit_kind(rows[i].id)), rows[i].unit_kind);
    }
    assert_null(aocs_evt_name(AOCS_EVT_NONE));
    assert_null(aocs_evt_name(AOCS_EVT_END));
    assert_int_equal(AOCS_SEV_INFO, 0);
    assert_int_equal(AOCS_SEV_CRITICAL, 3);
    assert_string_equal(aocs_evt_severity_name(AOCS_SEV_COUNT), "unknown");
}

/* ---- the log: sequence numbers, the ring, counts per severity ---- */
static void test_log_sequence_ring_and_counts(void **state)
{
    (void)state;
    aocs_evlog_t log;
    aocs_event_t e;
    uint32_t lost = 99u;
    aocs_evlog_init(&log);
    assert_int_equal(aocs_evlog_next(&log, 0u, &e, &lost), AOCS_ERR_INPUT_MISSING);
    assert_int_equal(aocs_evlog_raise(&log, AOCS_EVT_NONE, 1u, 0, AOCS_R(0.0), AOCS_R(0.0)), 0u);
    assert_int_equal(aocs_evlog_raise(&log, AOCS_EVT_END, 1u, 0, AOCS_R(0.0), AOCS_R(0.0)), 0u);
    /* 40 events: more than the ring holds */
    for (uint32_t k = 1u; k <= 40u; ++k) {
        const aocs_evt_id_t id = ((k % 2u) == 0u) ? AOCS_EVT_WHEEL_ISOLATED : AOCS_EVT_SAFE_LEFT;
        assert_int_equal(aocs_evlog_raise(&log, id, 1000u * k, (int32_t)(k % 4u), (real_t)k, AOCS_R(0.5)), k);
    }
    assert_int_equal(aocs_evlog_count(&log), 40u);
    assert_int_equal(aocs_evlog_count_at_least(&log, AOCS_SEV_INFO), 40u);
    assert_int_equal(aocs_evlog_count_at_least(&log, AOCS_SEV_WARNING), 20u); /* the error ones */
    assert_int_equal(aocs_evlog_count_at_least(&log, AOCS_SEV_CRITICAL), 0u);
    {
        /* the sum over severities saturates at UINT32_MAX, never wraps (two counts near it, as a long run
         * could hold them) */
        aocs_evlog_t big = log;
        big.count_by_severity[AOCS_SEV_WARNING] = UINT32_MAX - 5u;
        big.count_by_severity[AOCS_SEV_ERROR] = 10u;
        assert_int_equal(aocs_evlog_count_at_least(&big, AOCS_SEV_WARNING), UINT32_MAX);
        big.count_by_severity[AOCS_SEV_ERROR] = 5u;
        assert_int_equal(aocs_evlog_count_at_least(&big, AOCS_SEV_WARNING), UINT32_MAX);
        big.count_by_severity[AOCS_SEV_ERROR] = 4u;
        assert_int_equal(aocs_evlog_count_at_least(&big, AOCS_SEV_WARNING), UINT32_MAX - 1u);
    }
    /* a reader that saw nothing: the oldest held is 40 - 32 + 1 = 9, 8 were lost */
    assert_int_equal(aocs_evlog_next(&log, 0u, &e, &lost), AOCS_OK);
    assert_int_equal(e.seq, 9u);
    assert_int_equal(lost, 8u);
    assert_int_equal(e.t_ns, 9000u);
    assert_int_equal(e.id, AOCS_EVT_SAFE_LEFT);
    assert_int_equal(e.unit, 1);
    assert_close(e.value, 9.0, 0.0);
    /* a reader in step: every event once, in order, seq monotonic */
    {
        uint32_t seq = 8u;
        uint32_t n = 0u;
        while (aocs_evlog_next(&log, seq, &e, &lost) == AOCS_OK) {
            assert_int_equal(e.seq, seq + 1u);
            assert_int_equal(lost, 0u);
            assert_int_equal(e.severity, ((e.seq % 2u) == 0u) ? AOCS_SEV_ERROR : AOCS_SEV_INFO);
            assert_int_equal(e.unit_kind, ((e.seq % 2u) == 0u) ? AOCS_UNIT_WHEEL : AOCS_UNIT_NONE);
            seq = e.seq;
            ++n;
        }
        assert_int_equal(n, 32u);
        assert_int_equal(seq, 40u);
    }
    /* a non-finite statistic is stored as the largest real: the log never holds a NaN */
    assert_int_equal(aocs_evlog_raise(&log, AOCS_EVT_LINK_LOST, 1u, -1, (real_t)NAN, (real_t)INFINITY), 41u);
    assert_int_equal(aocs_evlog_next(&log, 40u, &e, NULL), AOCS_OK);
    assert_true(aocs_fdir_same(e.value, AOCS_REAL_MAX) != 0);
    assert_true(aocs_fdir_same(e.threshold, AOCS_REAL_MAX) != 0);
    assert_int_equal(aocs_evlog_next(NULL, 0u, &e, NULL), AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_evlog_count(NULL), 0u);
}

static void test_config_check(void **state)
{
    (void)state;
    aocs_fdir_config_t c;
    aocs_fdir_t f;
    aocs_fdir_config_default(&c);
    assert_int_equal(aocs_fdir_config_check(&c), AOCS_OK);
    assert_int_equal(aocs_fdir_config_check(NULL), AOCS_ERR_NULL_ARG);
    c.wheel_residual_frac = AOCS_R(1.5);
    assert_int_equal(aocs_fdir_init(&f, &c), AOCS_ERR_FDIR_CONFIG_INVALID);
    assert_int_equal(f.initialised, 0);
    aocs_fdir_config_default(&c);
    c.st_frozen_samples = 1u;
    assert_int_equal(aocs_fdir_config_check(&c), AOCS_ERR_FDIR_CONFIG_INVALID);
    aocs_fdir_config_default(&c);
    c.gyro_bias_persist = 0u;
    assert_int_equal(aocs_fdir_config_check(&c), AOCS_ERR_FDIR_CONFIG_INVALID);
    /* fdir.st_restore is a count of samples (the restoration run, the noise window): 0 is refused, and the
     * least one, 1, is a valid configuration (a tracker restored at its first consistent sample) */
    aocs_fdir_config_default(&c);
    c.st_restore = 0u;
    assert_int_equal(aocs_fdir_config_check(&c), AOCS_ERR_FDIR_CONFIG_INVALID);
    assert_int_equal(aocs_fdir_init(&f, &c), AOCS_ERR_FDIR_CONFIG_INVALID);
    assert_int_equal(f.initialised, 0);
    c.st_restore = 1u;
    assert_int_equal(aocs_fdir_config_check(&c), AOCS_OK);
    assert_int_equal(aocs_fdir_init(&f, &c), AOCS_OK);
    assert_int_equal(f.initialised, 1);
    aocs_fdir_config_default(&c);
    c.gyro_bias_chi2 = AOCS_R(-1.0);
    assert_int_equal(aocs_fdir_config_check(&c), AOCS_ERR_FDIR_CONFIG_INVALID);
    c.gyro_bias_chi2 = (real_t)INFINITY;
    assert_int_equal(aocs_fdir_config_check(&c), AOCS_ERR_FDIR_CONFIG_INVALID);
    c.gyro_bias_chi2 = AOCS_R(0.0); /* no test */
    assert_int_equal(aocs_fdir_config_check(&c), AOCS_OK);
    aocs_fdir_config_default(&c);
    c.st_chi2 = (real_t)NAN;
    assert_int_equal(aocs_fdir_config_check(&c), AOCS_ERR_FDIR_CONFIG_INVALID);
    aocs_fdir_config_default(&c);
    c.enabled = 2u;
    assert_int_equal(aocs_fdir_config_check(&c), AOCS_ERR_FDIR_CONFIG_INVALID);
    /* a zeroed configuration is the stage off */
    (void)memset(&c, 0, sizeof(c));
    assert_int_equal(aocs_fdir_config_check(&c), AOCS_OK);
    /* the defaults the executive takes are the registry's rows: the same values */
    {
        aocs_exec_config_t ec;
        aocs_exec_config_default(&ec);
        aocs_fdir_config_default(&c);
        assert_int_equal(ec.fdir.enabled, 1u);
        assert_true(memcmp(&ec.fdir, &c, sizeof(c)) == 0);
    }
}

/* ---- the wheel monitor against a wheel the test integrates ---- */

/* the test's friction: b w + c tanh(w / eps) */
static double test_friction(double b, double c, double eps, double w)
{
    return (b * w) + (c * tanh(w / eps));
}

typedef struct {
    aocs_wheels_t wa;
    aocs_fdir_t f;
    double omega[AOCS_WHEELS_MAX];
    uint64_t t_ns;
} wheel_rig_t;

static void rig_init(wheel_rig_t *r, uint32_t n_wheels, double b, double c)
{
    aocs_wheels_config_t wc;
    aocs_fdir_config_t fc;
    (void)memset(r, 0, sizeof(*r));
    test_wheels_pyramid(&wc);
    if (n_wheels == 3u) {
        wc.failed_mask = 1u << 3; /* three healthy wheels that span */
    }
    for (uint32_t i = 0u; i < 4u; ++i) {
        wc.viscous_nms[i] = (real_t)b;
        wc.coulomb_nm[i] = (real_t)c;
        wc.coulomb_width_radps[i] = AOCS_R(0.5);
        r->omega[i] = 20.0 + (15.0 * (double)i) - 30.0;
    }
    wc.period_s = AOCS_R(PERIOD_S);
    assert_int_equal(aocs_wheels_init(&r->wa, &wc), AOCS_OK);
    aocs_fdir_config_default(&fc);
    assert_int_equal(aocs_fdir_init(&r->f, &fc), AOCS_OK);
}

/* What the rig's wheels do besides taking their commands: a wheel whose motor is dead (bit i), one whose true
 * friction is a multiple of the test's b, c, and one whose tachometer reads 0 (AOCS_WHEELS_MAX: none). */
typedef struct {
    uint32_t dead_mask;
    double friction_scale[4];
    uint32_t tach_zero;
} rig_faults_t;

/* One step: fdir on the sample, the allocation of u_c, then the test's wheels over the period (100 substeps,
 * the motor applies u_s unless dead, friction b w + c tanh(w / 0.5) times the wheel's scale). */
static void rig_step_with(wheel_rig_t *r, aocs_vec3_t u_c, const rig_faults_t *fl, double b, double c)
{
    aocs_fdir_input_t in;
    aocs_wheels_alloc_t alloc;
    real_t om[AOCS_WHEELS_MAX] = {0};
    for (uint32_t i = 0u; i < AOCS_WHEELS_MAX; ++i) {
        om[i] = (real_t)r->omega[i];
    }
    if (fl->tach_zero < AOCS_WHEELS_MAX) {
        om[fl->tach_zero] = AOCS_R(0.0);
    }
    assert_int_equal(aocs_wheels_allocate(&r->wa, u_c, om, &alloc), AOCS_OK);
    (void)memset(&in, 0, sizeof(in));
    in.t_ns = r->t_ns;
    in.period_s = AOCS_R(PERIOD_S);
    in.have_sample = 1;
    in.input_status = AOCS_OK;
    in.mode = AOCS_EXEC_MODE_NOMINAL;
    in.wheel_speed_radps = om;
    in.alloc = &alloc;
    aocs_fdir_step(&r->f, &in, &r->wa);
    /* the wheels over the period: Js dOmega/dt = u - f(Omega) (the body does not turn here) */
    for (uint32_t i = 0u; i < 4u; ++i) {
        const double u = ((fl->dead_mask >> i) & 1u) ? 0.0 : (double)alloc.u_s_nm[i];
        const double h = PERIOD_S / 100.0;
        for (int k = 0; k < 100; ++k) {
            r->omega[i] += h * (u - (fl->friction_scale[i] * test_friction(b, c, 0.5, r->omega[i]))) /
                           TEST_WHEEL_JS_KGM2;
        }
    }
    r->t_ns += PERIOD_NS;
}

static void rig_step(wheel_rig_t *r, aocs_vec3_t u_c, uint32_t dead_mask, double b, double c)
{
    const rig_faults_t fl = {dead_mask, {1.0, 1.0, 1.0, 1.0}, AOCS_WHEELS_MAX};
    rig_step_with(r, u_c, &fl, b, c);
}

static uint32_t count_id(const aocs_evlog_t *log, aocs_evt_id_t id, int32_t unit, uint64_t *t_first)
{
    aocs_event_t e;
    uint32_t seq = 0u;
    uint32_t n = 0u;
    while (aocs_evlog_next(log, seq, &e, NULL) == AOCS_OK) {
        if ((e.id == id) && ((unit < 0) || (e.unit == unit))) {
            if ((n == 0u) && (t_first != NULL)) {
                *t_first = e.t_ns;
            }
            ++n;
        }
        seq = e.seq;
    }
    return n;
}

static void test_wheel_residual_is_the_formula(void **state)
{
    (void)state;
    /* 0.1 N m commanded; the wheel went from 10 to 10.1 rad/s in 0.1 s with Js 0.08: 0.08 N m delivered */
    assert_close(aocs_fdir_wheel_residual(AOCS_R(0.1), AOCS_R(0.08), AOCS_R(10.0), AOCS_R(10.1), AOCS_R(0.1)), 0.02,
                 TOL_LOOSE);
}

/* healthy wheels with friction (the model the allocation compensates, the test integrating the true one): no
 * event over 300 steps of a varying command through the zero crossings; a dead motor then raises
 * wheel_residual_high and wheel_isolated at the persist-th step after the first period it did not drive */
static void test_wheel_dies_is_detected_after_persist_steps_and_isolated(void **state)
{
    (void)state;
    const double b = 1.0e-5;
    const double c = 2.0e-3;
    wheel_rig_t r;
    uint64_t t_res = 0u;
    uint64_t t_iso = 0u;
    uint32_t k_fail = 300u;
    rig_init(&r, 4u, b, c);
    for (uint32_t k = 0u; k < 400u; ++k) {
        const double s = sin(0.05 * (double)k);
        const aocs_vec3_t u_c = aocs_vec3_make((real_t)(0.2 * s), (real_t)(-0.1 * s), (real_t)(0.15 * cos(0.03 * (double)k)));
        rig_step(&r, u_c, (k >= k_fail) ? (1u << 1) : 0u, b, c);
        if (k < k_fail) {
            assert_int_equal(aocs_evlog_count(&r.f.log), 0u);
        }
    }
    assert_int_equal(count_id(&r.f.log, AOCS_EVT_WHEEL_RESIDUAL_HIGH, 1, &t_res), 1u);
    assert_int_equal(count_id(&r.f.log, AOCS_EVT_WHEEL_ISOLATED, 1, &t_iso), 1u);
    assert_int_equal(aocs_evlog_count(&r.f.log), 2u); /* no other wheel accused */
    /* the first sample that shows the dead period is k_fail + 1; persist samples later (counting it) */
    assert_int_equal(t_res, (uint64_t)(k_fail + AOCS_FDIR_WHEEL_PERSIST_DEFAULT) * PERIOD_NS);
    assert_int_equal(t_iso, t_res);
    /* the array now flies on wheels 0, 2, 3: wheel 1 gets no command, the body torque is still delivered */
    assert_int_equal(r.wa.cfg.failed_mask, 1u << 1);
    assert_int_equal(r.wa.n_healthy, 3u);
    {
        aocs_wheels_alloc_t a;
        real_t om[AOCS_WHEELS_MAX] = {0};
        const aocs_vec3_t u = aocs_vec3_make(AOCS_R(0.05), AOCS_R(0.02), AOCS_R(-0.03));
        assert_int_equal(aocs_wheels_allocate(&r.wa, u, om, &a), AOCS_OK);
        assert_close(a.u_s_nm[1], 0.0, 0.0);
        assert_vec3_close(a.u_body_B_nm, u, TOL_LOOSE);
    }
    assert_int_equal(r.f.replan, 0); /* set on the isolation step only */
    assert_int_equal(r.f.safe_latched, 0);
}

/* 600 steps of the rig's wheels spinning one way (80 to 110 rad/s) under a slowly varying command, with the
 * test's friction; from step 150 wheel 1's friction is `scale` times the model, and, when tach_dead, its
 * tachometer reads 0 */
static void friction_rig_run(wheel_rig_t *r, double b, double c, double scale, int tach_dead)
{
    for (uint32_t i = 0u; i < 4u; ++i) {
        r->omega[i] = 80.0 + (10.0 * (double)i);
    }
    for (uint32_t k = 0u; k < 600u; ++k) {
        const aocs_vec3_t u_c = aocs_vec3_make(AOCS_R(0.02 * sin(0.01 * (double)k)), AOCS_R(0.01), AOCS_R(0.0));
        const int after = (k >= 150u) ? 1 : 0;
        const rig_faults_t fl = {0u, {1.0, (after != 0) ? scale : 1.0, 1.0, 1.0},
                                 ((after != 0) && (tach_dead != 0)) ? 1u : AOCS_WHEELS_MAX};
        rig_step_with(r, u_c, &fl, b, c);
    }
}

/* a tachometer that fails (reads 0 from step 150) jumps the residual far past the isolation threshold in the
 * friction window that holds it (some 70 N m against a window's 0.3 N m of friction model): that window is not
 * judged, and the later ones see a wheel at rest (no friction model to scale), so no friction is found 200 times
 * high and the model stays (the small commands here never persist above the isolation threshold: the
 * isolation of such a wheel is the SIL table's, spec 5.14.7) */
static void test_a_tachometer_failure_is_not_taken_for_friction(void **state)
{
    (void)state;
    wheel_rig_t r;
    rig_init(&r, 4u, 1.0e-5, 2.0e-3);
    friction_rig_run(&r, 1.0e-5, 2.0e-3, 1.0, 1);
    assert_int_equal(count_id(&r.f.log, AOCS_EVT_WHEEL_RESIDUAL_HIGH, -1, NULL), 0u);
    assert_int_equal(count_id(&r.f.log, AOCS_EVT_WHEEL_FRICTION_HIGH, -1, NULL), 0u);
    assert_close(r.wa.cfg.coulomb_nm[1], (double)AOCS_R(2.0e-3), 0.0);
}

/* wheel 1's true friction five times its model from step 150 (the rig's wheels spinning one way under a
 * command that keeps them so): no isolation (the extra 8 to 10 mN m is below the 25 mN m threshold), but at
 * the end of the friction window that holds it wheel_friction_high names wheel 1 with the scale found, the
 * model is scaled by it and follows the wheel after (no other event); with the test off, nothing. */
static void test_a_wheel_whose_friction_grew_is_found_and_its_model_rescaled(void **state)
{
    (void)state;
    const double b = 1.0e-5;
    const double c = 2.0e-3;
    for (int on = 0; on < 2; ++on) {
        wheel_rig_t r;
        aocs_event_t e;
        rig_init(&r, 4u, b, c);
        if (on == 0) {
            r.f.cfg.wheel_friction_excess = AOCS_R(0.0);
        }
        friction_rig_run(&r, b, c, 5.0, 0);
        assert_int_equal(count_id(&r.f.log, AOCS_EVT_WHEEL_ISOLATED, -1, NULL), 0u);
        if (on == 0) {
            assert_int_equal(aocs_evlog_count(&r.f.log), 0u);
            assert_close(r.wa.cfg.coulomb_nm[1], (double)(real_t)c, 0.0);
        } else {
            uint64_t t = 0u;
            assert_int_equal(count_id(&r.f.log, AOCS_EVT_WHEEL_FRICTION_HIGH, 1, &t), 1u);
            assert_int_equal(aocs_evlog_count(&r.f.log), 1u);
            /* windows of 100 residuals from the second sample close at steps 100, 200, ...: the one closing at
             * 200 holds 50 periods of the grown friction and 50 before, so its scale is about (1 + 5) / 2 */
            assert_int_equal(t, 200u * PERIOD_NS);
            assert_int_equal(aocs_evlog_next(&r.f.log, 0u, &e, NULL), AOCS_OK);
            assert_true(fabs((double)e.value - 3.0) < 0.1);
            /* the next window scales the model again, silently: it ends within 2 % of the truth */
            assert_true(fabs((double)r.wa.cfg.coulomb_nm[1] / c - 5.0) < 0.1);
            assert_true(fabs((double)r.wa.cfg.viscous_nms[1] / b - 5.0) < 0.1);
            assert_close(r.wa.cfg.coulomb_nm[0], (double)(real_t)c, 0.0);
        }
    }
}

/* The friction test's threshold is strict (spec 5.15.2: a friction excess *above* fdir.wheel_friction_excess
 * is high): a window whose sum r / sum f^ is exactly the threshold raises nothing. The samples are built here
 * so that every figure is exact in float and in double: the four wheels spin down from 100 rad/s, where
 * tanh(100 / 0.5) is 1 to the last bit (the model's friction is its Coulomb level c = 1/64 N m, no viscous
 * term); Js = 1/16 kg m^2, T = 1/8 s, no motor command (u_s = 0: the net torque the monitor expects is -c).
 * Wheel 1 slows by 1/16 rad/s a period, a net torque of -Js (1/16) / T = -2c: its friction is twice the
 * model's, r = -c + 2c = c on each of the window's 100 residuals, sum r / sum f^ = 100 c / 100 c = 1, the
 * default threshold (the friction doubled). The other wheels slow by 1/32 rad/s a period, the model's c: r = 0.
 * At the threshold 1: no event and the model kept. With the threshold at 7/8 the same samples are high:
 * wheel_friction_high names wheel 1 at the window's end (the 100th residual, sample 100) with the scale 2 and
 * the threshold 1 + 7/8, and its model is doubled (which shows the excess was 1 exactly). */
static void test_a_friction_excess_exactly_at_the_threshold_is_not_high(void **state)
{
    (void)state;
    const double c = 1.0 / 64.0;
    const uint64_t period_ns = 125000000ull;
    for (int below = 0; below < 2; ++below) {
        aocs_wheels_config_t wc;
        aocs_fdir_config_t fc;
        aocs_wheels_t wa;
        aocs_fdir_t f;
        aocs_wheels_alloc_t alloc;
        test_wheels_pyramid(&wc);
        wc.period_s = AOCS_R(0.125);
        for (uint32_t i = 0u; i < 4u; ++i) {
            wc.js_kgm2[i] = AOCS_R(0.0625);
            wc.coulomb_nm[i] = (real_t)c;
            wc.coulomb_width_radps[i] = AOCS_R(0.5);
        }
        assert_int_equal(aocs_wheels_init(&wa, &wc), AOCS_OK);
        aocs_fdir_config_default(&fc);
        assert_close(fc.wheel_friction_excess, 1.0, 0.0);
        assert_int_equal(fc.wheel_friction_window, 100u);
        if (below != 0) {
            fc.wheel_friction_excess = AOCS_R(0.875);
        }
        assert_int_equal(aocs_fdir_init(&f, &fc), AOCS_OK);
        (void)memset(&alloc, 0, sizeof(alloc));
        for (uint32_t k = 0u; k <= 100u; ++k) {
            aocs_fdir_input_t in;
            real_t om[AOCS_WHEELS_MAX] = {0};
            for (uint32_t i = 0u; i < 4u; ++i) {
                om[i] = (real_t)(100.0 - ((double)k * ((i == 1u) ? (1.0 / 16.0) : (1.0 / 32.0))));
            }
            (void)memset(&in, 0, sizeof(in));
            in.t_ns = (uint64_t)k * period_ns;
            in.period_s = AOCS_R(0.125);
            in.have_sample = 1;
            in.input_status = AOCS_OK;
            in.mode = AOCS_EXEC_MODE_NOMINAL;
            in.wheel_speed_radps = om;
            in.alloc = &alloc;
            aocs_fdir_step(&f, &in, &wa);
        }
        if (below == 0) {
            assert_int_equal(count_id(&f.log, AOCS_EVT_WHEEL_FRICTION_HIGH, -1, NULL), 0u);
            assert_int_equal(aocs_evlog_count(&f.log), 0u);
            assert_close(wa.cfg.coulomb_nm[1], c, 0.0);
        } else {
            aocs_event_t e;
            assert_int_equal(aocs_evlog_count(&f.log), 1u);
            assert_int_equal(aocs_evlog_next(&f.log, 0u, &e, NULL), AOCS_OK);
            assert_int_equal(e.id, AOCS_EVT_WHEEL_FRICTION_HIGH);
            assert_int_equal(e.unit, 1);
            assert_int_equal(e.t_ns, 100u * period_ns);
            assert_close(e.value, 2.0, 0.0);
            assert_close(e.threshold, 1.875, 0.0);
            assert_close(wa.cfg.coulomb_nm[1], 2.0 * c, 0.0);
            assert_close(wa.cfg.coulomb_nm[0], c, 0.0);
        }
    }
}

/* three wheels: the last three cannot lose one -> wheel_isolation_refused, SAFE latched, the array unchanged */
static void test_isolation_of_the_third_wheel_is_refused_and_latches_safe(void **state)
{
    (void)state;
    wheel_rig_t r;
    uint64_t t = 0u;
    rig_init(&r, 3u, 0.0, 0.0);
    for (uint32_t k = 0u; k < 50u; ++k) {
        rig_step(&r, aocs_vec3_make(AOCS_R(0.1), AOCS_R(0.1), AOCS_R(0.1)), (k >= 10u) ? 1u : 0u, 0.0, 0.0);
    }
    assert_int_equal(count_id(&r.f.log, AOCS_EVT_WHEEL_RESIDUAL_HIGH, 0, &t), 1u);
    assert_int_equal(count_id(&r.f.log, AOCS_EVT_WHEEL_ISOLATION_REFUSED, 0, NULL), 1u);
    assert_int_equal(count_id(&r.f.log, AOCS_EVT_WHEEL_ISOLATED, -1, NULL), 0u);
    assert_int_equal(r.wa.cfg.failed_mask, 1u << 3);
    assert_int_equal(r.wa.n_healthy, 3u);
    assert_int_equal(r.f.safe_latched, 1);
    assert_int_equal(aocs_evlog_count_at_least(&r.f.log, AOCS_SEV_CRITICAL), 1u);
}

/* ---- the star-tracker monitor on a given innovation sequence ---- */
/* a NOMINAL step's input at sample k with a sample (have) and the acceptance's verdict on it */
static aocs_fdir_input_t base_input(uint64_t k, int have, aocs_exec_mode_t mode)
{
    aocs_fdir_input_t in;
    (void)memset(&in, 0, sizeof(in));
    in.t_ns = k * PERIOD_NS;
    in.period_s = AOCS_R(PERIOD_S);
    in.have_sample = have;
    in.input_status = (have != 0) ? AOCS_OK : AOCS_ERR_INPUT_MISSING;
    in.mode = mode;
    return in;
}

static void st_feed(aocs_fdir_t *f, uint64_t k, real_t d2, aocs_status_t st_status)
{
    aocs_fdir_input_t in = base_input(k, 1, AOCS_EXEC_MODE_NOMINAL);
    aocs_det_output_t est;
    (void)memset(&est, 0, sizeof(est));
    est.status = AOCS_OK;
    est.st_status = st_status;
    est.innovation_chi2 = d2;
    in.est = &est;
    aocs_fdir_step(f, &in, NULL);
}

/* one tested tracker sample whose whitened innovation is z (d^2 = |z|^2), applied unless excluded */
/* The i-th of an alternating sequence +z, -z, +z, ...: white (a window of an even count sums to zero). */
static aocs_vec3_t alternating(aocs_vec3_t z, int i)
{
    return ((i % 2) == 0) ? z : aocs_vec3_scale(z, AOCS_R(-1.0));
}

static void st_feed_white(aocs_fdir_t *f, uint64_t k, aocs_vec3_t z)
{
    aocs_fdir_input_t in = base_input(k, 1, AOCS_EXEC_MODE_NOMINAL);
    aocs_det_output_t est;
    (void)memset(&est, 0, sizeof(est));
    est.status = AOCS_OK;
    est.innovation_white = z;
    est.innovation_chi2 = aocs_vec3_norm_sq(z);
    est.st_status = (f->st.excluded != 0) ? AOCS_ERR_MEKF_ST_EXCLUDED : AOCS_OK;
    in.est = &est;
    aocs_fdir_step(f, &in, NULL);
}

/* the tracker's noise adaptation (docs/spec.md 5.15.3): a noise 10 times its model excluded at the 5th
 * sample, then (a window of fdir.st_restore = 20 samples whose innovation is white) re-admitted with its noise
 * variances scaled by the measured spread, about 100; its noise back to the model's, the scale follows back
 * to 1 within a window; a bias (a white noise around a 20 sigma offset) fails the whiteness test: never
 * rescaled; with fdir.st_noise_scale_max 0 nothing is rescaled. */
static void test_noisy_tracker_rescaled_and_readmitted(void **state)
{
    (void)state;
    aocs_fdir_t f;
    aocs_fdir_config_t c;
    test_rng_t rng = {2026u};
    uint64_t k = 0u;
    uint64_t t = 0u;
    aocs_event_t e;
    aocs_fdir_config_default(&c);
    assert_int_equal(aocs_fdir_init(&f, &c), AOCS_OK);
    assert_close(f.st.noise_scale, 1.0, 0.0);
    /* the window starts with the sample that excluded it (the 5th high one): the 20th is the 24th sample */
    for (int i = 0; i < 24; ++i) {
        st_feed_white(&f, ++k, test_random_vec3(&rng, 10.0 * sqrt(3.0))); /* uniform: per axis variance 100 */
        assert_int_equal(f.st.excluded, ((i >= 4) && (i < 23)) ? 1 : 0);
        assert_int_equal(f.st_rescaled, (i == 23) ? 1 : 0);
    }
    assert_int_equal(count_id(&f.log, AOCS_EVT_ST_NOISE_RESCALED, -1, &t), 1u);
    assert_int_equal(t, k * PERIOD_NS);
    assert_int_equal(count_id(&f.log, AOCS_EVT_ST_RESTORED, -1, NULL), 1u);
    assert_true(((double)f.st.noise_scale > 50.0) && ((double)f.st.noise_scale < 200.0));
    assert_int_equal(aocs_evlog_next(&f.log, 2u, &e, NULL), AOCS_OK); /* the rescale event: the 1-sigma factor */
    assert_int_equal(e.id, AOCS_EVT_ST_NOISE_RESCALED);
    assert_close(e.value, sqrt((double)f.st.noise_scale), 1e-5 * sqrt((double)f.st.noise_scale));
    /* under the scaled model the innovation is white with unit spread: nothing moves */
    {
        const real_t s = f.st.noise_scale;
        for (int i = 0; i < 60; ++i) {
            st_feed_white(&f, ++k, test_random_vec3(&rng, sqrt(3.0)));
        }
        assert_close(f.st.noise_scale, s, 0.0);
    }
    /* the noise back to the model's: a spread of about 1 / 100 of the scaled model: back to 1 */
    for (int i = 0; i < 20; ++i) {
        st_feed_white(&f, ++k, test_random_vec3(&rng, 0.1 * sqrt(3.0)));
    }
    assert_true((double)f.st.noise_scale < 2.0);
    assert_int_equal(count_id(&f.log, AOCS_EVT_ST_NOISE_RESCALED, -1, NULL), 2u);
    assert_int_equal(f.st.excluded, 0);

    /* a 20 sigma bias with unit noise: excluded, never white, never rescaled */
    assert_int_equal(aocs_fdir_init(&f, &c), AOCS_OK);
    for (int i = 0; i < 200; ++i) {
        aocs_vec3_t z = test_random_vec3(&rng, sqrt(3.0));
        z.v[0] += AOCS_R(20.0);
        st_feed_white(&f, ++k, z);
    }
    assert_int_equal(f.st.excluded, 1);
    assert_int_equal(count_id(&f.log, AOCS_EVT_ST_NOISE_RESCALED, -1, NULL), 0u);
    assert_close(f.st.noise_scale, 1.0, 0.0);

    /* the adaptation off */
    c.st_noise_scale_max = AOCS_R(0.0);
    assert_int_equal(aocs_fdir_init(&f, &c), AOCS_OK);
    for (int i = 0; i < 100; ++i) {
        st_feed_white(&f, ++k, test_random_vec3(&rng, 10.0 * sqrt(3.0)));
    }
    assert_int_equal(f.st.excluded, 1);
    assert_int_equal(count_id(&f.log, AOCS_EVT_ST_NOISE_RESCALED, -1, NULL), 0u);
    /* a spread beyond the largest scale: stays excluded */
    c.st_noise_scale_max = AOCS_R(10.0);
    assert_int_equal(aocs_fdir_init(&f, &c), AOCS_OK);
    for (int i = 0; i < 100; ++i) {
        st_feed_white(&f, ++k, test_random_vec3(&rng, 10.0 * sqrt(3.0)));
    }
    assert_int_equal(f.st.excluded, 1);
    assert_int_equal(count_id(&f.log, AOCS_EVT_ST_NOISE_RESCALED, -1, NULL), 0u);
}

/* A watched tracker's sample whose whitened innovation is not finite (tested by the filter, but no z to sum)
 * restarts the noise window (spec 5.15.3: a window is W = fdir.st_restore = 20 tested samples of z): the
 * window then closes at the 20th sample after it, not before. The innovations are built here, z = +-(10, 10,
 * 10) alternating (d^2 = 300, far above st_chi2: the tracker is excluded at the 5th and never restored by the
 * innovation test); the window starts with that 5th sample, holds 10 when the non-finite one comes, and the
 * 20 samples after it sum to zero: white (mean 0), spread m = 20 x 300 / (3 x 19) = 6000 / 57, so at the 20th
 * the noise is scaled by m and the tracker re-admitted (st_noise_rescaled, value sqrt(m); st_restored,
 * value m). A window that kept counting across the non-finite sample would close one sample early. */
static void test_a_non_finite_innovation_restarts_the_noise_window(void **state)
{
    (void)state;
    aocs_fdir_t f;
    aocs_fdir_config_t c;
    const double m = 6000.0 / 57.0;
    const aocs_vec3_t z = aocs_vec3_make(AOCS_R(10.0), AOCS_R(10.0), AOCS_R(10.0));
    uint64_t k = 0u;
    uint64_t t = 0u;
    aocs_event_t e;
    aocs_fdir_config_default(&c);
    assert_int_equal(c.st_restore, 20u);
    assert_int_equal(aocs_fdir_init(&f, &c), AOCS_OK);
    for (int i = 0; i < 14; ++i) {
        st_feed_white(&f, ++k, alternating(z, i));
        assert_int_equal(f.st.excluded, (i >= 4) ? 1 : 0);
    }
    st_feed_white(&f, ++k, aocs_vec3_make((real_t)NAN, (real_t)NAN, (real_t)NAN));
    for (int i = 0; i < 19; ++i) {
        st_feed_white(&f, ++k, alternating(z, i));
    }
    /* 19 samples of the new window: nothing yet */
    assert_int_equal(f.st.excluded, 1);
    assert_int_equal(count_id(&f.log, AOCS_EVT_ST_NOISE_RESCALED, -1, NULL), 0u);
    assert_int_equal(count_id(&f.log, AOCS_EVT_ST_RESTORED, -1, NULL), 0u);
    assert_close(f.st.noise_scale, 1.0, 0.0);
    /* the 20th closes it */
    st_feed_white(&f, ++k, aocs_vec3_scale(z, AOCS_R(-1.0)));
    assert_int_equal(f.st.excluded, 0);
    assert_int_equal(f.st_rescaled, 1);
    assert_int_equal(count_id(&f.log, AOCS_EVT_ST_NOISE_RESCALED, -1, &t), 1u);
    assert_int_equal(t, k * PERIOD_NS);
    assert_int_equal(count_id(&f.log, AOCS_EVT_ST_RESTORED, -1, &t), 1u);
    assert_int_equal(t, k * PERIOD_NS);
    assert_close(f.st.noise_scale, m, 1.0e-6); /* relative */
    assert_int_equal(aocs_evlog_next(&f.log, 2u, &e, NULL), AOCS_OK); /* after innovation_high and excluded */
    assert_int_equal(e.id, AOCS_EVT_ST_NOISE_RESCALED);
    assert_close(e.value, sqrt(m), 1.0e-6);
    assert_int_equal(aocs_evlog_count(&f.log), 4u);
}

/* A rescaled tracker whose innovations become too small follows them down, but never below its model: the
 * scale is not below 1 (spec 5.15.3). The tracker is first excluded and rescaled as in the test above: z =
 * +-(10, 10, 10) alternating (d^2 = 300), excluded at the 5th sample, the window from that 5th sample to the
 * 24th sums to zero, m = 20 x 300 / (3 x 19) = 6000 / 57 (about 105): scaled by m and re-admitted. Rescaled,
 * it is watched; then 20 samples z = +-(1/16, 1/16, 1/16) alternating (d^2 = 3 / 256, consistent): mean 0
 * (white), spread m' = 20 x 3 / 256 / (3 x 19) = 20 / 4864, below AOCS_FDIR_ST_NOISE_BAND_LO = 1/4, and the
 * scale times m', (6000 / 57) x (20 / 4864) = 0.43, is below 1: the scale goes to exactly 1 (not to 0.43, and
 * not to anything below), with an st_noise_rescaled event of value sqrt(1) = 1 (threshold: the largest
 * 1-sigma factor, sqrt(fdir.st_noise_scale_max)). At 1 the tracker is no longer watched: nothing more. */
static void test_a_small_innovation_rescales_the_tracker_noise_back_to_1_not_below(void **state)
{
    (void)state;
    aocs_fdir_t f;
    aocs_fdir_config_t c;
    const double m = 6000.0 / 57.0;
    const aocs_vec3_t z = aocs_vec3_make(AOCS_R(10.0), AOCS_R(10.0), AOCS_R(10.0));
    const aocs_vec3_t zs = aocs_vec3_make(AOCS_R(0.0625), AOCS_R(0.0625), AOCS_R(0.0625));
    uint64_t k = 0u;
    aocs_event_t e;
    aocs_fdir_config_default(&c);
    assert_int_equal(c.st_restore, 20u);
    assert_true((double)c.st_noise_scale_max >= m);
    assert_int_equal(aocs_fdir_init(&f, &c), AOCS_OK);
    for (int i = 0; i < 24; ++i) {
        st_feed_white(&f, ++k, alternating(z, i));
        assert_int_equal(f.st.excluded, ((i >= 4) && (i < 23)) ? 1 : 0);
    }
    assert_int_equal(count_id(&f.log, AOCS_EVT_ST_NOISE_RESCALED, -1, NULL), 1u);
    assert_close(f.st.noise_scale, m, 1.0e-6); /* relative */
    /* the small innovations: 19 samples, the window still open */
    for (int i = 0; i < 19; ++i) {
        st_feed_white(&f, ++k, alternating(zs, i));
        assert_int_equal(f.st.excluded, 0);
    }
    assert_int_equal(count_id(&f.log, AOCS_EVT_ST_NOISE_RESCALED, -1, NULL), 1u);
    assert_close(f.st.noise_scale, m, 1.0e-6);
    /* the 20th closes it: the scale back to 1, exactly */
    st_feed_white(&f, ++k, aocs_vec3_scale(zs, AOCS_R(-1.0)));
    assert_int_equal(f.st.excluded, 0);
    assert_int_equal(f.st_rescaled, 1);
    assert_int_equal(count_id(&f.log, AOCS_EVT_ST_NOISE_RESCALED, -1, NULL), 2u);
    assert_close(f.st.noise_scale, 1.0, 0.0);
    /* events: innovation_high, excluded, rescaled, restored, then this rescale */
    assert_int_equal(aocs_evlog_count(&f.log), 5u);
    assert_int_equal(aocs_evlog_next(&f.log, 4u, &e, NULL), AOCS_OK);
    assert_int_equal(e.id, AOCS_EVT_ST_NOISE_RESCALED);
    assert_int_equal(e.t_ns, k * PERIOD_NS);
    assert_close(e.value, 1.0, 0.0);
    assert_close(e.threshold, sqrt((double)c.st_noise_scale_max), 1.0e-6);
    /* at 1 it is not watched: 40 more small samples change nothing */
    for (int i = 0; i < 40; ++i) {
        st_feed_white(&f, ++k, alternating(zs, i));
    }
    assert_close(f.st.noise_scale, 1.0, 0.0);
    assert_int_equal(aocs_evlog_count(&f.log), 5u);
}

static void test_st_excluded_after_persist_and_restored_after_restore(void **state)
{
    (void)state;
    aocs_fdir_t f;
    aocs_fdir_config_t c;
    uint64_t t = 0u;
    uint64_t k = 0u;
    aocs_fdir_config_default(&c);
    assert_int_equal(aocs_fdir_init(&f, &c), AOCS_OK);
    /* four high, one low, four high: never five in a row */
    for (int i = 0; i < 4; ++i) {
        st_feed(&f, ++k, AOCS_R(100.0), AOCS_ERR_MEKF_GATED);
    }
    st_feed(&f, ++k, AOCS_R(3.0), AOCS_OK);
    for (int i = 0; i < 4; ++i) {
        st_feed(&f, ++k, AOCS_R(100.0), AOCS_ERR_MEKF_GATED);
    }
    assert_int_equal(aocs_evlog_count(&f.log), 0u);
    /* a step without a sample does not break the run, the fifth high does */
    st_feed(&f, ++k, AOCS_R(0.0), AOCS_ERR_INPUT_MISSING);
    st_feed(&f, ++k, AOCS_R(100.0), AOCS_ERR_MEKF_GATED);
    assert_int_equal(count_id(&f.log, AOCS_EVT_ST_INNOVATION_HIGH, -1, &t), 1u);
    assert_int_equal(t, k * PERIOD_NS);
    assert_int_equal(count_id(&f.log, AOCS_EVT_ST_EXCLUDED, -1, NULL), 1u);
    assert_int_equal(f.st.excluded, 1);
    /* 19 consistent, one high (the run restarts), then 20 consistent: restored at the 20th */
    for (int i = 0; i < 19; ++i) {
        st_feed(&f, ++k, AOCS_R(2.0), AOCS_ERR_MEKF_ST_EXCLUDED);
    }
    st_feed(&f, ++k, AOCS_R(20.0), AOCS_ERR_MEKF_GATED);
    for (int i = 0; i < 19; ++i) {
        st_feed(&f, ++k, AOCS_R(2.0), AOCS_ERR_MEKF_ST_EXCLUDED);
    }
    assert_int_equal(f.st.excluded, 1);
    st_feed(&f, ++k, AOCS_R(2.0), AOCS_ERR_MEKF_ST_EXCLUDED);
    assert_int_equal(f.st.excluded, 0);
    assert_int_equal(count_id(&f.log, AOCS_EVT_ST_RESTORED, -1, &t), 1u);
    assert_int_equal(t, k * PERIOD_NS);
    assert_int_equal(aocs_evlog_count(&f.log), 3u);
}

/* ---- frozen tracker, stuck gyro: samples built here ---- */
static void sensor_feed(aocs_fdir_t *f, uint64_t k, aocs_quat_t q, aocs_vec3_t w)
{
    aocs_fdir_input_t in = base_input(k, 1, AOCS_EXEC_MODE_NOMINAL);
    in.st_q_SN = q;
    in.st_valid = 1;
    in.gyro_w_B = w;
    in.gyro_valid = 1;
    aocs_fdir_step(f, &in, NULL);
}

static void test_frozen_tracker_while_turning(void **state)
{
    (void)state;
    aocs_fdir_t f;
    aocs_fdir_config_t c;
    test_rng_t rng = {12345u};
    aocs_quat_t q = test_random_quat(&rng);
    uint64_t k = 0u;
    uint64_t t = 0u;
    aocs_fdir_config_default(&c);
    assert_int_equal(aocs_fdir_init(&f, &c), AOCS_OK);
    /* at rest (gyro 1e-5 rad/s < 1e-4): a constant quaternion is no fault */
    for (int i = 0; i < 20; ++i) {
        sensor_feed(&f, ++k, q, aocs_vec3_make(AOCS_R(1.0e-5), AOCS_R(0.0), AOCS_R(0.0)));
    }
    assert_int_equal(aocs_evlog_count(&f.log), 0u);
    /* turning at 1e-3 rad/s: the 5th identical sample (4 repeats) is a frozen tracker */
    for (int i = 0; i < 3; ++i) {
        sensor_feed(&f, ++k, q, aocs_vec3_make(AOCS_R(1.0e-3), AOCS_R(0.0), AOCS_R(0.0)));
    }
    assert_int_equal(aocs_evlog_count(&f.log), 0u);
    sensor_feed(&f, ++k, q, aocs_vec3_make(AOCS_R(1.0e-3), AOCS_R(0.0), AOCS_R(0.0)));
    assert_int_equal(count_id(&f.log, AOCS_EVT_ST_FROZEN, -1, &t), 1u);
    assert_int_equal(t, k * PERIOD_NS);
    assert_int_equal(count_id(&f.log, AOCS_EVT_ST_EXCLUDED, -1, NULL), 1u);
    assert_int_equal(f.st.excluded, 1);
}

/* q0 turned by a random rotation of about sigma_rad per axis (a tracker's noise) */
static aocs_quat_t noisy_quat(test_rng_t *rng, aocs_quat_t q0, double sigma_rad)
{
    const aocs_vec3_t e = test_random_vec3(rng, sigma_rad);
    aocs_quat_t q = q0;
    assert_int_equal(aocs_quat_normalize(aocs_quat_mul(q0, aocs_quat_make(AOCS_R(0.5) * e.v[0], AOCS_R(0.5) * e.v[1],
                                                                          AOCS_R(0.5) * e.v[2], AOCS_R(1.0))),
                                         &q),
                     AOCS_OK);
    return q;
}

/* a sample the MEKF tested (its tracker model has noise) with innovation d2 */
/* one sample of both sensors whose tracker sample the filter tested (innovation d2, its verdict st_status) */
static void filter_feed(aocs_fdir_t *f, uint64_t k, aocs_quat_t q, aocs_vec3_t w, real_t d2, aocs_status_t st_status)
{
    aocs_fdir_input_t in = base_input(k, 1, AOCS_EXEC_MODE_NOMINAL);
    aocs_det_output_t est;
    (void)memset(&est, 0, sizeof(est));
    est.status = AOCS_OK;
    est.st_status = st_status;
    est.innovation_chi2 = d2;
    in.est = &est;
    in.st_q_SN = q;
    in.st_valid = 1;
    in.gyro_w_B = w;
    in.gyro_valid = 1;
    aocs_fdir_step(f, &in, NULL);
}

/* a hold's sample (the gyro at a few 1e-6 rad/s), applied unless the tracker is excluded */
static void tested_feed(aocs_fdir_t *f, uint64_t k, aocs_quat_t q, real_t d2)
{
    filter_feed(f, k, q, aocs_vec3_make(AOCS_R(1.0e-6), AOCS_R(-2.0e-6), AOCS_R(0.5e-6)), d2,
                (f->st.excluded != 0) ? AOCS_ERR_MEKF_ST_EXCLUDED : AOCS_OK);
}

/* in a hold (the gyro far below st_frozen_rate_radps) a tracker the MEKF tests, i.e. models with noise, that
 * repeats its quaternion is frozen; a live one (noise on every sample) is not, and one that comes back to life
 * is restored after st_restore consistent samples */
static void test_frozen_tracker_in_a_hold_when_the_filter_models_its_noise(void **state)
{
    (void)state;
    aocs_fdir_t f;
    aocs_fdir_config_t c;
    test_rng_t rng = {4242u};
    const aocs_quat_t q0 = test_random_quat(&rng);
    uint64_t k = 0u;
    uint64_t t = 0u;
    aocs_fdir_config_default(&c);
    assert_int_equal(aocs_fdir_init(&f, &c), AOCS_OK);
    /* a live tracker: 1 arcsec of noise about a constant attitude, 50 samples, nothing */
    for (int i = 0; i < 50; ++i) {
        tested_feed(&f, ++k, noisy_quat(&rng, q0, 4.8e-6), AOCS_R(3.0));
    }
    assert_int_equal(aocs_evlog_count(&f.log), 0u);
    /* frozen at q0: the 5th identical sample (4 repeats) */
    for (int i = 0; i < 4; ++i) {
        tested_feed(&f, ++k, q0, AOCS_R(3.0));
    }
    assert_int_equal(aocs_evlog_count(&f.log), 0u);
    tested_feed(&f, ++k, q0, AOCS_R(3.0));
    assert_int_equal(count_id(&f.log, AOCS_EVT_ST_FROZEN, -1, &t), 1u);
    assert_int_equal(t, k * PERIOD_NS);
    assert_int_equal(f.st.excluded, 1);
    /* still frozen: consistent innovations do not restore it */
    for (int i = 0; i < 40; ++i) {
        tested_feed(&f, ++k, q0, AOCS_R(1.0));
    }
    assert_int_equal(f.st.excluded, 1);
    /* alive again: restored at the st_restore-th consistent sample */
    for (uint32_t i = 0u; i < c.st_restore; ++i) {
        assert_int_equal(f.st.excluded, 1);
        tested_feed(&f, ++k, noisy_quat(&rng, q0, 4.8e-6), AOCS_R(3.0));
    }
    assert_int_equal(f.st.excluded, 0);
    assert_int_equal(count_id(&f.log, AOCS_EVT_ST_RESTORED, -1, NULL), 1u);
    assert_int_equal(count_id(&f.log, AOCS_EVT_ST_FROZEN, -1, NULL), 1u);
}

/* ---- the gyro bias-jump monitor on a given sequence of filter outputs ---- */
#define BIAS_SIGMA 6.5e-8 /* the filter's bias 1-sigma per axis, rad/s (irassi_rw_mekf at 500 s) */
#define BIAS_RRW 1.0e-10  /* sigma_u, rad/s^1.5 */

/* a tracker sample the filter applied at step k, with bias estimate b and bias variances p (per axis) */
static void bias_feed_rrw(aocs_fdir_t *f, uint64_t k, aocs_vec3_t b, const double p[3], uint32_t restarts,
                          aocs_status_t st_status, double rrw)
{
    aocs_fdir_input_t in = base_input(k, 1, AOCS_EXEC_MODE_NOMINAL);
    aocs_det_output_t est;
    (void)memset(&est, 0, sizeof(est));
    est.status = AOCS_OK;
    est.st_status = st_status;
    est.bias_B_radps = b;
    /* the bias diagonal of the 6 x 6 upper triangle, row-major: (3,3) (4,4) (5,5) */
    est.p_upper[15] = (real_t)p[0];
    est.p_upper[18] = (real_t)p[1];
    est.p_upper[20] = (real_t)p[2];
    est.n_restarts = restarts;
    in.est = &est;
    in.gyro_rrw_radps1p5 = (real_t)rrw;
    aocs_fdir_step(f, &in, NULL);
}

static void bias_feed(aocs_fdir_t *f, uint64_t k, aocs_vec3_t b, const double p[3], uint32_t restarts,
                      aocs_status_t st_status)
{
    bias_feed_rrw(f, k, b, p, restarts, st_status, BIAS_RRW);
}

/* A steady filter whose estimate wanders inside its own sigma raises nothing over an hour of 10 Hz samples;
 * an estimate 6 sigma off its reference (36 sigma^2 against the bound 25 (2 sigma^2 + sigma_u^2 dt) = 50
 * sigma^2) is inside the bound for ever; 8 sigma off (64 sigma^2) raises gyro_st_inconsistent (unit: the
 * axis, y) at the 10th consecutive sample and asks for the re-inflation on that step only */
static void test_gyro_bias_jump_is_detected_when_the_estimate_leaves_its_bound(void **state)
{
    (void)state;
    aocs_fdir_t f;
    aocs_fdir_config_t c;
    test_rng_t rng = {99u};
    const double p[3] = {BIAS_SIGMA * BIAS_SIGMA, BIAS_SIGMA * BIAS_SIGMA, BIAS_SIGMA * BIAS_SIGMA};
    const aocs_vec3_t b0 = aocs_vec3_make(AOCS_R(4.8e-7), AOCS_R(-4.8e-7), AOCS_R(2.4e-7));
    uint64_t k = 0u;
    uint64_t t = 0u;
    aocs_fdir_config_default(&c);
    assert_int_equal(aocs_fdir_init(&f, &c), AOCS_OK);
    bias_feed(&f, ++k, b0, p, 0u, AOCS_OK);
    for (uint32_t i = 0u; i < 36000u; ++i) {
        const aocs_vec3_t n = test_random_vec3(&rng, BIAS_SIGMA); /* within +-sigma of the reference */
        bias_feed(&f, ++k, aocs_vec3_add(b0, n), p, 0u, AOCS_OK);
        assert_int_equal(f.reinflate_bias, 0);
    }
    assert_int_equal(aocs_evlog_count(&f.log), 0u);
    assert_int_equal(f.gyro.t_ref_ns, PERIOD_NS); /* the first sample is still the reference */
    for (uint32_t i = 0u; i < 100u; ++i) {
        bias_feed(&f, ++k, aocs_vec3_make(b0.v[0], b0.v[1] + AOCS_R(6.0 * BIAS_SIGMA), b0.v[2]), p, 0u, AOCS_OK);
    }
    assert_int_equal(aocs_evlog_count(&f.log), 0u);
    for (uint32_t i = 1u; i <= 10u; ++i) {
        bias_feed(&f, ++k, aocs_vec3_make(b0.v[0], b0.v[1] + AOCS_R(8.0 * BIAS_SIGMA), b0.v[2]), p, 0u, AOCS_OK);
        assert_int_equal(f.reinflate_bias, (i == 10u) ? 1 : 0);
        assert_int_equal(aocs_evlog_count(&f.log), (i == 10u) ? 1u : 0u);
    }
    assert_int_equal(count_id(&f.log, AOCS_EVT_GYRO_ST_INCONSISTENT, 1, &t), 1u);
    assert_int_equal(t, k * PERIOD_NS);
    assert_int_equal(f.gyro.bias_armed, 0);
    /* the next applied sample (the filter's covariance re-inflated) takes the reference afresh */
    {
        const double big[3] = {2.3e-11, 2.3e-11, 2.3e-11};
        bias_feed(&f, ++k, b0, big, 0u, AOCS_OK);
        assert_int_equal(f.gyro.bias_armed, 1);
        assert_int_equal(f.gyro.t_ref_ns, k * PERIOD_NS);
        assert_int_equal(f.reinflate_bias, 0);
    }
}

/* The bound grows with the gyro's rate random walk since the reference, sigma_u^2 dt: with sigma_u = 1e-9
 * rad/s^1.5, 3380 s after the reference the walk is 0.8 sigma^2, the bound 25 (2 + 0.8) sigma^2 = 70 sigma^2:
 * an estimate 7.5 sigma off (56.25 sigma^2, beyond the 50 sigma^2 of the bound without the walk) raises
 * nothing; 8.5 sigma off (72.25 sigma^2) is inconsistent at the 10th sample */
static void test_gyro_bias_bound_grows_with_the_rate_random_walk(void **state)
{
    (void)state;
    const double p[3] = {BIAS_SIGMA * BIAS_SIGMA, BIAS_SIGMA * BIAS_SIGMA, BIAS_SIGMA * BIAS_SIGMA};
    const aocs_vec3_t b0 = aocs_vec3_make(AOCS_R(4.8e-7), AOCS_R(-4.8e-7), AOCS_R(2.4e-7));
    const uint64_t later = (uint64_t)(0.8 * BIAS_SIGMA * BIAS_SIGMA / (1.0e-9 * 1.0e-9) / 0.1) + 1u; /* periods */
    for (int big = 0; big < 2; ++big) {
        aocs_fdir_t f;
        aocs_fdir_config_t c;
        aocs_fdir_config_default(&c);
        assert_int_equal(aocs_fdir_init(&f, &c), AOCS_OK);
        bias_feed_rrw(&f, 1u, b0, p, 0u, AOCS_OK, 1.0e-9);
        const double off = (big != 0) ? 8.5 : 7.5;
        for (uint64_t k = later; k < (later + 10u); ++k) {
            bias_feed_rrw(&f, k, aocs_vec3_make(b0.v[0], b0.v[1] + (real_t)(off * BIAS_SIGMA), b0.v[2]), p, 0u,
                          AOCS_OK, 1.0e-9);
        }
        assert_int_equal(count_id(&f.log, AOCS_EVT_GYRO_ST_INCONSISTENT, 1, NULL), (big != 0) ? 1u : 0u);
    }
}

/* A reference gone stale by the random walk alone is renewed (spec 5.15.4): with the filter's variance steady at
 * sigma^2, the reference's sigma^2 plus the walk since, sigma_u^2 dt, passes 2 sigma^2 once dt > sigma^2 /
 * sigma_u^2 (4225 s here); the first sample after 1.2 times that takes the estimate of the moment as the new
 * reference, so an estimate 9.5 sigma off the old one (90 sigma^2, over 25 x 3.2 sigma^2 against the old
 * reference) raises nothing, now or on the samples after it. */
static void test_a_reference_the_walk_made_stale_is_renewed(void **state)
{
    (void)state;
    const double p[3] = {BIAS_SIGMA * BIAS_SIGMA, BIAS_SIGMA * BIAS_SIGMA, BIAS_SIGMA * BIAS_SIGMA};
    const aocs_vec3_t b0 = aocs_vec3_make(AOCS_R(4.8e-7), AOCS_R(-4.8e-7), AOCS_R(2.4e-7));
    const aocs_vec3_t b1 = aocs_vec3_make(b0.v[0], b0.v[1] + (real_t)(9.5 * BIAS_SIGMA), b0.v[2]);
    const uint64_t later = (uint64_t)(1.2 * BIAS_SIGMA * BIAS_SIGMA / (1.0e-9 * 1.0e-9) / 0.1) + 1u; /* periods */
    aocs_fdir_t f;
    aocs_fdir_config_t c;
    aocs_fdir_config_default(&c);
    assert_true((double)c.gyro_bias_chi2 * 3.2 < 9.5 * 9.5); /* against the old reference it would be over */
    assert_int_equal(aocs_fdir_init(&f, &c), AOCS_OK);
    bias_feed_rrw(&f, 1u, b0, p, 0u, AOCS_OK, 1.0e-9);
    assert_int_equal(f.gyro.t_ref_ns, PERIOD_NS);
    for (uint64_t k = later; k < (later + 2u * c.gyro_bias_persist); ++k) {
        bias_feed_rrw(&f, k, b1, p, 0u, AOCS_OK, 1.0e-9);
        assert_int_equal(f.gyro.t_ref_ns, later * PERIOD_NS); /* renewed at the first late sample */
    }
    assert_int_equal(count_id(&f.log, AOCS_EVT_GYRO_ST_INCONSISTENT, -1, NULL), 0u);
}

/* The bias-jump test is strict (spec 5.15.4: z = d^2 / var above fdir.gyro_bias_chi2): a change exactly at
 * the bound is not over. Everything here is a power of two, so that d^2 and chi2 var are the same number in
 * double and in float: the filter's and the reference's bias variances 2^-40 (rad/s)^2 per axis, var = 2^-39;
 * chi2 = 32, chi2 var = 2^-34; the estimate 2^-17 rad/s off its reference on x, d^2 = 2^-34. The random walk
 * is sigma_u = 2^-100 rad/s^1.5: sigma_u^2 dt (2^-200 times at most 2 s) is 0 in float (underflow) and in
 * double far below half a unit in the last place of var (2^-92): var stays 2^-39 exactly. The reference is
 * never stale (2^-40 + walk is not above 2 x 2^-40). At the bound: nothing over any number of samples. The
 * control, the same sequence with chi2 = 31 (d^2 = 32 var, over): gyro_st_inconsistent at the
 * fdir.gyro_bias_persist-th sample, on axis x, value z = d^2 / var = 32 exactly, threshold 31. */
static void test_a_gyro_bias_change_exactly_at_the_bound_is_not_over(void **state)
{
    (void)state;
    const double p[3] = {ldexp(1.0, -40), ldexp(1.0, -40), ldexp(1.0, -40)};
    const double rrw = ldexp(1.0, -100);
    const aocs_vec3_t b0 = aocs_vec3_zero();
    const aocs_vec3_t b1 = aocs_vec3_make((real_t)ldexp(1.0, -17), AOCS_R(0.0), AOCS_R(0.0));
    for (int control = 0; control < 2; ++control) {
        aocs_fdir_t f;
        aocs_fdir_config_t c;
        uint64_t k = 0u;
        uint64_t t = 0u;
        aocs_event_t e;
        aocs_fdir_config_default(&c);
        c.gyro_bias_chi2 = (control != 0) ? AOCS_R(31.0) : AOCS_R(32.0);
        assert_int_equal(aocs_fdir_init(&f, &c), AOCS_OK);
        bias_feed_rrw(&f, ++k, b0, p, 0u, AOCS_OK, rrw); /* the reference */
        assert_int_equal(f.gyro.bias_armed, 1);
        for (uint32_t i = 1u; i <= c.gyro_bias_persist; ++i) {
            bias_feed_rrw(&f, ++k, b1, p, 0u, AOCS_OK, rrw);
            assert_int_equal(f.gyro.bias_run, (control != 0) ? i : 0u);
            assert_int_equal(f.reinflate_bias, ((control != 0) && (i == c.gyro_bias_persist)) ? 1 : 0);
        }
        if (control == 0) {
            assert_int_equal(f.gyro.t_ref_ns, PERIOD_NS); /* tested against the first sample throughout */
            assert_int_equal(aocs_evlog_count(&f.log), 0u);
        } else {
            assert_int_equal(count_id(&f.log, AOCS_EVT_GYRO_ST_INCONSISTENT, 0, &t), 1u);
            assert_int_equal(t, k * PERIOD_NS);
            assert_int_equal(aocs_evlog_next(&f.log, 0u, &e, NULL), AOCS_OK);
            assert_close(e.value, 32.0, 0.0);
            assert_close(e.threshold, 31.0, 0.0);
        }
    }
}

/* What does not test: a sample the filter did not apply (gated, excluded, none), a filter that restarted (the
 * reference afresh), no filter (sigma_u 0), the test switched off (chi2 0); a converging filter renews its
 * reference (stale: the reference's variance above twice the present one) instead of testing against it */
static void test_gyro_bias_monitor_tests_only_applied_samples_of_a_filter(void **state)
{
    (void)state;
    aocs_fdir_t f;
    aocs_fdir_config_t c;
    const double p[3] = {BIAS_SIGMA * BIAS_SIGMA, BIAS_SIGMA * BIAS_SIGMA, BIAS_SIGMA * BIAS_SIGMA};
    const aocs_vec3_t far = aocs_vec3_make(AOCS_R(1.0e-5), AOCS_R(0.0), AOCS_R(0.0));
    uint64_t k = 0u;
    aocs_fdir_config_default(&c);
    assert_int_equal(aocs_fdir_init(&f, &c), AOCS_OK);
    bias_feed(&f, ++k, aocs_vec3_zero(), p, 0u, AOCS_OK);
    assert_int_equal(f.gyro.bias_armed, 1);
    for (int i = 0; i < 20; ++i) {
        bias_feed(&f, ++k, far, p, 0u, AOCS_ERR_MEKF_GATED);
        bias_feed(&f, ++k, far, p, 0u, AOCS_ERR_MEKF_ST_EXCLUDED);
        bias_feed(&f, ++k, far, p, 0u, AOCS_ERR_INPUT_MISSING);
    }
    assert_int_equal(aocs_evlog_count(&f.log), 0u);
    /* a restart: the far estimate becomes the reference */
    for (int i = 0; i < 20; ++i) {
        bias_feed(&f, ++k, far, p, 1u, AOCS_OK);
    }
    assert_int_equal(aocs_evlog_count(&f.log), 0u);
    assert_true(aocs_fdir_same(f.gyro.b_ref_B.v[0], far.v[0]) != 0);
    /* converging: the variance halves every sample while the estimate moves 3 present sigma a sample */
    {
        double pc[3] = {1.0e-12, 1.0e-12, 1.0e-12};
        double b = 0.0;
        for (int i = 0; i < 30; ++i) {
            pc[0] *= 0.45;
            b += 3.0 * sqrt(pc[0]);
            bias_feed(&f, ++k, aocs_vec3_make((real_t)b, AOCS_R(0.0), AOCS_R(0.0)), pc, 2u, AOCS_OK);
        }
        assert_int_equal(aocs_evlog_count(&f.log), 0u);
    }
    /* no filter, or the test off: a jump raises nothing */
    aocs_fdir_config_default(&c);
    c.gyro_bias_chi2 = AOCS_R(0.0);
    assert_int_equal(aocs_fdir_init(&f, &c), AOCS_OK);
    for (int i = 0; i < 20; ++i) {
        bias_feed(&f, ++k, (i < 1) ? aocs_vec3_zero() : far, p, 0u, AOCS_OK);
    }
    assert_int_equal(aocs_evlog_count(&f.log), 0u);
    aocs_fdir_config_default(&c);
    assert_int_equal(aocs_fdir_init(&f, &c), AOCS_OK);
    for (int i = 0; i < 20; ++i) {
        bias_feed_rrw(&f, ++k, (i < 1) ? aocs_vec3_zero() : far, p, 0u, AOCS_OK, 0.0); /* no filter: sigma_u 0 */
    }
    assert_int_equal(aocs_evlog_count(&f.log), 0u);
    /* and with the filter and the test on, the same jump is found */
    for (int i = 0; i < 12; ++i) {
        bias_feed(&f, ++k, (i < 1) ? aocs_vec3_zero() : far, p, 0u, AOCS_OK);
    }
    assert_int_equal(count_id(&f.log, AOCS_EVT_GYRO_ST_INCONSISTENT, 0, NULL), 1u);
}

static void test_stuck_gyro_axis_excludes_the_gyro_and_latches_safe(void **state)
{
    (void)state;
    aocs_fdir_t f;
    aocs_fdir_config_t c;
    test_rng_t rng = {777u};
    const aocs_quat_t q = aocs_quat_identity();
    uint64_t k = 0u;
    uint64_t t = 0u;
    aocs_fdir_config_default(&c);
    assert_int_equal(aocs_fdir_init(&f, &c), AOCS_OK);
    /* a noise-free gyro at rest (every axis repeats at once): no fault */
    for (int i = 0; i < 30; ++i) {
        sensor_feed(&f, ++k, q, aocs_vec3_zero());
    }
    assert_int_equal(aocs_evlog_count(&f.log), 0u);
    /* a noisy gyro whose y axis sticks at its last value: the 10th identical y sample */
    {
        real_t y = AOCS_R(0.0);
        for (int i = 0; i < 10; ++i) {
            const aocs_vec3_t n = test_random_vec3(&rng, 1.0e-6);
            if (i == 0) {
                y = n.v[1];
            }
            sensor_feed(&f, ++k, q, aocs_vec3_make(n.v[0], y, n.v[2]));
            if (i < 9) {
                assert_int_equal(aocs_evlog_count(&f.log), 0u);
            }
        }
    }
    assert_int_equal(count_id(&f.log, AOCS_EVT_GYRO_STUCK, 1, &t), 1u);
    assert_int_equal(t, k * PERIOD_NS);
    assert_int_equal(count_id(&f.log, AOCS_EVT_GYRO_EXCLUDED, 1, NULL), 1u);
    {
        /* both events carry the stuck reading as their value and no threshold (0: a repeat test has none) */
        aocs_event_t e;
        uint32_t seq = 0u;
        while (aocs_evlog_next(&f.log, seq, &e, NULL) == AOCS_OK) {
            assert_close(e.threshold, 0.0, 0.0);
            seq = e.seq;
        }
        assert_int_equal(seq, 2u);
    }
    assert_int_equal(f.safe_latched, 1);
}

/* A stuck axis with an estimator that can fly without the gyro (docs/spec.md 5.6.12): the gyro excluded, no
 * SAFE latched, estimator_gyroless raised and go_gyroless set for the executive on that step only; the
 * excluded gyro then shown to no monitor (the executive's rule) raises nothing more. */
static void test_gyro_stuck_goes_gyroless(void **state)
{
    (void)state;
    aocs_fdir_t f;
    aocs_fdir_config_t c;
    test_rng_t rng = {4242u};
    const aocs_quat_t q = test_random_quat(&rng);
    uint64_t k = 0u;
    uint64_t t = 0u;
    real_t y = AOCS_R(0.0);
    aocs_fdir_config_default(&c);
    assert_int_equal(aocs_fdir_init(&f, &c), AOCS_OK);
    for (int i = 0; i < 10; ++i) {
        aocs_fdir_input_t in = base_input(++k, 1, AOCS_EXEC_MODE_NOMINAL);
        const aocs_vec3_t n = test_random_vec3(&rng, 1.0e-6);
        if (i == 0) {
            y = n.v[1];
        }
        in.st_q_SN = q;
        in.st_valid = 1;
        in.gyro_w_B = aocs_vec3_make(n.v[0], y, n.v[2]);
        in.gyro_valid = 1;
        in.gyroless_capable = 1;
        aocs_fdir_step(&f, &in, NULL);
        assert_int_equal(f.go_gyroless, (i == 9) ? 1 : 0);
    }
    assert_int_equal(count_id(&f.log, AOCS_EVT_GYRO_EXCLUDED, 1, NULL), 1u);
    assert_int_equal(count_id(&f.log, AOCS_EVT_ESTIMATOR_GYROLESS, -1, &t), 1u);
    assert_int_equal(t, k * PERIOD_NS);
    assert_int_equal(f.gyro.excluded, 1);
    assert_int_equal(f.safe_latched, 0);
    for (int i = 0; i < 30; ++i) {
        aocs_fdir_input_t in = base_input(++k, 1, AOCS_EXEC_MODE_NOMINAL);
        in.st_q_SN = q;
        in.st_valid = 1;
        in.gyroless_capable = 1;
        aocs_fdir_step(&f, &in, NULL);
        assert_int_equal(f.go_gyroless, 0);
    }
    assert_int_equal(aocs_evlog_count(&f.log), 3u); /* gyro_stuck, gyro_excluded, estimator_gyroless */
}

static void test_gyro_saturation(void **state)
{
    (void)state;
    aocs_fdir_t f;
    aocs_fdir_config_t c;
    uint64_t k = 0u;
    test_rng_t rng = {99u};
    aocs_fdir_config_default(&c);
    c.gyro_sat_radps = AOCS_R(0.1);
    assert_int_equal(aocs_fdir_init(&f, &c), AOCS_OK);
    for (int i = 0; i < 10; ++i) {
        const aocs_vec3_t n = test_random_vec3(&rng, 1.0e-6);
        sensor_feed(&f, ++k, aocs_quat_identity(), aocs_vec3_make(n.v[0], n.v[1], AOCS_R(-0.1)));
    }
    assert_int_equal(count_id(&f.log, AOCS_EVT_GYRO_SATURATED, 2, NULL), 1u);
    assert_int_equal(count_id(&f.log, AOCS_EVT_GYRO_EXCLUDED, 2, NULL), 1u);
}

/* the tracker's attitude turning at rate_radps about the unit axis e since t = 0, with a random error
 * rotation of sigma_rad per axis (0: none) */
static aocs_quat_t turning_quat(const double e[3], double rate_radps, double t_s, test_rng_t *rng, double sigma_rad)
{
    const double h = 0.5 * rate_radps * t_s;
    aocs_quat_t q = aocs_quat_make((real_t)(e[0] * sin(h)), (real_t)(e[1] * sin(h)), (real_t)(e[2] * sin(h)),
                                   (real_t)cos(h));
    if (sigma_rad > 0.0) {
        q = noisy_quat(rng, q, sigma_rad);
    }
    return q;
}


/* A gyro pinned on every axis (saturated at 1e-3 rad/s) during a 5e-3 rad/s turn: the tracker's innovations
 * fail first and exclude it (5 samples); at the 10th identical gyro sample the tracker has turned 9 x 0.5 mrad
 * against the gyro's 9 x 0.17 mrad: gyro_stuck (the axis of the largest reading: all equal, x), the gyro
 * excluded, SAFE latched, the tracker restored. A noise-free gyro at the same constant rate as the tracker
 * (every axis repeating too), with an 8 arcsec tracker noise: nothing over 200 samples. */
static void test_a_gyro_pinned_on_every_axis_while_the_tracker_turns(void **state)
{
    (void)state;
    const double e[3] = {0.6, 0.64, 0.48};
    const double rate = 5.0e-3;
    const double sigma = 8.0 * 4.84813681109536e-6;
    aocs_fdir_t f;
    aocs_fdir_config_t c;
    test_rng_t rng = {4242u};
    uint64_t t_stuck = 0u;
    uint64_t k = 0u;
    aocs_fdir_config_default(&c);
    assert_int_equal(aocs_fdir_init(&f, &c), AOCS_OK);
    for (int i = 0; i < 200; ++i) {
        ++k;
        filter_feed(&f, k, turning_quat(e, rate, (double)k * PERIOD_S, &rng, sigma),
                    aocs_vec3_make((real_t)(rate * e[0]), (real_t)(rate * e[1]), (real_t)(rate * e[2])), AOCS_R(1.0),
                    AOCS_ERR_MEKF_GATED);
    }
    assert_int_equal(aocs_evlog_count(&f.log), 0u);
    /* now the gyro clips at 1e-3 on every axis and the filter's innovations of the tracker fail */
    for (int i = 0; i < 12; ++i) {
        ++k;
        filter_feed(&f, k, turning_quat(e, rate, (double)k * PERIOD_S, &rng, sigma),
                    aocs_vec3_make(AOCS_R(1.0e-3), AOCS_R(1.0e-3), AOCS_R(1.0e-3)), AOCS_R(100.0), AOCS_ERR_MEKF_GATED);
        if (i == 4) {
            assert_int_equal(f.st.excluded, 1); /* the 5th failed innovation (fdir.st_persist) */
        }
    }
    assert_int_equal(count_id(&f.log, AOCS_EVT_ST_EXCLUDED, -1, NULL), 1u);
    assert_int_equal(count_id(&f.log, AOCS_EVT_GYRO_STUCK, 0, &t_stuck), 1u);
    /* the first pinned sample is the 1st of the 12, the 10th identical one the 10th */
    assert_int_equal(t_stuck, (k - 2u) * PERIOD_NS);
    assert_int_equal(count_id(&f.log, AOCS_EVT_GYRO_EXCLUDED, 0, NULL), 1u);
    assert_int_equal(count_id(&f.log, AOCS_EVT_ST_RESTORED, -1, NULL), 1u);
    assert_int_equal(f.st.excluded, 0);
    assert_int_equal(f.safe_latched, 1);
}

/* ---- link and modes ---- */
static void mode_feed(aocs_fdir_t *f, uint64_t k, int have, uint32_t missing, aocs_exec_mode_t mode)
{
    aocs_fdir_input_t in = base_input(k, have, mode);
    in.missing = missing;
    aocs_fdir_step(f, &in, NULL);
}

static void test_link_and_safe_events(void **state)
{
    (void)state;
    aocs_fdir_t f;
    aocs_fdir_config_t c;
    uint64_t t = 0u;
    aocs_fdir_config_default(&c);
    assert_int_equal(aocs_fdir_init(&f, &c), AOCS_OK);
    /* start-up in SAFE (an estimator acquiring) is no event */
    mode_feed(&f, 1u, 1, 0u, AOCS_EXEC_MODE_SAFE);
    mode_feed(&f, 2u, 1, 0u, AOCS_EXEC_MODE_NOMINAL);
    assert_int_equal(aocs_evlog_count(&f.log), 0u);
    /* two periods without a sample: below 3, nothing; a gap of 3 samples in the ticks: link_lost + restored */
    mode_feed(&f, 3u, 0, 0u, AOCS_EXEC_MODE_NOMINAL);
    mode_feed(&f, 4u, 0, 0u, AOCS_EXEC_MODE_NOMINAL);
    mode_feed(&f, 5u, 1, 0u, AOCS_EXEC_MODE_NOMINAL);
    assert_int_equal(aocs_evlog_count(&f.log), 0u);
    mode_feed(&f, 9u, 1, 3u, AOCS_EXEC_MODE_NOMINAL);
    assert_int_equal(count_id(&f.log, AOCS_EVT_LINK_LOST, -1, &t), 1u);
    assert_int_equal(t, 9u * PERIOD_NS);
    assert_int_equal(count_id(&f.log, AOCS_EVT_LINK_RESTORED, -1, NULL), 1u);
    /* three periods without a sample: link_lost at the third, SAFE entered; restored and SAFE left later */
    mode_feed(&f, 10u, 0, 0u, AOCS_EXEC_MODE_NOMINAL);
    mode_feed(&f, 11u, 0, 0u, AOCS_EXEC_MODE_NOMINAL);
    mode_feed(&f, 12u, 0, 0u, AOCS_EXEC_MODE_SAFE);
    assert_int_equal(count_id(&f.log, AOCS_EVT_LINK_LOST, -1, NULL), 2u);
    assert_int_equal(count_id(&f.log, AOCS_EVT_SAFE_ENTERED, -1, &t), 1u);
    assert_int_equal(t, 12u * PERIOD_NS);
    mode_feed(&f, 13u, 1, 0u, AOCS_EXEC_MODE_SAFE);
    assert_int_equal(count_id(&f.log, AOCS_EVT_LINK_RESTORED, -1, NULL), 2u);
    mode_feed(&f, 14u, 1, 0u, AOCS_EXEC_MODE_NOMINAL);
    assert_int_equal(count_id(&f.log, AOCS_EVT_SAFE_LEFT, -1, &t), 1u);
    assert_int_equal(t, 14u * PERIOD_NS);
    assert_int_equal(aocs_evlog_count(&f.log), 6u);
}

/* a step in mode with a sample whose acceptance verdict is input_status, and the estimate est (NULL: none) */
static void verdict_feed(aocs_fdir_t *f, uint64_t k, aocs_exec_mode_t mode, aocs_status_t input_status,
                         const aocs_det_output_t *est)
{
    aocs_fdir_input_t in = base_input(k, 1, mode);
    in.input_status = input_status;
    in.est = est;
    aocs_fdir_step(f, &in, NULL);
}

/* safe_entered's value is why SAFE was entered: the sample's acceptance verdict when the sample was refused
 * (whatever the estimator says then), the estimator's status only when the sample was accepted, and AOCS_OK
 * when neither failed or there is no estimate (the SAFE is another's: a law, a latch). Four entries, each left
 * for NOMINAL before the next. */
static void test_safe_entered_value_is_the_input_verdict_before_the_estimator_status(void **state)
{
    (void)state;
    static const struct {
        aocs_status_t input_status;
        int with_est;
        aocs_status_t est_status;
        aocs_status_t why;
    } rows[] = {
        {AOCS_ERR_INPUT_INVALID, 1, AOCS_ERR_MEKF_NO_ATTITUDE, AOCS_ERR_INPUT_INVALID},
        {AOCS_OK, 1, AOCS_ERR_MEKF_NO_ATTITUDE, AOCS_ERR_MEKF_NO_ATTITUDE},
        {AOCS_ERR_INPUT_INVALID, 0, AOCS_OK, AOCS_ERR_INPUT_INVALID},
        {AOCS_OK, 0, AOCS_OK, AOCS_OK},
    };
    aocs_fdir_t f;
    aocs_fdir_config_t c;
    aocs_det_output_t ok_est;
    uint64_t k = 0u;
    uint32_t seq = 0u;
    aocs_fdir_config_default(&c);
    assert_int_equal(aocs_fdir_init(&f, &c), AOCS_OK);
    (void)memset(&ok_est, 0, sizeof(ok_est));
    ok_est.status = AOCS_OK;
    for (size_t r = 0u; r < (sizeof(rows) / sizeof(rows[0])); ++r) {
        aocs_det_output_t est;
        aocs_event_t e;
        (void)memset(&est, 0, sizeof(est));
        est.status = rows[r].est_status;
        verdict_feed(&f, ++k, AOCS_EXEC_MODE_NOMINAL, AOCS_OK, &ok_est);
        verdict_feed(&f, ++k, AOCS_EXEC_MODE_SAFE, rows[r].input_status, (rows[r].with_est != 0) ? &est : NULL);
        /* the previous row's safe_left, then this row's safe_entered */
        if (r > 0u) {
            assert_int_equal(aocs_evlog_next(&f.log, seq, &e, NULL), AOCS_OK);
            assert_int_equal(e.id, AOCS_EVT_SAFE_LEFT);
            seq = e.seq;
        }
        assert_int_equal(aocs_evlog_next(&f.log, seq, &e, NULL), AOCS_OK);
        assert_int_equal(e.id, AOCS_EVT_SAFE_ENTERED);
        assert_int_equal(e.t_ns, k * PERIOD_NS);
        assert_close(e.value, (double)rows[r].why, 0.0);
        seq = e.seq;
    }
    assert_int_equal(aocs_evlog_count(&f.log), 7u);
}

static void test_disabled_is_silent(void **state)
{
    (void)state;
    aocs_fdir_t f;
    aocs_fdir_config_t c;
    aocs_fdir_config_default(&c);
    c.enabled = 0u;
    assert_int_equal(aocs_fdir_init(&f, &c), AOCS_OK);
    mode_feed(&f, 1u, 1, 0u, AOCS_EXEC_MODE_NOMINAL);
    for (uint64_t k = 2u; k < 10u; ++k) {
        mode_feed(&f, k, 0, 0u, AOCS_EXEC_MODE_SAFE);
    }
    assert_int_equal(aocs_evlog_count(&f.log), 0u);
    aocs_fdir_step(NULL, NULL, NULL); /* total */
}


/* ---- the momentum monitor against a rigid body the test integrates ---- */

/*
 * The body (J = diag(2000, 6000, 6000) kg m^2) with four wheels at constant speeds (their momentum h_w, fixed)
 * under an external torque: the constant disturbance d plus the thrusters' torques as they really fire (the
 * flight software's on-times, less a thruster stuck closed, plus one stuck open at full thrust), integrated
 * by the test: J dw/dt = tau - w x (J w + h_w), dq/dt = 1/2 Xi(q) w, 200 substeps per 1 s period. The
 * momentum stage (the thrusters of aocs_mom, irassi_day's twelve 1 N thrusters in six couples on 1.2 m arms)
 * dumps h_w continuously at 0.02 N m; the body takes the dumped momentum and turns (about 0.3 rad over the
 * run: the monitor must do its sums in the inertial frame). The estimate given to the monitor is the truth.
 */
#define MOM_T_S 1.0
#define MOM_THR 12u

typedef struct {
    aocs_fdir_t f;
    aocs_wheels_t wa;
    aocs_mom_t mom;
    double w[3];
    double q[4];      /* q_BN, vector first */
    real_t omega[AOCS_WHEELS_MAX];
    double hw[3];     /* sum Js g Omega of the wheels, B */
    unsigned latch_b; /* bit i: the test's thruster i is fed through latch valve B */
    uint64_t t_ns;
} mom_rig_t;

static const double mom_j[3] = {2000.0, 6000.0, 6000.0};

/* latch_b_mask: the thrusters fed through latch valve B (MOM_LATCH_TWINS: each couple's two on different
 * branches) */
#define MOM_LATCH_TWINS 0xAAAu
static void mom_rig_init_latch(mom_rig_t *r, double residual_nm, unsigned latch_b_mask)
{
    /* (pos, dir) of irassi_day's thrusters: couples (0, 1) +x, (2, 3) -x, (4, 5) +y, (6, 7) -y, (8, 9) +z,
     * (10, 11) -z */
    static const double pos[MOM_THR][3] = {{0, 1.2, 0}, {0, -1.2, 0}, {0, 1.2, 0}, {0, -1.2, 0},
                                           {0, 0, 1.2}, {0, 0, -1.2}, {0, 0, 1.2}, {0, 0, -1.2},
                                           {1.2, 0, 0}, {-1.2, 0, 0}, {1.2, 0, 0}, {-1.2, 0, 0}};
    static const double dir[MOM_THR][3] = {{0, 0, 1}, {0, 0, -1}, {0, 0, -1}, {0, 0, 1},
                                           {1, 0, 0}, {-1, 0, 0}, {-1, 0, 0}, {1, 0, 0},
                                           {0, 1, 0}, {0, -1, 0}, {0, -1, 0}, {0, 1, 0}};
    aocs_wheels_config_t wc;
    aocs_mom_config_t mc;
    aocs_fdir_config_t fc;
    (void)memset(r, 0, sizeof(*r));
    test_wheels_pyramid(&wc);
    wc.period_s = AOCS_R(MOM_T_S);
    wc.inertia_B_kgm2 = aocs_mat3_zero();
    for (uint32_t a = 0u; a < 3u; ++a) {
        wc.inertia_B_kgm2.m[a][a] = (real_t)mom_j[a];
    }
    assert_int_equal(aocs_wheels_init(&r->wa, &wc), AOCS_OK);
    (void)memset(&mc, 0, sizeof(mc));
    mc.policy = (uint32_t)AOCS_MOM_THRUSTERS;
    mc.trigger = AOCS_MOM_TRIGGER_CONTINUOUS;
    mc.dump_torque_Nm = AOCS_R(0.02);
    mc.thr_count = MOM_THR;
    mc.thr_thrust_N = AOCS_R(1.0);
    mc.thr_min_on_s = AOCS_R(0.01);
    mc.thr_quantum_s = AOCS_R(0.001);
    mc.thr_latch_b_mask = (uint32_t)latch_b_mask;
    for (uint32_t i = 0u; i < MOM_THR; ++i) {
        mc.thr_arm_x_m[i] = (real_t)((pos[i][1] * dir[i][2]) - (pos[i][2] * dir[i][1]));
        mc.thr_arm_y_m[i] = (real_t)((pos[i][2] * dir[i][0]) - (pos[i][0] * dir[i][2]));
        mc.thr_arm_z_m[i] = (real_t)((pos[i][0] * dir[i][1]) - (pos[i][1] * dir[i][0]));
    }
    assert_int_equal(aocs_mom_init(&r->mom, &mc), AOCS_OK);
    aocs_fdir_config_default(&fc);
    fc.mom_residual_nm = (real_t)residual_nm;
    assert_int_equal(aocs_fdir_init(&r->f, &fc), AOCS_OK);
    /* wheel speeds holding h_w = (10, 6, -8) N m s: Omega = G^T (G G^T)^-1 h / Js, solved here */
    {
        const double h[3] = {10.0, 6.0, -8.0};
        double g[4][3];
        double m[3][3] = {{0}};
        double y[3];
        for (uint32_t i = 0u; i < 4u; ++i) {
            for (uint32_t a = 0u; a < 3u; ++a) {
                g[i][a] = (double)wc.axis_B[i].v[a];
            }
        }
        for (uint32_t a = 0u; a < 3u; ++a) {
            for (uint32_t b = 0u; b < 3u; ++b) {
                for (uint32_t i = 0u; i < 4u; ++i) {
                    m[a][b] += g[i][a] * g[i][b];
                }
            }
        }
        {
            /* Cramer */
            const double det = (m[0][0] * ((m[1][1] * m[2][2]) - (m[1][2] * m[2][1]))) -
                               (m[0][1] * ((m[1][0] * m[2][2]) - (m[1][2] * m[2][0]))) +
                               (m[0][2] * ((m[1][0] * m[2][1]) - (m[1][1] * m[2][0])));
            for (uint32_t c = 0u; c < 3u; ++c) {
                double mc3[3][3];
                for (uint32_t a = 0u; a < 3u; ++a) {
                    for (uint32_t b = 0u; b < 3u; ++b) {
                        mc3[a][b] = (b == c) ? h[a] : m[a][b];
                    }
                }
                y[c] = ((mc3[0][0] * ((mc3[1][1] * mc3[2][2]) - (mc3[1][2] * mc3[2][1]))) -
                        (mc3[0][1] * ((mc3[1][0] * mc3[2][2]) - (mc3[1][2] * mc3[2][0]))) +
                        (mc3[0][2] * ((mc3[1][0] * mc3[2][1]) - (mc3[1][1] * mc3[2][0])))) / det;
            }
        }
        for (uint32_t i = 0u; i < 4u; ++i) {
            const double om = ((g[i][0] * y[0]) + (g[i][1] * y[1]) + (g[i][2] * y[2])) / TEST_WHEEL_JS_KGM2;
            r->omega[i] = (real_t)om;
            for (uint32_t a = 0u; a < 3u; ++a) {
                r->hw[a] += TEST_WHEEL_JS_KGM2 * g[i][a] * (double)r->omega[i];
            }
        }
    }
    r->q[3] = 1.0;
    r->latch_b = latch_b_mask;
}

static void mom_rig_init(mom_rig_t *r, double residual_nm)
{
    mom_rig_init_latch(r, residual_nm, MOM_LATCH_TWINS);
}

/* One period: the momentum stage and the monitor on the sample, then the body over the period with the
 * torques that really act. stuck_closed / stuck_open: a thruster index, or MOM_THR for none. */
static void mom_rig_step(mom_rig_t *r, const double d[3], uint32_t stuck_closed, uint32_t stuck_open)
{
    aocs_mom_input_t mi;
    aocs_fdir_input_t in;
    aocs_det_output_t est;
    double tau[3] = {d[0], d[1], d[2]};
    (void)memset(&mi, 0, sizeof(mi));
    mi.h_wheels_B_Nms = aocs_vec3_make((real_t)r->hw[0], (real_t)r->hw[1], (real_t)r->hw[2]);
    mi.h_valid = 1;
    mi.enabled = 1;
    mi.dt_s = AOCS_R(MOM_T_S);
    assert_int_equal(aocs_mom_step(&r->mom, &mi), AOCS_OK);
    (void)memset(&est, 0, sizeof(est));
    est.q_BN = aocs_quat_make((real_t)r->q[0], (real_t)r->q[1], (real_t)r->q[2], (real_t)r->q[3]);
    est.w_BN_B = aocs_vec3_make((real_t)r->w[0], (real_t)r->w[1], (real_t)r->w[2]);
    est.status = AOCS_OK;
    (void)memset(&in, 0, sizeof(in));
    in.t_ns = r->t_ns;
    in.period_s = AOCS_R(MOM_T_S);
    in.have_sample = 1;
    in.input_status = AOCS_OK;
    in.mode = AOCS_EXEC_MODE_NOMINAL;
    in.wheel_speed_radps = r->omega;
    in.est = &est;
    in.mom = &r->mom;
    aocs_fdir_step(&r->f, &in, &r->wa);
    for (uint32_t i = 0u; i < MOM_THR; ++i) {
        const aocs_vec3_t t_i = aocs_mom_thr_torque_B(&r->mom, i);
        double on = (double)r->mom.out.thruster_on_s[i];
        on = (i == stuck_closed) ? 0.0 : ((i == stuck_open) ? MOM_T_S : on);
        /* the test's valves: a closed one stops its branch, a stuck-open thruster too (it is upstream) */
        if (((r->mom.out.latch_closed_mask >> ((r->latch_b >> i) & 1u)) & 1u) != 0u) {
            on = 0.0;
        }
        for (uint32_t a = 0u; a < 3u; ++a) {
            tau[a] += (double)t_i.v[a] * on / MOM_T_S;
        }
    }
    for (int k = 0; k < 200; ++k) {
        const double h = MOM_T_S / 200.0;
        double hb[3], wxh[3], dq[4];
        for (uint32_t a = 0u; a < 3u; ++a) {
            hb[a] = (mom_j[a] * r->w[a]) + r->hw[a];
        }
        wxh[0] = (r->w[1] * hb[2]) - (r->w[2] * hb[1]);
        wxh[1] = (r->w[2] * hb[0]) - (r->w[0] * hb[2]);
        wxh[2] = (r->w[0] * hb[1]) - (r->w[1] * hb[0]);
        /* Xi(q) w: rho' = (q4 w + rho x w) / 2, q4' = -rho . w / 2 */
        dq[0] = 0.5 * ((r->q[3] * r->w[0]) + (r->q[1] * r->w[2]) - (r->q[2] * r->w[1]));
        dq[1] = 0.5 * ((r->q[3] * r->w[1]) + (r->q[2] * r->w[0]) - (r->q[0] * r->w[2]));
        dq[2] = 0.5 * ((r->q[3] * r->w[2]) + (r->q[0] * r->w[1]) - (r->q[1] * r->w[0]));
        dq[3] = -0.5 * ((r->q[0] * r->w[0]) + (r->q[1] * r->w[1]) + (r->q[2] * r->w[2]));
        for (uint32_t a = 0u; a < 3u; ++a) {
            r->w[a] += h * (tau[a] - wxh[a]) / mom_j[a];
        }
        {
            double n = 0.0;
            for (uint32_t a = 0u; a < 4u; ++a) {
                r->q[a] += h * dq[a];
                n += r->q[a] * r->q[a];
            }
            for (uint32_t a = 0u; a < 4u; ++a) {
                r->q[a] /= sqrt(n);
            }
        }
    }
    r->t_ns += (uint64_t)(MOM_T_S * 1.0e9);
}

/* the thruster the allocation fires longest this step */
static uint32_t mom_busiest(const aocs_mom_t *m)
{
    uint32_t best = 0u;
    for (uint32_t i = 1u; i < MOM_THR; ++i) {
        if (m->out.thruster_on_s[i] > m->out.thruster_on_s[best]) {
            best = i;
        }
    }
    return best;
}

/* every thruster working and a disturbance inside the bound: 600 s of continuous dumping, no event, though
 * the body turns by about 0.3 rad (its momentum is summed in the inertial frame); with the disturbance over
 * the bound: momentum_inconsistent at the end of the mom_persist-th window, and nothing isolated */
static void test_momentum_consistent_while_dumping_and_an_unexplained_torque(void **state)
{
    (void)state;
    const double d_in[3] = {1.0e-3, -1.0e-3, 1.0e-3};
    const double d_out[3] = {8.0e-3, 0.0, 0.0};
    mom_rig_t r;
    uint64_t t = 0u;
    mom_rig_init(&r, 5.0e-3);
    for (uint32_t k = 0u; k < 600u; ++k) {
        mom_rig_step(&r, d_in, MOM_THR, MOM_THR);
    }
    assert_int_equal(aocs_evlog_count(&r.f.log), 0u);
    assert_true((2.0 * acos(fabs(r.q[3]))) > 0.1); /* it did turn */
    mom_rig_init(&r, 5.0e-3);
    for (uint32_t k = 0u; k < 200u; ++k) {
        mom_rig_step(&r, d_out, MOM_THR, MOM_THR);
    }
    assert_int_equal(count_id(&r.f.log, AOCS_EVT_MOMENTUM_INCONSISTENT, -1, &t), 1u);
    /* windows of 30 periods from the second sample (the first gives the wheels' momentum to difference): the
     * second inconsistent one closes at sample 61 */
    assert_int_equal(t, (uint64_t)(1u + (AOCS_FDIR_MOM_PERSIST_DEFAULT * AOCS_FDIR_MOM_WINDOW_DEFAULT)) *
                            1000000000ull);
    assert_int_equal(aocs_evlog_count(&r.f.log), 1u);
    assert_int_equal(r.mom.thr_excluded_mask, 0u);
    /* the test off (0): silent on the same run */
    mom_rig_init(&r, 0.0);
    for (uint32_t k = 0u; k < 200u; ++k) {
        mom_rig_step(&r, d_out, MOM_THR, MOM_THR);
    }
    assert_int_equal(aocs_evlog_count(&r.f.log), 0u);
}

/* a tachometer that reads NaN for 80 s (no wheel momentum to sum): those samples belong to no window (the
 * momentum is not known; the test starts again from the next usable sample), so a run that is consistent
 * raises no momentum event; taking them as zero momentum would see the wheels' whole momentum vanish */
static void test_momentum_skips_samples_without_wheel_momentum(void **state)
{
    (void)state;
    const double d_in[3] = {1.0e-3, -1.0e-3, 1.0e-3};
    mom_rig_t r;
    real_t saved = AOCS_R(0.0);
    mom_rig_init(&r, 5.0e-3);
    for (uint32_t k = 0u; k < 300u; ++k) {
        if (k == 100u) {
            saved = r.omega[0];
            r.omega[0] = (real_t)NAN;
        }
        if (k == 180u) {
            r.omega[0] = saved;
        }
        mom_rig_step(&r, d_in, MOM_THR, MOM_THR);
    }
    assert_int_equal(count_id(&r.f.log, AOCS_EVT_MOMENTUM_INCONSISTENT, -1, NULL), 0u);
    assert_int_equal(count_id(&r.f.log, AOCS_EVT_THRUSTER_INEFFECTIVE, -1, NULL), 0u);
    assert_int_equal(r.mom.thr_excluded_mask, 0u);
}

/* the thruster the dump leans on most stops firing at t = 100 s: thruster_ineffective naming it and
 * unload_actuator_switched at the end of the second window that holds its deficit, it is out of the
 * allocation, its couple's partner fires instead, and no other event follows in the next 400 s */
static void test_thruster_stuck_closed_is_isolated_and_the_dump_goes_on(void **state)
{
    (void)state;
    const double d[3] = {1.0e-3, -1.0e-3, 1.0e-3};
    mom_rig_t r;
    uint64_t t_ineff = 0u;
    uint64_t t_sw = 0u;
    uint32_t dead = MOM_THR;
    mom_rig_init(&r, 5.0e-3);
    for (uint32_t k = 0u; k < 600u; ++k) {
        mom_rig_step(&r, d, (k >= 100u) ? dead : MOM_THR, MOM_THR);
        if (k == 0u) {
            dead = mom_busiest(&r.mom);
        }
        if (k < 100u) {
            assert_int_equal(aocs_evlog_count(&r.f.log), 0u);
        }
    }
    assert_int_equal(count_id(&r.f.log, AOCS_EVT_THRUSTER_INEFFECTIVE, (int32_t)dead, &t_ineff), 1u);
    assert_int_equal(count_id(&r.f.log, AOCS_EVT_UNLOAD_ACTUATOR_SWITCHED, (int32_t)dead, &t_sw), 1u);
    assert_int_equal(aocs_evlog_count(&r.f.log), 2u);
    /* windows close at 31, 61, 91, 121 (first deficit: [91, 121] holds 21 dead periods), 151: at 151 s */
    assert_int_equal(t_ineff, 151000000000ull);
    assert_int_equal(t_sw, t_ineff);
    assert_int_equal(r.mom.thr_excluded_mask, 1u << dead);
    assert_true(!(r.mom.out.thruster_on_s[dead] > AOCS_R(0.0)));
    assert_true(r.mom.out.thruster_on_s[dead ^ 1u] > AOCS_R(0.0)); /* its couple's partner */
}

/* thruster_ineffective needs fdir.mom_persist (2) windows in a row explained by the same thruster: a window
 * between two the dead thruster explains, that it does not explain, ends the run, whether that window is
 * consistent or inconsistent. Windows of 30 periods close at 31, 61, 91, 121, 151, 181 s. The thruster the dump
 * leans on most does not fire over the window [61, 91] (its deficit explains it: a first window); it fires
 * again over [91, 121], with the disturbance inside the bound (a consistent window) or, in the second case, with
 * an external torque of 30 mN m along x (0.9 N m s over the window against a bound of 0.15 N m s and a commanded
 * impulse per thruster below 0.5 N m s: no thruster explains it; one inconsistent window, so no
 * momentum_inconsistent); it is dead again from 121 s, so the windows [121, 151] and [151, 181] are the first
 * and the second of a new run: thruster_ineffective and unload_actuator_switched name it at 181 s, not at
 * 151 s, and nothing else is raised. */
static void test_a_window_the_dead_thruster_does_not_explain_ends_its_run(void **state)
{
    (void)state;
    const double d[3] = {1.0e-3, -1.0e-3, 1.0e-3};
    const double d_big[3] = {3.0e-2, 0.0, 0.0};
    for (int unexplained = 0; unexplained < 2; ++unexplained) {
        mom_rig_t r;
        uint64_t t_ineff = 0u;
        uint64_t t_sw = 0u;
        uint32_t dead = MOM_THR;
        mom_rig_init(&r, 5.0e-3);
        for (uint32_t k = 0u; k <= 181u; ++k) {
            const int big = ((unexplained != 0) && (k >= 91u) && (k < 121u)) ? 1 : 0;
            const int off = (((k >= 61u) && (k < 91u)) || (k >= 121u)) ? 1 : 0;
            mom_rig_step(&r, (big != 0) ? d_big : d, (off != 0) ? dead : MOM_THR, MOM_THR);
            if (k == 0u) {
                dead = mom_busiest(&r.mom);
            }
            if (k < 181u) {
                assert_int_equal(aocs_evlog_count(&r.f.log), 0u);
            }
        }
        assert_int_equal(count_id(&r.f.log, AOCS_EVT_THRUSTER_INEFFECTIVE, (int32_t)dead, &t_ineff), 1u);
        assert_int_equal(t_ineff, 181000000000ull);
        assert_int_equal(count_id(&r.f.log, AOCS_EVT_UNLOAD_ACTUATOR_SWITCHED, (int32_t)dead, &t_sw), 1u);
        assert_int_equal(t_sw, t_ineff);
        assert_int_equal(aocs_evlog_count(&r.f.log), 2u);
        assert_int_equal(r.mom.thr_excluded_mask, 1u << dead);
    }
}

/* the events of the log in order */
static uint32_t mom_events(const aocs_evlog_t *log, aocs_event_t *out, uint32_t max)
{
    uint32_t seq = 0u;
    uint32_t n = 0u;
    aocs_event_t e;
    while ((n < max) && (aocs_evlog_next(log, seq, &e, NULL) == AOCS_OK)) {
        out[n] = e;
        seq = e.seq;
        ++n;
    }
    return n;
}

/* |A(q)^T (J w + h_w) - h_w(0)|: the change of the rig's total momentum in N (q_BN vector first) */
static double mom_rig_dh_N(const mom_rig_t *r)
{
    const double *q = r->q;
    double h[3];
    double hn[3];
    double n2 = 0.0;
    for (uint32_t a = 0u; a < 3u; ++a) {
        h[a] = (mom_j[a] * r->w[a]) + r->hw[a];
    }
    /* A(q)^T h = (q4^2 - |rho|^2) h + 2 (rho . h) rho - 2 q4 (rho x h)... with the transpose's sign: + 2 q4 rho x h */
    {
        const double s = (q[3] * q[3]) - ((q[0] * q[0]) + (q[1] * q[1]) + (q[2] * q[2]));
        const double rh = (q[0] * h[0]) + (q[1] * h[1]) + (q[2] * h[2]);
        const double c[3] = {(q[1] * h[2]) - (q[2] * h[1]), (q[2] * h[0]) - (q[0] * h[2]), (q[0] * h[1]) - (q[1] * h[0])};
        for (uint32_t a = 0u; a < 3u; ++a) {
            hn[a] = (s * h[a]) + (2.0 * rh * q[a]) + (2.0 * q[3] * c[a]) - r->hw[a];
            n2 += hn[a] * hn[a];
        }
    }
    return sqrt(n2);
}

/* thruster `stuck` (never commanded: no dump) fires continuously from the period after sample 10: the period
 * residuals of samples 11, 12, 13 are its impulse: thruster_stuck_open at 13 s naming the first of its couple
 * (0 for either), the branch of 0 (A) closed at once; when 0 is the stuck one, a consistent window (13 to
 * 43 s) isolates it (thruster_isolated, branch A); when it is its twin 1, the residual goes on: on samples 14,
 * 15, 16 it names 1, branch A reopens and B closes at 16 s, and the window 16 to 46 s isolates 1. Nothing else
 * is raised, the valve stays closed, and the body stops gaining momentum */
static void stuck_open_case(uint32_t stuck)
{
    const double d[3] = {0.0, 0.0, 0.0};
    mom_rig_t r;
    aocs_event_t e[8];
    uint32_t n;
    mom_rig_init(&r, 5.0e-3);
    r.mom.cfg.trigger = AOCS_MOM_TRIGGER_THRESHOLD; /* no dump: the stuck thruster is never commanded */
    r.mom.cfg.h_start_Nms = AOCS_R(1.0e3);
    r.mom.cfg.h_stop_Nms = AOCS_R(1.0e2);
    for (uint32_t k = 0u; k < 100u; ++k) {
        mom_rig_step(&r, d, MOM_THR, (k >= 10u) ? stuck : MOM_THR);
    }
    n = mom_events(&r.f.log, e, 8u);
    assert_int_equal(e[0].id, AOCS_EVT_THRUSTER_STUCK_OPEN);
    assert_int_equal(e[0].unit, 0);
    assert_int_equal(e[0].t_ns, 13000000000ull);
    assert_true(fabs((double)e[0].value - 1.2) < 0.05); /* the residual's torque: the thruster's 1.2 N m */
    assert_int_equal(e[1].id, AOCS_EVT_THRUSTER_BRANCH_CLOSED);
    assert_int_equal(e[1].unit, 0);
    assert_int_equal((int)e[1].value, 0);
    assert_int_equal(e[1].t_ns, 13000000000ull);
    if (stuck == 0u) {
        assert_int_equal(n, 3u);
        assert_int_equal(e[2].id, AOCS_EVT_THRUSTER_ISOLATED);
        assert_int_equal(e[2].unit, 0);
        assert_int_equal((int)e[2].value, 0);
        assert_int_equal(e[2].t_ns, 43000000000ull);
        assert_int_equal(r.mom.out.latch_closed_mask, 1u);
    } else {
        assert_int_equal(n, 5u);
        assert_int_equal(e[2].id, AOCS_EVT_THRUSTER_BRANCH_REOPENED);
        assert_int_equal(e[2].unit, 1);
        assert_int_equal((int)e[2].value, 0);
        assert_int_equal(e[2].t_ns, 16000000000ull);
        assert_int_equal(e[3].id, AOCS_EVT_THRUSTER_BRANCH_CLOSED);
        assert_int_equal(e[3].unit, 1);
        assert_int_equal((int)e[3].value, 1);
        assert_int_equal(e[3].t_ns, 16000000000ull);
        assert_int_equal(e[4].id, AOCS_EVT_THRUSTER_ISOLATED);
        assert_int_equal(e[4].unit, 1);
        assert_int_equal((int)e[4].value, 1);
        assert_int_equal(e[4].t_ns, 46000000000ull);
        assert_int_equal(r.mom.out.latch_closed_mask, 2u);
    }
    /* the spacecraft's momentum: only the 3 (or 6) whole periods of 1.2 N m s before the valve closed */
    assert_true(fabs(mom_rig_dh_N(&r) - (((stuck == 0u) ? 3.0 : 6.0) * 1.2)) < 1.0e-3);
}

static void test_thruster_stuck_open_is_isolated_behind_its_latch_valve(void **state)
{
    (void)state;
    stuck_open_case(0u);
}

static void test_thruster_stuck_open_on_the_second_branch_is_found_by_swapping_the_valves(void **state)
{
    (void)state;
    stuck_open_case(1u);
}

/* every thruster behind one valve (mom.thr_latch_b_mask 0): closing it would leave no thruster, so the
 * stuck-open thruster is named once, no valve moves, and the window test raises momentum_inconsistent */
static void test_thruster_stuck_open_without_a_second_branch_is_momentum_inconsistent(void **state)
{
    (void)state;
    const double d[3] = {0.0, 0.0, 0.0};
    mom_rig_t r;
    uint64_t t = 0u;
    mom_rig_init_latch(&r, 5.0e-3, 0u);
    for (uint32_t k = 0u; k < 100u; ++k) {
        mom_rig_step(&r, d, MOM_THR, (k >= 10u) ? 0u : MOM_THR);
    }
    assert_int_equal(count_id(&r.f.log, AOCS_EVT_THRUSTER_STUCK_OPEN, 0, &t), 1u);
    assert_int_equal(t, 13000000000ull);
    assert_int_equal(count_id(&r.f.log, AOCS_EVT_THRUSTER_BRANCH_CLOSED, -1, NULL), 0u);
    assert_int_equal(count_id(&r.f.log, AOCS_EVT_MOMENTUM_INCONSISTENT, -1, &t), 1u);
    assert_int_equal(t, 61000000000ull);
    assert_int_equal(count_id(&r.f.log, AOCS_EVT_THRUSTER_INEFFECTIVE, -1, NULL), 0u);
    assert_int_equal(r.mom.out.latch_closed_mask, 0u);
    assert_int_equal(r.mom.thr_excluded_mask, 0u);
}

/* ---- the executive: a wheel dies under the allocation ---- */
static void exec_wheels_config(aocs_exec_config_t *cfg)
{
    aocs_exec_config_default(cfg);
    cfg->period_s = AOCS_R(PERIOD_S);
    cfg->law = AOCS_LAW_QUAT_PD;
    cfg->laws.quat_pd.kp = AOCS_R(4000.0);
    cfg->laws.quat_pd.kd = AOCS_R(8000.0);
    cfg->u_max_norm = AOCS_R(1.0);
    test_wheels_pyramid(&cfg->wheels);
}

static void test_executive_isolates_a_dead_wheel(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t out;
    double omega[4] = {10.0, -5.0, 3.0, 0.0};
    const aocs_evlog_t *log;
    uint64_t t_iso = 0u;
    exec_wheels_config(&cfg);
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    for (uint32_t k = 1u; k <= 100u; ++k) {
        aocs_exec_input_t in;
        (void)memset(&in, 0, sizeof(in));
        in.tick = k;
        in.t_sensor_ns = (uint64_t)k * PERIOD_NS;
        in.valid = AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE;
        /* a constant attitude error about x: a steady command the wheels carry (the body is held by the test) */
        in.q_BN = aocs_quat_make(AOCS_R(0.0099998), AOCS_R(0.0), AOCS_R(0.0), AOCS_R(0.99995));
        in.w_BN_B = aocs_vec3_zero();
        for (uint32_t i = 0u; i < 4u; ++i) {
            in.wheel_speed_radps[i] = (real_t)omega[i];
        }
        assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
        assert_int_equal(out.mode, AOCS_EXEC_MODE_NOMINAL);
        if ((k > 40u) && (exec.act.wheels.cfg.failed_mask != 0u)) {
            assert_close(out.wheels.u_s_nm[2], 0.0, 0.0); /* isolated: never commanded again */
        }
        for (uint32_t i = 0u; i < 4u; ++i) {
            const double u = ((i == 2u) && (k >= 30u)) ? 0.0 : (double)out.wheels.u_s_nm[i];
            omega[i] += PERIOD_S * u / TEST_WHEEL_JS_KGM2;
        }
    }
    log = aocs_exec_events(&exec);
    assert_non_null(log);
    assert_int_equal(count_id(log, AOCS_EVT_WHEEL_ISOLATED, 2, &t_iso), 1u);
    assert_int_equal(t_iso, (uint64_t)(30u + AOCS_FDIR_WHEEL_PERSIST_DEFAULT) * PERIOD_NS);
    assert_int_equal(aocs_evlog_count(log), 2u);
    assert_int_equal(exec.act.wheels.cfg.failed_mask, 1u << 2);
    assert_null(aocs_exec_events(NULL));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_event_ids_names_severities_are_the_wire_values),
        cmocka_unit_test(test_log_sequence_ring_and_counts),
        cmocka_unit_test(test_config_check),
        cmocka_unit_test(test_wheel_residual_is_the_formula),
        cmocka_unit_test(test_wheel_dies_is_detected_after_persist_steps_and_isolated),
        cmocka_unit_test(test_isolation_of_the_third_wheel_is_refused_and_latches_safe),
        cmocka_unit_test(test_a_wheel_whose_friction_grew_is_found_and_its_model_rescaled),
        cmocka_unit_test(test_a_tachometer_failure_is_not_taken_for_friction),
        cmocka_unit_test(test_a_friction_excess_exactly_at_the_threshold_is_not_high),
        cmocka_unit_test(test_st_excluded_after_persist_and_restored_after_restore),
        cmocka_unit_test(test_noisy_tracker_rescaled_and_readmitted),
        cmocka_unit_test(test_a_non_finite_innovation_restarts_the_noise_window),
        cmocka_unit_test(test_a_small_innovation_rescales_the_tracker_noise_back_to_1_not_below),
        cmocka_unit_test(test_frozen_tracker_while_turning),
        cmocka_unit_test(test_frozen_tracker_in_a_hold_when_the_filter_models_its_noise),
        cmocka_unit_test(test_gyro_bias_jump_is_detected_when_the_estimate_leaves_its_bound),
        cmocka_unit_test(test_gyro_bias_bound_grows_with_the_rate_random_walk),
        cmocka_unit_test(test_a_gyro_bias_change_exactly_at_the_bound_is_not_over),
        cmocka_unit_test(test_a_reference_the_walk_made_stale_is_renewed),
        cmocka_unit_test(test_gyro_bias_monitor_tests_only_applied_samples_of_a_filter),
        cmocka_unit_test(test_stuck_gyro_axis_excludes_the_gyro_and_latches_safe),
        cmocka_unit_test(test_gyro_stuck_goes_gyroless),
        cmocka_unit_test(test_gyro_saturation),
        cmocka_unit_test(test_a_gyro_pinned_on_every_axis_while_the_tracker_turns),
        cmocka_unit_test(test_link_and_safe_events),
        cmocka_unit_test(test_safe_entered_value_is_the_input_verdict_before_the_estimator_status),
        cmocka_unit_test(test_disabled_is_silent),
        cmocka_unit_test(test_momentum_consistent_while_dumping_and_an_unexplained_torque),
        cmocka_unit_test(test_momentum_skips_samples_without_wheel_momentum),
        cmocka_unit_test(test_thruster_stuck_closed_is_isolated_and_the_dump_goes_on),
        cmocka_unit_test(test_a_window_the_dead_thruster_does_not_explain_ends_its_run),
        cmocka_unit_test(test_thruster_stuck_open_is_isolated_behind_its_latch_valve),
        cmocka_unit_test(test_thruster_stuck_open_on_the_second_branch_is_found_by_swapping_the_valves),
        cmocka_unit_test(test_thruster_stuck_open_without_a_second_branch_is_momentum_inconsistent),
        cmocka_unit_test(test_executive_isolates_a_dead_wheel),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
