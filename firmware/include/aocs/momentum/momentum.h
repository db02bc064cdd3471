/*
 * The momentum-management stage (ARCHITECTURE.md "The flight pipeline"):
 * after actuation, from the wheel array's momentum, the unloading commands
 * (magnetorquer dipole, thruster torque) and the body torque the wheels must
 * absorb meanwhile, by one of the policies of aocs/momentum/momentum.def.
 * Today the only policy is NONE (no unloading: its output is zero and the
 * executive applies nothing of it); the interface is here for the next ones.
 */
#ifndef AOCS_MOMENTUM_MOMENTUM_H
#define AOCS_MOMENTUM_MOMENTUM_H

#include <stdint.h>

#include "aocs/types.h"
#include "aocs/math3.h"
#include "aocs/actuation/wheel_array.h"
#include "aocs/momentum/momentum.def"

#define AOCS_MOM_ENUM_ROW(ID, ...) AOCS_MOM_##ID,
typedef enum {
    AOCS_MOMENTUM_ROWS(AOCS_MOM_ENUM_ROW)
    AOCS_MOM_COUNT
} aocs_mom_id_t;

/* Configuration of the stage (aocs_exec_config_t.momentum). */
typedef struct {
    uint32_t policy;              /* aocs_mom_id_t value; default 0 = NONE (no configuration key yet) */
} aocs_mom_config_t;

/* The commands of one step. */
typedef struct {
    aocs_vec3_t dipole_Am2;       /* magnetorquer dipole, A m^2 (zero: none) */
    aocs_vec3_t u_unload_B_Nm;    /* body torque the unloading actuators apply, N m (zero: none) */
} aocs_mom_output_t;

typedef struct {
    aocs_mom_id_t id;
    aocs_mom_output_t out;        /* the commands of the last step (zero from init; NONE leaves them zero) */
    int initialised;
} aocs_mom_t;

/* Name of a policy ("none"); "unknown" out of range. Total. */
const char *aocs_mom_name(aocs_mom_id_t id);

/* AOCS_ERR_NULL_ARG; AOCS_ERR_MOMENTUM_POLICY_UNKNOWN (policy out of range). */
aocs_status_t aocs_mom_init(aocs_mom_t *m, const aocs_mom_config_t *cfg);

/*
 * One step on the array's momentum h (NULL without an array): the policy
 * updates m->out (aocs_mom_output). AOCS_ERR_NULL_ARG, AOCS_ERR_NOT_INITIALISED,
 * or the policy's status (on an error m->out is zero).
 */
aocs_status_t aocs_mom_step(aocs_mom_t *m, const aocs_wheels_momentum_t *h);

/* The commands of the last step; zero for NULL or a stage not initialised. Total. */
aocs_mom_output_t aocs_mom_output(const aocs_mom_t *m);

/* ---- the rows' functions (momentum.def), declared from the rows ---- */
#define AOCS_MOM_PROTOTYPES(ID, NAME, STEP) aocs_status_t STEP(aocs_mom_t *m, const aocs_wheels_momentum_t *h);
AOCS_MOMENTUM_ROWS(AOCS_MOM_PROTOTYPES)

#endif /* AOCS_MOMENTUM_MOMENTUM_H */
