"""The registry's entry for `<name>.html` (winder.export.registry): the report page of a planned job."""

from __future__ import annotations

from winder.export.summary import summary_dict
from winder.progress import Progress
from winder.report.html import report_html
from winder.winding.results import WindingPlan


def export(plan: WindingPlan, job, progress: Progress | None = None) -> str:
    """The page of plan (job is the registry's second argument; the plan carries all it needs)."""
    return report_html(plan, summary_dict(plan), progress=progress)
