/*
 * Momentum policy THRUSTERS (row of aocs/momentum/momentum.def; docs/spec.md
 * 5.9.3): a dumping torque opposing the wheel momentum error dh,
 *
 *     tau_d = -(dh / |dh|) min(dump_torque_nm, |dh| / dt)      (never more than dh in one period),
 *
 * allocated to thruster on-times by pulse-width modulation over the control
 * period. Thruster i at full thrust F applies the torque t_i = F (r_i x d_i)
 * (the rows mom.thr_arm_*_m hold r_i x d_i). At init, for each signed body
 * axis s e_k the least-propellant non-negative duty vector c with
 * sum_i c_i t_i = s e_k (per N m) is found among the basic solutions of that
 * linear programme: every invertible triple of thruster torques (the torque
 * mapping of Basilisk's thrForceMapping, non-negative by construction). A step's duties are
 * f = sum_k |tau_k| c_(sign tau_k, k), scaled down together when one exceeds 1
 * (the direction of tau kept), on-times t_i = f_i dt quantised to
 * thr_quantum_s and dropped below thr_min_on_s (the minimum impulse bit); what
 * was requested and not fired is added to the next period's request while
 * the unload lasts (error feedback: over many periods the impulse delivered
 * follows the impulse requested to within one minimum pulse per thruster).
 * The torque of the quantised on-times, sum_i (t_i / dt) t_i, is fed forward
 * to the wheels.
 */
#include <stddef.h>
#include <string.h>

#include "aocs/executive.h"

/* Torque of thruster i at full thrust, N m. */
static aocs_vec3_t thr_torque(const aocs_mom_config_t *c, uint32_t i)
{
    const aocs_vec3_t arm = {{c->thr_arm_x_m[i], c->thr_arm_y_m[i], c->thr_arm_z_m[i]}};
    return aocs_vec3_scale(arm, c->thr_thrust_N);
}

static uint32_t thr_bit(uint32_t i)
{
    return (uint32_t)1u << i;
}

/* The thrusters of the configuration, as bits. */
static uint32_t thr_all_bits(const aocs_mom_config_t *c)
{
    return (c->thr_count >= 32u) ? UINT32_MAX : (thr_bit(c->thr_count) - 1u);
}

static aocs_status_t thr_check(const aocs_mom_config_t *c)
{
    aocs_status_t st = AOCS_OK;
    if ((c->thr_count < 3u) || (c->thr_count > AOCS_MOM_THRUSTERS_MAX) ||
        ((c->thr_latch_b_mask & ~thr_all_bits(c)) != 0u) ||
        !(AOCS_IS_FINITE(c->thr_thrust_N) && (c->thr_thrust_N > AOCS_R(0.0))) ||
        !(AOCS_IS_FINITE(c->dump_torque_Nm) && (c->dump_torque_Nm > AOCS_R(0.0))) ||
        !(AOCS_IS_FINITE(c->thr_min_on_s) && (c->thr_min_on_s >= AOCS_R(0.0))) ||
        !(AOCS_IS_FINITE(c->thr_quantum_s) && (c->thr_quantum_s >= AOCS_R(0.0)))) {
        st = AOCS_ERR_MOMENTUM_CONFIG_INVALID;
    } else {
        for (uint32_t i = 0u; i < c->thr_count; ++i) {
            if (aocs_vec3_is_finite(thr_torque(c, i)) == 0) {
                st = AOCS_ERR_MOMENTUM_CONFIG_INVALID;
            }
        }
    }
    return st;
}

/* The triple (i, j, l) for the unit torque e (columns ti tj tl; Cramer's rule): when it is invertible, its
 * duties are non-negative and cheaper than *best, they replace duty and *best; 1 then. */
