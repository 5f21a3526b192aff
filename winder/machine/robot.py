"""A robot's rows: eye poses of every pass, densified where the exact eye path bows off the chords.

A robot moves the eye linearly in the mandrel frame from pose to pose, while the exact pose between two
planned points lies on the envelope around the guide curve: a chord between poses spaced like the
fiber's points (several mm, around an envelope of radius R) cuts into the clearance by about
L^2 / (8 R) (on the elbow sample 0.13 mm, with a chord tolerance of 0.05 mm). As on a straight
machine (winder.machine.densify), the poses at the interval midpoints, on the exact fiber
(winder.machine.exact), give each
pass's bow in the scaled pose space of the point reduction (position, angle_scale x direction); a
pass bowing more than DENSE_SHARE of the tolerance is resampled at dense_factor points per interval,
which leaves the rest of the tolerance to the point reduction.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from winder.config.machine import MachineConfig
from winder.geometry.measure import row_norms
from winder.machine.batch import all_poses, batch_poses
from winder.machine.densify import dense_factor, dense_u
from winder.machine.envelope import EyeEnvelope
from winder.machine.exact import exact_points
from winder.machine.kinematics import Guide, RobotPoses
from winder.machine.smooth import SmoothPaths
from winder.winding.results import FiberPass, WindingPlan


@dataclasses.dataclass(frozen=True, eq=False)
class RobotRows:
    """The dense pose rows of every non-empty pass, in plan order.

    table : (m, 6) eye position (mm) and unit fiber direction. u : (m,) fractional point index of
    each row in its pass. contacts : (m, 3) contact points. on_envelope : (m,) bool. lead : (m,) mm.
    sizes : (k,) rows per pass. dense : (k,) bool, whether the pass was densified.
    """

    table: np.ndarray
    u: np.ndarray
    contacts: np.ndarray
    on_envelope: np.ndarray
    lead: np.ndarray
    sizes: np.ndarray
    dense: np.ndarray


def robot_rows(plan: WindingPlan, machine: MachineConfig, env: EyeEnvelope, guide: Guide, angle_scale: float,
               tol: float) -> RobotRows:
    """The rows of a robot program for plan (module docstring)."""
    passes = [fp for layer in plan.layers for fp in layer.passes if len(fp.points)]
    if not passes:
        return RobotRows(np.zeros((0, 6)), np.zeros(0), np.zeros((0, 3)), np.zeros(0, dtype=bool), np.zeros(0),
                         np.zeros(0, dtype=int), np.zeros(0, dtype=bool))
    base = all_poses(plan, machine, env, guide)
    where = {id(fp): k for k, fp in enumerate(passes)}
    smooth, slot = {}, {}  # the smooth paths of each layer; each pass's (layer, number in its layer)
    for layer in plan.layers:
        if any(len(fp.points) >= 2 for fp in layer.passes):
            smooth[layer.index] = SmoothPaths(plan.surface_of(layer.index), list(layer.passes))
            slot.update((id(fp), (layer.index, j)) for j, fp in enumerate(layer.passes) if len(fp.points) >= 2)
    two = [fp for fp in passes if id(fp) in slot]
    mids = _poses_at(plan, machine, env, guide, smooth,
                     [(fp, slot[id(fp)], np.arange(len(fp.points) - 1) + 0.5) for fp in two],
                     [base[where[id(fp)]].lead.ravel() for fp in two])
    dense_u_of: dict[int, np.ndarray] = {}
    for fp, (mid, _) in zip(two, mids):
        q = _scaled(base[where[id(fp)]], angle_scale)
        bow = float(np.max(row_norms(_scaled(mid, angle_scale) - 0.5 * (q[:-1] + q[1:]))))
        factor = dense_factor(bow, tol)
        if factor is not None:
            dense_u_of[id(fp)] = dense_u(len(fp.points), factor)
    dense_fp = [fp for fp in two if id(fp) in dense_u_of]
    # The planned points, every factor-th dense row, have their poses already: only the others are solved.
    between = {id(fp): np.mod(dense_u_of[id(fp)], 1.0) != 0.0 for fp in dense_fp}
    found = dict(zip(map(id, dense_fp), _poses_at(plan, machine, env, guide, smooth,
                                                   [(fp, slot[id(fp)], dense_u_of[id(fp)][between[id(fp)]])
                                                    for fp in dense_fp],
                                                   [base[where[id(fp)]].lead.ravel() for fp in dense_fp])))
    rows = []
    for fp, poses in zip(passes, base):
        if id(fp) in found:
            rows.append(_merged(poses, fp, *found[id(fp)], dense_u_of[id(fp)], between[id(fp)]))
        else:
            rows.append((poses, np.arange(len(fp.points), dtype=float), np.asarray(fp.points, dtype=float)))
    return RobotRows(table=np.concatenate([np.column_stack([p.position, p.direction]) for p, _, _ in rows]),
                     u=np.concatenate([u for _, u, _ in rows]), contacts=np.concatenate([c for _, _, c in rows]),
                     on_envelope=np.concatenate([p.on_envelope for p, _, _ in rows]).astype(bool).ravel(),
                     lead=np.concatenate([p.lead for p, _, _ in rows]).ravel(),
                     sizes=np.array([len(u) for _, u, _ in rows], dtype=int),
                     dense=np.array([id(fp) in found for fp in passes], dtype=bool))


def _merged(planned: RobotPoses, fp: FiberPass, poses: RobotPoses, contacts: np.ndarray, u: np.ndarray,
            between: np.ndarray) -> tuple[RobotPoses, np.ndarray, np.ndarray]:
    """(poses, u, contacts) of a densified pass: its planned points' poses at the integer u, the
    dense ones solved (at u[between]) between them."""
    fields = []
    for name in ("position", "direction", "station", "lead", "on_envelope"):
        mine, theirs = np.asarray(getattr(planned, name)), np.asarray(getattr(poses, name))
        out = np.empty((u.size,) + mine.shape[1:], dtype=np.result_type(mine, theirs))
        out[~between], out[between] = mine, theirs
        fields.append(out)
    points = np.empty((u.size, 3))
    points[~between], points[between] = np.asarray(fp.points, dtype=float), contacts
    return RobotPoses(*fields), u, points


def _scaled(poses: RobotPoses, angle_scale: float) -> np.ndarray:
    """The point reduction's pose coordinates (m, 6): position and angle_scale x direction."""
    return np.column_stack([poses.position, angle_scale * poses.direction])


