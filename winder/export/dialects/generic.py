"""The winding program `<name>.gcode` (SPEC.md "Output files", MATH.md 6).

Straight-axis winder: `G1` moves of the four axes (letters from machine.axes) in the order carriage,
rotation, cross-feed, yaw, with the feed F (mm/min) on every move; the axis values are those of
winder.machine.kinematics.eye_path (its docstring defines them, B included). Values have 3 decimals (mm, deg);
A is cumulative over the whole program: each pass and layer continues from the last; to reach a
pass that starts elsewhere (a new layer) the mandrel turns on in its winding sense, less than a turn
for the contact point and never back more than TURN_BACK_DEG for the eye. Every pass is checked
against machine.limits (ExportError naming the file, layer, circuit, pass, axis, value and limits).

Point reduction: of each pass's contact points, a point is dropped when its axis values lie within
machine.chord_tolerance of the straight (axis-space) move between the kept neighbours, distances in
the scaled axis space (X mm, Z mm, A as the arc at the largest eye radius, B as the arc that makes
YAW_TOLERANCE_DEG count as one chord tolerance): Douglas-Peucker, so every dropped point is within
the tolerance of the move that replaces it. The first and last point of each pass are kept. Two
consecutive moves are never identical after rounding.

Robot mode (machine.robot, or a bent mandrel axis): instead of axis moves, one line per kept eye pose
in the mandrel frame:

    POSE X<x> Y<y> Z<z> I<i> J<j> K<k> F<feed>

X Y Z the eye position (mm, 3 decimals), I J K the unit vector from the eye to its contact point
(6 decimals), the free fiber as it leaves the eye (winder.machine.kinematics.robot_poses). Poses are reduced
the same way (eye position in mm, direction as YAW_TOLERANCE_DEG). machine.limits name winder axes
and are not applied to poses. The preamble and comments are the same in both modes. The text is
deterministic: no timestamps, no timings.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, replace

import numpy as np

from winder.config.machine import MachineConfig
from winder.errors import ExportError
from winder.machine.kinematics import (EyeEnvelope, RobotPoses, check_limits, eye_envelope, eye_path, make_guide,
                            robot_poses)
from winder.winding.results import FiberPass, LayerPlan, PassKind, WindingPlan

DECIMALS = 3  # mm and deg
DIRECTION_DECIMALS = 6  # unit vectors of robot poses
YAW_TOLERANCE_DEG = 0.5  # a yaw (or fiber direction) deviation this large counts as chord_tolerance
PREAMBLE = ("G21", "G90", "G94")
END = "M2"
_NEG_ZERO = re.compile(r"(?<![0-9])-(0\.0+)(?![0-9])")
TURN_BACK_DEG = 1.0  # moving to a new layer, the mandrel may turn back this much, not more
_CONTINUITY_TOL = 1e-9  # rad: two passes whose angles meet this closely are continuous
_TWO_PI = 2.0 * np.pi
_POINT_TOL = 1e-6  # mm: a pass starting this close to where the last one ended continues it


@dataclass(frozen=True)
class Move:
    """One programmed line: the pass it comes from and the index of its contact point in the pass.

    values : the line's numbers as written (rounded): (carriage, rotation, cross_feed, yaw) for a
    winder, (x, y, z, i, j, k) for a robot pose.
    """

    layer: int
    circuit: int
    number: int
    kind: PassKind
    index: int
    values: tuple[float, ...]


def is_robot(plan: WindingPlan, machine: MachineConfig) -> bool:
    """Whether the program is written as robot poses (bent axis or machine.robot)."""
    return bool(machine.robot or not plan.surface.curve.is_straight)


def reduce_points(q: np.ndarray, tol: float) -> np.ndarray:
    """Indices kept by Douglas-Peucker on the polyline q (m, k) with tolerance tol: every dropped
    point lies within tol of the segment between its kept neighbours. First and last are kept."""
    q = np.asarray(q, dtype=float)
    m = q.shape[0]
    if m <= 2:
        return np.arange(m)
    keep = np.zeros(m, dtype=bool)
    keep[[0, -1]] = True
    stack = [(0, m - 1)]
    while stack:
        i, k = stack.pop()
        if k - i < 2:
            continue
        a = q[i]
        seg = q[k] - a
        rel = q[i + 1:k] - a
        len2 = float(seg @ seg)
        u = np.clip(rel @ seg / len2, 0.0, 1.0) if len2 > 0.0 else np.zeros(k - i - 1)
        dist = np.linalg.norm(rel - u[:, None] * seg, axis=1)
        j = int(np.argmax(dist))
        if dist[j] > tol:
            j += i + 1
            keep[j] = True
            stack.append((j, k))
            stack.append((i, j))
    return np.flatnonzero(keep)


def _fmt(value: float, decimals: int = DECIMALS) -> str:
    return _NEG_ZERO.sub(r"\1", f"{value:.{decimals}f}")


def _clean(text: str) -> str:
    """A comment's text on one line."""
    return " ".join(str(text).split())


