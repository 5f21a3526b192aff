"""One motion program per plan and machine (winder.export.programs): built once, the same as a fresh build."""

from __future__ import annotations

import gc
from dataclasses import replace

import numpy as np

from conftest import surface_of
from plans import cylinder_plan
from winder.config.machine import MachineConfig
from winder.config.mandrel import ConstantProfile, LineAxis
from winder.export import programs
from winder.machine.program import build_program

MACHINE = MachineConfig(eye_radius=60.0, eye_clearance=None, chord_tolerance=0.05)


def _plan():
    return cylinder_plan(surface_of(LineAxis(300.0), ConstantProfile(40.0)))


def test_the_gcode_and_the_summary_share_one_program_equal_to_a_fresh_build():
    plan = _plan()
    first = programs.program_of(plan, MACHINE)
    assert programs.program_of(plan, MACHINE) is first
    fresh = build_program(plan, MACHINE)
    assert first.times.total_s == fresh.times.total_s
    assert np.array_equal(first.values, fresh.values) and np.array_equal(first.feed, fresh.feed)


def test_another_machine_or_plan_is_built_anew_and_a_dead_plan_is_forgotten():
    plan = _plan()
    first = programs.program_of(plan, MACHINE)
    other = replace(MACHINE, chord_tolerance=0.1)
    assert programs.program_of(plan, other) is not first
    again = _plan()
    assert programs.program_of(again, MACHINE) is not first
    del plan, again
    gc.collect()
    assert programs._LAST == []
