/*
 * The configuration registry's table and setters (aocs/config_registry.h),
 * checked against the typed struct written out here: a value set through a
 * row lands in the member the row names (and nowhere else), every rule is
 * applied whoever calls, an error leaves the config untouched, lookups by
 * key and by PIL id agree, and aocs_exec_config_default holds the DEFAULT
 * column. Both precisions.
 */
#include <string.h>

#include "test_support.h"

#include "aocs/config_registry.h"
#include "aocs/executive.h"

/* bit-for-bit equality (the registry must not change a single bit of a value) */
static int same_r(real_t a, real_t b)
{
    return (memcmp(&a, &b, sizeof(a)) == 0) ? 1 : 0;
}

static int same_d(double a, double b)
{
    return (memcmp(&a, &b, sizeof(a)) == 0) ? 1 : 0;
}

static aocs_config_ref_t ref_of(const char *key)
{
    aocs_config_ref_t ref = {NULL, 0u};
    if (aocs_config_find_key(key, &ref) == 0) {
        fail_msg("no registry row for key '%s'", key);
    }
    return ref;
}

static void test_a_value_lands_in_the_member_its_row_names(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    const double ks = 12.5;
    const double axis[3] = {0.0, 0.6, 0.8};
    const double lim[3] = {0.25, 0.5, 0.75};
    const double j[9] = {10.0, 0.5, 0.0, 0.5, 12.0, 0.0, 0.0, 0.0, 15.0};
    aocs_exec_config_default(&cfg);
    assert_int_equal(aocs_config_set_reals(&cfg, ref_of("k_safe"), &ks, 1u), AOCS_OK);
    assert_true(same_r(cfg.k_safe, (real_t)12.5));
    assert_int_equal(aocs_config_set_reals(&cfg, ref_of("u_max_axis"), lim, 3u), AOCS_OK);
    assert_true((same_r(cfg.u_max_axis.v[0], (real_t)0.25)) && (same_r(cfg.u_max_axis.v[2], (real_t)0.75)));
    assert_int_equal(aocs_config_set_reals(&cfg, ref_of("wheel4.axis_B"), axis, 3u), AOCS_OK);
    assert_true((same_r(cfg.wheels.axis_B[4].v[1], (real_t)0.6)) && (same_r(cfg.wheels.axis_B[4].v[2], (real_t)0.8)));
    assert_true(same_r(cfg.wheels.axis_B[3].v[1], (real_t)0.0)); /* not another wheel's */
    assert_int_equal(aocs_config_set_reals(&cfg, ref_of("inertia"), j, 9u), AOCS_OK);
    assert_true((same_r(cfg.laws.smc.inertia.m[0][1], (real_t)0.5)) && (same_r(cfg.laws.smc.inertia.m[2][2], (real_t)15.0)));
    assert_int_equal(aocs_config_set_uint(&cfg, ref_of("recover_good_samples"), 7u), AOCS_OK);
    assert_int_equal(cfg.recover_good_samples, 7u);
    assert_int_equal(aocs_config_set_uint(&cfg, ref_of("stale_timeout_s"), 123456789u), AOCS_OK);
    assert_true(cfg.stale_timeout_ns == 123456789u);
    assert_int_equal(aocs_config_set_uint(&cfg, ref_of("guidance.mode"), 1u), AOCS_OK);
    assert_int_equal(cfg.guidance.mode, AOCS_GUIDANCE_MODE_SLEW);
    assert_int_equal(aocs_config_set_uint(&cfg, ref_of("guidance.profile"), 1u), AOCS_OK);
    assert_int_equal(cfg.guidance.slew.profile, AOCS_SLEW_PROFILE_JERK_LIMITED);
    assert_int_equal(aocs_config_set_uint(&cfg, ref_of("law"), (uint64_t)AOCS_LAW_SMC), AOCS_OK);
    assert_int_equal(cfg.law, AOCS_LAW_SMC);
    assert_int_equal(aocs_config_set_table(&cfg, ref_of("hinf.table"), "hinf_min"), AOCS_OK);
    assert_true(!same_r(cfg.laws.hinf.k[0][0], (real_t)0.0));
}