class _Turns:
    """Carries the contact angle over the whole program: each pass's unwrapped theta plus whole
    turns, so that A is cumulative. A pass continuing where the last one ended keeps its angles; a
    pass starting elsewhere (a new layer) is reached by turning on in the winding sense (that of the
    previous pass), less than a turn, never backwards."""

    def __init__(self) -> None:
        self.offset = 0.0
        self.end: float | None = None
        self.end_point: np.ndarray | None = None
        self.sense = 1.0

    def place(self, theta: np.ndarray, first: np.ndarray) -> tuple[np.ndarray, bool]:
        """(the pass's program angles, whether it starts away from where the last pass ended);
        first: the pass's first contact point."""
        jumped = False
        if self.end is not None:
            self.offset += _TWO_PI * np.round((self.end - (theta[0] + self.offset)) / _TWO_PI)
            gap = theta[0] + self.offset - self.end
            jumped = abs(gap) > _CONTINUITY_TOL or float(np.linalg.norm(first - self.end_point)) > _POINT_TOL
            if abs(gap) > _CONTINUITY_TOL and gap * self.sense < 0.0:
                self.offset += _TWO_PI * self.sense
        return theta + self.offset, jumped

    def turn_on(self, theta: np.ndarray) -> np.ndarray:
        """One more turn in the winding sense (the eye, not only the contact, must not turn back)."""
        self.offset += _TWO_PI * self.sense
        return theta + self.offset

    def done(self, cum: np.ndarray, last: np.ndarray) -> None:
        if cum[-1] != cum[0]:
            self.sense = float(np.sign(cum[-1] - cum[0]))
        self.end = float(cum[-1])
        self.end_point = np.asarray(last, dtype=float)


def _layer_line(layer: LayerPlan) -> str:
    return (f"layer {layer.index}: {layer.type.value}, angle {_fmt(layer.angle_deg)} deg (requested "
            f"{_fmt(layer.requested_angle_deg)}), circuits {layer.circuits}, pattern {layer.pattern}, "
            f"passes {len(layer.passes)}, fiber {_fmt(layer.fiber_length_mm)} mm")


def _header(plan: WindingPlan, machine: MachineConfig, robot: bool, env: EyeEnvelope) -> list[str]:
    ax = machine.axes
    lines = ["; winder filament-winding program", f"; job: {_clean(plan.name)}",
             f"; source: {_clean(plan.source)}"]
    if robot:
        lines += ["; machine: robot; eye poses in the mandrel frame",
                  "; POSE X Y Z: eye position (mm); I J K: unit fiber direction from the eye to its "
                  "contact point; F feed (mm/min)"]
    else:
        lines += [f"; machine: straight-axis winder; {ax.carriage} carriage (mm), {ax.rotation} mandrel "
                  f"rotation (deg, cumulative), {ax.cross_feed} cross-feed: eye distance from the axis "
                  f"(mm), {ax.yaw} eye yaw (deg)",
                  f"; kinematics: eye at mandrel-frame ({ax.cross_feed} cos(-{ax.rotation}), "
                  f"{ax.cross_feed} sin(-{ax.rotation}), {ax.carriage}), on the tangent line of the "
                  "fiber path at its contact point",
                  f"; yaw: {ax.yaw} = eye rotation about the cross-feed axis from the hoop orientation: "
                  f"the free fiber's direction d at the eye, {ax.yaw} = atan2(d.z, d.u) with u the eye's "
                  f"tangential direction (0 hoop, + forward, - return); on a cylinder of radius R with the "
                  f"eye at {ax.cross_feed}: tan({ax.yaw}) = {ax.cross_feed} / (R tan(alpha)), alpha the "
                  f"winding angle on the mandrel"]
    if env.constant is not None:
        lines.append(f"; eye envelope: radius {_fmt(env.constant)} mm around the axis")
    else:
        lines.append(f"; eye envelope: clearance {_fmt(env.clearance)} mm from the mandrel")
    lines.append(f"; feed {_fmt(machine.feed)} mm/min, chord tolerance {_fmt(machine.chord_tolerance)} mm")
    lines.append(f"; layers: {len(plan.layers)}, fiber {_fmt(plan.total_fiber_length_mm)} mm")
    lines += [f"; {_layer_line(layer)}" for layer in plan.layers]
    return lines


def _pass_where(plan: WindingPlan, fp: FiberPass) -> str:
    return f"{plan.source}: layer {fp.layer} circuit {fp.circuit} pass {fp.number} ({fp.kind.value})"


def _all_poses(plan: WindingPlan, machine: MachineConfig, env: EyeEnvelope, guide) -> list[RobotPoses]:
    """Robot poses of every non-empty pass, solved in one batch (the solver's cost is per call)."""
    passes = [fp for layer in plan.layers for fp in layer.passes if len(fp.points)]
    if not passes:
        return []
    sizes = np.cumsum([len(fp.points) for fp in passes])[:-1]
    try:
        batch = robot_poses(np.concatenate([fp.points for fp in passes]),
                            np.concatenate([fp.direction for fp in passes]), plan.surface, machine,
                            envelope=env, guide=guide)
    except ExportError:
        for fp in passes:  # name the pass that fails
            robot_poses(fp.points, fp.direction, plan.surface, machine, envelope=env, guide=guide,
                        where=_pass_where(plan, fp))
        raise
    parts = [np.split(np.asarray(getattr(batch, f)), sizes) for f in
             ("position", "direction", "station", "lead", "on_envelope")]
    return [RobotPoses(*fields) for fields in zip(*parts)]


