/*
 * hinf: H-infinity state feedback for the linearised Earth-pointing attitude
 * model (SPEC 2.6, Duan and Yu, LMIs in Control Systems).
 *
 *     u = +K x,   x = [phi theta psi phidot thetadot psidot]
 *
 * Sign: +K as in the reference (the LMI design returns a K whose useful
 * entries are negative), so init does not check signs.
 * Angles: 3-2-1 Euler angles of qe = q (x) qd^-1, i.e. of the body relative
 * to the target (orbital) frame, A(qe) = R1(phi) R2(theta) R3(psi):
 * roll phi about x, pitch theta about y, yaw psi about z.
 * Rates: we = w - wd is the body rate relative to the target frame in B;
 * the Euler-angle rates follow from the exact 3-2-1 kinematics
 *     phidot   = p + (q sin phi + r cos phi) tan theta
 *     thetadot = q cos phi - r sin phi
 *     psidot   = (q sin phi + r cos phi) / cos theta
 * with we = [p q r] (inverse of p = phidot - psidot sin theta,
 * q = thetadot cos phi + psidot sin phi cos theta,
 * r = -thetadot sin phi + psidot cos phi cos theta); for small angles the
 * Euler rates equal we. At the 3-2-1 singularity (theta = +-90 deg, far
 * outside the validity of the linear model) cos theta is bounded below by
 * AOCS_HINF_COS_PITCH_MIN so the output stays finite.
 */
#ifndef AOCS_CONTROL_HINF_H
#define AOCS_CONTROL_HINF_H

#include "aocs/control/law_io.h"

typedef struct {
    real_t k[3][6]; /* columns: phi theta psi (N m/rad), then their rates (N m s/rad) */
} aocs_hinf_config_t;

typedef struct {
    aocs_hinf_config_t cfg;
    int initialised;
} aocs_hinf_t;

/* Lower bound on cos(theta) in the Euler-rate conversion (gimbal lock guard). */
#define AOCS_HINF_COS_PITCH_MIN AOCS_R(1.0e-6)

/*
 * Validates and copies cfg: every entry finite (AOCS_ERR_PARAM_NOT_FINITE),
 * at least one nonzero entry (AOCS_ERR_GAIN_TABLE_INVALID).
 */
aocs_status_t aocs_hinf_init(aocs_hinf_t *law, const aocs_hinf_config_t *cfg);

/*
 * u_out = K x. Input checked by aocs_att_input_check; on any error
 * *u_out = 0 and the status is returned; a non-finite result gives
 * AOCS_ERR_OUTPUT_NOT_FINITE.
 */
aocs_status_t aocs_hinf_step(aocs_hinf_t *law, const aocs_att_input_t *in, aocs_vec3_t *u_out);

#endif /* AOCS_CONTROL_HINF_H */
