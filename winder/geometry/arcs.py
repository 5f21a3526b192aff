"""Circular arcs and tangent-continuous chains of lines and arcs as guide curves (see
winder.geometry.curves for the conventions and the line)."""

from __future__ import annotations

import dataclasses
from typing import NamedTuple

import numpy as np

from winder.geometry.curves import X_AXIS, Z_AXIS, CurveEval, Line

__all__ = ["Arc", "ArcSpec", "Path", "chain"]


@dataclasses.dataclass(frozen=True, eq=False)
class Arc:
    """A circular arc of bend radius `radius` turning from `tangent` toward `toward_dir`.

    Its RMF is the rotation about the binormal b = T0 x u by the swept angle phi = z / radius:
    a frame vector v maps to (v.u) N(phi) + (v.b) b, N(phi) = -sin(phi) T0 + cos(phi) u.
    """

    length: float
    radius: float
    origin: np.ndarray
    tangent: np.ndarray
    e2: np.ndarray
    toward_dir: np.ndarray
    is_straight: bool = False

    def __post_init__(self) -> None:
        b = np.cross(self.tangent, self.toward_dir)
        e3 = np.cross(self.tangent, self.e2)
        # Cached because evaluation sits in the solver's inner loop.
        object.__setattr__(self, "_coef", (b, self.e2 @ self.toward_dir, self.e2 @ b,
                                           e3 @ self.toward_dir, e3 @ b))

    @property
    def frame_components(self) -> tuple[np.ndarray, float, float, float, float]:
        """The binormal b = T0 x u (3,) and e2.u, e2.b, e3.u, e3.b: the frame is e2 = (e2.u) N + (e2.b) b."""
        return self._coef

    def evaluate(self, z: np.ndarray) -> CurveEval:
        x, tan, nrm = self._point_tangent_normal(z)
        b, e2u, e2b, e3u, e3b = self._coef
        rho = self.radius
        return CurveEval(x, tan, nrm / rho, -tan / rho**2, e2u * nrm + e2b * b, e3u * nrm + e3b * b)

    def centerline(self, z: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """GuideCurve.centerline."""
        x, tan, nrm = self._point_tangent_normal(z)
        return x, tan, nrm / self.radius

    def _point_tangent_normal(self, z: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Point, unit tangent and in-plane unit normal toward the centre of curvature, (m, 3) each."""
        z = np.asarray(z, dtype=float)
        rho, t0, u = self.radius, self.tangent, self.toward_dir
        phi = (z / rho)[:, None]
        c, s = np.cos(phi), np.sin(phi)
        x = self.origin + rho * s * t0 + rho * (1.0 - c) * u
        return x, c * t0 + s * u, -s * t0 + c * u

    def max_curvature(self) -> float:
        return 1.0 / self.radius


class ArcSpec(NamedTuple):
    """An arc of a chain: bend radius (mm), bend angle and the side it bends toward (deg, in the
    frame at its start, measured like theta from e2 toward e3)."""

    radius: float
    angle_deg: float
    toward_deg: float = 0.0


def _arc_from(origin: np.ndarray, tangent: np.ndarray, e2: np.ndarray, cfg: ArcSpec) -> Arc:
    toward = np.radians(cfg.toward_deg)
    e3 = np.cross(tangent, e2)
    u = np.cos(toward) * e2 + np.sin(toward) * e3
    return Arc(cfg.radius * np.radians(cfg.angle_deg), cfg.radius, origin, tangent, e2, u)


@dataclasses.dataclass(frozen=True, eq=False)
class Path:
    """A tangent-continuous chain of lines and arcs; frames carried across the joints.

    Evaluated in one vectorized pass: every piece is an arc of curvature kappa (0 for a line) in
    the plane of its start tangent T0 and in-plane normal u, with the sinc forms of sin(phi) / kappa
    and (1 - cos(phi)) / kappa, so lines need no special case.
    """

    pieces: tuple[Line | Arc, ...]
    starts: np.ndarray  # (k,) float, station where each piece begins
    length: float
    is_straight: bool = False

    def __post_init__(self) -> None:
        rows = []
        for piece in self.pieces:
            t0 = piece.tangent
            if isinstance(piece, Arc):
                u, kappa = piece.toward_dir, 1.0 / piece.radius
            else:
                u, kappa = piece.e2, 0.0
            b = np.cross(t0, u)
            e3 = np.cross(t0, piece.e2)
            rows.append((piece.origin, t0, u, b, kappa, piece.e2 @ u, piece.e2 @ b, e3 @ u, e3 @ b))
        cols = list(zip(*rows))
        object.__setattr__(self, "_vec", tuple(np.array(c, dtype=float) for c in cols))
        # Piece-major tables for the multi-piece gather: one fancy index along the pieces gives
        # contiguous (rows, m) component rows. 1 / kappa is 0 on lines, where it is never selected,
        # so the evaluation divides nothing by zero.
        origin, t0, u, b, kappa, e2u, e2b, e3u, e3b = self._vec
        inv = np.divide(1.0, kappa, out=np.zeros_like(kappa), where=kappa > 0.0)
        object.__setattr__(self, "_columns", np.concatenate([origin.T, t0.T, u.T, b.T]))
        object.__setattr__(self, "_scalars", np.stack([kappa, inv, e2u, e2b, e3u, e3b]))
        # One piece: its parameters broadcast as they are, as (3, 1) columns and floats, with the
        # binormal's constant parts of the frame, e2b b and e3b b, formed once.
        col = tuple(a[0][:, None] for a in (origin, t0, u, b))
        object.__setattr__(self, "_single", (*col, float(kappa[0]), float(e2u[0]), float(e3u[0]),
                                             e2b[0] * col[3], e3b[0] * col[3]))

    def evaluate(self, z: np.ndarray) -> CurveEval:
        x, tan, nrm, kappa, e2u, e2bb, e3u, e3bb = self._pieces_at(z)
        return CurveEval(x.T, tan.T, (kappa * nrm).T, (-(kappa * kappa) * tan).T, (e2u * nrm + e2bb).T,
                         (e3u * nrm + e3bb).T)

    def centerline(self, z: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """x, x' and x'' at stations z (m,): evaluate's first three fields (each (m, 3), new arrays)
        without the frame, for closest-point searches that do not need it."""
        x, tan, nrm, kappa = self._pieces_at(z, frame=False)[:4]
        return x.T, tan.T, (kappa * nrm).T

    def _pieces_at(self, z: np.ndarray, frame: bool = True) -> tuple:
        """Point, unit tangent and in-plane normal (each (3, m)), the curvature, and the frame's
        coefficients (e2.u, (e2.b) b, e3.u, (e3.b) b; None without frame) of the pieces holding the
        stations z (m,)."""
        z = np.asarray(z, dtype=float)
        if len(self.pieces) == 1:  # no per-point gather
            origin, t0, u, b, kappa, e2u, e3u, e2bb, e3bb = self._single
            zl = z
        else:
            k = np.clip(np.searchsorted(self.starts, z, side="right") - 1, 0, len(self.pieces) - 1)
            cols = self._columns[:, k]
            origin, t0, u, b = cols[0:3], cols[3:6], cols[6:9], cols[9:12]
            kappa, inv, e2u, e2b, e3u, e3b = self._scalars[:, k]
            e2bb, e3bb = (e2b * b, e3b * b) if frame else (None, None)
            zl = z - self.starts[k]
        # Component-major (3, m): the arithmetic runs along m. sin(phi) / kappa and
        # (1 - cos(phi)) / kappa = 2 sin(phi / 2)^2 / kappa tend to z and 0 on lines (kappa = 0).
        phi = kappa * zl
        c, s = np.cos(phi), np.sin(phi)
        if np.ndim(kappa) == 0:
            along, across = (s / kappa, 2.0 * np.sin(0.5 * phi) ** 2 / kappa) if kappa > 0.0 else (zl, 0.0)
        else:
            arc = kappa > 0.0
            along = np.where(arc, s * inv, zl)
            across = np.where(arc, 2.0 * np.sin(0.5 * phi) ** 2 * inv, 0.0)
        x = origin + along * t0 + across * u
        tan = c * t0 + s * u
        nrm = c * u - s * t0
        return x, tan, nrm, kappa, e2u, e2bb, e3u, e3bb

    def max_curvature(self) -> float:
        return max(p.max_curvature() for p in self.pieces)


def chain(segments: tuple[float | ArcSpec, ...]) -> Path:
    """A tangent-continuous chain from +z at the origin: each segment a line length (mm) or an arc."""
    origin, tangent, e2 = np.zeros(3), Z_AXIS.copy(), X_AXIS.copy()
    pieces: list[Line | Arc] = []
    starts = []
    z0 = 0.0
    for seg in segments:
        piece: Line | Arc
        if not isinstance(seg, ArcSpec):
            piece = Line(float(seg), origin, tangent, e2)
        else:
            piece = _arc_from(origin, tangent, e2, seg)
        end = piece.evaluate(np.array([piece.length]))
        pieces.append(piece)
        starts.append(z0)
        z0 += piece.length
        origin, tangent, e2 = end.x[0], *_orthonormal(end.d1[0], end.e2[0])
    return Path(tuple(pieces), np.array(starts), z0)


def _orthonormal(tangent: np.ndarray, e2: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The frame (tangent, e2) made orthonormal again (Gram-Schmidt) at a joint. An arc maps its start
    frame through u = e2 (bent toward 0): a relative error eps in |e2| comes out as about 3 eps, so a
    chain of arcs carried unnormalized grew it 3x a piece, to NaN past ~90 pieces."""
    tangent = tangent / np.linalg.norm(tangent)
    e2 = e2 - (e2 @ tangent) * tangent
    return tangent, e2 / np.linalg.norm(e2)
