"""The reach check of a robot cell (docs/math/10-robot-cell.md 10.4): one inverse-kinematics branch for
the whole program, continuous, within the joint limits, away from the wrist singularity, no jump.

A program the arm cannot follow is refused (ExportError, exit 1) before any file is written, naming the
pose's layer, circuit and pass, the joint, its value and the limit.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

import numpy as np

from winder.config.arms import Arm
from winder.config.robot import RobotCell
from winder.errors import ExportError
from winder.machine.arm_ik import BRANCHES, ik

JOINT_NAMES = {"KUKA": ("A1", "A2", "A3", "A4", "A5", "A6"),
               "ABB": ("axis 1", "axis 2", "axis 3", "axis 4", "axis 5", "axis 6"),
               "Universal Robots": ("base", "shoulder", "elbow", "wrist 1", "wrist 2", "wrist 3")}
WRIST = 4  # the joint whose zero (and 180 deg) is the wrist singularity
ELBOW = 2  # the joint a pose beyond the arm's reach would stretch


@dataclasses.dataclass(frozen=True)
class Reach:
    """The joints of every pose, (m, 6) deg, continuous; the branch used (0..7); the least distance
    of any joint from its limits (deg); the least |sin| of the wrist joint, as an angle (deg)."""

    joints: np.ndarray
    branch: int
    limit_margin: float
    wrist_margin: float


@dataclasses.dataclass(frozen=True)
class _Failure:
    row: int
    joint: int
    what: str


def _continuous(q: np.ndarray, limits: np.ndarray) -> np.ndarray:
    """q (m, 6) made continuous along the rows (np.unwrap, NaN rows bridged), each column then moved
    by whole turns to the middle of its limits."""
    filled = q.copy()
    bad = np.isnan(filled)
    if bad.any():
        idx = np.where(~bad, np.arange(q.shape[0])[:, None], 0)
        np.maximum.accumulate(idx, axis=0, out=idx)
        filled = np.take_along_axis(np.where(bad, 0.0, q), idx, axis=0)
    out = np.unwrap(filled, period=360.0, axis=0)
    if out.shape[0]:
        middle = 0.5 * (np.nanmin(out, axis=0) + np.nanmax(out, axis=0))
        out += 360.0 * np.round((limits.mean(axis=1) - middle) / 360.0)
    return np.where(bad, np.nan, out)


def _first_failure(q: np.ndarray, arm: Arm, cell: RobotCell) -> _Failure | None:
    """The first row (and joint) of a branch's joints q (m, 6) the arm cannot follow, or None."""
    lo, hi = arm.limits[:, 0], arm.limits[:, 1]
    checks = []
    nan = np.isnan(q).any(axis=1)
    if nan.any():
        checks.append(_Failure(int(np.argmax(nan)), ELBOW, "has no solution: the pose is beyond the arm's reach (the elbow "
                                                           "would have to stretch past straight)"))
    with np.errstate(invalid="ignore"):
        out = (q < lo) | (q > hi)
        rows = np.flatnonzero(out.any(axis=1))
        if rows.size:
            r = int(rows[0])
            j = int(np.argmax(out[r]))
            bound = lo[j] if q[r, j] < lo[j] else hi[j]
            checks.append(_Failure(r, j, f"at {q[r, j]:.2f} deg, beyond its limit {bound:g} deg"))
        wrist = np.degrees(np.arcsin(np.minimum(np.abs(np.sin(np.radians(q[:, WRIST]))), 1.0)))
        near = np.flatnonzero(wrist < cell.singularity_margin)
        if near.size:
            r = int(near[0])
            checks.append(_Failure(r, WRIST, f"at {q[r, WRIST]:.2f} deg, within {cell.singularity_margin:g} deg of the "
                                             f"wrist singularity (machine.robot.singularity_margin)"))
        step = np.abs(np.diff(q, axis=0))
        jumps = np.flatnonzero((step > cell.max_joint_step).any(axis=1))
        if jumps.size:
            r = int(jumps[0]) + 1
            j = int(np.argmax(step[r - 1]))
            checks.append(_Failure(r, j, f"jumps {step[r - 1, j]:.2f} deg from the pose before, more than "
                                         f"{cell.max_joint_step:g} deg (machine.robot.max_joint_step)"))
    return min(checks, key=lambda f: f.row) if checks else None


def check_reach(arm: Arm, cell: RobotCell, flange: np.ndarray, where: Callable[[int], str]) -> Reach:
    """The reach check of the flange poses (m, 4, 4) in the arm's base frame; where(row) names a row's
    pass. ExportError (exit 1) where no branch serves the whole program."""
    solutions = ik(arm, flange)
    best: tuple[float, int, np.ndarray] | None = None
    worst: tuple[int, int, _Failure] | None = None
    for b in range(BRANCHES):
        q = _continuous(solutions[:, b], arm.limits)
        failure = _first_failure(q, arm, cell)
        if failure is None:
            margin = float(np.min(np.minimum(q - arm.limits[:, 0], arm.limits[:, 1] - q))) if q.size else 0.0
            if best is None or margin > best[0]:
                best = (margin, b, q)
        elif worst is None or failure.row > worst[0]:
            worst = (failure.row, b, failure)
    if best is None:
        assert worst is not None
        f = worst[2]
        joint = f"joint {JOINT_NAMES[arm.maker][f.joint]} " if f.joint >= 0 else ""
        raise ExportError(f"{where(f.row)}, program row {f.row}: the {arm.name} cannot reach the pose: {joint}{f.what}; "
                          f"move the ring (machine.robot.positioner.origin), the arm's base or the mandrel's mount "
                          f"(machine.robot.tool)")
    margin, b, q = best
    wrist = float(np.min(np.degrees(np.arcsin(np.minimum(np.abs(np.sin(np.radians(q[:, WRIST]))), 1.0))))) \
        if q.size else 90.0
    return Reach(q, b, margin, wrist)
