"""The traveller: the sheet an operator winds a job by (the report page printed: its print style shows
this section alone, on one A4 page per job).

Per layer the material, tows, tex, band, tension, angle, circuits, passes laid, time, fiber and resin
masses and a sign-off column; below, each material's totals (tow drawn, masses) and their cost where
the config gives prices (winding.material's fiber_price_per_kg, resin_price_per_kg). The numbers are the
summary's (winder.export.summary), the materials the config's.
"""

from __future__ import annotations

import html
from typing import Any

from winder.report.tables import _num, _passes, _time, duration

# In print the layer rows share TABLE_MM of the A4 page (the title, the fields, the header row and the
# materials take the rest): each row as tall as that allows up to ROW_MM (room to sign it off), its text
# at most FONT_PT and at most TEXT_SHARE of the row (one line); past MIN_FONT_PT (about 120 layers) the
# table no longer keeps to one page.
TABLE_MM = 160.0
ROW_MM = 8.0
BORDER_MM = 0.3  # a row's rule
FONT_PT = 9.0
MIN_FONT_PT = 3.5
TEXT_SHARE = 0.75
PT_MM = 25.4 / 72.0

PRINT_STYLE = """
section.traveller table{border-collapse:collapse;font-size:12px}
section.traveller th,section.traveller td{border:1px solid #9aa5b1;padding:3px 5px}
section.traveller td{text-align:right;white-space:nowrap} section.traveller td.text{text-align:left}
section.traveller td.sign{min-width:70px;width:22%} section.traveller table.fields{width:auto}
section.traveller .fields th{text-align:left} section.traveller .fields td{text-align:left;min-width:240px}
@page{size:A4;margin:10mm}
@media print{
 body{background:#fff} body>header,nav,main>section:not(.traveller){display:none !important}
 main{padding:0;max-width:none} section.traveller{border:none;margin:0;padding:0;break-inside:avoid}
 section.traveller table.layers,section.traveller table.totals{break-inside:avoid;width:100%}
 section.traveller h2{font-size:14pt;margin:0 0 4pt} section.traveller h3{font-size:11pt;margin:6pt 0 3pt}
 section.traveller table.fields,section.traveller table.totals,section.traveller p{font-size:8.5pt}
 section.traveller .unit{font-size:0.85em} section.traveller th{padding:1px 3px}
 section.traveller p.how{display:none}
}
"""


def _material_name(material) -> str:
    if material is None:
        return "–"
    if material.lamina is not None and material.lamina.name:
        return material.lamina.name
    if material.fiber_tex is not None:
        return f"{material.fiber_tex:g} tex"
    return f"ply {material.ply_thickness:g} mm"


def _tension(layer: dict[str, Any]) -> str:
    if "tension_n" not in layer:
        return "–"
    low, high = layer.get("tension_range_n") or (layer["tension_n"],) * 2
    if low == high:
        return _num(low, 1)
    return f"{_num(layer['tension_n'], 1)} <span class=dim>({_num(low, 1)}–{_num(high, 1)})</span>"


def _rows(summary: dict[str, Any], job) -> str:
    winding = job.winding
    band = winding.band_width
    out = []
    for i, layer in enumerate(summary.get("layers") or []):
        material = winding.material_of(i)
        sign = "±" if layer.get("type") == "helical" else ""
        cells = [_num(layer.get("index"), 0), html.escape(str(layer.get("type", "–"))),
                 html.escape(_material_name(material)),
                 _num(material.tows, 0) if material is not None and material.tows else "–",
                 _num(material.fiber_tex, 0) if material is not None and material.fiber_tex else "–",
                 _num(band, 1), _tension(layer), f"{sign}{_num(layer.get('angle_deg'), 2)}",
                 _num(layer.get("circuits"), 0), _passes(layer), duration(_time(layer)),
                 _num(layer.get("fiber_mass_kg"), 3), _num(layer.get("resin_mass_kg"), 3), ""]
        classes = ["", "text", "text"] + [""] * 10 + ["sign"]
        out.append("<tr>" + "".join(f"<td class={c}>{v}</td>" if c else f"<td>{v}</td>"
                                    for c, v in zip(classes, cells)) + "</tr>")
    return "".join(out)


