"""aocs_loop.core: the loop's order (sense, step, record, apply, advance) over a fake flight computer."""
from __future__ import annotations

from aocs_loop import core
from aocs_loop.frames import Command, PlantPort, Reply
from aocs_plant import Plant
from aocs_plant.scenario import load as _load


def load(sid, ov):
    return _load(sid, dict(ov, **{"metrics.window_s": ov["duration_s"]}))


class _Echo:
    """A flight computer that commands a torque and wheel torques from the tick, and notes what it saw."""

    def __init__(self, n_wheels):
        self.n, self.frames = n_wheels, []

    def step(self, f):
        self.frames.append(f)
        u = 1e-3 * (f.tick + 1)
        return Reply(Command(f.tick, (u, -u, 0.5 * u), (u,) * self.n), law_id=3)


class _Log(core.Hook):
    def __init__(self):
        self.rows, self.ended = [], None

    def period(self, frame, reply, plant):
        self.rows.append((frame.tick, plant.t if plant is not None else None, reply.command.u))

    def end(self, plant):
        self.ended = plant.t


def test_fly_senses_steps_records_applies_and_advances(aocs_lcm):
    sc = load("irassi_rw", {"duration_s": 1.0})
    plant = Plant(sc)
    fc, log = _Echo(4), _Log()
    assert core.fly(PlantPort(plant), fc, sc.n_steps, start_tick=5, hooks=[log]) == 10
    assert [f.tick for f in fc.frames] == list(range(5, 15))
    assert [r[0] for r in log.rows] == list(range(5, 15))
    assert [r[1] for r in log.rows] == [k * sc.dt for k in range(10)]   # recorded before the advance
    assert log.ended == 10 * sc.dt and plant.k == 10
    assert plant.wheel_array.u_cmd == (1e-3 * 15,) * 4                   # the last command reached the wheels
    assert plant.counters["commands"] == 10


def test_the_same_loop_twice_gives_the_same_frames(aocs_lcm):
    sc = load("irassi_rw", {"duration_s": 2.0})
    a, b = _Echo(4), _Echo(4)
    core.fly(PlantPort(Plant(sc)), a, sc.n_steps)
    core.fly(PlantPort(Plant(sc)), b, sc.n_steps)
    assert a.frames == b.frames


def test_replay_sends_the_frames_without_a_plant(aocs_lcm):
    sc = load("irassi_rw", {"duration_s": 1.0})
    first = _Echo(4)
    core.fly(PlantPort(Plant(sc)), first, sc.n_steps)
    again, log = _Echo(4), _Log()
    assert core.replay(again, first.frames, hooks=[log]) == sc.n_steps
    assert again.frames == first.frames and log.ended is None and {r[1] for r in log.rows} == {None}
