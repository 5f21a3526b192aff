"""The report's structure section (docs/math/09-structure.md): along the mandrel, each layer's thickness,
its first-ply failure index at the design pressure (Tsai-Wu and maximum stress), its fiber stress, and the
pressure at which it fails first against the netting burst; the gauge section shaded; with `winder
analyze`, CalculiX's fiber stress and failure index along the meridian beside them. Tables of the
summary's `analysis` block: the gauge's figures, the end zones apart, the ratios against the targets."""

from __future__ import annotations

import html
from typing import Any

import numpy as np

from winder.report.plotting import axis, axis_key, base_layout, colors, rounded, subplot_domains

HOW = ("Per layer along the mandrel (the stations of the layup): its thickness (stacked), the Tsai-Wu failure "
       "index of its most loaded ply at the design pressure (1: first-ply failure; dotted: maximum stress), its "
       "fiber stress, and the pressure at which its first ply fails (Tsai-Wu) beside the netting burst pressure "
       "of the whole wall (grey, where netting applies: outside the bosses). The shaded band is the gauge section "
       "the headline figures come from; outside it, the end zones. With winder analyze, CalculiX's shell model "
       "(markers) beside the laminate analysis (lines).")


def _line(x: list, y: np.ndarray, name: str, xa: str, ya: str, group: str, **extra: Any) -> dict:
    trace = {"type": "scatter", "mode": "lines", "x": x, "y": rounded(y, 4), "name": name, "xaxis": xa, "yaxis": ya,
             "legendgroup": group}
    trace.update(extra)
    return trace


def _fiber_stress(st, k: int) -> np.ndarray:
    """A layer's fiber stress (the larger of its plies' sigma_1) at the design pressure, per station."""
    mine = st.ply_layer == k
    return np.where(st.thickness[:, k] > 0.0, st.ply_stress[:, mine, 0].max(axis=1), np.nan)


def _fe_traces(fe) -> list[dict]:
    """CalculiX's fiber stress and Tsai-Wu index per layer, as markers."""
    data = []
    t = rounded(fe.t)
    for lay in fe.layers:
        color = colors(lay.layer)[0]
        marker = {"color": color, "size": 5, "symbol": "circle-open"}
        for y, ya, what in ((lay.fe_index, "y2", "Tsai-Wu (FE)"), (lay.fe_stress, "y3", "fiber stress (FE)")):
            data.append({"type": "scatter", "mode": "markers", "x": t, "y": rounded(y, 4), "name": what,
                         "xaxis": "x" + ya[1:], "yaxis": ya, "legendgroup": f"layer{lay.layer}",
                         "showlegend": False, "marker": marker})
    return data


