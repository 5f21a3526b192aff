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

from winder.config.robot import subprogram_name
from winder.export.dialects.robot_text import (ANGLE_DECIMALS, BRIDGE_NOTE, JOINT_DECIMALS, POSITION_DECIMALS,
                                               TIME_DECIMALS,
                                               bridges_after, cell_of, cell_start, header, layer_rows, quaternions,
                                               split_if_large)
from winder.export.dialects.text import fmt
from winder.machine.configuration import abb_confdata
from winder.machine.program import MotionProgram

QUATERNION_DECIMALS = 9  # a unit quaternion as written stays unit within 1e-8
NOT_USED = "9E9"  # RAPID's value of an external axis that is not there


def _frame(pose) -> str:
    q = quaternions(pose.matrix()[None, :3, :3])[0]
    return (f"[[{fmt(pose.x)},{fmt(pose.y)},{fmt(pose.z)}],["
            + ",".join(fmt(v, QUATERNION_DECIMALS) for v in q) + "]]")


def configuration(program: MotionProgram) -> np.ndarray:
    """(m, 4) ints: cf1, cf4, cf6, cfx of every row, in the configuration the row is reached in
    (winder.machine.configuration)."""
    cell = cell_of(program)
    return abb_confdata(cell.arm, cell.reach.arrive, cell.flange)


def _jointtarget(name: str, q: np.ndarray, ext: np.ndarray) -> str:
    return (f"  CONST jointtarget {name} := [[" + ",".join(fmt(v, JOINT_DECIMALS) for v in q) + "],["
            + ",".join(fmt(v) for v in ext) + f",{NOT_USED},{NOT_USED},{NOT_USED}]];")


def serialize(program: MotionProgram) -> dict[str, str]:
    """The .mod text of the program: past the cell's program limit, main calls a routine per layer,
    `layer_N;` (docs/math/10-robot-cell.md 10.10)."""
    return split_if_large(program, "rapid", _write)


def _write(program: MotionProgram, split: bool) -> dict[str, str]:
    """The .mod text of the program, split per layer or not."""
    cell, name, xyz, ext, time = cell_start(program, "RAPID")
    c = cell.cell
    quat = quaternions(cell.frames[:, :3, :3])
    conf = configuration(program)
    bridges = bridges_after(program)
    lines = [f"MODULE {name}"] + header(program, "  !")
    lines += [f"  PERS tooldata tRing := [FALSE,{_frame(c.ring)},[1,[0,0,1],[1,0,0,0],0,0,0]];",
              f"  PERS wobjdata wMandrel := [TRUE,TRUE,\"\",{_frame(c.tool)},[[0,0,0],[1,0,0,0]]];"]
    lines.append(_jointtarget("jStart", cell.reach.joints[0], ext[0]))
    targets: list[str] = []
    unsplit: list[str] = []
    blocks: dict[int, list[str]] | None = {} if split else None
    for moves, n, row in layer_rows(program, unsplit, blocks, "    !"):
        targets.append(f"  CONST robtarget p{n} := [[{fmt(xyz[row, 0], POSITION_DECIMALS)},"
                       f"{fmt(xyz[row, 1], POSITION_DECIMALS)},{fmt(xyz[row, 2], POSITION_DECIMALS)}],["
                       + ",".join(fmt(v, QUATERNION_DECIMALS) for v in quat[row]) + "],["
                       + ",".join(str(int(v)) for v in conf[row]) + f"],[{fmt(ext[row, 0], ANGLE_DECIMALS)},"
                       f"{fmt(ext[row, 1], ANGLE_DECIMALS)},{fmt(ext[row, 2], POSITION_DECIMALS)},"
                       f"{NOT_USED},{NOT_USED},{NOT_USED}]];")
        seconds = max(float(time[row]), 10.0 ** -TIME_DECIMALS) if n > 1 else 10.0 ** -TIME_DECIMALS
        zone = "fine" if row in bridges else "z0"  # the arm stops where it changes configuration
        moves.append(f"    MoveL p{n}, v1000 \\T:={fmt(seconds, TIME_DECIMALS)}, {zone}, tRing \\WObj:=wMandrel;")
        if row in bridges:
            targets.append(_jointtarget(f"jBridge{n}", bridges[row].after, ext[row]))
            moves += [f"    ! {BRIDGE_NOTE}", f"    MoveAbsJ jBridge{n}, v1000 \\T:={fmt(bridges[row].time_s, TIME_DECIMALS)}, "
                      "fine, tRing \\WObj:=wMandrel;"]
    lines += targets
    lines += ["  PROC main()", "    ConfL \\Off;", "    MoveAbsJ jStart, v100, fine, tRing \\WObj:=wMandrel;"]
    lines += unsplit + [f"    {subprogram_name(k)};" for k in blocks or {}] + ["  ENDPROC"]
    for k, moves in (blocks or {}).items():  # each layer a routine of the module
        lines += [f"  PROC {subprogram_name(k)}()"] + moves + ["  ENDPROC"]
    lines.append("ENDMODULE")
    return {".mod": "\n".join(lines) + "\n"}
