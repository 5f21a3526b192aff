"""winder.machine.envelope past its ends: an eye on the envelope, its straight continuation past the
table included, keeps its clearance from the part, measured here by brute force (every point against
every segment of the part's meridian polyline and its two end discs), not by winder's own distance.

A grown vessel keeps the bare one's frame and its laminate stands past the polar-opening planes
(docs/math/17 17.8): the part's end is a low corner (the grown boss, at t < 0) with the pile-up's wall
rising steeply within a millimetre behind it. The cap's first table samples lie on the wall's discs, not
on the end's, and the secant through them, continued past the table, ran steeper than the end's disc and
into it: on parts/tank_20.yaml the eye came within 24.673 mm of the part at clearance 25 (layer 1,
circuit 1, pass 2, carriage X -34.071), 0.33 mm inside the envelope's promise. Robot poses around a
straight axis were measured from end discs at 0 and T, past which the pile-ups stand: a point a
millimetre inside them read 8 mm clear."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from winder.config.job import load_config
from winder.config.machine import MachineConfig
from winder.machine.as_wound import finished_part
from winder.machine.collision import tube_distance
from winder.machine.envelope import eye_envelope
from winder.machine.kinematics import make_guide
from winder.winding.plan import plan as plan_job

ROOT = Path(__file__).resolve().parents[2]
# mm: an eye on the envelope lies at least its centre's clearance less this from the part (the table's
# chords over a steep cap, held to the dilation at three points each, cut into it by up to 3 um)
GAP = 5e-3
QUERIES = 4001  # envelope points per end
PAIR_BLOCK = 1 << 21  # point-segment pairs measured at once


def brute_distance(x: np.ndarray, z: np.ndarray, t: np.ndarray, r: np.ndarray,
                   window: tuple[float, float] = (-np.inf, np.inf)) -> np.ndarray:
    """Signed distance (< 0 inside) of the meridian points (x, z) (m,) from the solid of revolution of the
    polyline (t, r) (k,), closed by its end discs: the least over every segment of the polyline that
    reaches into the window of t (all by default) and the two discs' radii ((t0, 0)-(t0, r0),
    (tk, 0)-(tk, rk)), each point-segment pair measured."""
    j = np.flatnonzero((np.maximum(t[:-1], t[1:]) >= window[0]) & (np.minimum(t[:-1], t[1:]) <= window[1]))
    a = np.column_stack([np.concatenate([t[j], [t[0], t[-1]]]), np.concatenate([r[j], [0.0, 0.0]])])
    b = np.column_stack([np.concatenate([t[j + 1], [t[0], t[-1]]]), np.concatenate([r[j + 1], [r[0], r[-1]]])])
    seg = b - a
    length2 = np.einsum("ij,ij->i", seg, seg)
    q = np.column_stack([x, z])
    best = np.full(x.size, np.inf)
    for rows in np.array_split(np.arange(x.size), max(1, x.size * a.shape[0] // PAIR_BLOCK)):
        rel = q[rows, None, :] - a[None, :, :]
        u = np.clip(np.einsum("mij,ij->mi", rel, seg) / np.where(length2 > 0.0, length2, 1.0), 0.0, 1.0)
        best[rows] = np.sqrt(np.min(np.sum((rel - u[..., None] * seg) ** 2, axis=2), axis=1))
    inside = (x >= t[0]) & (x <= t[-1]) & (z < np.interp(x, t, r))
    return np.where(inside, -best, best)


def assert_clear(env, t: np.ndarray, r: np.ndarray) -> None:
    """Envelope points (x, Z_env(x)) from a little past each end's rim (c past the part) to 2 c inside it
    lie at least c - GAP from the part (t, r). Segments lying more than 3 c from every such point in t
    are left out: their distance exceeds c."""
    c = float(env.clearance)
    lo, hi = float(env.stations[0]), float(env.stations[-1])
    for x in (np.linspace(lo - c - 1.0, lo + 2.0 * c, QUERIES), np.linspace(hi - 2.0 * c, hi + c + 1.0, QUERIES)):
        z = env.at(x)
        d = brute_distance(x, z, t, r, (x[0] - 3.0 * c, x[-1] + 3.0 * c))
        k = int(np.argmin(d))
        assert d[k] >= c - GAP, f"the envelope at X {x[k]:.3f} Z {z[k]:.3f} lies {d[k]:.4f} mm from the part"


class GrownEnd:
    """Duck-typed straight circular SweepSurface (what eye_envelope reads of one) whose radius is the
    polyline (t, r), t from t[0] < 0: a grown vessel's meridian standing past its opening planes."""

    def __init__(self, t: np.ndarray, r: np.ndarray) -> None:
        self.t, self.r = t, r
        self.t_start, self.axial_length = float(t[0]), float(t[-1])
        self.length = self.axial_length - self.t_start

    def t_of_s(self, s):
        return np.asarray(s, dtype=float) + self.t_start

    def radius(self, s, th):
        return np.interp(self.t_of_s(s), self.t, self.r) + 0.0 * np.asarray(th, dtype=float)


