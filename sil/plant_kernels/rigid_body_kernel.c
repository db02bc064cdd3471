/*
 * aocs_rigid_body_kernel: the plant's attitude periods compiled (issue 24, docs/spec.md 5.13.1).
 *
 * One control period of the rigid body alone, n fixed RK4 substeps of length h with the torque T held:
 *
 *     J wdot = -w x (J w) + T + u_gg(q)          (SPEC 1.6; u_gg optional, SPEC 3.3)
 *     qdot   = 0.5 Xi(q) w                       (SPEC 1.2, scalar-last quaternion)
 *     u_gg   = c (R x Jg R),  R = A(q) d         (gravity gradient, a fixed direction d in N)
 *
 * It is the Python stepper of sil/aocs_plant/rigid_body.py (body_derivative, rk4_stepper) and the
 * gravity-gradient closure of sil/aocs_plant/effectors/gravity_gradient.py (gg_term) written again in C,
 * expression by expression in the same order (each C expression below parses to the same binary operations
 * as its Python twin; the build turns floating-point contraction off), so that a period gives the same
 * doubles, bit for bit: tests/python/aocs_plant/test_rigid_body_kernel.py checks it against the Python
 * stepper over random states and inertias. The Python code stays the definition and the fallback (no build);
 * this file only removes the interpreter's cost from the loop (about 6 us of a period, docs/benchmarks.md).
 *
 * The coupled period (CoupledStepper) is rigid_body.rk4_coupled_stepper over the plant's GENERAL effectors in the
 * same way: the body with the reaction wheels' axial momenta (effectors/reaction_wheels.py, derivative) and the
 * thrusters' impulse and propellant (effectors/thrusters.py, derivative), one RK4 over [q, w, x]:
 *
 *     Omega_i = h_i / Js_i - g_i . w,   tau_i = u_i - (b Omega_i + c tanh(Omega_i / Omega_eps))
 *                                       (u_i = 0 when u_i Omega_i > 0 and |Omega_i| >= Omega_max: the speed limit)
 *     body torque += -(w x Gs h) - Gs tau,   hdot_i = tau_i               (docs/spec.md 5.3)
 *     body torque += torque_b,   impulse' = A(q)^T force_b,   propellant' = mdot   (thrusters, held over the period)
 *
 * Python API (sil/aocs_plant/kernels.py):
 *     s = Stepper(J, Ji, gg)          J, Ji: row-major 9-sequences; gg: None or (c, (d1, d2, d3), Jg)
 *     q, w = s.period(q, w, h, n, T)  q: 4 floats, w and T: 3, h: float, n: substeps >= 1
 *     c = CoupledStepper(J, Ji, gg, effectors)   effectors: ("wheels", rows (g0, g1, g2, Js, Omega_max), b, c,
 *                                                Omega_eps) and/or ("thrusters",), in the plant's order
 *     q, w, x, cut = c.period(q, w, x, h, n, T, inputs)   inputs: the period's wheel motor torques, the thrusters'
 *                                                (mdot, force_b, torque_b); cut: bit i, wheel i cut at its limit
 * Bad arguments raise TypeError / ValueError naming the argument; non-finite values flow through as in Python.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>

typedef struct {
    double j[9];      /* inertia J (kg m^2), row-major */
    double ji[9];     /* its inverse */
    int diag;         /* J and Ji diagonal: body_derivative's diagonal variant */
    int has_gg;       /* a gravity-gradient term */
    double c;         /* its coefficient (1/s^2) */
    double d[3];      /* its direction in N */
    double jg[9];     /* the inertia it uses (the scenario's whole J) */
    int gg_diag;      /* Jg diagonal: gg_term's diagonal variant */
} Body;

typedef struct {
    PyObject_HEAD
    Body body;
} Stepper;

static int is_diagonal(const double m[9])
{
    return m[1] == 0.0 && m[2] == 0.0 && m[3] == 0.0 && m[5] == 0.0 && m[6] == 0.0 && m[7] == 0.0;
}

