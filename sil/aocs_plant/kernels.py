"""The plant's compiled kernels (sil/plant_kernels/*.c), found in the build tree and loaded once per process.

aocs_rigid_body_kernel has the two attitude periods of Plant.advance in C: the rigid body
alone (Stepper: n RK4 substeps with the torque held, an optional fixed-direction gravity gradient) and the body
with effector states (CoupledStepper: rk4_coupled_stepper over the reaction wheels and the thrusters). They
compute the same doubles as the Python steppers, bit for bit (tests/python/aocs_plant/test_rigid_body_kernel.py),
so whether it runs changes the speed of a run, never its numbers. The plant runs the Python stepper when the
module is not built (`cmake --build --preset host` builds it into <build>/lib) or when AOCS_PLANT_KERNELS=python
(aocs_core.compiled loads every kernel module).
aocs_direct_loop_kernel flies whole lockstep periods of the in-process transport (aocs_runner.compiled_loop), with
the same doubles and the same log as plant_node's Python loop; AOCS_PLANT_KERNELS=periods turns it off alone.
"""
from __future__ import annotations

from aocs_core import compiled
from aocs_core.compiled import DIRECT_LOOP, ENV, RIGID_BODY, enabled

__all__ = ["DIRECT_LOOP", "ENV", "RIGID_BODY", "enabled", "module", "rigid_body_period", "coupled_period"]


def module(name: str = RIGID_BODY):
    """The kernel module `name` from <build>/lib, or None (aocs_core.compiled.module)."""
    return compiled.module(name)


def rigid_body_period(J: tuple, Ji: tuple, compiled_terms):
    """period(q, w, h, n, torque) -> (q, w) of the compiled kernel for a body of inertia J (row-major 9-tuple, Ji
    its inverse) and its attitude terms in compiled form (Effector.compiled_term of each), or None when the kernel
    is not there or a term has no compiled form (at most one gravity gradient is compiled: with two, Python's
    sum_terms adds them from 0.0, another rounding)."""
    gg = gg_argument(compiled_terms)
    if gg is False:
        return None
    mod = module(RIGID_BODY)
    if mod is None:
        return None
    return mod.Stepper(J, Ji, gg).period


def gg_argument(compiled_terms):
    """The kernel's gg argument of the attitude terms (None: none), or False when they cannot be compiled."""
    terms = tuple(compiled_terms)
    if len(terms) > 1 or any(t is None or t[0] != "gravity_gradient" for t in terms):
        return False
    return tuple(terms[0][1:]) if terms else None


class CoupledKernel:
    """The coupled period compiled: period(q, w, x, h, n, torque) -> (q, w, x), or None when an effector cannot be
    compiled this period (compiled_input() None: an injected wheel fault), then the caller runs Python."""

    def __init__(self, stepper, effectors, specs):
        self._period = stepper.period
        self._effectors = effectors
        self._wheels = next((e for e, spec in zip(effectors, specs) if spec[0] == "wheels"), None)

    def period(self, q, w, x, h, n, torque):
        inputs = tuple([e.compiled_input() for e in self._effectors])
        if None in inputs:
            return None
        q, w, x, cut = self._period(q, w, x, h, n, torque, inputs)
        if cut:
            self._wheels.speed_limit_cut(cut)
        return q, w, x


def coupled_period(J: tuple, Ji: tuple, compiled_terms, general) -> CoupledKernel | None:
    """The compiled coupled period for a body of inertia J (Ji its inverse), its attitude terms in compiled form and
    its GENERAL effectors (in the plant's order), or None when the kernel is not there or one of them has no
    compiled form."""
    gg = gg_argument(compiled_terms)
    specs = tuple(e.compiled_general() for e in general)
    if gg is False or not specs or None in specs or len(specs) > 4:
        return None
    mod = module(RIGID_BODY)
    if mod is None:
        return None
    return CoupledKernel(mod.CoupledStepper(J, Ji, gg, specs), tuple(general), specs)
