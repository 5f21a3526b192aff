"""Reading a robot cell's program back (KRL .src + .dat, RAPID .mod, URScript .script), as strictly as
the G-code reader: each language's reader (winder.readback.krl, rapid, urscript) understands every line
or refuses it naming it (the controller's tension command, its description's `tension`, read as a
line of its own wherever it stands: each row runs at the tension last set before its move's line);
this module holds what they share and checks what they read against the config
(docs/math/10-robot-cell.md 10.8):

- numbers in ASCII digits only, finite, within the cell's size; times finite, positive, at most
  MAX_MOVE_S; the pass comments' numbers of at most 9 digits;
- the frames the program sets (KRL's $TOOL and $BASE, RAPID's tool and work object, URScript's TCP)
  equal to machine.robot's tool and ring within FRAME_TOL;
- the arm follows: the start joints within the limits and their flange (forward kinematics) on the
  first pose within the chord tolerance; then every pose reached by the inverse solution nearest the
  last joints (whole turns included), within the limits (JOINT_TOL), away from the wrist singularity,
  no joint stepping more than max_joint_step (another configuration is a jump, refused); a joint move
  within the program (a bridge) lands on the pose it starts from.

The eye in the mandrel frame then follows from the ring's axes (winder.machine.cell_frames.eye_of), at
every programmed pose and halfway along every move (the controller's interpolation: position
linearly, rotation by slerp, external axes linearly, URScript's ring on its own schedule).
"""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Callable

import numpy as np

from winder.config.arms import ARMS
from winder.config.machine import MachineConfig
from winder.config.robot import MAX_CELL_SIZE, Pose
from winder.errors import ConfigError
from winder.machine.arm_ik import fk, ik
from winder.machine.bridges import swap_time
from winder.machine.cell_frames import eye_of, mandrel_in_base
from winder.machine.reach import wrist_angle
from winder.readback.program_file import CELL_LINES

NUMBER = r"[-+]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][-+]?[0-9]{1,3})?"  # ASCII digits only
_PASS = re.compile(r"^\s*(?:;|!|#)\s*layer\s+([0-9]{1,9})\s+circuit\s+([0-9]{1,9})\s+pass\s+([0-9]{1,9})\s+([a-z]+)\s*$")
_PASS_LIKE = re.compile(r"^\s*(?:;|!|#)\s*layer\s+\S+\s+circuit\b")
_JOB = re.compile(r"^\s*(?:;|!|#)\s*job:\s*(.*)$")
FRAME_TOL = 1e-3  # mm and deg: a frame as written (3 decimals) against the config's
JOINT_TOL = 0.01  # deg: a joint read back from rounded poses may pass its limit by this much
MAX_MOVE_S = 3600.0  # s: no move of a winding program takes an hour
MAX_ANGLE = 1.0e7  # deg: a ring's cumulative turn (27,000 rounds)


def detect_cell(text: str) -> str | None:
    """krl, rapid or urscript when the text is one of those programs, else None (the lines
    winder.readback.program_file's survey looks for, line by line, in a file)."""
    return next((name for name, line in CELL_LINES if line.search(text)), None)


def number(text: str, source: str, line: int, what: str, low: float = -MAX_CELL_SIZE, high: float = MAX_CELL_SIZE) -> float:
    """A number of the program: ASCII digits, finite, within [low, high]; ConfigError naming the line."""
    if not re.fullmatch(NUMBER, text.strip()):
        raise ConfigError(f"{source}: line {line}: {what} must be a number in ASCII digits, got {text.strip()[:40]!r}")
    value = float(text)
    if not low <= value <= high:
        raise ConfigError(f"{source}: line {line}: {what} must be within [{low:g}, {high:g}], got {text.strip()[:40]}")
    return value


def seconds(text: str, source: str, line: int, what: str, least: float = 0.0) -> float:
    """A time or a speed: finite, positive and at least `least`, at most MAX_MOVE_S."""
    value = number(text, source, line, what, -MAX_MOVE_S, MAX_MOVE_S)
    if value <= 0.0 or value < least:
        bound = f"at least {least:g}" if least > 0.0 else "positive"
        raise ConfigError(f"{source}: line {line}: {what} must be {bound}, got {text.strip()[:40]}")
    return value


def numbers(body: str, source: str, line: int, what: str, count: int) -> list[float]:
    """count comma-separated numbers."""
    parts = body.split(",")
    if len(parts) != count:
        raise ConfigError(f"{source}: line {line}: {what} has {count} numbers, got {len(parts)}")
    return [number(p, source, line, what, -MAX_ANGLE, MAX_ANGLE) for p in parts]


