"""Fixtures for the SIL tests: built binaries, generated bindings, the private
network namespace, and a started fsw_node.

The build directory comes from AOCS_BUILD_DIR (default <repo>/build/host).
Missing binaries or bindings make a test FAIL with the command that builds
them (CI builds first); nothing here skips.
"""
from __future__ import annotations

import json
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from aocs_wire import netns

REPO = Path(__file__).resolve().parents[1]
# namespace of the test process before any fixture moved it
ORIGINAL_NETNS = netns.current_netns_id()
BUILD_HINT = "build it first: cmake --preset host && cmake --build --preset host"


def _build_dir() -> Path:
    return Path(os.environ.get("AOCS_BUILD_DIR", REPO / "build" / "host")).resolve()


@pytest.fixture(scope="session")
def aocs_build_dir() -> Path:
    d = _build_dir()
    if not d.is_dir():
        pytest.fail(f"build directory {d} does not exist (AOCS_BUILD_DIR); {BUILD_HINT}")
    return d


@pytest.fixture(scope="session")
def real_is_float(aocs_build_dir) -> bool:
    """True when the build under test uses real_t = float (AOCS_REAL_FLOAT=ON)."""
    cache = aocs_build_dir / "CMakeCache.txt"
    text = cache.read_text() if cache.is_file() else ""
    return re.search(r"^AOCS_REAL_FLOAT:BOOL=(ON|1|TRUE)$", text, re.M | re.I) is not None


@pytest.fixture(scope="session")
def fsw_node_bin(aocs_build_dir) -> Path:
    exe = aocs_build_dir / "bin" / "fsw_node"
    if not (exe.is_file() and os.access(exe, os.X_OK)):
        pytest.fail(f"fsw_node not found at {exe}; {BUILD_HINT} (AOCS_BUILD_SIL=ON)")
    return exe


@pytest.fixture(scope="session")
def sanitized_fsw_node_bin() -> Path:
    """fsw_node of the host-sanitize preset (ASan + UBSan abort on undefined behaviour): the integrity and the
    hostile-sensor tests (tests/e2e)."""
    d = Path(os.environ.get("AOCS_SANITIZE_BUILD_DIR", REPO / "build" / "host-sanitize")).resolve()
    exe = d / "bin" / "fsw_node"
    if not (exe.is_file() and os.access(exe, os.X_OK)):
        pytest.fail(f"sanitized fsw_node not found at {exe}; build it first: cmake --preset host-sanitize && "
                    "cmake --build --preset host-sanitize")
    return exe


@pytest.fixture(scope="session")
def aocs_lcm(aocs_build_dir):
    """The generated Python bindings (package aocs_lcm) from the build tree."""
    pydir = aocs_build_dir / "lcmtypes" / "python"
    if not (pydir / "aocs_lcm" / "__init__.py").is_file():
        pytest.fail(f"generated Python bindings missing under {pydir}; {BUILD_HINT}")
    if str(pydir) not in sys.path:
        sys.path.insert(0, str(pydir))
    import aocs_lcm  # noqa: E402

    return aocs_lcm


@pytest.fixture(scope="session")
def status_codes() -> dict[str, int]:
    """aocs_status_t name -> value: the rows of firmware/include/aocs/status.def, in order (AOCS_OK = 0)."""
    text = (REPO / "firmware/include/aocs/status.def").read_text()
    names = re.findall(r"^\s*X\((\w+), \"", text, re.M)
    return {f"AOCS_{name}": i for i, name in enumerate(names)}


@pytest.fixture(scope="session")
def original_netns() -> str:
    return ORIGINAL_NETNS


@pytest.fixture(scope="session")
def private_netns() -> str:
    """Moves this test process (and every child it starts) into a private
    network namespace, so udpm multicast stays on its own loopback."""
    try:
        return netns.enter_netns()
    except netns.NetnsError as exc:
        pytest.fail(f"cannot create the private network namespace LCM tests need: {exc}")