/* n doubles of a sequence, or -1 with an exception naming `what` */
static int read_doubles(PyObject *seq, Py_ssize_t n, double *out, const char *what)
{
    PyObject *fast = PySequence_Fast(seq, what);
    if (fast == NULL) {
        PyErr_Format(PyExc_TypeError, "%s: a sequence of %zd numbers", what, n);
        return -1;
    }
    if (PySequence_Fast_GET_SIZE(fast) != n) {
        PyErr_Format(PyExc_ValueError, "%s: %zd values, expected %zd", what, PySequence_Fast_GET_SIZE(fast), n);
        Py_DECREF(fast);
        return -1;
    }
    PyObject **items = PySequence_Fast_ITEMS(fast);
    for (Py_ssize_t i = 0; i < n; i++) {
        double v = PyFloat_AsDouble(items[i]);
        if (v == -1.0 && PyErr_Occurred()) {
            Py_DECREF(fast);
            PyErr_Format(PyExc_TypeError, "%s[%zd]: not a number", what, i);
            return -1;
        }
        out[i] = v;
    }
    Py_DECREF(fast);
    return 0;
}

/* v rotated by the quaternion q, as gg_term and Thrusters.derivative write it: sign -1 gives A(q) v (N to B), +1
 * A(q)^T v (B to N). (q4^2 - |e|^2) v + 2 (e . v) e + sign 2 q4 (e x v); with sign -1 the product (-2 q4) x is
 * exactly -(2 q4 x) and a + (-y) exactly a - y, so both are the Python expressions' doubles */
static void quat_rotate(const double q[4], const double v[3], double sign, double out[3])
{
    const double q1 = q[0], q2 = q[1], q3 = q[2], q4 = q[3], v1 = v[0], v2 = v[1], v3 = v[2];
    const double sq = q4 * q4 - (q1 * q1 + q2 * q2 + q3 * q3);
    const double vd = 2.0 * (q1 * v1 + q2 * v2 + q3 * v3);
    const double k = sign * (2.0 * q4);
    out[0] = sq * v1 + vd * q1 + k * (q2 * v3 - q3 * v2);
    out[1] = sq * v2 + vd * q2 + k * (q3 * v1 - q1 * v3);
    out[2] = sq * v3 + vd * q3 + k * (q1 * v2 - q2 * v1);
}

/* gg_term's g(q): c (R x Jg R), R = A(q) d */
static void gg_torque(const Body *s, const double q[4], double g[3])
{
    const double *jg = s->jg;
    const double c = s->c;
    double r[3];
    quat_rotate(q, s->d, -1.0, r);
    const double r1 = r[0], r2 = r[1], r3 = r[2];
    double g1, g2, g3;
    if (s->gg_diag) {
        g1 = jg[0] * r1;
        g2 = jg[4] * r2;
        g3 = jg[8] * r3;
    } else {
        g1 = jg[0] * r1 + jg[1] * r2 + jg[2] * r3;
        g2 = jg[3] * r1 + jg[4] * r2 + jg[5] * r3;
        g3 = jg[6] * r1 + jg[7] * r2 + jg[8] * r3;
    }
    g[0] = c * (r2 * g3 - r3 * g2);
    g[1] = c * (r3 * g1 - r1 * g3);
    g[2] = c * (r1 * g2 - r2 * g1);
}

/* body_derivative's f: y = (q1..q4, w1..w3) -> ydot */
static void derivative(const Body *s, const double y[7], const double t[3], double out[7])
{
    const double *j = s->j, *ji = s->ji;
    const double q1 = y[0], q2 = y[1], q3 = y[2], q4 = y[3], w1 = y[4], w2 = y[5], w3 = y[6];
    double hx, hy, hz, mx, my, mz;
    if (s->diag) {
        hx = j[0] * w1;
        hy = j[4] * w2;
        hz = j[8] * w3;
    } else {
        hx = j[0] * w1 + j[1] * w2 + j[2] * w3;
        hy = j[3] * w1 + j[4] * w2 + j[5] * w3;
        hz = j[6] * w1 + j[7] * w2 + j[8] * w3;
    }
    mx = t[0] - (w2 * hz - w3 * hy);
    my = t[1] - (w3 * hx - w1 * hz);
    mz = t[2] - (w1 * hy - w2 * hx);
    if (s->has_gg) {
        double g[3];
        gg_torque(s, y, g);
        mx = mx + g[0];
        my = my + g[1];
        mz = mz + g[2];
    }
    out[0] = 0.5 * (q4 * w1 - q3 * w2 + q2 * w3);
    out[1] = 0.5 * (q3 * w1 + q4 * w2 - q1 * w3);
    out[2] = 0.5 * (-q2 * w1 + q1 * w2 + q4 * w3);
    out[3] = -0.5 * (q1 * w1 + q2 * w2 + q3 * w3);
    if (s->diag) {
        out[4] = ji[0] * mx;
        out[5] = ji[4] * my;
        out[6] = ji[8] * mz;
    } else {
        out[4] = ji[0] * mx + ji[1] * my + ji[2] * mz;
        out[5] = ji[3] * mx + ji[4] * my + ji[5] * mz;
        out[6] = ji[6] * mx + ji[7] * my + ji[8] * mz;
    }
}

