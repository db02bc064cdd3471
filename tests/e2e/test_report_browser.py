"""The HTML reports in a real browser (issue 23): a run, a comparison and a campaign each written by its command's
--html, opened in headless Chromium (Debian's package, scripts/setup.sh) over the DevTools protocol
(tests/browser.py): no console error, every plot drawn (a plot area of real size whose traces have drawn paths,
the expected trace names), nothing loaded from anywhere, and for the campaign a real mouse click on a point shows
that run's repeat command. A screenshot of each page is kept in out/test-output/report-browser/."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "tests"))
from browser import Browser, chromium  # noqa: E402 - tests/browser.py, beside conftest.py

SHOTS = REPO / "out" / "test-output" / "report-browser"
SHORT = ["--set", "duration_s=20.0", "--set", "metrics.window_s=10.0"]

#: per plot: its title, height and width, traces drawn (SVG trace groups with a non-empty path or point), names
PLOTS_JS = """Array.from(document.querySelectorAll('.plot')).map(d => {
  const r = d.getBoundingClientRect();
  const drawn = Array.from(d.querySelectorAll('.scatterlayer .trace')).filter(g =>
      Array.from(g.querySelectorAll('path')).some(p => (p.getAttribute('d') || '').length > 10)).length;
  return {title: d.dataset.title, h: r.height, w: r.width, drawn: drawn, names: d.data.map(t => t.name)};
})"""


def aocs(*args, timeout=600):
    p = subprocess.run([sys.executable, "-m", "aocs.cli", *args], capture_output=True, text=True, timeout=timeout)
    assert p.returncode == 0, p.stdout + p.stderr
    return p


@pytest.fixture(scope="module")
def browser():
    if chromium() is None:
        pytest.fail("chromium not installed: scripts/setup.sh installs Debian's chromium")
    SHOTS.mkdir(parents=True, exist_ok=True)
    with Browser() as b:
        yield b


def open_page(browser, path: Path, name: str):
    page = browser.open(path, wait_js="window.aocsPlotsDrawn === document.querySelectorAll('.plot').length")
    page.screenshot(SHOTS / f"{name}.png")
    assert page.errors == [], page.errors
    assert page.evaluate("document.querySelectorAll('script[src], link[href], img[src^=\"http\"]').length") == 0
    plots = page.evaluate(PLOTS_JS)
    assert plots, "no plot on the page"
    for p in plots:
        assert p["h"] > 150 and p["w"] > 400, p
        assert p["drawn"] >= 1, f"{p['title']}: no trace drawn"
    return page, plots


def test_run_report(private_netns, browser, tmp_path):
    html = tmp_path / "r.html"
    aocs("run", "irassi_rw", "--law", "quat_pid", "--guidance", "slew", "--duration", "200", "--out",
         str(tmp_path / "run"), "--no-plots", "-q", "--html", str(html))
    assert (tmp_path / "run" / "telemetry.parquet").is_file()
    page, plots = open_page(browser, html, "run")
    names = plots[0]["names"]
    for n in ("pointing error (true vs target)", "torque command x", "wheel 1 torque command", "wheel 4 speed",
              "+speed limit 600 rad/s", "+torque limit 0.25 N m", "|H| total (body + wheels)",
              "mode (0 standby, 1 nominal, 2 safe)", "requirement 0.3 arcsec"):
        assert n in names, names
    assert plots[0]["drawn"] == len(names)        # every trace drawn (none empty on its axes)
    text = page.evaluate("document.body.innerText")
    assert "aocs run irassi_rw --law quat_pid" in text and "Verdict: passed" in text


def test_run_report_with_a_filter_shows_knowledge_and_control_error_with_3_sigma(private_netns, browser, tmp_path):
    html = tmp_path / "mekf.html"
    aocs("run", "irassi_hold_mekf", "--duration", "60", "--out", str(tmp_path / "run"), "--no-plots", "-q",
         "--html", str(html))
    page, plots = open_page(browser, html, "run-mekf")
    names = plots[0]["names"]
    for n in ("pointing error (true vs target)", "control error (estimate vs target)", "knowledge error x",
              "+3 sigma x (filter)", "-3 sigma z (filter)"):
        assert n in names, names


def test_compare_report(private_netns, browser, tmp_path):
    html = tmp_path / "c.html"
    aocs("compare", "irassi_small", "--laws", "quat_pd,smc", "--duration", "30", "--out", str(tmp_path / "cmp"),
         "-q", "--html", str(html))
    page, plots = open_page(browser, html, "compare")
    names = plots[0]["names"]
    assert {"quat_pd", "smc", "quat_pd |u|", "smc |u|"} <= set(names), names
    assert "aocs compare irassi_small --laws quat_pd,smc --duration 30" in page.evaluate("document.body.innerText")


def test_campaign_report_links_each_point_to_its_repeat_command(private_netns, browser, tmp_path):
    html, out = tmp_path / "mc.html", tmp_path / "mc"
    aocs("campaign", "irassi_small", "--law", "quat_pd", "--runs", "3", "--seed", "2", *SHORT, "--disperse",
         "plant.w0[0]=normal:0:1e-4", "--workers", "1", "--out", str(out), "-q", "--no-plots", "--html", str(html))
    page, plots = open_page(browser, html, "campaign")
    titles = [p["title"] for p in plots]
    assert any(t.startswith("CDF: pointing error") for t in titles), titles
    assert any("against plant.w0[0]" in t for t in titles), titles
    assert any(t.startswith("pointing error over 3 runs") for t in titles), titles
    # a real click on the first CDF's first point: the browser's own mouse events through plotly
    xy = page.evaluate("""(function () {
      const d = document.querySelector('.plot');
      d.scrollIntoView();
      const pt = d.querySelector('.scatterlayer .trace .points path');
      const r = pt.getBoundingClientRect();
      return [r.x + r.width / 2, r.y + r.height / 2];
    })()""")
    for kind in ("mouseMoved", "mousePressed", "mouseReleased"):
        page.call("Input.dispatchMouseEvent", type=kind, x=xy[0], y=xy[1], button="left", clickCount=1)
    assert page.wait_for("document.getElementById('chart-1-link').textContent.startsWith('run ')", 10)
    shown = page.evaluate("document.getElementById('chart-1-link').textContent")
    import pyarrow.parquet as pq

    rows = pq.read_table(out / "results.parquet").to_pandas()
    index = int(shown.split()[1].rstrip(":"))
    assert shown == f"run {index}: " + rows.set_index("index").loc[index, "repeat_command"]
    page.screenshot(SHOTS / "campaign-clicked.png")
