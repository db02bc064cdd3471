"""[[sensors.faults]] (sensors/faults.py): channels are the sensors the scenario has, each kind goes only
where a sensor takes it, and every error is one line naming the file and the key."""
import pytest

from aocs_plant import ScenarioError, load


def _fault(**kw):
    f = {"channel": "rate", "kind": "dropout", "start_s": 1.0, "end_s": 2.0}
    f.update(kw)
    return {"sensors.faults": [f]}


def _error(sid, ov) -> str:
    with pytest.raises(ScenarioError) as err:
        load(sid, ov)
    msg = str(err.value)
    assert "\n" not in msg and msg.startswith(str(load(sid).path) + ": sensors.faults[0].")
    return msg.split(": ", 1)[1]


def test_faults_are_read_in_order():
    sc = load("irassi_large", {"sensors.faults": [
        {"channel": "attitude", "kind": "nonunit", "start_s": 3.0, "end_s": 3.5, "factor": 1.2},
        {"channel": "all", "kind": "nan", "start_s": 0.0, "end_s": 1.0}]})
    assert [(f.channel, f.kind, f.start_s, f.end_s, f.factor) for f in sc.sensors.faults] == [
        ("attitude", "nonunit", 3.0, 3.5, 1.2), ("all", "nan", 0.0, 1.0, 1.5)]
    assert not sc.sensors.ideal and load("irassi_large").sensors.ideal


def test_the_channels_are_the_sensors_of_the_plant_kind():
    assert _error("irassi_large", _fault(channel="position")) == (
        "sensors.faults[0].channel: unknown value 'position', expected one of attitude, rate, all")
    assert _error("landsat8_q1", _fault(channel="rate")) == (
        "sensors.faults[0].channel: unknown value 'rate', expected one of position, velocity, all")
    # the tachometers take no faults: not a channel
    assert "unknown value 'tachometer'" in _error("irassi_rw", _fault(channel="tachometer"))


def test_nonunit_goes_only_to_the_quaternion_sensors():
    assert _error("irassi_large", _fault(kind="nonunit")) == (
        "sensors.faults[0].kind: nonunit applies to the attitude and star_tracker channel only")
    assert _error("landsat8_q1", _fault(channel="all", kind="nonunit")) == (
        "sensors.faults[0].kind: nonunit applies to the attitude and star_tracker channel only")
    load("irassi_large", _fault(channel="all", kind="nonunit"))     # all: the attitude sensor takes it
    assert _error("irassi_large", _fault(channel="attitude", kind="nonunit", factor=1.0)) == (
        "sensors.faults[0].factor: a nonunit fault needs factor != 1")


def test_times_are_checked():
    assert _error("irassi_large", _fault(start_s=2.0, end_s=2.0)).startswith("sensors.faults[0].end_s: must be after")
    assert _error("irassi_large", _fault(start_s=600.0, end_s=700.0)) == (
        "sensors.faults[0].start_s: 600.0 s is not inside the run (duration_s = 500.0)")
    assert _error("irassi_large", _fault(colour=1)) == "sensors.faults[0].colour: unknown key"
