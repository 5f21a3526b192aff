"""A robot cell's motion (docs/math/10-robot-cell.md): from the eye poses of the one motion program,
the ring's station frame S(t*) in the mandrel frame, the ring's external axes (E1 turn, E2 eye yaw,
E3 eye radius), the flange poses in the arm's base frame, the arm's joints (winder.machine.reach) and
each move's time from the dynamics (the tool, the external axes and the joints).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

import numpy as np

from winder.config.arms import ARMS, Arm
from winder.config.machine import MachineConfig
from winder.config.robot import RobotCell
from winder.errors import ExportError
from winder.machine.dynamics import MoveTimes, move_times
from winder.machine.reach import Reach, check_reach

JOINT_RAMP_S = 0.5  # s from rest to a joint's top speed (its acceleration; makers publish none)


@dataclasses.dataclass(frozen=True)
class CellMotion:
    """The cell's motion over the m program rows.

    station : (m,) t* (mm). frames : (m, 4, 4) S(t*), the ring's frame in the mandrel frame (what KRL's
    E6POS and RAPID's robtarget hold). external : (m, 3) E1 ring turn (deg, cumulative), E2 eye yaw
    (deg, continuous), E3 eye radius (mm). flange : (m, 4, 4) the flange in the arm's base frame.
    mandrel : (m, 4, 4) the mandrel frame in the arm's base frame (URScript's pose, TCP = tool).
    reach : the joints and margins. times : each move's time. tool_path : (m,) the ring centre's
    travel in the mandrel frame along each move (mm).
    """

    arm: Arm
    cell: RobotCell
    station: np.ndarray
    frames: np.ndarray
    external: np.ndarray
    flange: np.ndarray
    mandrel: np.ndarray
    reach: Reach
    times: MoveTimes
    tool_path: np.ndarray


def station_frames(guide, eye: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(t* (m,), S(t*) (m, 4, 4)) of eye positions (m, 3) in the mandrel frame: the closest guide
    station and its rotation-minimizing frame (axes e2, e3, e1), constant beyond the ends."""
    z, _, _, tan, _ = guide.project(eye, full=True)
    x, _, _ = guide.evaluate(z)
    ev = guide.curve.evaluate(np.clip(z, 0.0, guide.T))
    frames = np.zeros((z.size, 4, 4))
    frames[:, :3, 0], frames[:, :3, 1], frames[:, :3, 2] = ev.e2, ev.e3, tan
    frames[:, :3, 3], frames[:, 3, 3] = x, 1.0
    return z, frames


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


def cell_motion(machine: MachineConfig, guide, values: np.ndarray, fiber: np.ndarray,
                where: Callable[[int], str], source: str | None = None) -> CellMotion:
    """The motion of machine.cell over the program rows values (m, 6) (eye position, unit direction
    from the eye to its contact) that lay fiber (m,) mm each; ExportError where the arm cannot follow."""
    cell = machine.cell
    assert cell is not None
    arm = ARMS[cell.arm]
    eye = np.asarray(values[:, :3], dtype=float)
    station, frames = station_frames(guide, eye)
    external = ring_axes(frames, eye, -np.asarray(values[:, 3:6], dtype=float))
    if cell.axes < 3 and external.shape[0]:
        spread = float(np.ptp(external[:, 2]))
        if spread > machine.chord_tolerance:
            raise ExportError(f"the eye's radius on the ring varies by {spread:.3f} mm along the program (the eye "
                              f"envelope follows the mandrel), more than the chord tolerance: positioner.axes: 3 "
                              f"(the eye's radial slide) is needed", file=source, key_path="machine.robot.positioner.axes")
        external[:, 2] = float(np.mean(external[:, 2]))
    if cell.axes < 2:
        external[:, 1] = 0.0
    mandrel = mandrel_in_base(cell, frames)
    flange = mandrel @ np.linalg.inv(cell.tool.matrix())
    reach = check_reach(arm, cell, flange, where)
    dyn = machine.dynamics
    columns = np.column_stack([frames[:, :3, 3], external, reach.joints])
    speed = np.concatenate([np.full(3, dyn.carriage.speed / 60.0),
                            [dyn.rotation.speed / 60.0, dyn.yaw.speed / 60.0, dyn.cross_feed.speed / 60.0],
                            arm.speed])
    acc = np.concatenate([np.full(3, dyn.carriage.acceleration),
                          [dyn.rotation.acceleration, dyn.yaw.acceleration, dyn.cross_feed.acceleration],
                          arm.speed / JOINT_RAMP_S])
    times = move_times(columns, fiber, machine, True, limits=(speed, acc))
    tool_path = np.concatenate([[0.0], np.linalg.norm(np.diff(frames[:, :3, 3], axis=0), axis=1)])
    return CellMotion(arm, cell, station, frames, external, flange, mandrel, reach, times, tool_path)
