"""Winding angles and parameter velocities on the surface, and the Clairaut constant.

The winding angle alpha (heading) is the angle in the tangent plane from the direction of increasing
s (the meridian, Phi_s) toward increasing theta. The orthonormal tangent basis is e1 = Phi_s / |Phi_s|
and e2 = the unit part of Phi_theta orthogonal to e1. clairaut_constant: r sin(alpha) on a surface of
revolution, conserved along every geodesic (docs/math/04-checks.md).
"""

from __future__ import annotations

import numpy as np

from winder.errors import SolverError
from winder.geometry.surface import SweepSurface

__all__ = ["clairaut_constant", "heading_of_velocity", "row_dot", "tangent_basis", "velocity_of_heading"]


def row_dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise dot products of two (m, 3) arrays: (m,)."""
    return np.einsum("ij,ij->i", a, b)


def tangent_basis(ps: np.ndarray, pt: np.ndarray):
    """|Phi_s|, e1.Phi_theta and |w|, w = the part of Phi_theta orthogonal to e1; each (m,)."""
    ns = np.linalg.norm(ps, axis=1)
    e1 = ps / ns[:, None]
    along = row_dot(e1, pt)
    w = np.linalg.norm(pt - along[:, None] * e1, axis=1)
    return ns, along, w


def velocity_of_heading(surface: SweepSurface, s: np.ndarray, theta: np.ndarray,
                        heading_rad: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Parameter velocity (s', theta') of the unit tangent vector at winding angle heading_rad.

    The unit vector d = cos(a) e1 + sin(a) e2 written as d = s' Phi_s + theta' Phi_theta.
    All arguments (m,) float (broadcast); returns two (m,) arrays.
    """
    s, theta, a = np.broadcast_arrays(*(np.atleast_1d(np.asarray(v, dtype=float))
                                        for v in (s, theta, heading_rad)))
    ev = surface.evaluate(s, theta, order=1)
    ns, along, w = tangent_basis(ev.ps, ev.pt)
    dth = np.sin(a) / w
    ds = (np.cos(a) - dth * along) / ns
    return ds, dth


def heading_of_velocity(surface: SweepSurface, s: np.ndarray, theta: np.ndarray, ds: np.ndarray,
                        dtheta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Winding angle (rad, from the meridian toward increasing theta) and speed |J u'| (mm per unit).

    All arguments (m,) float (broadcast); returns two (m,) arrays.
    """
    s, theta, ds, dtheta = np.broadcast_arrays(*(np.atleast_1d(np.asarray(v, dtype=float))
                                                 for v in (s, theta, ds, dtheta)))
    ev = surface.evaluate(s, theta, order=1)
    ns, along, w = tangent_basis(ev.ps, ev.pt)
    c1 = ns * ds + along * dtheta  # component along e1
    c2 = w * dtheta  # component along e2
    return np.arctan2(c2, c1), np.hypot(c1, c2)


def clairaut_constant(surface: SweepSurface, s: np.ndarray, theta: np.ndarray, ds: np.ndarray,
                      dtheta: np.ndarray) -> np.ndarray:
    """r sin(alpha) at points (s, theta) moving with parameter velocity (ds, dtheta): (m,) float, mm.

    r is the distance from the axis, alpha the angle from the meridian (signed: positive toward
    increasing theta). Constant along every geodesic of a surface of revolution (Clairaut).
    Raises SolverError if the surface is not one of revolution.
    """
    if not surface.is_revolution:
        raise SolverError(f"Clairaut's relation needs a surface of revolution (a straight axis and a "
                          f"circular section); the mandrel {surface.name!r} is not one")
    alpha, _ = heading_of_velocity(surface, s, theta, ds, dtheta)
    s_b = np.broadcast_arrays(np.atleast_1d(np.asarray(s, dtype=float)), alpha)[0]
    th_b = np.broadcast_arrays(np.atleast_1d(np.asarray(theta, dtype=float)), alpha)[0]
    return surface.radius(s_b, th_b) * np.sin(alpha)
