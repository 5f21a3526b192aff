"""The sections other than the circle: ellipse, superellipse and rounded rectangle.

Each is a Section (winder.geometry.sections) scaled by the profile. They live apart from the circle so
that a job on round tubes never builds their classes.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from winder.geometry.sections import perimeter_of

__all__ = ["Ellipse", "RoundedRectangle", "Superellipse"]


@dataclasses.dataclass(frozen=True)
class Ellipse:
    """Semi-axis a along e2, b along e3: rho = a b / sqrt((b cos)^2 + (a sin)^2)."""

    a: float
    b: float
    is_circle: bool = False

    def polar(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        return self.polar_cs(np.cos(theta), np.sin(theta))

    def polar_cs(self, c: np.ndarray, s: np.ndarray, order: int = 2):
        """rho and its derivatives up to `order` (the others None) from cos(theta) and sin(theta) (m,),
        which the surface has already."""
        a, b = self.a, self.b
        q = (b * c) ** 2 + (a * s) ** 2
        rho = a * b * q**-0.5
        if order == 0:
            return rho, None, None
        q1 = 2.0 * (a * a - b * b) * s * c
        q15 = q**-1.5  # used twice: a power costs several multiplies
        d1 = -0.5 * a * b * q15 * q1
        if order == 1:
            return rho, d1, None
        q2 = 2.0 * (a * a - b * b) * (c * c - s * s)
        d2 = a * b * (0.75 * q**-2.5 * q1 * q1 - 0.5 * q15 * q2)
        return rho, d1, d2

    def perimeter(self) -> float:
        return perimeter_of(self)

    def joints(self) -> np.ndarray:
        return np.empty(0)  # smooth


@dataclasses.dataclass(frozen=True)
class Superellipse:
    """|x/a|^p + |y/b|^p = 1, p >= 2 (C2): rho = (|cos/a|^p + |sin/b|^p)^(-1/p)."""

    a: float
    b: float
    p: float
    is_circle: bool = False

    def polar(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        return self.polar_cs(np.cos(theta), np.sin(theta))

    def polar_cs(self, c: np.ndarray, s: np.ndarray, order: int = 2):
        p = self.p
        ac, as_ = np.abs(c) / self.a, np.abs(s) / self.b
        sc, ss = np.sign(c), np.sign(s)
        # f = ac^p + as^p, written as m^p (u^p + v^p) with m = max(ac, as), u = ac / m, v = as / m:
        # ac^p alone underflows for large p or large semi-axes (p = 100, a = 1e5: 1e-500).
        m = np.maximum(ac, as_)
        u, v = ac / m, as_ / m
        up, vp = u**p, v**p  # the powers are most of the cost: each is taken once
        g = up + vp  # in [1, 2]
        rho = g ** (-1.0 / p) / m
        if order == 0:
            return rho, None, None
        # g1 = f' / m^(p-1), g2 = f'' / m^(p-2); derivative of |cos|^p is -p |cos|^(p-1) sign(cos) sin
        g1 = p * (-(u ** (p - 1)) * sc * s / self.a + v ** (p - 1) * ss * c / self.b)
        gd = g ** (-1.0 / p - 1.0)
        d1 = -(1.0 / p) * gd * g1 / (m * m)
        if order == 1:
            return rho, d1, None
        g2 = p * ((p - 1) * u ** (p - 2) * s * s / self.a**2 - m * m * up
                  + (p - 1) * v ** (p - 2) * c * c / self.b**2 - m * m * vp)
        d2 = ((1.0 / p) * (1.0 / p + 1.0) * g ** (-1.0 / p - 2.0) * g1 * g1
              - (1.0 / p) * gd * g2) / (m * m * m)
        return rho, d1, d2

    def perimeter(self) -> float:
        return perimeter_of(self)

    def joints(self) -> np.ndarray:
        return np.empty(0)  # smooth


@dataclasses.dataclass(frozen=True)
class RoundedRectangle:
    """Width along e2, height along e3, corners of radius rc; C1 where sides meet corners."""

    width: float
    height: float
    corner_radius: float
    is_circle: bool = False

    def polar(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        theta = np.asarray(theta, dtype=float)
        return self.polar_cs(np.cos(theta), np.sin(theta))

    def polar_cs(self, c: np.ndarray, s: np.ndarray, order: int = 2):
        hw, hh, rc = 0.5 * self.width, 0.5 * self.height, self.corner_radius
        # Fold into the first quadrant; the shape is symmetric about both axes.
        ac, as_ = np.abs(c), np.abs(s)
        cx, cy = hw - rc, hh - rc
        # Corner arc spans the polar angles between the side tangency points.
        side_x = np.arctan2(cy, hw)  # below: the vertical side x = hw
        side_y = np.arctan2(hh, cx)  # above: the horizontal side y = hh
        phi = np.arctan2(as_, ac)
        # Strict: a joint belongs to the corner, so a zero-length side (corner_radius = height / 2 or
        # width / 2) never wins there; corner_radius > 0 (config) keeps the corner formula finite.
        # Each piece's points are gathered once, and each formula is taken on its own points only.
        on_x, on_y = phi < side_x, phi > side_y
        side, top, corner = np.flatnonzero(on_x), np.flatnonzero(on_y), np.flatnonzero(~(on_x | on_y))
        a1, s1, a3, s3 = ac[side], as_[side], ac[top], as_[top]
        aa = cx * ac[corner] + cy * as_[corner]  # centre . u
        bb = -cx * as_[corner] + cy * ac[corner]  # centre . u_perp
        q = np.sqrt(rc * rc - bb * bb)
        rho = np.empty_like(ac)
        rho[side], rho[corner], rho[top] = hw / a1, aa + q, hh / s3
        if order == 0:
            return rho, None, None
        d1 = np.empty_like(ac)
        d1[side], d1[corner], d1[top] = hw * s1 / a1**2, bb + aa * bb / q, -hh * a3 / s3**2
        sgn = np.sign(c * s)  # rho' flips sign under each reflection, rho'' does not
        if order == 1:
            return rho, sgn * d1, None
        d2 = np.empty_like(ac)
        d2[side] = hw * (1.0 + s1**2) / a1**3
        d2[corner] = -aa + (bb * bb - aa * aa) / q - aa * aa * bb * bb / q**3
        d2[top] = hh * (1.0 + a3**2) / s3**3
        return rho, sgn * d1, d2

    def perimeter(self) -> float:
        rc = self.corner_radius
        return 2.0 * (self.width + self.height) - 8.0 * rc + 2.0 * np.pi * rc

    def joints(self) -> np.ndarray:
        """The polar angles where a side meets a corner (the curvature jumps 0 <-> 1 / rc), as in
        polar_cs, reflected into each quadrant; a zero-length side's two coincide."""
        hw, hh, rc = 0.5 * self.width, 0.5 * self.height, self.corner_radius
        quarter = np.array([np.arctan2(hh - rc, hw), np.arctan2(hh, hw - rc)])
        return np.unique(np.mod(np.concatenate([quarter, np.pi - quarter, np.pi + quarter, -quarter]), 2.0 * np.pi))
