"""The report page: one self-contained HTML file, the summary tables and the figures.

plotly.js (from the plotly wheel) is inlined once, with the first figure; the page loads nothing
from the network, so it opens offline, from an e-mail attachment or a USB stick. The page holds no
date or random id, so the same plan gives the same bytes.
"""

from __future__ import annotations

import html
from typing import Any

from winder import __version__
from winder.winding.results import LayerPlan, WindingPlan
from winder.progress import Progress
from winder.report.coverage_map import LayerCoverageMap, coverage_figure, layer_coverage_map
from winder.report.plotting import figure_html, require_plotly
from winder.report.profiles import profiles_figure
from winder.report.tables import job_table, layer_table
from winder.report.traveller import PRINT_STYLE
from winder.report.unrolled import unrolled_figure
from winder.report.view3d import view3d_figure
from winder.geometry.sections import arc_map


STYLE = """
body{font-family:"Segoe UI",Helvetica,Arial,sans-serif;margin:0;color:#222;background:#fafbfc}
header{background:#1f3b57;color:#fff;padding:18px 28px}
header h1{margin:0;font-size:24px} header p{margin:4px 0 0;color:#cfd9e3;font-size:13px}
nav{padding:8px 28px;background:#e9eef3;font-size:14px} nav a{margin-right:18px;color:#1f3b57}
main{padding:8px 28px 40px;max-width:1500px}
section{background:#fff;border:1px solid #e1e5ea;border-radius:6px;margin:18px 0;padding:12px 18px}
h2{font-size:19px;margin:6px 0 10px;color:#1f3b57} p.how{color:#555;font-size:13px;margin:2px 0 8px}
table{border-collapse:collapse;font-size:13px} th,td{padding:4px 10px;border-bottom:1px solid #e6e9ed}
table.layers th{background:#f0f3f6;text-align:center;vertical-align:bottom}
table.layers th,table.layers td{padding:4px 6px}
table.layers td{text-align:right;white-space:nowrap} table.layers td .dim{display:block}
table.job th{text-align:left;color:#555}
.unit{font-weight:normal;color:#777;font-size:11px} .dim{color:#888} .bad{color:#c62828;font-weight:600}
ul.notes{font-size:13px;color:#444;margin:8px 0 0 0;padding-left:18px}
"""

HOW = {
    "unrolled": "The mandrel cut open along θ = 0 and laid flat: t along the mandrel against the arc-length "
                "position around the section (360° of arc per turn). Forward passes lay the +α bands, return "
                "passes the −α bands; a helical layer of N circuits shows 2N bands. Click a legend entry to hide it.",
    "coverage": "Band layers over each cell of the unrolled surface (a ±α layer is 2 where even). Red: a gap, "
                "where the forward or the return bands (or a hoop traverse) leave the mandrel bare although "
                "they are laid there. The bare fraction is measured exactly at the planner's coverage stations "
                "(ticks above each map) and equals 1 − covered fraction of the summary.",
    "profiles": "Winding angle from the meridian (the band between the least and the largest over all passes, "
                "and their mean), the band layers averaged around the perimeter, stacked layer on layer, and "
                "the wall thickness when the plan carries one.",
    "view3d": "The mandrel and every band's centre line, each layer slightly lifted off the one below. "
              "Drag to rotate, scroll to zoom, double-click to reset; click legend entries to hide layers.",
}


def layer_title(layer: LayerPlan) -> str:
    if layer.type.value == "hoop":
        return f"Layer {layer.index}: hoop {layer.angle_deg:.2f}°, {layer.circuits} traverse(s)"
    return (f"Layer {layer.index}: helical ±{layer.angle_deg:.2f}°, {layer.circuits} circuits, "
            f"pattern k = {layer.pattern}")


def _section(key: str, title: str, body: str) -> str:
    return f'<section id="{key}"><h2>{html.escape(title)}</h2><p class=how>{html.escape(HOW.get(key, ""))}</p>' \
           f"{body}</section>"


def _agreement(maps: tuple[LayerCoverageMap, ...], summary: dict[str, Any]) -> str:
    rows = []
    for m, layer in zip(maps, summary.get("layers") or []):
        covered = (layer.get("coverage") or {}).get("covered_fraction")
        ref = "–" if covered is None else f"{1.0 - covered:.6f}"
        rows.append(f"<tr><td>layer {m.layer}</td><td>{m.bare_fraction:.6f}</td><td>{ref}</td></tr>")
    return ("<table class=job><tr><th></th><th>bare fraction (map)</th><th>1 − covered (summary)</th></tr>"
            + "".join(rows) + "</table>")


