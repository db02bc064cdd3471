/*
 * aocs_rigid_body_kernel: the plant's attitude fast path compiled (issue 24, docs/spec.md 3.8).
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
 * Python API (sil/aocs_plant/rigid_body.py, compiled_period):
 *     s = Stepper(J, Ji, gg)          J, Ji: row-major 9-sequences; gg: None or (c, (d1, d2, d3), Jg)
 *     q, w = s.period(q, w, h, n, T)  q: 4 floats, w and T: 3, h: float, n: substeps >= 1
 * Bad arguments raise TypeError / ValueError naming the argument; non-finite values flow through as in Python.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>

typedef struct {
    PyObject_HEAD
    double j[9];      /* inertia J (kg m^2), row-major */
    double ji[9];     /* its inverse */
    int diag;         /* J and Ji diagonal: body_derivative's diagonal variant */
    int has_gg;       /* a gravity-gradient term */
    double c;         /* its coefficient (1/s^2) */
    double d[3];      /* its direction in N */
    double jg[9];     /* the inertia it uses (the scenario's whole J) */
    int gg_diag;      /* Jg diagonal: gg_term's diagonal variant */
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

/* gg_term's g(q1, q2, q3, q4) */
static void gg_torque(const Stepper *s, double q1, double q2, double q3, double q4, double g[3])
{
    const double *jg = s->jg;
    const double d1 = s->d[0], d2 = s->d[1], d3 = s->d[2], c = s->c;
    double sq = q4 * q4 - (q1 * q1 + q2 * q2 + q3 * q3);
    double vd = 2.0 * (q1 * d1 + q2 * d2 + q3 * d3);
    double k = 2.0 * q4;
    double r1 = sq * d1 + vd * q1 - k * (q2 * d3 - q3 * d2);
    double r2 = sq * d2 + vd * q2 - k * (q3 * d1 - q1 * d3);
    double r3 = sq * d3 + vd * q3 - k * (q1 * d2 - q2 * d1);
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
static void derivative(const Stepper *s, const double y[7], const double t[3], double out[7])
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
        gg_torque(s, q1, q2, q3, q4, g);
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

/* rk4_stepper's step: y advanced by h, q renormalised */
static void rk4_substep(const Stepper *s, double y[7], double h, const double t[3])
{
    double a[7], b[7], c[7], d[7], st[7];
    const double hh = 0.5 * h;
    derivative(s, y, t, a);
    for (int i = 0; i < 7; i++) {
        st[i] = y[i] + hh * a[i];
    }
    derivative(s, st, t, b);
    for (int i = 0; i < 7; i++) {
        st[i] = y[i] + hh * b[i];
    }
    derivative(s, st, t, c);
    for (int i = 0; i < 7; i++) {
        st[i] = y[i] + h * c[i];
    }
    derivative(s, st, t, d);
    const double h6 = h / 6.0;
    for (int i = 0; i < 7; i++) {
        y[i] = y[i] + h6 * (a[i] + 2.0 * (b[i] + c[i]) + d[i]);
    }
    const double nrm = 1.0 / sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2] + y[3] * y[3]);
    for (int i = 0; i < 4; i++) {
        y[i] = y[i] * nrm;
    }
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
    const double h = PyFloat_AsDouble(args[2]);
    if (h == -1.0 && PyErr_Occurred()) {
        PyErr_SetString(PyExc_TypeError, "h: not a number");
        return NULL;
    }
    const long n = PyLong_AsLong(args[3]);
    if (n == -1 && PyErr_Occurred()) {
        PyErr_SetString(PyExc_TypeError, "n: not an integer");
        return NULL;
    }
    if (n < 1) {
        PyErr_Format(PyExc_ValueError, "n: %ld substeps, at least 1", n);
        return NULL;
    }
    for (long i = 0; i < n; i++) {
        rk4_substep(self, y, h, t);
    }
    PyObject *q = tuple_of(y, 4);
    PyObject *w = q == NULL ? NULL : tuple_of(y + 4, 3);
    if (w == NULL) {
        Py_XDECREF(q);
        return NULL;
    }
    PyObject *out = PyTuple_Pack(2, q, w);
    Py_DECREF(q);
    Py_DECREF(w);
    return out;
}

static int Stepper_init(Stepper *self, PyObject *args, PyObject *kwds)
{
    static char *names[] = {"J", "Ji", "gg", NULL};
    PyObject *j, *ji, *gg = Py_None;
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "OO|O", names, &j, &ji, &gg)) {
        return -1;
    }
    if (read_doubles(j, 9, self->j, "J") < 0 || read_doubles(ji, 9, self->ji, "Ji") < 0) {
        return -1;
    }
    self->diag = is_diagonal(self->j) && is_diagonal(self->ji);
    self->has_gg = gg != Py_None;
    if (self->has_gg) {
        PyObject *c, *d, *jg;
        if (!PyTuple_Check(gg) || !PyArg_ParseTuple(gg, "OOO", &c, &d, &jg)) {
            PyErr_Clear();
            PyErr_SetString(PyExc_TypeError, "gg: None or a tuple (c, (d1, d2, d3), Jg)");
            return -1;
        }
        self->c = PyFloat_AsDouble(c);
        if (self->c == -1.0 && PyErr_Occurred()) {
            PyErr_SetString(PyExc_TypeError, "gg c: not a number");
            return -1;
        }
        if (read_doubles(d, 3, self->d, "gg d") < 0 || read_doubles(jg, 9, self->jg, "gg Jg") < 0) {
            return -1;
        }
        self->gg_diag = is_diagonal(self->jg);
    }
    return 0;
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

static struct PyModuleDef kernel_module = {
    PyModuleDef_HEAD_INIT, "aocs_rigid_body_kernel",
    "The plant's rigid-body RK4 period, compiled (sil/plant_kernels/rigid_body_kernel.c)", -1,
    NULL, NULL, NULL, NULL, NULL
};

PyMODINIT_FUNC PyInit_aocs_rigid_body_kernel(void)
{
    if (PyType_Ready(&StepperType) < 0) {
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
    return m;
}
