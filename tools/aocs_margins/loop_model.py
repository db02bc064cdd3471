"""The attitude loop broken at the plant input, as python-control models (docs/spec.md, "Stability margins").

    plant      x' = A x + B e,  y = x              (the rigid body about the hold; continuous)
    hold       e held over each control period     (zero-order hold: control.c2d(.., "zoh"))
    law        u(k) = K(z) y(k)                    (law_models.LinearLaw, the firmware's discrete form)
    delay      u applied `delay` periods later     (z^-delay: the computation delay)
    loop       L(z) = -z^-delay K(z) P_zoh(z)      (3 x 3; e = d + u_applied, so u_applied = -L e)

so that python-control's negative-feedback convention (S = (I + L)^-1) holds. Plants:

    rotation   y = [theta; we] about a target at rest (irassi_*): A = [[0, I], [0, 0]], B = [0; J^-1]
               (the gyroscopic term w x J w is second order at rest; the L2 gravity-gradient stiffness,
               ~1e-14 /s^2, is below anything the loop resolves);
    euler      y = [roll pitch yaw, Euler rates] about the LVLH frame (geo_hinf): the linearised
               Earth-pointing model of SPEC 2.6 with gravity gradient and orbit-rate coupling
               (aocs_design.models.hinf_model, the model the H-infinity gain was designed on).

The loop at one axis (loop-at-a-time) is the 1 x 1 transfer from the plant input i to the applied
command i with the loops of the other two axes closed: what an injection at axis i measures.
"""
from __future__ import annotations

from dataclasses import dataclass

import control
import numpy as np

from aocs_design.models import hinf_model

from .law_models import LinearLaw

AXES = ("x", "y", "z")


@dataclass(frozen=True)
class Plant:
    a: np.ndarray       # (6, 6)
    b: np.ndarray       # (6, 3)
    output: str         # "rotation" | "euler"


def plant(sc, output: str) -> Plant:
    """The scenario's rigid body linearised about its hold, state = the law's input y."""
    j = np.asarray(sc.attitude.inertia, float)
    if output == "euler":
        w0 = -float(sc.target.wd[1])
        m = hinf_model(j[0, 0], j[1, 1], j[2, 2], w0)
        return Plant(m.a, m.b2, output)
    a = np.zeros((6, 6))
    a[0:3, 3:6] = np.eye(3)
    b = np.vstack([np.zeros((3, 3)), np.linalg.inv(j)])
    return Plant(a, b, output)


def controller(law: LinearLaw, dt: float | None) -> control.StateSpace:
    """K(z) (dt given: the firmware's forward-Euler integrator) or K(s) (dt None)."""
    nz = law.states
    if dt is None:
        return control.ss(np.zeros((nz, nz)), law.bc, law.cc, law.dc)
    return control.ss(np.eye(nz), dt * law.bc, law.cc, law.dc, dt)


def delay_block(periods: int, dt: float, n: int = 3) -> control.StateSpace:
    """z^-periods on n channels."""
    if periods == 0:
        return control.ss(np.zeros((0, 0)), np.zeros((0, n)), np.zeros((n, 0)), np.eye(n), dt)
    m = periods * n
    a = np.zeros((m, m))
    a[n:, :-n] = np.eye(m - n)
    b = np.zeros((m, n))
    b[:n] = np.eye(n)
    c = np.zeros((n, m))
    c[:, -n:] = np.eye(n)
    return control.ss(a, b, c, np.zeros((n, n)), dt)


def loop(p: Plant, law: LinearLaw, dt: float | None, delay: int = 1) -> control.StateSpace:
    """L (3 x 3) broken at the plant input: discrete with ZOH and `delay` periods (dt given), or the
    continuous loop without hold and delay (dt None)."""
    if law.output != p.output:
        raise ValueError(f"law {law.law} reads a {law.output} state, the plant gives {p.output}")
    pc = control.ss(p.a, p.b, np.eye(6), np.zeros((6, 3)))
    if dt is None:
        return -(controller(law, None) * pc)
    pd = control.c2d(pc, dt, "zoh")
    return -(delay_block(delay, dt) * controller(law, dt) * pd)


def loop_at(big_l: control.StateSpace, i: int) -> control.StateSpace:
    """The SISO loop at input i with the other loops closed (u_j = -y_j for j != i)."""
    a, b, c, d = (np.asarray(m, float) for m in (big_l.A, big_l.B, big_l.C, big_l.D))
    n = b.shape[1]
    q = np.eye(n)
    q[i, i] = 0.0                       # the loops still closed
    pick = np.zeros((n, 1))
    pick[i, 0] = 1.0
    # u = pick v - q y, y = c x + d u  ->  u = m (pick v - q c x), m = (I + q d)^-1
    m = np.linalg.inv(np.eye(n) + q @ d)
    a2 = a - b @ m @ q @ c
    b2 = b @ m @ pick
    c2 = c[i:i + 1] - d[i:i + 1] @ m @ q @ c
    d2 = d[i:i + 1] @ m @ pick
    return control.ss(a2, b2, c2, d2, big_l.dt)


def response(sys: control.StateSpace, w: np.ndarray) -> np.ndarray:
    """Frequency response, (n_out, n_in, len(w)) complex."""
    r = sys.frequency_response(np.asarray(w, float))
    fr = np.asarray(r.frdata)
    return fr.reshape(sys.noutputs, sys.ninputs, -1)


def closed_loop_poles(big_l: control.StateSpace, k: float = 1.0) -> np.ndarray:
    """Poles of the loop closed with gain k at the plant input: eig(A - k B (I + k D)^-1 C)."""
    a, b, c, d = (np.asarray(m, float) for m in (big_l.A, big_l.B, big_l.C, big_l.D))
    m = np.linalg.inv(np.eye(d.shape[0]) + k * d)
    return np.linalg.eigvals(a - k * b @ m @ c)


def is_stable(big_l: control.StateSpace, k: float = 1.0) -> bool:
    p = closed_loop_poles(big_l, k)
    if big_l.dt:
        return bool(np.all(np.abs(p) < 1.0))
    return bool(np.all(p.real < 0.0))