static int thr_triple(const aocs_mom_config_t *c, aocs_vec3_t e, real_t tmax, const uint32_t ijl[3], real_t *best,
                      real_t *duty)
{
    const real_t det_min = AOCS_R(1.0e-6) * tmax * tmax * tmax;
    const aocs_vec3_t ti = thr_torque(c, ijl[0]);
    const aocs_vec3_t tj = thr_torque(c, ijl[1]);
    const aocs_vec3_t tl = thr_torque(c, ijl[2]);
    const real_t det = aocs_vec3_dot(ti, aocs_vec3_cross(tj, tl));
    int taken = 0;
    if (AOCS_FABS(det) > det_min) {
        const real_t ci = aocs_vec3_dot(e, aocs_vec3_cross(tj, tl)) / det;
        const real_t cj = aocs_vec3_dot(ti, aocs_vec3_cross(e, tl)) / det;
        const real_t cl = aocs_vec3_dot(ti, aocs_vec3_cross(tj, e)) / det;
        const real_t tol = AOCS_R(-1.0e-6) / tmax;
        const real_t cost = ci + cj + cl;
        if ((ci >= tol) && (cj >= tol) && (cl >= tol) && (cost < *best)) {
            *best = cost;
            for (uint32_t k = 0u; k < AOCS_MOM_THRUSTERS_MAX; ++k) {
                duty[k] = AOCS_R(0.0);
            }
            duty[ijl[0]] = (ci > AOCS_R(0.0)) ? ci : AOCS_R(0.0);
            duty[ijl[1]] = (cj > AOCS_R(0.0)) ? cj : AOCS_R(0.0);
            duty[ijl[2]] = (cl > AOCS_R(0.0)) ? cl : AOCS_R(0.0);
            taken = 1;
        }
    }
    return taken;
}

/* The cheapest duty vector giving the unit torque e among the invertible triples of thrusters not in
 * `excluded`; 1 when one exists. */
static int thr_axis_alloc(const aocs_mom_config_t *c, uint32_t excluded, aocs_vec3_t e, real_t tmax, real_t *duty)
{
    const uint32_t n = c->thr_count;
    real_t best = AOCS_REAL_MAX;
    int found = 0;
    for (uint32_t i = 0u; i < n; ++i) {
        for (uint32_t j = i + 1u; j < n; ++j) {
            for (uint32_t l = j + 1u; l < n; ++l) {
                const uint32_t ijl[3] = {i, j, l};
                if (((excluded & (thr_bit(i) | thr_bit(j) | thr_bit(l))) == 0u) &&
                    (thr_triple(c, e, tmax, ijl, &best, duty) != 0)) {
                    found = 1;
                }
            }
        }
    }
    return found;
}

/* The duty vectors of the six signed axes over the thrusters not in `excluded`, into alloc; AOCS_OK or
 * AOCS_ERR_MOMENTUM_THRUSTERS_NOT_SPANNING (alloc then partly written). */
static aocs_status_t thr_alloc_all(const aocs_mom_config_t *c, uint32_t excluded,
                                   real_t alloc[AOCS_MOM_AXES_SIGNED][AOCS_MOM_THRUSTERS_MAX])
{
    aocs_status_t st = AOCS_OK;
    real_t tmax = AOCS_R(0.0);
    for (uint32_t i = 0u; i < c->thr_count; ++i) {
        const real_t t = aocs_vec3_norm(thr_torque(c, i));
        tmax = (t > tmax) ? t : tmax;
    }
    if (!(tmax > AOCS_R(0.0))) {
        st = AOCS_ERR_MOMENTUM_CONFIG_INVALID;
    }
    for (uint32_t s = 0u; (st == AOCS_OK) && (s < AOCS_MOM_AXES_SIGNED); ++s) {
        aocs_vec3_t e = aocs_vec3_zero();
        e.v[s / 2u] = ((s % 2u) == 0u) ? AOCS_R(1.0) : AOCS_R(-1.0);
        if (thr_axis_alloc(c, excluded, e, tmax, alloc[s]) == 0) {
            st = AOCS_ERR_MOMENTUM_THRUSTERS_NOT_SPANNING;
        }
    }
    return st;
}

