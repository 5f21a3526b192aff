"""The registry's entry for `<name>.html` (winder.export.registry): the report page of a planned job."""

from __future__ import annotations

import numpy as np

from winder.export.summary import summary_dict
from winder.progress import Progress
from winder.report.html import report_html
from winder.report.traveller import traveller_html
from winder.winding.results import WindingPlan


def export(plan: WindingPlan, job, progress: Progress | None = None, program=None) -> str:
    """The page of plan, with the summary `<name>.summary.json` holds: job's machine gives the winding
    times (program: the job's motion program, built once by winder.app.jobs, or its build's error)."""
    structure = None
    if getattr(job, "analysis", None) is not None:  # the structure section (issue 32)
        from winder.analysis.structure import analyze  # noqa: PLC0415

        structure = analyze(plan, job)
    cell = None
    if program is not None and not isinstance(program, Exception) and program.cell is not None:  # its view too
        from winder.report.cell_view import cell_figure  # noqa: PLC0415

        guide = plan.surface.curve.evaluate(np.linspace(0.0, plan.surface.axial_length, 200)).x
        cell = cell_figure(program.cell, guide)
    summary = summary_dict(plan, job.machine, program, job)
    return report_html(plan, summary, progress=progress, structure=structure, cell=cell,
                       traveller=traveller_html(summary, job, _program_file(job)))


def _program_file(job) -> str:
    """The name of the program file the job's machine is wound by (its dialect's suffix)."""
    machine = getattr(job, "machine", None)
    if machine is None:
        return ""
    suffix = {"krl": ".src", "rapid": ".mod", "urscript": ".script"}.get(machine.dialect, ".gcode")
    return job.name + suffix
