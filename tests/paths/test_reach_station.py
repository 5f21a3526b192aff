"""winder.paths.ode.reach_station: k geodesics integrated together reach a station where each one
integrated alone does (its own step sequence), and on a cylinder where the helix's closed form puts it."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from winder.config.job import load_config
from winder.geometry.build import build_surface
from winder.paths.ode import reach_station

ROOT = Path(__file__).resolve().parents[2]
THETA_TOL = 1e-7  # rad: an integration at rtol 1e-10 on a spline axis against one at 1e-12
HELIX_TOL = 2e-8  # rad: the cylinder's closed form (1 um at R 50 after 450 mm of path)
REACH_TOL = 1e-6  # mm: the terminal event stops within round-off of the station (to ~1e-12 relative)


def test_fan_on_a_spline_axis_matches_each_ray_alone() -> None:
    """Integrated together the rays share one step sequence (the hardest ray's); alone each has its own,
    here a hundred times finer: two integrations at the same rtol differ by both their errors (1.2e-7
    rad measured, from step sequences that turn on the last bit of the curve's evaluation)."""
    surface = build_surface(load_config(ROOT / "configs" / "spline_tube.yaml").mandrel)
    starts = np.array([0.0, math.pi])
    target = 0.25 * surface.length
    th, _ = reach_station(surface, 0.0, starts, 50.0, target, 4.0 * surface.length, rtol=1e-10, atol=1e-10)
    alone = [reach_station(surface, 0.0, np.array([th0]), 50.0, target, 4.0 * surface.length, rtol=1e-12,
                           atol=1e-12)[0][0] for th0 in starts]
    assert np.max(np.abs(th - alone)) < THETA_TOL


def test_cylinder_helix_closed_form_and_a_ray_that_turns_back() -> None:
    surface = build_surface(load_config(ROOT / "configs" / "pipe.yaml").mandrel)
    r = float(surface.radius(np.array([0.0]), np.array([0.0]))[0])
    starts = np.array([0.0, 1.0, 2.0])
    th, far = reach_station(surface, 30.0, starts, 55.0, 400.0, 2000.0)
    assert th == pytest.approx(starts + math.tan(math.radians(55.0)) * 370.0 / r, abs=HELIX_TOL)
    assert np.all(far >= 400.0 - REACH_TOL)
