"""The run JSON's `faults` entries (aocs_analysis/faults.py, docs/spec.md 5.14.7): injected faults joined with
synthetic event logs and synthetic pointing series, each expected figure worked out by hand in the test."""
import numpy as np
import pytest

from aocs_analysis import faults as F
from aocs_analysis import verdict
from aocs_plant.faults import Fault

T = np.arange(0.0, 300.0 + 1e-9, 0.1)


def ev(t, name, unit_kind, unit=-1, severity="warning"):
    return {"t_s": t, "id": 1, "name": name, "severity": severity, "unit_kind": unit_kind, "unit": unit,
            "value": 1.0, "threshold": 0.5}


def pointing(recover_at=None, bad=100.0, good=0.1):
    """0.1 arcsec until 60 s, `bad` from then, back to `good` from recover_at (never if None)."""
    p = np.full(T.size, good)
    p[T >= 60.0 - 1e-9] = bad
    if recover_at is not None:
        p[T >= recover_at - 1e-9] = good
    return p


WHEEL = Fault("wheel_torque_loss", 1, 60.0, 300.0)


def test_detected_isolated_recovered_wheel():
    events = [ev(61.5, "wheel_residual_high", "wheel", 1), ev(62.0, "wheel_isolated", "wheel", 1, "error")]
    (e,) = F.entries([WHEEL], events, T, pointing(150.0), 0.3, 50.0)
    assert e["detected_s"] == 61.5 and e["isolated"] is True
    assert e["detection_latency_s"] == pytest.approx(1.5)
    assert e["recovered_s"] == pytest.approx(150.0)
    assert e["recovery_time_s"] == pytest.approx(150.0 - 61.5)
    assert e["handled"] and not F.not_handled([e])


def test_never_detected_is_not_handled_and_fails_the_verdict():
    (e,) = F.entries([WHEEL], [], T, pointing(150.0), 0.3, 50.0)
    assert e["detected_s"] is None and not e["isolated"]
    assert e["recovered_s"] is None and e["recovery_time_s"] is None and not e["handled"]
    v = verdict.judge({"faults": [e]}, [], realtime=False)
    assert not v["passed"] and v["failures"][0]["check"] == "fault-management"
    assert "never detected" in v["failures"][0]["reason"]
    assert verdict.judge({"faults": [e]}, [], realtime=False, allow=("fault-management",))["passed"]


@pytest.mark.parametrize("other", [2, 0])   # wheel 0 is a wheel like any other, not "no unit"
def test_an_event_of_another_wheel_is_not_this_faults_detection(other):
    events = [ev(61.0, "wheel_residual_high", "wheel", other), ev(61.2, "wheel_isolated", "wheel", other)]
    (e,) = F.entries([WHEEL], events, T, pointing(150.0), 0.3, 50.0)
    assert e["detected_s"] is None and e["isolated"] is False


def test_a_false_alarm_before_the_start_is_not_the_detection():
    events = [ev(30.0, "wheel_residual_high", "wheel", 1), ev(64.0, "wheel_residual_high", "wheel", 1)]
    (e,) = F.entries([WHEEL], events, T, pointing(150.0), 0.3, 50.0)
    assert e["detected_s"] == 64.0 and e["events_before_start"] == 1


def test_an_event_within_a_nanosecond_of_the_start_is_the_detection_and_not_before_it():
    # event times are rounded (the flight software's ns clock): 1e-9 s before the start counts as at the start,
    # so each event is either before the fault or a detection candidate, never both
    events = [ev(60.0 - 1e-9, "wheel_residual_high", "wheel", 1), ev(60.0 - 2e-9, "wheel_residual_high", "wheel", 1)]
    (e,) = F.entries([WHEEL], events, T, pointing(150.0), 0.3, 50.0)
    assert e["detected_s"] == 60.0 - 1e-9 and e["events_before_start"] == 1


def test_a_recovery_on_the_last_sample_of_the_run_counts():
    """recovered_at from the last sample: inside there, it is the recovery (to the end of the run, shorter than the
    window); outside, none."""
    t = np.array([0.0, 1.0, 2.0])
    assert F.recovered_at(t, np.array([5.0, 5.0, 0.1]), 2.0, 0.3, 50.0) == 2.0
    assert F.recovered_at(t, np.array([5.0, 0.1, 0.1]), 1.0, 0.3, 50.0) == 1.0      # from t_from's own sample
    assert F.recovered_at(t, np.array([5.0, 5.0, 0.4]), 2.0, 0.3, 50.0) is None
    assert F.recovered_at(t, np.array([5.0, 5.0, 0.1]), 2.5, 0.3, 50.0) is None      # nothing after t_from
    assert F.recovered_at(t, np.array([5.0, 5.0, 0.3]), 2.0, 0.3, 50.0) == 2.0      # at the requirement: met


def test_an_info_event_is_not_a_detection_and_a_unitless_event_matches():
    events = [ev(61.0, "wheel_residual_high", "wheel", 1, "info"), ev(62.0, "momentum_inconsistent", "wheel", -1)]
    (e,) = F.entries([WHEEL], events, T, pointing(150.0), 0.3, 50.0)
    assert e["detected_s"] == 62.0


