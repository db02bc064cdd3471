/*
 * Momentum policy MAGNETORQUERS (row of aocs/momentum/momentum.def;
 * docs/spec.md 5.9.2): the cross-product law
 *
 *     m_B = k (dh x B) / |B|^2,        torque  m_B x B = -k (dh - (dh . b) b) = -k dh_perp,  b = B / |B|
 *
 * (Markley & Crassidis 2014, sec. 7.5.3; Camillo & Markley 1980): the
 * dipole is perpendicular to B and its torque opposes the part of the wheel
 * momentum error dh = h_wheels - h_target perpendicular to the field (the
 * part along B cannot be removed at this instant). The rods' dipoles are
 * m_rod = (A^T)^-1 m_B (rows of A: the rod axes in B); when one exceeds its
 * limit the whole vector is scaled by the same factor, so the dipole keeps
 * its direction (still perpendicular to B). The expected torque
 * (A^T m_rod) x B_measured is fed forward to the wheels.
 */
#include <stddef.h>

#include "aocs/executive.h"

aocs_status_t aocs_mom_mtq_init(aocs_mom_t *m)
{
    aocs_status_t st = AOCS_OK;
    const aocs_mom_config_t *c = &m->cfg;
    const aocs_mat3_t at = aocs_mat3_transpose(c->mtq_axes);
    if (!(AOCS_IS_FINITE(c->k_mtq_per_s) && (c->k_mtq_per_s > AOCS_R(0.0))) ||
        (aocs_vec3_is_finite(c->mtq_max_dipole_Am2) == 0) || (aocs_mat3_is_finite(c->mtq_axes) == 0)) {
        st = AOCS_ERR_MOMENTUM_CONFIG_INVALID;
    } else {
        for (uint32_t i = 0u; i < 3u; ++i) {
            const aocs_vec3_t axis = {{c->mtq_axes.m[i][0], c->mtq_axes.m[i][1], c->mtq_axes.m[i][2]}};
            if (!(c->mtq_max_dipole_Am2.v[i] > AOCS_R(0.0)) ||
                (AOCS_FABS(aocs_vec3_norm(axis) - AOCS_R(1.0)) > AOCS_R(1.0e-3))) {
                st = AOCS_ERR_MOMENTUM_CONFIG_INVALID; /* a rod without a limit, or an axis not unit */
            }
        }
        if (st == AOCS_OK) {
            st = aocs_mat3_inverse(at, &m->mtq_inv);
            if (st != AOCS_OK) {
                st = AOCS_ERR_MOMENTUM_CONFIG_INVALID; /* rods not spanning the body */
            }
        }
    }
    return st;
}

aocs_status_t aocs_mom_mtq_step(aocs_mom_t *m, const aocs_mom_input_t *in)
{
    aocs_status_t st = AOCS_OK;
    aocs_mom_output_t *out = &m->out;
    const real_t b2 = aocs_vec3_norm_sq(in->b_B_T);
    if ((in->b_valid == 0) || (aocs_vec3_is_finite(in->b_B_T) == 0) || !(b2 > (AOCS_MOM_B_MIN_T * AOCS_MOM_B_MIN_T)) ||
        !AOCS_IS_FINITE(b2)) {
        st = AOCS_ERR_INPUT_MISSING; /* no usable field: no dipole */
    } else {
        /* dh x B / |B|^2 computed as (dh x b) / |B| with b the unit field: no overflow of |B|^2 */
        const real_t b_norm = AOCS_SQRT(b2);
        const aocs_vec3_t b_unit = aocs_vec3_scale(in->b_B_T, AOCS_R(1.0) / b_norm);
        const aocs_vec3_t m_cross =
            aocs_vec3_scale(aocs_vec3_cross(out->dh_B_Nms, b_unit), m->cfg.k_mtq_per_s / b_norm);
        /* projected onto the field's normal plane, m_B = m - (m . b) b: with dh nearly along B the cross
         * product is all rounding (of order eps |dh|), in no particular direction */
        const aocs_vec3_t m_B = aocs_vec3_sub(m_cross, aocs_vec3_scale(b_unit, aocs_vec3_dot(m_cross, b_unit)));
        aocs_vec3_t m_rod = aocs_mat3_mul_vec(m->mtq_inv, m_B);
        real_t scale = AOCS_R(1.0);
        for (uint32_t i = 0u; i < 3u; ++i) {
            const real_t a = AOCS_FABS(m_rod.v[i]);
            if ((a * scale) > m->cfg.mtq_max_dipole_Am2.v[i]) {
                scale = m->cfg.mtq_max_dipole_Am2.v[i] / a;
            }
        }
        m_rod = aocs_vec3_scale(m_rod, scale);
        if (aocs_vec3_is_finite(m_rod) == 0) {
            st = AOCS_ERR_INPUT_NOT_FINITE;
        } else {
            out->dipole_Am2 = m_rod;
            out->u_unload_B_Nm =
                aocs_vec3_cross(aocs_mat3_mul_vec(aocs_mat3_transpose(m->cfg.mtq_axes), m_rod), in->b_B_T);
        }
    }
    return st;
}
