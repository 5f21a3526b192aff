"""A small table of real six-axis arms, each described by its named links as the data sheets list them
(docs/math/10-robot-cell.md 10.3), with their sources.

A link is one revolute joint and the body it turns, in standard Denavit-Hartenberg form as
roboticstoolbox's RevoluteDH(d=..., a=..., alpha=..., offset=..., qlim=...): T_(i-1,i) = Rz(theta_i)
Tz(d_i) Tx(a_i) Rx(alpha_i), lengths in mm, angles in degrees, and the controller's joint angle
q_i = sign_i * (theta_i - offset_i) (KUKA's A1, A4 and A6 turn the other way round). Each link also
carries its top speed and the capsule that bounds its body for the collision check
(winder.machine.links): a segment in the link's own DH frame and a radius.

`flange` is the rotation from DH frame 6 to the controller's flange frame (KUKA $FLANGE, ABB tool0, UR
tool flange: z out of the flange); `base` the rotation from the controller's robot base frame to DH
frame 0. `language` is the one its controller runs, `configuration` how that language names an inverse
kinematics branch (winder.machine.configuration): KUKA's Status and Turn, ABB's confdata, none for UR.

A KUKA or ABB arm here is a spherical wrist on an ortho-parallel base (alpha = -90, 0, -90, 90, -90,
0); the UR10e is the UR geometry (alpha = 90, 0, 0, 90, -90, 0). Each has its closed-form inverse
(winder.machine.arm_ik); the table is in config so that `check` names them without the machine stage.
"""

from __future__ import annotations

import dataclasses

import numpy as np

SPHERICAL = "spherical"  # KUKA / ABB: wrist centre at the intersection of axes 4, 5, 6
UR = "ur"  # three parallel axes (2, 3, 4) and an offset wrist


@dataclasses.dataclass(frozen=True, kw_only=True)
class Link:
    """One joint and its body: name (the controller's), d, a (mm), alpha (deg) its DH parameters,
    offset (deg) and sign the map to the controller's angle, qlim (deg) its range, speed (deg/s) its
    top speed, capsule ((2, 3) mm: the ends of the body's axis in the link's DH frame) and radius (mm)."""

    name: str
    d: float
    a: float
    alpha: float
    qlim: tuple[float, float]
    speed: float
    offset: float = 0.0
    sign: float = 1.0
    capsule: tuple[tuple[float, float, float], tuple[float, float, float]] = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
    radius: float = 0.0


@dataclasses.dataclass(frozen=True, kw_only=True)
class Arm:
    """One arm model: its links (six), flange and base rotations (module docstring), kind (SPHERICAL or
    UR: which closed form), language and configuration scheme, payload (kg), the maker's stated reach
    (mm, for `check`) and where the numbers come from."""

    name: str
    maker: str
    kind: str
    links: tuple[Link, ...]
    flange: np.ndarray
    base: np.ndarray
    language: str
    configuration: str
    payload: float
    reach: float
    source: str
    capsule_source: str
    body: tuple[tuple[float, float, float], tuple[float, float, float]]  # the base's capsule (DH frame 0)
    body_radius: float

    @property
    def dh(self) -> np.ndarray:
        """(6, 3) (d, a, alpha) per joint (mm, mm, deg)."""
        return np.array([(k.d, k.a, k.alpha) for k in self.links], dtype=float)

    @property
    def offset(self) -> np.ndarray:
        return np.array([k.offset for k in self.links], dtype=float)

    @property
    def sign(self) -> np.ndarray:
        return np.array([k.sign for k in self.links], dtype=float)

    @property
    def limits(self) -> np.ndarray:
        """(6, 2) the controller's joint ranges (deg)."""
        return np.array([k.qlim for k in self.links], dtype=float)

    @property
    def speed(self) -> np.ndarray:
        """(6,) top joint speeds (deg/s)."""
        return np.array([k.speed for k in self.links], dtype=float)

    @property
    def joint_names(self) -> tuple[str, ...]:
        return tuple(k.name for k in self.links)


_RX180 = np.diag([1.0, -1.0, -1.0])
_RZ180 = np.diag([-1.0, -1.0, 1.0])

# KUKA KR 16-2 (KR C4): lengths 675 / 260 / 680 / 35 / 670 / 158 mm, axis ranges A1 +-185, A2 -155..35,
# A3 -130..154, A4 +-350, A5 +-130, A6 +-350 deg and speeds 156 156 156 330 330 615 deg/s from KUKA's
# KR 16-2 data sheet, as transcribed (joint origins, axes and limits) in ROS-Industrial's
# kuka_experimental/kuka_kr16_support/urdf/kr16_2_macro.xacro. Zero pose: upper arm horizontal forward,
# A1 turns about -z, A4 and A6 about -x. Reach 1610 mm, payload 16 kg (data sheet).
KUKA_KR16 = Arm(
    name="kuka_kr16", maker="KUKA", kind=SPHERICAL, links=(
        Link(name="A1", d=675, a=260, alpha=-90, qlim=(-185, 185), speed=156, sign=-1,
             capsule=((-498, 341, 8), (137, -32, -48)), radius=314),
        Link(name="A2", d=0, a=680, alpha=0, qlim=(-155, 35), speed=156,
             capsule=((93, 1, -160), (-772, 0, -144)), radius=143),
        Link(name="A3", d=0, a=35, alpha=-90, qlim=(-130, 154), speed=156, offset=90,
             capsule=((-8, 42, 356), (-12, 10, -406)), radius=261),
        Link(name="A4", d=-670, a=0, alpha=90, qlim=(-350, 350), speed=330,
             capsule=((1, 278, -22), (0, -65, 42)), radius=96),
        Link(name="A5", d=0, a=0, alpha=-90, qlim=(-130, 130), speed=330,
             capsule=((-2, -41, 78), (1, 40, -148)), radius=115),
        Link(name="A6", d=-158, a=0, alpha=0, qlim=(-350, 350), speed=615,
             capsule=((0, 39, 6), (0, -39, 6)), radius=40)),
    flange=_RX180, base=np.eye(3), language="krl", configuration="kuka", payload=16.0, reach=1610.0,
    source="KUKA KR 16-2 data sheet; ROS-Industrial kuka_experimental kr16_2_macro.xacro",
    capsule_source="fitted to ROS-Industrial's collision meshes by bench/arm_capsules.py",
    body=((-431, 65, 138), (223, -45, 365)), body_radius=376)

