"""The registry's entries of the robot-cell languages (winder.export.registry): each serializes the
job's one motion program (built once per job by winder.app.jobs) through its dialect
(winder.export.dialects.krl, rapid, urscript)."""

from __future__ import annotations

import importlib

from winder.errors import ConfigError
from winder.machine.program import MotionProgram
from winder.winding.results import WindingPlan


def _texts(plan: WindingPlan, job, language: str, program: MotionProgram | Exception | None) -> dict[str, str]:
    if isinstance(program, Exception):  # the build's error (an unreachable pose, a limit)
        raise program
    if program is None:
        from winder.machine.program import build_program  # noqa: PLC0415

        program = build_program(plan, job.machine)
    return importlib.import_module(f"winder.export.dialects.{language}").serialize(program)


def krl_src(plan: WindingPlan, job, program: MotionProgram | Exception | None = None) -> str:
    return _texts(plan, job, "krl", program)[".src"]


def krl_dat(plan: WindingPlan, job, program: MotionProgram | Exception | None = None) -> str:
    return _texts(plan, job, "krl", program)[".dat"]


def rapid(plan: WindingPlan, job, program: MotionProgram | Exception | None = None) -> str:
    return _texts(plan, job, "rapid", program)[".mod"]


def urscript(plan: WindingPlan, job, program: MotionProgram | Exception | None = None) -> str:
    return _texts(plan, job, "urscript", program)[".script"]


LANGUAGES = {"krl": "KRL", "rapid": "RAPID", "urscript": "URScript"}  # format -> the language's name


def require_cell(job, formats) -> None:
    """Refuse, from the config alone (ConfigError, exit 2: `check` and `run` before planning), a robot
    language the job cannot be written in: no robot cell, URScript for an arm that is not a Universal
    Robots one, a job name that is not the language's module name (its file's)."""
    import re  # noqa: PLC0415

    from winder.config.arms import ARMS, UR  # noqa: PLC0415

    for fmt in (f for f in formats if f in LANGUAGES):
        language = LANGUAGES[fmt]
        cell = job.machine.cell if job.machine is not None else None
        if cell is None:
            raise ConfigError(f"--format {fmt} needs a robot cell: {language} moves an arm, and this job has no "
                              "machine.robot (a mapping with an arm: kuka_kr16, abb_irb4600, ur10e)",
                              file=job.source, key_path="machine.robot")
        arm = ARMS[cell.arm]
        if fmt == "urscript" and arm.kind != UR:
            raise ConfigError(f"URScript moves a Universal Robots arm in its own base frame; the cell's arm is "
                              f"{arm.name} ({arm.maker}): write krl or rapid for it, got {cell.arm!r}",
                              file=job.source, key_path="machine.robot.arm")
        longest = importlib.import_module(f"winder.export.dialects.{fmt}").NAME_LENGTH
        if not re.fullmatch(rf"[A-Za-z][A-Za-z0-9_]{{0,{longest - 1}}}", job.name):
            raise ConfigError(f"{language} needs a module name of letters, digits and _, starting with a letter, at "
                              f"most {longest} characters, the same as its file's: rename the job, got {job.name!r}",
                              file=job.source, key_path="name")