def _totals(summary: dict[str, Any], job) -> str:
    """Per material: layers, tow drawn, fiber and resin mass, and the cost where prices are given."""
    winding = job.winding
    groups: dict[Any, dict[str, Any]] = {}
    for i, layer in enumerate(summary.get("layers") or []):
        material = winding.material_of(i)
        g = groups.setdefault(material, {"layers": [], "tow": 0.0, "fiber": 0.0, "resin": 0.0})
        g["layers"].append(int(layer.get("index", i + 1)))
        for key, field in (("tow", "material_length_mm"), ("fiber", "fiber_mass_kg"), ("resin", "resin_mass_kg")):
            g[key] += layer.get(field) or 0.0
    priced = any(m is not None and (m.fiber_price_per_kg is not None or m.resin_price_per_kg is not None)
                 for m in groups)
    head = ["material", "layers", "tow drawn<br><span class=unit>m</span>", "fiber<br><span class=unit>kg</span>",
            "resin<br><span class=unit>kg</span>"] + (["cost"] if priced else [])
    rows = []
    for material, g in groups.items():
        cells = [html.escape(_material_name(material)), _ranges(g["layers"]), _num(g["tow"] * 1e-3, 1),
                 _num(g["fiber"], 3), _num(g["resin"], 3)]
        if priced:
            fiber_price = getattr(material, "fiber_price_per_kg", None) if material is not None else None
            resin_price = getattr(material, "resin_price_per_kg", None) if material is not None else None
            cost = (g["fiber"] * (fiber_price or 0.0)) + (g["resin"] * (resin_price or 0.0))
            cells.append(_num(cost, 2) if fiber_price is not None or resin_price is not None else "–")
        rows.append("<tr>" + "".join(f"<td>{c}</td>" for c in cells) + "</tr>")
    total = summary.get("material_cost")
    if total is not None:
        rows.append(f"<tr><td class=text colspan=5><b>total</b> (fiber {_num(total['fiber'], 2)}, resin "
                    f"{_num(total['resin'], 2)})</td><td><b>{_num(total['total'], 2)}</b></td></tr>")
    return ("<table class=totals><tr>" + "".join(f"<th>{h}</th>" for h in head) + "</tr>" + "".join(rows)
            + "</table>")


def _ranges(numbers: list[int]) -> str:
    """Layer numbers as runs: 1-4, 7, 9-12."""
    runs: list[list[int]] = []
    for k in numbers:
        if runs and k == runs[-1][1] + 1:
            runs[-1][1] = k
        else:
            runs.append([k, k])
    return ", ".join(f"{a}" if a == b else f"{a}–{b}" for a, b in runs)


def print_size(layers: int) -> tuple[float, float]:
    """The layer table's font size (pt) and row height (mm) in print, so that the table keeps to one
    A4 page (module constants)."""
    row = min(ROW_MM, TABLE_MM / max(layers, 1)) - BORDER_MM
    return max(MIN_FONT_PT, min(FONT_PT, TEXT_SHARE * row / PT_MM)), row


def traveller_html(summary: dict[str, Any], job, program_name: str = "") -> str:
    """The traveller section of the report (module docstring); empty without a winding plan."""
    if getattr(job, "winding", None) is None:
        return ""
    name = html.escape(str(summary.get("name", "")))
    head = ["layer", "type", "material", "tows", "tex<br><span class=unit>g/km</span>",
            "band<br><span class=unit>mm</span>", "tension<br><span class=unit>N</span>",
            "angle<br><span class=unit>deg</span>", "circuits", "passes<br><span class=unit>laid</span>",
            "time<br><span class=unit>h:mm:ss</span>", "fiber<br><span class=unit>kg</span>",
            "resin<br><span class=unit>kg</span>", "sign-off<br><span class=unit>initials, time</span>"]
    fields = [("job", name), ("config", html.escape(str(summary.get("source", "")))),
              ("program", html.escape(program_name)), ("mandrel / serial", ""), ("machine", ""),
              ("date, operator", "")]
    pt, mm = print_size(len(summary.get("layers") or []))
    rule = (f"section.traveller table.layers{{font-size:{pt:.2f}pt}}"
            f"section.traveller table.layers tbody td{{height:{mm:.2f}mm;line-height:1;padding:0 3px}}")
    return (f"<section id=traveller class=traveller><h2>Traveller: {name}</h2>"
            "<p class=how>The sheet to wind this job by: the report prints as this page alone (A4), a row per "
            "layer to sign off as it is wound.</p>"
            "<table class=fields>" + "".join(f"<tr><th>{k}</th><td>{v}</td></tr>" for k, v in fields) + "</table>"
            f"<style>@media print{{{rule}}}</style>"
            "<table class=layers style='margin-top:8px'><thead><tr>"
            + "".join(f"<th>{h}</th>" for h in head) + f"</tr></thead><tbody>{_rows(summary, job)}</tbody></table>"
            f"<h3>Materials</h3>{_totals(summary, job)}"
            f"<p>{_job_figures(summary)}</p></section>")


def _job_figures(summary: dict[str, Any]) -> str:
    """The job's totals under the tables: winding time, laminate mass, and what the summary gives of a
    vessel's volume or a pipe's mass per metre."""
    out = [f"Total winding time {duration(summary.get('winding_time_s') or summary.get('estimated_time_s'))}",
           f"laminate mass {_num(summary.get('mass_kg'), 3)} kg"]
    if summary.get("volume_l") is not None:
        out.append(f"enclosed volume {_num(summary['volume_l'], 2)} L")
    if summary.get("mass_per_metre_kg") is not None:
        out.append(f"{_num(summary['mass_per_metre_kg'], 3)} kg per metre")
    return "; ".join(out) + "."
