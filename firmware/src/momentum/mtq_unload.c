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

/* The field's normal-plane direction of dh x b, scaled so that no intermediate is subnormal: u = (dh /
 * |dh|_inf) x b has components of order sin(dh, B) and is projected onto B's normal plane, u - (u . b) b (with
 * dh nearly along B the cross product is rounding only, in no particular direction). Zero when dh and B are
 * parallel within AOCS_MOM_PARALLEL_SIN. *scale_out = |dh|_inf. */
static aocs_vec3_t mtq_normal_direction(aocs_vec3_t dh, aocs_vec3_t b_unit, real_t *scale_out)
{
    aocs_vec3_t u = aocs_vec3_zero();
    const real_t dh_max = aocs_vec3_norm_inf(dh);
    *scale_out = dh_max;
    if (dh_max > AOCS_R(0.0)) {
        const aocs_vec3_t cross = aocs_vec3_cross(aocs_vec3_scale(dh, AOCS_R(1.0) / dh_max), b_unit);
        u = aocs_vec3_sub(cross, aocs_vec3_scale(b_unit, aocs_vec3_dot(cross, b_unit)));
        if (aocs_vec3_norm_inf(u) < AOCS_MOM_PARALLEL_SIN) {
            u = aocs_vec3_zero();
        }
    }
    return u;
}

aocs_status_t aocs_mom_mtq_step(aocs_mom_t *m, const aocs_mom_input_t *in)
{
    aocs_status_t st = AOCS_OK;
    aocs_mom_output_t *out = &m->out;
    /* a field within [B_MIN, B_MAX]: its norm neither underflows nor overflows in either precision */
    real_t b_norm = AOCS_R(0.0);
    if ((in->b_valid != 0) && (aocs_vec3_is_finite(in->b_B_T) != 0) &&
        (aocs_vec3_norm_inf(in->b_B_T) <= AOCS_MOM_B_MAX_T)) {
        b_norm = aocs_vec3_norm(in->b_B_T);
    }
    if (!(b_norm > AOCS_MOM_B_MIN_T)) {
        st = AOCS_ERR_INPUT_MISSING; /* no usable field: no dipole */
    } else {
        /* m_B = k (dh x B) / |B|^2 = (k / |B|) |dh|_inf u, u of mtq_normal_direction */
        real_t dh_max = AOCS_R(0.0);
        const aocs_vec3_t u =
            mtq_normal_direction(out->dh_B_Nms, aocs_vec3_scale(in->b_B_T, AOCS_R(1.0) / b_norm), &dh_max);
        const aocs_vec3_t m_B = aocs_vec3_scale(u, (m->cfg.k_mtq_per_s / b_norm) * dh_max);
        aocs_vec3_t m_rod = aocs_mat3_mul_vec(m->mtq_inv, m_B);
        real_t scale = AOCS_R(1.0);
        for (uint32_t i = 0u; i < 3u; ++i) {
            const real_t a = AOCS_FABS(m_rod.v[i]);
            if ((a * scale) > m->cfg.mtq_max_dipole_Am2.v[i]) {
                scale = m->cfg.mtq_max_dipole_Am2.v[i] / a;
            }
        }
        m_rod = aocs_vec3_scale(m_rod, scale);
        if (aocs_vec3_norm_inf(m_rod) < AOCS_MOM_DIPOLE_MIN_AM2) {
            m_rod = aocs_vec3_zero(); /* below any rod's resolution */
        }
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
