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
from winder.errors import ConfigError, WinderError
from winder.export.paths import shown
from winder.geometry.build import build_surface
from winder.progress import doing

if TYPE_CHECKING:
    from winder.geometry.surface import SweepSurface
    from winder.winding.budget import Budget

__all__ = ["refuse_formats", "validate", "validate_job", "validate_within"]


def validate_job(job: JobConfig) -> tuple[SweepSurface, Budget]:
    """The surface and the work budget of a loaded job that `run` can plan; ConfigError otherwise."""
    with doing(f"building the mandrel's surface of {shown(job.source)} and checking it (folds, self-contact)"):
        surface = build_surface(job.mandrel, job.source, job.name)
    if job.winding is None:
        raise ConfigError("required key missing; `run` needs a winding plan (band_width and layers)",
                          file=job.source, key_path="winding")
    from winder.analysis.job import check_analysis  # noqa: PLC0415 - ply names and data, SPEC "Structural analysis"

    check_analysis(job)
    if job.machine is not None and job.machine.cell is not None:  # a ring out of the arm's reach
        from winder.export.robot_programs import require_cell  # noqa: PLC0415
        from winder.machine.cell_check import check_cell_reach  # noqa: PLC0415

        require_cell(job, (job.machine.dialect,))  # the language `run` writes by default

        check_cell_reach(job.machine.cell, surface, job.source)
    # The planner's modules load after the geometry's refusals (a folded mandrel is refused at once).
    from winder.winding.budget import check_budget  # noqa: PLC0415

    with doing(f"computing the work budget of {shown(job.source)} (circuits, passes, points, memory)"):
        return surface, check_budget(job, surface)


def validate(path: str | os.PathLike) -> tuple[JobConfig, SweepSurface, Budget]:
    """Read a job file and validate it as `run` would, before any computation."""
    with doing(f"reading {shown(os.fspath(path))}"):
        job = load_config(path)
    surface, budget = validate_job(job)
    return job, surface, budget


def validate_within(path: str | os.PathLike, seconds: float | None) -> tuple[JobConfig, SweepSurface, Budget]:
    """validate, stopped past seconds of wall-clock time (`check --time-limit`): a WinderError (exit 1:
    the config is neither found valid nor invalid) naming what the check was doing then."""
    from winder.app.interrupts import raise_if_interrupted  # noqa: PLC0415
    from winder.app.wall_clock import TimeUp, time_limit  # noqa: PLC0415

    try:
        with time_limit(seconds):
            return validate(path)
    except TimeUp as up:
        raise_if_interrupted(up)
        doing = f": stopped while {up.activity}" if up.activity else ""
        raise WinderError(f"the check did not finish within its time limit of {seconds:g} s (check --time-limit)"
                          f"{doing}", file=os.fspath(path)) from None


def refuse_formats(job: JobConfig, formats) -> None:
    """Refuse the outputs the config alone cannot give (ConfigError, exit 2), before any planning: the
    layup without a material, a robot language without its cell, arm or module name, the Abaqus deck
    without its ply data and load case (SPEC "Structural analysis")."""
    if "layup" in formats:
        from winder.export.layup import require_material  # noqa: PLC0415

        require_material(job)
    from winder.export.robot_programs import require_cell  # noqa: PLC0415

    require_cell(job, formats)
    if "abaqus" in formats:
        from winder.export.abaqus import require_analysis  # noqa: PLC0415

        require_analysis(job)
