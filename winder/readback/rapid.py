"""ABB RAPID read back (winder.export.dialects.rapid writes it): every line one of the statements below
or a comment, anything else refused naming its line (winder.readback.cells).

`MODULE name`, `PERS tooldata tRing := [FALSE,[[x,y,z],[q]],[1,[0,0,1],[1,0,0,0],0,0,0]];` (the ring, a
stationary tool), `PERS wobjdata wMandrel := [TRUE,TRUE,"",[[x,y,z],[q]],[[0,0,0],[1,0,0,0]]];` (the
mandrel's mount), `CONST jointtarget jName := [[6 joints],[3 axes,9E9,9E9,9E9]];`, `CONST robtarget
pN := [[x,y,z],[q],[cf1,cf4,cf6,cfx],[3 axes,9E9,9E9,9E9]];`, `PROC main()`, `ConfL \\Off;`, `MoveAbsJ
jStart, v100, fine, tRing \\WObj:=wMandrel;` (the start), `MoveL pN, v1000 \\T:=t, z0|fine, tRing
\\WObj:=wMandrel;`, `MoveAbsJ jBridgeN, v1000 \\T:=t, fine, tRing \\WObj:=wMandrel;` (a bridge, after a
MoveL to fine), `ENDPROC`, `ENDMODULE`. Quaternions unit within QUATERNION_TOL.
"""

from __future__ import annotations

import re

import numpy as np

from winder.config.machine import MachineConfig
from winder.errors import ConfigError
from winder.readback.cells import NUMBER, CellRead, Rows, frames_of, numbers, same_frame, seconds
from winder.readback.subprograms import RAPID, in_order

QUATERNION_TOL = 1e-6  # |q| - 1 of a written quaternion
_N = NUMBER
_NAME = r"[A-Za-z][A-Za-z0-9_]{0,31}"
_FIXED = {"PROC main()", "ConfL \\Off;", "ENDPROC"}
_MODULE = re.compile(rf"^MODULE ({_NAME})$")
_TOOL = re.compile(r"^PERS tooldata tRing := \[FALSE,\[\[([^\]]*)\],\[([^\]]*)\]\],\[1,\[0,0,1\],\[1,0,0,0\],0,0,0\]\];$")
_WOBJ = re.compile(r"^PERS wobjdata wMandrel := \[TRUE,TRUE,\"\",\[\[([^\]]*)\],\[([^\]]*)\]\],\[\[0,0,0\],\[1,0,0,0\]\]\];$")
_JOINTS = re.compile(rf"^CONST jointtarget ({_NAME}) := \[\[([^\]]*)\],\[([^\]]*)\]\];$")
_TARGET = re.compile(rf"^CONST robtarget ({_NAME}) := \[\[([^\]]*)\],\[([^\]]*)\],\[([^\]]*)\],\[([^\]]*)\]\];$")
_START = re.compile(r"^MoveAbsJ jStart, v100, fine, tRing \\WObj:=wMandrel;$")
_MOVEL = re.compile(rf"^MoveL ({_NAME}), v1000 \\T:=(\S+?), (z0|fine), tRing \\WObj:=wMandrel;$")
_BRIDGE = re.compile(rf"^MoveAbsJ ({_NAME}), v1000 \\T:=(\S+?), fine, tRing \\WObj:=wMandrel;$")


def _quaternion(body: str, source: str, line: int, what: str) -> np.ndarray:
    q = np.array(numbers(body, source, line, what, 4))
    norm = float(np.linalg.norm(q))
    if abs(norm - 1.0) > QUATERNION_TOL:
        raise ConfigError(f"{source}: line {line}: {what} must be a unit quaternion, got norm {norm:.9f}")
    return q


def _rotation(q: np.ndarray) -> np.ndarray:
    """Rotations (m, 3, 3) of quaternions (m, 4) (w, x, y, z)."""
    from scipy.spatial.transform import Rotation  # noqa: PLC0415

    if q.shape[0] == 0:
        return np.zeros((0, 3, 3))
    return Rotation.from_quat(np.column_stack([q[:, 1:], q[:, 0]])).as_matrix()


