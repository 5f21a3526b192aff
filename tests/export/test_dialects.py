"""The dialects serialize one motion program: marlin (fiberpath's X A B machines) and linuxcnc (G93
inverse time) parsed back independently give the generic program's moves, times within the axes."""

from __future__ import annotations

import json
import re
from dataclasses import replace

import numpy as np
import pytest

from conftest import surface_of
from plans import cylinder_plan
from winder.config.job import parse_config
from winder.config.machine import MachineConfig
from winder.config.mandrel import ConstantProfile, LineAxis
from winder.errors import ExportError
from winder.export.gcode import gcode_text
from winder.machine.program import build_program
from winder.winding.plan import plan as plan_job

GENERIC = MachineConfig(eye_radius=60.0, eye_clearance=None, chord_tolerance=0.05)
SPEED = np.array([30000.0, 20000.0, 10000.0, 20000.0]) / 60.0  # the default dynamics, per s
SLACK = 1e-3  # relative: what 3-decimal rounding of the axes adds to a speed
MARLIN_OPCODES = {"G0", "G1", "G21", "G90", "G92", "G94"}


@pytest.fixture(scope="module")
def plan():
    return cylinder_plan(surface_of(LineAxis(300.0), ConstantProfile(40.0)))


def moves(text: str, letters: str) -> tuple[np.ndarray, np.ndarray]:
    """(axis rows, F) of the G1 lines."""
    rows, feeds = [], []
    for line in text.splitlines():
        if line.startswith("G1 "):
            words = {w[0]: float(w[1:]) for w in line.split()[1:]}
            assert set(words) == set(letters) | {"F"}, line
            rows.append([words[c] for c in letters])
            feeds.append(words["F"])
    return np.array(rows), np.array(feeds)


def test_marlin_program(plan):
    text = gcode_text(plan, replace(GENERIC, dialect="marlin"), 10.0)
    lines = text.splitlines()
    assert lines[0].startswith("; Parameters {")
    params = json.loads(lines[0].removeprefix("; Parameters "))
    assert params["mandrel"] == {"diameter": 80.0, "windLength": 300.0}
    assert params["tow"]["width"] == 10.0 and "thickness" in params["tow"]
    for line in lines:
        if line and not line.startswith(";"):
            assert line.split()[0] in MARLIN_OPCODES, line
            assert ";" not in line and line == line.strip()
    marlin, feed = moves(text, "XAB")
    generic, _ = moves(gcode_text(plan, GENERIC), "XAZB")
    # The same moves, cut at each full turn of A (one written unit short of it) for fiberpath's plot:
    # A and B in fiberpath's sense (A grows as the mandrel winds).
    cut = np.abs(np.mod(marlin[:, 1] + 0.001 + 180.0, 360.0) - 180.0) < 1e-6
    assert np.all(np.floor(marlin[1:, 1] / 360.0) - np.floor(marlin[:-1, 1] / 360.0) <= 1)
    assert np.array_equal(marlin[~cut, 0], generic[:, 0])
    assert (np.allclose(marlin[~cut, 1], -generic[:, 1], atol=0)
            and np.allclose(marlin[~cut, 2], -generic[:, 3], atol=0))
    assert np.all(np.diff(marlin[:, 1]) >= 0.0)
    assert "; fixed eye: cross-feed Z60.000 mm from the mandrel axis" in lines
    # Marlin's move time from F: |dX| / F when X moves, else the rotation over F.
    d = np.abs(np.diff(marlin, axis=0))
    dist = np.where(d[:, 0] > 0, d[:, 0], np.hypot(d[:, 1], d[:, 2]))
    t = 60.0 * dist / feed[1:]
    rates = d / t[:, None]
    assert (rates <= SPEED[[0, 1, 3]] * (1 + SLACK)).all()
    program = build_program(plan, GENERIC)
    assert np.sum(t) == pytest.approx(program.times.total_s, rel=1e-3)  # winding_time_s: acceleration included


def test_marlin_refuses_a_moving_eye():
    """On a cone the clearance envelope moves the eye radially: no cross-feed axis to do it."""
    job = parse_config({"name": "cone", "mandrel": {"axis": {"type": "line", "length": 300},
                                                    "profile": {"type": "cone", "start_radius": 40, "end_radius": 60}},
                        "winding": {"band_width": 20, "points": 20, "layers": [{"type": "helical", "angle": 30}]},
                        "machine": {"eye": {"clearance": 20}, "dialect": "marlin"}}, "cone.yaml")
    with pytest.raises(ExportError, match=r"machine.dialect: marlin has no cross-feed axis.*eye: \{radius: Z\}"):
        gcode_text(plan_job(job), job.machine)


def test_linuxcnc_program(plan):
    text = gcode_text(plan, replace(GENERIC, dialect="linuxcnc"))
    lines = text.splitlines()
    code = [ln for ln in lines if not ln.startswith(";")]
    assert code[:3] == ["%", "G21 G90 G94 G17 G40 G49 G80 G54", "G64 P0.050"]
    assert code[3].startswith("G0 ") and code[4] == "G93"
    assert code[-3:] == ["G94", "M2", "%"]
    rows, inverse = moves(text, "XAZB")
    generic, _ = moves(gcode_text(plan, GENERIC), "XAZB")
    assert np.array_equal(rows, generic[1:])  # the first move is the rapid to the start
    start = np.array([float(w[1:]) for w in code[3].split()[1:]])
    t = 60.0 / inverse
    d = np.abs(np.diff(np.vstack([start, rows]), axis=0))
    assert (d / t[:, None] <= SPEED * (1 + SLACK)).all()
    program = build_program(plan, GENERIC)
    assert np.sum(t) == pytest.approx(program.times.total_s, rel=1e-3)  # winding_time_s: acceleration included
    assert not re.search(r"F[0-9.]*e", text)


def test_generic_is_the_default(plan):
    assert gcode_text(plan, GENERIC) == gcode_text(plan, replace(GENERIC, dialect="generic"))


@pytest.mark.parametrize("dialect", ["generic", "marlin", "linuxcnc"])
def test_lines_alone_are_the_lines_with_moves(plan, dialect):
    """serialize without its moves (what gcode_text asks for) writes the same lines, and each move's
    F is the feed formatted one value at a time (text.fmt)."""
    from winder.export.dialects.text import fmt, serialize  # noqa: PLC0415
    from winder.export.gcode import dialect_for  # noqa: PLC0415

    program = build_program(plan, replace(GENERIC, dialect=dialect))
    lines, found = serialize(program, dialect_for(program, 10.0))
    alone, none = serialize(program, dialect_for(program, 10.0), moves=False)
    assert alone == lines and none == [] and len(found) > 0
    if dialect == "generic":
        generic = dialect_for(program)
        for row in range(0, len(program.feed), 7):
            assert generic.move_lines(program, row, "X1", None, (1.0,)) == [f"G1 X1 F{fmt(program.feed[row])}"]
