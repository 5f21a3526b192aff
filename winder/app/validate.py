"""The one validation path of a job: what `check` reports is exactly what `run` refuses before it
computes anything (exit 2), because both call `validate_job`.

Reading the file and its values (winder.config), building the surface (what only the geometry can
tell: folds, dome fits), the winding section that `run` needs, and the work budget
(winder.winding.budget: circuits, passes, points, memory) with a pattern that fits the circuits.
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING

from winder.config.job import JobConfig, load_config
from winder.errors import ConfigError
from winder.geometry.build import build_surface

if TYPE_CHECKING:
    from winder.geometry.surface import SweepSurface
    from winder.winding.budget import Budget

__all__ = ["validate", "validate_job"]


CELL_LANGUAGES = ("krl", "rapid", "urscript")


def validate_job(job: JobConfig, formats: tuple[str, ...] = ()) -> tuple[SweepSurface, Budget]:
    """The surface and the work budget of a loaded job that `run` can plan; ConfigError otherwise.
    formats: the outputs asked for besides the job's own (a robot language among them is checked
    against the cell like the job's dialect)."""
    languages = tuple(dict.fromkeys(x for x in (getattr(job.machine, "dialect", None), *formats) if x in CELL_LANGUAGES))
    if languages:  # the robot languages' names and arm, before anything is built
        from winder.machine.cell_check import check_cell_program  # noqa: PLC0415

        check_cell_program(job, languages)
    surface = build_surface(job.mandrel, job.source, job.name)
    if job.winding is None:
        raise ConfigError("required key missing; `run` needs a winding plan (band_width and layers)",
                          file=job.source, key_path="winding")
    from winder.analysis.job import check_analysis  # noqa: PLC0415 - ply names and data, SPEC "Structural analysis"

    check_analysis(job)
    if job.machine is not None and job.machine.cell is not None:  # a ring out of the arm's reach
        from winder.machine.cell_check import check_cell_reach  # noqa: PLC0415

        check_cell_reach(job.machine.cell, surface, job.source)
    # The planner's modules load after the geometry's refusals (a folded mandrel is refused at once).
    from winder.winding.budget import check_budget  # noqa: PLC0415

    return surface, check_budget(job, surface)


def validate(path: str | os.PathLike) -> tuple[JobConfig, SweepSurface, Budget]:
    """Read a job file and validate it as `run` would, before any computation."""
    job = load_config(path)
    surface, budget = validate_job(job)
    return job, surface, budget
