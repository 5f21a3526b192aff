"""Reading a robot cell's program back (KRL .src + .dat, RAPID .mod, URScript .script): each
language's own small reader to the station frames S(t*), the ring's axes and each move's time, then
the cell's forward kinematics (winder.machine.cell.eye_of) to the eye in the mandrel frame, at every
programmed pose and halfway along every move (the pose interpolated as the controller does: the
position linearly, the rotation by slerp, the external axes linearly). No parser of these languages
exists on the registries; these read what winder writes, and refuse what is not that, naming the line.
"""

from __future__ import annotations

import re
from collections.abc import Iterator

import numpy as np

from winder.config.controllers import read_pattern
from winder.config.machine import MachineConfig
from winder.errors import ConfigError
from winder.readback.parsed import ParsedProgram
from winder.readback.program_file import CELL_LINES
from winder.machine.cell import eye_of, mandrel_in_base

_PASS = re.compile(r"^\s*(?:;|!|#)\s*layer\s+(\d+)\s+circuit\s+(\d+)\s+pass\s+(\d+)\s+(\w+)\s*$")
_JOB = re.compile(r"^\s*(?:;|!|#)\s*job:\s*(.*)$")
_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
_E6POS = re.compile(r"^\s*DECL\s+E6POS\s+(\w+)\s*=\s*\{(.*)\}\s*$", re.I)
_ROBTARGET = re.compile(r"^\s*CONST\s+robtarget\s+(\w+)\s*:=\s*\[\[(.*)\]\]\s*;\s*$")
_MOVEL = re.compile(rf"^\s*MoveL\s+(\w+)\s*,\s*\w+\s*\\T:=({_NUMBER})\s*,\s*\w+\s*,\s*\w+\s*\\WObj:=\w+\s*;\s*$")
_RING = re.compile(rf"^\s*ring\(({_NUMBER}),\s*({_NUMBER}),\s*({_NUMBER}),\s*({_NUMBER})\)\s*$")
_URMOVE = re.compile(rf"^\s*movel\(p\[([^\]]*)\],\s*a=({_NUMBER}),\s*v=({_NUMBER}),\s*t=({_NUMBER}),\s*r=({_NUMBER})\)\s*$")
QUATERNION_TOL = 1e-6  # |q| - 1 of a written quaternion


def detect_cell(text: str) -> str | None:
    """krl, rapid or urscript when the text is one of those programs, else None (the lines
    winder.readback.program_file's survey looks for, line by line, in a file)."""
    return next((name for name, line in CELL_LINES if line.search(text)), None)


