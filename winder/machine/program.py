"""One motion program on logical axes: what the machine does to lay a winding plan (docs/math/06-machine.md).

Straight-axis winder: per kept contact point the four logical axes carriage (mm), rotation (deg,
cumulative over the whole program), cross_feed (mm) and yaw (deg, continuous), from
winder.machine.kinematics.eye_path, with the feed on every move. Rotation continues from pass to pass
and layer to layer: to reach a pass that starts elsewhere (a new layer) the mandrel turns on in its
winding sense, less than a turn for the contact point and never back more than
winder.machine.axis_batch.TURN_BACK_DEG for the eye; yaw keeps its turn count across passes. Every
pass is checked against machine.limits.

Robot mode (machine.robot, or a bent mandrel axis): instead of axis values, eye poses in the mandrel
frame (position, and the unit fiber direction from the eye to its contact point;
winder.machine.kinematics.robot_poses).

Point reduction: of each pass's contact points, a point is dropped when its axis values lie within
machine.chord_tolerance of the straight (axis-space) move between the kept neighbours, distances in
the scaled axis space (carriage and cross-feed in mm, rotation as the arc at the largest eye radius,
yaw as the arc that makes YAW_TOLERANCE_DEG count as one chord tolerance; robot poses: position in mm,
direction as YAW_TOLERANCE_DEG): Douglas-Peucker, so every dropped point is within the tolerance of
the move that replaces it. The first and last point of each pass are kept.

A controller dialect (winder.export.dialects) only serializes the program: letters, number format,
preamble, comments.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from winder.config.machine import MachineConfig
from winder.machine.as_wound import finished_part
from winder.machine.cell import CellMotion, cell_motion
from winder.machine.chords import CLEAR_ROUNDS, refine
from winder.machine.collision import GAP_TOL, check_collision, clearance_gaps
from winder.machine.batch import all_dense, all_leads, all_midpoints, pass_where
from winder.machine.densify import DENSE_SHARE
from winder.machine.dynamics import MoveTimes, move_times
from winder.machine.envelope import eye_envelope
from winder.machine.axis_batch import straight_axes
from winder.machine.kinematics import eye_path, make_guide
from winder.machine.limits import AXIS_DECIMALS
from winder.machine.robot import robot_rows
from winder.machine.reduce import far_contacts, reduce_table
from winder.machine.smooth import SmoothPaths
from winder.machine.straight import straight_passes
from winder.winding.layer_batches import robot_poses
from winder.winding.results import FiberPass, LayerPlan, PassKind, WindingPlan
from winder.geometry.measure import row_norms

YAW_TOLERANCE_DEG = 0.5  # a yaw (or fiber direction) deviation this large counts as chord_tolerance
# The clearance holds for the program as written (AXIS_DECIMALS decimals): each written carriage and
# cross-feed value lies within half a unit of the last decimal of the computed one, which moves the eye
# up to ROUNDING_MARGIN (the part is a solid of revolution: A does not move the eye off it), kept out of
# the point reduction's tolerance. A pass whose written moves still come too close (a dense polyline's
# bow above its estimate) is reduced again at TIGHTEN times its tolerance, at most TIGHTEN_ROUNDS times.
ROUNDING_MARGIN = float(np.hypot(0.5, 0.5)) * 10.0 ** -AXIS_DECIMALS
TIGHTEN = 0.5
TIGHTEN_ROUNDS = 6

AXES = ("carriage", "rotation", "cross_feed", "yaw")
APPROACH = "approach"  # the comment word of a pass's approach rows (Segment.approach)
POSE_AXES = ("x", "y", "z", "i", "j", "k")


@dataclasses.dataclass(frozen=True)
class Segment:
    """One pass of the program: its moves are rows [start, stop) of the program's arrays.

    capped : how many of the pass's contact points run so nearly along the axis that the eye is held
    at the largest lead, max_lead (mm), off the envelope (0: none).
    """

    layer: int
    circuit: int
    number: int
    kind: PassKind
    start: int
    stop: int
    capped: int = 0
    max_lead: float = 0.0
    approach: int = 0  # leading rows that bring the eye from another pass clear of the part (no fiber)
    tension: float | None = None  # N per band while this pass is wound (winder.machine.tension); None: none set


@dataclasses.dataclass(frozen=True, eq=False)
class MotionProgram:
    """The machine's moves for a whole plan, before any controller's text.

    values : (m, 4) float, the logical axes AXES (carriage mm, rotation deg, cross_feed mm, yaw deg)
        of each move; for a robot (m, 6), the eye pose POSE_AXES (position mm, unit direction).
    feed : (m,) float, fiber feed of each move (mm/min; machine.feed unless an axis' top speed limits
        it). index : (m,) float, the move's contact point in its pass: the point index, fractional where
        the pass was densified between planned points (winder.machine.densify). fiber : (m,) float, the fiber the
        move to the row lays (mm, along the pass's points; 0 for the first row of a pass).
    times : the moves' cruise and profiled times from machine.dynamics (winder.machine.dynamics).
    layers : the plan's layers (comments); segments : per layer, its passes in order (empty passes too).
    envelope_radius / envelope_clearance : the eye envelope, one of them set.
    """

    name: str
    source: str
    robot: bool
    machine: MachineConfig
    layers: tuple[LayerPlan, ...]
    total_fiber_length_mm: float
    envelope_radius: float | None
    envelope_clearance: float | None
    values: np.ndarray
    feed: np.ndarray
    index: np.ndarray
    segments: tuple[tuple[Segment, ...], ...]
    fiber: np.ndarray
    times: MoveTimes
    mandrel_radius: float = 0.0  # the mandrel's largest section radius (mm)
    axial_length: float = 0.0  # the mandrel's length along its axis (mm)
    cell: CellMotion | None = None  # a robot cell's motion (machine.robot as a mapping), its times the program's
    invariants: object = None  # winder.machine.invariants.Invariants, once the job has proved them

    @property
    def layer_times_s(self) -> tuple[float, ...]:
        """Profiled time of each layer: the moves ending on its rows."""
        out = []
        for segs in self.segments:
            lo, hi = (segs[0].start, segs[-1].stop) if segs else (0, 0)
            out.append(float(np.sum(self.times.time_s[lo:hi])))
        return tuple(out)

    @property
    def axes(self) -> tuple[str, ...]:
        return POSE_AXES if self.robot else AXES

    @property
    def layer_tensions(self) -> tuple[tuple[float, float, float] | None, ...]:
        """Per layer (its first pass's, least, largest) tension (N), None where none is programmed."""
        out = []
        for segs in self.segments:
            values = [seg.tension for seg in segs if seg.tension is not None]
            out.append((values[0], min(values), max(values)) if values else None)
        return tuple(out)


def approach(last: np.ndarray, first: np.ndarray, clear: float) -> np.ndarray | None:
    """Rows (2, 4) that take the eye from the row `last` to a pass starting elsewhere (`first`, a new
    layer) around the part, not through it: out to the cross-feed `clear` (the envelope's largest
    radius), along, and in; the mandrel turning on meanwhile (a third of the turn per move). None
    where both lie at `clear` (a straight move there keeps clear)."""
    if min(last[2], first[2]) >= clear - 1e-9:
        return None
    da = first[1] - last[1]
    return np.array([[last[0], last[1] + da / 3.0, clear, last[3]],
                     [first[0], last[1] + 2.0 * da / 3.0, clear, first[3]]])


def _stepwise(plan: WindingPlan, nonempty: list[FiberPass], wheres: list[str], env, machine: MachineConfig,
              sense: float, surface, tol: float, scaled, least: list | None = None) -> tuple:
    """straight_passes' result step by step: the leads, the densify check and the dense points of
    winder.machine.batch, then axis_batch.straight_axes; a refusal names its pass. least: as
    straight_passes'."""
    leads = all_leads(plan, env)
    lead_of = {id(fp): lead for fp, lead in zip(nonempty, leads)}
    # Each layer's smooth paths lie on the surface it was wound on (the mandrel grown by the layers below).
    smooth = {layer.index: SmoothPaths(plan.surface_of(layer.index), list(layer.passes)) for layer in plan.layers}
    number = {id(fp): j for layer in plan.layers for j, fp in enumerate(layer.passes)}
    mids = all_midpoints(plan, smooth, number, env)

    def axes_of(fp: FiberPass):
        where = pass_where(plan, fp)
        return lambda p, d, th, ld: scaled(eye_path(p, d, surface, machine, theta=th, envelope=env, sense=sense,
                                                    where=where, lead=ld))

    def axes_many(p, d, th, ld, sizes) -> np.ndarray:
        return scaled(eye_path(p, d, surface, machine, theta=th, envelope=env, sense=sense, lead=ld, sizes=sizes))

    more = {} if least is None else {id(fp): v for fp, v in zip(nonempty, least) if v is not None}
    dense_of = all_dense(plan, smooth, number, lead_of, mids, env, axes_of, tol, axes_many, least=more)
    dense = [dense_of.get(id(fp)) for fp in nonempty]
    path, sizes, jumped = straight_axes(nonempty, wheres, leads, dense, env, machine, sense)
    return (path, sizes, jumped, [None if dn is None else dn[3] for dn in dense],
            np.concatenate([fp.points if dn is None else dn[0] for fp, dn in zip(nonempty, dense)]))


def _moves(laid: tuple, kept: list[np.ndarray], width: int) -> tuple[np.ndarray, ...]:
    """The program's rows from the laid passes (build_program's arrays of all passes, one after the
    other: table, u, contact points, on_envelope, lead; each pass's rows; its approach rows) and the
    rows each keeps: (values (m, width), index (m,), fiber (m,); per pass its approach rows, its
    capped points and its largest lead), every pass at once. The fiber of a row is the polyline
    length along the pass's contact points since its last kept row, from each pass's own running sum
    (the same sums as pass by pass: the passes of one size are rows of one cumsum), scaled so that
    the pass's rows lay its own length (laid's `lengths`, the smooth path's): the chords between
    planned points run short of the path (0.5 % on a 55 deg helix of 30 points), and the feed limit
    would let the fiber run that much faster than machine.feed."""
    table, u, points, on_envelope, lead, n, lifts, lengths = laid
    if n.size == 0:
        return np.zeros((0, width)), np.zeros(0), np.zeros(0), *(np.zeros(0, dtype=int),) * 2, np.zeros(0)
    start = np.cumsum(n) - n
    step = row_norms(points[1:] - points[:-1])  # np.diff per pass (and across passes, unused)
    along = np.zeros(points.shape[0])
    by_size: dict[int, list[int]] = {}
    for i, k in enumerate(n.tolist()):
        if k >= 2:
            by_size.setdefault(k, []).append(i)
    for k, group in by_size.items():
        at = start[group][:, None] + np.arange(k - 1)
        along[at + 1] = np.cumsum(step[at], axis=1)
    ends = start + np.maximum(n - 1, 0)
    chord = along[ends]
    scale = np.where(chord > 0.0, np.asarray(lengths, dtype=float) / np.where(chord > 0.0, chord, 1.0), 1.0)
    along *= np.repeat(scale, n)
    rows = np.concatenate([keep + s for keep, s in zip(kept, start.tolist())])
    counts = np.array([keep.size for keep in kept], dtype=int)
    first = np.cumsum(counts) - counts
    contact = far_contacts(table, points, u, n, rows, first, as_written(table[rows], width > 4))  # a flat's far end
    at_kept = np.interp(contact, np.arange(along.size), along)
    fiber = np.empty(at_kept.size)
    fiber[1:] = at_kept[1:] - at_kept[:-1]
    fiber[first] = at_kept[first] - at_kept[first]  # each pass's first row lays nothing (as np.diff's prepend)
    values, index = table.take(rows, axis=0), np.interp(contact, np.arange(u.size), u)  # take: beats fancy indexing
    lifted = np.zeros(n.size, dtype=int)
    if lifts:  # a pass's approach rows go before its first kept row: no fiber, index -1
        at = np.concatenate([np.full(lift.shape[0], first[i]) for i, lift in lifts])
        values = np.insert(values, at, np.concatenate([lift for _, lift in lifts]), axis=0)
        index, fiber = np.insert(index, at, -1.0), np.insert(fiber, at, 0.0)
        lifted[[i for i, _ in lifts]] = [lift.shape[0] for _, lift in lifts]
    capped = np.add.reduceat((~on_envelope).astype(int), start)
    max_lead = np.maximum.reduceat(np.asarray(lead, dtype=float), start)
    return values, index, fiber, lifted, capped, max_lead


def as_written(values: np.ndarray, robot: bool) -> np.ndarray:
    """The program's rows (m, 4) or robot poses (m, 6) as the dialects print them (positions and axes
    AXIS_DECIMALS decimals, a pose's unit direction ROBOT_DIRECTION_DECIMALS)."""
    if not robot:
        return np.round(values, AXIS_DECIMALS)
    return np.column_stack([np.round(values[:, :3], AXIS_DECIMALS), np.round(values[:, 3:], ROBOT_DIRECTION_DECIMALS)])


ROBOT_DIRECTION_DECIMALS = 6  # winder.export.dialects.robot writes a pose's direction so


def _kept_clear(q: np.ndarray, sizes: np.ndarray, tols: np.ndarray, laid: tuple, width: int, env,
                machine: MachineConfig, guide) -> tuple:
    """The point reduction (winder.machine.reduce, every pass in one batch) whose moves, as written,
    keep the clearance: (kept per pass, _moves' arrays, joins, clearance_gaps of the written rows).
    joins : a robot's rows that go straight from one pass's last pose to the next's first (no approach
    lift), else None. A pass with a written move too close is reduced again at a tighter tolerance
    (ROUNDING_MARGIN's comment); what no tolerance cures is left to check_collision to refuse."""
    tols = np.array(tols, dtype=float)
    kept = reduce_table(q, sizes, tols)
    q_start = np.cumsum(sizes) - sizes
    for _ in range(TIGHTEN_ROUNDS + 1):
        moves = _moves(laid, kept, width)
        counts = moves[3] + np.array([k.size for k in kept], dtype=int)
        row_start = np.cumsum(counts) - counts
        joins = row_start[(row_start > 0) & (counts > 0)] if guide is not None else None
        gaps = clearance_gaps(as_written(moves[0], guide is not None), env, machine, guide, joins)
        bad_rows = np.flatnonzero(gaps[0] < gaps[1] - GAP_TOL)
        bad = np.unique(np.searchsorted(row_start, bad_rows, side="right") - 1)
        bad = bad[np.array([kept[k].size < sizes[k] for k in bad.tolist()], dtype=bool)] if bad.size else bad
        if bad.size == 0:
            break
        tols[bad] *= TIGHTEN
        sub = np.concatenate([q[q_start[k]:q_start[k] + sizes[k]] for k in bad.tolist()])
        for k, again in zip(bad.tolist(), reduce_table(sub, sizes[bad], tols[bad])):
            kept[k] = again
    return kept, moves, joins, gaps


def build_program(plan: WindingPlan, machine: MachineConfig, part=finished_part) -> MotionProgram:
    """The motion program of a plan on a machine (module docstring; docs/math/06-machine.md).

    Parameters
    ----------
    plan : WindingPlan
        The planned layers (winder.winding.plan.plan).
    machine : MachineConfig
        The winder: axes, eye envelope, feed, chord tolerance, limits, dynamics, robot mode.
    part : WoundProfile, None or callable
        The finished part (winder.machine.as_wound), which the eye clears, or the function of the
        plan giving it.

    Returns
    -------
    MotionProgram
        `values` (m, 4): carriage (mm), rotation (deg, cumulative), cross-feed (mm), yaw (deg) per
        move, or (m, 6) eye poses for a robot; the feed, the fiber each move lays, the moves' times,
        and the passes each layer's rows belong to.

    Raises
    ------
    ExportError
        Where the eye cannot clear the mandrel or an axis would leave machine.limits, naming the pass.

    Examples
    --------
    >>> from winder.config.job import parse_config
    >>> from winder.winding.plan import plan
    >>> hoops = {"band_width": 10, "layers": [{"type": "hoop", "passes": 2}]}
    >>> tube = {"axis": {"type": "line", "length": 300}, "profile": {"type": "constant", "radius": 50}}
    >>> job = parse_config({"name": "tube", "mandrel": tube, "winding": hoops}, "tube.yaml")
    >>> program = build_program(plan(job), job.machine)
    >>> program.values.shape[1]  # carriage, rotation, cross-feed, yaw
    4
    >>> round(float(program.values[:, 2].min()), 6)  # the eye keeps the default 20 mm clearance: radius 50 + 20
    70.0
    """
    robot = robot_poses(machine, plan.surface)  # a bent axis or machine.robot
    surface = plan.outer_surface  # the eye clears the finished part, laminate included
    env = eye_envelope(surface, machine, part(plan) if callable(part) else part)
    guide = make_guide(surface, env) if robot else None
    tol = float(machine.chord_tolerance)
    angle_scale = tol / np.radians(YAW_TOLERANCE_DEG)  # mm per radian of yaw / direction
    arc_radius = env.max_radius  # the mandrel-turn arc of A, at the largest eye radius

    def scaled(path) -> np.ndarray:
        return np.column_stack([path.x, path.z, np.radians(path.a_deg) * arc_radius,
                                np.radians(path.b_deg) * angle_scale])

    layer_segments: list[tuple[Segment, ...]] = []
    count = 0
    progress = sum(float(fp.theta[-1] - fp.theta[0]) for layer in plan.layers for fp in layer.passes
                   if len(fp.theta))
    sense = -1.0 if progress < 0.0 else 1.0  # the winding sense of the whole program (for B)
    nonempty = [fp for layer in plan.layers for fp in layer.passes if len(fp.points)]
    wheres = [pass_where(plan, fp) for fp in nonempty]
    # The laid passes, one after the other: axis table, scaled axes, fractional point index u, contact
    # points, on_envelope, lead; each pass's rows, whether it was densified; its approach rows.
    sizes = np.array([len(fp.points) for fp in nonempty], dtype=int)
    dense = np.zeros(len(nonempty), dtype=bool)
    lifts: list[tuple[int, np.ndarray]] = []
    cut = np.zeros(len(nonempty))  # each pass's dense polyline's largest cut into the clearance (mm)
    if robot:
        rows = robot_rows(plan, machine, env, guide, angle_scale, tol)
        table, u, contacts, on_envelope, lead = rows.table, rows.u, rows.contacts, rows.on_envelope, rows.lead
        q = np.column_stack([table[:, :3], angle_scale * table[:, 3:]])
        sizes, dense = rows.sizes, rows.dense
    elif nonempty:
        # The dense polyline keeps the clearance by construction (docs/math/13-clearance-chords.md): measured,
        # and cut finer where a move still cuts in (a few rounds at most; none on a cylinder).
        least, planned = None, np.array([len(fp.points) for fp in nonempty], dtype=np.int64)
        for _ in range(CLEAR_ROUNDS + 1):
            found = straight_passes(plan, nonempty, wheres, env, machine, sense, arc_radius, angle_scale, tol, least)
            path, sizes, jumped, us, contacts = found if found is not None else _stepwise(
                plan, nonempty, wheres, env, machine, sense, surface, tol, scaled, least)
            u = np.concatenate([np.arange(k, dtype=float) if v is None else v for k, v in zip(sizes.tolist(), us)])
            least, cut = refine(path.x, path.z, sizes, u, planned, env, DENSE_SHARE * tol, least)
            if least is None:
                break
        table = np.column_stack([path.x, path.a_deg, path.z, path.b_deg])
        q, on_envelope, lead = scaled(path), path.on_envelope, path.lead
        dense = np.array([u is not None for u in us], dtype=bool)
        last = np.cumsum(sizes) - 1
        for k in np.flatnonzero(jumped).tolist():
            lift = approach(table[last[k - 1]], table[last[k] - sizes[k] + 1], env.max_radius) if k else None
            if lift is not None:
                lifts.append((k, lift))
    else:
        table = q = np.zeros((0, 4))
        u, contacts, on_envelope, lead = np.zeros(0), np.zeros((0, 3)), np.zeros(0, dtype=bool), np.zeros(0)
    # A densified pass leaves DENSE_SHARE of the tolerance to the dense polyline's own bow; every pass
    # its own polyline's cut into the clearance (docs/math/13-clearance-chords.md 13.2).
    tols = np.maximum(np.minimum(np.where(dense, tol * (1.0 - DENSE_SHARE), tol), tol - cut) - ROUNDING_MARGIN, 0.0)
    width = len(POSE_AXES if robot else AXES)
    laid = (table, u, contacts, on_envelope, lead, sizes, lifts, [fp.length for fp in nonempty])
    kept, moves, joins, gaps = _kept_clear(q, sizes, tols, laid, width, env, machine, guide)
    values, index, fiber, lifted, capped, max_lead = moves
    sizes_of = iter((lifted + np.array([k.size for k in kept], dtype=int)).tolist())
    per_pass = iter(zip(lifted.tolist(), capped.tolist(), max_lead.tolist()))
    for layer in plan.layers:
        segments: list[Segment] = []
        for fp in layer.passes:
            if len(fp.points) == 0:
                segments.append(Segment(fp.layer, fp.circuit, fp.number, fp.kind, count, count))
                continue
            size = next(sizes_of)
            lift, cap, top = next(per_pass)
            segments.append(Segment(fp.layer, fp.circuit, fp.number, fp.kind, count, count + size, cap,
                                    top if cap else 0.0, lift))
            count += size
        layer_segments.append(tuple(segments))
    starts = [(seg.start, seg) for segs in layer_segments for seg in segs if seg.stop > seg.start]

    def where(row: int) -> str:  # the pass of a row, named as the batches name a pass
        return pass_where(plan, max((s for s in starts if s[0] <= row), key=lambda s: s[0])[1])

    check_collision(values, env, machine, where, guide, joins, gaps)
    cell = None
    if robot and machine.cell:
        pass_start = np.zeros(values.shape[0], dtype=bool)
        pass_start[[seg.start for _, seg in starts]] = True
        cell = cell_motion(machine, guide, values, fiber, where, plan.source, pass_start, surface)
    times = cell.program_times if cell is not None else move_times(values[:, :3] if robot else values, fiber, machine, robot)
    return MotionProgram(
        name=plan.name, source=plan.source, robot=robot, machine=machine, layers=tuple(plan.layers),
        total_fiber_length_mm=plan.total_fiber_length_mm, envelope_radius=env.constant,
        envelope_clearance=env.clearance, values=values, feed=times.feed,
        index=index,
        segments=tuple(layer_segments), fiber=fiber, times=times,
        mandrel_radius=float(np.max(env.mandrel_radius)), axial_length=float(surface.axial_length), cell=cell)
