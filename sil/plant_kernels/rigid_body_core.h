/*
 * The rigid body's period in C, shared by the plant's compiled kernels (rigid_body_kernel.c: the periods alone;
 * direct_loop_kernel.c: the whole lockstep period of the in-process transport). Each function is the Python
 * expression of sil/aocs_plant/rigid_body.py (body_derivative, rk4_stepper) and effectors/gravity_gradient.py
 * (gg_term) written again in C, in the same order, so a period gives the same doubles bit for bit (the build turns
 * floating-point contraction off); rigid_body_kernel.c's header comment has the equations, docs/spec.md 5.13.1
 * the contract.
 */
#ifndef AOCS_RIGID_BODY_CORE_H
#define AOCS_RIGID_BODY_CORE_H

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

static inline int is_diagonal(const double m[9])
{
    return m[1] == 0.0 && m[2] == 0.0 && m[3] == 0.0 && m[5] == 0.0 && m[6] == 0.0 && m[7] == 0.0;
}

/* n doubles of a sequence, or -1 with an exception naming `what` */
static inline int read_doubles(PyObject *seq, Py_ssize_t n, double *out, const char *what)
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
static inline void quat_rotate(const double q[4], const double v[3], double sign, double out[3])
{
    const double q1 = q[0], q2 = q[1], q3 = q[2], q4 = q[3], v1 = v[0], v2 = v[1], v3 = v[2];
    const double sq = q4 * q4 - (q1 * q1 + q2 * q2 + q3 * q3);
    const double vd = 2.0 * (q1 * v1 + q2 * v2 + q3 * v3);
    const double k = sign * (2.0 * q4);
    out[0] = sq * v1 + vd * q1 + k * (q2 * v3 - q3 * v2);
    out[1] = sq * v2 + vd * q2 + k * (q3 * v1 - q1 * v3);
    out[2] = sq * v3 + vd * q3 + k * (q1 * v2 - q2 * v1);
}

/* out = m v, m row-major; a diagonal m as Python's diagonal variants write it (m_ii v_i, no zero terms added) */
static inline void mat_vec(const double m[9], int diag, double v1, double v2, double v3, double out[3])
{
    if (diag) {
        out[0] = m[0] * v1;
        out[1] = m[4] * v2;
        out[2] = m[8] * v3;
    } else {
        out[0] = m[0] * v1 + m[1] * v2 + m[2] * v3;
        out[1] = m[3] * v1 + m[4] * v2 + m[5] * v3;
        out[2] = m[6] * v1 + m[7] * v2 + m[8] * v3;
    }
}

/* gg_term's g(q): c (R x Jg R), R = A(q) d */
static inline void gg_torque(const Body *s, const double q[4], double g[3])
{
    const double c = s->c;
    double r[3], jr[3];
    quat_rotate(q, s->d, -1.0, r);
    const double r1 = r[0], r2 = r[1], r3 = r[2];
    mat_vec(s->jg, s->gg_diag, r1, r2, r3, jr);
    const double g1 = jr[0], g2 = jr[1], g3 = jr[2];
    g[0] = c * (r2 * g3 - r3 * g2);
    g[1] = c * (r3 * g1 - r1 * g3);
    g[2] = c * (r1 * g2 - r2 * g1);
}

/* body_derivative's f: y = (q1..q4, w1..w3) -> ydot */
static inline void derivative(const Body *s, const double y[7], const double t[3], double out[7])
{
    const double q1 = y[0], q2 = y[1], q3 = y[2], q4 = y[3], w1 = y[4], w2 = y[5], w3 = y[6];
    double h[3], mx, my, mz;
    mat_vec(s->j, s->diag, w1, w2, w3, h);
    const double hx = h[0], hy = h[1], hz = h[2];
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
    mat_vec(s->ji, s->diag, mx, my, mz, out + 4);
}

/* the state of an RK4 stage: yst = y + step ky (the body), xst = x + step kx (the m effector states) */
static inline void stage_state(const double y[7], const double *x, int m, double step, const double ky[7],
                               const double *kx, double yst[7], double *xst)
{
    for (int i = 0; i < 7; i++) {
        yst[i] = y[i] + step * ky[i];
    }
    for (int i = 0; i < m; i++) {
        xst[i] = x[i] + step * kx[i];
    }
}

/* the RK4 update of n values, v += h/6 (ka + 2 (kb + kc) + kd) */
static inline void rk4_update(double *v, int n, double h, const double *ka, const double *kb,
                              const double *kc, const double *kd)
{
    const double h6 = h / 6.0;
    for (int i = 0; i < n; i++) {
        v[i] = v[i] + h6 * (ka[i] + 2.0 * (kb[i] + kc[i]) + kd[i]);
    }
}

/* q (y[0..3]) renormalised: q / sqrt(q . q) as 1 / sqrt times each component */
static inline void renormalise(double y[7])
{
    const double nrm = 1.0 / sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2] + y[3] * y[3]);
    for (int i = 0; i < 4; i++) {
        y[i] = y[i] * nrm;
    }
}

/* rk4_stepper's step: y advanced by h, q renormalised */
static inline void rk4_substep(const Body *s, double y[7], double h, const double t[3])
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

static inline PyObject *tuple_of(const double *v, Py_ssize_t n)
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

/* Body from (J, Ji, gg): 0, or -1 with the exception set */
static inline int read_body(Body *b, PyObject *j, PyObject *ji, PyObject *gg)
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

#endif /* AOCS_RIGID_BODY_CORE_H */