/* Every value of every field through the table, and back: each row reaches only its own bytes. */
static void test_every_row_round_trips_and_touches_only_its_member(void **state)
{
    (void)state;
    for (uint32_t i = 0u; i < aocs_config_field_count(); ++i) {
        const aocs_config_field_t *f = aocs_config_field_at(i);
        const uint32_t units = (aocs_config_field_is_per_wheel(f) != 0) ? (uint32_t)AOCS_WHEELS_MAX : 1u;
        for (uint32_t w = 0u; w < units; ++w) {
            const aocs_config_ref_t ref = {f, w};
            aocs_exec_config_t before;
            aocs_exec_config_t after;
            double v[AOCS_CONFIG_VALUES_MAX];
            double back[AOCS_CONFIG_VALUES_MAX];
            size_t changed = 0u;
            aocs_exec_config_default(&before);
            after = before;
            if ((f->kind == AOCS_CONFIG_KIND_REALS) || (f->kind == AOCS_CONFIG_KIND_INERTIA)) {
                const aocs_config_rule_info_t *r = aocs_config_rule_info(f->rule);
                for (uint32_t k = 0u; k < f->count; ++k) {
                    v[k] = 0.5 + (double)k + (double)i;
                    if (v[k] > r->hi) { /* a bounded row: a value inside its range */
                        v[k] = r->lo + ((r->hi - r->lo) * (double)(k + 1u) / (double)(f->count + 2u));
                    }
                }
                assert_int_equal(aocs_config_set_reals(&after, ref, v, f->count), AOCS_OK);
                assert_int_equal(aocs_config_get_reals(&after, ref, back, AOCS_CONFIG_VALUES_MAX), f->count);
                for (uint32_t k = 0u; k < f->count; ++k) {
                    assert_true(same_d(back[k], (double)(real_t)v[k]));
                }
            } else if (f->kind != AOCS_CONFIG_KIND_TABLE) {
                uint64_t u = ((f->kind == AOCS_CONFIG_KIND_LAW) || (f->kind == AOCS_CONFIG_KIND_ENUM))
                                 ? (uint64_t)(f->enum_count - 1u) : 7u; /* 7: no row's default */
                if ((u == 7u) && (aocs_config_rule_holds(f->rule, 7.0) == 0)) {
                    /* a narrow rule (FLAG: 0 or 1): the end of its range the default is not at */
                    const aocs_config_rule_info_t *r = aocs_config_rule_info(f->rule);
                    u = (aocs_config_get_uint(&before, ref) == (uint64_t)r->hi) ? (uint64_t)r->lo : (uint64_t)r->hi;
                }
                assert_int_equal(aocs_config_set_uint(&after, ref, u), AOCS_OK);
                assert_true(aocs_config_get_uint(&after, ref) == u);
            } else {
                continue;
            }
            /* the bytes that changed all lie inside this field's value */
            for (size_t b = 0u; b < sizeof(after); ++b) {
                if (((const unsigned char *)&after)[b] != ((const unsigned char *)&before)[b]) {
                    const size_t lo = f->offset + ((size_t)w * f->stride);
                    size_t width = sizeof(uint64_t); /* U64, NS, BUDGET; an enum is at most that wide */
                    if ((f->kind == AOCS_CONFIG_KIND_REALS) || (f->kind == AOCS_CONFIG_KIND_INERTIA)) {
                        width = (size_t)f->count * sizeof(real_t);
                    } else if (f->kind == AOCS_CONFIG_KIND_U32) {
                        width = sizeof(uint32_t);
                    }
                    if ((b < lo) || (b >= (lo + width))) {
                        fail_msg("row %s (wheel %u): byte %zu changed, outside [%zu, %zu)", f->pil_name, (unsigned)w,
                                 b, lo, lo + width);
                    }
                    ++changed;
                }
            }
            assert_true(changed > 0u);
        }
    }
}

