/*
 * The executive's input (one sensor sample), output (the commands of one
 * step) and event counters (part of aocs/executive.h).
 */
#ifndef AOCS_EXEC_IO_H
#define AOCS_EXEC_IO_H

#include <stdint.h>

#include "aocs/types.h"
#include "aocs/math3.h"
#include "aocs/actuation/wheel_array.h"
#include "aocs/exec/law_dispatch.h"
#include "aocs/exec/modes.h"
#include "aocs/estimation/estimate.h"

/* Validity flags of aocs_exec_input_t.valid (set by the sensor adapter). */
#define AOCS_EXEC_VALID_ATT   (1u << 0) /* q_BN usable */
#define AOCS_EXEC_VALID_RATE  (1u << 1) /* w_BN_B usable */
#define AOCS_EXEC_VALID_ORBIT (1u << 2) /* pos_m, vel_mps usable */
#define AOCS_EXEC_VALID_ST    (1u << 3) /* st_q_SN is a new star-tracker sample, measured at st_t_meas_ns */
#define AOCS_EXEC_VALID_GYRO  (1u << 4) /* gyro_w_B usable */
#define AOCS_EXEC_VALID_MAG   (1u << 5) /* mag_B_T is a magnetometer reading */

/* Target held by the executive (attitude laws; the orbit law regulates to zero). */
typedef struct {
    aocs_quat_t qd_DN;      /* target attitude, unit */
    aocs_vec3_t wd_B;       /* target rate, rad/s */
    aocs_vec3_t wd_dot_B;   /* target angular acceleration, rad/s^2 */
} aocs_exec_target_t;

/* One sensor sample (lockstep: one per control period). */
typedef struct {
    uint32_t tick;                /* frame counter of the sample; gaps count as missing samples */
    uint64_t t_sensor_ns;         /* sensor time, ns; must advance. Real-time mode: HAL time base */
    uint32_t valid;               /* AOCS_EXEC_VALID_* flags */
    aocs_quat_t q_BN;             /* estimated attitude */
    aocs_vec3_t w_BN_B;           /* estimated body rate, rad/s */
    aocs_vec3_t pos_m;            /* orbit: position error [dx dy dz], m (SPEC 2.8) */
    aocs_vec3_t vel_mps;          /* orbit: velocity [du dv dw], m/s (SPEC 2.8) */
    real_t wheel_speed_radps[AOCS_WHEELS_MAX]; /* tachometers: wheel speeds relative to the body, rad/s
                                   * (read when a wheel array is configured) */
    aocs_quat_t st_q_SN;          /* star tracker: attitude of its frame S w.r.t. N, scalar last (A(q_SN) maps
                                   * N to S); a new sample when AOCS_EXEC_VALID_ST is set */
    uint64_t st_t_meas_ns;        /* its time of measurement, ns, the clock of t_sensor_ns, <= t_sensor_ns */
    aocs_vec3_t gyro_w_B;         /* gyro: measured body rate in B, rad/s, the mean over the sample period
                                   * (angle increment / period; AOCS_EXEC_VALID_GYRO) */
    aocs_vec3_t mag_B_T;          /* magnetometer: geomagnetic field in B, T (AOCS_EXEC_VALID_MAG) */
} aocs_exec_input_t;

/* Event counters (saturate at UINT32_MAX, never wrap). */
typedef struct {
    uint32_t steps;               /* step and step_no_input calls that produced an output */
    uint32_t invalid;             /* samples with NaN/Inf, non-unit q, or a needed validity flag off */
    uint32_t stale;               /* samples whose time did not advance or is older than the timeout */
    uint32_t missing;             /* missed samples (tick gaps and periods without a sample) */
    uint32_t law_error;           /* law step returned an error (e.g. CRP singular) */
    uint32_t overrun;             /* step time > budget */
    uint32_t mode_transitions;    /* every change of the actual mode */
    uint32_t saturated;           /* steps whose command was limited (or zeroed for NaN) */
    uint32_t select_accepted;
    uint32_t select_rejected;     /* unknown law, invalid target, invalid law config */
    uint64_t step_time_max_ns;    /* largest step time seen */
} aocs_exec_counters_t;

typedef struct {
    aocs_vec3_t u_cmd;            /* saturated command: torque N m (force N for orbit_lqr) */
    aocs_vec3_t u_unsat;          /* command before saturation (law or safe-mode output) */
    aocs_law_id_t law;            /* selected law */
    aocs_exec_mode_t mode;        /* actual mode of this step */
    aocs_status_t law_status;     /* status of the law step (AOCS_OK when not run) */
    aocs_status_t input_status;   /* AOCS_OK or why the sample was rejected (INPUT_*, QUAT_NOT_UNIT) */
    int saturated;                /* 1 when u_cmd != u_unsat */
    int overrun;                  /* 1 when step_time_ns > budget_ns */
    aocs_exec_target_t target;    /* target given to the law this step (rotating or slew: qd(t), wd_B,
                                   * wd_dot_B; wd_B and wd_dot_B only on a usable sample, else 0);
                                   * all zero from step_no_input (no law runs) */
    aocs_vec3_t u_ff;             /* slew feedforward added to the law's output this step (else 0), N m */
    uint64_t step_time_ns;        /* HAL time around guidance + law + saturation */
    uint32_t step_cycles;         /* aocs_hal_cycles() difference (0 where the platform has none) */
    uint64_t budget_ns;
    uint32_t tick;                /* tick of the sample (last tick for step_no_input) */
    aocs_exec_counters_t counters;
    aocs_wheels_alloc_t wheels;   /* wheel torque commands (all zero without an array) */
    aocs_wheels_momentum_t momentum; /* total momentum and speed margin (zero without an array) */
    aocs_status_t wheels_status;  /* AOCS_OK, or why the allocation gave a zero command */
    aocs_det_output_t estimate;   /* the attitude-determination stage's estimate and its telemetry this step */
    /* the momentum-management stage's output: aocs_exec_momentum() (exec/pipeline.h) */
} aocs_exec_output_t;

#endif /* AOCS_EXEC_IO_H */
