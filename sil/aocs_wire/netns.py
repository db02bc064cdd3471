"""Private network namespaces for everything that speaks LCM.

LCM's default transport is UDP multicast (udpm). It must never reach the
machine's real network, so every process that opens LCM runs inside a fresh
network namespace whose only interface is a loopback with multicast enabled
and a route for 224.0.0.0/4 (docs/wire-contract.md, "Isolation").

Three ways in, all ending in the same kind of namespace:

- ``wrap(cmd)``: a command list that runs ``cmd`` alone in a new namespace
  (``unshare -n sh -c '<bring up lo> && exec "$@"' ...``).
- ``reexec_in_netns()``: an entry point (the runner) calls it first; the
  process re-executes itself once inside a new namespace, detected through the
  ``AOCS_NETNS`` environment variable, so all the processes it later starts
  (plant, fsw_node, logger) share that namespace.
- ``enter_netns()``: the calling process moves itself into a new namespace
  with unshare(2) (root only). Used by the pytest fixtures: the test process
  and its children then share one namespace without re-executing pytest.

``AOCS_NETNS`` holds the namespace id (``net:[inode]``) it was set for, so a
copy inherited by a process outside that namespace is not mistaken for
isolation.
"""
from __future__ import annotations

import ctypes
import os
import shutil
import subprocess
import sys
import threading
from typing import Sequence

from aocs_core import libc as clib

ENV_VAR = "AOCS_NETNS"

#: LCM URL to use inside the namespace: default udpm group, ttl=0 (never routed).
LCM_URL = "udpm://239.255.76.67:7667?ttl=0"

_CLONE_NEWNET = 0x40000000

#: shell commands that make the fresh namespace usable for udpm on loopback
SETUP_COMMANDS: tuple[tuple[str, ...], ...] = (
    ("ip", "link", "set", "lo", "up"),
    ("ip", "link", "set", "lo", "multicast", "on"),
    ("ip", "route", "add", "224.0.0.0/4", "dev", "lo"),
)


class NetnsError(RuntimeError):
    """The private namespace could not be created or configured."""


def current_netns_id() -> str:
    """Identifier of the calling thread's network namespace, e.g. 'net:[4026532285]'."""
    return os.readlink("/proc/thread-self/ns/net")


#: namespaces this process made or joined (enter_netns, join_netns): a campaign worker flies runs in several
#: threads at once, each in a namespace of its own, and AOCS_NETNS (one per process) names only the last
_OURS: set[str] = set()


def in_netns() -> bool:
    """True when the calling thread runs inside a namespace made by this module (by this process, or by the
    one that started it: AOCS_NETNS)."""
    here = current_netns_id()
    return here in _OURS or os.environ.get(ENV_VAR) == here


def _setup_script() -> str:
    setup = " && ".join(" ".join(c) for c in SETUP_COMMANDS)
    return f'{setup} && {ENV_VAR}="$(readlink /proc/self/ns/net)" && export {ENV_VAR} && exec "$@"'


def _require_tools() -> None:
    for tool in ("unshare", "ip"):
        if shutil.which(tool) is None:
            raise NetnsError(f"'{tool}' not found (Debian packages util-linux and iproute2)")


def wrap(cmd: Sequence[str]) -> list[str]:
    """Command list that runs ``cmd`` in a new private network namespace."""
    if not cmd:
        raise ValueError("empty command")
    _require_tools()
    return ["unshare", "-n", "sh", "-c", _setup_script(), "aocs-netns", *[str(c) for c in cmd]]


def run(cmd: Sequence[str], **kwargs) -> subprocess.CompletedProcess:
    """subprocess.run of ``cmd`` inside a new private namespace."""
    return subprocess.run(wrap(cmd), **kwargs)


def popen(cmd: Sequence[str], **kwargs) -> subprocess.Popen:
    """subprocess.Popen of ``cmd`` inside a new private namespace."""
    return subprocess.Popen(wrap(cmd), **kwargs)


def reexec_in_netns(argv: Sequence[str] | None = None) -> None:
    """Re-execute this Python program inside a new namespace, unless already in one.

    Does not return when it re-executes. ``argv`` defaults to the interpreter
    plus ``sys.argv`` (works for ``python script.py`` and console scripts).
    """
    if in_netns():
        return
    if argv is None:
        argv = [sys.executable, *sys.argv]
    sys.stdout.flush()
    sys.stderr.flush()
    full = wrap(argv)
    os.execvp(full[0], full)


def enter_netns(fresh: bool = False) -> str:
    """Move the calling process into a new private namespace and bring up lo.

    Needs CAP_SYS_ADMIN (root, or in a user namespace of its own). Call it from
    the main thread before any LCM object exists; threads and processes
    created afterwards inherit the namespace. Idempotent: returns at once when
    already inside one, unless ``fresh``: then the calling thread moves into a
    new one even so (a campaign worker, one namespace per run; the namespace
    is per thread in Linux, so call it from the thread that starts the run).
    Returns the namespace id.
    """
    if in_netns() and not fresh:
        return current_netns_id()
    _require_tools()
    before = current_netns_id()
    libc = clib.libc()
    if libc.unshare(_CLONE_NEWNET) != 0:
        err = ctypes.get_errno()
        raise NetnsError(f"unshare(CLONE_NEWNET) failed: {os.strerror(err)} "
                         "(LCM tests and runs need root to create a private network namespace)")
    after = current_netns_id()
    if after == before:
        raise NetnsError("unshare(CLONE_NEWNET) returned success but the namespace did not change")
    for c in SETUP_COMMANDS:
        res = subprocess.run(list(c), capture_output=True, text=True)
        if res.returncode != 0:
            raise NetnsError(f"{' '.join(c)} failed: {res.stderr.strip()}")
    if threading.current_thread() is threading.main_thread():
        # the variable is process-wide and tells children which namespace is ours: only the main thread's
        # namespace may name it (a thread's fresh one, a campaign run's or a probe's, would leave every later
        # child of the process refusing to open udpm; a run's children get their own: aocs_runner.run)
        os.environ[ENV_VAR] = after
    _OURS.add(after)
    return after


def join_netns(path: str) -> str:
    """Move the calling thread into the namespace at path (/proc/PID/task/TID/ns/net of a thread that
    entered one with enter_netns): setns(2), CAP_SYS_ADMIN in the namespace's user namespace. A campaign's
    plant server forks the plant into the run's namespace this way. Returns the namespace id."""
    libc = clib.libc()
    fd = os.open(path, os.O_RDONLY)
    try:
        if libc.setns(fd, _CLONE_NEWNET) != 0:
            err = ctypes.get_errno()
            raise NetnsError(f"setns({path}) failed: {os.strerror(err)}")
    finally:
        os.close(fd)
    after = current_netns_id()
    os.environ[ENV_VAR] = after
    _OURS.add(after)
    return after


def require_netns() -> None:
    """Raise unless running inside a private namespace (guard before opening LCM)."""
    if not in_netns():
        raise NetnsError("refusing to open LCM udpm outside a private network namespace "
                         "(use aocs_wire.netns.enter_netns / reexec_in_netns / wrap)")


if __name__ == "__main__":
    # python -m aocs_wire.netns CMD...: run CMD in a fresh namespace
    if len(sys.argv) < 2:
        print("usage: python -m aocs_wire.netns CMD [ARG...]", file=sys.stderr)
        sys.exit(2)
    sys.exit(run(sys.argv[1:]).returncode)
