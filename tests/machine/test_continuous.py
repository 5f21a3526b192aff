"""Continuous programs (issue: machine programs a controller runs as written): on every straight-axis
sample the mandrel never stops or turns back while the eye moves, and the eye reverses at the ends
while the mandrel turns. The programs are the shipped references (`winder regress samples` holds them
to what `run` writes), read here by a parser of their own."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

SAMPLES = Path(__file__).resolve().parents[2] / "samples"
STRAIGHT = ["pipe", "cone", "vessel_hemi", "vessel_isotensoid", "elliptic_tube", "vessel_laminate"]
PRINTED = 1e-3  # the generic dialect's last printed place (mm, deg)
_WORD = re.compile(r"([A-Z])(-?\d+(?:\.\d+)?)")


def moves(name: str) -> np.ndarray:
    """(m, 4) X, A, Z, B of every G1 of the sample's reference program."""
    rows = []
    for line in (SAMPLES / "reference" / name / f"{name}.gcode").read_text().splitlines():
        if line.startswith("G1 "):
            words = dict(_WORD.findall(line.split(";")[0]))
            rows.append([float(words[k]) for k in "XAZB"])
    return np.array(rows)


@pytest.mark.parametrize("name", STRAIGHT)
def test_the_mandrel_never_stops_or_turns_back(name):
    v = moves(name)
    step = np.diff(v, axis=0)
    sense = np.sign(v[-1, 1] - v[0, 1])
    # Every move turns the mandrel on, in one sense (no dwell sample asks for a still mandrel).
    assert np.all(step[:, 1] * sense >= PRINTED / 2), np.flatnonzero(step[:, 1] * sense < PRINTED / 2)[:5]


@pytest.mark.parametrize("name", ["pipe", "cone", "elliptic_tube"])
def test_the_eye_reverses_while_the_mandrel_turns(name):
    """At each end of an open mandrel the carriage turns back: every reversal of X lies inside a
    stretch where A keeps moving, and the yaw passes through the hoop orientation (B = 0) there."""
    v = moves(name)
    dx = np.diff(v[:, 0])
    moving = np.flatnonzero(np.abs(dx) >= PRINTED / 2)
    flips = moving[1:][np.sign(dx[moving[1:]]) != np.sign(dx[moving[:-1]])]
    assert flips.size >= 2
    b = v[:, 3]
    for k in flips:
        window = b[max(k - 12, 0):k + 13]
        assert window.min() <= PRINTED and window.max() >= -PRINTED  # B crosses 0 nearby


@pytest.mark.parametrize("name", ["pipe", "cone", "vessel_laminate"])
def test_no_axis_over_its_speed_or_limits(name):
    """The sample's program in the linuxcnc dialect, where every move states its own time (G93
    inverse time, F = 60 / seconds), read back here: every axis within its top speed, the
    turnarounds' swings included, and every value within machine.limits."""
    from dataclasses import replace  # noqa: PLC0415

    from winder.config.job import load_config  # noqa: PLC0415
    from winder.export.gcode import gcode_text  # noqa: PLC0415
    from winder.winding.plan import plan as plan_job  # noqa: PLC0415

    job = load_config(SAMPLES / f"{name}.yaml")
    machine = replace(job.machine, dialect="linuxcnc")
    rows = []
    for line in gcode_text(plan_job(job), machine).splitlines():
        if line.startswith("G1 "):
            words = dict(_WORD.findall(line.split(";")[0]))
            rows.append([float(words[k]) for k in "XAZBF"])
    v = np.array(rows)
    seconds = 60.0 / v[1:, 4]
    dyn = machine.dynamics
    top = np.array([dyn.get(r).speed for r in ("carriage", "rotation", "cross_feed", "yaw")]) / 60.0
    speed = np.abs(np.diff(v[:, :4], axis=0)) / seconds[:, None]
    # The printed values round each move by up to one unit of the last place (and F to 3 decimals).
    slack = PRINTED / seconds[:, None] + top * 1e-3
    assert np.all(speed <= top + slack), np.unravel_index(np.argmax(speed / top), speed.shape)
    for k, role in enumerate(("carriage", "rotation", "cross_feed", "yaw")):
        span = machine.limits.get(role)
        if span is not None:
            assert span[0] - PRINTED <= v[:, k].min() and v[:, k].max() <= span[1] + PRINTED, role


def test_turnaround_joints_are_exact_on_a_cone_with_room():
    """A cone wound 50 mm short of both ends (friction turns the fiber round past the region): the
    ways in and out take the passes' own directions at the joints, so no move steps the eye at a
    standing mandrel (a 2e-6 rad mismatch printed 65 such 0.001 mm moves, F600000 in G93)."""
    from winder.config.job import load_config  # noqa: PLC0415
    from winder.export.gcode import gcode_text  # noqa: PLC0415
    from winder.winding.plan import plan as plan_job  # noqa: PLC0415

    job = load_config(Path(__file__).parent / "configs" / "cone_region_linuxcnc.yaml")
    rows = []
    for line in gcode_text(plan_job(job), job.machine).splitlines():
        if line.startswith("G1 "):
            words = dict(_WORD.findall(line.split(";")[0]))
            rows.append([float(words[k]) for k in "XAZB"])
    step = np.diff(np.array(rows), axis=0)
    assert np.all(np.abs(step[:, 1]) >= PRINTED / 2)
