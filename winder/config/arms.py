"""A small table of real six-axis arms: their kinematics as standard Denavit-Hartenberg parameters
(docs/math/10-robot-cell.md), how the DH angles map to the controller's joint angles, joint limits and
joint speeds, each with its source.

DH convention: T_(i-1,i) = Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i); lengths in mm, angles in degrees.
The controller's joint angle is q_i = sign_i * (theta_i - offset_i). `flange` is the rotation from DH
frame 6 to the controller's flange frame (KUKA $FLANGE, ABB tool0, UR tool flange: z out of the
flange); `base` the rotation from the controller's robot base frame to DH frame 0.

A KUKA or ABB arm here is a spherical wrist on an ortho-parallel base (alpha = -90, 0, -90, 90, -90,
0); the UR10e is the UR geometry (alpha = 90, 0, 0, 90, -90, 0). Each has its closed-form inverse
(winder.machine.arm_ik); a table in config so that `check` names them without the machine stage.
"""

from __future__ import annotations

import dataclasses

import numpy as np

SPHERICAL = "spherical"  # KUKA / ABB: wrist centre at the intersection of axes 4, 5, 6
UR = "ur"  # three parallel axes (2, 3, 4) and an offset wrist


@dataclasses.dataclass(frozen=True)
class Arm:
    """One arm model.

    dh : (6, 3) float, (d, a, alpha) per joint (mm, mm, deg). offset, sign : (6,) the map from DH
    theta to the controller's joint angle. limits : (6, 2) the controller's joint ranges (deg).
    speed : (6,) top joint speeds (deg/s). flange, base : (3, 3) rotations (module docstring).
    kind : SPHERICAL or UR (which closed form). source : where the numbers come from.
    payload : rated payload (kg); reach : the maker's stated reach (mm), for `check`.
    """

    name: str
    maker: str
    kind: str
    dh: np.ndarray
    offset: np.ndarray
    sign: np.ndarray
    limits: np.ndarray
    speed: np.ndarray
    flange: np.ndarray
    base: np.ndarray
    payload: float
    reach: float
    source: str


_RX180 = np.diag([1.0, -1.0, -1.0])
_RZ180 = np.diag([-1.0, -1.0, 1.0])


def _arm(name: str, maker: str, kind: str, dh: tuple, *, offset: tuple, sign: tuple, limits: tuple, speed: tuple,
         flange: np.ndarray, base: np.ndarray, payload: float, reach: float, source: str) -> Arm:
    """An Arm from its numbers as the data sheets list them: dh (d, a, alpha) joint after joint, limits
    (low, high) joint after joint."""
    return Arm(name=name, maker=maker, kind=kind, dh=np.array(dh, dtype=float).reshape(6, 3),
               offset=np.array(offset, dtype=float), sign=np.array(sign, dtype=float),
               limits=np.array(limits, dtype=float).reshape(6, 2), speed=np.array(speed, dtype=float), flange=flange,
               base=base, payload=payload, reach=reach, source=source)

# KUKA KR 16-2 (KR C4): lengths 675 / 260 / 680 / 35 / 670 / 158 mm, axis ranges A1 +-185, A2 -155..35,
# A3 -130..154, A4 +-350, A5 +-130, A6 +-350 deg and speeds 156 156 156 330 330 615 deg/s from KUKA's
# KR 16-2 data sheet, as transcribed (joint origins, axes and limits) in ROS-Industrial's
# kuka_experimental/kuka_kr16_support/urdf/kr16_2_macro.xacro. Zero pose: upper arm horizontal forward,
# A1 turns about -z, A4 and A6 about -x. Reach 1610 mm, payload 16 kg (data sheet).
KUKA_KR16 = _arm(
    "kuka_kr16", "KUKA", SPHERICAL, (675, 260, -90, 0, 680, 0, 0, 35, -90, -670, 0, 90, 0, 0, -90, -158, 0, 0),
    offset=(0, 0, 90, 0, 0, 0), sign=(-1, 1, 1, 1, 1, 1), limits=(-185, 185, -155, 35, -130, 154, -350, 350, -130, 130,
    -350, 350), speed=(156, 156, 156, 330, 330, 615), flange=_RX180, base=np.eye(3), payload=16.0, reach=1610.0,
    source="KUKA KR 16-2 data sheet; ROS-Industrial kuka_experimental kr16_2_macro.xacro")

# ABB IRB 4600-60/2.05 (IRC5): lengths 495 / 175 / 900 / 175 / 960 / 135 mm, axis ranges 1 +-180,
# 2 -90..150, 3 -180..75, 4 +-400, 5 -125..120, 6 +-400 deg and speeds 175 175 175 250 250 360 deg/s
# from ABB's IRB 4600 product specification (3HAC032885), as transcribed in ROS-Industrial's
# abb/abb_irb4600_support/urdf/irb4600_60_205_macro.xacro. Zero pose: upper arm vertical, forearm
# horizontal forward. Reach 2050 mm, payload 60 kg.
ABB_IRB4600 = _arm(
    "abb_irb4600", "ABB", SPHERICAL, (495, 175, -90, 0, 900, 0, 0, 175, -90, 960, 0, 90, 0, 0, -90, 135, 0, 0),
    offset=(0, -90, 0, 0, 0, 0), sign=(1, 1, 1, 1, 1, 1), limits=(-180, 180, -90, 150, -180, 75, -400, 400, -125, 120,
    -400, 400), speed=(175, 175, 175, 250, 250, 360), flange=_RZ180, base=np.eye(3), payload=60.0, reach=2050.0,
    source="ABB IRB 4600 product specification (60/2.05); ROS-Industrial abb irb4600_60_205_macro.xacro")

# Universal Robots UR10e: DH parameters d1 = 180.7, a2 = -612.7, a3 = -571.55, d4 = 174.15,
# d5 = 119.85, d6 = 116.55 mm, alpha = 90, 0, 0, 90, -90, 0 deg as published by Universal Robots
# ("Parameters for calculations of kinematics and dynamics", universal-robots.com, article 45257);
# every joint +-360 deg; speeds 120 120 180 180 180 180 deg/s, reach 1300 mm, payload 12.5 kg
# (UR10e technical specifications). The controller's base frame is DH frame 0 turned 180 deg about z.
UR10E = _arm(
    "ur10e", "Universal Robots", UR,
    (180.7, 0, 90, 0, -612.7, 0, 0, -571.55, 0, 174.15, 0, 90, 119.85, 0, -90, 116.55, 0, 0),
    offset=(0, 0, 0, 0, 0, 0), sign=(1, 1, 1, 1, 1, 1), limits=(-360, 360) * 6, speed=(120, 120, 180, 180, 180, 180),
    flange=np.eye(3), base=_RZ180, payload=12.5, reach=1300.0,
    source="Universal Robots, DH parameters of the e-Series (article 45257); UR10e technical specifications")

ARMS: dict[str, Arm] = {arm.name: arm for arm in (KUKA_KR16, ABB_IRB4600, UR10E)}