def _poses_at(plan: WindingPlan, machine: MachineConfig, env: EyeEnvelope, guide: Guide, smooth: dict,
              requests: list[tuple[FiberPass, tuple[int, int], np.ndarray]],
              leads: list[np.ndarray]) -> list[tuple[RobotPoses, np.ndarray]]:
    """(poses, contact points (k, 3)) at fractional point indices u of each request (pass, (layer,
    its number there), u (k,)) on its layer's smooth path, the leads interpolated from the planned
    points' (leads, each (n,)) as Newton's start: every point in one solve, pass by pass where that
    fails (naming the pass)."""
    if not requests:
        return []
    points, directions = [], []
    for _, (layer, j), u in requests:
        # The exact fiber between the planned points (a geodesic's ODE where it stands for the fiber), as
        # the straight winder's dense points: next to a joint of the guide the smooth path's direction was
        # 1.3e-3 rad off a hoop's on an elbow's straight leg, its eye 125 mm out 0.17 mm off the fiber.
        _, _, p, d = exact_points(smooth[layer], smooth[layer].offset[j] + u)
        points.append(p)
        directions.append(d)
    guess = np.concatenate([np.interp(u, np.arange(lead.size), lead) for (_, _, u), lead in zip(requests, leads)])
    poses = batch_poses(plan, machine, env, guide, [fp for fp, _, _ in requests], points, directions, guess)
    return list(zip(poses, points))
