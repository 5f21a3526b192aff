"""The registry's entries of the robot-cell languages (winder.export.registry): each serializes the
job's one motion program (built once per job by winder.app.jobs) through its dialect
(winder.export.dialects.krl, rapid, urscript)."""

from __future__ import annotations

import importlib

from winder.machine.program import MotionProgram
from winder.winding.results import WindingPlan


def _texts(plan: WindingPlan, job, language: str, program: MotionProgram | Exception | None) -> dict[str, str]:
    if isinstance(program, Exception):  # the build's error (an unreachable pose, a limit)
        raise program
    if program is None:
        from winder.machine.tension import job_program  # noqa: PLC0415

        program = job_program(plan, job)
    return importlib.import_module(f"winder.export.dialects.{language}").serialize(program)


def krl_src(plan: WindingPlan, job, program: MotionProgram | Exception | None = None) -> str:
    return _texts(plan, job, "krl", program)[".src"]


def krl_dat(plan: WindingPlan, job, program: MotionProgram | Exception | None = None) -> str:
    return _texts(plan, job, "krl", program)[".dat"]


def rapid(plan: WindingPlan, job, program: MotionProgram | Exception | None = None) -> str:
    return _texts(plan, job, "rapid", program)[".mod"]


def urscript(plan: WindingPlan, job, program: MotionProgram | Exception | None = None) -> str:
    return _texts(plan, job, "urscript", program)[".script"]
