"""The report's vessel section (docs/math/17-vessels-as-built.md): on each dome, the meridian bare and as
wound after each layer (the surface the next layer and the payout eye meet), each layer's wall along the
bare meridian (its reported thickness at the foot of each bare point, docs/math/08 8.11), and a table of
where each helical layer turned around on each dome."""

from __future__ import annotations

import html
from typing import Any

import numpy as np

from winder.geometry.vessel import VesselMeridian
from winder.report.plotting import axis, base_layout, colors, rounded
from winder.winding.results import WindingPlan

HOW = ("Each dome's meridian (axial station t against the radius), bare (black) and as wound after each layer: the "
       "surface the next layer winds on and the payout eye clears, the pile-ups next to the bosses as laid. Below, "
       "each layer's wall along the bare dome (its thickness read at the foot of each bare point), stacked. The "
       "table gives where each helical layer turned around on each dome (its own opening plus half a band by "
       "default, geodesic or held by friction).")
MERIDIAN_POINTS = 200  # per dome and curve
DOMAINS = ((0.0, 0.47), (0.53, 1.0))  # first dome left, end dome right
ROWS = ((0.56, 1.0), (0.0, 0.44))  # contours above, walls below


def is_wound_vessel(plan: WindingPlan) -> bool:
    """A vessel of revolution whose every layer carries a laminate: the section has something to show."""
    return (isinstance(plan.surface.profile, VesselMeridian) and plan.surface.is_revolution and bool(plan.layers)
            and all(layer.laminate is not None for layer in plan.layers))


def _dome_range(prof: VesselMeridian, end: bool) -> tuple[float, float]:
    return prof.dome_ranges.end_dome if end else prof.dome_ranges.dome


def _panel(i: int, row: int) -> tuple[str, str, str, str]:
    """(x axis key, y axis key, x anchor, y anchor) of the panel in column i, row row."""
    n = 1 + i + 2 * row
    xa, ya = ("xaxis", "yaxis") if n == 1 else (f"xaxis{n}", f"yaxis{n}")
    return xa, ya, "x" if n == 1 else f"x{n}", "y" if n == 1 else f"y{n}"


def vessel_figure(plan: WindingPlan) -> dict[str, Any]:
    """Contours bare and grown per layer, and each layer's wall, on both domes (module docstring)."""
    from winder.winding.dome_wall import layer_walls  # noqa: PLC0415 - vessels with a laminate only

    bare = plan.surface.profile
    layout = base_layout("The domes: bare and as wound after each layer; each layer's wall", 900,
                         legend={"groupclick": "toggleitem"})
    data: list[dict[str, Any]] = []
    surfaces = [plan.surface_of(layer.index + 1) if layer.index < len(plan.layers) else plan.outer_surface
                for layer in plan.layers]
    for i, end in enumerate((False, True)):
        xa, ya, xr, yr = _panel(i, 0)
        xw, yw, xwr, ywr = _panel(i, 1)
        name = "end dome" if end else "first dome"
        layout[xa] = axis(f"t (mm), {name}", domain=list(DOMAINS[i]), anchor=yr)
        layout[ya] = axis("r (mm)", domain=list(ROWS[0]), anchor=xr, scaleanchor=xr)
        layout[xw] = axis(f"bare radius on the {name} (mm)", domain=list(DOMAINS[i]), anchor=ywr)
        layout[yw] = axis("wall (mm)", domain=list(ROWS[1]), anchor=xwr, rangemode="tozero")
        s = np.linspace(*_dome_range(bare, end), MERIDIAN_POINTS)
        ev = bare.evaluate(s)
        data.append({"type": "scatter", "mode": "lines", "x": rounded(ev.z), "y": rounded(ev.r), "name": "bare liner",
                     "xaxis": xr, "yaxis": yr, "legendgroup": "bare", "showlegend": i == 0,
                     "line": {"color": "#000", "width": 2}})
        walls = layer_walls(plan, np.column_stack([ev.z, ev.r]))
        for k, (layer, surf) in enumerate(zip(plan.layers, surfaces)):
            color, group = colors(layer.index)[0], f"layer{layer.index}"
            prof = surf.profile
            g = prof.evaluate(np.linspace(*_dome_range(prof, end), MERIDIAN_POINTS))
            data.append({"type": "scatter", "mode": "lines", "x": rounded(g.z), "y": rounded(g.r),
                         "name": f"after layer {layer.index}", "xaxis": xr, "yaxis": yr, "legendgroup": group,
                         "showlegend": i == 0, "line": {"color": color, "width": 1}})
            data.append({"type": "scatter", "mode": "lines", "x": rounded(ev.r), "y": rounded(walls[k], 4),
                         "name": f"layer {layer.index}", "xaxis": xwr, "yaxis": ywr, "legendgroup": group,
                         "showlegend": False, "stackgroup": f"wall{i}", "line": {"color": color, "width": 1}})
    return {"data": data, "layout": layout}


def turnaround_table(summary: dict[str, Any]) -> str:
    """Where each helical layer turned on each dome (the summary's turnaround_radii_mm), and how."""
    rows = []
    for layer in summary.get("layers") or []:
        radii = layer.get("turnaround_radii_mm")
        if layer.get("type") != "helical" or not radii:
            continue
        notes = " ".join(layer.get("notes") or [])
        how = ["friction-held" if f"mm on the {d} dome (friction-held)" in notes else "geodesic"
               for d in ("first", "end")]
        cells = "".join(f"<td>{r:.2f}</td><td class=dim>{h}</td>" for r, h in zip(radii, how))
        rows.append(f"<tr><td>layer {layer['index']}</td><td>{layer['angle_deg']:.2f}°</td>{cells}</tr>")
    if not rows:
        return ""
    head = ("<table class=job><tr><th></th><th>angle</th><th>first dome r (mm)</th><th></th>"
            "<th>end dome r (mm)</th><th></th></tr>")
    walls = summary.get("domes") or []
    foot = "".join(f"<p class=how>{html.escape(d)} dome: largest wall {w['max_wall_mm']:.2f} mm at r = "
                   f"{w['max_wall_radius_mm']:.1f} mm (opening {w['opening_radius_mm']:.1f} mm)</p>"
                   for d, w in zip(("first", "end"), walls))
    return head + "".join(rows) + "</table>" + foot
