"""winder.machine.dilation: the eye envelope keeps its clearance from the part between its samples,
measured by the collision check's own distance (winder.machine.collision.part_distance, the meridian
polyline and its end discs), and the polyline's dilation against a brute-force one."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from winder.config.job import load_config
from winder.geometry.build import build_surface
from winder.machine.collision import part_distance
from winder.machine.dilation import polyline_dilation
from winder.machine.envelope import eye_envelope

ROOT = Path(__file__).resolve().parents[2]
ENVELOPE_GAP = 1e-3  # mm: an eye on the envelope lies at least clearance - this from the part (was 5e-2)
BRUTE_TOL = 1e-6  # mm: the exact dilation against discs around 20,000 points per segment-run


@pytest.mark.parametrize("config", ["configs/isotensoid.yaml", "configs/ellipsoid_vessel.yaml",
                                    "configs/vessel_friction.yaml"])
def test_envelope_keeps_the_clearance_between_its_samples(config: str) -> None:
    job = load_config(ROOT / config)
    env = eye_envelope(build_surface(job.mandrel), job.machine)
    x = env.stations if env.radius_stations is None else env.radius_stations
    xs = np.linspace(x[0], x[-1], 100_001)
    assert part_distance(env.at(xs), xs, env).min() >= env.clearance - ENVELOPE_GAP


def test_polyline_dilation_against_points() -> None:
    """A steep profile (a boss's rim): the dilation of the polyline equals that of many points along it."""
    t = np.array([0.0, 0.25, 0.5, 5.0, 10.0])
    r = np.array([30.0, 45.0, 52.0, 55.0, 55.0])
    c = 20.0
    xq = np.linspace(-19.0, 29.0, 97)
    dense = np.concatenate([np.linspace(0.0, 1.0, 20_000, endpoint=False) * (t[k + 1] - t[k]) + t[k]
                            for k in range(t.size - 1)] + [t[-1:]])
    rd = np.interp(dense, t, r)
    dx = xq[:, None] - dense[None, :]
    brute = np.where(np.abs(dx) <= c, rd + np.sqrt(np.maximum(c * c - dx * dx, 0.0)), -np.inf).max(axis=1)
    exact = polyline_dilation(xq, t, r, c)
    assert np.all(exact >= brute - BRUTE_TOL)
    assert np.max(exact - brute) < 1e-3  # the points are 12 um apart at most: their discs fall short by < 1 nm