static void test_every_reader_gets_the_rows_rules(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_exec_config_t kept;
    const double zero = 0.0;
    const double neg = -1.0;
    const double inf = (double)INFINITY;
    const double two[2] = {1.0, 2.0};
    aocs_exec_config_default(&cfg);
    kept = cfg;
    assert_int_equal(aocs_config_set_reals(&cfg, ref_of("k_safe"), &zero, 1u), AOCS_ERR_CONFIG_RULE);   /* POS */
    assert_int_equal(aocs_config_set_reals(&cfg, ref_of("u_max_norm"), &neg, 1u), AOCS_ERR_CONFIG_RULE); /* NONNEG */
    assert_int_equal(aocs_config_set_reals(&cfg, ref_of("u_max_norm"), &zero, 1u), AOCS_OK);
    assert_int_equal(aocs_config_set_reals(&cfg, ref_of("target_w"), &inf, 1u), AOCS_ERR_CONFIG_FIELD); /* count */
    assert_int_equal(aocs_config_set_reals(&cfg, ref_of("k_safe"), &inf, 1u), AOCS_ERR_PARAM_NOT_FINITE);
    assert_int_equal(aocs_config_set_reals(&cfg, ref_of("u_max_axis"), two, 2u), AOCS_ERR_CONFIG_FIELD);
    assert_int_equal(aocs_config_set_reals(&cfg, ref_of("law"), &zero, 1u), AOCS_ERR_CONFIG_FIELD);    /* kind */
    assert_int_equal(aocs_config_set_uint(&cfg, ref_of("recover_good_samples"), 0u), AOCS_ERR_CONFIG_RULE);
    assert_int_equal(aocs_config_set_uint(&cfg, ref_of("missing_max_periods"), 0x100000000ull), AOCS_ERR_CONFIG_RULE);
    assert_int_equal(aocs_config_set_uint(&cfg, ref_of("law"), (uint64_t)AOCS_LAW_COUNT), AOCS_ERR_CONFIG_RULE);
    assert_int_equal(aocs_config_set_uint(&cfg, ref_of("guidance.mode"), 2u), AOCS_ERR_CONFIG_RULE);
    assert_int_equal(aocs_config_set_uint(&cfg, ref_of("k_safe"), 1u), AOCS_ERR_CONFIG_FIELD);
    assert_int_equal(aocs_config_set_table(&cfg, ref_of("hinf.table"), "lqr_quat_ref"), AOCS_ERR_GAIN_TABLE_WRONG_LAW);
    assert_int_equal(aocs_config_set_table(&cfg, ref_of("hinf.table"), "nope"), AOCS_ERR_GAIN_TABLE_UNKNOWN);
    /* nothing of it reached the config but the one accepted zero */
    kept.u_max_norm = AOCS_R(0.0);
    assert_memory_equal(&cfg, &kept, sizeof(cfg));
}

/* issue 25, item 7: the physical ranges of the RULE column, applied by the setter every reader calls */
static void expect_rule(const char *key, double x, aocs_status_t want)
{
    aocs_exec_config_t cfg;
    aocs_exec_config_t kept;
    aocs_exec_config_default(&cfg);
    kept = cfg;
    if (aocs_config_set_reals(&cfg, ref_of(key), &x, 1u) != want) {
        fail_msg("%s = %g: status %d, expected %d", key, x, (int)aocs_config_set_reals(&cfg, ref_of(key), &x, 1u),
                 (int)want);
    }
    if (want != AOCS_OK) {
        assert_memory_equal(&cfg, &kept, sizeof(cfg));
    }
}

