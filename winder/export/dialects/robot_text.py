"""What the robot-cell dialects (krl.py, rapid.py, urscript.py) share: the header comments, the pass
comments simulate reads back, the rows worth a move, and the rotations in each language's form. They
serialize winder.machine.cell.CellMotion and compute nothing else."""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np

from winder.config.robot import name_problem
from winder.errors import ExportError
from winder.escape import krl_comment, rapid_comment, urscript_comment
from winder.export.dialects.text import JOB_LINE, fmt, layer_line
from winder.machine.program import MotionProgram

POSITION_DECIMALS = 4  # mm: the station's path read back keeps the move times to 1e-4 relative
ANGLE_DECIMALS = 4  # deg
TIME_DECIMALS = 4  # s
JOINT_DECIMALS = 6  # deg: a start or bridge joint as written puts the flange within 1e-4 mm of its pose
AXIS_LABELS = ("E1 ring turn (deg, cumulative)", "E2 eye yaw on the ring (deg)", "E3 eye radius (mm)")


def cell_of(program: MotionProgram):
    """The program's cell motion; ExportError when the machine has no robot cell."""
    if program.cell is None:
        raise ExportError(f"{program.source}: machine.dialect: a robot language needs a robot cell: machine.robot as "
                          f"a mapping with an arm (kuka_kr16, abb_irb4600, ur10e)")
    return program.cell


def checked_name(name: str, language: str) -> str:
    """The job's name as the language's module name, which must match the file's: refused otherwise
    (`check` refuses it first: winder.app.validate)."""
    problem = name_problem(name, language.lower())
    if problem is not None:
        raise ExportError(f"name: {problem}, got {name!r}")
    return name


def header(program: MotionProgram, mark: str) -> list[str]:
    """The comment lines every robot program starts with."""
    cell = cell_of(program)
    c = cell.cell
    clean = {";": krl_comment, "!": rapid_comment, "#": urscript_comment}[mark.strip()]
    lines = ["winder filament-winding program", f"{JOB_LINE[2:]} {clean(program.name)}",
             f"source: {clean(program.source)}",
             f"cell: {cell.arm.maker} {cell.arm.name} holds the mandrel (tool: its frame on the flange); the payout "
             f"eye rides a fixed winding ring (positioner) at {_pose_text(c.ring)} in the cell",
             f"arm base in the cell: {_pose_text(c.base)}; mandrel on the flange: {_pose_text(c.tool)}",
             "external axes: " + ", ".join(AXIS_LABELS[:max(c.axes, 1)] if c.axes < 3 else AXIS_LABELS),
             f"poses: the ring's centre in the mandrel frame (station t*, axes e2 e3 e1); time {fmt(cell.times.total_s)} s",
             f"layers: {len(program.layers)}, fiber {fmt(program.total_fiber_length_mm)} mm"]
    lines += [layer_line(layer) for layer in program.layers]
    return [f"{mark} {line}" for line in lines]


def _pose_text(pose) -> str:
    return (f"x {fmt(pose.x)} y {fmt(pose.y)} z {fmt(pose.z)} mm, rz {fmt(pose.rz)} ry {fmt(pose.ry)} "
            f"rx {fmt(pose.rx)} deg")


def rows(program: MotionProgram) -> Iterator[tuple[str | None, int]]:
    """(a pass comment to write before the row, or None; the row) of every row worth a move: the first,
    and every later one that takes time (a row the program repeats is no move)."""
    for head, row, _ in _rows_and_tensions(program):
        yield head, row


def _rows_and_tensions(program: MotionProgram) -> Iterator[tuple[str | None, int, float | None]]:
    """rows(program) with each row's pass's tension (N, None: none programmed)."""
    cell = cell_of(program)
    time = cell.times.time_s
    first = True
    for layer, segments in zip(program.layers, program.segments):
        for seg in segments:
            head = f"layer {layer.index} circuit {seg.circuit} pass {seg.number} {seg.kind.value}"
            told = False
            for row in range(seg.start, seg.stop):
                if not first and time[row] <= 0.0:
                    continue
                yield (None if told else head), row, seg.tension
                told, first = True, False


def cell_start(program: MotionProgram, language: str):
    """What a cell language's serializer starts from: (the cell motion, the module name, the frames'
    positions (m, 3), the external axes (m, 3), the move times (m,)); ExportError when the cell's arm's
    controller runs another language."""
    cell = cell_of(program)
    if cell.arm.language != language.lower():
        raise ExportError(f"machine.dialect: {language} runs on a {cell.arm.maker} controller; the cell's arm is "
                          f"{cell.arm.name} ({cell.arm.maker}), whose controller runs {cell.arm.language}")
    name = checked_name(program.name, language)
    return cell, name, cell.frames[:, :3, 3], cell.external, cell.times.time_s