/* the state of an RK4 stage: yst = y + step ky (the body), xst = x + step kx (the m effector states) */
static void stage_state(const double y[7], const double *x, int m, double step, const double ky[7], const double *kx,
                        double yst[7], double *xst)
{
    for (int i = 0; i < 7; i++) {
        yst[i] = y[i] + step * ky[i];
    }
    for (int i = 0; i < m; i++) {
        xst[i] = x[i] + step * kx[i];
    }
}

/* the RK4 update of n values, v += h/6 (ka + 2 (kb + kc) + kd) */
static void rk4_update(double *v, int n, double h, const double *ka, const double *kb, const double *kc,
                       const double *kd)
{
    const double h6 = h / 6.0;
    for (int i = 0; i < n; i++) {
        v[i] = v[i] + h6 * (ka[i] + 2.0 * (kb[i] + kc[i]) + kd[i]);
    }
}

/* q (y[0..3]) renormalised: q / sqrt(q . q) as 1 / sqrt times each component */
static void renormalise(double y[7])
{
    const double nrm = 1.0 / sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2] + y[3] * y[3]);
    for (int i = 0; i < 4; i++) {
        y[i] = y[i] * nrm;
    }
}

/* rk4_stepper's step: y advanced by h, q renormalised */
static void rk4_substep(const Body *s, double y[7], double h, const double t[3])
{
    double a[7], b[7], c[7], d[7], st[7];
    const double hh = 0.5 * h;
    derivative(s, y, t, a);
    stage_state(y, NULL, 0, hh, a, NULL, st, NULL);
    derivative(s, st, t, b);
    stage_state(y, NULL, 0, hh, b, NULL, st, NULL);
    derivative(s, st, t, c);
    stage_state(y, NULL, 0, h, c, NULL, st, NULL);
    derivative(s, st, t, d);
    rk4_update(y, 7, h, a, b, c, d);
    renormalise(y);
}

/* the substep length h (a number) and count n (an integer, at least 1): 0, or -1 with the exception set */
static int read_h_n(PyObject *h_obj, PyObject *n_obj, double *h, long *n)
{
    *h = PyFloat_AsDouble(h_obj);
    if (*h == -1.0 && PyErr_Occurred()) {
        PyErr_SetString(PyExc_TypeError, "h: not a number");
        return -1;
    }
    *n = PyLong_AsLong(n_obj);
    if (*n == -1 && PyErr_Occurred()) {
        PyErr_SetString(PyExc_TypeError, "n: not an integer");
        return -1;
    }
    if (*n < 1) {
        PyErr_Format(PyExc_ValueError, "n: %ld substeps, at least 1", *n);
        return -1;
    }
    return 0;
}

static PyObject *tuple_of(const double *v, Py_ssize_t n)
{
    PyObject *t = PyTuple_New(n);
    if (t == NULL) {
        return NULL;
    }
    for (Py_ssize_t i = 0; i < n; i++) {
        PyObject *f = PyFloat_FromDouble(v[i]);
        if (f == NULL) {
            Py_DECREF(t);
            return NULL;
        }
        PyTuple_SET_ITEM(t, i, f);
    }
    return t;
}

static PyObject *Stepper_period(Stepper *self, PyObject *const *args, Py_ssize_t nargs)
{
    double y[7], t[3];
    if (nargs != 5) {
        PyErr_Format(PyExc_TypeError, "period(q, w, h, n, torque): 5 arguments, got %zd", nargs);
        return NULL;
    }
    if (read_doubles(args[0], 4, y, "q") < 0 || read_doubles(args[1], 3, y + 4, "w") < 0
        || read_doubles(args[4], 3, t, "torque") < 0) {
        return NULL;
    }
    double h;
    long n;
    if (read_h_n(args[2], args[3], &h, &n) < 0) {
        return NULL;
    }
    for (long i = 0; i < n; i++) {
        rk4_substep(&self->body, y, h, t);
    }
    PyObject *q = tuple_of(y, 4);
    PyObject *w = q == NULL ? NULL : tuple_of(y + 4, 3);
    if (w == NULL) {
        Py_XDECREF(q);
        return NULL;
    }
    return Py_BuildValue("(NN)", q, w);
}

