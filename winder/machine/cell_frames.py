"""The frames of a robot cell (docs/math/10-robot-cell.md 10.2): the ring's station frame S(t*) in the
mandrel frame, the ring's external axes of an eye pose, the eye of the ring's axes (the cell's forward
kinematics) and the mandrel in the arm's base frame."""

from __future__ import annotations

import numpy as np

from winder.config.robot import RobotCell


def station_frames(guide, eye: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(t* (m,), S(t*) (m, 4, 4)) of eye positions (m, 3) in the mandrel frame: the closest guide
    station and its rotation-minimizing frame (axes e2, e3, e1), constant beyond the ends."""
    z = guide.project(eye)[0]
    return z, frames_at(guide, z)


def frames_at(guide, z: np.ndarray) -> np.ndarray:
    """S(t) (m, 4, 4) at stations z (m,): the guide's point (extended straight beyond its ends) and the
    rotation-minimizing frame (constant beyond the ends)."""
    x, tan, _ = guide.evaluate(np.asarray(z, dtype=float))
    ev = guide.curve.evaluate(np.clip(z, 0.0, guide.T))
    frames = np.zeros((np.size(z), 4, 4))
    frames[:, :3, 0], frames[:, :3, 1], frames[:, :3, 2] = ev.e2, ev.e3, tan
    frames[:, :3, 3], frames[:, 3, 3] = x, 1.0
    return frames


def ring_axes(frames: np.ndarray, eye: np.ndarray, toward_eye: np.ndarray) -> np.ndarray:
    """(m, 3) E1 (deg), E2 (deg), E3 (mm) of eyes (m, 3) at the station frames (m, 4, 4); toward_eye
    (m, 3) the fiber's unit direction from its contact point to the eye (docs/math/10 10.2)."""
    rel = eye - frames[:, :3, 3]
    e2, e3, e1 = frames[:, :3, 0], frames[:, :3, 1], frames[:, :3, 2]
    a, b = np.einsum("ij,ij->i", rel, e2), np.einsum("ij,ij->i", rel, e3)
    phi = np.unwrap(np.arctan2(b, a)) if a.size else a
    rho = np.hypot(a, b)
    sense = -1.0 if phi.size and phi[-1] < phi[0] else 1.0
    radial = np.cos(phi)[:, None] * e2 + np.sin(phi)[:, None] * e3
    u = np.cross(e1, radial)
    d = toward_eye
    yaw = np.arctan2(sense * np.einsum("ij,ij->i", d, e1), sense * np.einsum("ij,ij->i", d, u))
    yaw = np.unwrap(yaw) if yaw.size else yaw
    return np.column_stack([np.degrees(phi), np.degrees(yaw), rho])


def eye_of(frames: np.ndarray, external: np.ndarray) -> np.ndarray:
    """The cell's forward kinematics to the eye (m, 3), mandrel frame: x(t*) + E3 (cos E1 e2 + sin E1 e3)."""
    phi = np.radians(external[:, 0])
    return frames[:, :3, 3] + external[:, 2:3] * (np.cos(phi)[:, None] * frames[:, :3, 0]
                                                   + np.sin(phi)[:, None] * frames[:, :3, 1])


def mandrel_in_base(cell: RobotCell, frames: np.ndarray) -> np.ndarray:
    """The mandrel frame in the arm's base frame (m, 4, 4) that puts each station frame on the ring."""
    base_ring = np.linalg.inv(cell.base.matrix()) @ cell.ring.matrix()
    return base_ring @ np.linalg.inv(frames)