def test_recovery_needs_the_whole_window_inside():
    p = pointing(150.0)
    p[(T > 170.0) & (T < 170.5)] = 1.0            # a blip 20 s after the return: the stretch is too short
    events = [ev(61.0, "wheel_residual_high", "wheel", 1), ev(61.0, "wheel_isolated", "wheel", 1)]
    (e,) = F.entries([WHEEL], events, T, p, 0.3, 50.0)
    assert e["recovered_s"] == pytest.approx(170.5)
    (e,) = F.entries([WHEEL], events, T, p, 0.3, 10.0)   # a 10 s window fits before the blip
    assert e["recovered_s"] == pytest.approx(150.0)


def test_a_stretch_one_sample_short_of_the_window_is_not_a_recovery():
    """Inside from 150.0 s to 199.9 s (49.9 s: one 0.1 s sample short of the 50 s window), out at 200.0 s, inside
    again from 200.1 s to the end: recovered at 200.1 s; counting the sample that left would make it 150.0."""
    p = pointing(150.0)
    p[np.isclose(T, 200.0)] = 1.0
    assert F.recovered_at(T, p, 61.0, 0.3, 50.0) == pytest.approx(200.1)
    p[np.isclose(T, 200.0)] = 0.1                       # the same without the sample out: 150.0
    assert F.recovered_at(T, p, 61.0, 0.3, 50.0) == pytest.approx(150.0)


def test_recovery_at_the_end_of_the_run_counts_when_shorter_than_the_window():
    events = [ev(61.0, "wheel_residual_high", "wheel", 1), ev(61.0, "wheel_isolated", "wheel", 1)]
    (e,) = F.entries([WHEEL], events, T, pointing(290.0), 0.3, 50.0)
    assert e["recovered_s"] == pytest.approx(290.0)


def test_unitless_kinds_and_a_kind_without_expected_detection():
    st = Fault("st_frozen", None, 60.0, 100.0)
    outage = Fault("st_outage", None, 60.0, 70.0)
    events = [ev(63.0, "st_innovation_high", "star_tracker"), ev(63.1, "st_excluded", "star_tracker")]
    a, b = F.entries([st, outage], events, T, pointing(90.0), 0.3, 20.0)
    assert a["detected_s"] == 63.0 and a["isolated"] and a["recovered_s"] == pytest.approx(90.0)
    # the outage: the tracker's own event counts as its detection too; its recovery from its detection
    assert b["detected_s"] == 63.0 and b["handled"]
    (c,) = F.entries([outage], [], T, pointing(90.0), 0.3, 20.0)
    assert c["detected_s"] is None and c["recovered_s"] == pytest.approx(90.0) and c["handled"]


def test_events_in_any_order_and_the_json_form_of_a_fault():
    events = [ev(70.0, "wheel_residual_high", "wheel", 1), ev(65.0, "wheel_residual_high", "wheel", 1)]
    (e,) = F.entries([WHEEL.to_json()], events, T, pointing(None), 0.3, 50.0)
    assert e["detected_s"] == 65.0 and e["recovered_s"] is None
    assert F.not_handled([e]) == ["wheel_torque_loss unit 1 at 60 s: no wheel isolated, not recovered"]


def test_each_reason_a_fault_is_not_handled_in_its_own_words():
    """Never detected and never back: both said, the second as "not recovered"; detected and isolated but never
    back: the pointing named; detected and back but not isolated: only that."""
    never = F.entries([WHEEL], [], T, pointing(None), 0.3, 50.0)
    assert F.not_handled(never) == ["wheel_torque_loss unit 1 at 60 s: never detected, no wheel isolated, "
                                    "not recovered"]
    events = [ev(61.5, "wheel_residual_high", "wheel", 1), ev(62.0, "wheel_isolated", "wheel", 1, "error")]
    stays = F.entries([WHEEL], events, T, pointing(None), 0.3, 50.0)
    assert F.not_handled(stays) == ["wheel_torque_loss unit 1 at 60 s: pointing never back inside the requirement"]
    back = F.entries([WHEEL], events[:1], T, pointing(150.0), 0.3, 50.0)
    assert F.not_handled(back) == ["wheel_torque_loss unit 1 at 60 s: no wheel isolated"]


def test_the_summary_lines_name_each_fault_with_its_times():
    events = [ev(61.5, "wheel_residual_high", "wheel", 1), ev(62.0, "wheel_isolated", "wheel", 1)]
    rows = F.table_rows(F.entries([WHEEL, Fault("st_frozen", None, 10.0, 20.0)], events, T, pointing(150.0),
                                  0.3, 50.0))
    assert rows[0][0] == "fault 1: wheel_torque_loss wheel 1"
    assert "detected 61.5 s (latency 1.50 s)" in rows[0][1] and "recovered 150.0 s" in rows[0][1]
    assert rows[1][0] == "fault 2: st_frozen" and "detected never" in rows[1][1] and "NOT handled" in rows[1][1]


