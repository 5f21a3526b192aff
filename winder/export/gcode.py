"""The winding program `<name>.gcode` (SPEC.md "Output files", MATH.md 6): the motion program of
winder.machine.program, serialized by the dialect of machine.dialect (winder.export.dialects):
generic G-code, marlin, linuxcnc, or robot poses (always for a robot)."""

from __future__ import annotations

from winder.config.machine import MachineConfig
from winder.export.dialects.generic import GenericGcode
from winder.export.dialects.linuxcnc import LinuxcncGcode
from winder.export.dialects.marlin import MarlinGcode
from winder.export.dialects.robot import RobotPoses
from winder.export.dialects.text import Dialect, Move, serialize
from winder.export.programs import program_of
from winder.machine.program import MotionProgram
from winder.winding.results import WindingPlan


def dialect_for(program: MotionProgram, band_width: float = 0.0) -> Dialect:
    """The serializer of machine.dialect (robot poses whenever the program is a robot's)."""
    if program.robot:
        return RobotPoses()
    name = program.machine.dialect
    if name == "marlin":
        return MarlinGcode(band_width)
    if name == "linuxcnc":
        return LinuxcncGcode()
    return GenericGcode()


def program_moves(plan: WindingPlan, machine: MachineConfig) -> tuple[Move, ...]:
    """The programmed moves (or poses) of gcode_text, in order, with their contact points."""
    program = program_of(plan, machine)
    return tuple(serialize(program, dialect_for(program))[1])


def program_text(program: MotionProgram, band_width: float = 0.0) -> str:
    """A motion program as text in its machine's dialect (newline-terminated lines); band_width (mm)
    for the marlin header."""
    return "\n".join(serialize(program, dialect_for(program, band_width), moves=False)[0]) + "\n"


def gcode_text(plan: WindingPlan, machine: MachineConfig, band_width: float = 0.0) -> str:
    """The whole program of a plan on a machine as text (program_text)."""
    return program_text(program_of(plan, machine), band_width)


def export(plan: WindingPlan, job) -> str:
    """The registry's entry (winder.export.registry)."""
    band = job.winding.band_width if job.winding is not None else 0.0
    return gcode_text(plan, job.machine, band)