static void test_physical_ranges_of_wheel_and_guidance_values(void **state)
{
    (void)state;
    static const char *const absurd[] = {"wheel0.js_kgm2", "wheel3.js_kgm2", "wheel0.u_max_nm", "wheel5.u_max_nm",
                                         "wheel0.omega_max_radps", "wheel0.coulomb_width_radps",
                                         "wheel0.viscous_nms", "wheel0.coulomb_nm", "wheel0.null_speed_radps",
                                         "guidance.margin", "guidance.jerk_time_s", "guidance.rate_limit_radps",
                                         "wheels.null_gain"};
    for (size_t i = 0u; i < (sizeof(absurd) / sizeof(absurd[0])); ++i) {
        expect_rule(absurd[i], 1e300, AOCS_ERR_CONFIG_RULE);
    }
    /* a tiny positive value of a quantity that is > 0 or off (0) */
    static const char *const tiny[] = {"wheel0.js_kgm2", "wheel0.u_max_nm", "wheel0.omega_max_radps",
                                       "wheel0.coulomb_width_radps", "guidance.margin", "guidance.jerk_time_s",
                                       "guidance.rate_limit_radps", "wheels.null_gain"};
    for (size_t i = 0u; i < (sizeof(tiny) / sizeof(tiny[0])); ++i) {
        expect_rule(tiny[i], 1e-300, AOCS_ERR_CONFIG_RULE);
    }
    /* the reference values (SPEC 5.3's wheel, the slew defaults) and the "0 = off" values pass */
    expect_rule("wheel0.js_kgm2", 0.08, AOCS_OK);
    expect_rule("wheel0.u_max_nm", 0.25, AOCS_OK);
    expect_rule("wheel0.omega_max_radps", 600.0, AOCS_OK);
    expect_rule("wheel0.null_speed_radps", -300.0, AOCS_OK);
    expect_rule("guidance.margin", 0.8, AOCS_OK);
    expect_rule("guidance.margin", 1.0, AOCS_OK);
    expect_rule("guidance.jerk_time_s", 0.0, AOCS_OK);
    expect_rule("guidance.jerk_time_s", 5.0, AOCS_OK);
    expect_rule("guidance.rate_limit_radps", 0.0, AOCS_OK);
    expect_rule("wheels.null_gain", 0.0, AOCS_OK);
    expect_rule("wheel0.viscous_nms", 0.0, AOCS_OK);
    expect_rule("guidance.margin", 0.0, AOCS_ERR_CONFIG_RULE);   /* no "off" for a margin */
    expect_rule("guidance.margin", 1.0000001, AOCS_ERR_CONFIG_RULE);
    /* each rule's info: its text, and the edges inside */
    for (int r = 0; r < (int)AOCS_CONFIG_RULE_COUNT; ++r) {
        const aocs_config_rule_info_t *info = aocs_config_rule_info((aocs_config_rule_t)r);
        assert_non_null(info->name);
        assert_non_null(info->text);
        assert_true(info->lo <= info->hi);
        assert_int_equal(aocs_config_rule_holds((aocs_config_rule_t)r, info->hi), 1);
        assert_int_equal(aocs_config_rule_holds((aocs_config_rule_t)r, info->lo), (info->lo_open != 0) ? 0 : 1);
        assert_int_equal(aocs_config_rule_holds((aocs_config_rule_t)r, (double)NAN), 0);
    }
}

/* the fault-management rows carry the stage's own rules (aocs_fdir_config_check) as registry rules, so that
 * every reader refuses what the stage would: a switch of 0 or 1, a fraction in (0, 1], repeat counts >= 2 */
