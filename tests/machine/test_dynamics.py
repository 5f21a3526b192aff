"""winder.machine.dynamics: move times against hand computations from the axis dynamics, on programs
parsed back from their text; no axis over its top speed."""

from __future__ import annotations

import numpy as np
import pytest

from conftest import surface_of
from plans import cylinder_plan
from winder.config.machine import AxisDynamics, MachineConfig, MachineDynamics
from winder.config.mandrel import ConstantProfile, LineAxis
from winder.export.gcode import gcode_text
from winder.machine.dynamics import JUNCTION_JUMP, move_times
from winder.machine.program import build_program

TIME_TOL = 0.01  # relative: the profiled time against the stop-to-stop hand computation
SPEED_SLACK = 1e-6  # relative: an axis at its top speed, up to round-off

DYN = MachineDynamics(carriage=AxisDynamics(6000.0, 200.0), rotation=AxisDynamics(7200.0, 360.0),
                      cross_feed=AxisDynamics(3000.0, 100.0), yaw=AxisDynamics(3600.0, 180.0))
MACHINE = MachineConfig(eye_radius=60.0, eye_clearance=None, feed=1e6, chord_tolerance=0.05, dynamics=DYN)
SPEED = np.array([6000.0, 7200.0, 3000.0, 3600.0]) / 60.0  # per s: X, A, Z, B
ACC = np.array([200.0, 360.0, 100.0, 180.0])


@pytest.fixture(scope="module")
def plan():
    return cylinder_plan(surface_of(LineAxis(300.0), ConstantProfile(40.0)), hoop=False)


def parse_generic(text: str) -> np.ndarray:
    rows = []
    for line in text.splitlines():
        if line.startswith("G1 "):
            words = {w[0]: float(w[1:]) for w in line.split()[1:]}
            rows.append([words[c] for c in "XAZB"])
    return np.array(rows)


def hand_time(rows: np.ndarray) -> float:
    """Every move from rest to rest, all axes synchronous: the slowest axis sets the cruise time
    T = max |D_k| / v_k, the most loaded axis the acceleration of the move parameter u in [0, 1],
    alpha = min a_k / |D_k|; a trapezoid (t = T + 1 / (T alpha)) or a triangle (t = 2 / sqrt(alpha))."""
    total = 0.0
    for d in np.abs(np.diff(rows, axis=0)):
        if not d.any():
            continue
        cruise = float(np.max(d / SPEED))
        alpha = float(np.min(ACC[d > 0] / d[d > 0]))
        total += cruise + 1.0 / (cruise * alpha) if cruise * cruise * alpha >= 1.0 else 2.0 / np.sqrt(alpha)
    return total


def test_cylinder_time_against_hand_computation(plan):
    """A helical cylinder job: every move ends in a corner (reversal, dwell), so the profiled time is
    the stop-to-stop sum within the junction allowance."""
    rows = parse_generic(gcode_text(plan, MACHINE))
    program = build_program(plan, MACHINE)
    hand = hand_time(rows)
    assert program.times.total_s == pytest.approx(hand, rel=TIME_TOL)
    assert program.times.total_s <= hand * (1 + 1e-9)  # junction speeds only save time
    assert sum(program.layer_times_s) == pytest.approx(program.times.total_s, rel=1e-12)


def test_collinear_moves_run_through():
    """A straight move split into 50 collinear pieces takes the time of the one move: junctions
    without a direction change do not slow the machine."""
    one = np.array([[0.0, 0.0, 60.0, 0.0], [300.0, 900.0, 60.0, 0.0]])
    many = np.column_stack([np.linspace(0, 300, 51), np.linspace(0, 900, 51), np.full(51, 60.0), np.zeros(51)])
    t1 = move_times(one, np.zeros(2), MACHINE, False).total_s
    t50 = move_times(many, np.zeros(51), MACHINE, False).total_s
    assert t50 == pytest.approx(t1, rel=1e-9)
    assert t1 == pytest.approx(hand_time(one), rel=1e-12)


def test_reversal_nearly_stops():
    """Out and back: the junction allows JUNCTION_JUMP of the top speed, so the time is the two
    stop-to-stop moves within a few JUNCTION_JUMP."""
    rows = np.array([[0.0, 0.0, 60.0, 0.0], [100.0, 0.0, 60.0, 0.0], [0.0, 0.0, 60.0, 0.0]])
    t = move_times(rows, np.zeros(3), MACHINE, False).total_s
    assert t == pytest.approx(hand_time(rows), rel=4 * JUNCTION_JUMP)


def test_feed_limits_fiber_speed():
    """A move laying 100 mm of fiber at feed 600 mm/min takes 10 s of cruise, whatever the axes allow."""
    machine = MachineConfig(eye_radius=60.0, eye_clearance=None, feed=600.0, dynamics=DYN)
    rows = np.array([[0.0, 0.0, 60.0, 0.0], [10.0, 10.0, 60.0, 0.0]])
    times = move_times(rows, np.array([0.0, 100.0]), machine, False)
    assert times.cruise_s[1] == pytest.approx(10.0)
    assert times.feed[1] == pytest.approx(600.0)


def test_no_axis_over_its_speed(plan):
    """From the program's cruise times: every axis' speed within its top speed; the fiber feed never
    above machine.feed."""
    machine = MachineConfig(eye_radius=60.0, eye_clearance=None, feed=20000.0, dynamics=DYN)
    program = build_program(plan, machine)
    d = np.abs(np.diff(program.values, axis=0))
    t = program.times.cruise_s[1:]
    moving = d.any(axis=1)
    assert (d[moving] / t[moving, None] <= SPEED * (1 + SPEED_SLACK)).all()
    assert (program.feed <= 20000.0 * (1 + 1e-12)).all()
    assert (program.times.time_s >= program.times.cruise_s - 1e-12).all()
