/*
 * bench_laws: host benchmark of every control-law step, and of the full
 * executive step with that law (issue 5: "host timing per law: median and
 * worst step time in ns over a long run, and instruction counts per step
 * under valgrind --tool=callgrind").
 *
 * Timing mode (default): for each law, N steps (default 200000) over a ring
 * of BENCH_RING seeded pseudo-random states near that law's reference
 * scenario (SPEC 4); each step is bracketed by aocs_hal_time_ns()
 * (clock_gettime(CLOCK_MONOTONIC) on the host), the same clock the
 * executive uses to check its budgets. Per row: median, p99 (nearest rank),
 * worst and mean ns, the declared budget BUDGET_NS (laws.def) and how many
 * steps exceeded it. Rows:
 *   timer      two back-to-back clock reads: the overhead inside every row
 *   law        aocs_<law>_step alone
 *   exec       aocs_exec_step (input checks, law, saturation, counters) in
 *              lockstep, NOMINAL mode, timed from outside
 *   exec_self  the executive's own step_time_ns (law + saturation), the
 *              figure it compares with the budget; over_budget equals its
 *              overrun counter (checked here)
 * Every step must return AOCS_OK (and the executive stay NOMINAL); any
 * error is counted, printed and makes the exit status 1.
 *
 * Callgrind mode (--callgrind-steps N --law L [--exec]): exactly N steps of
 * one law (or of the executive with it), no clock reads, between
 * CALLGRIND_START_INSTRUMENTATION and CALLGRIND_STOP_INSTRUMENTATION. The
 * driver (bench_laws.py) runs it under
 *   valgrind --tool=callgrind --instr-atstart=no --toggle-collect=<symbol>
 * with the symbol printed by --list, so only instructions executed inside
 * the step function (and its callees) are counted: the total is exactly
 * N times the mean per step when N is a multiple of BENCH_RING. For the
 * executive the HAL clock reads inside it are toggled off as well
 * (--toggle-collect=aocs_hal_time_ns, aocs_hal_cycles): their count
 * depends on the clock value, and on the target they are a register read.
 *
 * The states are a deterministic function of --seed (splitmix64), so a
 * callgrind count is repeatable bit for bit. Not firmware: host only, but
 * built with the firmware warnings and no dynamic memory all the same.
 */
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aocs/executive.h"
#include "aocs/hal.h"
#include "aocs_registry.h"
#include "gains/aocs_gains.h"

#if defined(AOCS_BENCH_HAVE_CALLGRIND_H)
#include <valgrind/callgrind.h>
#define BENCH_CALLGRIND_H 1
#else
#define CALLGRIND_START_INSTRUMENTATION
#define CALLGRIND_STOP_INSTRUMENTATION
#define BENCH_CALLGRIND_H 0
#endif

#if defined(AOCS_REAL_IS_FLOAT)
#define BENCH_REAL_NAME "float"
#else
#define BENCH_REAL_NAME "double"
#endif

#define BENCH_RING 512u                 /* states in the ring, a power of two */
#define BENCH_RING_MASK (BENCH_RING - 1u)
#define BENCH_DEFAULT_STEPS 200000ull
#define BENCH_MAX_STEPS 1000000000ull
#define BENCH_DEFAULT_SEED 20240501ull
#define BENCH_WARMUP_MAX 2000ull        /* untimed steps before each row */
#define BENCH_HIST_BINS (1u << 18)      /* 1 ns bins up to 262 us, then one overflow bin */
#define BENCH_PI AOCS_R(3.14159265358979323846)
#define BENCH_DEG AOCS_R(0.017453292519943295)

/*
 * ---- the laws, the step symbol callgrind collects, the reference state family ----
 * Every row of aocs/laws.def (AOCS_LAW_ROWS), in id order: the step symbol is
 * its STEP column, the state family follows from its REF column (the law's
 * SPEC 4 reference scenario): a new law needs no edit here unless its
 * reference scenario is of a new family.
 */
typedef enum {
    FAM_RTC = 0,   /* rtc_*: crp_linear, J = I, large angles and rates, 100 Hz */
    FAM_IRASSI,    /* irassi_*: IRASSI slew at 10 Hz */
    FAM_GEO,       /* geo_*: small errors about a frame turning at the GEO orbit rate */
    FAM_GAO,       /* gao_*: errors up to 120 deg */
    FAM_LANDSAT,   /* landsat8_*: relative position and velocity */
    FAM_COUNT
} bench_family_t;

