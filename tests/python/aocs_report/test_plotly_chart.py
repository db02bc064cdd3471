"""Chart blocks: the plotly figure (panels, levels, marks, point ids), the page carrying plotly.js once and each link
list once, and Markdown's stand-in. (That the page draws in a browser: tests/e2e/test_report_browser.py.)"""
from __future__ import annotations

import base64
import gzip
import json
import re

import numpy as np
import pytest

from aocs_report import html, markdown, plotly_chart
from aocs_report.document import Chart, Document, Level, Mark, Panel, Section, Trace


def _chart(links=None) -> Chart:
    t = np.linspace(0.0, 10.0, 11)
    return Chart("errors", "t (s)", [Panel("error (arcsec)", log_y=True, levels=[Level(0.3, "requirement")]),
                                     Panel("torque (N m)")],
                 [Trace("pointing", t, t ** 2, 0), Trace("torque x", t, -t, 1, style="steps"),
                  Trace("runs", t, t, 1, style="markers", ids=np.arange(11))],
                 [Mark(4.0, "event")], links=links)


def _bdata(v) -> np.ndarray:
    """plotly's typed-array encoding back to numbers."""
    return np.frombuffer(base64.b64decode(v["bdata"]), dtype=np.dtype(v["dtype"]))


def test_figure_has_a_subplot_per_panel_levels_marks_and_ids():
    fig = json.loads(plotly_chart.figure_json(_chart()))
    names = [d["name"] for d in fig["data"]]
    assert names == ["pointing", "torque x", "runs", "requirement"]
    by = {d["name"]: d for d in fig["data"]}
    assert by["pointing"].get("yaxis", "y") == "y" and by["torque x"]["yaxis"] == "y2"
    assert by["torque x"]["line"]["shape"] == "hv"
    assert _bdata(by["pointing"]["y"]).tolist() == pytest.approx([x * x for x in range(11)])
    assert _bdata(by["runs"]["customdata"]).tolist() == list(range(11))
    # the level spans the chart's x range at its value, on its panel
    assert by["requirement"]["y"] == [0.3, 0.3] and by["requirement"]["x"] == [0.0, 10.0]
    lay = fig["layout"]
    assert lay["yaxis"]["type"] == "log" and lay["yaxis2"]["type"] == "linear"
    assert lay["xaxis"]["matches"] == "x2"            # one time axis: zooming one panel zooms the other
    assert lay["xaxis2"]["title"]["text"] == "t (s)"
    assert [s["x0"] for s in lay["shapes"]] == [4.0] and lay["annotations"][0]["text"] == "event"


def test_a_trace_on_a_missing_panel_is_refused():
    with pytest.raises(ValueError, match="panel 2 of 1"):
        Chart("c", "t", [Panel("y")], [Trace("a", [0], [0], 2)])
    with pytest.raises(ValueError, match="style"):
        Chart("c", "t", [Panel("y")], [Trace("a", [0], [0], 0, style="bars")])


def test_page_carries_plotly_js_once_and_each_link_list_once():
    links = ["aocs run a", "aocs run b"]
    doc = Document("T").add(_chart(links), Section("more").add(_chart(links), _chart()))
    page = html.render(doc)
    assert page.count('id="plotly-js-gz"') == 1
    gz = re.search(r'<script id="plotly-js-gz"[^>]*>([^<]+)</script>', page).group(1)
    from plotly.offline import get_plotlyjs

    assert gzip.decompress(base64.b64decode(gz)).decode() == get_plotlyjs()
    assert page.count('type="application/json" id="links-1"') == 1 and 'id="links-2"' not in page
    calls = re.findall(r'aocsPlot\("(chart-\d+)", .*?, (null|"links-\d+")\);', page)
    assert calls == [("chart-1", '"links-1"'), ("chart-2", '"links-1"'), ("chart-3", "null")]
    assert 'id="chart-1-link"' in page and 'id="chart-3-link"' not in page


def test_a_page_without_charts_has_no_plotly():
    assert "plotly" not in html.render(Document("T"))


def test_markdown_says_where_the_chart_is():
    assert markdown.render(Document("T").add(_chart())) == "# T\n\n*Interactive figure: errors (in the HTML report).*\n"


def test_script_end_tags_in_text_cannot_close_the_script():
    ch = Chart("</script><b>x", "t", [Panel("y")], [Trace("</script>", [0.0], [1.0])], links=["</script>"])
    page = html.render(Document("T").add(ch))
    body = page.split("<body>", 1)[1]
    assert body.count("</script>") == 2     # the links element's and the drawing call's own
