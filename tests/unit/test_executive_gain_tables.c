/*
 * Gain tables by name (executive gain_tables.c). Proves: every design of
 * gains/aocs_gains.h is listed (count equal to AOCS_GAINS_TABLE_COUNT, names
 * unique) and its name finds it; the law of each table follows from its
 * design name (checked here from the string, not from the lookup); apply
 * copies exactly the generated array (compared with the array symbol named
 * in this test) into the config of that law and nothing else; a table of
 * another law is refused with AOCS_ERR_GAIN_TABLE_WRONG_LAW and the configs
 * untouched; an unknown or differently-cased name, an id out of range and
 * NULL arguments have their own status; the executive initialises each law
 * from its tables.
 */
#include "test_support.h"

#include <string.h>

#include "aocs/executive.h"
#include "gains/aocs_gains.h"

/* the generated arrays by design name, written out here independently of gain_tables.c */
typedef struct {
    const char *name;
    const real_t *k; /* first entry of the 3 x n array, row-major */
    size_t n;        /* its number of entries: 18 (3x6) or 27 (3x9) */
} expected_table_t;

#define EXPECTED_ROW(NAME, SYMBOL) {(NAME), &(SYMBOL)[0][0], sizeof(SYMBOL) / sizeof(real_t)}
static const expected_table_t EXPECTED[] = {
    EXPECTED_ROW("lqr_quat_ref", aocs_gains_lqr_quat_ref_K),
    EXPECTED_ROW("lqr_quat_strong", aocs_gains_lqr_quat_strong_K),
    EXPECTED_ROW("hinf_min", aocs_gains_hinf_min_K),
    EXPECTED_ROW("hinf_regional", aocs_gains_hinf_regional_K),
    EXPECTED_ROW("orbit_lqr_q1", aocs_gains_orbit_lqr_q1_K),
    EXPECTED_ROW("orbit_lqr_q01", aocs_gains_orbit_lqr_q01_K),
    EXPECTED_ROW("orbit_lqr_q10", aocs_gains_orbit_lqr_q10_K),
    EXPECTED_ROW("lqr_quat_i_ref", aocs_gains_lqr_quat_i_ref_K),
    EXPECTED_ROW("hinf_bounded", aocs_gains_hinf_bounded_K),
    EXPECTED_ROW("lqr_quat_i_suite", aocs_gains_lqr_quat_i_suite_K),
    EXPECTED_ROW("lqr_quat_i_rw_suite", aocs_gains_lqr_quat_i_rw_suite_K),
};
#define N_EXPECTED ((int)(sizeof(EXPECTED) / sizeof(EXPECTED[0])))

/* law from the design-name prefix */
static aocs_law_id_t law_of_name(const char *name)
{
    aocs_law_id_t law = AOCS_LAW_NONE;
    if (strncmp(name, "lqr_quat_i_", 11) == 0) {
        law = AOCS_LAW_LQR_QUAT_I;
    } else if (strncmp(name, "lqr_quat_", 9) == 0) {
        law = AOCS_LAW_LQR_QUAT;
    } else if (strncmp(name, "hinf_", 5) == 0) {
        law = AOCS_LAW_HINF;
    } else if (strncmp(name, "orbit_lqr_", 10) == 0) {
        law = AOCS_LAW_ORBIT_LQR;
    } else {
        fail_msg("design name %s has no known law prefix", name);
    }
    return law;
}

/* the gain field of law in c (3x6, 3x9 for lqr_quat_i), by its first entry; *cols its columns */
static real_t *law_gain(aocs_exec_law_configs_t *c, aocs_law_id_t law, int *cols)
{
    real_t *k = NULL;
    *cols = 6;
    if (law == AOCS_LAW_LQR_QUAT) {
        k = &c->lqr_quat.k[0][0];
    } else if (law == AOCS_LAW_HINF) {
        k = &c->hinf.k[0][0];
    } else if (law == AOCS_LAW_LQR_QUAT_I) {
        k = &c->lqr_quat_i.k[0][0];
        *cols = 9;
    } else {
        k = &c->orbit_lqr.k[0][0];
    }
    return k;
}

static void fill_pattern(aocs_exec_law_configs_t *c)
{
    memset(c, 0xA5, sizeof(*c)); /* any change shows up in a byte compare */
}

