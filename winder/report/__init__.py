"""Stage 7, report: one self-contained HTML page per job, to check a program by looking at it.

Reads a planned job (a WindingPlan, which carries the band width it was laid with) and its summary
dict (winder.export.summary.summary_dict) and nothing else; it never plans, never writes files and never
prints. Pictures (plotly, the optional `plot` extra, imported lazily on first use):

- unrolled.py: every layer's band centre lines on the unrolled surface (t, position around the
  perimeter), +alpha and -alpha apart;
- coverage_map.py: band layers over the unrolled surface and the gaps, with the bare fraction at the
  planner's coverage stations (it equals 1 - covered_fraction of the summary);
- profiles.py: winding angle, band layers and (when the plan carries it) thickness along the mandrel;
- view3d.py: an interactive 3D view of the mandrel and the bands, decimated to stay small;
- tables.py / html.py: the summary and per-layer tables, and the page that holds everything;
- export.py: the `report` row of winder.export.registry (`<name>.html`).

May import: every earlier stage (errors, progress, config, geometry, paths, winding, machine, export).
"""

from __future__ import annotations

__all__ = ["report_html"]


def __getattr__(name: str):
    if name == "report_html":
        from winder.report.html import report_html  # noqa: PLC0415 - keeps `import winder.report` light

        return report_html
    raise AttributeError(name)
