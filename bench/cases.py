"""The bench's mandrels (the paper's three radius cases, Table 1) and their ground-truth lengths.

Closed forms (docs/math/04-checks.md) where they exist, written here from first principles and independent of
winder's surface code: a cone unrolls into a plane sector, a straight tube of any section into a
plane strip. The bent tube has none: its truth is tight shooting (winder.paths.shooting.shoot, DOP853),
cross-checked against the other methods on the results page.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np
from scipy.special import ellipe

from winder.config.axes import ArcAxis
from winder.config.mandrel import CircleSection, ConstantProfile, LineAxis, MandrelConfig
from winder.config.profiles import ConeProfile
from winder.config.sections import EllipseSection
from winder.paths.shooting import shoot
from winder.geometry.build import build_surface
from winder.geometry.surface import SweepSurface

TWO_PI = 2.0 * np.pi


@dataclass(frozen=True)
class Case:
    """One bench mandrel with its end points.

    start, end : (t mm, theta rad); rounds : extra full turns added to the end angle.
    closed_form : the exact geodesic length (mm), or None (truth by tight shooting).
    """

    key: str
    title: str
    radius_case: str
    mandrel: MandrelConfig
    description: str
    start: tuple[float, float]
    end: tuple[float, float]
    rounds: int
    closed_form: Callable[[], float] | None = None
    closed_form_text: str = ""

    def surface(self) -> SweepSurface:
        return build_surface(self.mandrel, "bench", self.key)

    def ends_s(self, surface: SweepSurface) -> tuple[tuple[float, float], tuple[float, float]]:
        """Start and end as internal stations (s, theta), the end angle without the rounds."""
        s0, s1 = (float(v) for v in surface.s_of_t(np.array([self.start[0], self.end[0]])))
        return (s0, self.start[1]), (s1, self.end[1])

    @property
    def sweep_angle(self) -> float:
        """theta_end + 2 pi rounds - theta_start (rad)."""
        return self.end[1] + TWO_PI * self.rounds - self.start[1]


# -- closed forms ---------------------------------------------------------------------------------------
def cone_length(r0: float, r1: float, axial: float, dtheta: float) -> float:
    """Geodesic on a circular cone frustum between radius r0 (t = 0) and r1 (t = axial), dtheta apart.

    Unrolled, the cone is a plane sector: a point at radius r lies at slant distance rho = r / sin(b)
    from the apex (b the half angle, sin b = |r1 - r0| / slant length) and at angle theta sin(b). The
    geodesic is the straight chord: L^2 = rho0^2 + rho1^2 - 2 rho0 rho1 cos(dtheta sin b). Valid while
    the chord stays on the frustum (checked by the caller's choice of end points).
    """
    sin_b = abs(r1 - r0) / np.hypot(axial, r1 - r0)
    rho0, rho1 = r0 / sin_b, r1 / sin_b
    phi = abs(dtheta) * sin_b
    if phi >= np.pi:
        raise ValueError("the unrolled angle reaches pi: the chord passes the apex")
    return float(np.sqrt(rho0**2 + rho1**2 - 2.0 * rho0 * rho1 * np.cos(phi)))


def ellipse_perimeter(a: float, b: float) -> float:
    """4 a E(e^2), e^2 = 1 - (b/a)^2 (a >= b), the complete elliptic integral of the second kind."""
    a, b = max(a, b), min(a, b)
    return float(4.0 * a * ellipe(1.0 - (b / a) ** 2))


def developable_tube_length(axial: float, arc: float) -> float:
    """A straight tube of any section unrolls into a strip: L = sqrt(dt^2 + s^2)."""
    return float(np.hypot(axial, arc))


# -- the three mandrels -----------------------------------------------------------------------------------
def _bend() -> Case:
    return Case(
        key="bend", title="Quarter bend (constant r)", radius_case="1: r constant, bent axis",
        mandrel=MandrelConfig(ArcAxis(150.0, 90.0), ConstantProfile(40.0), CircleSection()),
        description="ArcAxis(150 mm, 90 deg), ConstantProfile(40 mm); (t = 0, 0 deg) to "
                    "(t = end, 90 deg) + 1 round",
        start=(0.0, 0.0), end=(150.0 * np.pi / 2.0, np.pi / 2.0), rounds=1)


def _cone() -> Case:
    # End angle 90 deg + 1 round: unrolled angle 0.78 rad < pi/3, so the chord runs monotonically
    # from the large to the small end (at more than pi/3 it would dip below r = 30 and leave the
    # frustum past t = 300, and there would be no geodesic on the mandrel).
    dtheta = np.pi / 2.0 + TWO_PI
    return Case(
        key="cone", title="Cone (r(t))", radius_case="2: r(t), straight axis",
        mandrel=MandrelConfig(LineAxis(300.0), ConeProfile(60.0, 30.0), CircleSection()),
        description="LineAxis(300 mm), ConeProfile(60 -> 30 mm); (t = 0, 0 deg) to (t = 300, 90 deg) "
                    "+ 1 round",
        start=(0.0, 0.0), end=(300.0, np.pi / 2.0), rounds=1,
        closed_form=lambda: cone_length(60.0, 30.0, 300.0, dtheta),
        closed_form_text="unrolled sector: L^2 = rho0^2 + rho1^2 - 2 rho0 rho1 cos(dtheta sin b)")


def _ellipse() -> Case:
    # theta 0 -> 90 deg is a quarter of the ellipse (polar and parametric angles agree at 0 and 90).
    return Case(
        key="ellipse", title="Elliptic tube (r(t, theta))", radius_case="3: r(t, theta), straight axis",
        mandrel=MandrelConfig(LineAxis(400.0), None, EllipseSection(60.0, 35.0)),
        description="LineAxis(400 mm), EllipseSection(60, 35 mm); (t = 0, 0 deg) to (t = 400, 90 deg) "
                    "+ 2 rounds",
        start=(0.0, 0.0), end=(400.0, np.pi / 2.0), rounds=2,
        closed_form=lambda: developable_tube_length(400.0, 2.25 * ellipse_perimeter(60.0, 35.0)),
        closed_form_text="developable: L = sqrt(dt^2 + s^2), s = 2.25 perimeters (complete elliptic "
                         "integral E)")


def cases() -> list[Case]:
    return [_bend(), _cone(), _ellipse()]


def bent_tube() -> MandrelConfig:
    return _bend().mandrel


@dataclass(frozen=True)
class Truth:
    """The reference length of a case (mm) and how it was obtained."""

    length: float
    source: str
    shoot_length: float
    shoot_seconds: float
    shoot_converged: bool

    @property
    def shoot_vs_truth(self) -> float:
        """Relative difference of tight shooting from the truth (0 when shooting is the truth)."""
        return (self.shoot_length - self.length) / self.length


def truth(case: Case, surface: SweepSurface, tol: float) -> Truth:
    """The closed form if there is one, else tight shooting; tight shooting is run in both cases."""
    a, b = case.ends_s(surface)
    sh = shoot(surface, a, b, rounds=case.rounds, tol=tol)
    if case.closed_form is not None:
        return Truth(case.closed_form(), "closed form: " + case.closed_form_text, sh.length, sh.seconds,
                     sh.converged)
    return Truth(sh.length, f"shooting (winder.paths.shooting.shoot, DOP853, rtol = atol = {tol:g})", sh.length,
                 sh.seconds, sh.converged)