static void test_fault_management_rules_are_registry_rules(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_exec_config_default(&cfg);
    assert_int_equal(aocs_config_set_uint(&cfg, ref_of("fdir.enabled"), 2u), AOCS_ERR_CONFIG_RULE);
    assert_int_equal(aocs_config_set_uint(&cfg, ref_of("fdir.enabled"), 0u), AOCS_OK);
    assert_int_equal(cfg.fdir.enabled, 0u);
    assert_int_equal(aocs_config_set_uint(&cfg, ref_of("fdir.st_frozen_samples"), 1u), AOCS_ERR_CONFIG_RULE);
    assert_int_equal(aocs_config_set_uint(&cfg, ref_of("fdir.gyro_stuck_samples"), 1u), AOCS_ERR_CONFIG_RULE);
    assert_int_equal(aocs_config_set_uint(&cfg, ref_of("fdir.gyro_stuck_samples"), 2u), AOCS_OK);
    assert_int_equal(aocs_config_set_uint(&cfg, ref_of("fdir.st_persist"), 0u), AOCS_ERR_CONFIG_RULE);
    expect_rule("fdir.wheel_residual_frac", 1.5, AOCS_ERR_CONFIG_RULE);
    expect_rule("fdir.wheel_residual_frac", 0.0, AOCS_ERR_CONFIG_RULE);
    expect_rule("fdir.wheel_residual_frac", 1.0, AOCS_OK);
    expect_rule("fdir.gyro_bias_chi2", 0.0, AOCS_OK); /* 0 = no test */
    expect_rule("fdir.gyro_bias_chi2", -1.0, AOCS_ERR_CONFIG_RULE);
    /* and every value the rules let through, the stage takes */
    cfg.fdir.enabled = 1u;
    cfg.fdir.wheel_residual_frac = AOCS_R(1.0);
    cfg.fdir.st_frozen_samples = 2u;
    cfg.fdir.gyro_stuck_samples = 2u;
    cfg.fdir.gyro_bias_chi2 = AOCS_R(0.0);
    assert_int_equal(aocs_fdir_config_check(&cfg.fdir), AOCS_OK);
}

static void test_keys_and_pil_ids_name_the_same_rows(void **state)
{
    (void)state;
    aocs_config_ref_t a = {NULL, 0u};
    aocs_config_ref_t b = {NULL, 0u};
    const char *bad[] = {"", "k_safe2", "wheel6.js_kgm2", "wheel0.", "wheel.js_kgm2", "wheel00.js_kgm2", "js_kgm2",
                         "wheel1.k_safe", "guidance."};
    for (size_t i = 0u; i < (sizeof(bad) / sizeof(bad[0])); ++i) {
        if (aocs_config_find_key(bad[i], &a) != 0) {
            fail_msg("key '%s' should not be found", bad[i]);
        }
    }
    assert_int_equal(aocs_config_find_key("wheel3.coulomb_nm", &a), 1);
    assert_int_equal(a.wheel, 3u);
    assert_int_equal(aocs_config_pil_id(a), AOCS_PIL_CFG_WHEEL_BASE + (3u * AOCS_PIL_WHEEL_STRIDE) + 5u);
    assert_int_equal(aocs_config_find_pil(aocs_config_pil_id(a), &b), 1);
    assert_ptr_equal(a.field, b.field);
    assert_int_equal(b.wheel, 3u);
    assert_int_equal(aocs_config_find_pil(99u, &b), 0);
    assert_int_equal(aocs_config_find_pil(AOCS_PIL_CFG_WHEEL_BASE + (6u * AOCS_PIL_WHEEL_STRIDE), &b), 0);
    /* every row: unique key and PIL id, found by both */
    for (uint32_t i = 0u; i < aocs_config_field_count(); ++i) {
        const aocs_config_field_t *f = aocs_config_field_at(i);
        const aocs_config_ref_t r = {f, 0u};
        assert_int_equal(aocs_config_find_pil(aocs_config_pil_id(r), &b), 1);
        assert_ptr_equal(b.field, f);
        for (uint32_t k = i + 1u; k < aocs_config_field_count(); ++k) {
            const aocs_config_field_t *g = aocs_config_field_at(k);
            assert_int_not_equal(f->pil_id, g->pil_id);
            if (f->key[0] != '\0') {
                assert_true((strcmp(f->key, g->key) != 0) ||
                            (aocs_config_field_is_per_wheel(f) != aocs_config_field_is_per_wheel(g)));
            }
        }
    }
    assert_null(aocs_config_field_at(aocs_config_field_count()));
}