aocs_status_t aocs_mom_thr_init(aocs_mom_t *m)
{
    aocs_status_t st = thr_check(&m->cfg);
    if (st == AOCS_OK) {
        m->thr_excluded_mask = 0u;
        m->out.latch_closed_mask = 0u;
        st = thr_alloc_all(&m->cfg, 0u, m->thr_alloc_full);
        (void)memcpy(m->thr_alloc, m->thr_alloc_full, sizeof(m->thr_alloc));
    }
    return st;
}

aocs_vec3_t aocs_mom_thr_torque_B(const aocs_mom_t *m, uint32_t i)
{
    aocs_vec3_t t = aocs_vec3_zero();
    if ((m != NULL) && (m->initialised != 0) && (m->id == AOCS_MOM_THRUSTERS) && (i < m->cfg.thr_count)) {
        t = thr_torque(&m->cfg, i);
    }
    return t;
}

/* The rule of a couple's twins: torque tj is ti to 1e-6 of |ti|, compared squared (no root) against
 * tol2 = thr_twin_tol2(ti), computed once per ti. */
static real_t thr_twin_tol2(aocs_vec3_t ti)
{
    return AOCS_R(1.0e-12) * aocs_vec3_dot(ti, ti);
}

static int thr_torques_equal(aocs_vec3_t ti, aocs_vec3_t tj, real_t tol2)
{
    const aocs_vec3_t d = aocs_vec3_sub(tj, ti);
    return (aocs_vec3_dot(d, d) <= tol2) ? 1 : 0;
}

uint32_t aocs_mom_thr_like_on_branch(const aocs_mom_t *m, uint32_t b, uint32_t i)
{
    uint32_t found = AOCS_MOM_THRUSTERS_MAX;
    if ((m != NULL) && (m->initialised != 0) && (m->id == AOCS_MOM_THRUSTERS) && (i < m->cfg.thr_count)) {
        const aocs_mom_config_t *c = &m->cfg;
        const uint32_t on_b = (b == 1u) ? c->thr_latch_b_mask : (thr_all_bits(c) & ~c->thr_latch_b_mask);
        const uint32_t open = on_b & ~m->thr_excluded_mask;
        const aocs_vec3_t ti = thr_torque(c, i);
        const real_t tol2 = thr_twin_tol2(ti);
        if ((open & thr_bit(i)) != 0u) {
            found = i;
        }
        for (uint32_t j = 0u; (j < c->thr_count) && (found == AOCS_MOM_THRUSTERS_MAX); ++j) {
            if (((open & thr_bit(j)) != 0u) && (thr_torques_equal(ti, thr_torque(c, j), tol2) != 0)) {
                found = j;
            }
        }
    }
    return found;
}

/* A thruster not in `excluded`, other than i, whose torque is i's: its redundant twin; the thruster count when
 * there is none. */
static uint32_t thr_twin(const aocs_mom_config_t *c, uint32_t excluded, uint32_t i)
{
    const aocs_vec3_t ti = thr_torque(c, i);
    const real_t tol2 = thr_twin_tol2(ti);
    uint32_t twin = c->thr_count;
    for (uint32_t j = 0u; (j < c->thr_count) && (twin == c->thr_count); ++j) {
        if ((j != i) && ((excluded & thr_bit(j)) == 0u) && (thr_torques_equal(ti, thr_torque(c, j), tol2) != 0)) {
            twin = j;
        }
    }
    return twin;
}

/* The thrusters on the closed branches of latch_closed (bit b: branch b), as bits. */
static uint32_t thr_latched_bits(const aocs_mom_config_t *c, uint32_t latch_closed)
{
    uint32_t bits = 0u;
    if ((latch_closed & 1u) != 0u) {
        bits |= thr_all_bits(c) & ~c->thr_latch_b_mask;
    }
    if ((latch_closed & 2u) != 0u) {
        bits |= c->thr_latch_b_mask;
    }
    return bits;
}

/*
 * The allocation without the thrusters of mask, into trial, from the one over every thruster (init): where a
 * signed axis's duties use a thruster of mask and a twin with the same torque is left, its duty moves to the
 * twin (the same torque at the same propellant, so still the least-propellant basic solution: a few hundred
 * instructions); otherwise every axis is sought again over the thrusters left (thr_alloc_all: more than
 * 22,500 instructions on the Cortex-M4F, an overrun of that step's budget, docs/spec.md 5.15.8).
 */