def bridges_after(program: MotionProgram) -> dict[int, object]:
    """The cell's bridges (winder.machine.bridges) by the written row they follow: a bridge's own row,
    or the last row before it that rows(program) writes."""
    cell = cell_of(program)
    written = np.array([row for _, row in rows(program)], dtype=int)
    out = {}
    for bridge in cell.bridges:
        at = int(written[max(int(np.searchsorted(written, bridge.row, side="right")) - 1, 0)])
        out[at] = bridge
    return out


BRIDGE_NOTE = ("bridge: the arm changes configuration by a joint move, winding stopped: the ring holds its axes, the "
               "eye holds the fiber (docs/math/10-robot-cell.md 10.5)")


def numbered_rows(program: MotionProgram, comments: list[str], mark: str) -> Iterator[tuple[int, int]]:
    """(n, row) of every row of rows(program), n counted from 1; each pass comment is appended to
    comments, as `mark head`, before its row is given, and after it the controller's tension command
    (an analog output: its description's `tension`) where the tension as written changes."""
    for _, n, row in layer_rows(program, comments, None, mark):
        yield n, row


def layer_rows(program: MotionProgram, main: list[str], blocks: dict[int, list[str]] | None,
               mark: str) -> Iterator[tuple[list[str], int, int]]:
    """(the lines its move goes to, n, row) of every row of rows(program), n counted from 1: main, or
    where blocks is a dict, blocks[its layer's index] (each layer a subprogram of its own,
    docs/math/10-robot-cell.md 10.10). Each pass comment is appended to those lines, as `mark head`,
    before its row is given, and after it the controller's tension command where it changes."""
    controller = program.machine.controller
    indent = mark[:len(mark) - len(mark.lstrip())]
    layer_of: dict[int, int] = {}
    if blocks is not None:
        for layer, segments in zip(program.layers, program.segments):
            for seg in segments:
                layer_of.update((row, layer.index) for row in range(seg.start, seg.stop))
    said = None
    for n, (head, row, tension) in enumerate(_rows_and_tensions(program), start=1):
        lines = main if blocks is None else blocks.setdefault(layer_of[row], [])
        if head is not None:
            lines.append(f"{mark} {head}")
            if tension is not None and controller.tension and (line := controller.tension_line(tension)) != said:
                lines.append(indent + line)
                said = line
        yield lines, n, row


def split_if_large(program: MotionProgram, language: str, write) -> dict[str, str]:
    """write(program, split=False)'s texts, or where their bytes pass the cell's limit for the language
    (winder.config.robot.program_limit), write(program, split=True)'s: a main program calling one
    subprogram per layer (docs/math/10-robot-cell.md 10.10)."""
    from winder.config.robot import program_limit  # noqa: PLC0415

    texts = write(program, False)
    size = sum(len(t.encode("utf-8")) for t in texts.values())
    return write(program, True) if size > program_limit(cell_of(program).cell, language) else texts


def abc_deg(r: np.ndarray) -> np.ndarray:
    """KUKA's A, B, C (deg) (m, 3) of rotations (m, 3, 3) = Rz(A) Ry(B) Rx(C)."""
    b = np.arctan2(-r[:, 2, 0], np.hypot(r[:, 0, 0], r[:, 1, 0]))
    a = np.arctan2(r[:, 1, 0], r[:, 0, 0])
    c = np.arctan2(r[:, 2, 1], r[:, 2, 2])
    return np.degrees(np.column_stack([a, b, c]))


def quaternions(r: np.ndarray) -> np.ndarray:
    """Unit quaternions (w, x, y, z) (m, 4) of rotations (m, 3, 3), w >= 0."""
    from scipy.spatial.transform import Rotation  # noqa: PLC0415 - slow to import

    xyzw = Rotation.from_matrix(r).as_quat()
    q = np.column_stack([xyzw[:, 3], xyzw[:, :3]])
    return np.where(q[:, :1] < 0.0, -q, q)


def rotation_vectors(r: np.ndarray) -> np.ndarray:
    """Rotation vectors (rad) (m, 3) of rotations (m, 3, 3), URScript's pose orientation."""
    from scipy.spatial.transform import Rotation  # noqa: PLC0415

    return Rotation.from_matrix(r).as_rotvec()
