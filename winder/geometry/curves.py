"""Guide curves x(t), t the arc length, with their rotation-minimizing frames.

Conventions (docs/guide/conventions.md): x(0) = origin, x'(0) = +z, e2(0) = +x, e3 = e1 x e2. Every curve evaluates,
vectorized over stations z (m,), the point, its first three derivatives and the frame (e2, e3).
The line is here; arcs and chains of lines and arcs are in winder.geometry.arcs, the spline in
winder.geometry.spline_curves (loaded only for the mandrels that have them).
"""

from __future__ import annotations

import dataclasses
import functools
from dataclasses import field
from typing import NamedTuple, Protocol

import numpy as np


Z_AXIS = np.array([0.0, 0.0, 1.0])
X_AXIS = np.array([1.0, 0.0, 0.0])
Y_AXIS = np.array([0.0, 1.0, 0.0])


class CurveEval(NamedTuple):
    """A guide curve at stations z; every field (m, 3) float.

    x : point; d1 = x' (unit tangent T); d2 = x'' (= T'); d3 = x''' (= T'');
    e2, e3 : the rotation-minimizing frame's normals.
    """

    x: np.ndarray
    d1: np.ndarray
    d2: np.ndarray
    d3: np.ndarray
    e2: np.ndarray
    e3: np.ndarray


class GuideCurve(Protocol):
    length: float
    is_straight: bool

    def evaluate(self, z: np.ndarray) -> CurveEval: ...

    def centerline(self, z: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """x, x' and x'' at stations z (m,): evaluate's first three fields (each (m, 3), new arrays)
        without the frame, for closest-point searches that do not need it."""
        ...

    def max_curvature(self) -> float: ...


def tile(v: np.ndarray, m: int) -> np.ndarray:
    """v repeated m times: (m, 3), a view of (3, m) storage like every curve's evaluation."""
    return np.repeat(v[:, None], m, axis=1).T


@dataclasses.dataclass(frozen=True, eq=False)
class Line:
    """A straight segment from `origin` along `tangent`, frame constant."""

    length: float
    origin: np.ndarray = field(default_factory=lambda: np.zeros(3))
    tangent: np.ndarray = field(default_factory=lambda: Z_AXIS.copy())
    e2: np.ndarray = field(default_factory=lambda: X_AXIS.copy())
    is_straight: bool = True

    def evaluate(self, z: np.ndarray) -> CurveEval:
        z = np.asarray(z, dtype=float)
        m = z.shape[0]
        zero = np.zeros((3, m)).T
        return CurveEval((self.origin[:, None] + z * self.tangent[:, None]).T, tile(self.tangent, m), zero,
                         zero, tile(self.e2, m), tile(self.e3, m))

    def centerline(self, z: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """GuideCurve.centerline."""
        z = np.asarray(z, dtype=float)
        m = z.shape[0]
        return (self.origin[:, None] + z * self.tangent[:, None]).T, tile(self.tangent, m), np.zeros((m, 3))

    @functools.cached_property
    def e3(self) -> np.ndarray:
        """The frame's third vector, tangent x e2 (3,): constant along a line."""
        return np.cross(self.tangent, self.e2)

    def max_curvature(self) -> float:
        return 0.0
