"""Start, watch and stop the processes of a run, with a bound on every wait.

    with Processes() as procs:
        fc = procs.start("fsw_node", [exe, cfg], stdout=out / "fsw_node.stdout", stderr=...)
        ...
    # leaving the block (normally, on an exception, on SIGINT/SIGTERM) stops
    # every child still running: SIGTERM (+ SIGCONT), a bounded wait, SIGKILL.

Children also get PR_SET_PDEATHSIG(SIGTERM), so they end even when the
runner itself is killed with SIGKILL. Every LCM process runs in the runner's
private network namespace (netns.reexec_in_netns before any of this).
start_logger / stop_logger drive lcm-logger (`aocs run --recorder
lcm-logger`); the default recorder is recorder.py.
"""
from __future__ import annotations

import ctypes
import os
import signal
import subprocess
import threading
import time
from pathlib import Path

from aocs_core import libc as clib
from aocs_wire import netns, wire
from aocs_wire.recorder import marker_message
from aocs_wire.udpm import Udpm

_PR_SET_PDEATHSIG = 1
#: SO_RCVBUF asked for lcm-logger's socket (bytes); the kernel caps it at net.core.rmem_max
LOGGER_RECV_BUF = 4 * 1024 * 1024
#: nice value of lcm-logger (its threads are created after this is set? no: set right after start)
LOGGER_NICE = -10


class RunAborted(RuntimeError):
    """The run was interrupted (signal) or a child failed; message says which and why."""


_PR_SET_NAME = 15


def set_process_name(name: str) -> None:
    """The calling process's name (/proc/PID/comm, what ps and top show; 15 bytes at most); best effort."""
    try:
        libc = clib.libc()
        libc.prctl(_PR_SET_NAME, ctypes.c_char_p(name.encode()[:15]), 0, 0, 0)
    except OSError:
        pass


def set_pdeathsig():  # runs in the child between fork and exec (or in a forked plant, plant_fork.py)
    try:
        libc = clib.libc()
        libc.prctl(_PR_SET_PDEATHSIG, signal.SIGTERM)
    except OSError:
        pass


class Proc:
    def __init__(self, name: str, popen: subprocess.Popen, files: list, stderr_path: Path | None):
        self.name = name
        self.popen = popen
        self._files = files
        self.stderr_path = stderr_path

    @property
    def pid(self) -> int:
        return self.popen.pid

    def poll(self):
        return self.popen.poll()

    def alive(self) -> bool:
        return self.popen.poll() is None

    def wait(self, timeout: float):
        """Exit code, or None if still running after timeout seconds."""
        try:
            return self.popen.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            return None

    def stop(self, sig=signal.SIGTERM, timeout: float = 5.0):
        """Signal, wait up to timeout, then SIGKILL. Returns the exit code."""
        if self.popen.poll() is None:
            try:
                self.popen.send_signal(sig)
                if sig != signal.SIGKILL:
                    self.popen.send_signal(signal.SIGCONT)  # a stopped process must run to handle it
            except ProcessLookupError:
                pass
            rc = self.wait(timeout)
            if rc is None:
                self.popen.kill()
                rc = self.wait(5.0)
        self.close_files()
        return self.popen.returncode

    def close_files(self):
        for f in self._files:
            try:
                f.close()
            except OSError:
                pass
        self._files = []

    def stderr_tail(self, lines: int = 5) -> str:
        if self.stderr_path is None or not self.stderr_path.is_file():
            return ""
        text = self.stderr_path.read_text(errors="replace").strip().splitlines()
        return "\n".join(text[-lines:])


def describe_exit(rc) -> str:
    if rc is None:
        return "still running"
    if rc < 0:
        try:
            return f"killed by {signal.Signals(-rc).name}"
        except ValueError:
            return f"killed by signal {-rc}"
    return f"exit code {rc}"


class Processes:
    """Owns the children of a run; a context manager that always cleans up."""

    def __init__(self):
        self.procs: list[Proc] = []
        self._old = {}

    def __enter__(self):
        # signal handlers belong to the main thread; a run in a worker thread (aocs campaign) is
        # stopped by its owner, and its children still end with it (PR_SET_PDEATHSIG)
        if threading.current_thread() is threading.main_thread():
            for sig in (signal.SIGINT, signal.SIGTERM):
                self._old[sig] = signal.signal(sig, self._on_signal)
        return self

    def _on_signal(self, signum, frame):  # noqa: ARG002
        raise RunAborted(f"interrupted by {signal.Signals(signum).name}")

    def __exit__(self, *exc):
        try:
            self.stop_all()
        finally:
            for sig, old in self._old.items():
                signal.signal(sig, old)
        return False

    def start(self, name: str, cmd: list, *, stdout=None, stderr=None, env=None, cwd=None) -> Proc:
        """stdout/stderr: a path (file written), None (inherited) or subprocess.DEVNULL."""
        files = []

        def target(x):
            if isinstance(x, (str, Path)):
                f = open(x, "w")
                files.append(f)
                return f
            return x

        out, err = target(stdout), target(stderr)
        try:
            p = subprocess.Popen([str(c) for c in cmd], stdout=out, stderr=err, env=env, cwd=cwd,
                                 stdin=subprocess.DEVNULL, preexec_fn=set_pdeathsig)
        except OSError as exc:
            for f in files:
                f.close()
            raise RunAborted(f"cannot start {name} ({cmd[0]}): {exc}") from None
        proc = Proc(name, p, files, Path(stderr) if isinstance(stderr, (str, Path)) else None)
        self.procs.append(proc)
        return proc

    def adopt(self, name: str, popen) -> Proc:
        """A child started by other means (poll, wait(timeout), send_signal, kill, pid, returncode as
        subprocess.Popen), watched and stopped like the others."""
        proc = Proc(name, popen, [], None)
        self.procs.append(proc)
        return proc

    def stop_all(self, timeout: float = 5.0):
        for p in reversed(self.procs):
            p.stop(signal.SIGTERM, timeout)