static void test_enum_names_are_the_enums_values(void **state)
{
    (void)state;
    uint64_t v = 99u;
    const aocs_config_field_t *mode = ref_of("guidance.mode").field;
    const aocs_config_field_t *profile = ref_of("guidance.profile").field;
    assert_int_equal(aocs_config_enum_value(mode, "step", &v), 1);
    assert_int_equal(v, AOCS_GUIDANCE_MODE_STEP);
    assert_int_equal(aocs_config_enum_value(mode, "slew", &v), 1);
    assert_int_equal(v, AOCS_GUIDANCE_MODE_SLEW);
    assert_int_equal(aocs_config_enum_value(profile, "jerk_limited", &v), 1);
    assert_int_equal(v, AOCS_SLEW_PROFILE_JERK_LIMITED);
    v = 99u;
    assert_int_equal(aocs_config_enum_value(mode, "sle", &v), 0);
    assert_int_equal(aocs_config_enum_value(mode, "slewx", &v), 0);
    assert_int_equal(aocs_config_enum_value(mode, "", &v), 0);
    assert_int_equal(aocs_config_enum_value(mode, "step,slew", &v), 0);
    assert_int_equal(v, 99u);
    assert_int_equal(aocs_config_enum_value(ref_of("law").field, "quat_pid", &v), 1);
    assert_int_equal(v, AOCS_LAW_QUAT_PID);
    assert_int_equal(aocs_config_enum_value(ref_of("k_safe").field, "1", &v), 0);
    /* total for any row: an ENUM row without names has no values, and names on a row of another kind are
     * not values of it (the function reads the names only of an ENUM row) */
    {
        aocs_config_field_t odd = *mode;
        odd.names = NULL;
        v = 99u;
        assert_int_equal(aocs_config_enum_value(&odd, "step", &v), 0);
        odd = *ref_of("k_safe").field;
        odd.names = "step,slew";
        assert_int_equal(aocs_config_enum_value(&odd, "slew", &v), 0);
        assert_int_equal(v, 99u);
    }
}

/* "mom.policy" takes the names of the rows of momentum/momentum.def, in id order; the mom.* rows reach their
 * members (a 9-value MAT3 and a 12-value THR row among them) */
static void test_momentum_rows(void **state)
{
    (void)state;
    uint64_t v = 99u;
    aocs_exec_config_t cfg;
    const aocs_config_field_t *pol = ref_of("mom.policy").field;
    assert_int_equal(pol->kind, AOCS_CONFIG_KIND_ENUM);
    assert_int_equal(pol->enum_count, (uint32_t)AOCS_MOM_COUNT);
    for (int i = 0; i < (int)AOCS_MOM_COUNT; ++i) {
        assert_int_equal(aocs_config_enum_value(pol, aocs_mom_name((aocs_mom_id_t)i), &v), 1);
        assert_int_equal(v, (uint64_t)i);
    }
    assert_int_equal(aocs_config_enum_value(ref_of("mom.trigger").field, "continuous", &v), 1);
    assert_int_equal(v, (uint64_t)AOCS_MOM_TRIGGER_CONTINUOUS);
    aocs_exec_config_default(&cfg);
    assert_int_equal(cfg.momentum.policy, (uint32_t)AOCS_MOM_NONE);
    assert_true(cfg.momentum.mtq_axes.m[1][1] > AOCS_R(0.5)); /* identity by default */
    double axes[9] = {0, 1, 0, 0, 0, 1, 1, 0, 0};
    assert_int_equal(aocs_config_set_reals(&cfg, ref_of("mom.mtq_axes"), axes, 9u), AOCS_OK);
    assert_true(cfg.momentum.mtq_axes.m[0][1] > AOCS_R(0.5));
    assert_true(cfg.momentum.mtq_axes.m[2][0] > AOCS_R(0.5));
    double arm[12] = {0};
    arm[11] = -0.75;
    assert_int_equal(ref_of("mom.thr_arm_z_m").field->count, 12u);
    assert_int_equal(aocs_config_set_reals(&cfg, ref_of("mom.thr_arm_z_m"), arm, 12u), AOCS_OK);
    assert_true(cfg.momentum.thr_arm_z_m[11] < AOCS_R(-0.7));
    assert_int_equal(aocs_config_set_reals(&cfg, ref_of("mom.thr_arm_z_m"), arm, 11u), AOCS_ERR_CONFIG_FIELD);
    double neg = -1.0;
    assert_int_equal(aocs_config_set_reals(&cfg, ref_of("mom.h_start_nms"), &neg, 1u), AOCS_ERR_CONFIG_RULE);
}