def _external(body: str, source: str, line: int, what: str) -> list[float]:
    parts = body.split(",")
    if len(parts) != 6 or [p.strip() for p in parts[3:]] != ["9E9"] * 3:
        raise ConfigError(f"{source}: line {line}: {what} must be 3 numbers then 9E9,9E9,9E9, got [{body[:60]}]")
    return numbers(",".join(parts[:3]), source, line, what, 3)


def read_rapid(text: str, machine: MachineConfig, source: str) -> CellRead:  # noqa: C901, PLR0912
    """The program's rows, frames and ring axes (module docstring)."""
    cell = machine.cell
    rows = Rows.of(source, machine)
    lines = text.splitlines()
    if not lines or lines[-1].strip() != "ENDMODULE":
        raise ConfigError(f"{source}: the module does not end with ENDMODULE: cut short?")
    module, ended = None, False
    targets: dict[str, np.ndarray] = {}
    joints: dict[str, np.ndarray] = {}
    table, bridges, start, start_line, last_zone = [], {}, None, 0, ""
    for n, raw in in_order(list(enumerate(lines, start=1)), RAPID, source):  # each layer's routine where called
        line = raw.strip()
        if not line or rows.comment(line, n):
            continue
        if ended:
            raise ConfigError(f"{source}: line {n}: code after ENDMODULE, got {line[:60]!r}")
        if module is None:
            hit = _MODULE.match(line)
            if not hit:
                raise ConfigError(f"{source}: line {n}: the module must start with MODULE name, got {line[:60]!r}")
            module = hit[1]
        elif line == "ENDMODULE":
            ended = True
        elif line in _FIXED:
            continue
        elif (hit := _TOOL.match(line)) or (hit := _WOBJ.match(line)):
            ring = line.startswith("PERS tooldata")
            frame = frames_of(np.array([numbers(hit[1], source, n, "the frame's origin", 3)]),
                              _rotation(_quaternion(hit[2], source, n, "the frame's orientation")[None]))[0]
            same_frame(cell.ring if ring else cell.tool, frame, source, n, "tRing's frame" if ring else "wMandrel's user frame",
                       "machine.robot.positioner.origin" if ring else "machine.robot.tool")
        elif hit := _JOINTS.match(line):
            joints[hit[1]] = np.array(numbers(hit[2], source, n, "the joints", 6))
            _external(hit[3], source, n, "the external axes")
        elif hit := _TARGET.match(line):
            xyz = numbers(hit[2], source, n, "the position", 3)
            q = _quaternion(hit[3], source, n, "the orientation")
            conf = hit[4].split(",")
            if len(conf) != 4 or not all(re.fullmatch(r"-?[0-9]{1,2}", c.strip()) for c in conf):
                raise ConfigError(f"{source}: line {n}: robconf must be four whole numbers, got [{hit[4][:40]}]")
            targets[hit[1]] = np.array(xyz + q.tolist() + _external(hit[5], source, n, "the external axes"))
        elif _START.match(line):
            if "jStart" not in joints or start is not None or table:
                raise ConfigError(f"{source}: line {n}: the start MoveAbsJ must come once, after jStart, before the moves")
            start, start_line = joints["jStart"], n
        elif hit := _MOVEL.match(line):
            if start is None or hit[1] not in targets:
                raise ConfigError(f"{source}: line {n}: {hit[1]} is not declared before its move, or no start MoveAbsJ")
            secs = seconds(hit[2], source, n, "\\T") if table else 0.0
            rows.add(n, secs, raw)
            table.append(targets[hit[1]])
            last_zone = hit[3]
        elif hit := _BRIDGE.match(line):
            if hit[1] not in joints or not table or last_zone != "fine" or len(table) - 1 in bridges:
                raise ConfigError(f"{source}: line {n}: a MoveAbsJ within the program (a bridge) must follow a MoveL "
                                  f"to fine and name a declared jointtarget, got {line[:60]!r}")
            seconds(hit[2], source, n, "\\T")
            bridges[len(table) - 1] = (joints[hit[1]], n)
        else:
            raise ConfigError(f"{source}: line {n}: not a statement of winder's RAPID modules, got {line[:60]!r}")
    arr = np.array(table, dtype=float).reshape(-1, 10)
    frames = frames_of(arr[:, :3], _rotation(arr[:, 3:7]))
    return CellRead(rows, frames, arr[:, 7:10], start if start is not None else np.zeros(6), start_line, bridges)
