/*
 * The momentum-management stage (ARCHITECTURE.md "The flight pipeline";
 * docs/spec.md 5.9): from the wheel array's momentum, the unloading commands
 * (magnetorquer dipoles, thruster on-times) and the body torque they are
 * expected to apply, which the executive feeds forward into the wheel
 * command so the wheels absorb it and the body sees none (the law's torque
 * minus the unloading torque is what the wheels deliver).
 *
 * Policies (rows of aocs/momentum/momentum.def, configuration key mom.policy):
 *   none           no unloading (zero output)
 *   magnetorquers  the cross-product law m = k (dh x B) / |B|^2 (the torque m x B = -k dh_perp removes the
 *                  part of dh perpendicular to B), saturated per rod keeping its direction
 *                  (Markley & Crassidis 2014 sec. 7.5; Camillo & Markley 1980)
 *   thrusters      a dumping torque of magnitude dump_torque_nm opposing dh (at most |dh| per period),
 *                  allocated to non-negative on-times by pulse-width modulation over the control period:
 *                  per signed body axis the least-propellant thruster combination giving a unit torque
 *                  (chosen at init), quantised to thr_quantum_s, pulses below thr_min_on_s dropped; the
 *                  on-time not fired is carried to the next period (so a torque below the minimum impulse
 *                  bit per period is still delivered on average)
 * Trigger (mom.trigger): threshold (start when |dh| > h_start_nms, stop when |dh| < h_stop_nms:
 * hysteresis) or continuous (always, while the stage is enabled). dh = h_wheels - h_target.
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

/* Largest number of thrusters (the configuration rows mom.thr_arm_*_m hold this many values). */
#define AOCS_MOM_THRUSTERS_MAX 12u
/* Signed body axes of the thruster allocation: +x, -x, +y, -y, +z, -z. */
#define AOCS_MOM_AXES_SIGNED 6u
/* Smallest field magnitude the magnetorquer law divides by, T (the geomagnetic field is >= 2e-5 T in LEO
 * and ~1e-8 T at L2; below 1e-12 T a magnetometer reads noise only). */
#define AOCS_MOM_B_MIN_T AOCS_R(1.0e-12)
/* Largest field magnitude taken as a geomagnetic field, T: 1 mT, fifteen times the strongest field at the
 * Earth's surface (~6.7e-5 T); a magnetometer reading beyond it is no field to unload in. */
#define AOCS_MOM_B_MAX_T AOCS_R(1.0e-3)
/* Smallest sine of the angle between the momentum error and the field the magnetorquer law acts on: below
 * it the part of dh perpendicular to B is under a millionth of |dh| (nothing to unload) and the cross
 * product's direction is rounding (float's eps is 6e-8). */
#define AOCS_MOM_PARALLEL_SIN AOCS_R(1.0e-6)
/* Smallest rod dipole commanded, A m^2: below any rod's resolution (a 1 A m^2 rod on a 16-bit driver steps
 * by 3e-5 A m^2); a smaller dipole is commanded as zero, never as a subnormal number of no direction. */
#define AOCS_MOM_DIPOLE_MIN_AM2 AOCS_R(1.0e-12)

/* The trigger (mom.trigger): the values of aocs_mom_config_t.trigger. */
#define AOCS_MOM_TRIGGER_THRESHOLD 0u  /* hysteresis: start above h_start, stop below h_stop */
#define AOCS_MOM_TRIGGER_CONTINUOUS 1u /* always unloading while enabled */
#define AOCS_MOM_TRIGGER_COUNT 2u

