"""`machine.robot` as a robot cell (docs/math/10-robot-cell.md): the arm, its base in the cell, the
mandrel's mount on its flange (`tool`), the winding ring (`positioner`) with its external axes, and the
reach check's margins. `machine.robot: true` (eye poses only, no cell) stays as it was."""

from __future__ import annotations

import dataclasses
import re
from typing import TYPE_CHECKING, Any

import numpy as np

from winder.config.arms import ARMS

if TYPE_CHECKING:
    from winder.config.reader import Reader

# The longest module name of each cell language (its identifiers; the file's name is the module's):
# KRL 24 characters, RAPID 32, a URScript function 63.
NAME_LENGTH = {"krl": 24, "rapid": 32, "urscript": 63}
LANGUAGE_TITLE = {"krl": "KRL", "rapid": "RAPID", "urscript": "URScript"}
# The largest program (bytes of all its files) taken to fit each language's controller; a larger one is
# written as a main program calling one subprogram per layer (docs/math/10-robot-cell.md 10.10).
# `machine.robot.program_limit` overrides it. Sources (field reports; the makers publish none):
# KRL: a KR C4 on KSS 8.3 keeps its programs in a RAM drive of about 4 MB (robot-forum.com thread
# 49620, "KRC4 program capacity", 2024; about 8 MB in R1 per industrialmonitordirect.com). RAPID: no
# figure found for an IRC5 module; KRL's 4 MB taken. URScript: a script is streamed, an 18 MB script
# of 200,000 lines crashed PolyScope (zhangty019/S3_DeformFDM issue 19): 16 MB.
PROGRAM_LIMIT = {"krl": 4_000_000, "rapid": 4_000_000, "urscript": 16_000_000}
MIN_PROGRAM_LIMIT = 1000  # bytes: a smaller limit would split even a header
POSE_KEYS = ("x", "y", "z", "rx", "ry", "rz")
DEFAULT_TOOL = {"z": 250.0}  # the mandrel's origin 250 mm out from the flange, axes as the flange's
# The ring 1 m in front of the arm, 800 mm up, its axis across (the cell's +y), its x axis up: the
# flange then stays square to the forearm (the wrist far from its singularity) while the mandrel's
# bend turns it (docs/math/10-robot-cell.md 10.1).
DEFAULT_RING = {"x": 1000.0, "y": 0.0, "z": 800.0, "rx": 0.0, "ry": -90.0, "rz": -90.0}
DEFAULT_AXES = 2
DEFAULT_RING_WIDTH = 60.0  # mm: the ring's body along its axis
DEFAULT_RING_DEPTH = 80.0  # mm: the ring's body outward from its inner face
DEFAULT_JOINT_STEP = 20.0  # deg between consecutive poses
DEFAULT_SINGULARITY_MARGIN = 5.0  # deg of the wrist from its singularity
MAX_CELL_SIZE = 20000.0  # mm: no cell is larger


@dataclasses.dataclass(frozen=True)
class Pose:
    """A frame: position (mm) and rotations (deg), R = Rz(rz) Ry(ry) Rx(rx)."""

    x: float = 0.0
    y: float = 0.0
    z: float = 0.0
    rx: float = 0.0
    ry: float = 0.0
    rz: float = 0.0

    def matrix(self) -> np.ndarray:
        """The homogeneous transform (4, 4)."""
        a, b, c = np.radians([self.rz, self.ry, self.rx])
        rz = np.array([[np.cos(a), -np.sin(a), 0.0], [np.sin(a), np.cos(a), 0.0], [0.0, 0.0, 1.0]])
        ry = np.array([[np.cos(b), 0.0, np.sin(b)], [0.0, 1.0, 0.0], [-np.sin(b), 0.0, np.cos(b)]])
        rx = np.array([[1.0, 0.0, 0.0], [0.0, np.cos(c), -np.sin(c)], [0.0, np.sin(c), np.cos(c)]])
        out = np.eye(4)
        out[:3, :3] = rz @ ry @ rx
        out[:3, 3] = (self.x, self.y, self.z)
        return out


@dataclasses.dataclass(frozen=True)
class RobotCell:
    """A robot cell (YAML `machine.robot` as a mapping).

    arm : a name of winder.config.arms.ARMS. base : the arm's base in the cell. tool : the mandrel
    frame on the flange. ring : the winding ring's centre and axis (its z) in the cell
    (`positioner.origin`). axes : the ring's external axes, 1 (E1 the ring's turn), 2 (and E2 the
    eye's yaw, keeping a flat band flat), 3 (and E3 the eye's radial slide). max_joint_step (deg),
    singularity_margin (deg): the reach check's limits. ring_width, ring_depth (mm): the ring's body
    (positioner width and depth) that no link may touch (winder.machine.links). program_limit (bytes):
    the program size above which each layer is a subprogram (PROGRAM_LIMIT when None).
    """

    arm: str
    base: Pose = Pose()
    tool: Pose = Pose(**DEFAULT_TOOL)
    ring: Pose = Pose(**DEFAULT_RING)
    axes: int = DEFAULT_AXES
    max_joint_step: float = DEFAULT_JOINT_STEP
    singularity_margin: float = DEFAULT_SINGULARITY_MARGIN
    ring_width: float = DEFAULT_RING_WIDTH
    ring_depth: float = DEFAULT_RING_DEPTH
    program_limit: int | None = None  # bytes: PROGRAM_LIMIT's of the arm's language when None