def _program(plan: WindingPlan, machine: MachineConfig) -> tuple[list[str], list[Move]]:
    robot = is_robot(plan, machine)
    surface = plan.surface
    env = eye_envelope(surface, machine)
    guide = make_guide(surface, env) if robot else None
    tol = float(machine.chord_tolerance)
    angle_scale = tol / np.radians(YAW_TOLERANCE_DEG)  # mm per radian of yaw / direction
    arc_radius = env.max_radius  # the mandrel-turn arc of A, at the largest eye radius
    feed = f"F{_fmt(machine.feed)}"
    ax = machine.axes
    letters = (ax.carriage, ax.rotation, ax.cross_feed, ax.yaw)
    pose_letters = ("X", "Y", "Z", "I", "J", "K")

    lines = _header(plan, machine, robot, env) + list(PREAMBLE)
    moves: list[Move] = []
    last_words: str | None = None
    b_end: float | None = None
    a_end: float | None = None
    turns = _Turns()
    progress = sum(float(fp.theta[-1] - fp.theta[0]) for layer in plan.layers for fp in layer.passes
                   if len(fp.theta))
    sense = -1.0 if progress < 0.0 else 1.0  # the winding sense of the whole program (for B)
    poses = iter(_all_poses(plan, machine, env, guide) if robot else ())
    for layer in plan.layers:
        lines.append(f"; {_layer_line(layer)}")
        circuit = None
        for fp in layer.passes:
            if fp.circuit != circuit:
                circuit = fp.circuit
                lines.append(f"; layer {layer.index} circuit {circuit}")
            lines.append(f"; layer {layer.index} circuit {circuit} pass {fp.number} {fp.kind.value}")
            if len(fp.points) == 0:
                continue
            where = _pass_where(plan, fp)
            theta, jumped = turns.place(np.asarray(fp.theta, dtype=float), np.asarray(fp.points[0], float))
            if robot:
                pose = next(poses)
                capped = int(np.count_nonzero(~pose.on_envelope))
                lead = pose.lead
                q = np.column_stack([pose.position, angle_scale * pose.direction])
                table = np.column_stack([pose.position, pose.direction])
                decimals = (DECIMALS,) * 3 + (DIRECTION_DECIMALS,) * 3
            else:
                path = eye_path(fp.points, fp.direction, surface, machine, theta=theta, envelope=env,
                                sense=sense, where=where)
                if jumped and a_end is not None and (path.a_deg[0] - a_end) * turns.sense > TURN_BACK_DEG:
                    # A runs against theta: the eye would turn back on the way to this pass.
                    theta = turns.turn_on(np.asarray(fp.theta, dtype=float))
                    path = eye_path(fp.points, fp.direction, surface, machine, theta=theta, envelope=env,
                                    sense=sense, where=where)
                a_end = float(path.a_deg[-1])
                if b_end is not None:
                    path = replace(path, b_deg=path.b_deg + 360.0 * np.round((b_end - path.b_deg[0]) / 360.0))
                b_end = float(path.b_deg[-1])
                check_limits(path, machine, where)
                capped = int(np.count_nonzero(~path.on_envelope))
                lead = path.lead
                q = np.column_stack([path.x, path.z, np.radians(path.a_deg) * arc_radius,
                                     np.radians(path.b_deg) * angle_scale])
                table = np.column_stack([path.x, path.a_deg, path.z, path.b_deg])
                decimals = (DECIMALS,) * 4
            turns.done(theta, fp.points[-1])
            if capped:
                lines.append(f"; note: {capped} points of this pass run nearly along the axis: the eye is "
                             f"held at the largest lead, {_fmt(float(np.max(lead)))} mm, off the envelope")
            for i in reduce_points(q, tol):
                texts = [_fmt(v, n) for v, n in zip(table[i], decimals)]
                vals = tuple(float(v) for v in texts)
                words = " ".join(f"{c}{v}" for c, v in zip(pose_letters if robot else letters, texts))
                line = f"POSE {words} {feed}" if robot else f"G1 {words} {feed}"
                if words == last_words:
                    continue
                last_words = words
                lines.append(line)
                moves.append(Move(fp.layer, fp.circuit, fp.number, fp.kind, int(i), vals))
    lines.append(END)
    return lines, moves


def program_moves(plan: WindingPlan, machine: MachineConfig) -> tuple[Move, ...]:
    """The programmed moves (or poses) of gcode_text, in order, with their contact points."""
    return tuple(_program(plan, machine)[1])


def gcode_text(plan: WindingPlan, machine: MachineConfig) -> str:
    """The whole program as text (newline-terminated lines)."""
    return "\n".join(_program(plan, machine)[0]) + "\n"
