/*
 * Fault management, a thruster stuck open and its isolation by the latch valves (aocs/fdir/fdir.h; docs/spec.md
 * 5.15.8). The momentum monitor's residual of the last period alone,
 *
 *   dr = H_N(t_k) - H_N(t_k-1) - sum_i A(q_k-1)^T tau_i t_on,i(k-1),     bound b = mom_residual_nm T + e_k-1 + e_k
 *
 * (e the epoch uncertainty of each end, momentum_monitor.c), is tested every period against the hypothesis
 * "thruster i fired the whole period":
 *
 *   s_i = A(q_k-1)^T tau_i (T - t_on,i(k-1))      (it gave tau_i T where it was asked for tau_i t_on,i)
 *
 * The period matches i when it is inconsistent, |dr| > b, dr lies within b of s_i (|dr - s_i| <= b, the
 * smallest such distance over the thrusters on open branches, not excluded), and the two hypotheses are apart,
 * |s_i| > 2 b (a thruster too weak to tell from the bound in one period is never named). fdir.thr_open_persist
 * matching periods in a row naming the same thruster raise thruster_stuck_open.
 *
 * Isolation by test: a twin (the other thruster of a couple, same torque r x d) gives the same s_i, so the
 * residual cannot tell which of the two is open; the two are fed through different latch branches
 * (mom.thr_latch_b_mask). The suspect's branch is closed first (thruster_branch_closed; its thrusters leave the
 * unloading allocation, aocs_mom_latch_set) and the momentum window starts again. The residual matching a
 * stuck-open thruster again on fdir.thr_open_persist periods means the wrong branch: it is reopened
 * (thruster_branch_reopened) and the other one closed. A whole window consistent with a branch closed confirms
 * it (thruster_isolated, naming the thruster of that branch with the suspect's torque): the valve stays closed.
 * Each branch is tested once; with both tried, or a branch whose closing would leave some signed axis without a
 * thruster, the residual is left to the window test (momentum_inconsistent).
 */
#include <stddef.h>

#include "aocs/fdir/fdir.h"

/* The thruster on an open branch, not excluded, whose whole-period impulse s_i is nearest dr within bound and
 * apart from zero by more than 2 bound; AOCS_MOM_THRUSTERS_MAX when none. Compared in B at the period's start
 * (s_i = A^T tau_i (T - t_on,i) and dr turned by A: the same distances), squared (no root per thruster). */
static uint32_t open_match(const aocs_fdir_mom_t *m, const aocs_mom_t *mom, aocs_vec3_t dr_N, real_t bound,
                           real_t period_s)
{
    const aocs_vec3_t dr_B = aocs_mat3_mul_vec(aocs_mat3_transpose(m->a_prev_NB), dr_N);
    const real_t bound2 = bound * bound;
    uint32_t best = AOCS_MOM_THRUSTERS_MAX;
    real_t best_d2 = bound2;
    for (uint32_t i = 0u; (i < mom->cfg.thr_count) && (i < AOCS_MOM_THRUSTERS_MAX); ++i) {
        const uint32_t b = aocs_mom_thr_branch(mom, i);
        const uint32_t closed = (mom->out.latch_closed_mask >> b) & 1u;
        const uint32_t excluded = (mom->thr_excluded_mask >> i) & 1u;
        if ((closed == 0u) && (excluded == 0u)) {
            const aocs_vec3_t s_B = aocs_vec3_scale(aocs_mom_thr_torque_B(mom, i), period_s - m->on_prev_s[i]);
            const aocs_vec3_t e = aocs_vec3_sub(dr_B, s_B);
            const real_t d2 = aocs_vec3_dot(e, e);
            /* the nearest; of equals (twins) the first */
            if ((aocs_vec3_dot(s_B, s_B) > (AOCS_R(4.0) * bound2)) &&
                ((d2 < best_d2) || ((best == AOCS_MOM_THRUSTERS_MAX) && (d2 <= best_d2)))) {
                best_d2 = d2;
                best = i;
            }
        }
    }
    return best;
}

/* Closes the first untried branch that holds the suspect or its twin, the suspect's own first; 1 when a valve
 * was closed. A branch whose closing is refused (the rest would not span) counts as tried. */
