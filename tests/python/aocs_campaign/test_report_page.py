"""The campaign page from a campaign folder written by the campaign's own code (plan, dispersions, execute.record,
report.build) with 1000 runs whose rows are made here instead of flown: every point of a CDF or scatter plot is the
run it says (its id opens that run's repeat command, its x is that run's drawn input), the repeat commands are
written once, and the page of 1000 runs stays under 5 MB (issue 23)."""
from __future__ import annotations

import base64
import json
import re

import numpy as np
import pytest

from aocs_campaign import dispersions as D
from aocs_campaign import execute, report, report_page
from aocs_campaign import plan as P
from aocs_report import html, plotly_chart

RUNS = 1000


def _row(spec, rng) -> dict:
    pe = float(rng.lognormal(-1.5, 0.5))
    passed = pe < 0.4
    t = np.linspace(0.0, 500.0, 500)
    return {"index": spec.index, "status": "passed" if passed else "failed",
            "error": None if passed else "verdict: over the requirement", "wall_s": 1.0,
            "metrics": {"pointing_error_arcsec": {"final_max": pe, "final_rms": pe / 2},
                        "settle_time_s": float(rng.uniform(100, 200)), "max_torque_norm_nm": 0.8,
                        "effort": float(rng.uniform(50, 60)), "timing": {"step_ns_p99": 900.0},
                        "limits": {"commands_over_limit": 0, "commands_not_finite": 0},
                        "verdict": {"passed": passed, "failures": [], "allowed": []}},
            "series": {"t_s": t.tolist(), "pointing_error_arcsec": (3600.0 * np.exp(-t / 50.0) + pe).tolist()}}


@pytest.fixture(scope="module")
def campaign_folder(tmp_path_factory):
    out = tmp_path_factory.mktemp("mc")
    c = P.Campaign("irassi_large", "quat_pd", RUNS, 7, ["actuator.axis_limit=0.5"],
                   ["plant.w0=normal:0:1e-4", "plant.euler321_deg=rotation:2"])
    execute.prepare_dir(c, out)
    rng = np.random.default_rng(3)
    for spec in P.plan(c, D.parse_all(c.disperse)):
        execute.record(out, spec, _row(spec, rng))
    report.build(out, c, execute.read_rows(out, RUNS), plots=False)
    return out


def _values(v) -> np.ndarray:
    return np.frombuffer(base64.b64decode(v["bdata"]), dtype=np.dtype(v["dtype"])) if isinstance(v, dict) else \
        np.asarray(v)


def test_every_point_is_its_run(campaign_folder):
    doc = report_page.campaign_document(campaign_folder)
    df = report_page.read_table(campaign_folder).set_index("index")
    charts = [b for s in doc.blocks if hasattr(s, "title") and s.title == "Interactive figures" for b in s.blocks]
    scatter = next(ch for ch in charts if ch.title.endswith("against plant.w0[1]"))
    fig = json.loads(plotly_chart.figure_json(scatter))
    n = 0
    for tr in fig["data"]:
        ids = _values(tr["customdata"])
        x = _values(tr["x"])
        assert x == pytest.approx(df.loc[ids, "in.plant.w0[1]"].to_numpy(), rel=1e-6)   # float32 on the page
        assert set(df.loc[ids, "status"]) == {tr["name"].split()[0]}
        n += ids.size
    assert n == RUNS
    assert [scatter.links[i] for i in (0, 517, 999)] == [df.loc[i, "repeat_command"] for i in (0, 517, 999)]
    cdf = charts[0]
    x = np.asarray(cdf.traces[0].x)
    assert np.all(np.diff(x) >= 0) and cdf.traces[0].y[-1] == 1.0
    assert x == pytest.approx(df.loc[np.asarray(cdf.traces[0].ids), "m.pointing_error_arcsec.final_max"].to_numpy())


def test_the_page_of_1000_runs_is_under_5_mb_with_each_command_once(campaign_folder):
    page = html.render(report_page.campaign_document(campaign_folder))
    size = len(page.encode())
    print(f"campaign page of {RUNS} runs: {size / 1e6:.2f} MB")
    assert size < 5e6
    assert len(re.findall(r'type="application/json" id="links-\d+"', page)) == 1
    cmd = report_page.read_table(campaign_folder)["repeat_command"].iloc[0]
    assert page.count(json.dumps(cmd)[1:-1].replace("</", "<\\/")) == 1