def same_frame(pose: Pose, got: np.ndarray, source: str, line: int, what: str, key: str) -> None:
    """ConfigError unless the frame got (4, 4) is the config's pose within FRAME_TOL (mm; rad as deg)."""
    want = pose.matrix()
    off = float(np.linalg.norm(want[:3, 3] - got[:3, 3]))
    turn = float(np.degrees(np.arccos(np.clip((np.trace(want[:3, :3].T @ got[:3, :3]) - 1.0) / 2.0, -1.0, 1.0))))
    if off > FRAME_TOL or turn > FRAME_TOL:
        raise ConfigError(f"{source}: line {line}: {what} is {off:.3f} mm and {turn:.3f} deg off {key} of the config: "
                          f"the program was written for another cell")


@dataclasses.dataclass
class Rows:
    """What a reader collects, row by row: the pass key, kind, line and time of each pose, the job line."""

    source: str
    key: tuple[int, int, int] = (0, 0, 0)
    kind: str = ""
    job: str | None = None
    job_line: int | None = None
    keys: list = dataclasses.field(default_factory=list)
    kinds: list = dataclasses.field(default_factory=list)
    lines: list = dataclasses.field(default_factory=list)
    times: list = dataclasses.field(default_factory=list)
    read_tension: Callable[[str], float | None] | None = None  # the controller's (Controller.tension_reader)
    tension: float = float("nan")  # N: the tension set so far (nan before the first command)
    tensions: list = dataclasses.field(default_factory=list)

    @classmethod
    def of(cls, source: str, machine: MachineConfig) -> "Rows":
        """The rows of a program written for `machine` (its controller's tension command read)."""
        controller = machine.controller
        return cls(source=source, read_tension=controller.tension_reader() if controller is not None else None)

    def comment(self, line: str, number_: int) -> bool:
        """Whether the line is a comment or the tension command (read as they pass: pass and job
        comments, the tension set)."""
        set_to = self.read_tension(line) if self.read_tension is not None else None
        if set_to is not None:
            self.tension = set_to
            return True
        hit = _PASS.match(line)
        if hit:
            self.key, self.kind = (int(hit[1]), int(hit[2]), int(hit[3])), hit[4]
            return True
        if _PASS_LIKE.match(line):
            raise ConfigError(f"{self.source}: line {number_}: a pass comment must read 'layer L circuit C pass P kind' "
                              f"with numbers of at most 9 digits, got {line.strip()[:60]!r}")
        hit = _JOB.match(line)
        if hit and self.job is None:
            self.job, self.job_line = hit[1].strip(), number_
        return line.lstrip()[:1] in (";", "!", "#")

    def add(self, number_: int, secs: float, raw: str) -> None:
        if self.key == (0, 0, 0):
            raise ConfigError(f"{self.source}: line {number_}: a move before any 'layer L circuit C pass P kind' comment, "
                              f"got {raw.strip()[:60]!r}")
        self.keys.append(self.key)
        self.kinds.append(self.kind)
        self.lines.append(number_)
        self.times.append(secs)
        self.tensions.append(self.tension)


@dataclasses.dataclass(frozen=True)
class CellRead:
    """A cell program as read: its rows, the ring's frames in the mandrel frame (m, 4, 4), the ring's
    axes (m, 3), the start joints (6,) and their line, the bridges (row -> (joints, line)), the eye
    halfway along each move where the language times the ring itself (m, 3), else None, and a check
    of its own to run once the arm is known to follow (None: none)."""

    rows: Rows
    frames: np.ndarray
    external: np.ndarray
    start: np.ndarray
    start_line: int
    bridges: dict
    mids: np.ndarray | None = None
    then: Callable[[], None] | None = None


def _pick(solutions: np.ndarray, last: np.ndarray) -> np.ndarray:
    """The solution (6,) of solutions (8, 6) nearest the joints last (6,), each joint by whole turns."""
    shifted = solutions + 360.0 * np.round((last - solutions) / 360.0)
    step = np.max(np.abs(shifted - last), axis=1)
    step = np.where(np.isnan(step), np.inf, step)
    return shifted[int(np.argmin(step))]