/* Body from (J, Ji, gg): 0, or -1 with the exception set */
static int read_body(Body *b, PyObject *j, PyObject *ji, PyObject *gg)
{
    if (read_doubles(j, 9, b->j, "J") < 0 || read_doubles(ji, 9, b->ji, "Ji") < 0) {
        return -1;
    }
    b->diag = is_diagonal(b->j) && is_diagonal(b->ji);
    b->has_gg = gg != Py_None;
    if (b->has_gg) {
        PyObject *c, *d, *jg;
        if (!PyTuple_Check(gg) || !PyArg_ParseTuple(gg, "OOO", &c, &d, &jg)) {
            PyErr_Clear();
            PyErr_SetString(PyExc_TypeError, "gg: None or a tuple (c, (d1, d2, d3), Jg)");
            return -1;
        }
        b->c = PyFloat_AsDouble(c);
        if (b->c == -1.0 && PyErr_Occurred()) {
            PyErr_SetString(PyExc_TypeError, "gg c: not a number");
            return -1;
        }
        if (read_doubles(d, 3, b->d, "gg d") < 0 || read_doubles(jg, 9, b->jg, "gg Jg") < 0) {
            return -1;
        }
        b->gg_diag = is_diagonal(b->jg);
    }
    return 0;
}

static int Stepper_init(Stepper *self, PyObject *args, PyObject *kwds)
{
    static char *names[] = {"J", "Ji", "gg", NULL};
    PyObject *j, *ji, *gg = Py_None;
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "OO|O", names, &j, &ji, &gg)) {
        return -1;
    }
    return read_body(&self->body, j, ji, gg);
}

static PyMethodDef Stepper_methods[] = {
    {"period", (PyCFunction)(void (*)(void))Stepper_period, METH_FASTCALL,
     "period(q, w, h, n, torque) -> (q, w): n RK4 substeps of length h, the torque held, q renormalised"},
    {NULL, NULL, 0, NULL}
};

static PyTypeObject StepperType = {
    PyVarObject_HEAD_INIT(NULL, 0)
    .tp_name = "aocs_rigid_body_kernel.Stepper",
    .tp_basicsize = sizeof(Stepper),
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "Stepper(J, Ji, gg=None): the rigid body's RK4 period (rigid_body.py's fast path) compiled",
    .tp_new = PyType_GenericNew,
    .tp_init = (initproc)Stepper_init,
    .tp_methods = Stepper_methods,
};

/* ---- the coupled period: the body with effector states (Plant._segment_general, rk4_coupled_stepper) ---- */

#define MAX_GENERAL 4     /* GENERAL effectors compiled at once */
#define MAX_WHEELS 6      /* reaction_wheels.MAX_WHEELS, the flight software's array */
#define MAX_STATE (MAX_WHEELS + 4 * (MAX_GENERAL - 1))

enum { EFF_WHEELS = 1, EFF_THRUSTERS = 2 };

typedef struct {
    int kind;                 /* EFF_WHEELS | EFF_THRUSTERS */
    int lo, n;                /* its slice of the effector state x */
    /* wheels (reaction_wheels.py derivative): rows g_i, Js_i, Omega_max_i; friction b, c, Omega_eps */
    double g[MAX_WHEELS][3], js[MAX_WHEELS], wmax[MAX_WHEELS], b, c, eps;
    /* the period's input: wheels, the motor torques held; thrusters, mdot, force_b, torque_b */
    double u[MAX_WHEELS], mdot, force[3], torque[3];
} General;

typedef struct {
    PyObject_HEAD
    Body body;
    int count;                /* GENERAL effectors, in the plant's order */
    int size;                 /* the length of x */
    General eff[MAX_GENERAL];
} CoupledStepper;

