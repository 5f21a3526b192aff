"""The unrolled pattern: every layer's band centre lines on the plane (t, position around the mandrel).

A pass is drawn where it lies: t along the mandrel against its arc-length position around the section
(bands.py; 0..360 deg of arc, wrapping like a cylinder cut open along theta = 0). Forward passes
(t increasing) lay the +alpha bands, return passes the -alpha ones; a helical layer of N_c circuits
draws 2 N_c bands. Dwells (the mandrel turning while the carriage waits) are drawn thin and gray at
the ends; hoop traverses take the layer's two colors by their direction along t too.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from winder.winding.results import FiberPass, LayerPlan, PassKind, WindingPlan
from winder.report.plotting import axis, axis_key, base_layout, pass_style, rounded, style_groups, subplot_domains
from winder.geometry.sections import ArcMap

LINE_WIDTH = 1.6
FIRST_CIRCUIT_COLOR = "#111111"


@dataclasses.dataclass(frozen=True, eq=False)
class UnrolledBand:
    """One pass on the unrolled plane.

    t : (m,) float, mm; u_deg : (m,) float in [0, 360], deg of arc. Both NaN where the line leaves the
    top or bottom edge and comes back on the other (a wrap), with the edge point on either side.
    """

    layer: int
    circuit: int
    kind: PassKind
    t: np.ndarray
    u_deg: np.ndarray


def wrapped(t: np.ndarray, turns: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A polyline of unwrapped position (turns) cut where it crosses a whole turn.

    Returns t and u in deg ((m',) float each), with [edge point, NaN, edge point on the other side]
    inserted at every crossing (the segments are short: at most one crossing each).
    """
    k = np.floor(turns)
    cut = np.nonzero(k[1:] != k[:-1])[0]
    u = (turns - k) * 360.0
    if cut.size == 0:
        return t.copy(), u
    edge = np.maximum(k[cut], k[cut + 1])  # the whole turn crossed between points cut and cut + 1
    f = (edge - turns[cut]) / (turns[cut + 1] - turns[cut])
    t_edge = t[cut] + f * (t[cut + 1] - t[cut])
    rising = k[cut + 1] > k[cut]
    before = np.where(rising, 360.0, 0.0)
    after = 360.0 - before
    ins_t = np.column_stack([t_edge, np.full_like(t_edge, np.nan), t_edge]).ravel()
    ins_u = np.column_stack([before, np.full_like(before, np.nan), after]).ravel()
    at = np.repeat(cut + 1, 3)
    return np.insert(t, at, ins_t), np.insert(u, at, ins_u)


def unrolled_band(arcs: ArcMap, p: FiberPass) -> UnrolledBand:
    t, u = wrapped(np.asarray(p.t, float), arcs.fraction(p.theta))
    return UnrolledBand(p.layer, p.circuit, p.kind, t, u)


def unrolled_bands(arcs: ArcMap, layer: LayerPlan) -> tuple[UnrolledBand, ...]:
    """The laid bands of a layer (forward, return, hoop passes; no dwells or turnarounds), in winding
    order."""
    return tuple(unrolled_band(arcs, p) for p in layer.passes
                 if p.kind is not PassKind.DWELL and p.kind is not PassKind.TURNAROUND)


def _joined(bands: list[UnrolledBand]) -> tuple[list, list, list]:
    """One trace's x, y, customdata (circuit) for many bands: NaN between bands."""
    nan = np.array([np.nan])
    xs = np.concatenate([np.concatenate([b.t, nan]) for b in bands])
    ys = np.concatenate([np.concatenate([b.u_deg, nan]) for b in bands])
    cs = np.concatenate([np.full(b.t.size + 1, b.circuit) for b in bands])
    return rounded(xs), rounded(ys), cs.tolist()


def _traces(arcs: ArcMap, layer: LayerPlan, x: str, y: str, title: str) -> list[dict[str, Any]]:
    out = []
    for (kind, rising), passes in style_groups(layer.passes).items():
        label, color = pass_style(layer.index, kind, rising)
        bands = [unrolled_band(arcs, p) for p in passes]
        xs, ys, cs = _joined(bands)
        out.append({"type": "scattergl" if len(xs) > 20000 else "scatter", "mode": "lines", "x": xs, "y": ys,
                    "customdata": cs, "xaxis": x, "yaxis": y, "name": label,
                    "legendgroup": f"layer{layer.index}", "legendgrouptitle": {"text": title},
                    "line": {"color": color, "width": 1.0 if kind in ("dwell", "turnaround") else LINE_WIDTH},
                    "connectgaps": False, "meta": {"layer": layer.index, "kind": kind, "bands": len(bands)},
                    "hovertemplate": f"{label}<br>circuit %{{customdata}}<br>t %{{x}} mm, %{{y}} deg"
                                     f"<extra>layer {layer.index}</extra>"})
    first = [unrolled_band(arcs, p) for p in layer.passes if p.circuit == 1 and p.kind is not PassKind.HOOP]
    if layer.type.value == "helical" and first:
        xs, ys, cs = _joined(first)
        out.append({"type": "scatter", "mode": "lines", "x": xs, "y": ys, "xaxis": x, "yaxis": y,
                    "name": "circuit 1, to follow the pattern", "legendgroup": f"layer{layer.index}",
                    "line": {"color": FIRST_CIRCUIT_COLOR, "width": 2.6}, "hoverinfo": "skip",
                    "meta": {"layer": layer.index, "kind": "first circuit", "bands": 0}})
    return out


def unrolled_figure(plan: WindingPlan, arcs: ArcMap, titles: list[str]) -> dict[str, Any]:
    """One subplot per layer, stacked, sharing the t range."""
    n = len(plan.layers)
    layout = base_layout("Unrolled pattern: band centre lines on the mandrel cut open along θ = 0",
                         110 + 320 * n, legend={"groupclick": "toggleitem", "tracegroupgap": 16})
    data, annotations = [], []
    length = plan.surface.axial_length
    for i, (layer, title, dom) in enumerate(zip(plan.layers, titles, subplot_domains(n, 0.3 / max(n, 2)))):
        xa, x = axis_key("x", i)
        ya, y = axis_key("y", i)
        layout[xa] = axis("t along the mandrel (mm)", range=[0.0, length], anchor=y)
        layout[ya] = axis("around the mandrel (deg of arc)", range=[0.0, 360.0], dtick=90, domain=list(dom),
                          anchor=x)
        data += _traces(arcs, layer, x, y, title)
        annotations.append({"text": f"<b>{title}</b>", "xref": "paper", "yref": "paper", "x": 0.0,
                            "y": dom[1] + 0.01, "xanchor": "left", "yanchor": "bottom", "showarrow": False})
    layout["annotations"] = annotations
    return {"data": data, "layout": layout}
