/*
 * The guidance stage (aocs/guidance/guidance.h): the table of modes expanded
 * from aocs/guidance/guidance_modes.def, the dispatch to the selected row,
 * and mode STEP (the commanded target as it is).
 */
#include <stddef.h>

#include "aocs/executive.h"

/* What the stage needs to know of a row besides its functions. */
typedef struct {
    const char *name;
    int own_rates;      /* OWN_RATES */
    int planned;        /* PLANNED */
    int feedforward;    /* FEEDFORWARD */
    uint64_t budget_ns; /* BUDGET_NS */
} guidance_info_t;

#define GUIDANCE_INFO_ROW(ID, NAME, CHECK, STEP, OWN_RATES, PLANNED, FEEDFORWARD, BUDGET_NS, ...) \
    {(NAME), (OWN_RATES), (PLANNED), (FEEDFORWARD), (uint64_t)(BUDGET_NS)},

static const guidance_info_t guidance_info[AOCS_GUIDANCE_COUNT] = {AOCS_GUIDANCE_ROWS(GUIDANCE_INFO_ROW)};

static int guidance_id_in_range(aocs_guidance_id_t id)
{
    return (((int)id >= 0) && (id < AOCS_GUIDANCE_COUNT)) ? 1 : 0;
}

int aocs_guidance_vec_nonzero(aocs_vec3_t w)
{
    int nonzero = 0;
    for (int i = 0; i < 3; ++i) {
        if ((w.v[i] > AOCS_R(0.0)) || (w.v[i] < AOCS_R(0.0))) {
            nonzero = 1;
        }
    }
    return nonzero;
}

aocs_guidance_id_t aocs_guidance_resolve(const aocs_exec_guidance_config_t *gcfg, aocs_vec3_t rate_D)
{
    aocs_guidance_id_t id = AOCS_GUIDANCE_STEP;
    if ((gcfg != NULL) && (gcfg->mode == AOCS_GUIDANCE_MODE_SLEW)) {
        id = AOCS_GUIDANCE_SLEW;
    } else if (aocs_guidance_vec_nonzero(rate_D) != 0) {
        id = AOCS_GUIDANCE_ROTATING;
    } else {
        id = AOCS_GUIDANCE_STEP;
    }
    return id;
}

const char *aocs_guidance_name(aocs_guidance_id_t id)
{
    const char *name = "unknown";
    if (guidance_id_in_range(id) != 0) {
        name = guidance_info[id].name;
    }
    return name;
}

#define GUIDANCE_CHECK_CASE(ID, NAME, CHECK, ...) \
    case AOCS_GUIDANCE_##ID:                      \
        st = CHECK(gcfg, target, rate_D);         \
        break;

