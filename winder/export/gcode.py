"""The winding program `<name>.gcode` (SPEC.md "Output files", MATH.md 6): the motion program of
winder.machine.program, serialized by its dialect (robot poses for a robot, else generic G-code)."""

from __future__ import annotations

from winder.config.machine import MachineConfig
from winder.export.dialects.generic import GenericGcode
from winder.export.dialects.robot import RobotPoses
from winder.export.dialects.text import Dialect, Move, serialize
from winder.machine.program import MotionProgram, build_program
from winder.winding.results import WindingPlan


def dialect_for(program: MotionProgram) -> Dialect:
    return RobotPoses() if program.robot else GenericGcode()


def program_moves(plan: WindingPlan, machine: MachineConfig) -> tuple[Move, ...]:
    """The programmed moves (or poses) of gcode_text, in order, with their contact points."""
    program = build_program(plan, machine)
    return tuple(serialize(program, dialect_for(program))[1])


def gcode_text(plan: WindingPlan, machine: MachineConfig) -> str:
    """The whole program as text (newline-terminated lines)."""
    program = build_program(plan, machine)
    return "\n".join(serialize(program, dialect_for(program))[0]) + "\n"


def export(plan: WindingPlan, job) -> str:
    """The registry's entry (winder.export.registry)."""
    return gcode_text(plan, job.machine)
