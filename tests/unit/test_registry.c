/*
 * The law registry (firmware/include/aocs/laws.def) and what is expanded
 * from it: every row consistent with itself and with the others, the wire
 * values pinned (law ids 0..12 in the historical order, PIL field ids), and
 * every derived table agreeing with the rows:
 *   - names unique, ids contiguous and equal to the wire values, name <-> id
 *     round trip for every row (aocs_law_name / aocs_law_from_name);
 *   - budgets non-zero and those of aocs_law_budget_ns / aocs_budget_instructions;
 *   - every field of a law has a unique PIL id (unique over all CONFIG
 *     fields, the executive's included), a count that fits its type, a key
 *     and member of its law's config, a variant that exists;
 *   - each law's init rejects its zeroed config and accepts the reference
 *     configuration (REF column), and a step then runs;
 *   - every PIL field round-trips through the codec into its member;
 *   - every gain table belongs to a law with a TABLE field and applies to it.
 */
#include "test_support.h"

#include <string.h>

#include "aocs/budget.h"
#include "aocs/executive.h"
#include "aocs/pil_frame.h"
#include "aocs_registry.h"

/* ---- the wire values (docs/wire-contract.md "Law ids", docs/pil.md CONFIG fields) ---- */
static const char *const WIRE_LAWS[] = {
    "none",    "crp_linear", "quat_pd", "quat_nlpd_neg", "quat_nlpd_pos", "smc",
    "lqr_quat", "hinf",      "mrp_sat", "mrp_sat_tanh",  "orbit_lqr", "quat_pid", "lqr_quat_i",
};
#define N_WIRE_LAWS ((int)(sizeof(WIRE_LAWS) / sizeof(WIRE_LAWS[0])))

typedef struct {
    const char *key; /* fsw_node key, or the PIL name for the executive-only fields */
    uint32_t id;
} wire_field_t;

static const wire_field_t WIRE_LAW_FIELDS[] = {
    {"inertia", 15u},        {"crp_linear.k1", 16u},  {"crp_linear.k2", 17u},   {"quat_pd.kp", 18u},
    {"quat_pd.kd", 19u},     {"quat_nlpd.kp", 20u},   {"quat_nlpd.kd", 21u},    {"smc.lambda", 22u},
    {"smc.g", 23u},          {"smc.eps", 24u},        {"lqr_quat.k", 25u},      {"lqr_quat.table", 26u},
    {"hinf.k", 27u},         {"hinf.table", 28u},     {"mrp_sat.k", 29u},       {"mrp_sat.lambda", 30u},
    {"mrp_sat.u_max", 31u},  {"mrp_sat.l1", 32u},     {"mrp_sat.m1", 33u},      {"mrp_sat.l2", 34u},
    {"mrp_sat.m2", 35u},     {"orbit_lqr.k", 36u},    {"orbit_lqr.table", 37u},   {"quat_pid.kp", 38u},
    {"quat_pid.kd", 39u},    {"quat_pid.ki", 40u},    {"quat_pid.z_max", 41u},   {"lqr_quat_i.k", 42u},
    {"lqr_quat_i.table", 43u}, {"lqr_quat_i.z_max", 44u},
};
#define N_WIRE_LAW_FIELDS ((int)(sizeof(WIRE_LAW_FIELDS) / sizeof(WIRE_LAW_FIELDS[0])))

