"""winder.geometry.spline_fold: the chord-length cubic solved with numpy against scipy's CubicSpline
(a separate solver of the same interpolation), and a folded spline refused by `check` at once."""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import pytest

from winder.geometry.spline_fold import chord_cubic_moments, spline_bends

MOMENT_TOL = 1e-9  # relative: the second derivatives from two linear solvers
KAPPA_TOL = 1e-4  # relative: peak curvature from 256 samples per piece against 200,001 samples
LENGTH_TOL = 1e-7  # relative: Gauss-Legendre arc length against a fine trapezoid sum
CHECK_SECONDS = 1.0  # the issue: a folded mandrel is refused in under a second
ROOT = Path(__file__).resolve().parents[2]

CASES = [
    [[0, 0, 0], [0, 0, 300], [10, 10, 310], [20, 0, 320], [20, 0, 600]],
    [[0, 0, 0], [0, 0, 150], [40, 10, 300], [120, 30, 420]],
    [[0, 0, 0], [0, 0, 100], [30, 0, 150]],
]


@pytest.mark.parametrize("points", CASES)
def test_against_scipy_cubic(points: list) -> None:
    from scipy.interpolate import CubicSpline

    pts = np.asarray(points, dtype=float)
    u, m = chord_cubic_moments(pts)
    c = CubicSpline(u, pts, axis=0, bc_type="not-a-knot" if len(pts) > 3 else "natural")
    scale = np.abs(m).max()
    assert np.abs(c(u, 2) - m).max() <= MOMENT_TOL * scale
    uu = np.linspace(0.0, u[-1], 200_001)
    d1, d2 = c(uu, 1), c(uu, 2)
    sp = np.linalg.norm(d1, axis=1)
    kappa = np.linalg.norm(np.cross(d1, d2), axis=1) / sp**3
    length = float(np.sum(0.5 * (sp[1:] + sp[:-1]) * np.diff(uu)))
    bend = spline_bends(pts)
    assert bend.kappa.max() == pytest.approx(kappa.max(), rel=KAPPA_TOL)
    assert bend.length == pytest.approx(length, rel=LENGTH_TOL)


def test_folded_spline_refused_fast() -> None:
    """The issue's folded duct: a bend of radius ~9.4 mm under a 50 mm tube, refused in under a second
    (validation itself: the interpreter's imports are the same for every check)."""
    from winder.app.validate import validate
    from winder.errors import ConfigError

    path = ROOT / "tests" / "config" / "invalid" / "spline_axis_folded.yaml"
    start = time.perf_counter()
    with pytest.raises(ConfigError, match=r"mandrel\.axis\.points\[2\]: the axis bends with radius 9\.44"):
        validate(path)
    assert time.perf_counter() - start < CHECK_SECONDS
