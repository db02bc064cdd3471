/*
 * orbit_lqr: LQR station keeping relative to a reference point on a circular
 * orbit (SPEC 2.8, Bryson 1994, Clohessy-Wiltshire in Bryson's form).
 *
 * State x = [du dv dw dx dy dz] (inertial velocity resolved in the rotating
 * frame first, then position error; x along-track, y cross-track, z nadir).
 *     F = -K x   (N),   K = R^-1 B^T S from the continuous ARE.
 * K comes from the generated gain tables; the config only carries it.
 */
#ifndef AOCS_CONTROL_ORBIT_LQR_H
#define AOCS_CONTROL_ORBIT_LQR_H

#include "aocs/control/law_io.h"

typedef struct {
    real_t k[3][6]; /* columns: du dv dw (N s/m), then dx dy dz (N/m) */
} aocs_orbit_lqr_config_t;

typedef struct {
    aocs_orbit_lqr_config_t cfg;
    int initialised;
} aocs_orbit_lqr_t;

/*
 * Validates and copies cfg: every entry finite (AOCS_ERR_PARAM_NOT_FINITE);
 * the diagonal of the velocity block k[i][i] strictly positive, the damping
 * every stabilising LQR gain of this model has (AOCS_ERR_GAIN_TABLE_INVALID).
 */
aocs_status_t aocs_orbit_lqr_init(aocs_orbit_lqr_t *law, const aocs_orbit_lqr_config_t *cfg);

/*
 * f_out = -K x. Input checked by aocs_orbit_input_check; on any error
 * *f_out = 0 and the status is returned; a non-finite result (inputs near
 * REAL_MAX) gives AOCS_ERR_OUTPUT_NOT_FINITE.
 */
aocs_status_t aocs_orbit_lqr_step(aocs_orbit_lqr_t *law, const aocs_orbit_input_t *in, aocs_vec3_t *f_out);

#endif /* AOCS_CONTROL_ORBIT_LQR_H */