static const wire_field_t WIRE_EXEC_FIELDS[] = {
    {"LAW", 1u},         {"PERIOD_S", 2u},   {"TARGET_Q", 3u},          {"TARGET_W", 4u},
    {"TARGET_W_DOT", 5u}, {"TARGET_ROTATION_RATE", 6u}, {"TARGET_T0_NS", 7u}, {"U_MAX_AXIS", 8u},
    {"U_MAX_NORM", 9u},  {"K_SAFE", 10u},    {"RECOVER_GOOD_SAMPLES", 11u}, {"MISSING_MAX_PERIODS", 12u},
    {"STALE_TIMEOUT_NS", 13u}, {"BUDGET_INSTR", 14u},
    /* the slew guidance (executive.h), ids from 60 */
    {"GUIDANCE_MODE", 60u}, {"GUIDANCE_PROFILE", 61u}, {"GUIDANCE_MARGIN", 62u}, {"GUIDANCE_RATE_LIMIT", 63u},
    {"GUIDANCE_JERK_TIME", 64u},
    /* the wheel array (wheel_array.h), ids from 65 */
    {"WHEELS_COUNT", 65u}, {"WHEELS_FAILED_MASK", 66u}, {"WHEELS_NULL_GAIN", 67u},
    {"ESTIMATOR", 68u},
    /* the MEKF's configuration (estimation/mekf.h), ids from 69 */
    {"MEKF_ST_Q_SB", 69u}, {"MEKF_ST_SIGMA_CROSS", 70u}, {"MEKF_ST_SIGMA_ABOUT", 71u}, {"MEKF_GYRO_ARW", 72u},
    {"MEKF_GYRO_RRW", 73u}, {"MEKF_BIAS0", 74u}, {"MEKF_P0_ATT_SIGMA", 75u}, {"MEKF_P0_BIAS_SIGMA", 76u},
    {"MEKF_GATE_CHI2", 77u}, {"MEKF_MAX_GAP", 78u}, {"MEKF_INIT_MODE", 79u}, {"MEKF_INIT_Q_BN", 80u},
    {"MOM_POLICY", 81u}, {"MOM_TRIGGER", 82u}, {"MOM_H_TARGET", 83u}, {"MOM_H_START", 84u}, {"MOM_H_STOP", 85u},
    {"MOM_K_MTQ", 86u}, {"MOM_MTQ_AXES", 87u}, {"MOM_MTQ_MAX_DIPOLE", 88u}, {"MOM_DUMP_TORQUE", 89u},
    {"MOM_THR_COUNT", 90u}, {"MOM_THR_THRUST", 91u}, {"MOM_THR_MIN_ON", 92u}, {"MOM_THR_QUANTUM", 93u},
    {"MOM_THR_ARM_X", 94u}, {"MOM_THR_ARM_Y", 95u}, {"MOM_THR_ARM_Z", 96u},
    /* fault management (fdir/fdir.h): 97, 98, then from 160 (99 is kept free, 100 .. 147 are the wheels') */
    {"FDIR_ENABLED", 97u}, {"FDIR_WHEEL_RESIDUAL_FRAC", 98u}, {"FDIR_WHEEL_PERSIST", 160u}, {"FDIR_ST_CHI2", 161u},
    {"FDIR_ST_PERSIST", 162u}, {"FDIR_ST_RESTORE", 163u}, {"FDIR_ST_FROZEN_SAMPLES", 164u},
    {"FDIR_ST_FROZEN_RATE", 165u}, {"FDIR_GYRO_STUCK_SAMPLES", 166u}, {"FDIR_GYRO_SAT", 167u},
    {"FDIR_LINK_LOST_PERIODS", 168u},
    {"FDIR_GYRO_BIAS_CHI2", 169u},
    {"FDIR_GYRO_BIAS_PERSIST", 170u},
    {"FDIR_MOM_RESIDUAL", 171u}, {"FDIR_MOM_WINDOW", 172u}, {"FDIR_MOM_PERSIST", 173u},
    {"FDIR_WHEEL_FRICTION_WINDOW", 174u}, {"FDIR_WHEEL_FRICTION_EXCESS", 175u},
    /* the MEKF's gyroless model (docs/spec.md 5.6.12) */
    {"MEKF_GYROLESS_TORQUE_SIGMA", 176u}, {"MEKF_GYROLESS_P0_RATE_SIGMA", 177u}, {"MEKF_GYROLESS_RATE_SIGMA", 178u},
    {"FDIR_ST_NOISE_SCALE_MAX", 179u},
    /* latch-valve branches and the stuck-open test (docs/spec.md 5.15.8) */
    {"MOM_THR_LATCH_B_MASK", 180u}, {"FDIR_THR_OPEN_PERSIST", 181u},
    /* per wheel i: 100 + 8 i + field (pil_frame.h AOCS_PIL_WHEEL_FIELD_ROWS); wheel 0 and the last one here,
     * the rest by the rule in test_pil_ids_are_the_wire_values_and_unique */
    {"WHEEL0_AXIS", 100u}, {"WHEEL0_JS", 101u}, {"WHEEL0_U_MAX", 102u}, {"WHEEL0_OMEGA_MAX", 103u},
    {"WHEEL0_VISCOUS", 104u}, {"WHEEL0_COULOMB", 105u}, {"WHEEL0_COULOMB_WIDTH", 106u}, {"WHEEL0_NULL_SPEED", 107u},
};
#define N_WIRE_EXEC_FIELDS ((int)(sizeof(WIRE_EXEC_FIELDS) / sizeof(WIRE_EXEC_FIELDS[0])))