def test_a_recovery_is_judged_against_the_scenarios_recovery_figure_else_its_requirement_else_its_settle():
    from types import SimpleNamespace as NS
    sc = NS(metrics=NS(requirement_arcsec=0.3, recovery_arcsec=3.0), settle=NS(pointing_arcsec_max=10.0))
    assert F.requirement_of(sc) == 3.0
    sc.metrics.recovery_arcsec = None
    assert F.requirement_of(sc) == 0.3
    sc.metrics.requirement_arcsec = None
    assert F.requirement_of(sc) == 10.0
    # the same pointing (2 arcsec after 120 s) is recovered against 3 arcsec and never against 0.3
    p = pointing(recover_at=120.0, good=2.0)
    p[T < 60.0] = 0.1
    f = Fault(kind="wheel_torque_loss", unit=1, start_s=60.0, end_s=300.0)
    e = [ev(60.5, "wheel_residual_high", "wheel", 1), ev(60.5, "wheel_isolated", "wheel", 1, "error")]
    assert F.entry(f, e, T, p, 3.0, 10.0)["recovered_s"] == pytest.approx(120.0)
    assert F.entry(f, e, T, p, 0.3, 10.0)["recovered_s"] is None


def test_the_events_of_a_log_once_each_in_seq_order_with_their_units():
    """events(log): each seq once (a message heard twice is one event), in seq order, named from the registry;
    a unit of 0 (the first wheel, the x axis) is a unit, only a negative one means none; non-finite figures
    are None."""
    import types

    from aocs_analysis import events as E

    tab = {"seq": np.array([2, 1, 2]), "id": np.array([3, 2, 3]), "unit": np.array([0, -1, 0]),
           "t_s": np.array([60.5, 20.0, 60.5]), "severity": np.array([1, 1, 1]), "unit_kind": np.array([3, 2, 3]),
           "value": np.array([0.4, np.nan, 0.4]), "threshold": np.array([0.2, 9.0, 0.2])}
    evs = E.events(types.SimpleNamespace(fault_events=tab))
    assert [(e["seq"], e["name"], e["unit"]) for e in evs] == [(1, "gyro_st_inconsistent", None),
                                                              (2, "wheel_residual_high", 0)]
    assert evs[0]["value"] is None and evs[1]["value"] == 0.4 and evs[1]["severity"] == "warning"
    assert E.events(types.SimpleNamespace(fault_events=None)) == []
    one = {k: v[1:2] for k, v in tab.items()}                           # a log with a single event has it
    assert [e["name"] for e in E.events(types.SimpleNamespace(fault_events=one))] == ["gyro_st_inconsistent"]


def test_false_alarms_are_the_alarms_before_the_first_fault():
    from aocs_analysis import events as E

    evs = [ev(10.0, "link_lost", "link"), ev(20.0, "st_restored", "star_tracker", severity="info"),
           ev(59.9, "wheel_residual_high", "wheel", 2), ev(60.0, "wheel_residual_high", "wheel", 1),
           ev(90.0, "st_excluded", "star_tracker")]
    # two warnings before 60 s (the info event is no alarm); the 60 s one is the fault's own
    assert E.false_alarms(evs, [60.0, 120.0]) == 2 and E.false_alarms(evs, [120.0, 60.0]) == 2
    # a nominal run: every alarm is false
    assert E.false_alarms(evs, []) == 4 == E.alarms(evs)
    assert E.false_alarms([], []) == 0


def test_a_thruster_fault_is_detected_by_momentum_inconsistent_and_a_wheel_fault_is_not():
    """momentum_inconsistent names no unit (unit kind none): the catalogue lists it in the thruster kinds'
    detected_by (a thruster stuck open was never commanded, so the momentum test cannot name it); it detects no
    wheel fault, and before the start it is a false alarm of the thruster fault, not its detection."""
    stuck_open = Fault("thruster_stuck_open", 2, 60.0, 300.0)
    events = [ev(40.0, "momentum_inconsistent", "none"), ev(91.0, "momentum_inconsistent", "none")]
    (e,) = F.entries([stuck_open], events, T, pointing(None), 0.3, 50.0)
    assert e["detected_s"] == 91.0 and e["events_before_start"] == 1
    assert e["isolated"] is False and not e["handled"]
    (w,) = F.entries([WHEEL], [ev(91.0, "momentum_inconsistent", "none")], T, pointing(150.0), 0.3, 50.0)
    assert w["detected_s"] is None
    # a stuck-closed thruster named by the momentum test, and the dump switched off it
    closed = Fault("thruster_stuck_closed", 2, 60.0, 300.0)
    events = [ev(121.0, "thruster_ineffective", "thruster", 2),
              ev(121.0, "unload_actuator_switched", "thruster", 2, "error")]
    (c,) = F.entries([closed], events, T, pointing(100.0), 0.3, 50.0)
    assert c["detected_s"] == 121.0 and c["isolated"] is True and c["handled"]
    (c3,) = F.entries([Fault("thruster_stuck_closed", 3, 60.0, 300.0)], events, T, pointing(100.0), 0.3, 50.0)
    assert c3["detected_s"] is None and c3["isolated"] is False
