"""winder.machine.collision: the eye's body keeps its clearance along every move, checked on the
program parsed back from its text (cylinder: closed-form distances)."""

from __future__ import annotations

import numpy as np
import pytest

from conftest import surface_of
from plans import cylinder_plan
from winder.config.machine import MachineConfig
from winder.config.mandrel import ConstantProfile, LineAxis
from winder.errors import ExportError
from winder.export.gcode import gcode_text
from winder.machine.collision import check_collision, part_distance
from winder.machine.envelope import eye_envelope

R, T = 40.0, 300.0
CUT_TOL = 1e-6  # mm


@pytest.fixture(scope="module")
def tube():
    return surface_of(LineAxis(T), ConstantProfile(R))


def test_part_distance_closed_forms(tube):
    env = eye_envelope(tube, MachineConfig())
    rho = np.array([70.0, 10.0, 40.0, 50.0, 20.0])
    z = np.array([150.0, 310.0, -5.0, 306.0, 150.0])
    expected = np.array([30.0, 10.0, 5.0, np.hypot(10.0, 6.0), -20.0])
    assert part_distance(rho, z, env) == pytest.approx(expected, abs=1e-9)


def test_eye_body_keeps_the_clearance_along_every_move(tube):
    """An eye of 6 mm diameter at clearance 20: its centre runs at R + 23; sampled along every parsed
    move (the axes linear between lines) the body never comes nearer than 20 - chord_tolerance."""
    machine = MachineConfig(eye_clearance=20.0, eye_size=6.0, chord_tolerance=0.05)
    text = gcode_text(cylinder_plan(tube), machine)
    rows = np.array([[float(w[1:]) for w in ln.split()[1:4]] for ln in text.splitlines() if ln.startswith("G1 ")])
    assert np.allclose(rows[:, 2], R + 23.0, atol=1e-3)
    f = np.linspace(0.0, 1.0, 33)
    x = rows[:-1, None, 0] + f * np.diff(rows[:, 0])[:, None]
    rho = rows[:-1, None, 2] + f * np.diff(rows[:, 2])[:, None]
    beyond = np.maximum(np.maximum(-x, x - T), 0.0)
    dist = np.where(beyond > 0, np.hypot(beyond, np.maximum(rho - R, 0.0)), rho - R)
    assert (dist - 3.0 >= 20.0 - 0.05 - CUT_TOL).all()


def test_a_move_through_the_mandrel_is_refused(tube):
    machine = MachineConfig(eye_clearance=20.0, eye_size=4.0)
    env = eye_envelope(tube, machine)
    values = np.array([[0.0, 0.0, 62.0, 0.0], [100.0, 0.0, 62.0, 0.0], [200.0, 0.0, 45.0, 0.0]])
    with pytest.raises(ExportError, match=r"pass X: the payout eye \(size 4 mm\) comes within 3.000 mm"):
        check_collision(values, env, machine, lambda row: "pass X")
    check_collision(values[:2], env, machine, lambda row: "pass X")  # the first move keeps 20 mm


def _brute_distance(rho: np.ndarray, z: np.ndarray, t: np.ndarray, r: np.ndarray) -> np.ndarray:
    """Distance of (z, rho) from every meridian segment at once, the least kept (no search)."""
    q = np.column_stack([z, rho])[:, None, :]
    a = np.column_stack([t[:-1], r[:-1]])[None]
    seg = np.column_stack([np.diff(t), np.diff(r)])[None]
    u = np.clip(np.sum((q - a) * seg, axis=2) / np.sum(seg * seg, axis=2), 0.0, 1.0)
    return np.min(np.linalg.norm(q - a - u[..., None] * seg, axis=2), axis=1)


@pytest.mark.parametrize("profile", ["cylinder", "cone", "dome"])
def test_part_distance_is_the_least_over_all_segments(profile):
    """The slab search (and the nearest-vertex rule on a finely tabulated dome) against the distance
    from every segment of the meridian, at points outside the part within and past the ends."""
    t = np.linspace(0.0, 200.0, 801)
    r = {"cylinder": np.full_like(t, 40.0), "cone": 40.0 - 0.1 * t,
         "dome": np.sqrt(np.maximum(100.0**2 - (t - 100.0) ** 2, 0.0)) * 0.5 + 10.0}[profile]
    env = type("Env", (), {"stations": t, "mandrel_radius": r})()
    rng = np.random.default_rng(7)
    z = rng.uniform(0.0, 200.0, 4000)
    rho = np.interp(z, t, r) + rng.uniform(0.5, 30.0, z.size)
    assert part_distance(rho, z, env) == pytest.approx(_brute_distance(rho, z, t, r), abs=CUT_TOL)