/* Configuration of the stage (aocs_exec_config_t.momentum; the mom.* rows of config_fields.def). */
typedef struct {
    uint32_t policy;                 /* aocs_mom_id_t value; default 0 = NONE */
    uint32_t trigger;                /* AOCS_MOM_TRIGGER_THRESHOLD or _CONTINUOUS */
    aocs_vec3_t h_target_B_Nms;      /* wheel momentum target (zero or a bias), B, N m s */
    real_t h_start_Nms;              /* threshold: start when |dh| > this, N m s */
    real_t h_stop_Nms;               /* threshold: stop when |dh| < this (< h_start), N m s */
    real_t k_mtq_per_s;              /* magnetorquers: gain k, 1/s */
    aocs_mat3_t mtq_axes;            /* magnetorquers: row i = unit axis of rod i in B */
    aocs_vec3_t mtq_max_dipole_Am2;  /* magnetorquers: per-rod dipole limit, A m^2 */
    real_t dump_torque_Nm;           /* thrusters: dumping torque magnitude, N m */
    uint32_t thr_count;              /* thrusters: number, <= AOCS_MOM_THRUSTERS_MAX */
    real_t thr_thrust_N;             /* thrusters: thrust of each, N */
    real_t thr_min_on_s;             /* thrusters: shortest pulse, s (minimum impulse bit / thrust) */
    real_t thr_quantum_s;            /* thrusters: on-time quantum, s (0 = none) */
    real_t thr_arm_x_m[AOCS_MOM_THRUSTERS_MAX]; /* thrusters: x of r_i x d_i (torque per newton), m */
    real_t thr_arm_y_m[AOCS_MOM_THRUSTERS_MAX]; /* y of r_i x d_i, m */
    real_t thr_arm_z_m[AOCS_MOM_THRUSTERS_MAX]; /* z of r_i x d_i, m */
    uint32_t thr_latch_b_mask;       /* thrusters: bit i set: thruster i fed through latch valve B, else A */
} aocs_mom_config_t;

/* One step's input (the executive forms it before actuation). */
typedef struct {
    aocs_vec3_t h_wheels_B_Nms;      /* sum Js_i g_i Omega_i from the tachometers, B */
    int h_valid;                     /* 1: a wheel array with every healthy speed finite */
    aocs_vec3_t b_B_T;               /* magnetometer field in B, T */
    int b_valid;                     /* 1: the magnetometer reading is usable (flag set, finite) */
    int enabled;                     /* 1: the attitude is held (NOMINAL with an attitude law) */
    real_t dt_s;                     /* control period, s */
} aocs_mom_input_t;

/* The commands and telemetry of one step. */
typedef struct {
    aocs_vec3_t dipole_Am2;          /* magnetorquer dipole of each rod (along its axis), A m^2 */
    real_t thruster_on_s[AOCS_MOM_THRUSTERS_MAX]; /* thruster on-times within this period, s */
    aocs_vec3_t u_unload_B_Nm;       /* body torque the unloading actuators are expected to apply, N m */
    aocs_vec3_t h_wheels_B_Nms;      /* the momentum the stage used (zero when not valid) */
    aocs_vec3_t dh_B_Nms;            /* h_wheels - h_target */
    int unloading;                   /* 1: an unload in progress this step */
    uint32_t n_events;               /* unloads started (transitions to unloading), saturating */
    uint32_t latch_closed_mask;      /* thrusters: bit b set: the latch valve of branch b closed (0 A, 1 B);
                                      * held from step to step (aocs_mom_latch_set) */
    aocs_status_t status;            /* AOCS_OK, or why nothing was commanded (no field, no wheels) */
} aocs_mom_output_t;

typedef struct {
    aocs_mom_id_t id;
    aocs_mom_config_t cfg;
    aocs_mat3_t mtq_inv;             /* maps a B-frame dipole to the rods' dipoles: (axes^T)^-1 */
    real_t thr_alloc[AOCS_MOM_AXES_SIGNED][AOCS_MOM_THRUSTERS_MAX]; /* duty per N m about each signed axis */
    real_t thr_alloc_full[AOCS_MOM_AXES_SIGNED][AOCS_MOM_THRUSTERS_MAX]; /* the same over every thruster (init):
                                      * what an exclusion or a latch valve starts from */
    real_t thr_residual_s[AOCS_MOM_THRUSTERS_MAX]; /* on-time requested but not fired (quantum, minimum
                                      * pulse), carried to the next period while an unload lasts */
    uint32_t thr_excluded_mask;      /* bit i: thruster i taken out of the allocation (aocs_mom_thr_exclude) */
    aocs_mom_output_t out;           /* the commands of the last step (zero from init) */
    int initialised;
} aocs_mom_t;

/* Name of a policy ("none"); "unknown" out of range. Total. */
const char *aocs_mom_name(aocs_mom_id_t id);

/*
 * AOCS_ERR_NULL_ARG; AOCS_ERR_MOMENTUM_POLICY_UNKNOWN (policy out of range);
 * AOCS_ERR_MOMENTUM_CONFIG_INVALID (trigger out of range, a value not finite or negative, h_stop >= h_start
 * with the threshold trigger, the policy's own parameters: see momentum.def); the policy's INIT status.
 */
