"""The motion program of a large plan built a few layers at a time (winder.machine.program), so that
the machine stage's peak memory follows the program it writes, not the plan's densified points.

build_program takes every pass of a plan in one batch: the eye of every planned point, the densify
check's midpoints, the dense points around the domes' turnarounds (up to 64 per planned interval),
the point reduction and the clearance of every move, all held at once: about 7 kB per planned point
on a vessel, where the program keeps a few rows per pass. Here the layers are taken in groups of
about CHUNK_POINTS planned points; each group's program is built alone, its dense arrays freed
before the next (or, given run_groups, on other processes at the same time: winder.app.machine_pool),
and the groups' rows are joined as build_program joins its passes:

- A (rotation) and B (yaw) continue over the program. A group's own program starts at its first
  pass's planned angle; build_program's turn count (winder.machine.axis_batch.turn_counts) shifts a
  pass by whole turns only, and by the same shift every pass after it that continues, so the
  group's A differs from the whole program's by whole turns S (found from the last written row of
  the groups before, as turn_counts finds it from the last pass), and B likewise by 360 deg.
- A group whose first pass starts away from where the last group ended gets build_program's
  approach rows (winder.machine.program.approach); their moves are checked for clearance here.
- The moves' times are those of the joined rows (winder.machine.dynamics.move_times).

A plan of one group, a robot's (no turn count; its joins and cell are the program's), a machine
with rotation or yaw limits (checked on the joined values by build_program alone) or a plan whose
groups wind in another sense than the whole is built by build_program in one batch.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Iterable, Iterator

import numpy as np

from winder.config.machine import MachineConfig
from winder.machine.as_wound import finished_part
from winder.machine.axis_batch import TURN_BACK_DEG
from winder.machine.batch import pass_where
from winder.machine.collision import check_collision
from winder.machine.dynamics import move_times
from winder.machine.envelope import eye_envelope
from winder.machine.program import MotionProgram, Segment, approach, as_written, build_program
from winder.winding.memory_model import PROGRAM_CHUNK_POINTS
from winder.winding.layer_batches import point_groups, whole_plan
from winder.winding.results import FiberPass, WindingPlan

# Planned points of the layers built in one batch (about 4 kB each at the peak on a vessel); the work
# budget's memory estimate counts the same groups.
CHUNK_POINTS = PROGRAM_CHUNK_POINTS
_CONTINUITY_TOL = 1e-9  # rad, as axis_batch: two passes whose angles meet this closely are continuous
_POINT_TOL = 1e-6  # mm, as axis_batch: a pass starting this close to where the last one ended continues it
_TWO_PI = 2.0 * math.pi


def layer_groups(plan: WindingPlan, most: int = CHUNK_POINTS) -> list[tuple]:
    """The plan's layers in order, in groups of at most `most` planned points (a larger layer alone)."""
    points = [sum(len(fp.t) for fp in layer.passes) for layer in plan.layers]
    return [tuple(plan.layers[i] for i in group) for group in point_groups(points, most)]


def _sense_of(layers) -> float:
    """The winding sense build_program gives B for these layers: that of their whole turn."""
    turn = sum(float(fp.theta[-1] - fp.theta[0]) for layer in layers for fp in layer.passes if len(fp.theta))
    return -1.0 if turn < 0.0 else 1.0


def _nonempty(layers) -> list[FiberPass]:
    return [fp for layer in layers for fp in layer.passes if len(fp.points)]


GroupResult = tuple  # a group's own rows: values (m, 4), index (m,), fiber (m,), its layers' segments
GroupRunner = Callable[[Callable[[int], GroupResult], int], Iterable[GroupResult]]


