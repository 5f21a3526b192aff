"""Shared fixtures: the reference mandrels of docs/math/02-energy.md and the issues."""

from __future__ import annotations

import numpy as np
import pytest

from winder.config.axes import ArcAxis
from winder.config.mandrel import CircleSection, ConstantProfile, LineAxis, MandrelConfig
from winder.config.profiles import ConeProfile
from winder.config.sections import EllipseSection
from winder.geometry.build import build_surface
from winder.geometry.surface import SweepSurface


def surface_of(axis, profile=None, section=None) -> SweepSurface:
    return build_surface(MandrelConfig(axis, profile, section or CircleSection()), "test.yaml", "test")


@pytest.fixture(scope="session")
def quarter_bend() -> SweepSurface:
    """Quarter bend: bend radius 150, tube radius 40 (the reference tube of docs/math/02-energy.md)."""
    return surface_of(ArcAxis(150.0, 90.0), ConstantProfile(40.0))


@pytest.fixture(scope="session")
def straight_tube() -> SweepSurface:
    return surface_of(LineAxis(300.0), ConstantProfile(40.0))


@pytest.fixture(scope="session")
def elliptic_tube() -> SweepSurface:
    """Straight elliptic tube a = 60, b = 35, no profile: absolute section sizes."""
    return surface_of(LineAxis(400.0), None, EllipseSection(60.0, 35.0))


@pytest.fixture(scope="session")
def cone() -> SweepSurface:
    """Cone from radius 60 to 30 over 300 mm: half angle atan(0.1)."""
    return surface_of(LineAxis(300.0), ConeProfile(60.0, 30.0))


def ellipse_arc(a: float, b: float, th0: float, th1: float) -> float:
    """Arc length of the ellipse between polar angles th0 and th1 (unwrapped, radians).

    Independent of winder's section code: by the eccentric angle E (x = a cos E, y = b sin E) and
    the incomplete elliptic integral of the second kind.
    """
    from scipy.special import ellipeinc  # noqa: PLC0415

    def ecc(th: float) -> float:
        turns = np.floor((th + np.pi) / (2 * np.pi))
        base = th - 2 * np.pi * turns
        return float(np.arctan2(a * np.sin(base), b * np.cos(base)) + 2 * np.pi * turns)

    e0, e1 = ecc(th0), ecc(th1)
    m = 1.0 - (b / a) ** 2
    # ds/dE = a sqrt(1 - m cos^2 E); with phi = E - pi/2, cos^2 E = sin^2 phi.
    return a * (ellipeinc(e1 - np.pi / 2, m) - ellipeinc(e0 - np.pi / 2, m))
