/*
 * Fault management, the gyro bias-jump monitor (aocs/fdir/fdir.h; docs/spec.md 5.15.4): the MEKF's bias
 * estimate against its value at a reference time. For a consistent filter the change of the estimate over
 * (t_ref, t] has, per axis, a variance at most P_bb(t) + P_bb(t_ref) + sigma_u^2 (t - t_ref) (the two
 * estimation errors and the true bias's random walk; every covariance between them left out only makes the
 * bound larger, 5.15.4), so z_i = (b_i(t) - b_i(t_ref))^2 / that bound above fdir.gyro_bias_chi2 (1 degree
 * of freedom) on fdir.gyro_bias_persist consecutive applied tracker samples is a bias the filter is still
 * chasing: a jump of the gyro's bias (or a rate the gyro and the tracker disagree on). It raises
 * gyro_st_inconsistent and asks for the filter's bias covariance back at its prior (reinflate_bias), so that
 * the filter re-estimates the bias at the speed of its start; the reference is then taken afresh. The
 * reference is also taken afresh when it has gone stale (bias_stale): while the filter converges, and when
 * the random walk since outweighs the filter's own variance.
 */
#include <stddef.h>

#include "aocs/fdir/fdir.h"

/* diag of the bias block of P in aocs_det_output_t.p_upper (6 x 6 upper triangle, row-major) */
static const uint32_t bias_diag_index[3] = {15u, 18u, 20u};

static void bias_arm(aocs_fdir_gyro_t *g, const aocs_det_output_t *est, uint64_t t_ns)
{
    g->b_ref_B = est->bias_B_radps;
    for (uint32_t i = 0u; i < 3u; ++i) {
        g->p_ref[i] = est->p_upper[bias_diag_index[i]];
    }
    g->t_ref_ns = t_ns;
    g->restarts_ref = est->n_restarts;
    g->bias_run = 0u;
    g->bias_armed = 1;
}

/* 1 when the reference has gone stale: on some axis its variance and the walk since exceed twice the
 * filter's present variance (a converging filter, or a long time since): the bound is then mostly the
 * reference's, and a fresh one tests tighter */
static int bias_stale(const aocs_fdir_gyro_t *g, const aocs_det_output_t *est, real_t walk)
{
    int stale = 0;
    for (uint32_t i = 0u; i < 3u; ++i) {
        if ((g->p_ref[i] + walk) > (AOCS_R(2.0) * est->p_upper[bias_diag_index[i]])) {
            stale = 1;
        }
    }
    return stale;
}

void aocs_fdir_gyro_bias_step(aocs_fdir_t *f, const aocs_fdir_input_t *in)
{
    aocs_fdir_gyro_t *g = &f->gyro;
    const aocs_det_output_t *est = in->est;
    /* only a tracker sample the filter applied moves its bias estimate */
    if ((f->cfg.gyro_bias_chi2 > AOCS_R(0.0)) && (est != NULL) && (in->gyro_rrw_radps1p5 > AOCS_R(0.0)) &&
        (est->status == AOCS_OK) && (est->st_status == AOCS_OK)) {
        const uint64_t since_ns = (in->t_ns >= g->t_ref_ns) ? (in->t_ns - g->t_ref_ns) : 0u;
        const real_t dt_s = (real_t)since_ns * AOCS_R(1.0e-9);
        const real_t walk = in->gyro_rrw_radps1p5 * in->gyro_rrw_radps1p5 * dt_s;
        if ((g->bias_armed == 0) || (est->n_restarts != g->restarts_ref) || (in->t_ns < g->t_ref_ns) ||
            (bias_stale(g, est, walk) != 0)) {
            bias_arm(g, est, in->t_ns);
        } else {
            real_t z_max = AOCS_R(0.0);
            uint32_t axis = 0u;
            int over = 0;
            for (uint32_t i = 0u; i < 3u; ++i) {
                const real_t d = est->bias_B_radps.v[i] - g->b_ref_B.v[i];
                const real_t var = est->p_upper[bias_diag_index[i]] + g->p_ref[i] + walk;
                /* d^2 > chi2 var without a division (var may underflow in float) */
                if ((d * d) > (f->cfg.gyro_bias_chi2 * var)) {
                    const real_t z = (var > AOCS_R(0.0)) ? ((d * d) / var) : f->cfg.gyro_bias_chi2;
                    over = 1;
                    if (z >= z_max) {
                        z_max = z;
                        axis = i;
                    }
                }
            }
            g->bias_run = (over != 0) ? aocs_fdir_count_up(g->bias_run) : 0u;
            if (g->bias_run == f->cfg.gyro_bias_persist) {
                (void)aocs_evlog_raise(&f->log, AOCS_EVT_GYRO_ST_INCONSISTENT, in->t_ns, (int32_t)axis, z_max,
                                       f->cfg.gyro_bias_chi2);
                f->reinflate_bias = 1;
                g->bias_armed = 0; /* the reference afresh from the re-inflated covariance, next sample */
            }
        }
    }
}
