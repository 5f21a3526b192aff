"""Cross-section shapes as polar radius functions rho(theta), with two derivatives.

Every section is star-shaped around the axis (docs/math/01-surface.md 1.5), so each theta names one point:
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

    def joints(self) -> np.ndarray:
        """(k,) polar angles in [0, 2 pi) where the section's curvature jumps (a flat meeting a
        corner); empty for a smooth section."""
        ...


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

    def joints(self) -> np.ndarray:
        return np.empty(0)


@dataclasses.dataclass(frozen=True, eq=False)
class ArcMap:
    """Arc-length position along a section: fraction f in [0, 1) of the perimeter from theta = 0.

    The section is scaled uniformly by the profile, so the fraction of a polar angle does not depend
    on the station. Both directions are unwrapped: theta + 2 pi <-> f + 1.
    theta_grid, frac_grid, rate_grid : (k,) float, the monotone table over one turn (the section's
    joints among its nodes) and d f / d theta there, between the nodes a cubic Hermite.
    section, length : the section and its perimeter as the table sums it, for d theta / d f at any
    theta from the section itself (None on a circle).
    """

    theta_grid: np.ndarray
    frac_grid: np.ndarray
    identity: bool
    rate_grid: np.ndarray | None = None
    section: Section | None = None
    length: float = 1.0

    def dtheta_dfrac(self, theta: np.ndarray) -> np.ndarray:
        """d theta / d fraction at theta: 2 pi on a circle, else length / |d point / d theta|.

        From the section, not from the table: the rate's own derivative jumps where a flat meets a
        corner, and a linear table of the rate was 1.5e-3 of itself off next to such a joint (200 x
        100, corners 10): the planned direction 0.03 deg off, an eye 440 mm out along a 30 deg fiber
        0.26 mm off its tangent line."""
        theta = np.asarray(theta, dtype=float)
        if self.identity:
            return np.full_like(theta, 2.0 * np.pi)
        rho, d1, _ = self.section.polar_cs(np.cos(theta), np.sin(theta), order=1)
        return self.length / np.hypot(rho, d1)

    def fraction(self, theta: np.ndarray) -> np.ndarray:
        """The fraction at theta, a cubic Hermite of the table's values and rates: linear
        interpolation was 1.3e-4 mm of arc off on a corner of radius 10 seen from 100 mm, where
        d f / d theta changes by 2 % a cell, and a pass's spline through such fractions was tilted
        0.04 mm at the eye (the cubic: below 1e-9 mm)."""
        theta = np.asarray(theta, dtype=float)
        if self.identity:
            return theta / (2.0 * np.pi)
        turns = np.floor(theta / (2.0 * np.pi))
        x, g = theta - 2.0 * np.pi * turns, self.theta_grid
        k = np.clip(np.searchsorted(g, x, side="right") - 1, 0, g.size - 2)
        h = g[k + 1] - g[k]
        v = (x - g[k]) / h
        v2, v3 = v * v, v * v * v
        f0, f1, r0, r1 = self.frac_grid[k], self.frac_grid[k + 1], self.rate_grid[k], self.rate_grid[k + 1]
        return turns + ((2 * v3 - 3 * v2 + 1) * f0 + (v3 - 2 * v2 + v) * h * r0 + (3 * v2 - 2 * v3) * f1
                        + (v3 - v2) * h * r1)

    def theta(self, frac: np.ndarray) -> np.ndarray:
        """The polar angle at a fraction: the linear table's, then one Newton step on fraction (its
        error squared: the linear one's 1e-6 rad becomes 1e-12)."""
        frac = np.asarray(frac, dtype=float)
        if self.identity:
            return 2.0 * np.pi * frac
        turns = np.floor(frac)
        th = 2.0 * np.pi * turns + np.interp(frac - turns, self.frac_grid, self.theta_grid)
        return th - (self.fraction(th) - frac) * self.dtheta_dfrac(th)


ARC_MAP_SAMPLES = 20000  # cells over a turn; the cubic's error ~ (2 pi / samples)^4


def arc_grid(section: Section) -> np.ndarray:
    """(k,) polar angles 0 .. 2 pi, about ARC_MAP_SAMPLES cells, every joint of the section a node: a
    cell across a joint interpolates over the jump of the curvature (d f / d theta has a corner)."""
    turn = 2.0 * np.pi
    knots = np.unique(np.concatenate([[0.0], np.mod(section.joints(), turn), [turn]]))
    cells = np.maximum(1, np.rint(ARC_MAP_SAMPLES * np.diff(knots) / turn)).astype(int)
    spans = [np.linspace(a, b, n + 1)[:-1] for a, b, n in zip(knots[:-1], knots[1:], cells)]
    return np.concatenate(spans + [[turn]])


@functools.lru_cache(maxsize=16)
def arc_map(section: Section) -> ArcMap:
    """The arc-length map of a section (exact identity for circles), built once per section (sections
    are frozen, hashable values): the plan, its budget, every pass's splines and the report share it."""
    if section.is_circle:
        return ArcMap(np.array([0.0, 2.0 * np.pi]), np.array([0.0, 1.0]), True)
    th = arc_grid(section)
    rho, d1, _ = section.polar(th)
    speed = np.hypot(rho, d1)
    rho, d1, _ = section.polar(0.5 * (th[1:] + th[:-1]))
    # Simpson per cell (its midpoint inside the cell, never on a joint): O(h^5) a cell.
    cells = (speed[1:] + 4.0 * np.hypot(rho, d1) + speed[:-1]) * np.diff(th) / 6.0
    cum = np.concatenate([[0.0], np.cumsum(cells)])
    return ArcMap(th, cum / cum[-1], False, speed / cum[-1], section, float(cum[-1]))


def polar_arcs(section: Section) -> ArcMap | None:
    """The arc map that a path's splines run against on a non-circular section (arc_map's), or None
    on a circle, where theta is already proportional to arc length. A straight tube of any section unrolls flat, so a geodesic
    is a straight line in (station, perimeter fraction), which a spline carries; against theta it
    bends where a flat meets a corner, and a spline there misses the tangent by up to 0.2 deg
    (docs/math/12 12.2)."""
    return None if section.is_circle else arc_map(section)
