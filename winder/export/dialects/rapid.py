"""ABB RAPID (RobotWare 6): `<name>.mod` of a robot cell's program (docs/math/10-robot-cell.md).

The ring is a stationary tool (tooldata robhold FALSE, its frame the ring in the world) and the arm
holds the work object (wobjdata robhold TRUE, its user frame the mandrel on the flange). Each move is
`MoveL pN, v1000 \\T:=time, z0, tRing \\WObj:=wMandrel;` to a robtarget: the ring's centre and axes in
the mandrel frame (the station frame S(t*), a unit quaternion), the configuration of the reach check's
branch (cf1, cf4, cf6 the quadrants of axes 1, 4, 6; cfx from the wrist centre's side of axis 1 and of
the lower arm and axis 5's sign), and the external axes eax_a (ring turn, deg), eax_b (eye yaw, deg),
eax_c (eye radius, mm). \\T is the move's time from the dynamics. One serialize(program) entry point.
"""

from __future__ import annotations

import numpy as np

from winder.export.dialects.robot_text import (ANGLE_DECIMALS, POSITION_DECIMALS, TIME_DECIMALS, cell_of,
                                               cell_start, header, numbered_rows, quaternions)
from winder.export.dialects.text import fmt
from winder.machine.program import MotionProgram

NAME_LENGTH = 32  # RAPID identifiers
QUATERNION_DECIMALS = 9  # a unit quaternion as written stays unit within 1e-8
NOT_USED = "9E9"  # RAPID's value of an external axis that is not there


def _frame(pose) -> str:
    q = quaternions(pose.matrix()[None, :3, :3])[0]
    return (f"[[{fmt(pose.x)},{fmt(pose.y)},{fmt(pose.z)}],["
            + ",".join(fmt(v, QUATERNION_DECIMALS) for v in q) + "]]")


def configuration(program: MotionProgram) -> np.ndarray:
    """(m, 4) ints: cf1, cf4, cf6, cfx of every row (module docstring)."""
    cell = cell_of(program)
    q = cell.reach.joints
    arm = cell.arm
    wrist = cell.flange[:, :3, 3] - arm.dh[5, 0] * cell.flange[:, :3, 2]
    a1 = np.radians(q[:, 0])
    ahead = wrist[:, 0] * np.cos(a1) + wrist[:, 1] * np.sin(a1) - arm.dh[0, 1]
    up = wrist[:, 2] - arm.dh[0, 0]
    lower = np.radians(q[:, 1])  # the lower arm leans forward by axis 2 from the vertical
    behind_lower = (ahead * np.cos(lower) - up * np.sin(lower)) < 0.0
    cfx = 4 * (ahead + arm.dh[0, 1] < 0.0) + 2 * behind_lower + (q[:, 4] < 0.0)
    quadrant = np.floor(q[:, [0, 3, 5]] / 90.0).astype(int)
    return np.column_stack([quadrant, cfx.astype(int)])


def serialize(program: MotionProgram) -> dict[str, str]:
    """The .mod text of the program."""
    cell, name, xyz, ext, time = cell_start(program, "RAPID", NAME_LENGTH)
    c = cell.cell
    quat = quaternions(cell.frames[:, :3, :3])
    conf = configuration(program)
    lines = [f"MODULE {name}"] + header(program, "  !")
    if cell.arm.maker != "ABB":  # robconf is an ABB arm's; ConfL \Off lets an ABB arm in its place choose
        conf = np.zeros_like(conf)
        lines.append("  ! the cell's arm is not an ABB: the poses are the cell's, robconf left [0,0,0,0]")
    lines += [f"  PERS tooldata tRing := [FALSE,{_frame(c.ring)},[1,[0,0,1],[1,0,0,0],0,0,0]];",
              f"  PERS wobjdata wMandrel := [TRUE,TRUE,\"\",{_frame(c.tool)},[[0,0,0],[1,0,0,0]]];"]
    q0 = cell.reach.joints[0]
    lines.append("  CONST jointtarget jStart := [[" + ",".join(fmt(v) for v in q0) + "],["
                 + ",".join(fmt(v) for v in ext[0]) + f",{NOT_USED},{NOT_USED},{NOT_USED}]];")
    targets, moves = [], []
    for n, row in numbered_rows(program, moves, "    !"):
        targets.append(f"  CONST robtarget p{n} := [[{fmt(xyz[row, 0], POSITION_DECIMALS)},"
                       f"{fmt(xyz[row, 1], POSITION_DECIMALS)},{fmt(xyz[row, 2], POSITION_DECIMALS)}],["
                       + ",".join(fmt(v, QUATERNION_DECIMALS) for v in quat[row]) + "],["
                       + ",".join(str(int(v)) for v in conf[row]) + f"],[{fmt(ext[row, 0], ANGLE_DECIMALS)},"
                       f"{fmt(ext[row, 1], ANGLE_DECIMALS)},{fmt(ext[row, 2], POSITION_DECIMALS)},"
                       f"{NOT_USED},{NOT_USED},{NOT_USED}]];")
        seconds = max(float(time[row]), 10.0 ** -TIME_DECIMALS) if n > 1 else 10.0 ** -TIME_DECIMALS
        moves.append(f"    MoveL p{n}, v1000 \\T:={fmt(seconds, TIME_DECIMALS)}, z0, tRing \\WObj:=wMandrel;")
    lines += targets
    lines += ["  PROC main()", "    ConfL \\Off;",
              "    MoveAbsJ jStart, v100, fine, tRing \\WObj:=wMandrel;"] + moves + ["  ENDPROC", "ENDMODULE"]
    return {".mod": "\n".join(lines) + "\n"}
