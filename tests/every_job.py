"""Every sample (samples/*.yaml) and every config (configs/*.yaml), planned and programmed once per
test session and shared by the tests that read all of them (line lengths, LinuxCNC's interpreter,
PLY faces, the eye on the exact tangent): planning all 19 jobs takes about a minute on this machine.
"""

from __future__ import annotations

import functools
from dataclasses import replace
from pathlib import Path

from winder.config.job import JobConfig, load_config
from winder.errors import ExportError
from winder.machine.program import MotionProgram, build_program
from winder.winding.plan import plan as plan_job
from winder.winding.results import WindingPlan

ROOT = Path(__file__).resolve().parents[1]
SAMPLES = sorted((ROOT / "samples").glob("*.yaml"))
CONFIGS = sorted((ROOT / "configs").glob("*.yaml"))
EVERY = SAMPLES + CONFIGS
IDS = [f"{p.parent.name}/{p.stem}" for p in EVERY]
GCODE_DIALECTS = ("generic", "linuxcnc", "marlin")


@functools.cache
def job_of(path: Path) -> JobConfig:
    return load_config(path)


@functools.cache
def planned(path: Path) -> WindingPlan:
    return plan_job(job_of(path))


@functools.cache
def program_of(path: Path) -> MotionProgram:
    """The job's motion program as `run` writes it (its passes' tensions included)."""
    from winder.machine.tension import pass_tensions, with_tension  # noqa: PLC0415

    plan = planned(path)
    return with_tension(build_program(plan, job_of(path).machine), pass_tensions(job_of(path), plan))


@functools.cache
def text_of(path: Path, dialect: str) -> str | None:
    """The job's program in `dialect` (the job's own machine otherwise), None where the dialect
    refuses the job (marlin without a fixed eye; a G-code dialect for a robot's poses, robot poses
for a straight-axis program)."""
    from winder.export.gcode import program_text  # noqa: PLC0415

    job, program = job_of(path), program_of(path)
    if program.robot != (dialect == "robot"):  # machine.dialect robot makes the program a robot's (config)
        return None
    band = job.winding.band_width if job.winding is not None else 0.0
    try:
        return program_text(replace(program, machine=replace(program.machine, dialect=dialect)), band)
    except ExportError:
        if dialect == "marlin":
            return None
        raise
