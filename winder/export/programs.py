"""One motion program per plan and machine: the G-code and the summary's winding times share it.

Building the program (the eye's path, its leads and clearance, densify, the dynamics) is most of a
whole job's output time, and a job renders it for two files: `<name>.gcode` and the summary's
winding_time_s. The last program built is kept while its plan lives (a weak reference: a batch of
jobs holds at most one program, and never one whose plan is gone).
"""

from __future__ import annotations

import weakref

from winder.config.machine import MachineConfig
from winder.machine.program import MotionProgram, build_program
from winder.winding.results import WindingPlan

_LAST: list[tuple[weakref.ref, MachineConfig, MotionProgram]] = []


def _forget(plan_ref: weakref.ref) -> None:
    if _LAST and _LAST[0][0] is plan_ref:
        _LAST.clear()


def program_of(plan: WindingPlan, machine: MachineConfig) -> MotionProgram:
    """build_program(plan, machine), built once for the same plan and machine objects."""
    if _LAST:
        ref, mach, program = _LAST[0]
        if ref() is plan and mach is machine:
            return program
    program = build_program(plan, machine)
    ref = weakref.ref(plan)
    _LAST[:] = [(ref, machine, program)]
    weakref.finalize(plan, _forget, ref)
    return program
