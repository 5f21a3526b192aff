"""A geodesic's result: the solved path, its lengths and their error estimates, in scipy's result
vocabulary (winder.paths.geodesic computes it)."""

from __future__ import annotations

import dataclasses
import functools
from dataclasses import field
from enum import Enum

import numpy as np

from winder.geometry.measure import geodesic_curvature
from winder.geometry.surface import SweepSurface
from winder.paths.newton import Level, StopReason


class Method(Enum):
    NEWTON = "newton"
    LBFGS = "lbfgs"


@dataclasses.dataclass(frozen=True, eq=False)
class GeodesicResult:
    """A geodesic between two surface points.

    t, s, theta : (n + 2,) float: axial station (mm), internal station, unwrapped angle (rad).
    points : (n + 2, 3) float, xyz on the surface (mm).
    length : smooth-path length through the points (mm), the reported length.
    polyline_length, length_extrapolated (Richardson), error_estimate (|L_2n - L_n| / 3): mm.
    smooth_error_estimate : SMOOTH_SAFETY |length at n - length at 2n+1| + ROUNDOFF_FLOOR length (mm),
        a bound on the reported length's error (nan without the 2n + 1 solve); in tolerance mode plus
        5 LENGTH_SHARE tolerance where a solve stopped on the length's tolerance.
    spacing_deviation : max |segment / mean - 1|.  max_geodesic_curvature : 1/mm, on first use.
    refined_s, refined_theta : (n + 2,) float, Richardson-extrapolated vertices (O(h^4) from the
        geodesic instead of O(h^2)); None without the 2n + 1 solve.
    levels : every solve made, coarse-to-fine ladders and refinements, with its iteration cap.
    message : why the solve stopped (and which coarse levels stopped at their caps).
    """

    t: np.ndarray
    s: np.ndarray
    theta: np.ndarray
    points: np.ndarray
    length: float
    polyline_length: float
    length_extrapolated: float
    error_estimate: float
    smooth_error_estimate: float
    n: int
    iterations: int
    converged: bool
    reason: StopReason
    method: Method
    spacing_deviation: float
    seconds: float
    history: np.ndarray
    refined_s: np.ndarray | None = None
    refined_theta: np.ndarray | None = None
    nfev: int = 0
    levels: tuple[Level, ...] = ()
    message: str = ""
    surface: SweepSurface | None = field(default=None, repr=False)  # the mandrel, for the curvature

    @functools.cached_property
    def max_geodesic_curvature(self) -> float:
        """max |discrete geodesic curvature| over the interior vertices (1/mm). Computed on first use:
        a solve that wants the length or the path does not pay for it (a cross product per vertex,
        about 7 % of a 31-point solve); the surface's derivatives there are the solver's bit for bit
        (the evaluation is per point)."""
        inner = self.surface.evaluate(self.s[1:-1], self.theta[1:-1], order=1, with_point=False)
        kg = geodesic_curvature(self.surface, self.s, self.theta, self.points, (inner.ps, inner.pt))
        return float(np.maximum.reduce(np.abs(kg))) if kg.size else 0.0

    # scipy's result vocabulary (scipy.optimize.OptimizeResult); message is a field, above
    @property
    def success(self) -> bool:
        return self.converged

    @property
    def status(self) -> int:
        """0 converged, 1 the iteration limit was reached (scipy's codes)."""
        return 1 if self.reason is StopReason.MAX_ITER else 0

    @property
    def nit(self) -> int:
        return self.iterations
