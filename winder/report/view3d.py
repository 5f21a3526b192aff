"""The 3D view: the mandrel and every band, to rotate and zoom in the browser.

The mandrel is a surface on a MANDREL_STATIONS x MANDREL_ANGLES grid (closed around). Each pass is
drawn as its centre line lifted off the mandrel by LIFT of the largest radius per layer (so a layer is
not hidden in the mandrel or under the layer below), resampled at most STEP_DEG of turn apart, and
thinned so that all bands together keep at most MAX_BAND_POINTS points: the page stays small whatever
the job (a dense job draws its passes with longer chords).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from winder.winding.results import FiberPass, LayerPlan, WindingPlan
from winder.report.plotting import MANDREL_COLOR, base_layout, pass_style, rounded, style_groups

MANDREL_STATIONS = 90
MANDREL_ANGLES = 73  # 5 deg steps, first = last (closed)
MAX_BAND_POINTS = 60000
STEP_DEG = 6.0  # turn per drawn chord: the chord sinks r (1 - cos 3 deg) = 0.14 % of r, under the lift
LIFT = 0.02  # of the largest mandrel radius, per layer
# From above (x is up), the side (+y) and the start (t = 0), far enough for the longest extent (1).
EYE = {"x": 0.52, "y": 1.4, "z": 0.52}


def _mandrel(plan: WindingPlan) -> dict[str, Any]:
    surface = plan.surface
    s = np.linspace(0.0, surface.length, MANDREL_STATIONS)
    th = np.linspace(0.0, 2.0 * np.pi, MANDREL_ANGLES)
    ss, tt = np.meshgrid(s, th, indexing="ij")
    pts = surface.points(ss.ravel(), tt.ravel()).reshape(MANDREL_STATIONS, MANDREL_ANGLES, 3)
    return {"type": "surface", "x": rounded(pts[..., 0]), "y": rounded(pts[..., 1]), "z": rounded(pts[..., 2]),
            "surfacecolor": np.zeros((MANDREL_STATIONS, MANDREL_ANGLES)).tolist(),
            "colorscale": [[0.0, MANDREL_COLOR], [1.0, MANDREL_COLOR]], "showscale": False, "name": "mandrel",
            "showlegend": True, "hoverinfo": "skip", "opacity": 1.0,
            "lighting": {"ambient": 0.55, "diffuse": 0.7, "specular": 0.15, "roughness": 0.6},
            "contours": {"x": {"highlight": False}, "y": {"highlight": False}, "z": {"highlight": False}}}


def _aspect(mandrel: dict[str, Any]) -> dict[str, float]:
    """True proportions with the longest extent 1, so that every part, long or compact, fills the
    view the same way from the same eye."""
    ext = np.array([np.ptp(np.asarray(mandrel[k], dtype=float)) for k in ("x", "y", "z")])
    ext = np.maximum(ext, 1e-6 * ext.max())
    return dict(zip("xyz", (float(v) for v in ext / ext.max())))


def _largest_radius(plan: WindingPlan) -> float:
    surface = plan.surface
    s = np.linspace(0.0, surface.length, 64)
    th = np.linspace(0.0, 2.0 * np.pi, 36, endpoint=False)
    ss, tt = np.meshgrid(s, th, indexing="ij")
    return float(np.max(surface.radius(ss.ravel(), tt.ravel())))


def _samples(passes: list[FiberPass], budget: int) -> list[np.ndarray]:
    """Per pass, the fractional vertex indices to draw: dense enough that a chord never sinks into the
    mandrel (at most STEP_DEG of turn per chord), then thinned evenly so all passes keep within budget."""
    wanted = []
    for p in passes:
        turn = float(np.degrees(np.sum(np.abs(np.diff(p.theta)))))
        wanted.append(max(2, p.t.size if turn <= STEP_DEG * p.t.size else int(math.ceil(turn / STEP_DEG)) + 1))
    scale = min(1.0, budget / max(sum(wanted), 1))
    return [np.linspace(0.0, p.t.size - 1.0, max(2, int(n * scale))) for p, n in zip(passes, wanted)]


def _lifted(plan: WindingPlan, passes: list[FiberPass], budget: int, lift: float) -> np.ndarray:
    """(m, 3) points of the passes' centre lines on the mandrel, lifted along the normal, NaN rows
    between passes. Between vertices the line runs straight in (s, theta), so it stays on the surface."""
    s_all, th_all, breaks = [], [], []
    for p, u in zip(passes, _samples(passes, budget)):
        idx = np.arange(p.t.size, dtype=float)
        s_all.append(np.interp(u, idx, p.s))
        th_all.append(np.interp(u, idx, p.theta))
        breaks.append(u.size)
    s, th = np.concatenate(s_all), np.concatenate(th_all)
    pts = plan.surface.points(s, th) + lift * plan.surface.normals(s, th)
    at = np.cumsum(breaks)[:-1]
    return np.insert(pts, at, np.nan, axis=0)


def _band_traces(plan: WindingPlan, layer: LayerPlan, budget: int, lift: float, title: str) -> list[dict]:
    out = []
    for (kind, rising), passes in style_groups(layer.passes).items():
        label, color = pass_style(layer.index, kind, rising)
        pts = _lifted(plan, passes, budget, lift)
        out.append({"type": "scatter3d", "mode": "lines", "x": rounded(pts[:, 0]), "y": rounded(pts[:, 1]),
                    "z": rounded(pts[:, 2]), "name": label, "line": {"color": color, "width": 2 if kind == "dwell"
                                                                       else 3},
                    "legendgroup": f"layer{layer.index}", "legendgrouptitle": {"text": title},
                    "hoverinfo": "name", "connectgaps": False})
    return out


def view3d_figure(plan: WindingPlan, titles: list[str]) -> dict[str, Any]:
    """The mandrel surface and the band centre lines of every layer, in the mandrel frame (mm)."""
    radius = _largest_radius(plan)
    mandrel = _mandrel(plan)
    data = [mandrel]
    total = sum(len(layer.passes) for layer in plan.layers) or 1
    for layer, title in zip(plan.layers, titles):
        budget = MAX_BAND_POINTS * len(layer.passes) // total
        data += _band_traces(plan, layer, budget, LIFT * radius * layer.index, title)
    scene_axis = {"showbackground": True, "backgroundcolor": "#f4f6f8", "gridcolor": "#d8dde3"}
    layout = base_layout("3D view: mandrel and bands (drag to rotate, scroll to zoom)", 760,
                         margin={"l": 0, "r": 0, "t": 60, "b": 0},
                         legend={"groupclick": "toggleitem", "tracegroupgap": 12},
                         scene={"aspectmode": "manual", "aspectratio": _aspect(mandrel),
                                "xaxis": dict(scene_axis, title={"text": "x (mm)"}),
                                "yaxis": dict(scene_axis, title={"text": "y (mm)"}),
                                "zaxis": dict(scene_axis, title={"text": "z (mm), along the axis at t = 0"}),
                                "camera": {"up": {"x": 1, "y": 0, "z": 0}, "eye": EYE}})
    return {"data": data, "layout": layout}
