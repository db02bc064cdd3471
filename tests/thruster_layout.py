"""A thruster layout shared by the momentum tests (test_momentum_wire, test_pil_momentum, test_momentum_keys):
12 thrusters in couples, for each body axis k and sign s two thrusters at +-arm_m along axis j = k + 1 firing in
opposite directions along l = k + 2 (e_j x e_l = e_k: each gives a torque s arm_m e_k), optionally offset along k
and canted towards k (then no torque is purely about one axis), and the torque arms r x d. No tests here."""
from __future__ import annotations

import math


def cross(a, b) -> tuple:
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def couples(arm_m: float = 1.2, offset_m: float = 0.0, cant_deg: float = 0.0) -> tuple[tuple, tuple]:
    """(positions, directions) of the 12 thrusters, B frame, m and unit vectors."""
    cant = math.radians(cant_deg)
    pos, dirs = [], []
    for k in range(3):
        j, l = (k + 1) % 3, (k + 2) % 3
        for s in (1.0, -1.0):
            for side in (1.0, -1.0):
                r, d = [0.0] * 3, [0.0] * 3
                r[j], r[k] = arm_m * side, offset_m * side
                d[l], d[k] = s * side * math.cos(cant), math.sin(cant)
                pos.append(tuple(r))
                dirs.append(tuple(d))
    return tuple(pos), tuple(dirs)


def arms(pos, dirs) -> list[tuple]:
    """r_i x d_i of each thruster (torque per newton, m)."""
    return [cross(r, d) for r, d in zip(pos, dirs)]