# ABB IRB 4600-60/2.05 (IRC5): lengths 495 / 175 / 900 / 175 / 960 / 135 mm, axis ranges 1 +-180,
# 2 -90..150, 3 -180..75, 4 +-400, 5 -125..120, 6 +-400 deg and speeds 175 175 175 250 250 360 deg/s
# from ABB's IRB 4600 product specification (3HAC032885), as transcribed in ROS-Industrial's
# abb/abb_irb4600_support/urdf/irb4600_60_205_macro.xacro. Zero pose: upper arm vertical, forearm
# horizontal forward. Reach 2050 mm, payload 60 kg.
ABB_IRB4600 = Arm(
    name="abb_irb4600", maker="ABB", kind=SPHERICAL, links=(
        Link(name="axis 1", d=495, a=175, alpha=-90, qlim=(-180, 180), speed=175,
             capsule=((106, -147, 34), (-208, 405, -19)), radius=402),
        Link(name="axis 2", d=0, a=900, alpha=0, qlim=(-90, 150), speed=175, offset=-90,
             capsule=((101, -2, -188), (-1040, 0, -161)), radius=149),
        Link(name="axis 3", d=0, a=175, alpha=-90, qlim=(-180, 75), speed=175,
             capsule=((177, -30, -28), (-307, -121, 25)), radius=374),
        Link(name="axis 4", d=960, a=0, alpha=90, qlim=(-400, 400), speed=250,
             capsule=((0, 101, -11), (-13, -631, 12)), radius=134),
        Link(name="axis 5", d=0, a=0, alpha=-90, qlim=(-125, 120), speed=250,
             capsule=((19, 0, 78), (-10, 3, -80)), radius=90),
        Link(name="axis 6", d=135, a=0, alpha=0, qlim=(-400, 400), speed=360,
             capsule=((-4, 62, -17), (6, -62, -17)), radius=66)),
    flange=_RZ180, base=np.eye(3), language="rapid", configuration="abb", payload=60.0, reach=2050.0,
    source="ABB IRB 4600 product specification (60/2.05); ROS-Industrial abb irb4600_60_205_macro.xacro",
    capsule_source="fitted to ROS-Industrial's collision meshes by bench/arm_capsules.py",
    body=((282, -7, 55), (-404, 2, 159)), body_radius=281)

# Universal Robots UR10e: DH parameters d1 = 180.7, a2 = -612.7, a3 = -571.55, d4 = 174.15,
# d5 = 119.85, d6 = 116.55 mm, alpha = 90, 0, 0, 90, -90, 0 deg as published by Universal Robots
# ("Parameters for calculations of kinematics and dynamics", universal-robots.com, article 45257);
# every joint +-360 deg; speeds 120 120 180 180 180 180 deg/s, reach 1300 mm, payload 12.5 kg
# (UR10e technical specifications). The controller's Base frame is DH frame 0 (all joints at zero, the
# controller reports the tool flange at x = a2 + a3, y = -(d4 + d6), z = d1 - d5); ROS's base_link is
# that frame turned 180 deg about z, which the controller never uses.
UR10E = Arm(
    name="ur10e", maker="Universal Robots", kind=UR, links=(
        Link(name="base", d=180.7, a=0, alpha=90, qlim=(-360, 360), speed=120,
             capsule=((-95, 18, 89), (42, 78, -56)), radius=162),
        Link(name="shoulder", d=0, a=-612.7, alpha=0, qlim=(-360, 360), speed=120,
             capsule=((688, 0, 237), (-62, 0, 207)), radius=159),
        Link(name="elbow", d=0, a=-571.55, alpha=0, qlim=(-360, 360), speed=180,
             capsule=((633, 0, 44), (-46, -1, 15)), radius=100),
        Link(name="wrist 1", d=174.15, a=0, alpha=90, qlim=(-360, 360), speed=180,
             capsule=((0, 12, -56), (-3, -18, 73)), radius=82),
        Link(name="wrist 2", d=119.85, a=0, alpha=-90, qlim=(-360, 360), speed=180,
             capsule=((1, -8, -53), (0, 7, 72)), radius=72),
        Link(name="wrist 3", d=116.55, a=0, alpha=0, qlim=(-360, 360), speed=180,
             capsule=((0, 46, -11), (1, -53, -21)), radius=57)),
    flange=np.eye(3), base=np.eye(3), language="urscript", configuration="none", payload=12.5, reach=1300.0,
    source="Universal Robots, DH parameters of the e-Series (article 45257); UR10e technical specifications",
    capsule_source="fitted to ROS-Industrial's collision meshes by bench/arm_capsules.py",
    body=((12, -94, 34), (-11, 94, 34)), body_radius=102)

ARMS: dict[str, Arm] = {arm.name: arm for arm in (KUKA_KR16, ABB_IRB4600, UR10E)}
