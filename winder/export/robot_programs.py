"""The registry's entries of the robot-cell languages (winder.export.registry): each serializes the
job's one motion program (built once per job by winder.app.jobs) through its dialect
(winder.export.dialects.krl, rapid, urscript)."""

from __future__ import annotations

import importlib
import weakref

from winder.errors import ConfigError
from winder.machine.program import MotionProgram
from winder.winding.results import WindingPlan


_WRITTEN: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()  # program -> {language: its texts}


def _texts(plan: WindingPlan, job, language: str, program: MotionProgram | Exception | None) -> dict[str, str]:
    """The language's texts of the program, serialized once per program (KRL's .src and .dat are two
    formats of one serialization)."""
    if isinstance(program, Exception):  # the build's error (an unreachable pose, a limit)
        raise program
    if program is None:
        from winder.machine.tension import job_program  # noqa: PLC0415

        program = job_program(plan, job)
    written = _WRITTEN.setdefault(program, {})
    if language not in written:
        written[language] = importlib.import_module(f"winder.export.dialects.{language}").serialize(program)
    return written[language]


def krl_src(plan: WindingPlan, job, program: MotionProgram | Exception | None = None) -> str:
    return _texts(plan, job, "krl", program)[".src"]


def krl_dat(plan: WindingPlan, job, program: MotionProgram | Exception | None = None) -> str:
    return _texts(plan, job, "krl", program)[".dat"]


def krl_layers(plan: WindingPlan, job, program: MotionProgram | Exception | None = None) -> dict[str, str]:
    """{suffix: text} of the layers' modules of a KRL program split per layer (`_L<N>.src`, `_L<N>.dat`,
    docs/math/10-robot-cell.md 10.10), none when it is written whole."""
    return {k: v for k, v in _texts(plan, job, "krl", program).items() if k not in (".src", ".dat")}


def rapid(plan: WindingPlan, job, program: MotionProgram | Exception | None = None) -> str:
    return _texts(plan, job, "rapid", program)[".mod"]


def urscript(plan: WindingPlan, job, program: MotionProgram | Exception | None = None) -> str:
    return _texts(plan, job, "urscript", program)[".script"]


LANGUAGES = {"krl": "KRL", "rapid": "RAPID", "urscript": "URScript"}  # format -> the language's name


def require_cell(job, formats) -> None:
    """Refuse, from the config alone (ConfigError, exit 2: `check` and `run` before planning), a robot
    language the job cannot be written in: no robot cell, a language the cell's arm's controller does
    not run, a job name that is not the language's module name (its file's): winder.config.robot."""
    from winder.config.arms import ARMS  # noqa: PLC0415
    from winder.config.robot import language_problem, name_problem  # noqa: PLC0415

    for fmt in (f for f in formats if f in LANGUAGES):
        cell = job.machine.cell if job.machine is not None else None
        if cell is None:
            raise ConfigError(f"--format {fmt} needs a robot cell: {LANGUAGES[fmt]} moves an arm, and this job has no "
                              "machine.robot (a mapping with an arm: kuka_kr16, abb_irb4600, ur10e)",
                              file=job.source, key_path="machine.robot")
        problem = language_problem(cell, fmt)
        if problem is not None:
            raise ConfigError(f"{problem}: write {ARMS[cell.arm].language} for it, got --format {fmt}",
                              file=job.source, key_path="machine.robot.arm")
        problem = name_problem(job.name, fmt)
        if problem is not None:
            raise ConfigError(f"{problem}, got {job.name!r}", file=job.source, key_path="name")