/* ReactionWheels.derivative: the body torque (-(w x Gs h) - Gs tau) and tau into xd; *cut gets the speed-limit bits */
static void wheels_derivative(const General *e, const double body[7], const double *x, double torque[3],
                              double *xd, unsigned *cut)
{
    const double w1 = body[4], w2 = body[5], w3 = body[6];
    double hx = 0.0, hy = 0.0, hz = 0.0, gx = 0.0, gy = 0.0, gz = 0.0;
    for (int i = 0; i < e->n; i++) {
        const double g0 = e->g[i][0], g1 = e->g[i][1], g2 = e->g[i][2];
        const double h = x[i];
        const double o = h / e->js[i] - (g0 * w1 + g1 * w2 + g2 * w3);
        double u = e->u[i];
        if (u * o > 0.0 && fabs(o) >= e->wmax[i]) {
            u = 0.0;
            *cut |= 1u << i;
        }
        const double ti = u - (e->b * o + e->c * tanh(o / e->eps));
        xd[i] = ti;
        hx += g0 * h;
        hy += g1 * h;
        hz += g2 * h;
        gx += g0 * ti;
        gy += g1 * ti;
        gz += g2 * ti;
    }
    torque[0] = -(w2 * hz - w3 * hy) - gx;
    torque[1] = -(w3 * hx - w1 * hz) - gy;
    torque[2] = -(w1 * hy - w2 * hx) - gz;
}

/* Thrusters.derivative: the held torque, and (A(q)^T f, mdot) */
static void thrusters_derivative(const General *e, const double body[7], double torque[3], double *xd)
{
    if (e->mdot == 0.0) {
        torque[0] = torque[1] = torque[2] = 0.0;
        xd[0] = xd[1] = xd[2] = xd[3] = 0.0;
        return;
    }
    quat_rotate(body, e->force, 1.0, xd);   /* A(q)^T f: the force in N */
    xd[3] = e->mdot;
    torque[0] = e->torque[0];
    torque[1] = e->torque[1];
    torque[2] = e->torque[2];
}

/* G of rk4_coupled_stepper: one effector's derivative as it is, several summed from 0.0 (Plant._effector_rhs) */
static void general_rhs(const CoupledStepper *s, const double body[7], const double *x, double torque[3],
                        double *xd, unsigned *cut)
{
    if (s->count == 1) {
        const General *e = &s->eff[0];
        if (e->kind == EFF_WHEELS) {
            wheels_derivative(e, body, x, torque, xd, cut);
        } else {
            thrusters_derivative(e, body, torque, xd);
        }
        return;
    }
    torque[0] = torque[1] = torque[2] = 0.0;
    for (int k = 0; k < s->count; k++) {
        const General *e = &s->eff[k];
        double a[3];
        if (e->kind == EFF_WHEELS) {
            wheels_derivative(e, body, x + e->lo, a, xd + e->lo, cut);
        } else {
            thrusters_derivative(e, body, a, xd + e->lo);
        }
        torque[0] += a[0];
        torque[1] += a[1];
        torque[2] += a[2];
    }
}

/* one stage of rk4_coupled_stepper: the effectors' derivative kx and torque, then the body's ky with the held torque
 * t plus theirs, at (yst, xst) */
static void coupled_stage(const CoupledStepper *s, const double yst[7], const double *xst, const double t[3],
                          double ky[7], double *kx, unsigned *cut)
{
    double e[3], tt[3];
    general_rhs(s, yst, xst, e, kx, cut);
    tt[0] = t[0] + e[0];
    tt[1] = t[1] + e[1];
    tt[2] = t[2] + e[2];
    derivative(&s->body, yst, tt, ky);
}

/* rk4_coupled_stepper's step: y = (q, w) and x advanced by h, q renormalised */
static void rk4_coupled_substep(const CoupledStepper *s, double y[7], double *x, double h, const double t[3],
                                unsigned *cut)
{
    const int m = s->size;
    double a[7], bb[7], c[7], d[7], st[7];
    double ka[MAX_STATE], kb[MAX_STATE], kc[MAX_STATE], kd[MAX_STATE], xs[MAX_STATE];
    const double hh = 0.5 * h;
    coupled_stage(s, y, x, t, a, ka, cut);
    stage_state(y, x, m, hh, a, ka, st, xs);
    coupled_stage(s, st, xs, t, bb, kb, cut);
    stage_state(y, x, m, hh, bb, kb, st, xs);
    coupled_stage(s, st, xs, t, c, kc, cut);
    stage_state(y, x, m, h, c, kc, st, xs);
    coupled_stage(s, st, xs, t, d, kd, cut);
    rk4_update(y, 7, h, a, bb, c, d);
    rk4_update(x, m, h, ka, kb, kc, kd);
    renormalise(y);
}

