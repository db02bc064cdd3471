/*
 * The control-law stage's registry interface (part of aocs/executive.h): law
 * ids, names and facts, one config and one state of each law, and the direct
 * dispatch to a law's init/step, all expanded from the rows of aocs/laws.def.
 */
#ifndef AOCS_EXEC_LAW_DISPATCH_H
#define AOCS_EXEC_LAW_DISPATCH_H

#include <stdint.h>

#include "aocs/types.h"
#include "aocs/math3.h"
#include "aocs/attitude.h"
#include "aocs/laws.def"

/*
 * ---- law identifiers (laws.def, law_table.c) ----
 * AOCS_LAW_NONE = 0, then one id per AOCS_LAW_ROWS row in row order (the
 * wire values: crp_linear = 1 .. orbit_lqr = 10), then AOCS_LAW_COUNT.
 */
#define AOCS_LAW_ENUM_ROW(ID, ...) AOCS_LAW_##ID,
typedef enum {
    AOCS_LAW_NONE = 0, /* no law: STANDBY */
    AOCS_LAW_ROWS(AOCS_LAW_ENUM_ROW)
    AOCS_LAW_COUNT
} aocs_law_id_t;

/* CLI name of a law ("quat_pd"); "none" for AOCS_LAW_NONE, "unknown" when out of range. Total. */
const char *aocs_law_name(aocs_law_id_t law);

/*
 * Law id from its CLI name (exact, case-sensitive; "none" gives
 * AOCS_LAW_NONE). AOCS_ERR_UNKNOWN_LAW (and *law untouched) for any other
 * string, AOCS_ERR_NULL_ARG for NULL pointers.
 */
aocs_status_t aocs_law_from_name(const char *name, aocs_law_id_t *law);

/* 1 for a law whose formula includes the slew feedforward (AOCS_LAW_FEEDFORWARD_IN_FORMULA of laws.def:
 * the executive adds none to it), 0 otherwise. Total. */
int aocs_law_has_feedforward(aocs_law_id_t law);

/* 1 for an ORBIT law of laws.def (input pos/vel, output force), 0 otherwise. Total. */
int aocs_law_is_orbit(aocs_law_id_t law);

/* Declared host budget of one step of the law, ns (BUDGET_NS of its laws.def row); AOCS_EXEC_SAFE_BUDGET_NS
 * for AOCS_LAW_NONE and out of range. Total. */
uint64_t aocs_law_budget_ns(aocs_law_id_t law);

/*
 * One config of each law (member CFG of every CFG_OWN row of laws.def); only
 * the one selected (at init or by select) must be valid. The variants of a
 * law share one config; the law id forces the variant (VARIANT column).
 */
#define AOCS_LAW_CFG_DECL_CFG_OWN(CFG_T, CFG) CFG_T CFG;
#define AOCS_LAW_CFG_DECL_CFG_SHARED(CFG_T, CFG)
#define AOCS_LAW_CONFIG_MEMBER(ID, NAME, INPUT, TITLE, STATE, STATE_T, CFG, CFG_T, CFG_USE, ...) \
    AOCS_LAW_CFG_DECL_##CFG_USE(CFG_T, CFG)
typedef struct {
    AOCS_LAW_ROWS(AOCS_LAW_CONFIG_MEMBER)
} aocs_exec_law_configs_t;

/* Law states (member STATE of every laws.def row), one of each so a rejected select leaves the active one untouched. */
#define AOCS_LAW_STATE_MEMBER(ID, NAME, INPUT, TITLE, STATE, STATE_T, ...) STATE_T STATE;
typedef struct {
    AOCS_LAW_ROWS(AOCS_LAW_STATE_MEMBER)
} aocs_exec_law_states_t;

/*
 * Direct dispatch to one law, without the executive's checks (law_table.c;
 * the executive, the bench and the tests use it).
 * aocs_exec_law_init initialises states->STATE of `law` from cfgs->CFG, the
 * variant forced by the law id: the law init's status, AOCS_ERR_UNKNOWN_LAW
 * for NONE / out of range, AOCS_ERR_NULL_ARG.
 * aocs_exec_law_step runs one step of `law` (att for attitude laws, orbit
 * for the orbit law; both must be given); *u is zeroed on any error.
 */
aocs_status_t aocs_exec_law_init(aocs_exec_law_states_t *states, const aocs_exec_law_configs_t *cfgs,
                                 aocs_law_id_t law);
aocs_status_t aocs_exec_law_step(aocs_exec_law_states_t *states, aocs_law_id_t law,
                                 const aocs_att_input_t *att, const aocs_orbit_input_t *orbit,
                                 aocs_vec3_t *u);

#endif /* AOCS_EXEC_LAW_DISPATCH_H */
