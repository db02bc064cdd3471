/* orbit_lqr: SPEC 2.8, see orbit_lqr.h. */
#include <stddef.h>

#include "aocs/control/orbit_lqr.h"
#include "aocs/control/gain_matrix.h"

/* set by a successful init only: a zeroed or garbage struct never steps */
#define ORBIT_LQR_INIT_MAGIC 0x4F4C

aocs_status_t aocs_orbit_lqr_init(aocs_orbit_lqr_t *law, const aocs_orbit_lqr_config_t *cfg)
{
    aocs_status_t st = AOCS_OK;
    if (law != NULL) {
        law->initialised = 0;
    }
    if ((law == NULL) || (cfg == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else {
        /* velocity damping: the positive diagonal every stabilising LQR gain of this model has */
        st = aocs_gain_matrix_check(cfg->k, AOCS_GAIN_MATRIX_POS_DIAG);
        if (st == AOCS_OK) {
            law->cfg = *cfg;
            law->initialised = ORBIT_LQR_INIT_MAGIC;
        }
    }
    return st;
}

aocs_status_t aocs_orbit_lqr_step(aocs_orbit_lqr_t *law, const aocs_orbit_input_t *in, aocs_vec3_t *f_out)
{
    aocs_status_t st = AOCS_OK;
    aocs_vec3_t f = aocs_vec3_zero();

    if ((law == NULL) || (f_out == NULL) || (in == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else if (law->initialised != ORBIT_LQR_INIT_MAGIC) {
        st = AOCS_ERR_NOT_INITIALISED;
    } else {
        st = aocs_orbit_input_check(in);
    }
    if (st == AOCS_OK) {
        const aocs_orbit_lqr_config_t *c = &law->cfg;
        real_t x[6];
        /* SPEC 2.8 state order: velocities first, then positions; F = -K x */
        for (int i = 0; i < 3; ++i) {
            x[i] = in->vel_mps.v[i];
            x[3 + i] = in->pos_m.v[i];
        }
        f = aocs_gain_matrix_mul(c->k, x, AOCS_R(-1.0));
    }
    return aocs_law_set_output(st, f, f_out);
}
