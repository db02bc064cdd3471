"""`aocs compare` text: IRASSI columns only on IRASSI scenarios, no host timing in docs/results.md,
the no-integral-action explanation only for a run that has settled (issue 10 item 7). The rows are
built from metrics dicts with the keys a run writes; the numbers are chosen here."""
from __future__ import annotations

import numpy as np

from aocs_compare import compare as C
from aocs_plant.scenario import load
from aocs_report import markdown
from aocs_report.document import Column, Document


def _table(sc, rows, **kw) -> tuple[list[str], tuple]:
    """The comparison table's header labels (title and unit, as printed) and rows."""
    t = C.comparison_table_for(sc, rows, **kw)
    return [c.label for c in t.columns], t.rows


def _section_text(section) -> str:
    return "" if section is None else markdown.render(Document("t").add(section))


def _metrics(final, settle, k=None):
    m = {"limits": {"unlimited": True, "axis": None}, "settle_time_s": settle,
         "timing": {"step_ns_median": 800.0, "step_ns_p99": 1500.0, "budget_ns": 2000.0, "overruns": 3},
         "counters": {"time_in_saturation_s": 0.0}, "max_abs_torque_nm": [1.0, 1.0, 1.0],
         "max_torque_norm_nm": 1.7, "effort": 10.0,
         "pointing_error_arcsec": {"final_max": final, "per_axis_final_max": [final] * 3,
                                   "qe_arcsec_final_max": [final / 2] * 3}}
    if k is not None:
        m["gain"] = {"K": k.tolist(), "source": "designed"}
    return m


def test_irassi_columns_only_on_irassi_scenarios():
    rows = [C.Row("quat_pd", "quat_pd", None, metrics=_metrics(0.21, 20.0))]
    head, body = _table(load("irassi_small"), rows)
    assert {"qe_arcsec max", "0.3 as", "0.05 as", "step ns med/p99/budget"} <= set(head)
    assert body[0][head.index("0.3 as")] == "yes" and body[0][head.index("0.05 as")] == "NO"
    head, _ = _table(load("geo_hinf"), [C.Row("hinf-x", "hinf", "hinf_min", metrics=_metrics(4.0, 90.0))])
    assert not {"qe_arcsec max", "0.3 as", "0.05 as"} & set(head)
    head, body = _table(load("irassi_small"), rows, timing=False)
    assert "step ns med/p99/budget" not in head and "overruns" not in head and len(body[0]) == len(head)


def test_no_integral_action_explained_only_for_a_settled_run():
    sc = load("irassi_small")
    k_ref = np.zeros((3, 6))
    np.fill_diagonal(k_ref[:, :3], 447.2135954999579)
    # settled and at d / kp: the explanation holds
    settled = C.Row("lqr_quat-lqr_quat_ref", "lqr_quat", "lqr_quat_ref", metrics=_metrics(1.885, 38.8))
    text = _section_text(C.steady_state_section(sc, [settled]))
    assert "misses 0.3 arcsec because it has no integral action" in text
    # the same law still slewing (never settled): no steady state, no such explanation
    slewing = C.Row("lqr_quat-lqr_quat_ref", "lqr_quat", "lqr_quat_ref", metrics=_metrics(900.0, None))
    text = _section_text(C.steady_state_section(sc, [slewing]))
    assert "no integral action and its proportional gain" not in text
    assert "not settled: the slew has not finished" in text
    # a K designed for the scenario: its own kp (1414 = sqrt(2000 / 0.001)), not the table's
    k = np.zeros((3, 6))
    np.fill_diagonal(k[:, :3], 1414.2135623730951)
    designed = C.Row("lqr_quat", "lqr_quat", None, metrics=_metrics(0.596, 22.8, k))
    assert C.proportional_gain(sc, designed).tolist() == [1414.2135623730951] * 3


def _wheel(i, speed, torque, failed=False, at_torque=0.0):
    return {"wheel": i, "failed": failed, "peak_speed_rad_s": speed, "speed_limit_rad_s": 600.0,
            "peak_motor_torque_nm": torque, "torque_limit_nm": 0.25, "time_at_torque_limit_s": at_torque,
            "time_at_speed_limit_s": 0.0}


def test_wheel_columns_only_on_a_wheel_array_with_the_worst_wheel_and_the_removed_ones():
    rw = _metrics(0.21, 215.8)
    # wheel 0 failed (its figures ignored), wheel 2 the fastest, wheel 1 the hardest pushed
    rw["wheels"] = {"removed": [0], "within_limits": True,
                    "per_wheel": [_wheel(0, 599.0, 0.25, failed=True), _wheel(1, 120.0, 0.2, at_torque=1.5),
                                  _wheel(2, 300.0, 0.1), _wheel(3, 30.0, 0.05)]}
    over = _metrics(0.21, 215.8)
    over["wheels"] = {"removed": [], "within_limits": False, "per_wheel": [_wheel(i, 600.0, 0.25) for i in range(4)]}
    head, body = _table(load("irassi_rw"), [C.Row("a", "quat_pd", None, metrics=rw),
                                                      C.Row("b", "quat_pd", None, metrics=over)])
    cells = dict(zip(head, body[0]))
    assert (cells["removed"], cells["peak speed/max"], cells["peak u_s/max"], cells["at limit s"],
            cells["wheel limits"]) == ("0", "0.500", "0.800", "1.5", "within")
    assert dict(zip(head, body[1]))["wheel limits"] == "EXCEEDED" and len(body[1]) == len(head)
    head, _ = _table(load("irassi_small"), [C.Row("quat_pd", "quat_pd", None, metrics=_metrics(0.2, 20))])
    assert not {c.label for c in C.WHEEL_COLUMNS} & set(head)


def test_comparison_columns_carry_their_units():
    t = C.comparison_table_for(load("irassi_small"), [C.Row("quat_pd", "quat_pd", None, metrics=_metrics(0.2, 20))])
    assert {Column("settle", "s"), Column("max norm u", "N m"), Column("effort", "N m s"), Column("limit", "N m")} \
        <= set(t.columns)
    t = C.comparison_table_for(load("landsat8_q1"), [])
    assert {Column("pos err max", "m"), Column("vel err max", "m/s"), Column("max norm F", "N")} <= set(t.columns)
