"""The processes of one run, from the plant's start to the log's end (run.execute's middle step).

The plant first: once it listens for the flight computer's heartbeat, the recorder and then the
flight computer start (so in real time no period of the node passes before the plant runs; the
plant publishes nothing before that heartbeat). Every wait is bounded; leaving the
orchestrate.Processes block stops every child still running. A plant that never becomes ready
raises RunFailed; a process that ends badly afterwards is returned as a Failure, which the runner
explains with the log's last ticks (run.py).
"""
from __future__ import annotations

import json
import os
import sys
import time
from dataclasses import dataclass
from pathlib import Path

from aocs_core import paths
from aocs_wire.recorder import Recorder

from . import orchestrate, plant_fork

#: longest wait for the plant to listen for the flight computer, s
READY_TIMEOUT_S = 30.0
#: a real-time run is stopped this long after its simulated duration, s
REALTIME_GRACE_S = 60.0


class RunFailed(RuntimeError):
    """A process died or stopped answering; the message names it, its exit and the last tick."""


@dataclass
class Flight:
    """What to start: the run's plant, recorder and flight computer, and where they write."""
    scenario_id: str
    law: str
    mode: str                   # lockstep | realtime
    duration_s: float
    out: Path
    log_path: Path
    recorder: str               # builtin | plant | lcm-logger (run.recorder_of)
    plant_args: list            # plant_node's arguments (run.plant_arguments)
    fc_name: str
    fc_cmd: list
    env: dict
    plant_launcher: object = None   # run.RunOptions.plant_launcher
    transport: str = "lcm"          # lcm | direct (transport.py): direct starts the plant only
    cpus: tuple | None = None       # (plant CPU, flight computer CPU): each pinned to its own (transport.lockstep_cpus)

    @property
    def ready_file(self) -> Path:
        return self.out / "plant_node.ready"

    @property
    def done_file(self) -> Path:
        return self.out / "plant_node.done"

    @property
    def plant_records(self) -> bool:
        return self.recorder == "plant"


@dataclass
class Failure:
    """A process that ended badly: its name, exit code (None: did not finish in time) and Proc."""
    name: str
    rc: int | None
    proc: object
    why: str | None = None     # how it failed, when not its exit code (e.g. a plant that froze)


@dataclass
class _Recording:
    """Whichever records the run: the runner's recorder thread, lcm-logger, or the plant (a marker link)."""
    recorder: Recorder | None = None
    logger: object = None
    link: orchestrate.MarkerLink | None = None


def fly(f: Flight) -> Failure | None:
    """Starts the run's processes, waits for the end, stops them and ends the log; the first failure."""
    if f.transport == "direct":
        return _fly_direct(f)
    failure = None
    with orchestrate.Processes() as procs:
        plant = _start_plant(procs, f)
        rec = _start_recording(procs, f)
        try:
            _wait_until_ready(plant, f.ready_file)
            if f.plant_records:
                rec.link.publish("start", scenario=f.scenario_id, law=f.law, mode=f.mode)  # the plant listens
            fc = procs.start(f.fc_name, f.fc_cmd, stdout=f.out / "fsw_node.stdout",
                             stderr=f.out / "fsw_node.stderr", env=f.env)
            if f.cpus is not None:
                _pin(plant, fc, f.cpus)
            failure = _watch(plant, fc, f)
            rc_fc = fc.stop()  # SIGTERM: the node publishes its last status and reports
            if failure is None and rc_fc != 0:
                failure = Failure(f.fc_name, rc_fc, fc)
        finally:
            rc_p = _end_recording(rec, plant, f)
            if failure is None and rc_p not in (None, 0):
                failure = Failure("plant_node", rc_p, plant)
    return failure


def _pin(plant: orchestrate.Proc, fc: orchestrate.Proc, cpus: tuple) -> None:
    """The plant and the flight computer each on a CPU of its own, before the first period (the plant waits for
    the flight computer's first heartbeat). A process that has already ended is left alone: _watch reports it."""
    for proc, cpu in ((plant, cpus[0]), (fc, cpus[1])):
        try:
            os.sched_setaffinity(proc.pid, {cpu})
        except OSError:
            pass


def _fly_direct(f: Flight) -> Failure | None:
    """--transport direct: the plant process alone (the flight computer runs in it and it records the
    log with its markers, plant_node.py); waits for its exit."""
    with orchestrate.Processes() as procs:
        plant = _start_plant(procs, f)
        rc = plant.wait(None)
        f.ready_file.unlink(missing_ok=True)
        f.done_file.unlink(missing_ok=True)
        return Failure("plant_node", rc, plant) if rc != 0 else None


