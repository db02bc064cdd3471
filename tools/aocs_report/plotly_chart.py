"""A Chart (document.py) as a plotly figure, and plotly.js for a page that must open with no network.

figure_json(chart) is the figure as plotly's JSON (numbers as base64 typed arrays, float32: a 1000 s run
at 10 Hz stays small); panels are subplots on one shared x axis, each with its own legend at its right;
levels are dashed horizontal traces named with their label (they show in the legend and can be hidden);
marks are vertical lines across every panel, labelled at the top.

plotly.js (about 4.8 MB minified) is embedded once per page gzip-compressed and base64-encoded (about
2 MB) and unpacked by the browser (DecompressionStream, every current browser) before the figures are
drawn: the page needs nothing from the network and a report stays well under 5 MB.
"""
from __future__ import annotations

import base64
import gzip
import html
import json
from functools import lru_cache

import numpy as np

from .document import Chart

#: trace colours, in order (plotly's default cycle, as matplotlib's tab10)
COLORWAY = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22",
            "#17becf")
LEVEL_COLORS = ("#d62728", "#2ca02c", "#000000", "#9467bd")
#: height of one panel and of the title and axis margins, px
PANEL_PX, FRAME_PX = 230, 110
DASH = {"solid": "solid", "dash": "dash", "dot": "dot"}


def _array(v) -> np.ndarray:
    a = np.asarray(v, dtype=float)
    return a.astype(np.float32)


def figure(chart: Chart):
    """The plotly Figure of the chart."""
    import plotly.graph_objects as go  # deferred: ~0.3 s, only when a page with charts is written
    from plotly.subplots import make_subplots  # deferred: see above

    n = len(chart.panels)
    spacing = 0.06 if n > 1 else 0.0
    fig = make_subplots(rows=n, cols=1, shared_xaxes=True, vertical_spacing=spacing)
    height = FRAME_PX + PANEL_PX * n
    xs = [np.asarray(t.x, float) for t in chart.traces]
    finite = np.concatenate([x[np.isfinite(x)] for x in xs]) if xs else np.zeros(0)
    x_range = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 1.0)
    in_panel = [0] * n
    for tr in chart.traces:
        color = tr.color or COLORWAY[in_panel[tr.panel] % len(COLORWAY)]   # each panel's colours from the first
        in_panel[tr.panel] += 1
        kw = {"name": tr.name, "x": _array(tr.x), "y": _array(tr.y), "legend": _legend(tr.panel),
              "legendgroup": tr.group or tr.name}
        if tr.style == "markers":
            kw.update(mode="markers", marker={"size": 6, "color": color})
        else:
            kw.update(mode="lines", line={"width": 1.3, "dash": DASH.get(tr.dash, "solid"), "color": color,
                                          "shape": "hv" if tr.style == "steps" else "linear"})
        if tr.ids is not None:
            kw["customdata"] = np.asarray(tr.ids, dtype=np.int32)
            kw["hovertemplate"] = ("run %{customdata}<br>x %{x:.4g}<br>y %{y:.4g}<extra>" + tr.name
                                   + " (click: repeat command)</extra>")
        fig.add_trace(go.Scatter(**kw), row=tr.panel + 1, col=1)
    for p, panel in enumerate(chart.panels):
        fig.update_yaxes(title_text=panel.y_label, type="log" if panel.log_y else "linear", row=p + 1, col=1,
                         **({"range": list(panel.y_range)} if panel.y_range else {}))
        for j, lv in enumerate(panel.levels):
            fig.add_trace(go.Scatter(x=[x_range[0], x_range[1]], y=[lv.value, lv.value], mode="lines",
                                     name=lv.label, legend=_legend(p), hoverinfo="name+y",
                                     line={"width": 1.2, "dash": "dash", "color": LEVEL_COLORS[j % len(LEVEL_COLORS)]}),
                          row=p + 1, col=1)
    fig.update_xaxes(title_text=chart.x_label, row=n, col=1)
    fig.update_xaxes(showgrid=True, gridcolor="#e5e5e5", zeroline=False)
    fig.update_yaxes(showgrid=True, gridcolor="#e5e5e5", zeroline=False, exponentformat="power")
    shapes, notes = [], []
    for m in chart.marks:
        shapes.append({"type": "line", "xref": "x", "yref": "paper", "x0": m.x, "x1": m.x, "y0": 0, "y1": 1,
                       "line": {"width": 1, "dash": "dot", "color": "#555"}})
        notes.append({"x": m.x, "xref": "x", "y": 1.0, "yref": "paper", "text": m.label, "showarrow": False,
                      "textangle": -90, "xanchor": "right", "yanchor": "top", "font": {"size": 10, "color": "#555"}})
    layout = {"template": "none", "colorway": list(COLORWAY), "height": height, "title": {"text": chart.title},
              "margin": {"l": 80, "r": 260, "t": 60, "b": 50}, "hovermode": "closest", "shapes": shapes,
              "annotations": notes, "plot_bgcolor": "white", "paper_bgcolor": "white"}
    for p in range(n):
        dom = fig.layout[f"yaxis{'' if p == 0 else p + 1}"].domain
        layout[_legend(p)] = {"x": 1.01, "xanchor": "left", "y": dom[1], "yanchor": "top", "font": {"size": 10},
                              "tracegroupgap": 2}
    fig.update_layout(**layout)
    return fig


