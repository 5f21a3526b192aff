"""Bridging measured as a lift-off (docs/math/08-laminate-edges.md 8.10).

Over a concave stretch (k_n < 0) a fiber under tension does not follow the mandrel: it spans the
stretch straight. Along a pass of arc length l the surface curve's height over its tangent plane obeys
y'' = -k_n; the taut fiber is the upper concave envelope y* of (l, y), and the lift-off y* - y (mm) is
how far it stands off the surface. A circular dent of curvature -kappa over a length w between
strongly convex stretches gives the chord's sagitta kappa w^2 / 8.
"""

from __future__ import annotations

import dataclasses

import numpy as np


@dataclasses.dataclass(frozen=True)
class LiftOff:
    """The largest lift-off of a pass: lift_mm (>= 0) at vertex index `at` of the k_n samples."""

    lift_mm: float
    at: int


def heights(l: np.ndarray, k_n: np.ndarray) -> np.ndarray:
    """y(l) with y'' = -k_n, y(0) = y'(0) = 0 (trapezoid twice); l, k_n : (m,) float. (m,) float."""
    dl = np.diff(l)
    slope = np.concatenate([[0.0], np.cumsum(-0.5 * (k_n[1:] + k_n[:-1]) * dl)])
    return np.concatenate([[0.0], np.cumsum(0.5 * (slope[1:] + slope[:-1]) * dl)])


def upper_envelope(l: np.ndarray, y: np.ndarray) -> np.ndarray:
    """The least concave function above the points (l, y) (l increasing), at each l: (m,) float.

    The upper hull (scipy's Qhull on the points): its vertices in counterclockwise order run from the
    rightmost point over the top to the leftmost one."""
    from scipy.spatial import ConvexHull, QhullError  # noqa: PLC0415 - only passes that bridge

    if l.size < 3:
        return y.copy()
    # the hull is affine-invariant: take out the chord so Qhull sees the dent at its own scale
    chord = y[0] + (y[-1] - y[0]) * (l - l[0]) / (l[-1] - l[0])
    z = y - chord
    scale = max(float(np.ptp(z)), 1e-300)
    try:
        hull = ConvexHull(np.column_stack([(l - l[0]) / (l[-1] - l[0]), z / scale]))
    except QhullError:  # all on one line: the envelope is that line
        return y.copy()
    v = hull.vertices
    right = int(np.nonzero(v == l.size - 1)[0][0]) if np.any(v == l.size - 1) else int(np.argmax(l[v]))
    v = np.roll(v, -right)
    left = int(np.nonzero(v == 0)[0][0]) if np.any(v == 0) else int(np.argmin(l[v]))
    top = np.sort(v[:left + 1])
    env = np.interp(l, l[top], z[top])
    return np.maximum(env, z) + chord


def pass_lift_off(points: np.ndarray, k_n: np.ndarray, judged: np.ndarray | None = None) -> LiftOff:
    """The largest lift-off of one pass: points (m, 3) float its vertices, k_n (m - 2,) float the
    normal curvature at its interior vertices (winder.geometry.curvature.polyline_curvatures);
    judged (m - 2,) bool: where it counts (the wound region; a fiber bridging in a trimmed end is cut
    away with it), everywhere when None. The taut fiber's envelope is the whole pass's."""
    seg = np.sqrt(np.sum(np.diff(points, axis=0) ** 2, axis=1))
    l = np.cumsum(seg)[:-1]  # arc length at the interior vertices 1 .. m - 2
    if l.size < 3 or not np.all(np.isfinite(k_n)):
        return LiftOff(0.0, 0)
    y = heights(l, k_n)
    lift = upper_envelope(l, y) - y
    if judged is not None:
        if not np.any(judged):
            return LiftOff(0.0, 0)
        lift = np.where(judged, lift, -np.inf)
    i = int(np.argmax(lift))
    return LiftOff(max(float(lift[i]), 0.0), i)
