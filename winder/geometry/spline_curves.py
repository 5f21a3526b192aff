"""The C2 spline guide curve by arc length (see winder.geometry.curves for the conventions)."""

from __future__ import annotations

import dataclasses
import functools

import numpy as np

from winder.errors import ConfigError
from winder.geometry.curves import X_AXIS, Y_AXIS, CurveEval
from winder.geometry.frames import double_reflection, orthonormalize
from winder.geometry.interp import jet, piecewise

__all__ = ["SPLINE_GRID", "SplineCurve", "spline_curve"]


@dataclasses.dataclass(frozen=True)
class SplineCurve:
    """A C2 interpolating curve through points, re-parametrized by arc length.

    The interpolant c(u) (cubic, chord-length u) is sampled finely at equal arc length and fitted by
    a quintic spline in arc length, so x, x', x'', x''' are smooth and |x'| = 1 to ~1e-10. The RMF is
    computed on the same grid by double reflection and interpolated (then re-orthonormalized).

    Both splines are read as one table (interp.jet) of 15 columns, x, x', x'', x''' and e2: the
    planner evaluates the curve a few hundred stations at a time inside its solvers, where one call
    instead of five is 3x faster (s_duct: 1.5 s of a 3.9 s plan were the five B-spline calls).
    """

    xs: object  # BSpline of x(z), k = 5
    e2s: object  # BSpline of the RMF normal e2(z), k = 5
    length: float
    kappa_max: float
    is_straight: bool = False
    stall_t: float | None = None  # where the interpolant c(u) nearly stops (a cusp), if it does

    def __getstate__(self) -> dict:
        # The table is rebuilt where it is read: pickled with it a curve is 3.2 MB, not 263 kB.
        return {k: v for k, v in self.__dict__.items() if k != "_jet"}

    @functools.cached_property
    def _jet(self):
        return jet([(piecewise(self.xs), 3), (piecewise(self.e2s), 0)])

    def evaluate(self, z: np.ndarray) -> CurveEval:
        values = self._jet(np.asarray(z, dtype=float).ravel())  # (m, 15)
        x, d1, d2, d3, e2 = (values[:, i:i + 3] for i in range(0, 15, 3))
        e2, e3 = orthonormalize(e2, d1 / np.linalg.norm(d1, axis=1)[:, None])
        return CurveEval(x, d1, d2, d3, e2, e3)

    def centerline(self, z: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """x, x' and x'' at stations z (m,): evaluate's first three fields (each (m, 3), views of one
        new array) without the frame, for closest-point searches that do not need it."""
        values = self._jet(np.asarray(z, dtype=float).ravel())
        return values[:, 0:3], values[:, 3:6], values[:, 6:9]

    def max_curvature(self) -> float:
        return self.kappa_max


SPLINE_GRID = 4097  # samples of the arc-length fit; the fit error is far below solver tolerances
# Least speed |c'(u)| of the chord-length interpolant, relative to its mean: well-spaced points keep it
# near 1 (0.9 through a right-angle zigzag); it reaches 0 where the curve stops and turns back (a cusp),
# as when a point lies 1e-6 mm beside one 100 mm away and the spline swings to and fro between them.
STALL_SPEED = 0.01


def spline_curve(points: np.ndarray, source: str, key: str = "mandrel.axis.points") -> SplineCurve:
    """The C2 arc-length spline through points (k, 3); `source: key` prefixes its refusal."""
    from scipy.interpolate import CubicSpline, make_interp_spline  # noqa: PLC0415 - slow to import

    pts = np.asarray(points, dtype=float)
    pts = pts - pts[0]
    chord = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    u = np.concatenate([[0.0], np.cumsum(chord)])
    bc = "not-a-knot" if len(pts) > 3 else "natural"
    c = CubicSpline(u, pts, axis=0, bc_type=bc)
    # Arc length of c by Gauss-Legendre on a fine sub-grid of u.
    fine = np.linspace(0.0, u[-1], 8 * SPLINE_GRID + 1)
    gx, gw = np.polynomial.legendre.leggauss(6)
    a, b = fine[:-1], fine[1:]
    nodes = 0.5 * (a + b)[:, None] + 0.5 * (b - a)[:, None] * gx
    speed = np.linalg.norm(c(nodes.ravel(), 1), axis=1).reshape(nodes.shape)
    seg = 0.5 * (b - a) * (speed @ gw)
    ell = np.concatenate([[0.0], np.cumsum(seg)])
    length = float(ell[-1])
    slowest = int(np.argmin(speed))
    stall_t = None
    if speed.flat[slowest] < STALL_SPEED * length / u[-1]:
        stall_t = float(np.interp(nodes.flat[slowest], fine, ell))
    zgrid = np.linspace(0.0, length, SPLINE_GRID)
    ugrid = np.interp(zgrid, ell, fine)
    for _ in range(3):  # Newton on ell(u) = z, ell by Gauss-Legendre from the grid node below u
        k = np.clip(np.searchsorted(fine, ugrid, side="right") - 1, 0, fine.size - 2)
        half = 0.5 * (ugrid - fine[k])
        nodes = (fine[k] + half)[:, None] + half[:, None] * gx
        sp = np.linalg.norm(c(nodes.ravel(), 1), axis=1).reshape(nodes.shape)
        cur = ell[k] + half * (sp @ gw)
        ugrid = ugrid - (cur - zgrid) / np.linalg.norm(c(ugrid, 1), axis=1)
    xs = make_interp_spline(zgrid, c(ugrid), k=5, axis=0)
    tangent = xs(zgrid, 1)
    tangent /= np.linalg.norm(tangent, axis=1)[:, None]
    t0 = tangent[0]
    ref = X_AXIS if abs(t0 @ X_AXIS) < 1.0 - 1e-9 else Y_AXIS
    e2_0 = ref - (ref @ t0) * t0
    e2_0 /= np.linalg.norm(e2_0)
    e2 = double_reflection(xs(zgrid), tangent, e2_0)
    kappa = np.linalg.norm(xs(zgrid, 2), axis=1)
    if not np.all(np.isfinite(kappa)):
        raise ConfigError(f"{source}: {key}: the spline through the points is not finite")
    return SplineCurve(xs, make_interp_spline(zgrid, e2, k=5, axis=0), length, float(kappa.max()),
                       stall_t=stall_t)