def _rz_ry_rx(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    from scipy.spatial.transform import Rotation  # noqa: PLC0415 - slow to import

    return Rotation.from_euler("ZYX", np.column_stack([a, b, c]), degrees=True).as_matrix()


def _frames(xyz: np.ndarray, rot: np.ndarray) -> np.ndarray:
    out = np.zeros((xyz.shape[0], 4, 4))
    out[:, :3, :3], out[:, :3, 3], out[:, 3, 3] = rot, xyz, 1.0
    return out


class _Rows:
    """The rows a reader collects: (frame fields, external axes, time, pass key, kind, line)."""

    def __init__(self, source: str, machine: MachineConfig | None = None) -> None:
        self.source = source
        controller = machine.controller if machine is not None else None
        tension = controller.tension if controller is not None else None
        self._tension = read_pattern(tension) if tension else None
        self._controller, self.tension, self.tensions = controller, np.nan, []
        self.key, self.kind, self.job = (0, 0, 0), "", None
        self.keys: list[tuple[int, int, int]] = []
        self.kinds: list[str] = []
        self.lines: list[int] = []
        self.times: list[float] = []

    def comment(self, line: str) -> bool:
        """Whether the line is a comment or the tension command (read as they pass)."""
        set_to = self._tension.match(line) if self._tension is not None else None
        if set_to:
            self.tension = self._controller.newtons(set_to.groupdict())
            return True
        hit = _PASS.match(line)
        if hit:
            self.key, self.kind = (int(hit[1]), int(hit[2]), int(hit[3])), hit[4]
            return True
        hit = _JOB.match(line)
        if hit and self.job is None:
            self.job = hit[1].strip()
        return line.lstrip()[:1] in (";", "!", "#")

    def code_lines(self, text: str, last: str, unended: str) -> Iterator[tuple[int, str, str]]:
        """(line number, stripped line, raw line) of each line that is neither blank nor a comment
        (comments read as they pass); ConfigError `unended` when the text's last line is not `last`."""
        lines = text.splitlines()
        if not (lines and lines[-1].strip() == last):
            raise ConfigError(f"{self.source}: {unended}: cut short?")
        for number, raw in enumerate(lines, start=1):
            line = raw.strip()
            if line and not self.comment(line):
                yield number, line, raw

    def add(self, number: int, seconds: float, raw: str) -> None:
        if self.key == (0, 0, 0):
            raise ConfigError(f"{self.source}: line {number}: a move before any 'layer L circuit C pass P kind' comment, "
                              f"got {raw.strip()[:60]!r}")
        self.keys.append(self.key)
        self.kinds.append(self.kind)
        self.lines.append(number)
        self.times.append(seconds)
        self.tensions.append(self.tension)


def _fields(body: str, number: int, source: str) -> dict[str, float]:
    out = {}
    for part in body.split(","):
        words = part.split()
        if len(words) != 2:
            raise ConfigError(f"{source}: line {number}: unreadable E6POS component {part.strip()!r}")
        try:
            out[words[0].upper()] = float(words[1])
        except ValueError as exc:
            raise ConfigError(f"{source}: line {number}: unreadable number in {part.strip()!r}") from exc
    return out


def _krl(text: str, machine: MachineConfig, source: str) -> tuple[_Rows, np.ndarray, np.ndarray]:
    src, _, dat = text.partition("&ACCESS RVP\n&REL 1\nDEFDAT") if "DEFDAT" in text else (text, "", "")
    if not dat:
        raise ConfigError(f"{source}: a KRL program needs its .dat (DEFDAT ... ENDDAT) beside the .src")
    points: dict[str, dict[str, float]] = {}
    dat_lines = ("DEFDAT" + dat).splitlines()
    if not dat_lines[-1].strip().upper() == "ENDDAT":
        raise ConfigError(f"{source}: the .dat does not end with ENDDAT: cut short?")
    for k, line in enumerate(dat_lines, start=1):
        hit = _E6POS.match(line)
        if hit:
            points[hit[1].upper()] = _fields(hit[2], k, source)
    rows = _Rows(source, machine)
    names: list[str] = []
    speed, share, mode = np.nan, 100.0, "cp"
    code = [(n, raw) for n, raw in enumerate(src.splitlines(), start=1)]
    ended = False
    top_e1 = machine.dynamics.rotation.speed / 60.0
    for number, raw in code:
        line = raw.strip()
        if not line or rows.comment(line):
            continue
        if ended:
            raise ConfigError(f"{source}: line {number}: code after END, got {line[:60]!r}")
        upper = line.split(";")[0].strip()
        if upper.upper() == "END":
            ended = True
        elif upper.startswith("$VEL.CP"):
            speed, mode = float(upper.split("=")[1]), "cp"
        elif upper.startswith("$VEL_EXTAX[1]"):
            share = float(upper.split("=")[1])
            mode = "ext" if share < 100.0 else mode
        elif upper.upper().startswith("LIN "):
            name = upper.split()[1].upper()
            if name not in points:
                raise ConfigError(f"{source}: line {number}: {name} is not declared in the .dat")
            p = points[name]
            if names:
                q = points[names[-1]]
                if mode == "cp":
                    dist = np.sqrt((p["X"] - q["X"]) ** 2 + (p["Y"] - q["Y"]) ** 2 + (p["Z"] - q["Z"]) ** 2)
                    seconds = dist / (speed * 1000.0)
                else:
                    seconds = abs(p["E1"] - q["E1"]) / (share / 100.0 * top_e1)
            else:
                seconds = 0.0
            rows.add(number, seconds, raw)
            names.append(name)
    if not ended:
        raise ConfigError(f"{source}: the .src stops without END: cut short?")
    table = np.array([[points[n][k] for k in ("X", "Y", "Z", "A", "B", "C", "E1", "E2", "E3")] for n in names])
    table = table.reshape(-1, 9)
    frames = _frames(table[:, :3], _rz_ry_rx(table[:, 3], table[:, 4], table[:, 5]))
    return rows, frames, table[:, 6:9]


def _rapid(text: str, machine: MachineConfig, source: str) -> tuple[_Rows, np.ndarray, np.ndarray]:
    from scipy.spatial.transform import Rotation  # noqa: PLC0415

    targets: dict[str, list[float]] = {}
    rows = _Rows(source, machine)
    names: list[str] = []
    for number, line, raw in rows.code_lines(text, "ENDMODULE", "the module does not end with ENDMODULE"):
        hit = _ROBTARGET.match(line)
        if hit:
            parts = [p for p in re.split(r"\]\s*,\s*\[", hit[2])]
            try:
                values = [float(v) for part in (parts[0], parts[1], parts[3]) for v in part.split(",")[:4]]
            except (ValueError, IndexError) as exc:
                raise ConfigError(f"{source}: line {number}: unreadable robtarget {line[:60]!r}") from exc
            norm = np.linalg.norm(values[3:7])
            if abs(norm - 1.0) > QUATERNION_TOL:
                raise ConfigError(f"{source}: line {number}: the orientation must be a unit quaternion, got norm {norm:.9f}")
            targets[hit[1]] = values[:10]
            continue
        hit = _MOVEL.match(line)
        if hit:
            if hit[1] not in targets:
                raise ConfigError(f"{source}: line {number}: {hit[1]} is not declared before its move")
            rows.add(number, float(hit[2]) if names else 0.0, raw)
            names.append(hit[1])
    table = np.array([targets[n] for n in names]).reshape(-1, 10)
    w, xyz_q = table[:, 3], table[:, 4:7]
    rot = Rotation.from_quat(np.column_stack([xyz_q, w])).as_matrix() if table.shape[0] else np.zeros((0, 3, 3))
    return rows, _frames(table[:, :3], rot), table[:, 7:10]


def _urscript(text: str, machine: MachineConfig, source: str) -> tuple[_Rows, np.ndarray, np.ndarray]:
    from scipy.spatial.transform import Rotation  # noqa: PLC0415

    rows = _Rows(source, machine)
    poses, ring = [], None
    external = []
    for number, line, raw in rows.code_lines(text, "end", "the script does not end with its function's end"):
        hit = _RING.match(line)
        if hit:
            ring = [float(hit[1]), float(hit[2]), float(hit[3])]
            continue
        hit = _URMOVE.match(line)
        if hit:
            if ring is None:
                raise ConfigError(f"{source}: line {number}: a movel without the ring's targets before it")
            pose = [float(v) for v in hit[1].split(",")]
            if len(pose) != 6:
                raise ConfigError(f"{source}: line {number}: a pose has 6 numbers, got {len(pose)}")
            rows.add(number, float(hit[4]) if poses else 0.0, raw)
            poses.append(pose)
            external.append(ring)
    table = np.array(poses, dtype=float).reshape(-1, 6)
    mandrel = _frames(1000.0 * table[:, :3], Rotation.from_rotvec(table[:, 3:]).as_matrix()
                      if table.shape[0] else np.zeros((0, 3, 3)))
    # The ring's frame in the mandrel frame: mandrel_in_base of the identity station is the ring in the base.
    ring_in_base = mandrel_in_base(machine.cell, np.eye(4)[None])[0]
    frames = np.linalg.inv(mandrel) @ ring_in_base
    return rows, frames, np.array(external, dtype=float).reshape(-1, 3)


def _midpoints(frames: np.ndarray, external: np.ndarray) -> np.ndarray:
    """The eye halfway along the move to each row (m, 3) (row 0: the row itself)."""
    from scipy.spatial.transform import Rotation  # noqa: PLC0415

    if frames.shape[0] < 2:
        return eye_of(frames, external)
    r0 = Rotation.from_matrix(frames[:-1, :3, :3])
    r1 = Rotation.from_matrix(frames[1:, :3, :3])
    half = r0 * Rotation.from_rotvec(0.5 * (r0.inv() * r1).as_rotvec())
    mid = _frames(0.5 * (frames[:-1, :3, 3] + frames[1:, :3, 3]), half.as_matrix())
    eyes = eye_of(mid, 0.5 * (external[:-1] + external[1:]))
    return np.vstack([eye_of(frames[:1], external[:1]), eyes])


def parse_cell(text: str, machine: MachineConfig, source: str, dialect: str):
    """The ParsedProgram (winder.readback.gcode) of a robot cell's program."""

    if machine.cell is None:
        raise ConfigError(f"{source}: a {dialect} program needs the robot cell it was written for: the config's "
                          f"machine.robot must be a mapping with an arm")
    if dialect == "krl":
        rows, frames, external = _krl(text, machine, source)
    elif dialect == "rapid":
        rows, frames, external = _rapid(text, machine, source)
    else:
        rows, frames, external = _urscript(text, machine, source)
    if not rows.keys:
        raise ConfigError(f"{source}: the program has no moves")
    eye = eye_of(frames, external)
    values = np.column_stack([eye, np.zeros_like(eye)])
    return ParsedProgram(dialect, values, np.array(rows.keys, dtype=int).reshape(-1, 3), tuple(rows.kinds),
                         np.full(len(rows.keys), np.nan), np.array(rows.lines, dtype=int), rows.job,
                         mids=_midpoints(frames, external), move_s=np.array(rows.times),
                         tension=np.array(rows.tensions, dtype=float))
