"""The compiled kernels (CPython extension modules built by the host preset into <build>/lib), loaded once per process.

Each computes what a Python function beside it computes, bit for bit (its tests compare the two), so whether it runs
changes the speed of a run, never its numbers; the Python runs when the module is not built or AOCS_PLANT_KERNELS
turns it off:

- aocs_rigid_body_kernel: the plant's attitude periods (aocs_plant.kernels; sil/plant_kernels/rigid_body_kernel.c);
- aocs_direct_loop_kernel: whole lockstep periods of the in-process transport (aocs_runner.compiled_loop;
  sil/plant_kernels/direct_loop_kernel.c);
- aocs_lcmlog_kernel: the bulk log reader's walk over the events and its gather of payload rows (aocs_wire.lcmlog;
  sil/wire_kernels/lcmlog_kernel.c).
"""
from __future__ import annotations

import importlib.machinery
import importlib.util
import os
import threading

from . import paths

#: environment variable: "python" runs Python everywhere a kernel would (the plant's steppers and loop, the log
#: reader's numpy walk) even when the kernels are built; "periods" the compiled periods in plant_node's Python loop
#: (no compiled loop, aocs_runner.compiled_loop)
ENV = "AOCS_PLANT_KERNELS"
RIGID_BODY = "aocs_rigid_body_kernel"
DIRECT_LOOP = "aocs_direct_loop_kernel"
LCMLOG = "aocs_lcmlog_kernel"

#: the modules each value of ENV turns off (any other value, or none: every module built runs)
_OFF = {"python": {RIGID_BODY, DIRECT_LOOP, LCMLOG}, "periods": {DIRECT_LOOP}}

_loaded: dict = {}


def enabled(name: str) -> bool:
    """Whether AOCS_PLANT_KERNELS leaves the kernel module `name` on."""
    return name not in _OFF.get(os.environ.get(ENV, "").strip().lower(), ())


#: the file name ending CMake's WITH_SOABI gives (".cpython-311-x86_64-linux-gnu.so"): importlib's constant, not
#: sysconfig.get_config_var("EXT_SUFFIX"), whose first call fills a dict that another thread may read half-filled (a
#: campaign worker's two runs loading the log kernel at once got None)
EXT_SUFFIX = importlib.machinery.EXTENSION_SUFFIXES[0]
_lock = threading.Lock()


def module(name: str):
    """The kernel module `name` from <build>/lib, or None (not built, or turned off by AOCS_PLANT_KERNELS). Loaded once
    per process, whichever thread asks first."""
    if not enabled(name):
        return None
    if name in _loaded:   # loaded (or found missing) already: no lock on the readers' every call
        return _loaded[name]
    with _lock:
        if name not in _loaded:
            path = paths.build_dir() / "lib" / (name + EXT_SUFFIX)
            mod = None
            if path.is_file():
                loader = importlib.machinery.ExtensionFileLoader(name, str(path))
                spec = importlib.util.spec_from_file_location(name, str(path), loader=loader)
                mod = importlib.util.module_from_spec(spec)
                loader.exec_module(mod)
            _loaded[name] = mod
        return _loaded[name]