/* the enum constants are the same numbers (a renumbering fails to compile this list into these values) */
static void test_law_ids_are_the_wire_values(void **state)
{
    (void)state;
    assert_int_equal(AOCS_LAW_NONE, 0);
    assert_int_equal(AOCS_LAW_CRP_LINEAR, 1);
    assert_int_equal(AOCS_LAW_QUAT_PD, 2);
    assert_int_equal(AOCS_LAW_QUAT_NLPD_NEG, 3);
    assert_int_equal(AOCS_LAW_QUAT_NLPD_POS, 4);
    assert_int_equal(AOCS_LAW_SMC, 5);
    assert_int_equal(AOCS_LAW_LQR_QUAT, 6);
    assert_int_equal(AOCS_LAW_HINF, 7);
    assert_int_equal(AOCS_LAW_MRP_SAT_LINEAR, 8);
    assert_int_equal(AOCS_LAW_MRP_SAT_TANH, 9);
    assert_int_equal(AOCS_LAW_ORBIT_LQR, 10);
    assert_int_equal(AOCS_LAW_QUAT_PID, 11);
    assert_int_equal(AOCS_LAW_LQR_QUAT_I, 12);
    /* new laws are appended: the historical ones keep their ids and names */
    /* exact on purpose (docs/extending.md): a new row of laws.def must be appended here too */
    if ((int)AOCS_LAW_COUNT != N_WIRE_LAWS) {
        fail_msg("laws.def has %d laws (with none), WIRE_LAWS lists %d: append the new law's wire name",
                 (int)AOCS_LAW_COUNT, N_WIRE_LAWS);
    }
    for (int i = 0; i < N_WIRE_LAWS; ++i) {
        aocs_law_id_t id = AOCS_LAW_COUNT;
        assert_string_equal(aocs_law_name((aocs_law_id_t)i), WIRE_LAWS[i]);
        assert_int_equal(aocs_law_from_name(WIRE_LAWS[i], &id), AOCS_OK);
        assert_int_equal(id, i);
    }
}

static void test_rows_are_contiguous_unique_and_round_trip(void **state)
{
    (void)state;
    assert_int_equal(aocs_registry_law_count, (size_t)AOCS_LAW_COUNT - 1u);
    assert_null(aocs_registry_law(AOCS_LAW_NONE));
    assert_null(aocs_registry_law(AOCS_LAW_COUNT));
    for (size_t i = 0u; i < aocs_registry_law_count; ++i) {
        const aocs_registry_law_t *l = &aocs_registry_laws[i];
        aocs_law_id_t id = AOCS_LAW_NONE;
        assert_int_equal((int)l->id, (int)i + 1);
        assert_ptr_equal(aocs_registry_law(l->id), l);
        assert_true(strlen(l->name) > 0u);
        assert_string_not_equal(l->name, "none");
        assert_string_not_equal(l->name, "unknown");
        assert_string_equal(aocs_law_name(l->id), l->name);
        assert_int_equal(aocs_law_from_name(l->name, &id), AOCS_OK);
        assert_int_equal(id, l->id);
        assert_int_equal(strncmp(l->enum_name, "AOCS_LAW_", 9u), 0);
        for (size_t j = 0u; j < i; ++j) {
            assert_string_not_equal(l->name, aocs_registry_laws[j].name);
            assert_string_not_equal(l->enum_name, aocs_registry_laws[j].enum_name);
            assert_string_not_equal(l->state, aocs_registry_laws[j].state);
        }
        assert_true((strcmp(l->input, "attitude") == 0) || (strcmp(l->input, "orbit") == 0));
        assert_int_equal(aocs_law_is_orbit(l->id), (strcmp(l->input, "orbit") == 0) ? 1 : 0);
        assert_true(strlen(l->reference_scenario) > 0u);
    }
    assert_string_equal(aocs_law_name(AOCS_LAW_COUNT), "unknown");
}