def build_program_in_groups(plan: WindingPlan, machine: MachineConfig, most: int = CHUNK_POINTS,
                            run_groups: GroupRunner | None = None) -> MotionProgram:
    """build_program(plan, machine), built a group of layers at a time (module docstring).

    run_groups(task, n): task(0), .., task(n - 1) (each group's own program), yielded in order and
    each taken as its group is joined; default one after the other. The groups do not depend on one
    another until they are joined, so a caller may build them on several processes
    (winder.app.machine_pool); it is closed when the join stops early."""
    groups = layer_groups(plan, most)
    whole = _sense_of(plan.layers)
    if len(groups) <= 1 or whole_plan(machine, plan.surface) or any(_sense_of(g) != whole for g in groups):
        return build_program(plan, machine)
    part = finished_part(plan)  # every group's eye clears the whole finished part
    env = eye_envelope(plan.outer_surface, machine, part)
    firsts = np.cumsum([0] + [len(g) for g in groups]).tolist()  # each group's first layer

    def task(i: int) -> GroupResult:
        # The layers before stay, without passes: a layer's number is its place in the plan.
        done = firsts[i]
        earlier = tuple(dataclasses.replace(layer, passes=()) for layer in plan.layers[:done])
        own = build_program(dataclasses.replace(plan, layers=earlier + groups[i]), machine, part)
        # its times are recomputed on the joined rows; its dense arrays are gone already
        return own.values, own.index, own.fiber, own.segments[done:]

    results = (run_groups or _one_by_one)(task, len(groups))
    parts: list[tuple] = []  # per group: values, index, fiber, segments (rows numbered in the whole)
    rows, sense = 0, 1.0
    last: FiberPass | None = None  # the last non-empty pass of the groups so far, and its last row
    end_row: np.ndarray | None = None
    try:
        for i, (values, index, fiber, own_segments) in enumerate(results):  # to the end: the pool shuts down
            passes = _nonempty(groups[i])
            added = 0
            if end_row is not None and last is not None and passes and values.shape[0]:
                values, jumped = _joined(end_row, values, last, passes[0], sense)
                lift = approach(end_row, values[0], env.max_radius) if jumped else None
                if lift is not None:
                    added = lift.shape[0]
                    values = np.vstack([lift, values])
                    index = np.concatenate([np.full(added, -1.0), index])
                    fiber = np.concatenate([np.zeros(added), fiber])
                    where = pass_where(plan, passes[0])
                    window = as_written(np.vstack([end_row[None, :], values[:added + 1]]), False)  # as written
                    check_collision(window, env, machine, lambda _row: where)
            parts.append((values, index, fiber, _shifted(own_segments, rows, added)))
            rows += values.shape[0]
            if values.shape[0]:
                end_row = values[-1]
            if passes:
                last = passes[-1]
                sense = _sense_after(passes, sense)
    finally:  # the workers of groups not yet joined stop when the join fails
        close = getattr(results, "close", None)
        if close is not None:
            close()
    values = np.vstack([p[0] for p in parts])
    fiber = np.concatenate([p[2] for p in parts])
    times = move_times(values, fiber, machine, False)
    return MotionProgram(
        name=plan.name, source=plan.source, robot=False, machine=machine, layers=tuple(plan.layers),
        total_fiber_length_mm=plan.total_fiber_length_mm, envelope_radius=env.constant,
        envelope_clearance=env.clearance, values=values, feed=times.feed,
        index=np.concatenate([p[1] for p in parts]),
        segments=tuple(s for p in parts for s in p[3]), fiber=fiber, times=times,
        mandrel_radius=float(np.max(env.mandrel_radius)), axial_length=float(plan.outer_surface.axial_length))


def _one_by_one(task: Callable[[int], GroupResult], n: int) -> Iterator[GroupResult]:
    """The groups one after the other, each one's dense arrays freed before the next is built."""
    return (task(i) for i in range(n))


def _joined(end_row: np.ndarray, values: np.ndarray, prev: FiberPass, first: FiberPass,
            sense: float) -> tuple[np.ndarray, bool]:
    """A group's rows (m, 4) with A and B continued from the row end_row (the whole program's last so
    far, after the pass prev) as turn_counts continues them, and whether its first pass jumped."""
    a_end, b_end = float(end_row[1]), float(end_row[3])
    theta_end = float(prev.theta[-1])
    # The whole program's angle offset at prev: whole turns; A = -(theta + offset + lead) in degrees,
    # the lead within half a turn.
    offset = _TWO_PI * float(np.rint((-math.radians(a_end) - theta_end) / _TWO_PI))
    end = theta_end + offset
    t0 = float(first.theta[0])
    offset += _TWO_PI * float(np.rint((end - (t0 + offset)) / _TWO_PI))
    gap = t0 + offset - end
    jumped = abs(gap) > _CONTINUITY_TOL or float(np.linalg.norm(first.points[0] - prev.points[-1])) > _POINT_TOL
    if abs(gap) > _CONTINUITY_TOL and gap * sense < 0.0:
        offset += _TWO_PI * sense
    if jumped and (float(values[0, 1]) - math.degrees(offset) - a_end) * sense > TURN_BACK_DEG:
        offset += _TWO_PI * sense  # the eye would turn back on the way to this pass: one more turn
    out = values.copy()
    out[:, 1] -= math.degrees(offset)
    out[:, 3] += 360.0 * float(np.rint((b_end - float(values[0, 3])) / 360.0))
    return out, jumped


def _shifted(segments: tuple, rows: int, added: int) -> list[tuple[Segment, ...]]:
    """A group's segments with their rows numbered in the whole program: `added` approach rows in
    front of its first non-empty pass, the group's rows from row `rows` on."""
    out = []
    for segs in segments:
        layer = []
        for seg in segs:
            if seg.stop == 0:  # empty, before any row of the group
                layer.append(dataclasses.replace(seg, start=rows, stop=rows))
            elif seg.start == 0:  # the first non-empty pass: the approach rows are its own
                layer.append(dataclasses.replace(seg, start=rows, stop=rows + added + seg.stop,
                                                 approach=seg.approach + added))
            else:
                layer.append(dataclasses.replace(seg, start=rows + added + seg.start, stop=rows + added + seg.stop))
        out.append(tuple(layer))
    return out


def _sense_after(passes: list[FiberPass], sense: float) -> float:
    """The winding sense turn_counts holds after these passes: that of the last one that turns."""
    for fp in reversed(passes):
        turn = float(fp.theta[-1]) - float(fp.theta[0])
        if turn != 0.0 and not math.isnan(turn):
            return math.copysign(1.0, turn)
    return sense
