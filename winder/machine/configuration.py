"""How each controller names an arm's configuration (the inverse-kinematics branch a pose is reached in),
computed from the arm's own links (winder.config.arms), for every program row
(docs/math/10-robot-cell.md 10.3).

- KUKA's Status S (bit 0: the wrist centre behind axis A1, the overhead area; bit 1: A3 at or beyond the
  angle at which the wrist centre lines up with A2 and A3, which follows from the arm's a3 and d4; bit 2:
  A5 <= 0) and Turn T (bit i: axis i + 1 negative), as KUKA's system software documentation defines them.
- ABB's confdata (cf1, cf4, cf6: the quadrants of axes 1, 4 and 6; cfx: bit 2 the wrist centre behind
  axis 1, bit 1 behind the lower arm, bit 0 axis 5 negative), as ABB's RAPID reference defines them.
"""

from __future__ import annotations

import numpy as np

from winder.config.arms import Arm


def stretched_elbow(arm: Arm) -> float:
    """The controller's angle of joint 3 (deg) at which the wrist centre lies on the line through the
    axes of joints 2 and 3 (KUKA's S bit 1 turns there): in frame 2 the wrist centre is at the angle
    theta3 + atan2(d4, a3), on the upper arm's line where that is 0 or 180 deg; the one within joint 3's
    range."""
    link3, link4 = arm.links[2], arm.links[3]
    beta = np.degrees(np.arctan2(link4.d, link3.a))
    for theta in (-beta, 180.0 - beta):
        q = (link3.sign * (theta - link3.offset) + 180.0) % 360.0 - 180.0
        if link3.qlim[0] <= q <= link3.qlim[1]:
            return float(q)
    return float((link3.sign * (-beta - link3.offset) + 180.0) % 360.0 - 180.0)


def _wrist_centre(arm: Arm, flange: np.ndarray) -> np.ndarray:
    """(m, 3) the wrist centre (the flange less d6 along its z) in the base frame."""
    return flange[:, :3, 3] - abs(arm.links[5].d) * flange[:, :3, 2]


def kuka_status_turn(arm: Arm, joints: np.ndarray, flange: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(S (m,), T (m,)) ints of joints (m, 6) (deg) at the flange poses (m, 4, 4) (module docstring)."""
    wrist = _wrist_centre(arm, flange)
    a1 = np.radians(arm.links[0].sign * joints[:, 0])  # A1's turn about the base's z
    ahead = wrist[:, 0] * np.cos(a1) + wrist[:, 1] * np.sin(a1)
    s = ((ahead < 0.0).astype(int) + 2 * (joints[:, 2] >= stretched_elbow(arm)).astype(int)
         + 4 * (joints[:, 4] <= 0.0).astype(int))
    t = np.sum((joints < 0.0).astype(int) * (1 << np.arange(6)), axis=1)
    return s, t


def abb_confdata(arm: Arm, joints: np.ndarray, flange: np.ndarray) -> np.ndarray:
    """(m, 4) ints cf1, cf4, cf6, cfx of joints (m, 6) (deg) at the flange poses (m, 4, 4)."""
    wrist = _wrist_centre(arm, flange)
    d1, a1 = arm.links[0].d, arm.links[0].a
    turn = np.radians(joints[:, 0])
    ahead = wrist[:, 0] * np.cos(turn) + wrist[:, 1] * np.sin(turn) - a1
    up = wrist[:, 2] - d1
    lower = np.radians(joints[:, 1])  # the lower arm leans forward by axis 2 from the vertical
    behind_lower = (ahead * np.cos(lower) - up * np.sin(lower)) < 0.0
    cfx = 4 * (ahead + a1 < 0.0) + 2 * behind_lower + (joints[:, 4] < 0.0)
    quadrant = np.floor(joints[:, [0, 3, 5]] / 90.0).astype(int)
    return np.column_stack([quadrant, cfx.astype(int)])