/* a CFG_SHARED row follows a CFG_OWN row of the same config and type; variants differ */
static void test_shared_configs_and_variants(void **state)
{
    (void)state;
    for (size_t i = 0u; i < aocs_registry_law_count; ++i) {
        const aocs_registry_law_t *l = &aocs_registry_laws[i];
        int owners_before = 0;
        for (size_t j = 0u; j < i; ++j) {
            const aocs_registry_law_t *o = &aocs_registry_laws[j];
            if (strcmp(o->config, l->config) == 0) {
                assert_string_equal(o->config_type, l->config_type);
                owners_before += o->config_owner;
                /* two laws on one config: each forces its own variant */
                assert_non_null(l->variant_value);
                assert_non_null(o->variant_value);
                assert_string_equal(l->variant_member, o->variant_member);
                assert_int_not_equal(l->variant_number, o->variant_number);
            }
        }
        assert_int_equal(owners_before, l->config_owner ? 0 : 1);
        if (l->variant_value == NULL) {
            assert_null(l->variant_member);
            assert_int_equal(l->variant_number, -1);
        } else {
            assert_true(l->variant_number >= 0);
        }
    }
}

/* a FROM_FIELD row names one field of another law's config, which then applies to it too */
static void test_from_field_rows_name_a_field(void **state)
{
    int n_from = 0;
    (void)state;
    for (size_t i = 0u; i < aocs_registry_law_count; ++i) {
        const aocs_registry_law_t *l = &aocs_registry_laws[i];
        int found = 0;
        if (l->from_field == NULL) {
            assert_null(l->from_member);
            continue;
        }
        n_from++;
        assert_non_null(l->from_member);
        assert_null(l->variant_value); /* one column: a variant or a copied field */
        for (size_t j = 0u; j < aocs_registry_field_count; ++j) {
            const aocs_registry_field_t *f = &aocs_registry_fields[j];
            if (strcmp(f->member, l->from_field) == 0) {
                found++;
                assert_int_not_equal(f->law, l->id);
                assert_int_equal(aocs_registry_field_applies(f, l), 1);
            }
        }
        assert_int_equal(found, 1);
    }
    assert_true(n_from >= 1); /* quat_pid takes the inertia field */
}

static void test_budgets_are_set_and_derived(void **state)
{
    (void)state;
    for (size_t i = 0u; i < aocs_registry_law_count; ++i) {
        const aocs_registry_law_t *l = &aocs_registry_laws[i];
        assert_true(l->budget_ns > 0u);
        assert_true(l->instr_m4f > 0u);
        assert_true(l->instr_m7 > 0u);
        assert_int_equal(aocs_law_budget_ns(l->id), l->budget_ns);
        assert_int_equal(aocs_budget_instructions(l->id, AOCS_BUDGET_TARGET_CORTEX_M4F), l->instr_m4f);
        assert_int_equal(aocs_budget_instructions(l->id, AOCS_BUDGET_TARGET_CORTEX_M7), l->instr_m7);
    }
    assert_int_equal(aocs_law_budget_ns(AOCS_LAW_NONE), (uint64_t)AOCS_EXEC_SAFE_BUDGET_NS);
    assert_int_equal(aocs_budget_instructions(AOCS_LAW_NONE, AOCS_BUDGET_TARGET_CORTEX_M4F),
                     AOCS_BUDGET_STANDBY_INSTR_M4F);
    assert_int_equal(aocs_budget_instructions(AOCS_LAW_NONE, AOCS_BUDGET_TARGET_CORTEX_M7),
                     AOCS_BUDGET_STANDBY_INSTR_M7);
    assert_int_equal(aocs_budget_instructions(AOCS_LAW_COUNT, AOCS_BUDGET_TARGET_CORTEX_M7), 0u);
}

