"""Cross-section shapes as polar radius functions rho(theta), with two derivatives.

Every section is star-shaped around the axis (SPEC.md), so each theta names one point:
the section point is rho(theta) (cos theta, sin theta) in the (e2, e3) plane. The circle is here; the
other sections are in winder.geometry.outlines.
"""

from __future__ import annotations

import dataclasses
import functools
from typing import Protocol

import numpy as np



class Section(Protocol):
    is_circle: bool

    def polar(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """rho, rho', rho'' at theta (radians), each (m,) float."""
        ...

    def polar_cs(self, c: np.ndarray, s: np.ndarray, order: int = 2) -> tuple:
        """polar from cos(theta) and sin(theta) (m,), which the surface has already; the derivatives
        beyond `order` are None."""
        ...

    def perimeter(self) -> float: ...


def perimeter_of(section: Section, samples: int = 20000) -> float:
    """The perimeter of a smooth section, for those without a closed form."""
    th = np.linspace(0.0, 2.0 * np.pi, samples + 1)[:-1] + np.pi / samples
    rho, d1, _ = section.polar(th)
    # Midpoint rule on a periodic integrand converges spectrally for smooth sections.
    return float(np.sum(np.hypot(rho, d1)) * 2.0 * np.pi / samples)


@dataclasses.dataclass(frozen=True)
class Circle:
    radius: float = 1.0
    is_circle: bool = True

    def polar(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        theta = np.asarray(theta, dtype=float)
        return self.polar_cs(theta, theta)

    def polar_cs(self, c: np.ndarray, s: np.ndarray, order: int = 2):
        return (np.full_like(c, self.radius), np.zeros_like(c) if order >= 1 else None,
                np.zeros_like(c) if order >= 2 else None)

    def perimeter(self) -> float:
        return 2.0 * np.pi * self.radius


@dataclasses.dataclass(frozen=True, eq=False)
class ArcMap:
    """Arc-length position along a section: fraction f in [0, 1) of the perimeter from theta = 0.

    The section is scaled uniformly by the profile, so the fraction of a polar angle does not depend
    on the station. Both directions are unwrapped: theta + 2 pi <-> f + 1.
    theta_grid, frac_grid : (k,) float, the monotone table over one turn.
    """

    theta_grid: np.ndarray
    frac_grid: np.ndarray
    identity: bool
    rate_grid: np.ndarray | None = None  # (k,) float, dfrac/dtheta on theta_grid

    def dtheta_dfrac(self, theta: np.ndarray) -> np.ndarray:
        """d theta / d fraction at theta: 2 pi on a circle."""
        theta = np.asarray(theta, dtype=float)
        if self.identity:
            return np.full_like(theta, 2.0 * np.pi)
        return 1.0 / np.interp(np.mod(theta, 2.0 * np.pi), self.theta_grid, self.rate_grid)

    def fraction(self, theta: np.ndarray) -> np.ndarray:
        theta = np.asarray(theta, dtype=float)
        if self.identity:
            return theta / (2.0 * np.pi)
        turns = np.floor(theta / (2.0 * np.pi))
        return turns + np.interp(theta - 2.0 * np.pi * turns, self.theta_grid, self.frac_grid)

    def theta(self, frac: np.ndarray) -> np.ndarray:
        frac = np.asarray(frac, dtype=float)
        if self.identity:
            return 2.0 * np.pi * frac
        turns = np.floor(frac)
        return 2.0 * np.pi * turns + np.interp(frac - turns, self.frac_grid, self.theta_grid)


ARC_MAP_SAMPLES = 20000  # linear interpolation error ~ (2 pi / samples)^2: 1e-7 of the perimeter


def arc_map(section: Section) -> ArcMap:
    """The arc-length map of a section (exact identity for circles)."""
    if section.is_circle:
        return ArcMap(np.array([0.0, 2.0 * np.pi]), np.array([0.0, 1.0]), True)
    th = np.linspace(0.0, 2.0 * np.pi, ARC_MAP_SAMPLES + 1)
    rho, d1, _ = section.polar(th)
    speed = np.hypot(rho, d1)
    cum = np.concatenate([[0.0], np.cumsum(0.5 * (speed[1:] + speed[:-1]) * np.diff(th))])
    return ArcMap(th, cum / cum[-1], False, speed / cum[-1])


@functools.lru_cache(maxsize=16)
def polar_arcs(section: Section) -> ArcMap | None:
    """The arc map that a path's splines run against on a non-circular section, built once per
    section (every pass asks; sections are frozen, hashable values), or None on a circle, where theta
    is already proportional to arc length. A straight tube of any section unrolls flat, so a geodesic
    is a straight line in (station, perimeter fraction), which a spline carries; against theta it
    bends where a flat meets a corner, and a spline there misses the tangent by up to 0.2 deg
    (docs/math/12 12.4)."""
    return None if section.is_circle else arc_map(section)
