"""The registry's entries of the robot-cell languages (winder.export.registry): each serializes the
job's one motion program (built once per job by winder.app.jobs) through its dialect
(winder.export.dialects.krl, rapid, urscript)."""

from __future__ import annotations

import importlib
import weakref

from winder.machine.program import MotionProgram
from winder.winding.results import WindingPlan


_WRITTEN: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()  # program -> {language: its texts}


def _texts(plan: WindingPlan, job, language: str, program: MotionProgram | Exception | None) -> dict[str, str]:
    """The language's texts of the program, serialized once per program (KRL's .src and .dat are two
    formats of one serialization)."""
    if isinstance(program, Exception):  # the build's error (an unreachable pose, a limit)
        raise program
    if program is None:
        from winder.machine.program import build_program  # noqa: PLC0415

        program = build_program(plan, job.machine)
    written = _WRITTEN.setdefault(program, {})
    if language not in written:
        written[language] = importlib.import_module(f"winder.export.dialects.{language}").serialize(program)
    return written[language]


def krl_src(plan: WindingPlan, job, program: MotionProgram | Exception | None = None) -> str:
    return _texts(plan, job, "krl", program)[".src"]


def krl_dat(plan: WindingPlan, job, program: MotionProgram | Exception | None = None) -> str:
    return _texts(plan, job, "krl", program)[".dat"]


def rapid(plan: WindingPlan, job, program: MotionProgram | Exception | None = None) -> str:
    return _texts(plan, job, "rapid", program)[".mod"]


def urscript(plan: WindingPlan, job, program: MotionProgram | Exception | None = None) -> str:
    return _texts(plan, job, "urscript", program)[".script"]
