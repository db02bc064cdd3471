"""Bode and Nichols plots of each axis loop: the prediction (python-control's frequency response of the
discrete loop), its margins marked, and the SIL measurements over it (DPI 160, aocs_analysis.plots)."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from aocs_analysis import plots as P

from .loop_model import AXES, loop_at, response
from .margins import grid


def _curve(big_l, i, w):
    h = response(loop_at(big_l, i), w)[0, 0]
    return 20 * np.log10(np.abs(h)), np.degrees(np.unwrap(np.angle(h)))


def _wrap_near(deg, ref):
    """deg shifted by whole turns to be nearest ref (measured phase against the unwrapped prediction)."""
    return deg + 360.0 * np.round((ref - deg) / 360.0)


def draw(res: dict, big_l, out: Path) -> list[Path]:
    out.mkdir(parents=True, exist_ok=True)
    w = grid(res["dt_s"], n=1200)
    wcs = [m["crossover_rad_s"] for m in res["loops"].values() if m.get("crossover_rad_s")]
    w = w[w >= (min(wcs) / 100.0 if wcs else 1e-3)]
    name = res["law"] + (f" ({res['table']})" if res["table"] else "")
    title = f"{res['scenario']} {name}: loop at the plant input, {res['control_rate_hz']:g} Hz ZOH + " \
            f"{res['delay_periods']} period delay"
    plt = P._plt()
    fig, (ag, ap) = plt.subplots(2, 1, figsize=(P.FIG_WIDTH_IN, 7.0), sharex=True)
    fig2, an = plt.subplots(figsize=(P.FIG_WIDTH_IN, 6.0))
    for i, ax in enumerate(AXES):
        g, ph = _curve(big_l, i, w)
        m = res["loops"][ax]
        c = P.COLORS[i]
        gm, pm = m["gain_margin_db"], m["phase_margin_deg"]
        lab = f"{ax}: GM {gm:.1f} dB" if gm is not None else f"{ax}: GM inf"
        lab += f", PM {pm:.1f} deg" if pm is not None else ""
        ag.semilogx(w, g, color=c, lw=1.2, label=lab)
        ap.semilogx(w, ph, color=c, lw=1.2, label=f"{ax} predicted")
        an.plot(ph, g, color=c, lw=1.2, label=lab)
        if m.get("crossover_rad_s"):
            ag.axvline(m["crossover_rad_s"], color=c, ls=":", lw=0.8)
        if m.get("phase_crossover_rad_s") and gm is not None:
            ag.annotate("", xy=(m["phase_crossover_rad_s"], 0.0), xytext=(m["phase_crossover_rad_s"], -gm),
                        arrowprops={"arrowstyle": "<->", "color": c})
        meas = m.get("measured")
        if meas:
            f = np.array([q["frequency_rad_s"] for q in meas])
            mg = np.array([q["gain_db"] for q in meas])
            mp = _wrap_near(np.array([q["phase_deg"] for q in meas]), np.interp(np.log(f), np.log(w), ph))
            ag.semilogx(f, mg, "o", color=c, mec="black", ms=6, label=f"{ax} measured in SIL ({len(f)} tones)")
            ap.semilogx(f, mp, "o", color=c, mec="black", ms=6)
            an.plot(mp, mg, "o", color=c, mec="black", ms=6, label=f"{ax} measured in SIL")
    ag.axhline(0.0, color="black", lw=0.8)
    ap.axhline(-180.0, color="black", lw=0.8)
    ag.set_ylabel("|L| (dB)", fontsize=P.LABEL_PT)
    ap.set_ylabel("arg L (deg)", fontsize=P.LABEL_PT)
    ap.set_xlabel("frequency (rad/s); dotted: gain crossovers, arrows: gain margins", fontsize=P.LABEL_PT)
    ag.set_title(title, fontsize=P.TITLE_PT)
    ag.set_ylim(-40, 60)
    for a in (ag, ap):
        a.grid(True, which="both", alpha=0.3)
    P.legend(ag)
    P.legend(ap)
    an.plot([-180.0], [0.0], "k+", ms=14, mew=2, label="critical point (-180 deg, 0 dB)")
    an.set_xlim(-360, 0)
    an.set_ylim(-30, 40)
    an.set_xlabel("arg L (deg)", fontsize=P.LABEL_PT)
    an.set_ylabel("|L| (dB)", fontsize=P.LABEL_PT)
    an.set_title(f"Nichols: {title}", fontsize=P.TITLE_PT - 1)
    an.grid(True, alpha=0.3)
    P.legend(an)
    return [P.save(fig, out / "bode.png"), P.save(fig2, out / "nichols.png")]