def structure_figure(structure, length: float, fe=None) -> dict[str, Any]:
    """Four stacked panels sharing t: thickness, failure index, fiber stress (MPa), failure and burst pressure
    (MPa), top to bottom; fe: `winder analyze`'s comparison, its markers on the index and stress panels."""
    st = structure.stations
    x = rounded(st.geometry.t)
    doms = subplot_domains(4, 0.06)
    layout = base_layout(f"Structure at {structure.pressure:g} MPa: thickness, failure index, fiber stress, failure "
                         "pressure", 1200, legend={"groupclick": "toggleitem"})
    names = ("thickness (mm)", "failure index at the pressure", "fiber stress (MPa)", "pressure (MPa)")
    for i, dom in enumerate(doms):
        xa, xr = axis_key("x", i)
        ya, yr = axis_key("y", i)
        layout[xa] = axis("t along the mandrel (mm)" if i == 3 else "", range=[0.0, length], anchor=yr,
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
        data.append(_line(x, _fiber_stress(st, k), "fiber stress (CLT)", "x3", "y3", group, showlegend=False,
                          line={"color": color, "width": 2}))
        data.append(_line(x, np.where(laid & np.isfinite(st.tsai_wu[:, k]), st.tsai_wu[:, k], np.nan),
                          "first-ply failure", "x4", "y4", group, showlegend=False, line={"color": color, "width": 2}))
    burst = np.where(st.netting_applies & np.isfinite(st.netting.burst), st.netting.burst, np.nan)
    data.append(_line(x, burst, "netting burst", "x4", "y4", "netting", line={"color": "#777", "width": 2}))
    data.append(_line(x, np.ones(st.geometry.t.size), "index 1", "x2", "y2", "netting", showlegend=False,
                      line={"color": "#c62828", "width": 1, "dash": "dash"}, hoverinfo="skip"))
    if fe is not None:
        data += _fe_traces(fe)
    lo, hi = structure.gauge_span
    if np.isfinite(lo) and np.isfinite(hi):
        layout["shapes"] = [{"type": "rect", "xref": "x", "yref": "paper", "x0": lo, "x1": hi, "y0": 0, "y1": 1,
                             "fillcolor": "#1f3b57", "opacity": 0.06, "line": {"width": 0}, "layer": "below"}]
    return {"data": data, "layout": layout}


def _cell(value: Any, unit: str = "") -> str:
    return "–" if value is None else html.escape(f"{value}{unit}")


def _figures(block: dict[str, Any]) -> list[tuple[str, str]]:
    return [("burst pressure, netting", _cell(block.get("burst_pressure_netting_mpa"), " MPa")
             + f" (layer {_cell(block.get('burst_netting_layer'))} {_cell(block.get('burst_netting_limit'))}, "
             f"{_cell(block.get('burst_netting_wall'))} wall, at t = {_cell(block.get('burst_netting_t'), ' mm')})"),
            ("first-ply failure, Tsai-Wu", _cell(block.get("first_ply_failure_pressure_mpa"), " MPa")
             + f" (layer {_cell(block.get('layer'))}, t = {_cell(block.get('t'), ' mm')})"),
            ("first-ply failure, max stress", _cell(block.get("first_ply_failure_max_stress_mpa"), " MPa")
             + f" (layer {_cell(block.get('max_stress_layer'))}, t = {_cell(block.get('max_stress_t'), ' mm')})")]


def _verdict(ok: bool | None) -> str:
    return "" if ok is None else (" <b>pass</b>" if ok else " <span class=bad>fail</span>")


def structure_table(block: dict[str, Any]) -> str:
    """The summary's `analysis` block as small tables: the gauge's figures, the end zones', the targets."""
    span = block.get("gauge_t_mm")
    where = f" (t {span[0]} to {span[1]} mm)" if span else ""
    rows = [("pressure", _cell(block.get("pressure_mpa"), " MPa")
             + f", axial force {_cell(block.get('axial_force_n'), ' N')}, torque {_cell(block.get('torque_nmm'), ' N mm')}"),
            ("gauge section", _cell(block.get("gauge")) + html.escape(where))]
    rows += _figures(block)
    rows += [("burst ratio (netting burst / pressure)", _cell(block.get("burst_ratio"))
              + (f" against {_cell(block.get('burst_ratio_required'))} ({_cell(block.get('burst_pressure_required_mpa'), ' MPa')})"
                 + _verdict(block.get("burst_pass")) if "burst_pass" in block else "")),
             ("first-ply failure ratio (first-ply failure / pressure)", _cell(block.get("first_ply_failure_ratio"))),
             ("netting optimum angle", _cell(block.get("netting_optimum_angle_deg"), "°"))]
    for ratio in block.get("stress_ratio") or []:
        rows.append((f"stress ratio, {ratio['material']} (layers {', '.join(map(str, ratio['layers']))})",
                     _cell(ratio.get("achieved")) + (f" against {_cell(ratio['required'])}" if ratio.get("required")
                                                     else " (no stress_ratio asked)") + _verdict(ratio.get("pass"))))
    body = "".join(f"<tr><th>{html.escape(k)}</th><td>{v}</td></tr>" for k, v in rows)
    ends = block.get("end_zones")
    end_rows = "".join(f"<tr><th>{html.escape(k)}</th><td>{v}</td></tr>" for k, v in _figures(ends)) if ends else ""
    keys = ("first_ply_failure_pressure_mpa", "first_ply_failure_max_stress_mpa", "tsai_wu_index")
    per = "".join(f"<tr><td>layer {_cell(x.get('layer'))}</td>" + "".join(f"<td>{_cell(x.get(k))}</td>" for k in keys)
                  + "</tr>" for x in block.get("layers") or [])
    allow = "".join(f"<tr><td>layer {a['layer']}</td><td>{_cell(a['material'])}</td><td>{_cell(a['fiber_allowable_mpa'])}"
                    f"</td><td>{_cell(a['source'])}</td><td>{_cell(a['ply_xt_over_vf_mpa'])}</td></tr>"
                    for a in block.get("netting_allowables") or [])
    notes = "".join(f"<li>{html.escape(n)}</li>" for n in block.get("notes") or [])
    return (f"<table class=job>{body}</table>"
            + (f"<h3>End zones, apart: {html.escape(ends['label'])}</h3><table class=job>{end_rows}</table>" if ends else "")
            + "<table class=job style='margin-top:10px'><tr><th>in the gauge</th><th>first-ply failure (Tsai-Wu, MPa)</th>"
            f"<th>(max stress, MPa)</th><th>largest Tsai-Wu index</th></tr>{per}</table>"
            "<table class=job style='margin-top:10px'><tr><th>netting allowable</th><th>material</th><th>fiber (MPa)</th>"
            f"<th>from</th><th>Xt / V_f (MPa)</th></tr>{allow}</table>"
            + (f"<ul class=notes>{notes}</ul>" if notes else ""))