/* "estimator" takes the names of the rows of estimation/determination.def, in id order */
static void test_estimator_names_are_the_determination_rows(void **state)
{
    (void)state;
    uint64_t v = 99u;
    aocs_exec_config_t cfg;
    const aocs_config_field_t *est = ref_of("estimator").field;
    assert_int_equal(est->kind, AOCS_CONFIG_KIND_ENUM);
    assert_int_equal(est->enum_count, (uint32_t)AOCS_DET_COUNT);
    for (int i = 0; i < (int)AOCS_DET_COUNT; ++i) {
        assert_int_equal(aocs_config_enum_value(est, aocs_det_name((aocs_det_id_t)i), &v), 1);
        assert_int_equal(v, (uint64_t)i);
    }
    /* nothing but the rows: the names string has exactly AOCS_DET_COUNT names */
    {
        uint32_t commas = 0u;
        for (const char *c = est->names; *c != '\0'; ++c) {
            commas += (*c == ',') ? 1u : 0u;
        }
        assert_int_equal(commas + 1u, (uint32_t)AOCS_DET_COUNT);
    }
    assert_int_equal(aocs_config_enum_value(est, "kalman", &v), 0);
    aocs_exec_config_default(&cfg);
    assert_int_equal(cfg.determination.estimator, (uint32_t)AOCS_DET_PASSTHROUGH);
    assert_int_equal(aocs_config_set_uint(&cfg, ref_of("estimator"), (uint64_t)AOCS_DET_MEKF), AOCS_OK);
    assert_int_equal(cfg.determination.estimator, (uint32_t)AOCS_DET_MEKF);
    assert_int_equal(aocs_config_get_uint(&cfg, ref_of("estimator")), (uint64_t)AOCS_DET_MEKF);
    assert_int_equal(aocs_config_set_uint(&cfg, ref_of("estimator"), (uint64_t)AOCS_DET_COUNT), AOCS_ERR_CONFIG_RULE);
    assert_int_equal(cfg.determination.estimator, (uint32_t)AOCS_DET_MEKF);
}

