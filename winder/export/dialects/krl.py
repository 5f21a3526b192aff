"""KUKA KRL (KSS 8): `<name>.src` and `<name>.dat` of a robot cell's program (docs/math/10-robot-cell.md).

The arm holds the mandrel and the ring is a fixed external TCP: $IPO_MODE = #TCP, $TOOL the mandrel
frame on the flange (machine.robot.tool), $BASE the ring in the world (machine.robot.positioner.origin;
the cell is the world, machine.robot.base the robot's $ROBROOT, a machine datum). Each move is
`LIN Pn C_DIS` to an E6POS of the .dat: X Y Z A B C the ring's centre and axes in the mandrel frame
(the station frame S(t*)), S and T the configuration of the branch the reach check chose, E1 the
ring's turn, E2 the eye's yaw, E3 the eye's radius. Before it, `$VEL.CP` (m/s) is the ring centre's
path length over the move's time from the dynamics, so that the move takes that time; where the ring
centre hardly moves (a hoop at one station) `$VEL_EXTAX[1]` (% of E1's top speed) sets it instead.
One serialize(program) entry point: {suffix: text}.
"""

from __future__ import annotations

import numpy as np

from winder.config.robot import NAME_LENGTH
from winder.errors import ExportError
from winder.export.dialects.robot_text import (ANGLE_DECIMALS, BRIDGE_NOTE, JOINT_DECIMALS, POSITION_DECIMALS, abc_deg,
                                               bridges_after, cell_of, cell_start, header, layer_rows,
                                               split_if_large)
from winder.export.dialects.text import fmt, fmt_significant
from winder.machine.configuration import kuka_status_turn
from winder.machine.program import MotionProgram

TOOL_STILL_MM = 1e-3  # a move whose ring centre travels less is timed by E1's speed


def _frame_text(pose) -> str:
    return (f"{{X {fmt(pose.x)},Y {fmt(pose.y)},Z {fmt(pose.z)},A {fmt(pose.rz)},B {fmt(pose.ry)},"
            f"C {fmt(pose.rx)}}}")


def status_turn(program: MotionProgram) -> tuple[np.ndarray, np.ndarray]:
    """KUKA's S and T of every row, in the configuration the row is reached in
    (winder.machine.configuration)."""
    cell = cell_of(program)
    return kuka_status_turn(cell.arm, cell.reach.arrive, cell.flange)


def _axes(q: np.ndarray, ext: np.ndarray) -> str:
    """An E6AXIS aggregate: the joints (deg) and the external axes."""
    return "{" + ",".join(f"A{i + 1} {fmt(q[i], JOINT_DECIMALS)}" for i in range(6)) + "," + ",".join(
        f"E{i + 1} {fmt(ext[i])}" for i in range(3)) + "}"


def serialize(program: MotionProgram) -> dict[str, str]:
    """{suffix: text} of the program: its .src and .dat, and past the cell's program limit a module per
    layer, `_L<N>.src` + `_L<N>.dat`, that the main .src calls as `<name>_L<N>( )` in layer order, its
    own .dat empty of points (docs/math/10-robot-cell.md 10.10)."""
    return split_if_large(program, "krl", _write)