/* the PIL count of a type; a gain is 3 x n (3x6, or 3x9 for lqr_quat_i): its count must be one of those */
static uint32_t type_count(const char *type, uint32_t count)
{
    uint32_t n = 0u;
    if (strcmp(type, "real") == 0) {
        n = 1u;
    } else if (strcmp(type, "vec3") == 0) {
        n = 3u;
    } else if (strcmp(type, "mat3") == 0) {
        n = 9u;
    } else if (strcmp(type, "gain") == 0) {
        n = ((count == 18u) || (count == 27u)) ? count : 18u;
    } else if (strcmp(type, "table") == 0) {
        n = 1u;
    }
    return n;
}

static void test_pil_ids_are_the_wire_values_and_unique(void **state)
{
    (void)state;
    /* the listed ones, then wheels 1 .. 5 with wheel 0's fields at +8 each */
    assert_int_equal((int)aocs_registry_exec_field_count, N_WIRE_EXEC_FIELDS + 5 * 8);
    for (int i = 0; i < N_WIRE_EXEC_FIELDS; ++i) {
        assert_string_equal(aocs_registry_exec_fields[i].name, WIRE_EXEC_FIELDS[i].key);
        assert_int_equal(aocs_registry_exec_fields[i].pil_id, WIRE_EXEC_FIELDS[i].id);
    }
    for (int w = 1; w < 6; ++w) {
        for (int f = 0; f < 8; ++f) {
            const aocs_registry_exec_field_t *x = &aocs_registry_exec_fields[N_WIRE_EXEC_FIELDS + (w - 1) * 8 + f];
            const aocs_registry_exec_field_t *x0 = &aocs_registry_exec_fields[N_WIRE_EXEC_FIELDS - 8 + f];
            char name[40];
            (void)snprintf(name, sizeof(name), "WHEEL%d_%s", w, x0->name + strlen("WHEEL0_"));
            assert_string_equal(x->name, name);
            assert_int_equal(x->pil_id, x0->pil_id + 8u * (uint32_t)w);
        }
    }
    assert_int_equal(AOCS_PIL_CFG_WHEELS_COUNT, 65);
    assert_int_equal(AOCS_PIL_CFG_WHEEL_BASE, 100);
    assert_int_equal(AOCS_PIL_WHEEL_STRIDE, 8);
    assert_int_equal(AOCS_PIL_CFG_LAW, 1);
    assert_int_equal(AOCS_PIL_CFG_BUDGET_INSTR, 14);
    assert_int_equal(AOCS_PIL_CFG_INERTIA, 15);
    assert_int_equal(AOCS_PIL_CFG_QUAT_PD_KP, 18);
    assert_int_equal(AOCS_PIL_CFG_HINF_TABLE, 28);
    assert_int_equal(AOCS_PIL_CFG_ORBIT_TABLE, 37);
    /* the historical fields keep their ids; new fields are appended */
    assert_true((int)aocs_registry_field_count >= N_WIRE_LAW_FIELDS);
    for (int i = 0; i < N_WIRE_LAW_FIELDS; ++i) {
        assert_string_equal(aocs_registry_fields[i].key, WIRE_LAW_FIELDS[i].key);
        assert_int_equal(aocs_registry_fields[i].pil_id, WIRE_LAW_FIELDS[i].id);
    }
    for (size_t i = 0u; i < aocs_registry_field_count; ++i) {
        const aocs_registry_field_t *f = &aocs_registry_fields[i];
        assert_true((f->pil_id > 0u) && (f->pil_id < 255u));
        for (size_t j = 0u; j < i; ++j) {
            assert_int_not_equal(f->pil_id, aocs_registry_fields[j].pil_id);
            assert_string_not_equal(f->key, aocs_registry_fields[j].key);
            assert_string_not_equal(f->name, aocs_registry_fields[j].name);
        }
        for (size_t j = 0u; j < aocs_registry_exec_field_count; ++j) {
            assert_int_not_equal(f->pil_id, aocs_registry_exec_fields[j].pil_id);
            assert_string_not_equal(f->name, aocs_registry_exec_fields[j].name);
        }
    }
}

