"""The winding program `<name>.gcode` (docs/guide/conventions.md, docs/math/06-machine.md): the motion program of
winder.machine.program, serialized by the dialect machine.dialect names in the dialect registry
(winder.config.dialects; the serializers in winder.export.dialects): generic G-code, marlin,
linuxcnc, or robot poses (always for a robot). The program is built once per job by the caller
(winder.app.jobs) and handed in; built here only when none is given."""

from __future__ import annotations

import importlib

from winder.config.controllers import builtin
from winder.config.dialects import entry, robot_dialects
from winder.config.machine import MachineConfig
from winder.export.dialects.text import Dialect, Move, serialize
from winder.machine.program import MotionProgram, build_program
from winder.winding.results import WindingPlan


def dialect_for(program: MotionProgram, band_width: float = 0.0) -> Dialect:
    """The serializer of machine.dialect from the registry (robot poses whenever the program is a
    robot's and the dialect is not a robot's)."""
    found = entry(program.machine.dialect)
    if found.cell or (program.robot and not found.robot):  # a cell's language is written beside, as its own files
        found = entry(robot_dialects()[0])
        dialect = importlib.import_module(found.module).make(program, band_width)
        dialect.controller = builtin(found.name)
        return dialect
    return importlib.import_module(found.module).make(program, band_width)


def program_moves(plan: WindingPlan, machine: MachineConfig, program: MotionProgram | None = None) -> tuple[Move, ...]:
    """The programmed moves (or poses) of gcode_text, in order, with their contact points."""
    program = program if program is not None else build_program(plan, machine)
    return tuple(serialize(program, dialect_for(program))[1])


def program_text(program: MotionProgram, band_width: float = 0.0) -> str:
    """A motion program as text in its machine's dialect (newline-terminated lines); band_width (mm)
    for the marlin header."""
    return "\n".join(serialize(program, dialect_for(program, band_width), moves=False)[0]) + "\n"


def gcode_text(plan: WindingPlan, machine: MachineConfig, band_width: float = 0.0,
               program: MotionProgram | None = None) -> str:
    """The whole program of a plan on a machine as text (program_text; built here unless given)."""
    return program_text(program if program is not None else build_program(plan, machine), band_width)


def export(plan: WindingPlan, job, program: MotionProgram | Exception | None = None) -> str:
    """The registry's entry (winder.export.registry); program: the job's motion program, or the
    error that kept it from being built (raised here)."""
    if isinstance(program, Exception):
        raise program
    band = job.winding.band_width if job.winding is not None else 0.0
    return gcode_text(plan, job.machine, band, program)
