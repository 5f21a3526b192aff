"""URScript (e-Series): `<name>.script` of a robot cell's program (docs/math/10-robot-cell.md).

A UR controller has no stationary TCP and interpolates no external axis: URScript's movel moves the
arm's six joints only. So the pose is the mandrel frame (the TCP, set_tcp = machine.robot.tool) in the
robot's base frame (metres, a rotation vector), and the ring follows move by move: before each movel,
`ring(e1, e2, e3, t)` writes the ring's targets (turn and yaw in deg, radius in mm) and the move's time
to output float registers 0-3, from which the ring's own drive (a PLC reading RTDE registers, or a
URCap driving the axis) runs the same time. That keeps each move's end synchronised, not the path
between: within a move the eye lags or leads by up to the share of the ring's turn the drive's own
ramp makes it, which is why the UR cell is offered for small parts, and KRL or RAPID (coordinated
external axes) for production. One serialize(program) entry point.
"""

from __future__ import annotations

import numpy as np

from winder.config.arms import UR
from winder.errors import ExportError
from winder.export.dialects.robot_text import (TIME_DECIMALS, cell_of, checked_name, header, numbered_rows,
                                               rotation_vectors)
from winder.export.dialects.text import fmt
from winder.machine.program import MotionProgram

NAME_LENGTH = 63
METRE_DECIMALS = 7  # 0.1 micrometre
RADIAN_DECIMALS = 8


def _pose(position_mm: np.ndarray, rotvec: np.ndarray) -> str:
    values = [fmt(v / 1000.0, METRE_DECIMALS) for v in position_mm] + [fmt(v, RADIAN_DECIMALS) for v in rotvec]
    return "p[" + ", ".join(values) + "]"


def serialize(program: MotionProgram) -> dict[str, str]:
    """The .script text of the program."""
    cell = cell_of(program)
    if cell.arm.kind != UR:
        raise ExportError(f"machine.robot.arm: URScript moves a Universal Robots arm in its own base frame; the cell's "
                          f"arm is {cell.arm.name} ({cell.arm.maker}): write krl or rapid for it")
    name = checked_name(program.name, "URScript", NAME_LENGTH)
    c = cell.cell
    tool = c.tool.matrix()
    rv = rotation_vectors(cell.mandrel[:, :3, :3])
    xyz = cell.mandrel[:, :3, 3]
    ext = cell.external
    time = cell.times.time_s
    q0 = np.radians(cell.reach.joints[0])
    lines = [f"def {name}():"] + header(program, "  #")
    lines += ["  def ring(e1, e2, e3, t):", "    write_output_float_register(0, e1)",
              "    write_output_float_register(1, e2)", "    write_output_float_register(2, e3)",
              "    write_output_float_register(3, t)", "  end",
              f"  set_tcp({_pose(tool[:3, 3], rotation_vectors(tool[None, :3, :3])[0])})",
              f"  ring({fmt(ext[0, 0])}, {fmt(ext[0, 1])}, {fmt(ext[0, 2])}, 0)",
              "  movej([" + ", ".join(fmt(v, RADIAN_DECIMALS) for v in q0) + "], a=0.5, v=0.5)"]
    for n, row in numbered_rows(program, lines, "  #"):
        seconds = max(float(time[row]), 10.0 ** -TIME_DECIMALS) if n > 1 else 10.0 ** -TIME_DECIMALS
        t = fmt(seconds, TIME_DECIMALS)
        lines.append(f"  ring({fmt(ext[row, 0], 4)}, {fmt(ext[row, 1], 4)}, {fmt(ext[row, 2], 4)}, {t})")
        lines.append(f"  movel({_pose(xyz[row], rv[row])}, a=1.2, v=0.25, t={t}, r=0)")
    lines.append("end")
    return {".script": "\n".join(lines) + "\n"}