/* one static effector spec: ("wheels", ((g0, g1, g2, Js, Omega_max), ...), b, c, eps) or ("thrusters",) */
static int read_general(General *e, PyObject *spec, int index)
{
    PyObject *kind;
    if (!PyTuple_Check(spec) || PyTuple_GET_SIZE(spec) < 1 || !PyUnicode_Check(kind = PyTuple_GET_ITEM(spec, 0))) {
        PyErr_Format(PyExc_TypeError, "effectors[%d]: a tuple whose first item is its kind", index);
        return -1;
    }
    if (PyUnicode_CompareWithASCIIString(kind, "thrusters") == 0 && PyTuple_GET_SIZE(spec) == 1) {
        e->kind = EFF_THRUSTERS;
        e->n = 4;
        return 0;
    }
    if (PyUnicode_CompareWithASCIIString(kind, "wheels") != 0 || PyTuple_GET_SIZE(spec) != 5) {
        PyErr_Format(PyExc_ValueError, "effectors[%d]: (\"wheels\", rows, b, c, eps) or (\"thrusters\",)", index);
        return -1;
    }
    e->kind = EFF_WHEELS;
    PyObject *rows = PySequence_Fast(PyTuple_GET_ITEM(spec, 1), "wheel rows");
    if (rows == NULL) {
        return -1;
    }
    const Py_ssize_t n = PySequence_Fast_GET_SIZE(rows);
    if (n < 1 || n > MAX_WHEELS) {
        Py_DECREF(rows);
        PyErr_Format(PyExc_ValueError, "effectors[%d]: %zd wheels, 1 to %d", index, n, MAX_WHEELS);
        return -1;
    }
    e->n = (int)n;
    for (Py_ssize_t i = 0; i < n; i++) {
        double r[5];
        if (read_doubles(PySequence_Fast_GET_ITEM(rows, i), 5, r, "wheel row (g0, g1, g2, Js, Omega_max)") < 0) {
            Py_DECREF(rows);
            return -1;
        }
        e->g[i][0] = r[0];
        e->g[i][1] = r[1];
        e->g[i][2] = r[2];
        e->js[i] = r[3];
        e->wmax[i] = r[4];
    }
    Py_DECREF(rows);
    double f[3];
    PyObject *tail = PyTuple_GetSlice(spec, 2, 5);
    const int rc = tail == NULL ? -1 : read_doubles(tail, 3, f, "wheel friction (b, c, eps)");
    Py_XDECREF(tail);
    if (rc < 0) {
        return -1;
    }
    e->b = f[0];
    e->c = f[1];
    e->eps = f[2];
    return 0;
}

static int CoupledStepper_init(CoupledStepper *self, PyObject *args, PyObject *kwds)
{
    static char *names[] = {"J", "Ji", "gg", "effectors", NULL};
    PyObject *j, *ji, *gg, *effs;
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "OOOO", names, &j, &ji, &gg, &effs)) {
        return -1;
    }
    if (read_body(&self->body, j, ji, gg) < 0) {
        return -1;
    }
    if (!PyTuple_Check(effs) || PyTuple_GET_SIZE(effs) < 1 || PyTuple_GET_SIZE(effs) > MAX_GENERAL) {
        PyErr_Format(PyExc_ValueError, "effectors: a tuple of 1 to %d effector specs", MAX_GENERAL);
        return -1;
    }
    int lo = 0, wheels = 0;
    self->count = (int)PyTuple_GET_SIZE(effs);
    for (int k = 0; k < self->count; k++) {
        General *e = &self->eff[k];
        if (read_general(e, PyTuple_GET_ITEM(effs, k), k) < 0) {
            return -1;
        }
        wheels += e->kind == EFF_WHEELS;
        e->lo = lo;
        lo += e->n;
    }
    if (wheels > 1) {
        PyErr_SetString(PyExc_ValueError, "effectors: one wheel array at most");
        return -1;
    }
    self->size = lo;
    return 0;
}

