"""winder.machine.reach: the configuration chosen by dynamic programming over the whole program. Poses
made by the forward kinematics of a joint path whose wrist (A5) passes through its singularity: no one
IK branch follows it (A4 and A6 flip by 180 deg at the crossing), so the sequence bridges once, to the
flipped wrist, and every row's joints land on its pose; without bridges it is refused at the crossing, naming a joint."""

from __future__ import annotations

import numpy as np
import pytest

from winder.config.arms import ARMS
from winder.config.robot import RobotCell
from winder.errors import ExportError
from winder.machine.arm_ik import fk
from winder.machine.reach import configure

POSITION_TOL_MM = 1e-6
ROWS = 41


def _path() -> np.ndarray:
    q = np.tile([130.4, -39.4, 3.5, 172.2, 0.0, 130.4], (ROWS, 1))  # the other branches past A2, A3 or A5 limits
    q[:, 4] = np.linspace(10.25, -9.75, ROWS)  # A5 through 0 between two rows
    q[:, 0] += np.linspace(0.0, 10.0, ROWS)
    return q


def test_wrist_through_its_singularity_bridges_once() -> None:
    arm = ARMS["kuka_kr16"]
    cell = RobotCell("kuka_kr16", singularity_margin=0.0, max_joint_step=20.0)
    poses = fk(arm, _path())
    reach = configure(arm, cell, poses, np.r_[np.inf, np.full(ROWS - 1, 1.0e4)], str)
    assert reach.bridges.size == 1
    row = int(reach.bridges[0])
    assert np.sign(reach.arrive[row, 4]) != np.sign(reach.joints[row, 4])  # the wrist flipped
    for q in (reach.joints, reach.arrive):
        assert np.max(np.abs(fk(arm, q)[:, :3, 3] - poses[:, :3, 3])) < POSITION_TOL_MM
    assert np.max(np.abs(np.diff(reach.joints[:row + 1], axis=0))) <= cell.max_joint_step
    assert np.max(np.abs(np.diff(reach.joints[row:], axis=0))) <= cell.max_joint_step


def test_without_bridges_the_jump_is_refused() -> None:
    arm = ARMS["kuka_kr16"]
    cell = RobotCell("kuka_kr16", singularity_margin=0.0, max_joint_step=20.0)
    with pytest.raises(ExportError, match=r"program row 21: the kuka_kr16 cannot reach the pose: joint A[1-6] "):
        configure(arm, cell, fk(arm, _path()), np.full(ROWS, np.inf), lambda r: f"row {r}")
