"""The smooth path between planned points never folds back where the points' spacing jumps (issue 29:
a 28 deg helix's 20 mm steps on the cylinder meeting 1.3 mm steps on the dome made the index spline
run backwards at the junction; the eye on the tangent then swung across the part in one move, 5 mm
from a CNG tank where 25 mm were due)."""

from __future__ import annotations

import numpy as np

from conftest import surface_of
from plans import make_pass
from winder.config.mandrel import ConstantProfile, LineAxis
from winder.machine.smooth import SmoothPaths
from winder.winding.results import PassKind

R = 140.0
STEPS = (20.7,) * 8 + (1.3,) * 8  # mm along the tube: the cng tank's layer 7 at its dome junction
SAMPLES = 64  # per interval


def _helix_pass(surface):
    """A helix (a geodesic on the tube: t and R theta in a fixed ratio) through unevenly spaced points,
    with its exact tangent."""
    tan_alpha = np.tan(np.radians(28.0))
    s = 10.0 + np.concatenate([[0.0], np.cumsum(STEPS)])
    theta = (s - s[0]) * tan_alpha / R
    ev = surface.evaluate(s, theta, order=1)
    d = ev.ps + ev.pt * (tan_alpha / R)
    return make_pass(surface, s, theta, d, layer=1, circuit=1, number=1, kind=PassKind.FORWARD)


def test_smooth_path_runs_on_along_unevenly_spaced_points():
    surface = surface_of(LineAxis(400.0), ConstantProfile(R))
    fp = _helix_pass(surface)
    paths = SmoothPaths(surface, [fp])
    u = np.linspace(0.0, len(fp.s) - 1.0, (len(fp.s) - 1) * SAMPLES + 1)
    s, _, p, d = paths.point(u)
    # The exact curve's station rises with u: so must the smooth path's, and its tangent runs forward.
    assert np.all(np.diff(p[:, 2]) > 0.0)
    assert np.all(np.diff(s) > 0.0)
    assert np.all(np.einsum("ij,j->i", d, fp.direction[0]) > 0.0)


ARC_TOL = 1e-9  # mm: an interval's arc length against the helix's closed form (quadrature and round-off)


def test_arc_of_turned_copies_is_the_helix_length():
    """Turned copies of a helix pass share their arc-length quadrature (SmoothPaths.arc): each copy's
    every interval is still the helix's closed-form length, delta s / cos(alpha)."""
    surface = surface_of(LineAxis(400.0), ConstantProfile(R))
    base = _helix_pass(surface)
    rng = np.random.default_rng(3)
    copies = []
    for turn in rng.uniform(0.0, 40.0, 30):
        ev = surface.evaluate(base.s, base.theta + turn, order=1)
        d = ev.ps + ev.pt * (np.tan(np.radians(28.0)) / R)
        copies.append(make_pass(surface, base.s, base.theta + turn, d, layer=1, circuit=1, number=1,
                                kind=PassKind.FORWARD))
    paths = SmoothPaths(surface, copies)
    want = np.diff(base.s) / np.cos(np.radians(28.0))
    for j in range(len(copies)):
        own = paths.offset[j] + np.arange(len(base.s))
        np.testing.assert_allclose(np.diff(paths.arc[own]), want, rtol=0.0, atol=ARC_TOL)


def test_a_piece_keeps_moving_between_points_spaced_unevenly():
    """Points 31 mm apart meeting points 0.45 mm apart: the short pieces' end slopes are held to
    SLOPE_LIMIT chords, where the cubic's speed stays at half the chord's at least (at three chords it
    vanished halfway and the fiber's direction there was round-off)."""
    import numpy as np  # noqa: PLC0415

    from winder.machine.smooth import SLOPE_LIMIT  # noqa: PLC0415

    h = np.linspace(0.0, 1.0, 101)
    speed = 6 * h * (1 - h) + SLOPE_LIMIT * (1 - 4 * h + 3 * h * h) + SLOPE_LIMIT * (3 * h * h - 2 * h)
    assert speed.min() >= 0.5 - 1e-12  # the Hermite's derivative over a unit chord, both ends at the limit
