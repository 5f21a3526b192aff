"""The coverage map: band layers over the unrolled surface of each layer, and its gaps.

Each layer's bands are counted on a grid over (t, u) (bands.py), MAP_ROWS stations along the mandrel by
MAP_COLUMNS cells around it. A cell is a gap where one of the layer's coverage groups (the forward
passes, the return passes, each hoop traverse) is laid at that station but leaves the cell bare: a +-alpha
layer is even only where each direction covers once.

The map's number is the bare fraction: at each of the planner's coverage stations (Coverage.stations),
the perimeter the worst group leaves bare, as an exact union of the bands (not a count of cells), the
largest over the stations. That is 1 - covered_fraction by winder.coverage's definition, so the picture
and the summary tell the same story.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from winder.winding.results import LayerPlan, WindingPlan
from winder.report.bands import band_counts, coverage_groups, covered_fraction, crossings
from winder.report.plotting import GAP_COLOR, axis, axis_key, base_layout, ramp, rounded, subplot_domains
from winder.geometry.sections import ArcMap

MAP_ROWS = 300  # stations along the mandrel
MAP_COLUMNS = 240  # cells around it: 1.5 deg of arc each
COUNT_CAP = 8  # counts above share the darkest color (the pile-up at vessel turnarounds reaches 20 and more)
COUNT_RAMP = ("#ffffff", "#dbe9f6", "#9ecae1", "#4292c6", "#2171b5", "#08519c", "#08306b")


@dataclasses.dataclass(frozen=True, eq=False)
class LayerCoverageMap:
    """One layer's coverage on the unrolled surface.

    t : (n,) float, the map's stations (mm); u_deg : (m,) float, cell centres around (deg of arc).
    count : (n, m) int, band layers over each cell (all passes of the layer).
    gap : (n, m) bool, cells a coverage group leaves bare where it is laid.
    stations : (k,) float, the planner's coverage stations (mm).
    bare_at_stations : (k,) float, the perimeter fraction the worst group leaves bare at each of them.
    """

    layer: int
    t: np.ndarray
    u_deg: np.ndarray
    count: np.ndarray
    gap: np.ndarray
    stations: np.ndarray
    bare_at_stations: np.ndarray

    @property
    def bare_fraction(self) -> float:
        """The largest bare fraction over the coverage stations (= 1 - covered_fraction)."""
        return float(self.bare_at_stations.max()) if self.bare_at_stations.size else 0.0

    @property
    def worst_station(self) -> float | None:
        """t (mm) of the station where the bare fraction is largest, None without stations."""
        return float(self.stations[np.argmax(self.bare_at_stations)]) if self.stations.size else None


def layer_coverage_map(plan: WindingPlan, layer: LayerPlan, arcs: ArcMap, band_width: float,
                       rows: int = MAP_ROWS, columns: int = MAP_COLUMNS) -> LayerCoverageMap:
    surface = plan.surface
    t = np.linspace(0.0, surface.axial_length, rows)
    stations = np.asarray(layer.coverage.stations, dtype=float)
    every = np.concatenate([t, stations])  # the map's rows, then the coverage stations
    count = np.zeros((rows, columns), dtype=np.int32)
    gap = np.zeros((rows, columns), dtype=bool)
    bare = np.zeros(stations.size)
    for group in coverage_groups(layer.passes):
        hits = crossings(surface, arcs, group, every, band_width)
        on_map = hits.row < rows
        grid_hits = type(hits)(hits.row[on_map], hits.centre[on_map], hits.half[on_map])
        counts = band_counts(grid_hits, rows, columns)
        count += counts
        gap |= (counts == 0) & grid_hits.rows_hit(rows)[:, None]
        at = type(hits)(hits.row[~on_map] - rows, hits.centre[~on_map], hits.half[~on_map])
        bare = np.maximum(bare, 1.0 - covered_fraction(at, stations.size))
    u_deg = (np.arange(columns) + 0.5) * 360.0 / columns
    return LayerCoverageMap(layer.index, t, u_deg, count, gap, stations, bare)


def coverage_maps(plan: WindingPlan, arcs: ArcMap, band_width: float) -> tuple[LayerCoverageMap, ...]:
    """The coverage map of every layer, in winding order."""
    return tuple(layer_coverage_map(plan, layer, arcs, band_width) for layer in plan.layers)


def _count_scale(top: int) -> list[list[Any]]:
    """A stepped colorscale: one flat color per integer band count 0..top (white for 0)."""
    top = max(top, 1)
    shades = ["#ffffff"] + ramp(COUNT_RAMP[1:], top)
    scale = []
    for k, color in enumerate(shades):
        scale += [[k / (top + 1), color], [(k + 1) / (top + 1), color]]
    return scale


def coverage_figure(maps: tuple[LayerCoverageMap, ...], titles: list[str], length: float) -> dict[str, Any]:
    """One heatmap per layer, stacked: band layers in blues, gaps in red, coverage stations dotted."""
    n = len(maps)
    top = min(int(max((int(m.count.max()) for m in maps), default=1)), COUNT_CAP)
    ticks = list(range(top + 1))
    labels = [str(k) for k in ticks[:-1]] + [f"≥{top}" if top == COUNT_CAP else str(top)]
    layout = base_layout("Coverage map: band layers over the unrolled surface (red: gaps)", 110 + 300 * n,
                         coloraxis={"colorscale": _count_scale(top), "cmin": -0.5, "cmax": top + 0.5,
                                    "colorbar": {"title": {"text": "band<br>layers"}, "tickvals": ticks, "ticktext": labels,
                                                 "len": 0.6, "y": 1.0, "yanchor": "top"}},
                         showlegend=True, legend={"x": 1.0, "xanchor": "left", "y": 0.3, "yanchor": "top"})
    data: list[dict[str, Any]] = []
    annotations, shapes = [], []
    for i, (m, title, dom) in enumerate(zip(maps, titles, subplot_domains(n, 0.35 / max(n, 2)))):
        xa, x = axis_key("x", i)
        ya, y = axis_key("y", i)
        layout[xa] = axis("t along the mandrel (mm)", range=[0.0, length], anchor=y)
        layout[ya] = axis("around the mandrel (deg of arc)", range=[0.0, 360.0], dtick=90, domain=list(dom),
                          anchor=x)
        xs, ys = rounded(m.t), rounded(m.u_deg)
        data.append({"type": "heatmap", "x": xs, "y": ys, "z": m.count.T.tolist(), "coloraxis": "coloraxis",
                     "xaxis": x, "yaxis": y, "name": f"layer {m.layer}",
                     "hovertemplate": "t %{x} mm, %{y} deg<br>%{z} band layers<extra>layer " + str(m.layer)
                     + "</extra>"})
        data.append({"type": "heatmap", "x": xs, "y": ys, "z": m.gap.T.astype(np.int8).tolist(), "zmin": 0,
                     "zmax": 1, "colorscale": [[0.0, "rgba(0,0,0,0)"], [1.0, GAP_COLOR]], "showscale": False,
                     "hoverinfo": "skip", "xaxis": x, "yaxis": y, "name": "gap (a direction leaves it bare)",
                     "showlegend": i == 0, "legendgroup": "gap"})
        for st in m.stations:
            shapes.append({"type": "line", "xref": x, "yref": f"{y} domain", "x0": float(st), "x1": float(st),
                           "y0": 1.0, "y1": 1.04, "line": {"color": "#333", "width": 1}})
        worst = m.worst_station
        where = f" at t = {worst:.1f} mm" if worst is not None and m.bare_fraction >= 5e-5 else ""
        annotations.append({"text": f"<b>{title}</b> — bare {m.bare_fraction:.4f} of the perimeter at the worst "
                                    f"coverage station{where} (ticks: the stations)",
                            "xref": "paper", "yref": "paper", "x": 0.0, "y": dom[1] + 0.02, "xanchor": "left",
                            "yanchor": "bottom", "showarrow": False, "font": {"size": 13}})
    # The gap legend entry needs a visible swatch: a marker outside the plotted range.
    data.append({"type": "scatter", "x": [None], "y": [None], "mode": "markers", "name": "gap (a direction "
                 "leaves it bare)", "marker": {"color": GAP_COLOR, "symbol": "square", "size": 12},
                 "legendgroup": "gap", "showlegend": True, "xaxis": "x", "yaxis": "y"})
    data[1]["showlegend"] = False
    layout["annotations"] = annotations
    layout["shapes"] = shapes
    return {"data": data, "layout": layout}