class MarkerLink:
    """The runner's AOCS_RUNNER markers (aocs_wire.recorder.marker_message), for lcm-logger or the
    recording plant: a udpm publisher only (no socket of it joins the group)."""

    def __init__(self):
        netns.require_netns()
        self.pub = Udpm(netns.LCM_URL, receive=False)
        self.n = 0

    def publish(self, what: str, **info) -> bytes:
        self.n += 1
        data = marker_message(what, f"{what}-{self.n}", **info)
        self.pub.publish(wire.RUNNER, data)
        return data

    def close(self) -> None:
        self.pub.close()


def end_plant_log(link: MarkerLink, plant: Proc, timeout: float = 10.0, **info):
    """The end marker for a plant that records the bus (plant_node --log), published until the plant,
    which stops recording on it, has ended (bounded: then stopped); the plant's exit code."""
    deadline = time.monotonic() + timeout
    while plant.alive() and time.monotonic() < deadline:
        link.publish("end", **info)
        plant.wait(0.05)
    return plant.stop()   # the exit code of a plant that has ended; SIGTERM first to one that has not


def _file_contains(path: Path, needle: bytes) -> bool:
    """Looks at the last 1 MiB only: markers are written last."""
    try:
        with open(path, "rb") as f:
            f.seek(0, os.SEEK_END)
            size = f.tell()
            f.seek(max(0, size - (1 << 20)))
            return needle in f.read()
    except FileNotFoundError:
        return False


def wait_marker_logged(link: MarkerLink, log_path: Path, logger: Proc, what: str, timeout: float = 5.0,
                       **info) -> None:
    """Publish a marker until it is in the log file (the logger records and flushes)."""
    end = time.monotonic() + timeout
    while True:
        data = link.publish(what, **info)
        t_next = time.monotonic() + 0.05
        while time.monotonic() < t_next:
            if _file_contains(log_path, data):
                return
            if not logger.alive():
                raise RunAborted(f"lcm-logger {describe_exit(logger.poll())}: {logger.stderr_tail()}")
            time.sleep(0.005)
        if time.monotonic() > end:
            raise RunAborted(f"lcm-logger did not record the '{what}' marker within {timeout} s")


def start_logger(procs: Processes, exe: str, log_path: Path, link: MarkerLink, stderr_path: Path,
                 **info) -> Proc:
    """lcm-logger recording every channel to log_path, ready when this returns."""
    # a 4 MiB socket buffer (the kernel's rmem_max here) rides out ~100 ms of the
    # logger being descheduled at 30,000 messages/s; the default 208 KiB did not
    url = f"{netns.LCM_URL}&recv_buf_size={LOGGER_RECV_BUF}"
    logger = procs.start("lcm-logger", [exe, "--quiet", "--force", "--flush-interval=10", f"--lcm-url={url}",
                                        str(log_path)],
                         stdout=subprocess.DEVNULL, stderr=stderr_path)
    # LCM queues at most 30 unhandled messages per subscription and drops the
    # rest: at 30,000 messages/s that is 1 ms of the logger's main thread not
    # running. A higher scheduling priority (root; ignored otherwise) keeps it
    # from being starved by the plant and the flight computer on a 2-core machine.
    wait_marker_logged(link, log_path, logger, "start", **info)
    renice_threads(logger.pid, LOGGER_NICE)  # every thread exists once it records
    return logger


def renice_threads(pid: int, nice: int) -> None:
    """setpriority on every thread of a process (Linux: per thread); best effort."""
    try:
        tids = [int(t) for t in os.listdir(f"/proc/{pid}/task")]
    except OSError:
        return
    for tid in tids:
        try:
            os.setpriority(os.PRIO_PROCESS, tid, nice)
        except OSError:
            pass


def stop_logger(logger: Proc, link: MarkerLink, log_path: Path, **info) -> None:
    """End marker recorded (so everything before it is in the file), then SIGINT."""
    try:
        if logger.alive():
            wait_marker_logged(link, log_path, logger, "end", **info)
    finally:
        logger.stop(signal.SIGINT, 5.0)
        link.close()


def wait_ready_line(proc: Proc, path: Path, needle: str, timeout: float) -> bool:
    """Wait until a text appears in a child's output file (bounded)."""
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if path.is_file() and needle in path.read_text(errors="replace"):
            return True
        if not proc.alive():
            return False
        time.sleep(0.01)
    return False


def env_with_pythonpath(extra: list[str]) -> dict:
    env = dict(os.environ)
    parts = [str(x) for x in extra]
    if env.get("PYTHONPATH"):
        parts.append(env["PYTHONPATH"])
    env["PYTHONPATH"] = os.pathsep.join(parts)
    return env