/* scenario name prefix of each family, in bench_family_t order (also --list) */
static const char *const bench_family_names[FAM_COUNT] = {"rtc", "irassi", "geo", "gao", "landsat8"};

typedef struct {
    aocs_law_id_t id;
    const char *step_symbol;   /* function the callgrind count is restricted to */
    const char *ref_scenario;  /* decides the family (bench_family_of) */
} bench_law_info_t;

#define BENCH_LAW_ROW(ID, NAME, INPUT, TITLE, STATE, STATE_T, CFG, CFG_T, CFG_USE, INIT, STEP, VARIANT, VMEMBER, VVALUE, \
                      BUDGET_NS, M4F, M7, REF)                                                                     \
    {AOCS_LAW_##ID, #STEP, REF},

static const bench_law_info_t bench_law_list[] = {AOCS_LAW_ROWS(BENCH_LAW_ROW)};
#define BENCH_LAW_COUNT (sizeof(bench_law_list) / sizeof(bench_law_list[0]))
#define BENCH_EXEC_SYMBOL "aocs_exec_step"
/*
 * HAL reads inside aocs_exec_step: their instruction count depends on the
 * clock value (glibc's clock_gettime under valgrind), so the driver toggles
 * collection off inside them to keep the executive count exact. They are
 * never called in the callgrind loop outside aocs_exec_step.
 */
#define BENCH_EXEC_EXCLUDED "aocs_hal_time_ns,aocs_hal_cycles"

/* Where a family's states come from (SPEC 4 scenario data). */
typedef struct {
    aocs_quat_t qd_DN;     /* target attitude */
    aocs_vec3_t wd_B;      /* target rate, rad/s */
    real_t angle_max_rad;  /* error rotation angle drawn uniformly in [0, this] */
    real_t rate_max;       /* each rate error component uniform in [-this, this], rad/s */
    real_t dt_s;           /* control period */
    real_t pos_max_m;      /* orbit: each position component in [-this, this] */
    real_t vel_max_mps;    /* orbit: each velocity component in [-this, this] */
} bench_family_data_t;

/* One state of the ring, in the three input forms. */
typedef struct {
    aocs_att_input_t att;
    aocs_orbit_input_t orbit;
    aocs_exec_input_t exec; /* tick and t_sensor_ns are set by the loop */
} bench_sample_t;

typedef struct {
    uint32_t bins[BENCH_HIST_BINS]; /* bins[k]: samples of k ns; the last bin: >= BENCH_HIST_BINS - 1 */
    uint64_t n;
    uint64_t max_ns;
    uint64_t over_budget;
    uint64_t budget_ns;
    double sum_ns;
} bench_hist_t;

typedef struct {
    uint64_t steps;
    uint64_t errors;
    double checksum; /* sum over the steps of u1 + 2 u2 + 3 u3: shows the work was done */
} bench_result_t;

/* large objects are static (no dynamic memory, no big stack frames) */
static bench_sample_t bench_ring[BENCH_RING];
static bench_hist_t bench_hist_outer;
static bench_hist_t bench_hist_self;
static aocs_exec_law_states_t bench_states;
static aocs_exec_t bench_exec;

/* ---- deterministic pseudo-random numbers: splitmix64 (Steele, Lea, Flood 2014) ---- */
static uint64_t bench_rng_next(uint64_t *s)
{
    uint64_t z;
    *s += 0x9E3779B97F4A7C15ull;
    z = *s;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/* uniform in [0, 1): the top 53 bits */
static real_t bench_rng_unit(uint64_t *s)
{
    return (real_t)((double)(bench_rng_next(s) >> 11) * (1.0 / 9007199254740992.0));
}

/* uniform in [-a, a] */
static real_t bench_rng_sym(uint64_t *s, real_t a)
{
    return a * ((AOCS_R(2.0) * bench_rng_unit(s)) - AOCS_R(1.0));
}

/* three draws in the order x, y, z (argument evaluation order is unspecified in C) */
static aocs_vec3_t bench_rng_vec3(uint64_t *s, real_t a)
{
    aocs_vec3_t v;
    v.v[0] = bench_rng_sym(s, a);
    v.v[1] = bench_rng_sym(s, a);
    v.v[2] = bench_rng_sym(s, a);
    return v;
}

/* The family of a reference scenario: the longest family name that prefixes it; FAM_COUNT if none. */
static bench_family_t bench_family_of(const char *scenario)
{
    bench_family_t fam = FAM_COUNT;
    size_t best = 0u;
    for (int i = 0; i < (int)FAM_COUNT; ++i) {
        size_t n = strlen(bench_family_names[i]);
        if ((n > best) && (strncmp(scenario, bench_family_names[i], n) == 0)) {
            fam = (bench_family_t)i;
            best = n;
        }
    }
    return fam;
}

static void bench_family_data(bench_family_t fam, bench_family_data_t *d)
{
    aocs_euler321_t e = {AOCS_R(0.0), AOCS_R(0.0), AOCS_R(0.0)};
    d->wd_B = aocs_vec3_zero();
    d->pos_max_m = AOCS_R(0.0);
    d->vel_max_mps = AOCS_R(0.0);
    d->dt_s = AOCS_R(0.1);
    switch (fam) {
    case FAM_RTC:
        /* rtc_ex*: |rho0| up to ~20 (>= 170 deg), w0 up to 48 rad/s; kept below 170 deg */
        d->angle_max_rad = AOCS_R(170.0) * BENCH_DEG;
        d->rate_max = AOCS_R(1.0);
        d->dt_s = AOCS_R(0.01);
        break;
    case FAM_IRASSI:
        /* irassi_large: target Euler 3-2-1 [30 -20 1] deg, slew of ~45 deg at low rates */
        e.yaw = AOCS_R(30.0) * BENCH_DEG;
        e.pitch = AOCS_R(-20.0) * BENCH_DEG;
        e.roll = AOCS_R(1.0) * BENCH_DEG;
        d->angle_max_rad = AOCS_R(50.0) * BENCH_DEG;
        d->rate_max = AOCS_R(0.01);
        break;
    case FAM_GEO:
        /* geo_hinf: 0.5 deg errors, 1e-5 rad/s rate errors, target turning at -w0 about y */
        d->wd_B = aocs_vec3_make(AOCS_R(0.0), -AOCS_GAINS_GEO_W0_RADPS, AOCS_R(0.0));
        d->angle_max_rad = AOCS_R(2.0) * BENCH_DEG;
        d->rate_max = AOCS_R(1.0e-4);
        break;
    case FAM_GAO:
        /* gao_mrp: sigma0 = [-0.3 -0.4 0.2] (~62 deg); up to 120 deg, |sigma| <= 0.58 */
        d->angle_max_rad = AOCS_R(120.0) * BENCH_DEG;
        d->rate_max = AOCS_R(0.02);
        break;
    default: /* FAM_LANDSAT: x0 = [1 -1 -6 50 -100 350] */
        d->angle_max_rad = AOCS_R(0.0);
        d->rate_max = AOCS_R(0.0);
        d->pos_max_m = AOCS_R(400.0);
        d->vel_max_mps = AOCS_R(6.0);
        break;
    }
    d->qd_DN = aocs_euler321_to_quat(e);
}

/*
 * Ring of states: q_BN = qerr (x) qd (so qe = q (x) qd^-1 = qerr, SPEC 1),
 * qerr a rotation of uniform angle about a uniformly distributed axis, its
 * sign flipped for half the states (an estimator may deliver either
 * hemisphere: the sign(qe4) branches run); rates wd + uniform errors.
 */
static void bench_ring_fill(bench_family_t fam, uint64_t seed)
{
    bench_family_data_t d;
    uint64_t s = seed;
    bench_family_data(fam, &d);
    for (uint32_t k = 0u; k < BENCH_RING; ++k) {
        bench_sample_t *x = &bench_ring[k];
        real_t z = bench_rng_sym(&s, AOCS_R(1.0));
        real_t az = AOCS_R(2.0) * BENCH_PI * bench_rng_unit(&s);
        real_t r = AOCS_SQRT(AOCS_R(1.0) - (z * z));
        real_t half = AOCS_R(0.5) * d.angle_max_rad * bench_rng_unit(&s);
        real_t sh = AOCS_SIN(half);
        aocs_quat_t qerr = aocs_quat_make(sh * r * AOCS_COS(az), sh * r * AOCS_SIN(az), sh * z, AOCS_COS(half));
        aocs_quat_t q = aocs_quat_mul(qerr, d.qd_DN);
        aocs_vec3_t w;
        if (bench_rng_unit(&s) < AOCS_R(0.5)) {
            for (int i = 0; i < 4; ++i) {
                q.q[i] = -q.q[i];
            }
        }
        w = aocs_vec3_add(d.wd_B, bench_rng_vec3(&s, d.rate_max));
        x->att.q_BN = q;
        x->att.w_BN_B = w;
        x->att.qd_DN = d.qd_DN;
        x->att.wd_B = d.wd_B;
        x->att.wd_dot_B = aocs_vec3_zero();
        x->att.dt_s = d.dt_s;
        x->att.u_max_axis = aocs_vec3_zero();
        x->att.u_max_norm = AOCS_R(0.0);
        x->orbit.vel_mps = bench_rng_vec3(&s, d.vel_max_mps);
        x->orbit.pos_m = bench_rng_vec3(&s, d.pos_max_m);
        x->orbit.dt_s = d.dt_s;
        (void)memset(&x->exec, 0, sizeof(x->exec));
        x->exec.valid = AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE | AOCS_EXEC_VALID_ORBIT;
        x->exec.q_BN = q;
        x->exec.w_BN_B = w;
        x->exec.pos_m = x->orbit.pos_m;
        x->exec.vel_mps = x->orbit.vel_mps;
    }
}

/*
 * ---- law configurations ----
 * The reference configuration of the registry (the REF column of every
 * config field in aocs/laws.def: the SPEC 4 reference scenarios' values);
 * the states are direct dispatches of the executive (aocs_exec_law_init /
 * aocs_exec_law_step: the variant forced by the law id), whose switch the
 * callgrind counts exclude (they collect inside the step symbol only).
 */
static int bench_law_configs(aocs_exec_law_configs_t *c)
{
    char err[256];
    int rc = aocs_registry_reference_configs(c, err, sizeof(err));
    if (rc != 0) {
        (void)fprintf(stderr, "bench_laws: reference configuration: %s\n", err);
    }
    return rc;
}

static aocs_status_t bench_law_init(aocs_law_id_t id, const aocs_exec_law_configs_t *c)
{
    return aocs_exec_law_init(&bench_states, c, id);
}

static aocs_status_t bench_law_step(aocs_law_id_t id, const bench_sample_t *x, aocs_vec3_t *u)
{
    return aocs_exec_law_step(&bench_states, id, &x->att, &x->orbit, u);
}

/* Executive in lockstep with one law, NOMINAL from the first step. */
static aocs_status_t bench_exec_init(const bench_law_info_t *info, const aocs_exec_law_configs_t *c,
                                     uint64_t *period_ns)
{
    aocs_exec_config_t cfg;
    bench_family_data_t d;
    aocs_status_t st;
    bench_family_data(bench_family_of(info->ref_scenario), &d);
    aocs_exec_config_default(&cfg);
    cfg.period_s = d.dt_s;
    cfg.law = info->id;
    cfg.target.qd_DN = d.qd_DN;
    cfg.target.wd_B = d.wd_B;
    cfg.target.wd_dot_B = aocs_vec3_zero();
    cfg.laws = *c;
    /* a limit that does not bind for these states: the unsaturated path of a nominal step */
    cfg.u_max_axis = aocs_vec3_make(AOCS_R(1.0e4), AOCS_R(1.0e4), AOCS_R(1.0e4));
    cfg.clock = AOCS_EXEC_CLOCK_LOCKSTEP;
    st = aocs_exec_init(&bench_exec, &cfg);
    if (st == AOCS_OK) {
        st = aocs_exec_period_to_ns(cfg.period_s, period_ns);
    }
    return st;
}

static void bench_exec_input(uint64_t k, uint64_t period_ns, aocs_exec_input_t *in)
{
    *in = bench_ring[k & BENCH_RING_MASK].exec;
    in->tick = (uint32_t)(k + 1u); /* lockstep: one sample per period, ticks and time advance */
    in->t_sensor_ns = (k + 1u) * period_ns;
}

static int bench_exec_step_ok(aocs_status_t st, const aocs_exec_output_t *out)
{
    return ((st == AOCS_OK) && (out->mode == AOCS_EXEC_MODE_NOMINAL) && (out->law_status == AOCS_OK) &&
            (out->input_status == AOCS_OK))
               ? 1
               : 0;
}

/* ---- histogram of step times ---- */
static void bench_hist_reset(bench_hist_t *h, uint64_t budget_ns)
{
    (void)memset(h->bins, 0, sizeof(h->bins));
    h->n = 0u;
    h->max_ns = 0u;
    h->over_budget = 0u;
    h->budget_ns = budget_ns;
    h->sum_ns = 0.0;
}

static void bench_hist_add(bench_hist_t *h, uint64_t ns)
{
    uint64_t bin = (ns < (uint64_t)(BENCH_HIST_BINS - 1u)) ? ns : (uint64_t)(BENCH_HIST_BINS - 1u);
    h->bins[bin] += 1u;
    h->n += 1u;
    h->sum_ns += (double)ns;
    if (ns > h->max_ns) {
        h->max_ns = ns;
    }
    if ((h->budget_ns > 0u) && (ns > h->budget_ns)) {
        h->over_budget += 1u;
    }
}

/* Nearest-rank percentile (rank ceil(p n)); a rank in the overflow bin reports the worst time. */
static uint64_t bench_hist_percentile(const bench_hist_t *h, uint32_t per_mille)
{
    uint64_t rank = ((h->n * per_mille) + 999u) / 1000u;
    uint64_t cum = 0u;
    uint64_t v = h->max_ns;
    if (rank == 0u) {
        rank = 1u;
    }
    for (uint32_t k = 0u; k < (BENCH_HIST_BINS - 1u); ++k) {
        cum += h->bins[k];
        if (cum >= rank) {
            v = k;
            break;
        }
    }
    return v;
}

/* ---- output ---- */
#define BENCH_ROW_FMT "%-10s %-14s %10s %10s %10s %10s %10s %10s %11s %7s %s\n"

static void bench_print_header(void)
{
    (void)printf(BENCH_ROW_FMT, "kind", "law", "steps", "median_ns", "p99_ns", "worst_ns", "mean_ns", "budget_ns",
                 "over_budget", "errors", "checksum");
}

static void bench_print_row(const char *kind, const char *law, const bench_hist_t *h, const bench_result_t *r)
{
    double mean = (h->n > 0u) ? (h->sum_ns / (double)h->n) : 0.0;
    (void)printf("%-10s %-14s %10llu %10llu %10llu %10llu %10.1f %10llu %11llu %7llu %.17g\n", kind, law,
                 (unsigned long long)h->n, (unsigned long long)bench_hist_percentile(h, 500u),
                 (unsigned long long)bench_hist_percentile(h, 990u), (unsigned long long)h->max_ns, mean,
                 (unsigned long long)h->budget_ns, (unsigned long long)h->over_budget,
                 (unsigned long long)r->errors, r->checksum);
}

/* u1 + 2 u2 + 3 u3: a checksum that also tells the axes apart */
static double bench_sum3(aocs_vec3_t u)
{
    return ((double)u.v[0] + (2.0 * (double)u.v[1])) + (3.0 * (double)u.v[2]);
}

/* ---- the runs ---- */
static void bench_time_clock(uint64_t steps)
{
    bench_result_t r = {0u, 0u, 0.0};
    bench_hist_reset(&bench_hist_outer, 0u);
    for (uint64_t k = 0u; k < steps; ++k) {
        uint64_t t0 = aocs_hal_time_ns();
        uint64_t t1 = aocs_hal_time_ns();
        bench_hist_add(&bench_hist_outer, t1 - t0);
    }
    r.steps = steps;
    bench_print_row("timer", "-", &bench_hist_outer, &r);
}

static int bench_time_law(const bench_law_info_t *info, uint64_t steps, uint64_t warmup)
{
    bench_result_t r = {0u, 0u, 0.0};
    aocs_vec3_t u = aocs_vec3_zero();
    for (uint64_t k = 0u; k < warmup; ++k) {
        (void)bench_law_step(info->id, &bench_ring[k & BENCH_RING_MASK], &u);
    }
    bench_hist_reset(&bench_hist_outer, aocs_law_budget_ns(info->id));
    for (uint64_t k = 0u; k < steps; ++k) {
        const bench_sample_t *x = &bench_ring[k & BENCH_RING_MASK];
        uint64_t t0 = aocs_hal_time_ns();
        aocs_status_t st = bench_law_step(info->id, x, &u);
        uint64_t t1 = aocs_hal_time_ns();
        bench_hist_add(&bench_hist_outer, t1 - t0);
        if (st != AOCS_OK) {
            r.errors += 1u;
        }
        r.checksum += bench_sum3(u);
    }
    r.steps = steps;
    bench_print_row("law", aocs_law_name(info->id), &bench_hist_outer, &r);
    return (r.errors == 0u) ? 0 : 1;
}

static int bench_time_exec(const bench_law_info_t *info, const aocs_exec_law_configs_t *c, uint64_t steps,
                           uint64_t warmup)
{
    bench_result_t r = {0u, 0u, 0.0};
    aocs_exec_output_t out;
    aocs_exec_input_t in;
    uint64_t period_ns = 0u;
    uint64_t budget = aocs_law_budget_ns(info->id);
    int rc = 0;
    aocs_status_t st = bench_exec_init(info, c, &period_ns);
    if (st != AOCS_OK) {
        (void)fprintf(stderr, "bench_laws: executive init with %s failed: %s\n", aocs_law_name(info->id),
                      aocs_status_name(st));
        rc = 1;
    } else {
        uint32_t overruns_before;
        uint64_t over_own_budget = 0u; /* steps whose own time exceeds the budget the executive gave them */
        for (uint64_t k = 0u; k < warmup; ++k) {
            bench_exec_input(k, period_ns, &in);
            st = aocs_exec_step(&bench_exec, &in, &out);
            if (bench_exec_step_ok(st, &out) == 0) {
                r.errors += 1u;
            }
        }
        overruns_before = aocs_exec_counters(&bench_exec).overrun;
        bench_hist_reset(&bench_hist_outer, budget);
        bench_hist_reset(&bench_hist_self, budget);
        for (uint64_t k = warmup; k < (warmup + steps); ++k) {
            uint64_t t0;
            uint64_t t1;
            bench_exec_input(k, period_ns, &in);
            t0 = aocs_hal_time_ns();
            st = aocs_exec_step(&bench_exec, &in, &out);
            t1 = aocs_hal_time_ns();
            bench_hist_add(&bench_hist_outer, t1 - t0);
            bench_hist_add(&bench_hist_self, out.step_time_ns);
            if (out.step_time_ns > out.budget_ns) {
                over_own_budget += 1u;
            }
            if (bench_exec_step_ok(st, &out) == 0) {
                r.errors += 1u;
            }
            r.checksum += bench_sum3(out.u_cmd);
        }
        r.steps = steps;
        bench_print_row("exec", aocs_law_name(info->id), &bench_hist_outer, &r);
        bench_print_row("exec_self", aocs_law_name(info->id), &bench_hist_self, &r);
        /* the executive's overrun counter must agree with its own times against the budget of each step
         * (out.budget_ns: the law's plus the allowances of the stages on, fault management's among them;
         * the rows above count against the law's alone) */
        if ((uint64_t)(aocs_exec_counters(&bench_exec).overrun - overruns_before) != over_own_budget) {
            (void)fprintf(stderr, "bench_laws: %s: executive overrun counter %u disagrees with %llu steps over budget\n",
                          aocs_law_name(info->id), (unsigned)(aocs_exec_counters(&bench_exec).overrun - overruns_before),
                          (unsigned long long)over_own_budget);
            rc = 1;
        }
        if (r.errors != 0u) {
            rc = 1;
        }
    }
    return rc;
}

/* Exactly `steps` steps, no clock reads, instrumented by callgrind only inside the loop. */
static int bench_callgrind(const bench_law_info_t *info, const aocs_exec_law_configs_t *c, uint64_t steps,
                           int use_exec)
{
    bench_result_t r = {0u, 0u, 0.0};
    aocs_exec_output_t out;
    aocs_exec_input_t in;
    aocs_vec3_t u = aocs_vec3_zero();
    uint64_t period_ns = 0u;
    aocs_status_t st = AOCS_OK;
    if (use_exec != 0) {
        st = bench_exec_init(info, c, &period_ns);
    }
    if (st != AOCS_OK) {
        (void)fprintf(stderr, "bench_laws: executive init with %s failed: %s\n", aocs_law_name(info->id),
                      aocs_status_name(st));
        r.errors = 1u;
    } else if (use_exec != 0) {
        CALLGRIND_START_INSTRUMENTATION;
        for (uint64_t k = 0u; k < steps; ++k) {
            bench_exec_input(k, period_ns, &in);
            st = aocs_exec_step(&bench_exec, &in, &out);
            if (bench_exec_step_ok(st, &out) == 0) {
                r.errors += 1u;
            }
            r.checksum += bench_sum3(out.u_cmd);
        }
        CALLGRIND_STOP_INSTRUMENTATION;
    } else {
        CALLGRIND_START_INSTRUMENTATION;
        for (uint64_t k = 0u; k < steps; ++k) {
            st = bench_law_step(info->id, &bench_ring[k & BENCH_RING_MASK], &u);
            if (st != AOCS_OK) {
                r.errors += 1u;
            }
            r.checksum += bench_sum3(u);
        }
        CALLGRIND_STOP_INSTRUMENTATION;
    }
    r.steps = steps;
    (void)printf("%-10s %-14s %10s %7s %s\n", "kind", "law", "steps", "errors", "checksum");
    (void)printf("%-10s %-14s %10llu %7llu %.17g\n", (use_exec != 0) ? "exec" : "law", aocs_law_name(info->id),
                 (unsigned long long)r.steps, (unsigned long long)r.errors, r.checksum);
    return (r.errors == 0u) ? 0 : 1;
}

/* ---- command line ---- */
static void bench_usage(FILE *f)
{
    (void)fprintf(f,
                  "usage: bench_laws [--steps N] [--law NAME]... [--seed S]\n"
                  "       bench_laws --callgrind-steps N --law NAME [--exec] [--seed S]\n"
                  "       bench_laws --list\n"
                  "  --steps N            timed steps per row (default %llu)\n"
                  "  --law NAME           only this law (repeatable; default: every law)\n"
                  "  --seed S             seed of the state ring (default %llu)\n"
                  "  --callgrind-steps N  run exactly N untimed steps of one law between\n"
                  "                       CALLGRIND_START/STOP_INSTRUMENTATION\n"
                  "  --exec               callgrind mode: step the executive with the law\n"
                  "  --list               law, callgrind symbol, budget_ns, family per line\n",
                  (unsigned long long)BENCH_DEFAULT_STEPS, (unsigned long long)BENCH_DEFAULT_SEED);
}

static int bench_parse_u64(const char *s, uint64_t lo, uint64_t hi, uint64_t *out)
{
    char *end = NULL;
    int ok = 0;
    if ((s != NULL) && (s[0] >= '0') && (s[0] <= '9')) {
        unsigned long long v;
        errno = 0;
        v = strtoull(s, &end, 0);
        if ((errno == 0) && (end != NULL) && (*end == '\0') && (v >= lo) && (v <= hi)) {
            *out = (uint64_t)v;
            ok = 1;
        }
    }
    return ok;
}

static const bench_law_info_t *bench_find(const char *name)
{
    const bench_law_info_t *found = NULL;
    for (size_t i = 0u; i < BENCH_LAW_COUNT; ++i) {
        if (strcmp(name, aocs_law_name(bench_law_list[i].id)) == 0) {
            found = &bench_law_list[i];
        }
    }
    return found;
}

static const char *bench_family_name(bench_family_t fam)
{
    return ((int)fam < (int)FAM_COUNT) ? bench_family_names[fam] : "none";
}

int main(int argc, char **argv)
{
    int selected[BENCH_LAW_COUNT];
    int any_selected = 0;
    int use_exec = 0;
    int list = 0;
    uint64_t steps = BENCH_DEFAULT_STEPS;
    uint64_t seed = BENCH_DEFAULT_SEED;
    uint64_t cg_steps = 0u;
    aocs_exec_law_configs_t configs;
    int rc = 0;

    (void)memset(selected, 0, sizeof(selected));
    for (int a = 1; (a < argc) && (rc == 0); ++a) {
        const char *arg = argv[a];
        const char *val = ((a + 1) < argc) ? argv[a + 1] : NULL;
        if (strcmp(arg, "--steps") == 0) {
            rc = bench_parse_u64(val, 1u, BENCH_MAX_STEPS, &steps) ? 0 : 2;
            ++a;
        } else if (strcmp(arg, "--callgrind-steps") == 0) {
            rc = bench_parse_u64(val, 1u, BENCH_MAX_STEPS, &cg_steps) ? 0 : 2;
            ++a;
        } else if (strcmp(arg, "--seed") == 0) {
            rc = bench_parse_u64(val, 0u, UINT64_MAX, &seed) ? 0 : 2;
            ++a;
        } else if (strcmp(arg, "--law") == 0) {
            const bench_law_info_t *info = (val != NULL) ? bench_find(val) : NULL;
            if (info == NULL) {
                (void)fprintf(stderr, "bench_laws: unknown law '%s'\n", (val != NULL) ? val : "");
                rc = 2;
            } else {
                selected[info - bench_law_list] = 1;
                any_selected = 1;
            }
            ++a;
        } else if (strcmp(arg, "--exec") == 0) {
            use_exec = 1;
        } else if (strcmp(arg, "--list") == 0) {
            list = 1;
        } else if ((strcmp(arg, "--help") == 0) || (strcmp(arg, "-h") == 0)) {
            bench_usage(stdout);
            return 0;
        } else {
            (void)fprintf(stderr, "bench_laws: unknown option '%s'\n", arg);
            rc = 2;
        }
        if (rc == 2) {
            (void)fprintf(stderr, "bench_laws: bad value for %s\n", arg);
        }
    }
    if ((rc == 0) && (cg_steps > 0u)) {
        int n = 0;
        for (size_t i = 0u; i < BENCH_LAW_COUNT; ++i) {
            n += selected[i];
        }
        if (n != 1) {
            (void)fprintf(stderr, "bench_laws: --callgrind-steps needs exactly one --law\n");
            rc = 2;
        }
    }
    if ((rc == 0) && (use_exec != 0) && (cg_steps == 0u)) {
        (void)fprintf(stderr, "bench_laws: --exec belongs to the callgrind mode (timing runs both)\n");
        rc = 2;
    }
    if (rc == 2) {
        bench_usage(stderr);
        return 2;
    }

    if (list != 0) {
        (void)printf("# law step_symbol budget_ns family (executive symbol: %s; excluded: %s; callgrind.h: %d)\n",
                     BENCH_EXEC_SYMBOL, BENCH_EXEC_EXCLUDED, BENCH_CALLGRIND_H);
        for (size_t i = 0u; i < BENCH_LAW_COUNT; ++i) {
            (void)printf("%s %s %llu %s\n", aocs_law_name(bench_law_list[i].id), bench_law_list[i].step_symbol,
                         (unsigned long long)aocs_law_budget_ns(bench_law_list[i].id),
                         bench_family_name(bench_family_of(bench_law_list[i].ref_scenario)));
        }
        return 0;
    }

    if (bench_law_configs(&configs) != 0) {
        rc = 1;
    }
    for (size_t i = 0u; (i < BENCH_LAW_COUNT) && (rc == 0); ++i) {
        if (bench_family_of(bench_law_list[i].ref_scenario) == FAM_COUNT) {
            (void)fprintf(stderr, "bench_laws: %s: reference scenario '%s' is of no state family of the bench\n",
                          aocs_law_name(bench_law_list[i].id), bench_law_list[i].ref_scenario);
            rc = 1;
        }
        if ((any_selected == 0) || (selected[i] != 0)) {
            aocs_status_t st = bench_law_init(bench_law_list[i].id, &configs);
            if (st != AOCS_OK) {
                (void)fprintf(stderr, "bench_laws: %s init failed: %s\n", aocs_law_name(bench_law_list[i].id),
                              aocs_status_name(st));
                rc = 1;
            }
        }
    }

    if ((rc == 0) && (cg_steps > 0u)) {
        for (size_t i = 0u; i < BENCH_LAW_COUNT; ++i) {
            if (selected[i] != 0) {
                bench_ring_fill(bench_family_of(bench_law_list[i].ref_scenario), seed);
                rc = bench_callgrind(&bench_law_list[i], &configs, cg_steps, use_exec);
            }
        }
    } else if (rc == 0) {
        uint64_t warmup = (steps < BENCH_WARMUP_MAX) ? steps : BENCH_WARMUP_MAX;
        (void)printf("# bench_laws: real_t=%s steps=%llu ring=%u seed=%llu warmup=%llu clock=aocs_hal_time_ns "
                     "(CLOCK_MONOTONIC); percentiles by nearest rank, ns\n",
                     BENCH_REAL_NAME, (unsigned long long)steps,
                     (unsigned)BENCH_RING, (unsigned long long)seed, (unsigned long long)warmup);
        bench_print_header();
        bench_time_clock(steps);
        for (size_t i = 0u; i < BENCH_LAW_COUNT; ++i) {
            if ((any_selected == 0) || (selected[i] != 0)) {
                const bench_law_info_t *info = &bench_law_list[i];
                bench_ring_fill(bench_family_of(info->ref_scenario), seed);
                if (bench_time_law(info, steps, warmup) != 0) {
                    rc = 1;
                }
                if (bench_time_exec(info, &configs, steps, warmup) != 0) {
                    rc = 1;
                }
                (void)fflush(stdout);
            }
        }
    } else {
        /* init failed, reported above */
    }
    return rc;
}
