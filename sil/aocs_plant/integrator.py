"""RK4 over a concatenated state: the body and every effector state together.

rk4(F, t, y, h, *args) advances y' = F(t, y, *args) by one classical RK4 step
on a tuple of floats. The stage arithmetic (y + h/2 k, y + h k) and the
weights h/6 (k1 + 2 (k2 + k3) + k4) are written exactly as in the fast
attitude stepper (rigid_body.rk4_stepper) and NonlinearOrbit.propagate, so
that with no effector state the body components come out identical. The
plant uses it only when an effector has state or a state-dependent
contribution (Form.GENERAL); the command is held by the caller through args.
"""
from __future__ import annotations


def rk4(F, t, y, h, *args):
    hh = 0.5 * h
    a = F(t, y, *args)
    b = F(t + hh, tuple([v + hh * k for v, k in zip(y, a)]), *args)
    c = F(t + hh, tuple([v + hh * k for v, k in zip(y, b)]), *args)
    d = F(t + h, tuple([v + h * k for v, k in zip(y, c)]), *args)
    h6 = h / 6.0
    return tuple([v + h6 * (k1 + 2.0 * (k2 + k3) + k4) for v, k1, k2, k3, k4 in zip(y, a, b, c, d)])