def program_limit(cell: RobotCell, language: str) -> int:
    """The size (bytes) above which the cell's program in the language is split per layer."""
    return cell.program_limit if cell.program_limit is not None else PROGRAM_LIMIT[language]


def subprogram_name(layer: int) -> str:
    """The name of a layer's subprogram in RAPID and URScript (KRL's is a module of its own:
    winder.export.dialects.krl.layer_module)."""
    return f"layer_{layer}"


def name_problem(name: str, language: str) -> str | None:
    """Why the job's name cannot name the language's module (letters, digits and _, starting with a
    letter, at most NAME_LENGTH characters, not a layer's subprogram's), or None."""
    longest = NAME_LENGTH[language]
    if language == "krl" and re.fullmatch(r"(?i).*_L[0-9]+", name):
        return ("KRL programs split per layer name each layer's module <name>_L<N>: a job's name cannot end in "
                "_L and a number")
    if re.fullmatch(r"(?i)layer_[0-9]+", name):
        return (f"{LANGUAGE_TITLE[language]} programs name each layer's subprogram layer_N: rename the job (its "
                f"module's name)")
    if re.fullmatch(rf"[A-Za-z][A-Za-z0-9_]{{0,{longest - 1}}}", name):
        return None
    return (f"{LANGUAGE_TITLE[language]} needs a module name of letters, digits and _, starting with a letter, at "
            f"most {longest} characters, the same as its file's: rename the job")


def language_problem(cell: RobotCell, language: str) -> str | None:
    """Why the cell's arm cannot run the language, or None."""
    arm = ARMS[cell.arm]
    if arm.language == language:
        return None
    return (f"{LANGUAGE_TITLE.get(language, language)} is not the language of the cell's arm: {arm.name}'s "
            f"{arm.maker} controller runs {arm.language}")


def parse_pose(rd: Reader, value: Any, path: str, default: dict | None = None) -> Pose:
    m = rd.mapping(value, path, POSE_KEYS)
    values = dict(default or {})
    for key, v in m.items():
        number = rd.number(v, rd.at(path, key))
        limit = MAX_CELL_SIZE if key in ("x", "y", "z") else 360.0
        if abs(number) > limit:
            raise rd.error(rd.at(path, key), f"must be within +-{limit:g} ({'mm' if limit > 360 else 'deg'})", v)
        values[key] = number
    return Pose(**values)


def parse_robot_cell(rd: Reader, value: dict, path: str) -> RobotCell:
    """The cell of `machine.robot: {arm: ..., ...}`."""
    m = rd.mapping(value, path, ("arm", "base", "tool", "positioner", "max_joint_step", "singularity_margin",
                                      "program_limit"),
                   required=("arm",))
    arm = m["arm"]
    if not isinstance(arm, str) or arm not in ARMS:
        raise rd.error(rd.at(path, "arm"), f"must be one of {', '.join(ARMS)}", arm)
    base = parse_pose(rd, m["base"], rd.at(path, "base")) if "base" in m else Pose()
    tool = parse_pose(rd, m["tool"], rd.at(path, "tool")) if "tool" in m else Pose(**DEFAULT_TOOL)
    ring, axes = Pose(**DEFAULT_RING), DEFAULT_AXES
    size = {"width": DEFAULT_RING_WIDTH, "depth": DEFAULT_RING_DEPTH}
    if "positioner" in m:
        where = rd.at(path, "positioner")
        pm = rd.mapping(m["positioner"], where, ("axes", "origin", "width", "depth"))
        if "axes" in pm:
            axes = rd.integer(pm["axes"], rd.at(where, "axes"), 1, 3,
                              "must be 1 (the ring's turn), 2 (and the eye's yaw) or 3 (and its radial slide)")
        if "origin" in pm:
            ring = parse_pose(rd, pm["origin"], rd.at(where, "origin"))
        for key in ("width", "depth"):
            if key in pm:
                size[key] = rd.positive(pm[key], rd.at(where, key))
                if size[key] > MAX_CELL_SIZE:
                    raise rd.error(rd.at(where, key), f"must be at most {MAX_CELL_SIZE:g} mm", pm[key])
    step = rd.positive(m.get("max_joint_step", DEFAULT_JOINT_STEP), rd.at(path, "max_joint_step"))
    if step > 180.0:
        raise rd.error(rd.at(path, "max_joint_step"), "must be <= 180 deg (a larger step is a flip)",
                       m["max_joint_step"])
    margin = rd.number(m.get("singularity_margin", DEFAULT_SINGULARITY_MARGIN), rd.at(path, "singularity_margin"))
    if not 0.0 <= margin < 90.0:
        raise rd.error(rd.at(path, "singularity_margin"), "must be >= 0 and < 90 deg", m["singularity_margin"])
    limit = None
    if "program_limit" in m:
        limit = rd.integer(m["program_limit"], rd.at(path, "program_limit"), MIN_PROGRAM_LIMIT, None,
                           f"must be a whole number of bytes >= {MIN_PROGRAM_LIMIT}")
    return RobotCell(arm, base, tool, ring, axes, step, margin, size["width"], size["depth"], limit)
