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
#include "rigid_body_core.h"

typedef struct {
    PyObject_HEAD
    Body body;
} Stepper;

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
