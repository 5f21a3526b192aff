"""Along the mandrel: winding angle, band layers and (when the plan carries it) wall thickness against t.

- Winding angle: |alpha| of every laid pass, interpolated onto PROFILE_STATIONS stations; the band
  between the least and the largest over the passes (they differ on bends and non-circular sections)
  and their mean.
- Band layers: each layer's band count averaged around the perimeter (coverage_map.py), stacked: the
  plies the laminate builds up, 2 per even +-alpha layer, piling up toward vessel turnarounds.
- Thickness (mm), stacked, for layers that carry a laminate record (a job with a material); plans
  without one simply have no thickness panel.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from winder.winding.results import LayerPlan, PassKind, WindingPlan
from winder.report.coverage_map import LayerCoverageMap
from winder.report.plotting import axis, axis_key, base_layout, colors, rounded, subplot_domains

PROFILE_STATIONS = 400


def angle_profile(layer: LayerPlan, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Least, mean and largest |alpha| (deg) over the layer's wound passes at stations t ((n,) each;
    NaN where no pass lies; dwells and turnarounds, past the winding region, are not wound at the
    layer's angle)."""
    rows = []
    for p in layer.passes:
        if p.kind in (PassKind.DWELL, PassKind.TURNAROUND) or p.t.size < 2:
            continue
        order = slice(None) if p.t[-1] > p.t[0] else slice(None, None, -1)
        tp, ap = p.t[order], np.abs(p.alpha_deg[order])
        rows.append(np.where((t >= tp[0]) & (t <= tp[-1]), np.interp(t, tp, ap), np.nan))
    if not rows:
        nan = np.full(t.shape, np.nan)
        return nan, nan, nan
    grid = np.vstack(rows)
    seen = np.isfinite(grid).any(axis=0)
    with np.errstate(invalid="ignore"):
        lo = np.where(seen, np.nanmin(np.where(seen, grid, 0.0), axis=0), np.nan)
        hi = np.where(seen, np.nanmax(np.where(seen, grid, 0.0), axis=0), np.nan)
        mean = np.where(seen, np.nanmean(np.where(seen, grid, 0.0), axis=0), np.nan)
    return lo, mean, hi


def layer_thickness(layer: Any) -> tuple[np.ndarray, np.ndarray] | None:
    """(t (k,) mm, thickness (k,) mm) of a layer that carries a wall, else None.

    Read from the layer's laminate record (`laminate.t`, `laminate.thickness`: the mean thickness per
    station the build-up computed), present when the job gives a material.
    """
    lam = getattr(layer, "laminate", None)
    if lam is None:
        return None
    return np.asarray(lam.t, dtype=float), np.asarray(lam.thickness, dtype=float)


def _line(x: list, y: np.ndarray, name: str, color: str, xa: str, ya: str, group: str, **extra: Any) -> dict:
    trace = {"type": "scatter", "mode": "lines", "x": x, "y": rounded(y, 3), "name": name, "xaxis": xa,
             "yaxis": ya, "legendgroup": group, "line": {"color": color, "width": 2}}
    trace.update(extra)
    return trace


def profiles_figure(plan: WindingPlan, maps: tuple[LayerCoverageMap, ...], titles: list[str]) -> dict[str, Any]:
    """Stacked panels sharing t: winding angle, band layers, and thickness when any layer has one."""
    length = plan.surface.axial_length
    t = np.linspace(0.0, length, PROFILE_STATIONS)
    x = rounded(t)
    thick = [layer_thickness(layer) for layer in plan.layers]
    panels = ["angle", "plies"] + (["thickness"] if any(v is not None for v in thick) else [])
    doms = subplot_domains(len(panels), 0.1)
    layout = base_layout("Along the mandrel: winding angle, band layers, thickness", 90 + 290 * len(panels),
                         legend={"groupclick": "toggleitem", "tracegroupgap": 12})
    names = {"angle": "winding angle |α| (deg)", "plies": "band layers (mean around)",
             "thickness": "wall thickness (mm)"}
    for i, (panel, dom) in enumerate(zip(panels, doms)):
        xa, xr = axis_key("x", i)
        ya, yr = axis_key("y", i)
        layout[xa] = axis("t along the mandrel (mm)" if i == len(panels) - 1 else "", range=[0.0, length],
                          anchor=yr, matches="x" if i else None)
        layout[ya] = axis(names[panel], domain=list(dom), anchor=xr, rangemode="tozero")
        if layout[xa].get("matches") is None:
            layout[xa].pop("matches")
    layout["yaxis"]["range"] = [0.0, 90.0]
    layout["yaxis"]["dtick"] = 15
    data: list[dict[str, Any]] = []
    for layer, m, title, th in zip(plan.layers, maps, titles, thick):
        color = colors(layer.index)[0]
        group = f"layer{layer.index}"
        lo, mean, hi = angle_profile(layer, t)
        data.append(_line(x, lo, "least |α|", color, "x", "y", group, showlegend=False, hoverinfo="skip",
                          line={"color": color, "width": 0.5}))
        data.append(_line(x, hi, "range over passes", color, "x", "y", group, fill="tonexty", opacity=0.3,
                          line={"color": color, "width": 0.5}, legendgrouptitle={"text": title},
                          hovertemplate="t %{x} mm: largest |α| %{y} deg<extra></extra>"))
        data.append(_line(x, mean, "|α| mean over passes", color, "x", "y", group,
                          hovertemplate="t %{x} mm: |α| %{y} deg<extra>layer " + str(layer.index) + "</extra>"))
        data.append(_line(x, np.interp(t, m.t, m.count.mean(axis=1)), "band layers", color, "x2", "y2", group,
                          stackgroup="plies", showlegend=False, hovertemplate="t %{x} mm: %{y} band layers of this layer"
                          "<extra>layer " + str(layer.index) + "</extra>"))
        if th is not None:
            data.append(_line(x, np.interp(t, th[0], th[1], left=0.0, right=0.0), "thickness", color, "x3", "y3",
                              group, stackgroup="mm", showlegend=False, hovertemplate="t %{x} mm: %{y} mm of this layer"
                              "<extra>layer " + str(layer.index) + "</extra>"))
    return {"data": data, "layout": layout}