def report_html(plan: WindingPlan, summary: dict[str, Any], band_width: float | None = None,
                progress: Progress | None = None, structure=None, cell: dict[str, Any] | None = None,
                fe=None, traveller: str = "") -> str:
    """The whole report page of a planned job.

    Parameters
    ----------
    plan : the job's plan. summary : its summary dict (winder.export.summary.summary_dict(plan)).
    band_width : the band width (mm) the coverage map draws; default the plan's own.
    progress : called as progress(fraction done, label) after each step (winder.progress).
    structure : the job's winder.analysis.structure.Structure (a job with `analysis:`), for its section.
    cell : a robot cell's figure (winder.report.cell_view), shown after the 3D view.
    fe : `winder analyze`'s winder.analysis.fe_compare.Comparison, drawn beside the laminate analysis.
    traveller : the traveller section (winder.report.traveller), last: the page prints as it alone.

    Raises ConfigError (exit 2) when plotly, the `plot` extra, is not installed.
    """
    require_plotly()
    band_width = plan.band_width if band_width is None else band_width
    if band_width is None:
        raise ValueError("report_html: the plan carries no band width; pass band_width")
    steps = len(plan.layers) + 4
    done = 0

    def step(label: str) -> None:
        nonlocal done
        done += 1
        if progress is not None:
            progress(done / steps, label)

    arcs = arc_map(plan.surface.section)
    titles = [layer_title(layer) for layer in plan.layers]
    maps = []
    for layer in plan.layers:
        maps.append(layer_coverage_map(plan, layer, arcs, band_width))
        step(f"coverage map of layer {layer.index}")
    maps = tuple(maps)
    length = plan.surface.axial_length
    figures = []
    for key, make in (("unrolled", lambda: unrolled_figure(plan, arcs, titles)),
                      ("coverage", lambda: coverage_figure(maps, titles, length)),
                      ("profiles", lambda: profiles_figure(plan, maps, titles)),
                      ("view3d", lambda: view3d_figure(plan, titles))):
        figures.append(figure_html(make(), f"winder-{key}", include_plotlyjs=not figures))
        step(f"{key} figure")
    extra = [("band width", f"{band_width:g} mm"), ("mandrel length T", f"{length:.2f} mm"),
             ("config", html.escape(str(summary.get("source", plan.source))))]
    name = html.escape(str(summary.get("name", plan.name)))
    sections = [
        _section("summary", "Summary", job_table(summary, extra) + "<h2 style='margin-top:16px'>Layers</h2>"
                 + layer_table(summary)),
        _section("unrolled", "Unrolled pattern", figures[0]),
        _section("coverage", "Coverage map", figures[1] + _agreement(maps, summary)),
        _section("profiles", "Along the mandrel", figures[2]),
        _section("view3d", "3D view", figures[3]),
    ]
    links = [("summary", "Summary"), ("unrolled", "Unrolled pattern"), ("coverage", "Coverage map"),
             ("profiles", "Along the mandrel"), ("view3d", "3D view")]
    from winder.report.vessel import is_wound_vessel  # noqa: PLC0415

    if is_wound_vessel(plan):  # the domes as wound (issue 42)
        from winder.report.vessel import HOW as VESSEL_HOW, turnaround_table, vessel_figure  # noqa: PLC0415
        HOW.setdefault("vessel", VESSEL_HOW)
        body = figure_html(vessel_figure(plan), "winder-vessel", include_plotlyjs=False) + turnaround_table(summary)
        sections.append(_section("vessel", "The domes as wound", body))
        links.append(("vessel", "Domes"))
    if "analysis" in summary:  # the structure (issue 32)
        from winder.report.structure import HOW as STRUCTURE_HOW, structure_figure, structure_table  # noqa: PLC0415

        body = structure_table(summary["analysis"])
        if structure is not None and structure.stations is not None:
            body += figure_html(structure_figure(structure, length, fe), "winder-structure", include_plotlyjs=False)
        HOW.setdefault("structure", STRUCTURE_HOW)
        sections.append(_section("structure", "Will it hold?", body))
        links.append(("structure", "Structure"))
    if cell is not None:
        sections.append(_section("cell", "Robot cell", figure_html(cell, "winder-cell", include_plotlyjs=False)))
        links.append(("cell", "Robot cell"))
    if traveller:
        sections.append(traveller)
        links.append(("traveller", "Traveller"))
    nav = "".join(f'<a href="#{k}">{t}</a>' for k, t in links)
    return (f"<!DOCTYPE html>\n<html lang=en><head><meta charset=utf-8><title>{name}: winding report</title>"
            f"<meta name=viewport content='width=device-width, initial-scale=1'><style>{STYLE}{PRINT_STYLE}</style>"
            "</head>"
            f"<body><header><h1>{name}: winding report</h1><p>winder {html.escape(__version__)} · "
            f"{len(plan.layers)} layer(s) · self-contained page, opens offline</p></header><nav>{nav}</nav>"
            f"<main>{''.join(sections)}</main></body></html>\n")