static aocs_status_t thr_alloc_without(const aocs_mom_t *m, uint32_t mask,
                                       real_t trial[AOCS_MOM_AXES_SIGNED][AOCS_MOM_THRUSTERS_MAX])
{
    aocs_status_t st = AOCS_OK;
    int search = 0;
    (void)memcpy(trial, m->thr_alloc_full, sizeof(m->thr_alloc_full));
    for (uint32_t i = 0u; i < m->cfg.thr_count; ++i) {
        if ((mask & thr_bit(i)) != 0u) {
            uint32_t twin = AOCS_MOM_THRUSTERS_MAX + 1u; /* sought when a duty needs it */
            for (uint32_t s = 0u; s < AOCS_MOM_AXES_SIGNED; ++s) {
                if (trial[s][i] > AOCS_R(0.0)) {
                    twin = (twin > AOCS_MOM_THRUSTERS_MAX) ? thr_twin(&m->cfg, mask, i) : twin;
                    if (twin < m->cfg.thr_count) {
                        trial[s][twin] += trial[s][i];
                    } else {
                        search = 1;
                    }
                    trial[s][i] = AOCS_R(0.0);
                }
            }
        }
    }
    if (search != 0) {
        st = thr_alloc_all(&m->cfg, mask, trial);
    }
    return st;
}

/* The allocation for an excluded set and the latch valves' state; m unchanged unless AOCS_OK. */
static aocs_status_t thr_reallocate(aocs_mom_t *m, uint32_t excluded, uint32_t latch_closed)
{
    real_t trial[AOCS_MOM_AXES_SIGNED][AOCS_MOM_THRUSTERS_MAX];
    const uint32_t mask = excluded | thr_latched_bits(&m->cfg, latch_closed);
    const aocs_status_t st = thr_alloc_without(m, mask, trial);
    if (st == AOCS_OK) {
        (void)memcpy(m->thr_alloc, trial, sizeof(trial));
        m->thr_excluded_mask = excluded;
        m->out.latch_closed_mask = latch_closed;
        for (uint32_t i = 0u; i < m->cfg.thr_count; ++i) {
            if ((mask & thr_bit(i)) != 0u) {
                m->thr_residual_s[i] = AOCS_R(0.0); /* nothing owed by a thruster that no longer fires */
            }
        }
    }
    return st;
}

uint32_t aocs_mom_thr_branch(const aocs_mom_t *m, uint32_t i)
{
    uint32_t b = 0u;
    if ((m != NULL) && (i < AOCS_MOM_THRUSTERS_MAX) && ((m->cfg.thr_latch_b_mask & thr_bit(i)) != 0u)) {
        b = 1u;
    }
    return b;
}

aocs_status_t aocs_mom_latch_set(aocs_mom_t *m, uint32_t b, int closed)
{
    aocs_status_t st = AOCS_OK;
    if (m == NULL) {
        st = AOCS_ERR_NULL_ARG;
    } else if (m->initialised == 0) {
        st = AOCS_ERR_NOT_INITIALISED;
    } else if ((m->id != AOCS_MOM_THRUSTERS) || (b >= AOCS_MOM_LATCH_BRANCHES)) {
        st = AOCS_ERR_MOMENTUM_CONFIG_INVALID;
    } else {
        const uint32_t was = m->out.latch_closed_mask;
        const uint32_t now = (closed != 0) ? (was | thr_bit(b)) : (was & ~thr_bit(b));
        st = thr_reallocate(m, m->thr_excluded_mask, now);
        if (st == AOCS_OK) {
            const uint32_t shut = thr_latched_bits(&m->cfg, now & ~was);
            for (uint32_t i = 0u; i < m->cfg.thr_count; ++i) {
                if ((shut & thr_bit(i)) != 0u) {
                    m->out.thruster_on_s[i] = AOCS_R(0.0); /* the valve stops this period's pulse too */
                }
            }
        }
    }
    return st;
}