def grown_vessel(past: float, boss: float, tail: float, step: float, radius: float = 120.0,
                 depth: float = 70.0, cylinder: float = 300.0) -> GrownEnd:
    """A vessel's meridian grown past both opening planes by `past` (mm), as tank_20's: at each end the
    grown surface's boss corner (radius `boss`) leads a tail `tail` mm long rising 6 mm (as the square root
    of the distance: a dome square to the axis at its opening), then the pile-up's wall stands `step` mm
    higher (the bare meridian moved out by the wall, which ends short of the grown surface's end), then an
    elliptic dome of `depth` to the cylinder; the far end's boss 5 mm wider."""
    u = np.linspace(0.0, 1.0, 41)
    tail_t, tail_r = -past + tail * u, boss + 6.0 * np.sqrt(u)
    v = np.linspace(0.0, 1.0, 200)
    top = tail_r[-1] + step
    dome_t = tail_t[-1] + 1e-3 + (depth - tail_t[-1]) * (1.0 - np.cos(0.5 * np.pi * v))
    dome_r = top + (radius - top) * np.sin(0.5 * np.pi * v)
    near_t, near_r = np.concatenate([tail_t, dome_t]), np.concatenate([tail_r, dome_r])
    far_t, far_r = 2.0 * depth + cylinder - near_t[::-1], (near_r + 5.0 * (1.0 - near_r / radius))[::-1]
    return GrownEnd(np.concatenate([near_t, far_t]), np.concatenate([near_r, far_r]))


@pytest.mark.parametrize("clearance", [15.0, 25.0, 30.0])
@pytest.mark.parametrize(("past", "boss", "tail", "step"), [
    (9.4, 38.9, 0.75, 9.4),  # tank_20's first end: the grown boss 9.4 mm past the plane, the wall 0.75 mm in
    (11.5, 30.0, 0.4, 15.0),  # a shorter tail, a higher wall
    (6.0, 25.0, 1.2, 6.0),  # a longer tail, a lower wall
    (3.0, 45.0, 0.2, 3.0),  # a short step
])
def test_an_envelope_clears_a_grown_vessels_ends(past, boss, tail, step, clearance):
    surface = grown_vessel(past, boss, tail, step)
    env = eye_envelope(surface, MachineConfig(eye_clearance=clearance, eye_radius=None, eye_size=2.0))
    assert env.stations[0] == surface.t_start < 0.0
    assert_clear(env, env.stations, env.mandrel_radius)


@pytest.fixture(scope="module")
def tank_20():
    job = load_config(ROOT / "parts" / "tank_20.yaml")
    plan = plan_job(job)
    part = finished_part(plan)
    return job, plan, part, eye_envelope(plan.outer_surface, job.machine, part)


def test_tank_20s_envelope_clears_its_finished_part(tank_20):
    """The envelope is built on the part the invariants measure (the finished part's table) and keeps the
    clearance from it at both ends, where the old continuation came 0.327 mm inside it."""
    job, plan, part, env = tank_20
    t, r = part.table()
    assert np.array_equal(env.stations, t) and np.array_equal(env.mandrel_radius, r)
    assert t[0] == plan.outer_surface.t_start < -9.0  # the grown boss stands 9.4 mm past the plane
    assert_clear(env, t, r)


def test_robot_distances_see_the_pile_ups_past_the_opening_planes(tank_20):
    """machine.robot around tank_20's straight axis: points 1 mm inside and 3 mm outside the wound part
    at stations past the opening planes (t < 0, t > T) and over the domes read their brute-force distance."""
    job, plan, part, env = tank_20
    guide = make_guide(plan.outer_surface, env)
    t, r = part.table()
    T = plan.outer_surface.axial_length
    station = np.array([t[0] + 0.3, -6.0, -3.0, 1.0, 40.0, T - 2.0, T + 1.0, t[-1] - 0.3])
    for lift in (-1.0, 3.0):
        rho = np.interp(station, t, r) + lift
        points = np.column_stack([rho, np.zeros_like(rho), station])
        truth = brute_distance(station, rho, t, r)
        assert tube_distance(points, env, guide) == pytest.approx(truth, abs=1e-6)
