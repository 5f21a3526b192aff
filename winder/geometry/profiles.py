"""Radius along the axis: the profile r(s) of a mandrel, with its axial station z(s).

Every profile is parametrized by an internal station s in [0, length]. For tubes and cones s is
the axial arc length t itself (z(s) = s). For vessels s is the meridian arc length, so nothing is
singular on the domes down to the polar opening; the user-facing station t = z(s) stays axial.
"""

from __future__ import annotations

import dataclasses
import functools
from typing import TYPE_CHECKING, NamedTuple, Protocol

import numpy as np

if TYPE_CHECKING:
    from scipy.interpolate import CubicSpline

from winder.errors import ConfigError


class ProfileEval(NamedTuple):
    """A profile evaluated at stations s, each array (m,) float.

    z, z1, z2 : axial station t = z(s) and its first two derivatives in s.
    r, r1, r2 : radius r(s) and its first two derivatives in s.
    """

    z: np.ndarray
    z1: np.ndarray
    z2: np.ndarray
    r: np.ndarray
    r1: np.ndarray
    r2: np.ndarray


class Profile(Protocol):
    """What the surface needs of a profile."""

    length: float  # internal station range: s in [0, length]
    axial_length: float  # T, the axial length covered
    reference_radius: float  # profile(0) (docs/math/01-surface.md 1.5), scales a non-circular section

    def evaluate(self, s: np.ndarray) -> ProfileEval: ...

    def s_of_t(self, t: np.ndarray) -> np.ndarray: ...


def _axial(s: np.ndarray, r: np.ndarray, r1: np.ndarray, r2: np.ndarray) -> ProfileEval:
    return ProfileEval(s, np.ones_like(s), np.zeros_like(s), r, r1, r2)


@dataclasses.dataclass(frozen=True)
class AxialProfile:
    """A profile over the axial station itself (z(s) = s): constant, cone and table profiles.

    r(t) is a cubic polynomial piece list (a scipy CubicSpline, C2; one Cubic piece for a straight
    profile), so all three share one path.
    """

    spline: Cubic | CubicSpline
    length: float
    reference_radius: float

    @property
    def axial_length(self) -> float:
        return self.length

    @functools.cached_property
    def constant_radius(self) -> float | None:
        """r where the profile is one constant piece (a straight tube), else None: an evaluator can
        then skip the profile, whose derivatives are all 0."""
        if self.spline.c.shape[1] != 1:
            return None
        c3, c2, c1, c0 = (float(v) for v in self.spline.c[:, 0])
        return c0 if c3 == c2 == c1 == 0.0 else None

    def evaluate(self, s: np.ndarray) -> ProfileEval:
        s = np.asarray(s, dtype=float)
        if self.spline.c.shape[1] == 1:
            # One cubic piece (constant and cone profiles): Horner directly, no spline call overhead.
            c3, c2, c1, c0 = self.spline.c[:, 0]
            x = s - self.spline.x[0]
            return _axial(s, ((c3 * x + c2) * x + c1) * x + c0, (3.0 * c3 * x + 2.0 * c2) * x + c1,
                          6.0 * c3 * x + 2.0 * c2)
        return _axial(s, self.spline(s), self.spline(s, 1), self.spline(s, 2))

    def s_of_t(self, t: np.ndarray) -> np.ndarray:
        return np.asarray(t, dtype=float)

    def t_of_s(self, s: np.ndarray) -> np.ndarray:
        return np.asarray(s, dtype=float)


@dataclasses.dataclass(frozen=True, eq=False)
class Cubic:
    """One cubic piece over [x[0], x[1]] in CubicSpline's layout (c (4, 1), highest power first; x (2,)),
    callable like it (extrapolating): a straight profile needs no scipy, which is slow to import."""

    c: np.ndarray
    x: np.ndarray

    def __call__(self, t: np.ndarray, nu: int = 0) -> np.ndarray:
        c3, c2, c1, c0 = self.c[:, 0]
        u = np.asarray(t, dtype=float) - self.x[0]
        if nu == 0:
            return ((c3 * u + c2) * u + c1) * u + c0
        return (3.0 * c3 * u + 2.0 * c2) * u + c1 if nu == 1 else 6.0 * c3 * u + 2.0 * c2


def linear(length: float, r0: float, r1: float) -> Cubic:
    # A straight piece as a degenerate cubic: exact, and shares the evaluation path.
    return Cubic(np.array([[0.0], [0.0], [(r1 - r0) / length], [r0]]), np.array([0.0, length]))


def table_profile(points: np.ndarray, axial_length: float | None, source: str,
                  key: str = "mandrel.profile.points") -> AxialProfile:
    """r(t) through the (t, r) points (k, 2), C2 (a straight piece for two points); refused where the
    smooth interpolation dips to r <= 0, which only the built curve shows."""
    pts = np.asarray(points, dtype=float)
    length = float(pts[-1, 0]) if axial_length is None else axial_length
    if pts.shape[0] == 2:
        spline = linear(float(pts[1, 0]), float(pts[0, 1]), float(pts[1, 1]))
    else:
        from scipy.interpolate import CubicSpline  # noqa: PLC0415 - slow to import: only for tables

        spline = CubicSpline(pts[:, 0], pts[:, 1], bc_type="not-a-knot")
    grid = np.linspace(0.0, length, 4001)
    rmin = float(np.min(spline(grid)))
    if not rmin > 0.0:
        bad = float(grid[np.argmin(spline(grid))])
        raise ConfigError(f"{source}: {key}: the smooth interpolation through the "
                          f"points dips to radius {rmin:.4g} at t = {bad:.4g}; radius must be > 0 "
                          f"everywhere (add points or soften the steps)")
    return AxialProfile(spline, length, float(pts[0, 1]))