static int latch_close_next(aocs_fdir_t *f, const aocs_fdir_input_t *in, uint32_t suspect)
{
    aocs_fdir_mom_t *m = &f->mom;
    aocs_mom_t *const mom = in->mom; /* the stage fault management may reconfigure (fdir.h) */
    const uint32_t own = aocs_mom_thr_branch(mom, suspect);
    int closed = 0;
    for (uint32_t k = 0u; (k < AOCS_MOM_LATCH_BRANCHES) && (closed == 0); ++k) {
        const uint32_t b = (own + k) % AOCS_MOM_LATCH_BRANCHES;
        if (((m->latch_tried >> b) & 1u) == 0u) {
            m->latch_tried |= (uint32_t)1u << b;
            if ((aocs_mom_thr_like_on_branch(mom, b, suspect) < AOCS_MOM_THRUSTERS_MAX) && (aocs_mom_latch_set(mom, b, 1) == AOCS_OK)) {
                (void)aocs_evlog_raise(&f->log, AOCS_EVT_THRUSTER_BRANCH_CLOSED, in->t_ns, (int32_t)suspect,
                                       (real_t)b, AOCS_R(0.0));
                m->latch_testing = b + 1u;
                m->latch_suspect = suspect;
                closed = 1;
            }
        }
    }
    return closed;
}

int aocs_fdir_open_test(aocs_fdir_t *f, const aocs_fdir_input_t *in, aocs_vec3_t dr_N, real_t bound)
{
    aocs_fdir_mom_t *m = &f->mom;
    aocs_mom_t *const mom = in->mom; /* the stage fault management may reconfigure (fdir.h) */
    int changed = 0;
    uint32_t i = AOCS_MOM_THRUSTERS_MAX;
    if ((mom != NULL) && (mom->id == AOCS_MOM_THRUSTERS) && !(aocs_vec3_dot(dr_N, dr_N) <= (bound * bound))) {
        i = open_match(m, mom, dr_N, bound, in->period_s);
    }
    if (i < AOCS_MOM_THRUSTERS_MAX) {
        m->open_run = ((m->open_run > 0u) && (m->open_suspect == i)) ? aocs_fdir_count_up(m->open_run) : 1u;
        m->open_suspect = i;
    } else {
        m->open_run = 0u;
    }
    if ((m->open_run > 0u) && (m->open_run >= f->cfg.thr_open_persist)) {
        m->open_run = 0u;
        if (m->latch_testing == 0u) {
            if (m->latch_tried != ((uint32_t)1u << AOCS_MOM_LATCH_BRANCHES) - 1u) {
                (void)aocs_evlog_raise(&f->log, AOCS_EVT_THRUSTER_STUCK_OPEN, in->t_ns, (int32_t)i,
                                       aocs_vec3_norm(dr_N) / in->period_s, f->cfg.mom_residual_nm);
                changed = latch_close_next(f, in, i);
            }
        } else {
            /* still open with that branch closed: the other branch holds the stuck thruster */
            const uint32_t b = m->latch_testing - 1u;
            if (aocs_mom_latch_set(mom, b, 0) == AOCS_OK) {
                (void)aocs_evlog_raise(&f->log, AOCS_EVT_THRUSTER_BRANCH_REOPENED, in->t_ns, (int32_t)i, (real_t)b,
                                       AOCS_R(0.0));
            }
            m->latch_testing = 0u;
            (void)latch_close_next(f, in, i);
            changed = 1;
        }
    }
    return changed;
}

void aocs_fdir_latch_confirm(aocs_fdir_t *f, const aocs_fdir_input_t *in)
{
    aocs_fdir_mom_t *m = &f->mom;
    if ((m->latch_testing != 0u) && (in->mom != NULL)) {
        const uint32_t b = m->latch_testing - 1u;
        /* the thruster of the closed branch with the suspect's torque: the suspect, or else its twin */
        const uint32_t like = aocs_mom_thr_like_on_branch(in->mom, b, m->latch_suspect);
        const uint32_t unit = (like < AOCS_MOM_THRUSTERS_MAX) ? like : m->latch_suspect;
        (void)aocs_evlog_raise(&f->log, AOCS_EVT_THRUSTER_ISOLATED, in->t_ns, (int32_t)unit, (real_t)b, AOCS_R(0.0));
        m->latch_testing = 0u;
    }
}