static void test_fields_fit_their_law(void **state)
{
    (void)state;
    for (size_t i = 0u; i < aocs_registry_field_count; ++i) {
        const aocs_registry_field_t *f = &aocs_registry_fields[i];
        const aocs_registry_law_t *owner = aocs_registry_law(f->law);
        size_t cfg_len;
        assert_non_null(owner);
        cfg_len = strlen(owner->config);
        assert_int_equal(f->count, type_count(f->type, f->count));
        assert_true(owner->config_owner || (strcmp(f->type, "table") == 0));
        /* the member is in the owner's config */
        assert_int_equal(strncmp(f->member, owner->config, cfg_len), 0);
        assert_int_equal(f->member[cfg_len], '.');
        if (strcmp(f->type, "table") == 0) {
            /* a TABLE field fills the gain of a GAIN field of the same config */
            int gains = 0;
            for (size_t j = 0u; j < aocs_registry_field_count; ++j) {
                const aocs_registry_field_t *g = &aocs_registry_fields[j];
                gains += ((strcmp(g->type, "gain") == 0) && (strcmp(g->member, f->member) == 0)) ? 1 : 0;
            }
            assert_int_equal(gains, 1);
            assert_string_equal(f->rule, "any");
            assert_int_equal(strncmp(f->key, owner->config, cfg_len), 0);
            assert_string_equal(&f->key[cfg_len], ".table");
        } else {
            /* "<config>.<member>", or the bare member name (the historical "inertia") */
            assert_true((strcmp(f->key, f->member) == 0) || (strcmp(f->key, &f->member[cfg_len + 1u]) == 0));
        }
        assert_true((strcmp(f->rule, "any") == 0) || (strcmp(f->rule, "pos") == 0) ||
                    (strcmp(f->rule, "nonneg") == 0));
        assert_true(strlen(f->help) > 0u);
        /* a variant-only field names a variant of a law on this config */
        if (strcmp(f->variant, "ALL") != 0) {
            int found = 0;
            for (size_t j = 0u; j < aocs_registry_law_count; ++j) {
                const aocs_registry_law_t *l = &aocs_registry_laws[j];
                found += ((strcmp(l->config, owner->config) == 0) && (l->variant_value != NULL) &&
                          (strcmp(l->variant_value, f->variant) == 0))
                             ? 1
                             : 0;
            }
            assert_int_equal(found, 1);
        }
    }
    /* every law takes at least one field */
    for (size_t i = 0u; i < aocs_registry_law_count; ++i) {
        int n = 0;
        for (size_t j = 0u; j < aocs_registry_field_count; ++j) {
            n += aocs_registry_field_applies(&aocs_registry_fields[j], &aocs_registry_laws[i]);
        }
        assert_true(n > 0);
    }
}

static aocs_exec_law_states_t states;