def follow(machine: MachineConfig, read: CellRead, source: str) -> np.ndarray:
    """The joints (m, 6) the arm takes through the program (module docstring); ConfigError naming the
    line where it cannot."""
    cell = machine.cell
    arm = ARMS[cell.arm]
    lo, hi = arm.limits[:, 0] - JOINT_TOL, arm.limits[:, 1] + JOINT_TOL
    flange = mandrel_in_base(cell, read.frames) @ np.linalg.inv(cell.tool.matrix())
    solutions = ik(arm, flange)
    names = arm.joint_names
    q = np.asarray(read.start, dtype=float)
    lines = read.rows.lines

    def refuse(line: int, what: str) -> ConfigError:
        return ConfigError(f"{source}: line {line}: the {arm.name} cannot follow: {what}")

    def land(joints: np.ndarray, row: int, line: int, what: str) -> None:
        bad = np.flatnonzero((joints < lo) | (joints > hi))
        if bad.size:
            j = int(bad[0])
            raise refuse(line, f"{what} joint {names[j]} at {joints[j]:.3f} deg is beyond its limits "
                               f"[{arm.limits[j, 0]:g}, {arm.limits[j, 1]:g}] deg")
        off = float(np.linalg.norm(fk(arm, joints)[:3, 3] - flange[row, :3, 3]))
        if off > machine.chord_tolerance:
            raise refuse(line, f"{what} joints put the flange {off:.3f} mm from the pose of line {lines[row]}")

    land(q, 0, read.start_line, "the start")
    out = np.empty((flange.shape[0], 6))
    for row in range(flange.shape[0]):
        if np.isnan(solutions[row]).any(axis=1).all():
            raise refuse(lines[row], "the pose is beyond the arm's reach (no inverse kinematics solution)")
        nxt = _pick(solutions[row], q)
        step = np.abs(nxt - q)
        if row and step.max() > cell.max_joint_step:
            j = int(np.argmax(step))
            raise refuse(lines[row], f"joint {names[j]} jumps {step[j]:.2f} deg from the pose before (another "
                                     f"configuration), more than {cell.max_joint_step:g} deg")
        bad = np.flatnonzero((nxt < lo) | (nxt > hi))
        if bad.size:
            j = int(bad[0])
            raise refuse(lines[row], f"joint {names[j]} at {nxt[j]:.3f} deg is beyond its limits "
                                     f"[{arm.limits[j, 0]:g}, {arm.limits[j, 1]:g}] deg")
        if wrist_angle(nxt) < cell.singularity_margin - JOINT_TOL:
            raise refuse(lines[row], f"joint {names[4]} at {nxt[4]:.3f} deg is within {cell.singularity_margin:g} deg "
                                     f"of the wrist singularity")
        q = out[row] = nxt
        if row in read.bridges:
            joints, line = read.bridges[row]
            land(joints, row, line, "the bridge's")
            q = joints
    return out


def bridge_times(machine: MachineConfig, read: CellRead, joints: np.ndarray) -> np.ndarray:
    """(m,) each row's bridge's joint-move time (0 where none)."""
    arm = ARMS[machine.cell.arm]
    out = np.zeros(joints.shape[0])
    for row, (after, _) in read.bridges.items():
        out[row] = swap_time(arm, joints[row], after)
    return out


def frames_of(xyz: np.ndarray, rot: np.ndarray) -> np.ndarray:
    out = np.zeros((xyz.shape[0], 4, 4))
    out[:, :3, :3], out[:, :3, 3], out[:, 3, 3] = rot, xyz, 1.0
    return out


def midpoints(frames: np.ndarray, external: np.ndarray, halfway: np.ndarray | None = None) -> np.ndarray:
    """The eye halfway along the move to each row (m, 3) (row 0: the row itself): the pose halfway
    (position linearly, rotation by slerp) with the ring's axes halfway (halfway (m, 3) where the ring
    keeps a schedule of its own, else the mean of the two rows')."""
    from scipy.spatial.transform import Rotation  # noqa: PLC0415

    if frames.shape[0] < 2:
        return eye_of(frames, external)
    r0 = Rotation.from_matrix(frames[:-1, :3, :3])
    r1 = Rotation.from_matrix(frames[1:, :3, :3])
    half = r0 * Rotation.from_rotvec(0.5 * (r0.inv() * r1).as_rotvec())
    mid = frames_of(0.5 * (frames[:-1, :3, 3] + frames[1:, :3, 3]), half.as_matrix())
    eyes = eye_of(mid, 0.5 * (external[:-1] + external[1:]) if halfway is None else halfway[1:])
    return np.vstack([eye_of(frames[:1], external[:1]), eyes])