aocs_status_t aocs_mom_init(aocs_mom_t *m, const aocs_mom_config_t *cfg);

/*
 * One step: the trigger, then the policy updates m->out. AOCS_ERR_NULL_ARG, AOCS_ERR_NOT_INITIALISED, or the
 * policy's status (also in m->out.status; on an error the commands are zero). A step not enabled or without a
 * valid momentum stops an unload in progress and commands nothing.
 */
aocs_status_t aocs_mom_step(aocs_mom_t *m, const aocs_mom_input_t *in);

/* The commands of the last step; zero for NULL or a stage not initialised. Total. */
aocs_mom_output_t aocs_mom_output(const aocs_mom_t *m);

/* Host budget the policy adds to every step, ns (momentum.def BUDGET_NS); 0 for NULL. Total. */
uint64_t aocs_mom_budget_ns(const aocs_mom_t *m);

/* Torque of thruster i at full thrust in B, N m (F (r_i x d_i)); zero for NULL, a policy other than thrusters or
 * i out of range. Total. */
aocs_vec3_t aocs_mom_thr_torque_B(const aocs_mom_t *m, uint32_t i);

/*
 * Takes thruster i out of the thruster allocation (fault management, docs/spec.md 5.15.8): the least-propellant
 * duty of every signed axis is sought again among the thrusters left. AOCS_OK (the allocation and the mask
 * replaced, the thruster's carried on-time dropped); AOCS_ERR_NULL_ARG, AOCS_ERR_NOT_INITIALISED;
 * AOCS_ERR_MOMENTUM_CONFIG_INVALID (not the thrusters policy, i out of range or already out);
 * AOCS_ERR_MOMENTUM_THRUSTERS_NOT_SPANNING (the thrusters left cannot torque some signed axis): m unchanged.
 */
aocs_status_t aocs_mom_thr_exclude(aocs_mom_t *m, uint32_t i);

/* Latch-valve branches (docs/spec.md 5.15.8): two, A (0) and B (1); mom.thr_latch_b_mask gives each thruster's. */
#define AOCS_MOM_LATCH_BRANCHES 2u

/* Thruster i itself when it is on branch b (0 A, 1 B) and not excluded, else the first such thruster with i's
 * torque (to 1e-6 of it: its twin, the rule by which an exclusion moves a duty); AOCS_MOM_THRUSTERS_MAX when
 * none, for NULL, another policy or i out of range. Total. */
uint32_t aocs_mom_thr_like_on_branch(const aocs_mom_t *m, uint32_t b, uint32_t i);

/* The branch of thruster i (0 A, 1 B; 0 for NULL or i out of range). Total. */
uint32_t aocs_mom_thr_branch(const aocs_mom_t *m, uint32_t i);

/*
 * Closes (closed = 1) or opens (0) the latch valve of branch b: the thrusters on a closed branch are out of the
 * allocation as an excluded one is (the least-propellant duties of the thrusters left, by their twins when
 * they have them), this step's on-times of a newly closed branch are zeroed (the unloading torque this step
 * fed forward to the wheels stays as computed: at most one period of the dump torque), and
 * out.latch_closed_mask holds the valves' state on the wire. AOCS_OK; AOCS_ERR_NULL_ARG, AOCS_ERR_NOT_INITIALISED;
 * AOCS_ERR_MOMENTUM_CONFIG_INVALID (not the thrusters policy, b not a branch);
 * AOCS_ERR_MOMENTUM_THRUSTERS_NOT_SPANNING (the thrusters left cannot torque some signed axis): m unchanged.
 */
aocs_status_t aocs_mom_latch_set(aocs_mom_t *m, uint32_t b, int closed);

/* The hysteresis trigger alone: the next "unloading" state from the current one and |dh|. Total. */
int aocs_mom_trigger(const aocs_mom_config_t *cfg, int unloading, real_t dh_norm_Nms);

/* ---- the rows' functions (momentum.def), declared from the rows ---- */
#define AOCS_MOM_PROTOTYPES(ID, NAME, INIT, STEP, BUDGET_NS, INSTR_M4F, INSTR_M7) \
    aocs_status_t INIT(aocs_mom_t *m);                                             \
    aocs_status_t STEP(aocs_mom_t *m, const aocs_mom_input_t *in);
AOCS_MOMENTUM_ROWS(AOCS_MOM_PROTOTYPES)

#endif /* AOCS_MOMENTUM_MOMENTUM_H */