static void test_every_design_is_listed(void **state)
{
    (void)state;
    assert_int_equal((int)AOCS_GAIN_TABLE_COUNT, AOCS_GAINS_TABLE_COUNT);
    assert_int_equal(N_EXPECTED, AOCS_GAINS_TABLE_COUNT);
    for (int i = 0; i < (int)AOCS_GAIN_TABLE_COUNT; ++i) {
        const char *name = aocs_gain_table_name((aocs_gain_table_id_t)i);
        for (int j = 0; j < i; ++j) {
            assert_string_not_equal(name, aocs_gain_table_name((aocs_gain_table_id_t)j));
        }
        aocs_gain_table_id_t id = AOCS_GAIN_TABLE_COUNT;
        assert_int_equal(aocs_gain_table_find(name, &id), AOCS_OK);
        assert_int_equal(id, i);
        assert_int_equal(aocs_gain_table_law(id), law_of_name(name));
    }
    /* and every expected design name is found */
    for (int e = 0; e < N_EXPECTED; ++e) {
        aocs_gain_table_id_t id = AOCS_GAIN_TABLE_COUNT;
        assert_int_equal(aocs_gain_table_find(EXPECTED[e].name, &id), AOCS_OK);
        assert_string_equal(aocs_gain_table_name(id), EXPECTED[e].name);
    }
    /* the enum comments of executive.h name the same designs */
    assert_string_equal(aocs_gain_table_name(AOCS_GAIN_TABLE_HINF_REGIONAL), "hinf_regional");
    assert_string_equal(aocs_gain_table_name(AOCS_GAIN_TABLE_ORBIT_LQR_Q01), "orbit_lqr_q01");
    assert_string_equal(aocs_gain_table_name(AOCS_GAIN_TABLE_LQR_QUAT_STRONG), "lqr_quat_strong");
}

static void test_apply_copies_the_generated_array(void **state)
{
    (void)state;
    for (int e = 0; e < N_EXPECTED; ++e) {
        aocs_gain_table_id_t id = AOCS_GAIN_TABLE_COUNT;
        aocs_exec_law_configs_t c;
        aocs_exec_law_configs_t before;
        aocs_law_id_t law = law_of_name(EXPECTED[e].name);
        assert_int_equal(aocs_gain_table_find(EXPECTED[e].name, &id), AOCS_OK);
        fill_pattern(&c);
        before = c;
        int cols = 0;
        assert_int_equal(aocs_gain_table_apply(id, law, &c), AOCS_OK);
        assert_memory_equal(law_gain(&c, law, &cols), EXPECTED[e].k, sizeof(real_t) * EXPECTED[e].n);
        assert_int_equal((size_t)(3 * cols), EXPECTED[e].n);
        /* nothing else moved: the old struct with only that gain replaced */
        memcpy(law_gain(&before, law, &cols), EXPECTED[e].k, sizeof(real_t) * EXPECTED[e].n);
        assert_memory_equal(&c, &before, sizeof(c));
    }
}

