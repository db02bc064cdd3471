"""A campaign worker's plant server: one single-threaded process per worker that has the plant's modules
imported once and forks a plant_node per run.

Why: a new interpreter per run costs ~0.3-0.5 s of imports; forking the plant from the Dask worker itself
saves them but forks a multi-threaded process (Dask's event loop, the run's recorder and LCM's receive
threads), whose child inherits every lock another thread held at that instant (glib's allocator, LCM's
handles) with nobody left to release it. The server is started with subprocess (exec: no inherited
threads) before the worker's first run and never starts a thread, so its children are forks of a
single-threaded process.

Protocol (one JSON object per line over a socketpair): the worker sends {"id", "args", "stdout",
"netns", "here"}; the server forks a child that joins the network namespace at "netns" (the run thread's
/proc/PID/task/TID/ns/net, netns.join_netns), writes its stdout to "stdout", runs plant_node.main(args)
and leaves with os._exit; it answers {"id", "pid"} (or {"id", "error"}), and {"pid", "exit"} (the exit
code as subprocess gives it: negative for a signal) when it has reaped the child. With "here" (a
--transport direct run: no socket, so no namespace) the server flies the run itself, without a fork
(plant_fork.run_here: a fork, its copy-on-write faults and its exit cost more kernel time than the run's loop);
it answers {"id", "pid"} with its own pid, then {"id", "exit"}, and reads no request meanwhile. The server ends when the
worker does (end of file on the socket); its children end with it (PR_SET_PDEATHSIG).
"""
from __future__ import annotations

import json
import os
import select
import signal
import socket
import subprocess
import sys
import threading
import time

from aocs_core import libc
from aocs_runner import plant_fork


def _child(req: dict) -> None:
    """In the forked child: never returns."""
    from aocs_runner import plant_fork  # deferred: imported by the server before any fork

    signal.set_wakeup_fd(-1)   # the server's wake-up pipe is the server's
    plant_fork.child_main(req["args"], req["stdout"], req["netns"])


def serve(sock: socket.socket) -> int:
    """The server loop (single thread): requests in, forks, exit statuses out."""
    from aocs_runner import plant_fork  # deferred: imported once (the plant too), inherited by every fork

    # no PDEATHSIG here: it follows the thread that started us (a Dask worker thread), not the worker; the
    # end of file on the socket says the worker is gone
    signal.signal(signal.SIGINT, signal.SIG_IGN)   # the worker's Ctrl-C is the worker's: it ends us
    # a child's exit wakes the loop at once (SIGCHLD through a wake-up pipe): its status reaches the waiting run
    # without a polling delay
    wake_r, wake_w = os.pipe()
    os.set_blocking(wake_r, False)
    os.set_blocking(wake_w, False)
    signal.set_wakeup_fd(wake_w)
    signal.signal(signal.SIGCHLD, lambda signum, frame: None)
    plant_fork.preload()   # the kernels, the node library, the bindings, libc: loaded once, inherited by every fork
    libc.keep_freed_memory()   # the runs it flies itself, one after another, reuse each other's memory
    children: set[int] = set()
    buf = b""
    out = sock.makefile("wb", buffering=0)

    def send(msg: dict) -> None:
        out.write((json.dumps(msg) + "\n").encode())

    sock.sendall(b'{"ready": true}\n')
    while True:
        r, _, _ = select.select([sock, wake_r], [], [], 0.05 if children else 0.5)
        if wake_r in r:
            try:
                os.read(wake_r, 4096)
            except BlockingIOError:
                pass
        if sock in r:
            chunk = sock.recv(65536)
            if not chunk:   # the worker is gone
                return 0
            buf += chunk
            while b"\n" in buf:
                line, buf = buf.split(b"\n", 1)
                req = json.loads(line)
                if req.get("here"):   # a direct run flown by this process itself: no fork, nothing to reap
                    send({"id": req["id"], "pid": os.getpid()})
                    send({"id": req["id"], "exit": plant_fork.run_here(req["args"], req["stdout"])})
                    continue
                try:
                    pid = os.fork()
                except OSError as exc:
                    send({"id": req["id"], "error": f"fork: {exc}"})
                    continue
                if pid == 0:
                    sock.close()
                    _child(req)
                children.add(pid)
                send({"id": req["id"], "pid": pid})
        for pid in list(children):
            done, status = os.waitpid(pid, os.WNOHANG)
            if done:
                children.discard(pid)
                send({"pid": pid, "exit": os.waitstatus_to_exitcode(status)})