/* the period's inputs, one per effector: wheels, the n motor torques; thrusters, (mdot, f1, f2, f3, t1, t2, t3) */
static int read_inputs(CoupledStepper *self, PyObject *inputs)
{
    PyObject *fast = PySequence_Fast(inputs, "inputs");
    if (fast == NULL) {
        return -1;
    }
    if (PySequence_Fast_GET_SIZE(fast) != self->count) {
        PyErr_Format(PyExc_ValueError, "inputs: %zd, one per effector (%d)", PySequence_Fast_GET_SIZE(fast),
                     self->count);
        Py_DECREF(fast);
        return -1;
    }
    int rc = 0;
    for (int k = 0; k < self->count && rc == 0; k++) {
        General *e = &self->eff[k];
        PyObject *item = PySequence_Fast_GET_ITEM(fast, k);
        if (e->kind == EFF_WHEELS) {
            rc = read_doubles(item, e->n, e->u, "wheel motor torques");
        } else {
            double v[7];
            rc = read_doubles(item, 7, v, "thrusters (mdot, force, torque)");
            if (rc == 0) {
                e->mdot = v[0];
                e->force[0] = v[1]; e->force[1] = v[2]; e->force[2] = v[3];
                e->torque[0] = v[4]; e->torque[1] = v[5]; e->torque[2] = v[6];
            }
        }
    }
    Py_DECREF(fast);
    return rc;
}

static PyObject *CoupledStepper_period(CoupledStepper *self, PyObject *const *args, Py_ssize_t nargs)
{
    double y[7], t[3], x[MAX_STATE];
    unsigned cut = 0u;
    if (nargs != 7) {
        PyErr_Format(PyExc_TypeError, "period(q, w, x, h, n, torque, inputs): 7 arguments, got %zd", nargs);
        return NULL;
    }
    if (read_doubles(args[0], 4, y, "q") < 0 || read_doubles(args[1], 3, y + 4, "w") < 0
        || read_doubles(args[2], self->size, x, "x") < 0 || read_doubles(args[5], 3, t, "torque") < 0
        || read_inputs(self, args[6]) < 0) {
        return NULL;
    }
    double h;
    long n;
    if (read_h_n(args[3], args[4], &h, &n) < 0) {
        return NULL;
    }
    for (long i = 0; i < n; i++) {
        rk4_coupled_substep(self, y, x, h, t, &cut);
    }
    PyObject *q = tuple_of(y, 4);
    PyObject *w = q == NULL ? NULL : tuple_of(y + 4, 3);
    PyObject *xs = w == NULL ? NULL : tuple_of(x, self->size);
    if (xs == NULL) {
        Py_XDECREF(q);
        Py_XDECREF(w);
        return NULL;
    }
    return Py_BuildValue("(NNNI)", q, w, xs, cut);
}

static PyMethodDef CoupledStepper_methods[] = {
    {"period", (PyCFunction)(void (*)(void))CoupledStepper_period, METH_FASTCALL,
     "period(q, w, x, h, n, torque, inputs) -> (q, w, x, cut): n coupled RK4 substeps; cut: the wheels whose motor "
     "a stage cut at the speed limit (bit i)"},
    {NULL, NULL, 0, NULL}
};

static PyTypeObject CoupledStepperType = {
    PyVarObject_HEAD_INIT(NULL, 0)
    .tp_name = "aocs_rigid_body_kernel.CoupledStepper",
    .tp_basicsize = sizeof(CoupledStepper),
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "CoupledStepper(J, Ji, gg, effectors): the body with wheels and thrusters (rk4_coupled_stepper) compiled",
    .tp_new = PyType_GenericNew,
    .tp_init = (initproc)CoupledStepper_init,
    .tp_methods = CoupledStepper_methods,
};

static struct PyModuleDef kernel_module = {
    PyModuleDef_HEAD_INIT, "aocs_rigid_body_kernel",
    "The plant's rigid-body RK4 period, compiled (sil/plant_kernels/rigid_body_kernel.c)", -1,
    NULL, NULL, NULL, NULL, NULL
};

PyMODINIT_FUNC PyInit_aocs_rigid_body_kernel(void)
{
    if (PyType_Ready(&StepperType) < 0 || PyType_Ready(&CoupledStepperType) < 0) {
        return NULL;
    }
    PyObject *m = PyModule_Create(&kernel_module);
    if (m == NULL) {
        return NULL;
    }
    Py_INCREF(&StepperType);
    if (PyModule_AddObject(m, "Stepper", (PyObject *)&StepperType) < 0) {
        Py_DECREF(&StepperType);
        Py_DECREF(m);
        return NULL;
    }
    Py_INCREF(&CoupledStepperType);
    if (PyModule_AddObject(m, "CoupledStepper", (PyObject *)&CoupledStepperType) < 0) {
        Py_DECREF(&CoupledStepperType);
        Py_DECREF(m);
        return NULL;
    }
    return m;
}
