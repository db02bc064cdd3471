"""plant_node as a fork of a process that has the plant's modules imported, instead of a new interpreter.

A new interpreter costs ~0.12 s of imports (numpy, the plant, the bindings) at every run; a fork costs a
few milliseconds. Only a single-threaded parent may fork: a child of a multi-threaded process inherits
every lock another thread held at that instant (glib's allocator, LCM's handles) with nobody left to
release it. `aocs run` forks the plant before its recorder thread starts (`can_fork`); a campaign's Dask
worker is multi-threaded, so its plants are forked by a single-threaded plant server instead
(aocs_campaign.plant_server), whose children run `child_main` as well.
"""
from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading
import time
import traceback

from aocs_core import libc, paths, registry
from aocs_loop import direct_adapter
from aocs_plant import kernels
from aocs_wire import netns

from . import orchestrate, plant_node


def can_fork() -> bool:
    """True when this process has no other Python thread (the condition for a safe fork)."""
    return threading.active_count() == 1 and hasattr(os, "fork")


def preload() -> None:
    """What every plant loads at its start, loaded once in a process that forks many (a campaign's plant server):
    its forks inherit it. The compiled kernels, the in-process node library, the wire bindings, the law registry,
    the C library. What cannot be loaded is left for the plant to report."""
    for load in (lambda: kernels.module(kernels.RIGID_BODY), lambda: kernels.module(kernels.DIRECT_LOOP),
                 direct_adapter.library, paths.import_bindings, registry.load, libc.libc):
        try:
            load()
        except Exception:  # noqa: BLE001, S112 - the plant reports it when it needs it
            continue


def child_main(args: list, stdout_path, netns_path: str | None = None) -> None:
    """In a forked child: plant_node.main(args), its stdout to stdout_path, in the network namespace at
    netns_path (None: the parent's); ends the process with plant_node's exit code, never returns."""
    code = 1
    try:
        fd = os.open(str(stdout_path), os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
        os.dup2(fd, 1)
        os.close(fd)
        null = os.open(os.devnull, os.O_RDONLY)
        os.dup2(null, 0)
        os.close(null)
        orchestrate.set_pdeathsig()   # ends with its parent, as the runner's other children
        orchestrate.set_process_name("plant_node")   # its command line is still its parent's
        for sig in (signal.SIGINT, signal.SIGTERM, signal.SIGCHLD):
            signal.signal(sig, signal.SIG_DFL)   # plant_node sets its own
        sys.stdout = open(1, "w", closefd=False)
        sys.stderr = open(2, "w", closefd=False)
        if netns_path is not None:
            netns.join_netns(netns_path)
        plant_node.T_PROCESS = time.perf_counter()
        code = plant_node.main([str(a) for a in args])
    except SystemExit as exc:
        code = exc.code if isinstance(exc.code, int) else 1
    except BaseException:  # noqa: BLE001 - the child must end here, whatever happened
        traceback.print_exc()
        code = 1
    finally:
        try:
            sys.stdout.flush()
            sys.stderr.flush()
        finally:
            os._exit(code)


def run_here(args: list, stdout_path) -> int:
    """plant_node.main(args) in this process, in its main thread, its stdout to stdout_path; plant_node's exit code.
    The process's stdout and its SIGINT and SIGTERM handlers are as they were afterwards, so that a process can fly
    one run after another (a campaign's in-process plant runner, aocs_campaign.plant_server)."""
    sys.stdout.flush()
    saved_fd = os.dup(1)
    saved = {sig: signal.getsignal(sig) for sig in (signal.SIGINT, signal.SIGTERM)}
    code = 1
    try:
        fd = os.open(str(stdout_path), os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
        os.dup2(fd, 1)
        os.close(fd)
        plant_node.T_PROCESS = time.perf_counter()
        code = plant_node.main([str(a) for a in args])
    except SystemExit as exc:
        code = exc.code if isinstance(exc.code, int) else 1
    except Exception:  # noqa: BLE001 - a run that broke is its exit code; the process flies the next
        traceback.print_exc()
        code = 1
    finally:
        try:
            sys.stdout.flush()
        finally:
            os.dup2(saved_fd, 1)
            os.close(saved_fd)
            for sig, handler in saved.items():
                signal.signal(sig, handler)
    return code


class ForkedChild:
    """A forked plant with the part of subprocess.Popen that orchestrate.Proc uses."""

    def __init__(self, pid: int):
        self.pid = pid
        self.returncode = None

    def poll(self):
        if self.returncode is None:
            done, status = os.waitpid(self.pid, os.WNOHANG)
            if done:
                self.returncode = os.waitstatus_to_exitcode(status)
        return self.returncode

    def wait(self, timeout=None):
        end = None if timeout is None else time.monotonic() + timeout
        while self.poll() is None:
            if end is not None and time.monotonic() > end:
                raise subprocess.TimeoutExpired(f"pid {self.pid}", timeout)
            time.sleep(0.001)
        return self.returncode

    def send_signal(self, sig):
        if self.poll() is None:
            try:
                os.kill(self.pid, sig)
            except ProcessLookupError:
                pass

    def kill(self):
        self.send_signal(signal.SIGKILL)


def fork(args: list, stdout_path) -> ForkedChild:
    """plant_node.main(args) in a fork of this (single-threaded: can_fork) process."""
    sys.stdout.flush()
    sys.stderr.flush()
    pid = os.fork()
    if pid == 0:
        child_main(args, stdout_path)
    return ForkedChild(pid)
