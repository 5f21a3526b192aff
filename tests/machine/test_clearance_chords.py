"""The program keeps the eye's clearance along every straight move as written (issue 29, "limits by
construction"; docs/math/13-clearance-chords.md). A small ellipsoid-dome tank whose eye sweeps the
cylinder-to-dome junction of its envelope within one planned interval: its program is written, read
back, and every move between two consecutive rows sampled densely; each sample's distance from the
finished part is computed here on its own: the meridian (axial station, radius) of the part's outer
surface sampled finely, with the end discs over the polar openings, and the nearest sample found by a
k-d tree (not winder.machine.collision's segment search)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.spatial import cKDTree

from winder.config.job import load_config
from winder.readback.gcode import parse_program
from winder.export.gcode import program_text
from winder.machine.chords import move_cuts
from winder.machine.envelope import eye_envelope
from winder.machine.program import build_program
from winder.winding.plan import plan

HERE = Path(__file__).resolve().parent
MOVE_SAMPLES = 64  # points per written move, ends included
MERIDIAN_SAMPLES = 20_001  # along the part's meridian: 26 um apart at most on this tank
# The nearest meridian sample overstates the distance to the curve between samples by at most
# spacing^2 / (8 distance) (< 4e-6 mm at the 25 mm clearance, far inside SAMPLING_TOL; 200,001
# samples cost a minute of k-d tree search, every sample of a dome lying nearly as far from the eye),
# and a move's worst point lies within half a sample spacing of a sample (a slope of 1 at most:
# 1.5 mm / 64 / 2 of distance).
SAMPLING_TOL = 1e-3
CUT_TOL = 1e-6  # mm: a sampled cut against the closed form, where the worst point is a sample (an end)


def _meridian(surface) -> np.ndarray:
    """(k, 2) (axial station, radius) of the part's meridian and its end discs down to the axis."""
    s = np.linspace(0.0, surface.length, MERIDIAN_SAMPLES)
    p = surface.points(s, np.zeros_like(s))
    t, r = p[:, 2], np.hypot(p[:, 0], p[:, 1])
    step = float(np.median(np.hypot(np.diff(t), np.diff(r))))
    discs = [np.column_stack([np.full(int(r[i] / step) + 1, t[i]), np.linspace(0.0, r[i], int(r[i] / step) + 1)])
             for i in (0, -1)]
    return np.vstack([np.column_stack([t, r]), *discs])


@pytest.fixture(scope="module")
def junction():
    """The tank's job and plan, planned once for this file's tests."""
    job = load_config(HERE / "configs/ellipsoid_junction.yaml")
    return job, plan(job)


def test_every_written_move_keeps_the_clearance(junction):
    job, pl = junction
    machine = job.machine
    prog = build_program(pl, machine)
    read = parse_program(program_text(prog), machine)
    x, z = read.values[:, 0], read.values[:, 2]  # carriage and cross-feed as written: the eye's (t, rho)
    f = np.linspace(0.0, 1.0, MOVE_SAMPLES)
    xs = (x[:-1, None] + f * (x[1:] - x[:-1])[:, None]).ravel()
    zs = (z[:-1, None] + f * (z[1:] - z[:-1])[:, None]).ravel()
    dist, _ = cKDTree(_meridian(pl.outer_surface)).query(np.column_stack([xs, np.abs(zs)]))
    need = machine.eye_clearance - machine.chord_tolerance  # the eye's body (size 0 here)
    assert machine.eye_size == 0.0
    worst = dist.reshape(-1, MOVE_SAMPLES).min(axis=1)
    assert worst.min() >= need - SAMPLING_TOL, (worst.min(), int(np.argmin(worst)))
    # The junction is where it was tight: some move there comes within a tolerance of the clearance.
    assert worst.min() < machine.eye_clearance


def test_a_move_across_a_bend_cuts_its_sagitta(junction):
    """move_cuts against the cylinder's closed form: a chord between two eye points on the envelope's
    level part cuts nothing; a chord from the envelope to a point 1 mm below it at the same carriage
    cuts the clearance less that point's height over the part's radius there."""
    job, pl = junction
    env = eye_envelope(pl.outer_surface, job.machine)
    mid = 0.5 * (env.stations[0] + env.stations[-1])
    level = float(env.at(np.array([mid]))[0])
    x = np.array([mid - 5.0, mid + 5.0, mid + 5.0])
    z = np.array([level, level, level - 1.0])
    cuts = move_cuts(x, z, np.array([3]), env)
    assert cuts[0] == 0.0
    surface = pl.outer_surface
    s = np.linspace(0.0, surface.length, MERIDIAN_SAMPLES)
    p = surface.points(s, np.zeros_like(s))
    radius = float(np.interp(x[2], p[:, 2], np.hypot(p[:, 0], p[:, 1])))  # the cylinder's, at that station
    assert abs(cuts[1] - (env.clearance - (z[2] - radius))) < CUT_TOL
    assert cuts[1] > 0.9
