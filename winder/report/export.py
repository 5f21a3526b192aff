"""The registry's entry for `<name>.html` (winder.export.registry): the report page of a planned job."""

from __future__ import annotations

from winder.export.summary import summary_dict
from winder.progress import Progress
from winder.report.html import report_html
from winder.winding.results import WindingPlan


def export(plan: WindingPlan, job, progress: Progress | None = None, program=None) -> str:
    """The page of plan, with the summary `<name>.summary.json` holds: job's machine gives the winding
    times (program: the job's motion program, built once by winder.app.jobs, or its build's error)."""
    return report_html(plan, summary_dict(plan, job.machine, program), progress=progress)