def _write(program: MotionProgram, split: bool) -> dict[str, str]:
    """The .src and .dat texts of the program, split per layer or not."""
    cell, name, xyz, ext, time = cell_start(program, "KRL")
    c = cell.cell
    abc = abc_deg(cell.frames[:, :3, :3])
    s, t = status_turn(program)
    bridges = bridges_after(program)
    top_e1 = program.machine.dynamics.rotation.speed / 60.0  # deg/s
    src = ["&ACCESS RVP", "&REL 1", f"DEF {name}( )"] + header(program, ";")
    src += [";FOLD INI", "  BAS(#INITMOV, 0)", ";ENDFOLD",
            f"$TOOL = {_frame_text(c.tool)}  ; the mandrel frame on the flange",
            f"$BASE = {_frame_text(c.ring)}  ; the winding ring, a fixed external TCP",
            "$IPO_MODE = #TCP", f"$APO.CDIS = {fmt(program.machine.chord_tolerance)}",
            "$VEL_EXTAX[1] = 100", "$VEL_EXTAX[2] = 100", "$VEL_EXTAX[3] = 100"]
    src.append(f"PTP {_axes(cell.reach.joints[0], ext[0])}  ; the first pose, joint by joint")
    dat = ["&ACCESS RVP", "&REL 1", f"DEFDAT {name} PUBLIC"]
    slow, prev = False, 0
    blocks: dict[int, list[str]] | None = {} if split else None
    dats: dict[int, list[str]] = {}  # id(a layer's lines) -> its points, when split
    for lines, n, row in layer_rows(program, src, blocks, ";"):
        points = dat if blocks is None else dats.setdefault(id(lines), [])
        points.append(f"DECL E6POS P{n}={{X {fmt(xyz[row, 0], POSITION_DECIMALS)},Y {fmt(xyz[row, 1], POSITION_DECIMALS)},"
                   f"Z {fmt(xyz[row, 2], POSITION_DECIMALS)},A {fmt(abc[row, 0], ANGLE_DECIMALS)},"
                   f"B {fmt(abc[row, 1], ANGLE_DECIMALS)},C {fmt(abc[row, 2], ANGLE_DECIMALS)},"
                   + f"S {s[row]},T {t[row]},"
                   + f"E1 {fmt(ext[row, 0], ANGLE_DECIMALS)},E2 {fmt(ext[row, 1], ANGLE_DECIMALS)},"
                   + f"E3 {fmt(ext[row, 2], POSITION_DECIMALS)},E4 0.0,E5 0.0,E6 0.0}}")
        if n > 1:
            if cell.tool_path[row] >= TOOL_STILL_MM:
                if slow:
                    lines.append("$VEL_EXTAX[1] = 100")
                    slow = False
                lines.append(f"$VEL.CP = {fmt_significant(cell.tool_path[row] / time[row] / 1000.0)}")
            else:
                share = 100.0 * abs(ext[row, 0] - ext[prev, 0]) / time[row] / top_e1
                lines.append(f"$VEL_EXTAX[1] = {fmt_significant(min(max(share, 1e-3), 100.0))}")
                slow = True
        if row in bridges:  # the arm stops at the point, then changes configuration
            lines += [f"LIN P{n}", f"; {BRIDGE_NOTE}", f"PTP {_axes(bridges[row].after, ext[row])}"]
        else:
            lines.append(f"LIN P{n} C_DIS")
        prev = row
    modules = {k: layer_module(name, k) for k in blocks or {}}
    src += [f"{module}( )  ; layer {k}: {module}.src + .dat" for k, module in modules.items()] + ["END"]
    dat.append("ENDDAT")
    texts = {".src": "\n".join(src) + "\n", ".dat": "\n".join(dat) + "\n"}
    for k, module in modules.items():  # each layer a module of its own: its moves' .src, their points' .dat
        lines = blocks[k]
        texts[module[len(name):] + ".src"] = "\n".join(
            ["&ACCESS RVP", "&REL 1", f"DEF {module}( )", f"; {name}'s layer {k}, called from {name}.src"]
            + lines + ["END"]) + "\n"
        texts[module[len(name):] + ".dat"] = "\n".join(
            ["&ACCESS RVP", "&REL 1", f"DEFDAT {module} PUBLIC"] + dats[id(lines)] + ["ENDDAT"]) + "\n"
    return texts


def layer_module(name: str, layer: int) -> str:
    """The module (its .src and .dat's name) of a layer of the job's KRL program split per layer:
    `<name>_L<layer>`; ExportError past KRL's NAME_LENGTH."""
    module = f"{name}_L{layer}"
    if len(module) > NAME_LENGTH["krl"]:
        raise ExportError(f"name: the KRL program is split per layer (docs/math/10-robot-cell.md 10.10) and layer "
                          f"{layer}'s module {module} is longer than KRL's {NAME_LENGTH['krl']} characters: shorten the "
                          f"job's name to {NAME_LENGTH['krl'] - len(module) + len(name)} or raise "
                          f"machine.robot.program_limit")
    return module
