"""The report's structure section (docs/math/09-structure.md): along the mandrel, each layer's thickness,
its first-ply failure index at the design pressure (Tsai-Wu and maximum stress), and the pressure at which
it fails first against the netting burst; with a table of the summary's `analysis` block."""

from __future__ import annotations

import html
from typing import Any

import numpy as np

from winder.report.plotting import axis, axis_key, base_layout, colors, rounded, subplot_domains

HOW = ("Per layer along the mandrel (the stations of the layup): its thickness (stacked), the Tsai-Wu failure "
       "index of its most loaded ply at the design pressure (1: first-ply failure; dotted: maximum stress), and "
       "the pressure at which its first ply fails (Tsai-Wu) beside the netting burst pressure of the whole wall "
       "(grey, where netting applies: outside the bosses).")


def _line(x: list, y: np.ndarray, name: str, xa: str, ya: str, group: str, **extra: Any) -> dict:
    trace = {"type": "scatter", "mode": "lines", "x": x, "y": rounded(y, 4), "name": name, "xaxis": xa, "yaxis": ya,
             "legendgroup": group}
    trace.update(extra)
    return trace


def structure_figure(structure, length: float) -> dict[str, Any]:
    """Three stacked panels sharing t: thickness, failure index, failure and burst pressure (MPa)."""
    st = structure.stations
    x = rounded(st.geometry.t)
    doms = subplot_domains(3, 0.08)
    layout = base_layout(f"Structure at {structure.pressure:g} MPa: thickness, failure index, failure pressure",
                         960, legend={"groupclick": "toggleitem"})
    names = ("thickness (mm)", "failure index at the pressure", "pressure (MPa)")
    for i, dom in enumerate(doms):
        xa, xr = axis_key("x", i)
        ya, yr = axis_key("y", i)
        layout[xa] = axis("t along the mandrel (mm)" if i == 2 else "", range=[0.0, length], anchor=yr,
                          **({"matches": "x"} if i else {}))
        layout[ya] = axis(names[i], domain=list(dom), anchor=xr, rangemode="tozero")
    data: list[dict[str, Any]] = []
    for k, layer in enumerate(st.layers):
        color = colors(int(layer))[0]
        group = f"layer{int(layer)}"
        laid = st.thickness[:, k] > 0.0
        data.append(_line(x, st.thickness[:, k], f"layer {int(layer)}", "x", "y", group, stackgroup="mm",
                          line={"color": color, "width": 1}))
        data.append(_line(x, np.where(laid, st.tsai_wu_index[:, k], np.nan), "Tsai-Wu", "x2", "y2", group,
                          showlegend=False, line={"color": color, "width": 2}))
        data.append(_line(x, np.where(laid, st.max_stress_index[:, k], np.nan), "max stress", "x2", "y2", group,
                          showlegend=False, line={"color": color, "width": 1, "dash": "dot"}))
        data.append(_line(x, np.where(laid & np.isfinite(st.tsai_wu[:, k]), st.tsai_wu[:, k], np.nan),
                          "first-ply failure", "x3", "y3", group, showlegend=False, line={"color": color, "width": 2}))
    burst = np.where(st.netting_applies & np.isfinite(st.netting.burst), st.netting.burst, np.nan)
    data.append(_line(x, burst, "netting burst", "x3", "y3", "netting", line={"color": "#777", "width": 2}))
    data.append(_line(x, np.ones(st.geometry.t.size), "index 1", "x2", "y2", "netting", showlegend=False,
                      line={"color": "#c62828", "width": 1, "dash": "dash"}, hoverinfo="skip"))
    return {"data": data, "layout": layout}


def structure_table(block: dict[str, Any]) -> str:
    """The summary's `analysis` block as a small table."""
    def cell(value: Any, unit: str = "") -> str:
        return "–" if value is None else html.escape(f"{value}{unit}")

    rows = [("pressure", cell(block.get("pressure_mpa"), " MPa")),
            ("burst pressure, netting", cell(block.get("burst_pressure_netting_mpa"), " MPa")
             + f" ({cell(block.get('burst_netting_limit'))} limit at t = {cell(block.get('burst_netting_t'), ' mm')})"),
            ("first-ply failure, Tsai-Wu", cell(block.get("first_ply_failure_pressure_mpa"), " MPa")
             + f" (layer {cell(block.get('layer'))}, t = {cell(block.get('t'), ' mm')})"),
            ("first-ply failure, max stress", cell(block.get("first_ply_failure_max_stress_mpa"), " MPa")
             + f" (layer {cell(block.get('max_stress_layer'))}, t = {cell(block.get('max_stress_t'), ' mm')})"),
            ("netting optimum angle", cell(block.get("netting_optimum_angle_deg"), "°"))]
    body = "".join(f"<tr><th>{html.escape(k)}</th><td>{v}</td></tr>" for k, v in rows)
    keys = ("first_ply_failure_pressure_mpa", "first_ply_failure_max_stress_mpa", "tsai_wu_index")
    per = "".join(f"<tr><td>layer {cell(x.get('layer'))}</td>" + "".join(f"<td>{cell(x.get(k))}</td>" for k in keys)
                  + "</tr>" for x in block.get("layers") or [])
    return (f"<table class=job>{body}</table><table class=job style='margin-top:10px'><tr><th></th>"
            "<th>first-ply failure (Tsai-Wu, MPa)</th><th>(max stress, MPa)</th><th>largest Tsai-Wu index</th></tr>"
            f"{per}</table>")