static void test_init_rejects_zero_and_accepts_the_reference(void **state)
{
    aocs_exec_law_configs_t zero;
    aocs_exec_law_configs_t ref;
    char err[256] = "";
    aocs_att_input_t att;
    aocs_orbit_input_t orb;
    (void)state;
    (void)memset(&zero, 0, sizeof(zero));
    if (aocs_registry_reference_configs(&ref, err, sizeof(err)) != 0) {
        print_error("reference configuration: %s\n", err);
        fail();
    }
    (void)memset(&att, 0, sizeof(att));
    assert_int_equal(aocs_quat_normalize(aocs_quat_make(AOCS_R(0.1), AOCS_R(-0.2), AOCS_R(0.05), AOCS_R(0.97)),
                                         &att.q_BN),
                     AOCS_OK);
    att.qd_DN = aocs_quat_identity();
    att.w_BN_B = aocs_vec3_make(AOCS_R(0.001), AOCS_R(0.0), AOCS_R(-0.002));
    att.dt_s = AOCS_R(0.1);
    att.u_max_axis = aocs_vec3_zero();
    att.u_max_norm = AOCS_R(0.0);
    (void)memset(&orb, 0, sizeof(orb));
    orb.pos_m = aocs_vec3_make(AOCS_R(1.0), AOCS_R(-2.0), AOCS_R(3.0));
    orb.dt_s = AOCS_R(0.1);
    for (size_t i = 0u; i < aocs_registry_law_count; ++i) {
        const aocs_registry_law_t *l = &aocs_registry_laws[i];
        aocs_vec3_t u = aocs_vec3_make(AOCS_R(1.0), AOCS_R(1.0), AOCS_R(1.0));
        aocs_status_t st = aocs_exec_law_init(&states, &zero, l->id);
        if (st == AOCS_OK) {
            print_error("%s: init accepted the zeroed config\n", l->name);
            fail();
        }
        st = aocs_exec_law_init(&states, &ref, l->id);
        if (st != AOCS_OK) {
            print_error("%s: init rejected the reference config: %s\n", l->name, aocs_status_name(st));
            fail();
        }
        assert_int_equal(aocs_exec_law_step(&states, l->id, &att, &orb, &u), AOCS_OK);
        assert_true(AOCS_IS_FINITE(u.v[0]) && AOCS_IS_FINITE(u.v[1]) && AOCS_IS_FINITE(u.v[2]));
    }
    assert_int_equal(aocs_exec_law_init(&states, &ref, AOCS_LAW_NONE), AOCS_ERR_UNKNOWN_LAW);
    assert_int_equal(aocs_exec_law_init(&states, &ref, AOCS_LAW_COUNT), AOCS_ERR_UNKNOWN_LAW);
}

/* ---- every PIL field lands in its member (expanded from the rows, like the codec) ---- */
static int expect_reals(const real_t *got, uint32_t n, real_t base)
{
    for (uint32_t i = 0u; i < n; ++i) {
        const real_t want = base + (real_t)i; /* small integers: exact in both precisions */
        if ((got[i] < want) || (got[i] > want)) {
            return 1;
        }
    }
    return 0;
}

