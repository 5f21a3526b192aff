"""The torispherical head (docs/math/17-vessels-as-built.md 17.2): a spherical crown of radius R_c on a
toroidal knuckle of radius r_k, tangent to each other and to the cylinder of radius R (r_k < R <= R_c).

By arc length sigma from the equator: on the knuckle psi = sigma / r_k, h = r_k sin psi,
r = R - r_k + r_k cos psi; on the crown psi = psi_j + (sigma - r_k psi_j) / R_c, h = h_c + R_c sin psi,
r = R_c cos psi, with cos psi_j = (R - r_k) / (R_c - r_k) and h_c = -(R_c - r_k) sin psi_j. Exact values
and derivatives (closed forms); the meridian's curvature jumps from 1 / r_k to 1 / R_c at the joint, as
on every drawn head. The depth to the opening plane is computed from u (the arc length from the
opening) by the sum-to-product forms, so it keeps relative precision there.
"""

from __future__ import annotations

import math

import numpy as np

from winder.geometry.domes import DomeMeridian


class Torispherical(DomeMeridian):
    """A torispherical dome from its equator to the opening radius r0 (< R)."""

    kind = "torispherical"

    def __init__(self, radius: float, crown: float, knuckle: float, r0: float):
        R, rc, rk = float(radius), float(crown), float(knuckle)
        self.radius, self.polar_opening, self.semi_axis = R, float(r0), None
        self.crown_radius, self.knuckle_radius = rc, rk
        self.psi_joint = math.acos(min(1.0, (R - rk) / (rc - rk)))
        self.sigma_joint = rk * self.psi_joint
        self.crown_centre = -(rc - rk) * math.sin(self.psi_joint)
        r_joint = rc * math.cos(self.psi_joint)
        if r0 <= r_joint:  # the opening is on the crown
            self._psi_end = math.acos(r0 / rc)
            self.length = self.sigma_joint + rc * (self._psi_end - self.psi_joint)
        else:
            self._psi_end = math.acos((r0 - R + rk) / rk)
            self.length = rk * self._psi_end
        self.end_radius = float(r0)
        self.joints = (self.sigma_joint,) if 0.0 < self.sigma_joint < self.length else ()
        self.depth = float(self._h(np.array([self._psi_end]))[0])
        self._tab_sigma = np.linspace(0.0, self.length, 129)
        self._tab_h = self.evaluate(self._tab_sigma).h

    def _h(self, psi: np.ndarray) -> np.ndarray:
        """h at tangent angles psi (on the knuckle below psi_joint, else the crown)."""
        on_k = psi <= self.psi_joint
        return np.where(on_k, self.knuckle_radius * np.sin(psi), self.crown_centre + self.crown_radius * np.sin(psi))

    def psi_of_sigma(self, sigma: np.ndarray) -> np.ndarray:
        """The meridian's tangent angle from the axis at arc lengths sigma."""
        sigma = np.asarray(sigma, dtype=float)
        return np.where(sigma <= self.sigma_joint, sigma / self.knuckle_radius,
                        self.psi_joint + (sigma - self.sigma_joint) / self.crown_radius)

    def _eval2(self, sigma: np.ndarray, u: np.ndarray) -> tuple[np.ndarray, ...]:
        R, rc, rk, pe = self.radius, self.crown_radius, self.knuckle_radius, self._psi_end
        on_k = sigma <= self.sigma_joint
        psi = self.psi_of_sigma(sigma)
        # near the opening psi from u keeps its precision: psi = psi_end - u / (radius of that arc)
        end_on_crown = self.length > self.sigma_joint
        near = (u < 0.5 * self.length) & (~on_k if end_on_crown else on_k)
        rad_end = rc if end_on_crown else rk
        psi = np.where(near, pe - u / rad_end, psi)
        s, c = np.sin(psi), np.cos(psi)
        rho = np.where(on_k, rk, rc)
        h = np.where(on_k, rk * s, self.crown_centre + rc * s)
        r = np.where(on_k, R - rk + rk * c, rc * c)
        # depth - h: on the end arc 2 rho cos((pe + psi) / 2) sin((pe - psi) / 2), elsewhere a difference
        g = np.where(near, 2.0 * rad_end * np.cos(0.5 * (pe + psi)) * np.sin(0.5 * (pe - psi)), self.depth - h)
        return (g, h, c, -s / rho, r, -s, -c / rho)
