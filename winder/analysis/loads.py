"""Membrane loads of a thin shell of revolution (docs/math/09-structure.md 9.1), vectorized over stations.

Each resultant is affine in the pressure: N = p N_p + N_0 (N_0 from the axial force and torque), so the
failure pressure is a load factor on N_p with N_0 held (9.4).
"""

from __future__ import annotations

import dataclasses

import numpy as np


@dataclasses.dataclass(frozen=True)
class LoadCase:
    """Internal pressure (MPa), axial force (N, tension +), torque (N mm) and whether the pressure's end
    thrust acts on the wall (closed ends: vessels, capped pipes)."""

    pressure: float = 0.0
    axial_force: float = 0.0
    torque: float = 0.0
    closed: bool = True


@dataclasses.dataclass(frozen=True)
class StationGeometry:
    """The inner face of the wall at stations along the meridian.

    t : (n,) axial station (mm). r : (n,) radius (mm). r2 : (n,) circumferential principal radius r / cos(phi)
    (the normal's length to the axis). k1 : (n,) meridional curvature 1 / r_1 (1/mm, > 0 on a convex dome,
    0 on a cylinder or cone).
    """

    t: np.ndarray
    r: np.ndarray
    r2: np.ndarray
    k1: np.ndarray


def revolution_geometry(t: np.ndarray, r: np.ndarray, r_s: np.ndarray, z_s: np.ndarray, r_ss: np.ndarray,
                        z_ss: np.ndarray) -> StationGeometry:
    """StationGeometry from the meridian (r(s), z(s)) and its first two derivatives in any parameter s,
    each (n,) float."""
    speed = np.hypot(r_s, z_s)
    cos_phi = np.abs(z_s) / speed
    with np.errstate(divide="ignore"):
        r2 = np.where(cos_phi > 0.0, r / np.where(cos_phi > 0.0, cos_phi, 1.0), np.inf)
    k1 = (r_s * z_ss - z_s * r_ss) / speed ** 3 * np.sign(z_s)  # the sign: meridians run either way in z
    return StationGeometry(np.asarray(t, float), np.asarray(r, float), r2, k1)


def resultants(geo: StationGeometry, case: LoadCase) -> tuple[np.ndarray, np.ndarray]:
    """(N_p, N_0): per unit pressure and from the held loads, each (n, 3) [N_m, N_h, N_mh] (N/mm).

    N_m = p r2 / 2 [closed] + F r2 / (2 pi r^2); N_h = r2 (p - k1 N_m) (Laplace); N_mh = T / (2 pi r^2).
    """
    r, r2, k1 = geo.r, geo.r2, geo.k1
    m_p = 0.5 * r2 if case.closed else np.zeros_like(r)
    m_0 = case.axial_force * r2 / (2.0 * np.pi * r * r)
    per_p = np.column_stack([m_p, r2 * (1.0 - k1 * m_p), np.zeros_like(r)])
    held = np.column_stack([m_0, -r2 * k1 * m_0, np.full_like(r, case.torque) / (2.0 * np.pi * r * r)])
    return per_p, held