class Link:
    """The test's side of the wire: publish and collect messages."""

    CHANNELS = ("AOCS_ACTUATOR_CMD", "AOCS_STATUS")

    def __init__(self, aocs_lcm):
        import lcm

        netns.require_netns()
        self.t = aocs_lcm
        self.lc = lcm.LCM(netns.LCM_URL)
        self.inbox: dict[str, list] = {c: [] for c in self.CHANNELS}
        self.lc.subscribe("AOCS_ACTUATOR_CMD", lambda c, d: self.inbox[c].append(aocs_lcm.actuator_cmd_t.decode(d)))
        self.lc.subscribe("AOCS_STATUS", lambda c, d: self.inbox[c].append(aocs_lcm.status_t.decode(d)))
        self.frame = 0

    def pump(self, seconds: float) -> None:
        end = time.monotonic() + seconds
        while True:
            left = end - time.monotonic()
            if left <= 0:
                return
            self.lc.handle_timeout(max(1, int(left * 1000)))

    def wait_for(self, channel: str, count: int = 1, timeout: float = 2.0, pred=None) -> list:
        """Waits until `count` messages on channel (matching pred) arrived since the inbox was cleared."""
        end = time.monotonic() + timeout
        while True:
            got = [m for m in self.inbox[channel] if pred is None or pred(m)]
            if len(got) >= count:
                return got
            left = end - time.monotonic()
            if left <= 0:
                raise AssertionError(f"timeout: {len(got)}/{count} messages on {channel} after {timeout} s")
            self.lc.handle_timeout(max(1, int(min(left, 0.1) * 1000)))

    def clear(self) -> None:
        for v in self.inbox.values():
            v.clear()

    def sensors(self, tick: int, q, w, *, t_s=None, valid=None, frame=None, version=None, pos=(0, 0, 0),
                vel=(0, 0, 0)):
        t = self.t.sensors_t
        m = t()
        m.protocol_version = t.PROTOCOL_VERSION if version is None else version
        m.frame = self.frame if frame is None else frame
        self.frame = m.frame + 1
        m.utime = 1000 + tick * 100000
        m.tick = tick
        m.t_s = 0.1 * tick if t_s is None else t_s
        m.valid = (t.VALID_ATTITUDE | t.VALID_RATE) if valid is None else valid
        m.q = [float(x) for x in q]
        m.w = [float(x) for x in w]
        m.pos = [float(x) for x in pos]
        m.vel = [float(x) for x in vel]
        return m

    def send_sensors(self, *args, **kwargs):
        m = self.sensors(*args, **kwargs)
        self.lc.publish("AOCS_SENSORS", m.encode())
        return m

    def send_command(self, request: int, *, law_id=None, mode=None, qd=None, wd=(0, 0, 0)):
        c = self.t.command_t
        m = c()
        m.protocol_version = c.PROTOCOL_VERSION
        m.frame = request
        m.utime = 0
        m.request = request
        m.law_id = c.LAW_KEEP if law_id is None else law_id
        m.mode = c.MODE_KEEP if mode is None else mode
        m.set_target = qd is not None
        m.qd = [float(x) for x in (qd if qd is not None else (0, 0, 0, 1))]
        m.wd = [float(x) for x in wd]
        self.lc.publish("AOCS_COMMAND", m.encode())
        return m


@pytest.fixture
def lcm_link(private_netns, aocs_lcm) -> Link:
    return Link(aocs_lcm)


BASE_CONFIG = {
    "law": "quat_pd",
    "mode": "lockstep",
    "control_period_s": "0.1",
    "quat_pd.kp": "4.0",
    "quat_pd.kd": "8.0",
    "crp_linear.k1": "19",
    "crp_linear.k2": "13",
    "u_max_axis": "0.5 0.6 0.7",
    "k_safe": "2.0",
    "recover_good_samples": "3",
    "missing_max_periods": "3",
    "idle_timeout_s": "5",
    "run_timeout_s": "20",
    "status_period_s": "0.05",
}


def write_config(path: Path, cfg: dict) -> Path:
    path.write_text("# written by tests/conftest.py\n" + "".join(f"{k} = {v}\n" for k, v in cfg.items()))
    return path


class Node:
    """A running fsw_node (inside the test's namespace)."""

    def __init__(self, exe: Path, workdir: Path, cfg: dict, name: str):
        self.cfg_path = write_config(workdir / f"{name}.cfg", cfg)
        self.out_path = workdir / f"{name}.stdout"
        self.err_path = workdir / f"{name}.stderr"
        self._out = open(self.out_path, "w")
        self._err = open(self.err_path, "w")
        self.proc = subprocess.Popen([str(exe), str(self.cfg_path)], stdout=self._out, stderr=self._err)

    def wait_ready(self, link: Link, timeout: float = 5.0) -> None:
        """Ready = its loop runs: a heartbeat on AOCS_STATUS arrived.

        Messages already queued (a previous node's last words) are drained
        first; a heartbeat of the new node may be dropped with them, the next
        one follows within status_period_s."""
        link.pump(0.02)
        link.clear()
        try:
            link.wait_for("AOCS_STATUS", 1, timeout, pred=lambda s: not s.exiting)
        except AssertionError:
            raise AssertionError(f"fsw_node sent no heartbeat; stderr: {self.stderr()}") from None
        link.clear()

    def stop(self, timeout: float = 5.0) -> int:
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
        rc = self.proc.wait(timeout=timeout)
        self._out.close()
        self._err.close()
        return rc

    def kill(self) -> None:
        if self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait(timeout=5)
        self._out.close()
        self._err.close()

    def stderr(self) -> str:
        self._err.flush()
        return self.err_path.read_text()

    def stats(self) -> dict:
        lines = [l for l in self.out_path.read_text().splitlines() if l.startswith("{")]
        assert lines, f"no JSON stats line on stdout; stderr: {self.stderr()}"
        return json.loads(lines[-1])["fsw_node"]


@pytest.fixture
def fsw_node(fsw_node_bin, private_netns, tmp_path):
    """Factory: fsw_node(**overrides) starts a node with BASE_CONFIG + overrides."""
    nodes: list[Node] = []

    def start(name: str = "node", drop=(), **overrides) -> Node:
        cfg = dict(BASE_CONFIG)
        for k in drop:
            cfg.pop(k, None)
        cfg.update({k.replace("__", "."): str(v) for k, v in overrides.items()})
        node = Node(fsw_node_bin, tmp_path, cfg, f"{name}{len(nodes)}")
        nodes.append(node)
        return node

    yield start
    for n in nodes:
        n.kill()


@pytest.fixture
def node_config():
    """(BASE_CONFIG copy, write_config) for tests that run fsw_node by hand."""
    return dict(BASE_CONFIG), write_config