static void test_wrong_law_and_unknown(void **state)
{
    (void)state;
    const aocs_law_id_t laws[5] = {AOCS_LAW_LQR_QUAT, AOCS_LAW_HINF, AOCS_LAW_ORBIT_LQR, AOCS_LAW_QUAT_PD,
                                   AOCS_LAW_LQR_QUAT_I};
    aocs_exec_law_configs_t c;
    aocs_exec_law_configs_t before;
    fill_pattern(&c);
    before = c;
    for (int i = 0; i < (int)AOCS_GAIN_TABLE_COUNT; ++i) {
        aocs_gain_table_id_t id = (aocs_gain_table_id_t)i;
        for (int l = 0; l < 5; ++l) {
            if (laws[l] != aocs_gain_table_law(id)) {
                assert_int_equal(aocs_gain_table_apply(id, laws[l], &c), AOCS_ERR_GAIN_TABLE_WRONG_LAW);
                assert_memory_equal(&c, &before, sizeof(c));
            }
        }
    }
    aocs_gain_table_id_t id = AOCS_GAIN_TABLE_HINF_MIN;
    assert_int_equal(aocs_gain_table_find("hinf_optimal", &id), AOCS_ERR_GAIN_TABLE_UNKNOWN);
    assert_int_equal(aocs_gain_table_find("HINF_MIN", &id), AOCS_ERR_GAIN_TABLE_UNKNOWN);
    assert_int_equal(aocs_gain_table_find("hinf_min ", &id), AOCS_ERR_GAIN_TABLE_UNKNOWN);
    assert_int_equal(aocs_gain_table_find("", &id), AOCS_ERR_GAIN_TABLE_UNKNOWN);
    assert_int_equal(id, AOCS_GAIN_TABLE_HINF_MIN); /* untouched */
    assert_int_equal(aocs_gain_table_find(NULL, &id), AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_gain_table_find("hinf_min", NULL), AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_gain_table_apply(AOCS_GAIN_TABLE_COUNT, AOCS_LAW_HINF, &c), AOCS_ERR_GAIN_TABLE_UNKNOWN);
    assert_int_equal(aocs_gain_table_apply((aocs_gain_table_id_t)-1, AOCS_LAW_HINF, &c), AOCS_ERR_GAIN_TABLE_UNKNOWN);
    assert_memory_equal(&c, &before, sizeof(c));
    assert_int_equal(aocs_gain_table_apply(AOCS_GAIN_TABLE_HINF_MIN, AOCS_LAW_HINF, NULL), AOCS_ERR_NULL_ARG);
    assert_string_equal(aocs_gain_table_name(AOCS_GAIN_TABLE_COUNT), "unknown");
    assert_int_equal(aocs_gain_table_law(AOCS_GAIN_TABLE_COUNT), AOCS_LAW_NONE);
    assert_int_equal(aocs_gain_table_law((aocs_gain_table_id_t)-3), AOCS_LAW_NONE);
}

/* each law initialises from each of its tables through the executive */
static void test_executive_runs_each_table(void **state)
{
    (void)state;
    for (int i = 0; i < (int)AOCS_GAIN_TABLE_COUNT; ++i) {
        aocs_gain_table_id_t id = (aocs_gain_table_id_t)i;
        aocs_exec_config_t cfg;
        aocs_exec_t exec;
        aocs_exec_output_t out;
        aocs_exec_input_t in;
        aocs_exec_config_default(&cfg);
        cfg.law = aocs_gain_table_law(id);
        cfg.u_max_norm = AOCS_R(1.0e6);
        assert_int_equal(aocs_gain_table_apply(id, cfg.law, &cfg.laws), AOCS_OK);
        cfg.laws.lqr_quat_i.z_max = AOCS_R(1.0); /* not in its table: lqr_quat_i.z_max */
        assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
        memset(&in, 0, sizeof(in));
        in.tick = 1u;
        in.t_sensor_ns = 100000000u;
        in.valid = AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE | AOCS_EXEC_VALID_ORBIT;
        in.q_BN = aocs_quat_identity();
        in.w_BN_B = aocs_vec3_make(AOCS_R(0.0), AOCS_R(0.001), AOCS_R(0.0)); /* a pure rate error */
        in.vel_mps = aocs_vec3_make(AOCS_R(0.0), AOCS_R(0.01), AOCS_R(0.0));
        assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
        assert_int_equal(out.mode, AOCS_EXEC_MODE_NOMINAL);
        assert_int_equal(out.law_status, AOCS_OK);
        /* zero angles (and z = 0) and a rate / velocity along axis 2: the torque is the table's rate
           column of axis 2 (index 4; lqr_quat_i x = [z; qe_vec; we]: index 7) */
        int cols = 0;
        const real_t *k = law_gain(&cfg.laws, cfg.law, &cols);
        double sign = (cfg.law == AOCS_LAW_HINF) ? 1.0 : -1.0; /* hinf u = +K x, the LQRs -K x */
        double mag = (cfg.law == AOCS_LAW_ORBIT_LQR) ? 0.01 : 0.001;
        int col = (cfg.law == AOCS_LAW_ORBIT_LQR) ? 1 : ((cfg.law == AOCS_LAW_LQR_QUAT_I) ? 7 : 4);
        for (int r = 0; r < 3; ++r) {
            assert_close(out.u_unsat.v[r], sign * (double)k[r * cols + col] * mag, TOL_TIGHT);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_design_is_listed),
        cmocka_unit_test(test_apply_copies_the_generated_array),
        cmocka_unit_test(test_wrong_law_and_unknown),
        cmocka_unit_test(test_executive_runs_each_table),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