aocs_status_t aocs_guidance_check(const aocs_exec_guidance_config_t *gcfg, const aocs_exec_target_t *target,
                                  aocs_vec3_t rate_D)
{
    aocs_status_t st = AOCS_OK;
    if ((gcfg == NULL) || (target == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else if (((int)gcfg->mode < 0) || (gcfg->mode >= AOCS_GUIDANCE_MODE_COUNT)) {
        st = AOCS_ERR_GUIDANCE_MODE_INVALID;
    } else {
        switch (aocs_guidance_resolve(gcfg, rate_D)) {
        AOCS_GUIDANCE_ROWS(GUIDANCE_CHECK_CASE)
        default:
            st = AOCS_ERR_GUIDANCE_MODE_INVALID;
            break;
        }
    }
    return st;
}

void aocs_guidance_init(aocs_guidance_t *g, const aocs_exec_guidance_config_t *gcfg,
                        const aocs_exec_target_t *target, aocs_vec3_t rate_D, uint64_t t0_ns,
                        aocs_vec3_t u_max_axis, real_t u_max_norm)
{
    if ((g != NULL) && (gcfg != NULL) && (target != NULL)) {
        g->id = aocs_guidance_resolve(gcfg, rate_D);
        g->cfg = *gcfg;
        g->rate_D = rate_D;
        g->u_max_axis = u_max_axis;
        g->u_max_norm = u_max_norm;
        g->target = *target;
        g->target_t0_ns = t0_ns;
        g->slew_pending = guidance_info[g->id].planned;
        g->slew_t0_ns = 0u;
    }
}

int aocs_guidance_owns_rates(const aocs_guidance_t *g)
{
    int own = 0;
    if ((g != NULL) && (guidance_id_in_range(g->id) != 0)) {
        own = guidance_info[g->id].own_rates;
    }
    return own;
}

void aocs_guidance_command(aocs_guidance_t *g, const aocs_exec_target_t *target, int have_sample,
                           uint64_t t_last_ns)
{
    if ((g != NULL) && (target != NULL) && (guidance_id_in_range(g->id) != 0)) {
        g->target = *target;
        g->slew_pending = guidance_info[g->id].planned; /* planned rows: from the next usable sample */
        if (have_sample != 0) {
            /* the commanded attitude is the target now: the time of the last sample */
            g->target_t0_ns = t_last_ns;
        }
    }
}

real_t aocs_guidance_profile_time_s(const aocs_guidance_t *g, uint64_t t_ns)
{
    real_t tau = AOCS_R(0.0);
    if (g != NULL) {
        if (g->scaled != 0) {
            tau = g->scale_tau0_s + (g->time_scale * aocs_guidance_elapsed_s(t_ns, g->scale_t0_ns));
        } else {
            tau = aocs_guidance_elapsed_s(t_ns, g->slew_t0_ns);
        }
    }
    return tau;
}

void aocs_guidance_slow_down(aocs_guidance_t *g, uint64_t t_ns, real_t k)
{
    if ((g != NULL) && (guidance_id_in_range(g->id) != 0) && (guidance_info[g->id].planned != 0) &&
        (g->slew_pending == 0) && (k > AOCS_R(0.0)) && (k <= AOCS_R(1.0))) {
        const real_t tau = aocs_guidance_profile_time_s(g, t_ns);
        if (tau < g->slew.t_end_s) {
            g->time_scale = (g->scaled != 0) ? (g->time_scale * k) : k;
            g->scale_tau0_s = tau;
            g->scale_t0_ns = t_ns;
            g->scaled = 1;
        }
    }
}

void aocs_guidance_set_epoch(aocs_guidance_t *g, uint64_t t0_ns)
{
    if (g != NULL) {
        g->target_t0_ns = t0_ns;
    }
}

#define GUIDANCE_STEP_CASE(ID, NAME, CHECK, STEP, ...) \
    case AOCS_GUIDANCE_##ID:                           \
        STEP(g, in, target);                           \
        break;

void aocs_guidance_step(aocs_guidance_t *g, const aocs_guidance_input_t *in, aocs_exec_target_t *target)
{
    if (target == NULL) {
        /* nowhere to write */
    } else if ((g == NULL) || (in == NULL) || (in->est == NULL)) {
        target->qd_DN = aocs_quat_identity();
        target->wd_B = aocs_vec3_zero();
        target->wd_dot_B = aocs_vec3_zero();
    } else {
        *target = g->target;
        switch (g->id) {
        AOCS_GUIDANCE_ROWS(GUIDANCE_STEP_CASE)
        default:
            /* not reachable: id comes from aocs_guidance_resolve; the commanded target as it is */
            break;
        }
    }
}

int aocs_guidance_has_feedforward(const aocs_guidance_t *g)
{
    int ff = 0;
    if ((g != NULL) && (guidance_id_in_range(g->id) != 0)) {
        ff = guidance_info[g->id].feedforward;
    }
    return ff;
}

aocs_vec3_t aocs_guidance_feedforward(const aocs_guidance_t *g, const aocs_exec_target_t *target,
                                      aocs_vec3_t h_wheels_B)
{
    aocs_vec3_t u_ff = aocs_vec3_zero();
    if ((g != NULL) && (target != NULL)) {
        /* SPEC 5.1: u_ff = J wd_dot + wd x (J wd + h_wheels), h_wheels = sum Js g Omega from the tachometers */
        u_ff = aocs_slew_feedforward(g->cfg.slew.inertia_kgm2, target->wd_B, target->wd_dot_B, h_wheels_B);
    }
    return u_ff;
}

uint64_t aocs_guidance_budget_ns(const aocs_guidance_t *g)
{
    uint64_t budget = 0u;
    if ((g != NULL) && (guidance_id_in_range(g->id) != 0)) {
        budget = guidance_info[g->id].budget_ns;
    }
    return budget;
}

/* ---- mode STEP: the law sees the commanded target at once ---- */

aocs_status_t aocs_guidance_step_check(const aocs_exec_guidance_config_t *gcfg, const aocs_exec_target_t *target,
                                       aocs_vec3_t rate_D)
{
    (void)gcfg;
    (void)target;
    (void)rate_D;
    return AOCS_OK; /* the slew fields are not used */
}

void aocs_guidance_step_step(aocs_guidance_t *g, const aocs_guidance_input_t *in, aocs_exec_target_t *target)
{
    /* fixed target: the commanded target as it is (already in *target) */
    (void)g;
    (void)in;
    (void)target;
}