#define T_AT_REAL(MEMBER) (&cfg.laws.MEMBER)
#define T_AT_VEC3(MEMBER) (cfg.laws.MEMBER.v)
#define T_AT_MAT3(MEMBER) (&cfg.laws.MEMBER.m[0][0])
#define T_AT_GAIN(MEMBER) (&cfg.laws.MEMBER[0][0])
#define T_AT_TABLE(MEMBER) (&cfg.laws.MEMBER[0][0])
/* the member holds exactly COUNT reals (a TABLE field: its gain's), so the codec's count is its size */
#define T_FIELD_CHECK(NAME, LAW, KEY, MEMBER, TYPE, COUNT, RULE, HELP, PIL_ID, ...)                                \
    if (strcmp(#TYPE, "TABLE") != 0) {                                                                      \
        assert_int_equal(sizeof(cfg.laws.MEMBER) / sizeof(real_t), (COUNT));                                \
    }                                                                                                       \
    check_field(#NAME, (aocs_pil_cfg_field_t)(PIL_ID), (COUNT), strcmp(#TYPE, "TABLE") == 0, AOCS_LAW_##LAW, \
                &cfg, T_AT_##TYPE(MEMBER), (uint32_t)(sizeof(cfg.laws.MEMBER) / sizeof(real_t)));

static void check_field(const char *name, aocs_pil_cfg_field_t id, uint32_t count, int is_table, aocs_law_id_t law,
                        aocs_exec_config_t *cfg_out, const real_t *at, uint32_t member_reals)
{
    uint8_t buf[AOCS_PIL_PAYLOAD_MAX];
    uint32_t pos = 0u;
    uint64_t budget = 0u;
    uint32_t field = 0u;
    aocs_status_t status = AOCS_OK;
    aocs_pil_err_t err;
    real_t vals[27];
    aocs_exec_config_default(cfg_out);
    if (is_table) {
        /* the first table of the law, by name: its matrix lands in the member */
        int found = 0;
        for (size_t t = 0u; (t < aocs_registry_table_count) && (found == 0); ++t) {
            if (aocs_registry_tables[t].law == law) {
                assert_int_equal(aocs_pil_config_put_name(buf, sizeof(buf), &pos, id, aocs_registry_tables[t].name),
                                 AOCS_PIL_OK);
                found = 1;
            }
        }
        assert_int_equal(found, 1);
    } else {
        for (uint32_t i = 0u; i < count; ++i) {
            vals[i] = AOCS_R(7.0) + (real_t)i;
        }
        assert_int_equal(aocs_pil_config_put_reals(buf, sizeof(buf), &pos, id, vals, count), AOCS_PIL_OK);
    }
    err = aocs_pil_config_decode(buf, pos, cfg_out, &budget, &field, &status);
    if ((err != AOCS_PIL_OK) || (status != AOCS_OK)) {
        print_error("%s: decode %s (field %u), %s\n", name, aocs_pil_err_name(err), (unsigned)field,
                    aocs_status_name(status));
        fail();
    }
    if (is_table) {
        int nonzero = 0;
        for (uint32_t i = 0u; i < member_reals; ++i) {
            nonzero += (AOCS_FABS(at[i]) > AOCS_R(0.0)) ? 1 : 0;
        }
        assert_true(nonzero > 0);
    } else if (expect_reals(at, count, AOCS_R(7.0)) != 0) {
        print_error("%s: values did not land in the member\n", name);
        fail();
    }
    /* one value too many or too few is refused with the field's id */
    if (!is_table) {
        pos = 0u;
        buf[pos++] = (uint8_t)id;
        buf[pos++] = (uint8_t)(count + 1u);
        (void)memset(&buf[pos], 0, 8u * (count + 1u));
        pos += 8u * (count + 1u);
        aocs_exec_config_default(cfg_out);
        assert_int_equal(aocs_pil_config_decode(buf, pos, cfg_out, &budget, &field, &status), AOCS_PIL_ERR_FIELD);
        assert_int_equal(field, (uint32_t)id);
    }
}

static void test_every_pil_field_reaches_its_member(void **state)
{
    aocs_exec_config_t cfg;
    (void)state;
    aocs_exec_config_default(&cfg);
    AOCS_LAW_FIELD_ROWS(T_FIELD_CHECK)
}

static void test_gain_tables_fit_their_law(void **state)
{
    (void)state;
    assert_int_equal(aocs_registry_table_count, (size_t)AOCS_GAIN_TABLE_COUNT);
    for (size_t t = 0u; t < aocs_registry_table_count; ++t) {
        const aocs_registry_table_t *tb = &aocs_registry_tables[t];
        aocs_exec_law_configs_t c;
        aocs_gain_table_id_t id = AOCS_GAIN_TABLE_COUNT;
        int table_fields = 0;
        assert_int_equal((int)tb->id, (int)t);
        assert_string_equal(aocs_gain_table_name(tb->id), tb->name);
        assert_int_equal(aocs_gain_table_law(tb->id), tb->law);
        assert_int_equal(aocs_gain_table_find(tb->name, &id), AOCS_OK);
        assert_int_equal(id, tb->id);
        for (size_t j = 0u; j < aocs_registry_field_count; ++j) {
            table_fields += ((aocs_registry_fields[j].law == tb->law) &&
                             (strcmp(aocs_registry_fields[j].type, "table") == 0))
                                ? 1
                                : 0;
        }
        assert_int_equal(table_fields, 1);
        (void)memset(&c, 0, sizeof(c));
        assert_int_equal(aocs_gain_table_apply(tb->id, tb->law, &c), AOCS_OK);
        for (size_t j = 0u; j < t; ++j) {
            assert_string_not_equal(tb->name, aocs_registry_tables[j].name);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_law_ids_are_the_wire_values),
        cmocka_unit_test(test_rows_are_contiguous_unique_and_round_trip),
        cmocka_unit_test(test_shared_configs_and_variants),
        cmocka_unit_test(test_from_field_rows_name_a_field),
        cmocka_unit_test(test_budgets_are_set_and_derived),
        cmocka_unit_test(test_pil_ids_are_the_wire_values_and_unique),
        cmocka_unit_test(test_fields_fit_their_law),
        cmocka_unit_test(test_init_rejects_zero_and_accepts_the_reference),
        cmocka_unit_test(test_every_pil_field_reaches_its_member),
        cmocka_unit_test(test_gain_tables_fit_their_law),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
