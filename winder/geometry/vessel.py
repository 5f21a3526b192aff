"""A pressure vessel's meridian: a dome, a cylinder, an end dome.

Vessel: VesselMeridian implements the Profile protocol of winder.geometry.profiles. Its internal station s is
the meridian arc length from the first polar opening: the first dome reversed, then the cylinder, then
the end dome. The axial station t = z(s) is 0 in the plane of the first dome's polar opening
(docs/guide/conventions.md), so T = depth(dome) + cylinder_length + depth(end_dome). A grown vessel keeps the bare one's
frame (its equators at the same t): where the laminate rises past the first boss's plane, its near end
is at t = origin < 0.
"""

from __future__ import annotations

import dataclasses
from typing import NamedTuple

import numpy as np

from winder.geometry.domes import DomeMeridian
from winder.geometry.profiles import ProfileEval


class VesselRanges(NamedTuple):
    """Intervals of the internal station s covered by each part of a vessel."""

    dome: tuple[float, float]
    cylinder: tuple[float, float]
    end_dome: tuple[float, float]


@dataclasses.dataclass(frozen=True)
class VesselMeridian:
    """A vessel's meridian (z(s), r(s)), s the arc length from the first polar opening.

    s in [0, L1]: the first dome reversed, evaluated from its opening with u = s (z = D1 - h_dome(L1 - s)
    = the dome's drop at u = s); [L1, L1 + C]: the cylinder (r = R, z = s - L1 + D1); [L1 + C, length]:
    the end dome (z = D1 + C + h_end(s - L1 - C)). z(0) = 0 is the first opening's plane;
    z(length) = axial_length; z is clipped to [0, T] against round-off on [0, length]. The meridian is
    C1 (unit speed, tangent-continuous) everywhere; r2 (the meridian curvature) jumps at the two
    equators, as on every real vessel. At a junction itself the cylinder's values are returned.
    Outside [0, length] the end pieces are continued smoothly (not part of the mandrel).

    dome_ranges: the s-intervals of the dome, the cylinder and the end dome; equator_s / equator_t:
    s and t of the two dome/cylinder junctions; dome, end_dome: the DomeMeridian of each end.
    """

    radius: float
    cylinder_length: float
    dome: DomeMeridian
    end_dome: DomeMeridian
    origin: float = 0.0  # t at s = 0: 0 on the bare vessel, below 0 where a laminate rises past its boss

    @property
    def length(self) -> float:
        return self.dome.length + self.cylinder_length + self.end_dome.length

    @property
    def axial_length(self) -> float:
        """t at the far end (T on the bare vessel)."""
        return self.origin + self.dome.depth + self.cylinder_length + self.end_dome.depth

    @property
    def t_start(self) -> float:
        """t at the near end (0 on the bare vessel)."""
        return self.origin

    @property
    def reference_radius(self) -> float:
        return self.dome.end_radius

    @property
    def equator_s(self) -> tuple[float, float]:
        return (self.dome.length, self.dome.length + self.cylinder_length)

    @property
    def equator_t(self) -> tuple[float, float]:
        return (self.origin + self.dome.depth, self.origin + self.dome.depth + self.cylinder_length)

    @property
    def joints(self) -> tuple[float, ...]:
        """Stations s where a dome's own meridian curvature jumps (a torispherical head's knuckle
        meeting its crown), increasing; the equators are not among them."""
        a, b = self.equator_s
        return tuple(sorted([a - j for j in self.dome.joints] + [b + j for j in self.end_dome.joints]))

    @property
    def dome_ranges(self) -> VesselRanges:
        a, b = self.equator_s
        return VesselRanges((0.0, a), (a, b), (b, self.length))

    def evaluate(self, s: np.ndarray) -> ProfileEval:
        s = np.asarray(s, dtype=float)
        shape = s.shape
        s = s.ravel()
        a, b = self.equator_s
        d1, C = self.origin + self.dome.depth, self.cylinder_length
        out = np.empty((6, s.size))
        # cylinder (also the default at the junctions)
        out[0] = d1 + (s - a)
        out[1], out[2] = 1.0, 0.0
        out[3], out[4], out[5] = self.radius, 0.0, 0.0
        m = s < a
        if np.any(m):
            g, e = self.dome.drop_and_evaluate_from_opening(s[m])
            out[:, m] = (g + self.origin, e.h1, -e.h2, e.r, -e.r1, e.r2)
        m = s > b
        if np.any(m):
            e = self.end_dome.evaluate(s[m] - b)
            out[:, m] = (d1 + C + e.h, e.h1, e.h2, e.r, e.r1, e.r2)
        # round-off guard: t stays within [0, T] on [0, length]
        inside = (s >= 0.0) & (s <= self.length)
        out[0, inside] = np.clip(out[0, inside], self.origin, self.axial_length)
        return ProfileEval(*(o.reshape(shape) for o in out))

    def t_of_s(self, s: np.ndarray) -> np.ndarray:
        return self.evaluate(s).z

    def s_of_t(self, t: np.ndarray) -> np.ndarray:
        """Internal station s of the axial station t (clipped to [0, axial_length])."""
        t = np.clip(np.asarray(t, dtype=float), self.origin, self.axial_length)
        shape = t.shape
        t = t.ravel()
        a, b = self.equator_s
        ta, tb = self.equator_t
        s = a + (t - ta)
        m = t < ta
        if np.any(m):
            s[m] = self.dome.u_of_drop(t[m] - self.origin)
        m = t > tb
        if np.any(m):
            s[m] = b + self.end_dome.sigma_of_h(t[m] - tb)
        return s.reshape(shape)
