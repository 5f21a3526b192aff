"""Rotation-minimizing frames (RMF) along a guide curve.

Lines and planar arcs have exact frames (curves.py). A general guide gets its RMF by the double
reflection method (Wang, Juettler, Zheng, Liu 2008; paper section 4.2) on a fine grid: its error is
O(h^4), far below anything the geodesic solver can see at the grid sizes used.
"""

from __future__ import annotations

import numpy as np


def double_reflection(x: np.ndarray, tangent: np.ndarray, e2_start: np.ndarray) -> np.ndarray:
    """Carry a normal vector along sampled curve points by double reflection.

    x : (m, 3) float, points on the curve.
    tangent : (m, 3) float, unit tangents at those points.
    e2_start : (3,) float, unit normal at x[0], orthogonal to tangent[0].
    Returns e2 : (m, 3) float, the rotation-minimizing normal at every point.
    """
    m = x.shape[0]
    e2 = np.empty((m, 3))
    e2[0] = e2_start
    # The recursion is sequential by nature; it runs once per mandrel on the build grid, never in a
    # solver loop.
    for i in range(m - 1):
        v1 = x[i + 1] - x[i]
        c1 = v1 @ v1
        r_l = e2[i] - (2.0 / c1) * (v1 @ e2[i]) * v1
        t_l = tangent[i] - (2.0 / c1) * (v1 @ tangent[i]) * v1
        v2 = tangent[i + 1] - t_l
        c2 = v2 @ v2
        e2[i + 1] = r_l - (2.0 / c2) * (v2 @ r_l) * v2 if c2 > 1e-300 else r_l
    return e2


def orthonormalize(e2: np.ndarray, tangent: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Make interpolated normals exactly orthonormal to the tangents.

    e2, tangent : (m, 3) float. Returns (e2, e3), each (m, 3) float, e3 = tangent x e2.
    """
    e2 = e2 - np.sum(e2 * tangent, axis=1)[:, None] * tangent
    e2 /= np.linalg.norm(e2, axis=1)[:, None]
    return e2, np.cross(tangent, e2)