/* The mekf.* rows: their members, rules, and the filter's defaults (aocs_mekf_config_default) */
static void test_mekf_rows(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_mekf_config_t ref;
    const double q[4] = {0.0, 0.0, 0.6, 0.8};
    const double sig = 2.0e-5;
    const double zero = 0.0;
    const double b[3] = {1.0e-5, -2.0e-5, 3.0e-5};
    aocs_exec_config_default(&cfg);
    aocs_mekf_config_default(&ref);
    assert_memory_equal(&cfg.determination.mekf, &ref, sizeof(ref));
    assert_int_equal(aocs_config_set_reals(&cfg, ref_of("mekf.st_q_SB"), q, 4u), AOCS_OK);
    assert_true(same_r(cfg.determination.mekf.q_SB.q[2], (real_t)0.6));
    assert_int_equal(aocs_config_set_reals(&cfg, ref_of("mekf.st_sigma_cross_rad"), &sig, 1u), AOCS_OK);
    assert_true(same_r(cfg.determination.mekf.st_sigma_cross_rad, (real_t)2.0e-5));
    assert_int_equal(aocs_config_set_reals(&cfg, ref_of("mekf.gyro_arw_radpsqrts"), &zero, 1u), AOCS_ERR_CONFIG_RULE);
    assert_int_equal(aocs_config_set_reals(&cfg, ref_of("mekf.bias0_radps"), b, 3u), AOCS_OK);
    assert_true(same_r(cfg.determination.mekf.bias0_B_radps.v[2], (real_t)3.0e-5));
    assert_int_equal(aocs_config_set_reals(&cfg, ref_of("mekf.max_gap_s"), &sig, 1u), AOCS_OK);
    assert_true(same_r(cfg.determination.mekf.max_gap_s, (real_t)2.0e-5));
    assert_int_equal(ref_of("mekf.gate_chi2").field->status, AOCS_ERR_MEKF_GATE_INVALID);
    assert_int_equal(ref_of("mekf.gyro_rrw_radps1p5").field->status, AOCS_ERR_MEKF_NOISE_NOT_POSITIVE);
}

static void test_the_default_config_holds_the_default_column(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_exec_config_default(&cfg);
    assert_true(same_r(cfg.period_s, AOCS_R(0.1)));
    assert_true(same_r(cfg.k_safe, AOCS_R(1.0)));
    assert_true(same_r(cfg.guidance.slew.margin, AOCS_R(0.8)));
    assert_int_equal(cfg.recover_good_samples, 10u);
    assert_int_equal(cfg.missing_max_periods, 3u);
    assert_true(cfg.stale_timeout_ns == 200000000u);
    assert_int_equal(cfg.law, AOCS_LAW_NONE);
    assert_int_equal(cfg.guidance.mode, AOCS_GUIDANCE_MODE_STEP);
    assert_true(same_r(cfg.target.qd_DN.q[3], AOCS_R(1.0)));
    assert_int_equal(cfg.wheels.n, 0u);
    assert_true(same_r(cfg.wheels.coulomb_width_radps[5], AOCS_R(0.1)));
}

static void test_one_inertia_is_shared_with_guidance_and_wheels(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    const double j[9] = {12.0, 0.5, -0.25, 0.5, 9.0, 0.125, -0.25, 0.125, 7.0};
    uint32_t i;
    aocs_exec_config_default(&cfg);
    assert_int_equal(aocs_config_set_reals(&cfg, ref_of("inertia"), j, 9u), AOCS_OK);
    assert_false(same_r(cfg.guidance.slew.inertia_kgm2.m[0][0], AOCS_R(12.0))); /* not shared before the call */
    aocs_config_share_inertia(&cfg);
    for (i = 0u; i < 9u; ++i) {
        assert_true(same_r(cfg.guidance.slew.inertia_kgm2.m[i / 3u][i % 3u], (real_t)j[i]));
        assert_true(same_r(cfg.wheels.inertia_B_kgm2.m[i / 3u][i % 3u], (real_t)j[i]));
    }
    aocs_config_share_inertia(NULL); /* total */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_a_value_lands_in_the_member_its_row_names),
        cmocka_unit_test(test_every_row_round_trips_and_touches_only_its_member),
        cmocka_unit_test(test_every_reader_gets_the_rows_rules),
        cmocka_unit_test(test_physical_ranges_of_wheel_and_guidance_values),
        cmocka_unit_test(test_fault_management_rules_are_registry_rules),
        cmocka_unit_test(test_keys_and_pil_ids_name_the_same_rows),
        cmocka_unit_test(test_enum_names_are_the_enums_values),
        cmocka_unit_test(test_estimator_names_are_the_determination_rows),
        cmocka_unit_test(test_momentum_rows),
        cmocka_unit_test(test_mekf_rows),
        cmocka_unit_test(test_the_default_config_holds_the_default_column),
        cmocka_unit_test(test_one_inertia_is_shared_with_guidance_and_wheels),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
