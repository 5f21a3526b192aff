"""The registry's entries of the robot-cell languages (winder.export.registry): each renders the job's
one motion program through its dialect (winder.export.dialects.krl, rapid, urscript)."""

from __future__ import annotations

from winder.export.programs import program_of
from winder.winding.results import WindingPlan


_LAST: list = []  # [program, language, texts]: KRL's two files come from one serialization


def _texts(plan: WindingPlan, job, language: str) -> dict[str, str]:
    import importlib  # noqa: PLC0415

    program = program_of(plan, job.machine)
    if _LAST and _LAST[0] is program and _LAST[1] == language:
        return _LAST[2]
    texts = importlib.import_module(f"winder.export.dialects.{language}").serialize(program)
    _LAST[:] = [program, language, texts]
    return texts


def krl_src(plan: WindingPlan, job) -> str:
    return _texts(plan, job, "krl")[".src"]


def krl_dat(plan: WindingPlan, job) -> str:
    return _texts(plan, job, "krl")[".dat"]


def rapid(plan: WindingPlan, job) -> str:
    return _texts(plan, job, "rapid")[".mod"]


def urscript(plan: WindingPlan, job) -> str:
    return _texts(plan, job, "urscript")[".script"]
