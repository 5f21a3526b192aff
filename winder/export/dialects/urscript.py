"""URScript (e-Series): `<name>.script` of a robot cell's program (docs/math/10-robot-cell.md).

A UR controller has no stationary TCP and interpolates no external axis: URScript's movel moves the
arm's six joints only. So the pose is the mandrel frame (the TCP, set_tcp = machine.robot.tool) in the
controller's Base frame (DH frame 0; metres, a rotation vector), and the arm never stops inside the
program: each movel has its time t (at least the 2 ms control cycle) and a blend radius r within the
chord tolerance (winder.machine.blends), none only at the ends and at a bridge.

The ring follows by the schedule of winder.machine.blends (docs/math/10 10.7): before each movel,
`ring(e1, e2, e3, t)` writes the ring's targets (turn and yaw in deg, radius in mm) and the time to
reach them to output float registers 0-3 and counts the line on output integer register 0; the
ring's drive moves linearly to the targets in that time from when the count changes, and echoes the
count on input integer register 0 when it is there: the program waits for that echo at the start
(`ring_wait()`), after the movej to the start joints, whose flange is the first pose (the first movel,
one cycle long, moves nowhere). After a pass comment, the controller's tension command
(set_standard_analog_out, robot_text.numbered_rows) where the tension changes. One serialize(program)
entry point.
"""

from __future__ import annotations

import numpy as np

from winder.config.robot import subprogram_name
from winder.export.dialects.robot_text import (BRIDGE_NOTE, TIME_DECIMALS, bridges_after, cell_start, header,
                                               layer_rows, rotation_vectors, rows,
                                               split_if_large)
from winder.export.dialects.text import fmt
from winder.machine.blends import CYCLE_S, blend_radii, line_times, ring_targets
from winder.machine.program import MotionProgram

METRE_DECIMALS = 7  # 0.1 micrometre
RADIAN_DECIMALS = 8
RING_DECIMALS = 4
PROLOGUE = ("  global ring_n = 0",
            "  def ring(e1, e2, e3, t):",
            "    write_output_float_register(0, e1)",
            "    write_output_float_register(1, e2)",
            "    write_output_float_register(2, e3)",
            "    write_output_float_register(3, t)",
            "    ring_n = ring_n + 1",
            "    write_output_integer_register(0, ring_n)",
            "  end",
            "  def ring_wait():",
            "    while read_input_integer_register(0) != ring_n:",
            "      sync()",
            "    end",
            "  end")


def _pose(position_mm: np.ndarray, rotvec: np.ndarray) -> str:
    values = [fmt(v / 1000.0, METRE_DECIMALS) for v in position_mm] + [fmt(v, RADIAN_DECIMALS) for v in rotvec]
    return "p[" + ", ".join(values) + "]"


def _joints(q_deg: np.ndarray) -> str:
    return "[" + ", ".join(fmt(v, RADIAN_DECIMALS) for v in np.radians(q_deg)) + "]"


def motion(program: MotionProgram):
    """The written rows' (index (k,), move times (k,) s, blend radii (k,) mm, pauses (k,) s, the ring's
    targets (k, 3) and times (k,)) of the program (module docstring)."""
    cell = program.cell
    written = np.array([row for _, row in rows(program)], dtype=int)
    poses = cell.mandrel[written]
    # as written: the ring's schedule runs on the times and radii the controller reads
    # the first movel is to the first pose, where the movej put the arm: one cycle
    move_s = np.round(np.concatenate([[CYCLE_S], np.maximum(cell.times.time_s[written[1:]], CYCLE_S)]), TIME_DECIMALS)
    bridges = bridges_after(program)
    stop = np.isin(written, list(bridges))
    pause = np.round([bridges[r].time_s if r in bridges else 0.0 for r in written.tolist()], TIME_DECIMALS)
    ring_centre = (np.linalg.inv(cell.cell.base.matrix()) @ cell.cell.ring.matrix())[:3, 3]
    lever = np.linalg.norm(ring_centre - poses[:, :3, 3], axis=1) + cell.external[written, 2]
    radii = np.round(blend_radii(poses, lever, program.machine.chord_tolerance, stop, cell.external[written], move_s), METRE_DECIMALS - 3)
    arrive, starts = line_times(move_s, radii, poses, pause)
    targets, spans = ring_targets(arrive, cell.external[written], starts, pause)
    spans[0] = move_s[0]  # the ring holds its start through the first movel
    return written, move_s, radii, pause, targets, spans


def serialize(program: MotionProgram) -> dict[str, str]:
    """The .script text of the program: past the cell's program limit, the main function calls a
    function per layer, `layer_N()`, each defined within it before the calls
    (docs/math/10-robot-cell.md 10.10)."""
    return split_if_large(program, "urscript", _write)


def _write(program: MotionProgram, split: bool) -> dict[str, str]:
    """The .script text of the program, split per layer or not."""
    cell, name, _, _, _ = cell_start(program, "URScript")
    tool = cell.cell.tool.matrix()
    rv = rotation_vectors(cell.mandrel[:, :3, :3])
    xyz = cell.mandrel[:, :3, 3]
    written, move_s, radii, pause, targets, spans = motion(program)
    bridges = bridges_after(program)
    lines = [f"def {name}():"] + header(program, "  #") + list(PROLOGUE)
    body: list[str] = []
    blocks: dict[int, list[str]] | None = {} if split else None
    pad = "    " if split else "  "  # a layer's function's lines one level in
    # each pass comment, and after it the controller's tension command where it changes, before its row
    for moves, n, row in layer_rows(program, body, blocks, pad + "#"):
        k = n - 1  # motion()'s rows are rows(program)'s, as layer_rows gives them
        t = fmt(move_s[k], TIME_DECIMALS)
        moves.append(pad + "ring(" + ", ".join(fmt(v, RING_DECIMALS) for v in targets[k])
                     + f", {fmt(spans[k], TIME_DECIMALS)})")
        moves.append(pad + f"movel({_pose(xyz[row], rv[row])}, a=1.2, v=0.25, t={t}, "
                      f"r={fmt(radii[k] / 1000.0, METRE_DECIMALS)})")
        if row in bridges:
            moves += [f"{pad}# {BRIDGE_NOTE}",
                      f"{pad}movej({_joints(bridges[row].after)}, a=1.0, v=1.0, t={fmt(pause[k], TIME_DECIMALS)}, r=0)"]
    for k, inner in (blocks or {}).items():  # each layer a function of the script, defined before its call
        lines += [f"  def {subprogram_name(k)}():"] + inner + ["  end"]
    lines += [f"  set_tcp({_pose(tool[:3, 3], rotation_vectors(tool[None, :3, :3])[0])})",
              f"  movej({_joints(cell.reach.joints[0])}, a=0.5, v=0.5)",
              "  ring(" + ", ".join(fmt(v, RING_DECIMALS) for v in targets[0]) + ", 0)",
              "  ring_wait()"]
    lines += body + [f"  {subprogram_name(k)}()" for k in blocks or {}] + ["end"]
    return {".script": "\n".join(lines) + "\n"}
