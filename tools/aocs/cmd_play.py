"""`aocs play LOG [--speed S] [--with CMD ...]`: publish a recorded run again, paced by its
simulation clock, for people watching it (lcm-spy, a plotter) rather than for regression.

    aocs play out/irassi_large-quat_pd/run.lcmlog --speed 10 --with lcm-spy

A lockstep log carries the recorder's wall-clock receive times (docs/sil.md,
"The LCM log for people"): 500 s of simulation recorded in a third of a second,
so `lcm-logplayer` replays it in a third of a second. This command paces by
the simulation time of the messages instead: every event is published when
the wall clock reaches (its simulation time) / S since the start, its
simulation time being that of the last AOCS_SENSORS or AOCS_TRUTH message
before it (t_s). Payloads go out byte for byte, on their channels, in the
logged order.

LCM multicast never leaves this machine: the player runs in a private network
namespace, so a viewer must run in the same one. --with CMD starts CMD as a
child inside it (with CLASSPATH set to the project's lcm-spy types jar, so
`--with lcm-spy` decodes every channel), plays, then waits for CMD to exit
(--keep-open) or stops it. Exit 0 when every event was published.
"""
from __future__ import annotations

import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import lcm

from aocs_core import paths
from aocs_wire import lcmlog, netns, wire

EXIT_OK, EXIT_USAGE = 0, 2
#: slowest and fastest pacing (simulated seconds per wall second)
SPEED_MIN, SPEED_MAX = 1e-3, 1e6


class PlayError(ValueError):
    pass


def add_arguments(p) -> None:
    p.add_argument("log", help="run.lcmlog of an `aocs run`")
    p.add_argument("--speed", type=float, default=1.0,
                   help=f"simulated seconds per wall second (default 1 = real time; {SPEED_MIN:g} .. {SPEED_MAX:g})")
    p.add_argument("--with", dest="with_cmd", nargs="+", metavar="CMD",
                   help="a viewer to start in the same private network namespace first, e.g. lcm-spy")
    p.add_argument("--keep-open", action="store_true", help="after the last event, wait for the viewer to exit")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress line")


def sim_times(events, codecs) -> list[float]:
    """Simulation time of each event: t_s of the last sensors or truth message at or before it (0 before)."""
    by_channel = {wire.SENSORS: codecs.sensors, wire.TRUTH: codecs.truth}
    t, out = 0.0, []
    for ch, data, _ in events:
        codec = by_channel.get(ch)
        if codec is not None:
            v = codec.unpack(data)
            if v is not None:
                t = max(t, float(v[codec.index("t_s")]))
        out.append(t)
    return out


def _viewer(cmd: list[str]) -> subprocess.Popen:
    exe = shutil.which(cmd[0]) or str(Path(sys.executable).with_name(cmd[0]))
    if not Path(exe).exists():
        raise PlayError(f"--with {cmd[0]}: no such program")
    env = paths.python_env()
    jar = paths.build_dir() / "lcmtypes" / "aocs_lcmtypes.jar"
    if jar.is_file():
        env["CLASSPATH"] = os.pathsep.join(p for p in (str(jar), env.get("CLASSPATH", "")) if p)
    return subprocess.Popen([exe, *cmd[1:]], env=env)


def play(log_path: Path, speed: float, with_cmd=None, keep_open=False, quiet=False) -> int:
    if not (SPEED_MIN <= speed <= SPEED_MAX):
        raise PlayError(f"--speed {speed:g}: must be within [{SPEED_MIN:g}, {SPEED_MAX:g}]")
    try:
        lcmlog.scan(log_path)
    except lcmlog.LogIntegrityError as exc:
        raise PlayError(str(exc)) from None
    log = lcmlog.read(log_path, keep_raw=True)
    codecs = wire.Codecs(paths.import_bindings())
    times = sim_times(log.events, codecs)
    viewer = _viewer(with_cmd) if with_cmd else None
    if viewer is not None:
        time.sleep(2.0)  # let the viewer subscribe before the first event
    lc = lcm.LCM(netns.LCM_URL)
    t0 = time.monotonic()
    n = len(log.events)
    try:
        for i, ((ch, data, _), ts) in enumerate(zip(log.events, times)):
            due = t0 + ts / speed
            now = time.monotonic()
            if due > now:
                time.sleep(due - now)
            lc.publish(ch, data)
            if not quiet and i % 2000 == 0:
                print(f"aocs play: {i}/{n} events, t = {ts:.1f} s", file=sys.stderr, flush=True)
        if not quiet:
            print(f"aocs play: {n} events published, {times[-1] if times else 0:.1f} s of simulation in "
                  f"{time.monotonic() - t0:.1f} s", file=sys.stderr)
        if viewer is not None and keep_open:
            viewer.wait()
    finally:
        if viewer is not None and viewer.poll() is None:
            viewer.terminate()
            try:
                viewer.wait(timeout=5)
            except subprocess.TimeoutExpired:
                viewer.kill()
    return EXIT_OK


def run(args) -> int:
    netns.reexec_in_netns(paths.self_argv())
    try:
        return play(Path(args.log), args.speed, args.with_cmd, args.keep_open, args.quiet)
    except (PlayError, FileNotFoundError, paths.SetupError, netns.NetnsError) as exc:
        print(f"aocs play: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