def _legend(panel: int) -> str:
    return "legend" if panel == 0 else f"legend{panel + 1}"


def figure_json(chart: Chart) -> str:
    """The figure as JSON for Plotly.newPlot (data and layout)."""
    import plotly.io as pio  # deferred: see figure

    return pio.to_json(figure(chart), validate=False, pretty=False)


@lru_cache(maxsize=1)
def plotly_js_gzip_b64() -> str:
    """plotly.js, minified, gzip-compressed, base64: what the page unpacks."""
    from plotly.offline import get_plotlyjs  # deferred: see figure

    return base64.b64encode(gzip.compress(get_plotlyjs().encode("utf-8"), compresslevel=9, mtime=0)).decode("ascii")


def plotly_js_version() -> str:
    from plotly.offline import get_plotlyjs_version  # deferred: see figure

    return get_plotlyjs_version()


#: unpacks plotly.js (the element #plotly-js-gz) and defines aocsPlot(div, figure, links), which draws a
#: figure once plotly.js is there and shows, for a point with an id, the chart's link text below it
LOADER = """window.aocsPlotly = (async function () {
  const b64 = document.getElementById("plotly-js-gz").textContent.trim();
  const bytes = Uint8Array.from(atob(b64), c => c.charCodeAt(0));
  const stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream("gzip"));
  const code = await new Response(stream).text();
  const s = document.createElement("script");
  s.textContent = code;
  document.head.appendChild(s);
  return window.Plotly;
})();
window.aocsPlotsDrawn = 0;
window.aocsPlot = function (id, fig, linksId) {
  window.aocsPlotly.then(function (Plotly) {
    const div = document.getElementById(id);
    return Plotly.newPlot(div, fig.data, fig.layout, {responsive: true, displaylogo: false}).then(function () {
      window.aocsPlotsDrawn += 1;
      if (!linksId) { return; }
      const links = JSON.parse(document.getElementById(linksId).textContent);
      const out = document.getElementById(id + "-link");
      div.on("plotly_click", function (ev) {
        const p = ev.points[0];
        if (p.customdata === undefined) { return; }
        out.textContent = "run " + p.customdata + ": " + links[p.customdata];
      });
    });
  }).catch(function (err) { console.error("aocs report: " + err); });
};"""


def page_head() -> str:
    """The script elements every page with charts carries once (in its head)."""
    return (f'<script id="plotly-js-gz" type="application/octet-stream" data-plotly-version="{plotly_js_version()}">'
            f"{plotly_js_gzip_b64()}</script>\n<script>\n{LOADER}\n</script>")


def links_json(links) -> str:
    """The links as JSON safe inside a script element."""
    return json.dumps(list(links)).replace("</", "<\\/")


def chart_html(chart: Chart, div_id: str, links_id: str | None) -> str:
    """The chart's element and the call that draws it."""
    fig = figure_json(chart).replace("</", "<\\/")
    note = f'<p class="chart-note">{_esc(chart.note)}</p>' if chart.note else ""
    link = (f'<pre class="chart-link" id="{div_id}-link">click a point for its run\'s repeat command</pre>'
            if links_id else "")
    arg = f'"{links_id}"' if links_id else "null"
    return (f'<figure class="chart"><div class="plot" id="{div_id}" data-title="{_esc(chart.title)}"></div>{link}'
            f"{note}</figure>\n<script>aocsPlot(\"{div_id}\", {fig}, {arg});</script>")


def _esc(s: str) -> str:
    return html.escape(s)