def _start_plant(procs: orchestrate.Processes, f: Flight) -> orchestrate.Proc:
    """plant_node: forked while this process has no other thread (plant_fork.py), else by the
    caller's launcher (the campaign's plant server) or as a new interpreter."""
    if f.plant_records:
        f.done_file.unlink(missing_ok=True)
    f.ready_file.unlink(missing_ok=True)
    stdout = f.out / "plant_node.stdout"
    if f.plant_launcher is not None:
        return procs.adopt("plant_node", f.plant_launcher(f.plant_args, stdout, f.env))
    if plant_fork.can_fork():
        return procs.adopt("plant_node", plant_fork.fork(f.plant_args, stdout))
    return procs.start("plant_node", [sys.executable, "-m", "aocs_runner.plant_node", *f.plant_args],
                       stdout=stdout, stderr=None, env=f.env)


def _start_recording(procs: orchestrate.Processes, f: Flight) -> _Recording:
    if f.recorder == "lcm-logger":
        link = orchestrate.MarkerLink()
        logger = orchestrate.start_logger(procs, paths.lcm_logger_exe(), f.log_path, link,
                                          f.out / "lcm-logger.stderr", scenario=f.scenario_id, law=f.law,
                                          mode=f.mode)
        return _Recording(logger=logger, link=link)
    if f.plant_records:
        return _Recording(link=orchestrate.MarkerLink())
    return _Recording(recorder=Recorder(f.log_path).start(scenario=f.scenario_id, law=f.law, mode=f.mode))


def _wait_until_ready(plant: orchestrate.Proc, ready: Path) -> None:
    end = time.monotonic() + READY_TIMEOUT_S
    while not ready.is_file():
        if not plant.alive():
            raise RunFailed(f"plant_node {orchestrate.describe_exit(plant.poll())} before it was ready")
        if time.monotonic() > end:
            raise RunFailed(f"plant_node was not ready within {READY_TIMEOUT_S:g} s")
        time.sleep(0.002)
    ready.unlink()


def _watch(plant: orchestrate.Proc, fc: orchestrate.Proc, f: Flight) -> Failure | None:
    """Waits for the plant to finish the run (or, when it records, to have flown the last tick)."""
    hard_end = (time.monotonic() + f.duration_s + REALTIME_GRACE_S) if f.mode == "realtime" else None
    while True:
        rc_p, rc_f = plant.poll(), fc.poll()
        if rc_p is not None:
            return Failure("plant_node", rc_p, plant) if rc_p != 0 else None
        if f.plant_records and f.done_file.is_file():
            return None   # the last tick is flown; the plant records on until the end marker
        if rc_f is not None:
            plant.stop()
            if rc_f == 0 and f.mode == "lockstep" and _fc_end_reason(f) == "idle":
                # the flight computer ended because no sensor frame came for its idle timeout: the plant,
                # alive but not sending (frozen, stopped, starved), is what failed
                return Failure("plant_node", None, plant, why="stopped sending sensor frames (alive, but the "
                               "flight computer received none for its idle timeout and ended: frozen or starved)")
            return Failure(f.fc_name, rc_f, fc)
        if hard_end is not None and time.monotonic() > hard_end:
            plant.stop()
            return Failure("plant_node", None, plant)
        time.sleep(0.005)


def _fc_end_reason(f: Flight) -> str | None:
    """The reason the flight computer gave for its end (the "reason" of its last JSON line), or None."""
    try:
        lines = (f.out / "fsw_node.stdout").read_text(errors="replace").splitlines()
    except OSError:
        return None
    for line in reversed(lines):
        try:
            doc = json.loads(line)
        except ValueError:
            continue
        node = next(iter(doc.values()), None) if isinstance(doc, dict) and len(doc) == 1 else doc
        if isinstance(node, dict) and isinstance(node.get("reason"), str):
            return node["reason"]
    return None


def _end_recording(rec: _Recording, plant: orchestrate.Proc, f: Flight) -> int | None:
    """Stops the recorder and closes the log; the plant's exit code when the plant recorded (else None)."""
    if rec.recorder is not None:
        rec.recorder.stop(scenario=f.scenario_id)
        return None
    if f.plant_records:
        try:   # the plant has recorded everything before the end marker, and ends
            rc_p = orchestrate.end_plant_log(rec.link, plant, scenario=f.scenario_id)
        finally:
            rec.link.close()
        f.done_file.unlink(missing_ok=True)
        return rc_p
    orchestrate.stop_logger(rec.logger, rec.link, f.log_path, scenario=f.scenario_id)
    return None
