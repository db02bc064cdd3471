"""The plant's compiled kernels (sil/plant_kernels/*.c), found in the build tree and loaded once per process.

Today one: aocs_rigid_body_kernel, the attitude fast path of Plant.advance (the rigid body alone, n RK4
substeps with the torque held, an optional fixed-direction gravity gradient) in C. It computes the same
doubles as the Python stepper of rigid_body.py, bit for bit (tests/python/aocs_plant/test_rigid_body_kernel.py),
so whether it runs changes the speed of a run, never its numbers. The plant runs the Python stepper when the
module is not built (`cmake --build --preset host` builds it into <build>/lib) or when AOCS_PLANT_KERNELS=python.
"""
from __future__ import annotations

import importlib.machinery
import importlib.util
import os
import sysconfig

from aocs_core import paths

#: environment variable: "python" runs the plant's Python steppers even when the kernels are built
ENV = "AOCS_PLANT_KERNELS"
RIGID_BODY = "aocs_rigid_body_kernel"

_loaded: dict = {}


def enabled() -> bool:
    return os.environ.get(ENV, "").strip().lower() != "python"


def module(name: str = RIGID_BODY):
    """The kernel module `name` from <build>/lib, or None (not built, or turned off by AOCS_PLANT_KERNELS)."""
    if not enabled():
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
    terms = tuple(compiled_terms)
    if len(terms) > 1 or any(t is None or t[0] != "gravity_gradient" for t in terms):
        return None
    mod = module(RIGID_BODY)
    if mod is None:
        return None
    gg = tuple(terms[0][1:]) if terms else None
    return mod.Stepper(J, Ji, gg).period
