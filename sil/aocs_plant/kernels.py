"""The plant's compiled kernels (sil/plant_kernels/*.c), found in the build tree and loaded once per process.

aocs_rigid_body_kernel has the two attitude periods of Plant.advance in C: the rigid body
alone (Stepper: n RK4 substeps with the torque held, an optional fixed-direction gravity gradient) and the body
with effector states (CoupledStepper: rk4_coupled_stepper over the reaction wheels and the thrusters). They
compute the same doubles as the Python steppers, bit for bit (tests/python/aocs_plant/test_rigid_body_kernel.py),
so whether it runs changes the speed of a run, never its numbers. The plant runs the Python stepper when the
module is not built (`cmake --build --preset host` builds it into <build>/lib) or when AOCS_PLANT_KERNELS=python.
aocs_direct_loop_kernel flies whole lockstep periods of the in-process transport (aocs_runner.compiled_loop), with
the same doubles and the same log as plant_node's Python loop; AOCS_PLANT_KERNELS=periods turns it off alone.
"""
from __future__ import annotations

import importlib.machinery
import importlib.util
import os
import sysconfig

from aocs_core import paths

#: environment variable: "python" runs the plant's Python steppers and loop even when the kernels are built;
#: "periods" the compiled periods in plant_node's Python loop (no compiled loop, aocs_runner.compiled_loop)
ENV = "AOCS_PLANT_KERNELS"
RIGID_BODY = "aocs_rigid_body_kernel"
#: whole lockstep periods of the in-process transport (sil/plant_kernels/direct_loop_kernel.c)
DIRECT_LOOP = "aocs_direct_loop_kernel"

#: the modules each value of ENV turns off (any other value, or none: every module built runs)
_OFF = {"python": {RIGID_BODY, DIRECT_LOOP}, "periods": {DIRECT_LOOP}}

_loaded: dict = {}


def enabled(name: str = RIGID_BODY) -> bool:
    """Whether AOCS_PLANT_KERNELS leaves the kernel module `name` on."""
    return name not in _OFF.get(os.environ.get(ENV, "").strip().lower(), ())


def module(name: str = RIGID_BODY):
    """The kernel module `name` from <build>/lib, or None (not built, or turned off by AOCS_PLANT_KERNELS)."""
    if not enabled(name):
        return None
    if name not in _loaded:
        path = paths.build_dir() / "lib" / (name + sysconfig.get_config_var("EXT_SUFFIX"))
        mod = None
        if path.is_file():
            loader = importlib.machinery.ExtensionFileLoader(name, str(path))
            spec = importlib.util.spec_from_file_location(name, str(path), loader=loader)
            mod = importlib.util.module_from_spec(spec)
            loader.exec_module(mod)
        _loaded[name] = mod
    return _loaded[name]


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
