"""winder.machine.arm_ik against forward kinematics written here independently: KUKA's and ABB's as
the joint chains ROS-Industrial publishes (joint origins and axes in the zero pose, as URDF), the
UR10e from Universal Robots' published DH table, both with plain matrices."""

from __future__ import annotations

import numpy as np
import pytest

from winder.config.arms import ARMS
from winder.machine.arm_ik import fk, ik

POSITION_TOL_MM = 1e-6
ROTATION_TOL = 1e-9
# (origin of each joint in its parent's zero-pose frame (m), axis), then the flange (tool0) origin
# and its rotation about y: kuka_kr16_support/urdf/kr16_2_macro.xacro, abb_irb4600_support/urdf/
# irb4600_60_205_macro.xacro.
CHAINS = {
    "kuka_kr16": ([((0, 0, 0.675), (0, 0, -1)), ((0.26, 0, 0), (0, 1, 0)), ((0.68, 0, 0), (0, 1, 0)),
                   ((0.67, 0, -0.035), (-1, 0, 0)), ((0, 0, 0), (0, 1, 0)), ((0, 0, 0), (-1, 0, 0))],
                  (0.158, 0, 0)),
    "abb_irb4600": ([((0, 0, 0.495), (0, 0, 1)), ((0.175, 0, 0), (0, 1, 0)), ((0, 0, 0.9), (0, 1, 0)),
                     ((0, 0, 0.175), (1, 0, 0)), ((0.96, 0, 0), (0, 1, 0)), ((0.135, 0, 0), (1, 0, 0))],
                    (0, 0, 0)),
}
# The controller's Base frame is DH frame 0 (not ROS's base_link, turned 180 deg about z).
UR10E_DH = [(0.1807, 0, np.pi / 2), (0, -0.6127, 0), (0, -0.57155, 0), (0.17415, 0, np.pi / 2),
            (0.11985, 0, -np.pi / 2), (0.11655, 0, 0)]  # (d, a, alpha), m


def _rot(axis, angle: float) -> np.ndarray:
    k = np.asarray(axis, dtype=float)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


def _homog(r: np.ndarray, p) -> np.ndarray:
    t = np.eye(4)
    t[:3, :3], t[:3, 3] = r, p
    return t


def independent_fk(name: str, q_deg: np.ndarray) -> np.ndarray:
    """The flange pose (4, 4), mm, of one joint vector (controller's degrees)."""
    q = np.radians(q_deg)
    t = np.eye(4)
    if name == "ur10e":
        for (d, a, alpha), th in zip(UR10E_DH, q):
            t = t @ _homog(_rot((0, 0, 1), th), (0, 0, d)) @ _homog(_rot((1, 0, 0), alpha), (a, 0, 0))
    else:
        joints, flange = CHAINS[name]
        for (origin, axis), th in zip(joints, q):
            t = t @ _homog(np.eye(3), origin) @ _homog(_rot(axis, th), (0, 0, 0))
        t = t @ _homog(_rot((0, 1, 0), np.pi / 2), flange)
    t[:3, 3] *= 1000.0
    return t


def _random_joints(name: str, n: int, seed: int) -> np.ndarray:
    arm = ARMS[name]
    rng = np.random.default_rng(seed)
    lo, hi = np.maximum(arm.limits[:, 0], -170.0), np.minimum(arm.limits[:, 1], 170.0)
    return rng.uniform(lo, hi, (n, 6))


@pytest.mark.parametrize("name", sorted(ARMS))
def test_fk_matches_the_published_kinematics(name: str) -> None:
    q = _random_joints(name, 50, 3)
    ours = fk(ARMS[name], q)
    for k in range(q.shape[0]):
        theirs = independent_fk(name, q[k])
        assert np.max(np.abs(ours[k, :3, 3] - theirs[:3, 3])) < POSITION_TOL_MM
        assert np.max(np.abs(ours[k, :3, :3] - theirs[:3, :3])) < ROTATION_TOL


@pytest.mark.parametrize("name", sorted(ARMS))
def test_ik_finds_the_joints_and_every_branch_lands(name: str) -> None:
    q = _random_joints(name, 100, 7)
    poses = np.array([independent_fk(name, row) for row in q])
    solutions = ik(ARMS[name], poses)
    found = np.abs((solutions - q[:, None, :] + 180.0) % 360.0 - 180.0).max(axis=2)
    assert np.all(np.nanmin(found, axis=1) < 1e-6)  # the joints that made the pose are a branch
    for k in range(q.shape[0]):
        for branch in solutions[k]:
            if np.isnan(branch).any():
                continue
            back = independent_fk(name, branch)
            assert np.max(np.abs(back[:3, 3] - poses[k, :3, 3])) < POSITION_TOL_MM * 10
            assert np.max(np.abs(back[:3, :3] - poses[k, :3, :3])) < ROTATION_TOL * 10


def test_ur10e_zero_pose_in_the_controllers_base() -> None:
    """All joints at zero, the UR controller reports the flange at x = a2 + a3, y = -(d4 + d6),
    z = d1 - d5 in its Base frame (UR's published DH table): winder's base frame is the controller's."""
    pose = fk(ARMS["ur10e"], np.zeros(6))
    expected = np.array([-612.7 - 571.55, -(174.15 + 116.55), 180.7 - 119.85])
    assert np.max(np.abs(pose[:3, 3] - expected)) < POSITION_TOL_MM


def test_arms_are_named_links() -> None:
    """Each arm is six named links with its DH numbers, range and speed; KUKA's Status bit 1 turns
    where the wrist centre lines up with A2 and A3: A3 = -atan(a3 / |d4|) on the KR 16 (35, 670 mm)."""
    from winder.machine.configuration import stretched_elbow  # noqa: PLC0415

    kuka = ARMS["kuka_kr16"]
    assert kuka.joint_names == ("A1", "A2", "A3", "A4", "A5", "A6")
    assert (kuka.links[2].a, kuka.links[3].d, kuka.links[4].qlim) == (35, -670, (-130, 130))
    assert abs(stretched_elbow(kuka) - (-np.degrees(np.arctan(35.0 / 670.0)))) < 1e-9
    assert ARMS["ur10e"].language == "urscript" and ARMS["abb_irb4600"].configuration == "abb"