class ServerEnded(RuntimeError):
    """The plant server's socket closed: the server is gone."""


class ServedChild(plant_fork.ForkedChild):
    """A plant forked by the server (not a child of this process), or the server itself flying a run: its exit status
    comes from the server, under `key` (the fork's pid; ("run", request id) for a run the server flies)."""

    def __init__(self, server: "PlantServer", pid: int, key):
        super().__init__(pid)
        self._server = server
        self._key = key

    def poll(self):
        if self.returncode is None:
            self.returncode = self._server.exit_code(self._key)
        return self.returncode


class PlantServer:
    """The worker's side: starts the server (once; again if it died) and asks it for plants."""

    def __init__(self):
        self._lock = threading.Lock()
        self._proc = None
        self._sock = None
        self._buf = b""
        self._exits: dict[int, int] = {}
        self._n = 0

    def ensure_running(self) -> None:
        with self._lock:
            if self._proc is not None and self._proc.poll() is None:
                return
            mine, theirs = socket.socketpair()
            self._proc = subprocess.Popen([sys.executable, "-m", "aocs_campaign.plant_server",
                                           str(theirs.fileno())], pass_fds=[theirs.fileno()],
                                          stdin=subprocess.DEVNULL)
            theirs.close()
            self._sock, self._buf, self._exits = mine, b"", {}
            self._read_until(lambda m: m.get("ready"), 60.0, "start")

    def _pump(self, timeout: float, what: str) -> list[dict]:
        """The messages that arrive within timeout (at most one read; exit statuses kept); the caller
        holds the lock. Raises when the server has ended."""
        r, _, _ = select.select([self._sock], [], [], max(0.0, timeout))
        if r:
            chunk = self._sock.recv(65536)
            if not chunk:
                raise ServerEnded(f"the plant server ended ({what}): exit {self._proc.poll()}")
            self._buf += chunk
        msgs = []
        while b"\n" in self._buf:
            line, self._buf = self._buf.split(b"\n", 1)
            msg = json.loads(line)
            if "exit" in msg:
                self._exits[msg["pid"] if "pid" in msg else ("run", msg["id"])] = msg["exit"]
            msgs.append(msg)
        return msgs

    def _read_until(self, done, timeout: float, what: str) -> dict:
        end = time.monotonic() + timeout
        while True:
            for msg in self._pump(end - time.monotonic(), what):
                if done(msg):
                    return msg
            if time.monotonic() > end:
                raise RuntimeError(f"the plant server did not answer ({what}) within {timeout:g} s")

    def launch(self, args: list, stdout_path, env: dict, here: bool = False) -> ServedChild:  # noqa: ARG002 - env
        """plant_node.main(args) in a child of the server, in the calling thread's network namespace; with here, in
        the server itself (plant_fork.run_here: a --transport direct run, which opens no socket), whose pid the
        returned child then has: a server flies one such run at a time (aocs_campaign.worker keeps one per thread)."""
        self.ensure_running()
        with self._lock:
            self._n += 1
            rid = self._n
            req = {"id": rid, "args": [str(a) for a in args], "stdout": str(stdout_path),
                   "netns": f"/proc/{os.getpid()}/task/{threading.get_native_id()}/ns/net", "here": here}
            self._sock.sendall((json.dumps(req) + "\n").encode())
            msg = self._read_until(lambda m: m.get("id") == rid and "exit" not in m, 30.0, "fork")
        if "error" in msg:
            raise RuntimeError(f"the plant server could not start plant_node: {msg['error']}")
        return ServedChild(self, msg["pid"], ("run", rid) if here else msg["pid"])

    def exit_code(self, key) -> int | None:
        with self._lock:
            if key not in self._exits:
                try:
                    self._pump(0.0, "poll")
                except ServerEnded:   # the server died: its children died with it (PDEATHSIG)
                    self._exits[key] = -signal.SIGKILL
            return self._exits.pop(key, None)

    @property
    def pid(self) -> int | None:
        return None if self._proc is None else self._proc.pid


if __name__ == "__main__":
    sys.exit(serve(socket.socket(fileno=int(sys.argv[1]))))