aocs_status_t aocs_mom_thr_exclude(aocs_mom_t *m, uint32_t i)
{
    aocs_status_t st = AOCS_OK;
    if (m == NULL) {
        st = AOCS_ERR_NULL_ARG;
    } else if (m->initialised == 0) {
        st = AOCS_ERR_NOT_INITIALISED;
    } else if ((m->id != AOCS_MOM_THRUSTERS) || (i >= m->cfg.thr_count) ||
               ((m->thr_excluded_mask & thr_bit(i)) != 0u)) {
        st = AOCS_ERR_MOMENTUM_CONFIG_INVALID;
    } else {
        st = thr_reallocate(m, m->thr_excluded_mask | thr_bit(i), m->out.latch_closed_mask);
    }
    return st;
}

/* On-time of a requested on-time t over dt: quantised to q (0 = none), below t_min dropped, within [0, dt]. */
static real_t thr_on_time(real_t t_req, real_t dt, real_t q, real_t t_min)
{
    real_t t = t_req;
    if ((q > AOCS_R(0.0)) && ((t / q) < AOCS_R(4.0e9))) {
        const uint32_t k = (uint32_t)((t / q) + AOCS_R(0.5));
        t = (real_t)k * q;
    }
    if (t > dt) {
        t = dt;
    }
    if ((t < t_min) || !(t > AOCS_R(0.0))) {
        t = AOCS_R(0.0);
    }
    return t;
}

aocs_status_t aocs_mom_thr_step(aocs_mom_t *m, const aocs_mom_input_t *in)
{
    aocs_status_t st = AOCS_OK;
    aocs_mom_output_t *out = &m->out;
    const aocs_mom_config_t *c = &m->cfg;
    const real_t dh_norm = aocs_vec3_norm(out->dh_B_Nms);
    if (!AOCS_IS_FINITE(dh_norm)) {
        st = AOCS_ERR_INPUT_NOT_FINITE;
    } else if (dh_norm > AOCS_R(0.0)) {
        const real_t dt = in->dt_s;
        const real_t mag = (c->dump_torque_Nm < (dh_norm / dt)) ? c->dump_torque_Nm : (dh_norm / dt);
        const aocs_vec3_t tau = aocs_vec3_scale(out->dh_B_Nms, -mag / dh_norm);
        real_t duty[AOCS_MOM_THRUSTERS_MAX];
        real_t fmax = AOCS_R(0.0);
        aocs_vec3_t u = aocs_vec3_zero();
        for (uint32_t i = 0u; i < AOCS_MOM_THRUSTERS_MAX; ++i) {
            duty[i] = AOCS_R(0.0);
        }
        for (uint32_t k = 0u; k < 3u; ++k) {
            const uint32_t s = (2u * k) + ((tau.v[k] < AOCS_R(0.0)) ? 1u : 0u);
            const real_t a = AOCS_FABS(tau.v[k]);
            for (uint32_t i = 0u; i < c->thr_count; ++i) {
                duty[i] += a * m->thr_alloc[s][i];
            }
        }
        for (uint32_t i = 0u; i < c->thr_count; ++i) {
            fmax = (duty[i] > fmax) ? duty[i] : fmax;
        }
        for (uint32_t i = 0u; i < c->thr_count; ++i) {
            const real_t f = (fmax > AOCS_R(1.0)) ? (duty[i] / fmax) : duty[i];
            const real_t t_req = (f * dt) + m->thr_residual_s[i];
            const real_t t_on = thr_on_time(t_req, dt, c->thr_quantum_s, c->thr_min_on_s);
            real_t rest = t_req - t_on;
            rest = (rest > dt) ? dt : rest;
            m->thr_residual_s[i] = (rest < -dt) ? -dt : rest;
            out->thruster_on_s[i] = t_on;
            u = aocs_vec3_add(u, aocs_vec3_scale(thr_torque(c, i), t_on / dt));
        }
        out->u_unload_B_Nm = u;
    } else {
        st = AOCS_OK; /* nothing to dump */
    }
    return st;
}
