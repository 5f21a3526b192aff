"""The payout eye never comes closer to the part than its clearance, along every move (not only at
the programmed points): the controller moves the axes linearly between two points, so each move is
sampled at SAMPLES_PER_MOVE points and the eye's centre (forward kinematics: mandrel-frame
(Z cos(-A), Z sin(-A), X)) measured against the mandrel.

The part is taken as the solid of revolution of the largest section radius r_max(t) over
0 <= t <= T (for a circular section exactly the mandrel; otherwise a conservative hull), its ends
closed: the distance of a point (rho, z) is that to the meridian polyline (r_max(t), t) and to the end
discs. Required: distance - size / 2 >= clearance - chord_tolerance with `eye: {clearance}` (the
envelope puts the body exactly at the clearance; the programmed chords may cut in by the
tolerance), distance - size / 2 > 0 with `eye: {radius}`.

Robot poses (a bent axis, or machine.robot): the eye moves linearly in the mandrel frame between
poses, and the part is the tube of radius r_max(t) around the guide curve, its ends closed by discs
square to the end tangents: a point at distance rho from its closest guide point x(t*) lies
(rho - r_max(t*)) / sqrt(1 + r_max'(t*)^2) from it (exact where r_max is constant; to first order in
the tube's taper otherwise), and past an end as far as from that end's disc. Around a straight guide
(machine.robot on a straight axis: a vessel) the part is the solid of revolution above, measured as
such: its ends those of the table, which a vessel's laminate carries past 0 and T.
"""

from __future__ import annotations

import numpy as np

from winder.config.machine import MachineConfig
from winder.errors import ExportError
from winder.machine.dilation import without_straight_runs
from winder.machine.envelope import EyeEnvelope
from winder.machine.kinematics import Guide
from winder.geometry.measure import grid_groups, row_norms

SAMPLES_PER_MOVE = 8
SLAB_SEGMENTS = 16  # segments measured per point; more in its slab: the nearest vertex's two
SEGMENT_BLOCK = 1 << 20  # point-segment pairs measured at once (memory stays bounded)
SAME_POINT = 1e-10  # mm: moves whose ends agree this closely are sampled once (sampled_moves)
GAP_TOL = 1e-9  # mm: a move this little inside its clearance counts as keeping it


def part_distance(rho: np.ndarray, z: np.ndarray, env: EyeEnvelope) -> np.ndarray:
    """Distance (mm) of meridian points (rho, z) (m,) from the part (module docstring); < 0 inside."""
    t, r = without_straight_runs(env.stations, env.mandrel_radius)
    q = np.column_stack([z, rho])
    # The segment over each point's own station bounds its distance d0 from above, so the nearest
    # point of the meridian lies within the slab |t - z| <= d0: only the segments crossing it count.
    last = t.size - 2
    own = np.clip(np.searchsorted(t, z) - 1, 0, last)
    d0 = _segment_distance(q, t, r, own)
    lo = np.clip(np.searchsorted(t, z - d0, side="left") - 1, 0, last)
    hi = np.clip(np.searchsorted(t, z + d0, side="right") - 1, 0, last)
    best = d0.copy()
    width = hi - lo + 1
    wide = width > SLAB_SEGMENTS
    for w in np.flatnonzero(np.bincount(width[~wide & (width > 1)])):  # np.unique imports numpy.ma
        rows = np.flatnonzero(width == w)
        for chunk in np.array_split(rows, max(1, rows.size * int(w) // SEGMENT_BLOCK)):
            j = lo[chunk, None] + np.arange(w)
            d = _segment_distance(np.repeat(q[chunk], w, axis=0), t, r, j.ravel())
            best[chunk] = np.minimum(best[chunk], d.reshape(-1, w).min(axis=1))
    if wide.any():  # a finely tabulated curved meridian (a dome): the nearest vertex's two segments
        best[wide] = _near_vertex_distance(q[wide], t, r)
    # End discs: a point beyond an end within the end radius is that far from the disc.
    for end, radius in ((t[0], r[0]), (t[-1], r[-1])):
        beyond = (z - end) * (1.0 if end == t[-1] else -1.0)
        on_disc = (beyond > 0.0) & (rho <= radius)
        best = np.where(on_disc, np.minimum(best, beyond), best)
    inside = (z >= t[0]) & (z <= t[-1]) & (rho < np.interp(z, t, r))
    return np.where(inside, -best, best)


def sampled_moves(x0: np.ndarray, z0: np.ndarray, x1: np.ndarray, z1: np.ndarray, f: np.ndarray,
                  env: EyeEnvelope) -> np.ndarray:
    """part_distance (m, k) of the eye centre at the fractions f (k,) of the straight moves from
    (x0, z0) to (x1, z1) (m,) each (carriage, cross-feed). Moves whose ends agree within SAME_POINT
    (a layer's turned circuits) are sampled once: a copy gets its representative's distances less the
    larger of its two ends' separations, which bounds how much nearer the part its own samples lie."""
    first, group = grid_groups(np.column_stack([x0, z0, x1, z1]), SAME_POINT)
    rep = first[group]
    sep = np.maximum(np.hypot(x0 - x0[rep], z0 - z0[rep]), np.hypot(x1 - x1[rep], z1 - z1[rep]))
    x = x0[first, None] + f * (x1 - x0)[first, None]
    z = z0[first, None] + f * (z1 - z0)[first, None]
    d = part_distance(np.abs(z).ravel(), x.ravel(), env).reshape(x.shape)
    return d[group] - sep[:, None]


def _near_vertex_distance(q: np.ndarray, t: np.ndarray, r: np.ndarray) -> np.ndarray:
    """Distance of points q (m, 2) from the two segments around their nearest meridian vertex: on a
    meridian tabulated finely against the eye's distance, the nearest point lies on one of them."""
    from scipy.spatial import cKDTree  # noqa: PLC0415 - scipy.spatial is slow to import: only for domes

    _, k = cKDTree(np.column_stack([t, r])).query(q)
    last = t.size - 2
    return np.minimum(_segment_distance(q, t, r, np.clip(k - 1, 0, last)),
                      _segment_distance(q, t, r, np.clip(k, 0, last)))


def _segment_distance(q: np.ndarray, t: np.ndarray, r: np.ndarray, j: np.ndarray) -> np.ndarray:
    """Distance of points q (m, 2) as (z, rho) from the meridian segments j (m,)."""
    a = np.column_stack([t[j], r[j]])
    seg = np.column_stack([t[j + 1], r[j + 1]]) - a
    u = np.clip(np.einsum("ij,ij->i", q - a, seg) / np.einsum("ij,ij->i", seg, seg), 0.0, 1.0)
    return row_norms(q - a - u[:, None] * seg)


def move_distances(values: np.ndarray, env: EyeEnvelope, guide: Guide | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The eye centre's least distance (mm, < 0 inside) from the part along the move to each row of
    values from the row before, at SAMPLES_PER_MOVE points, and the fraction of the move where it is
    least: two (m,) arrays. values : (m, 4) axes (carriage, rotation, cross_feed, yaw), or with a
    guide (robot poses) (m, >= 3) whose first three columns are the eye position."""
    f = np.linspace(0.0, 1.0, SAMPLES_PER_MOVE + 1)[1:]
    start = np.vstack([values[:1], values[:-1]])
    if guide is not None:
        e = start[:, None, :3] + f[:, None] * (values[:, None, :3] - start[:, None, :3])
        # Each sample's closest station starts between those of its move's two ends.
        at_row = guide.project(values[:, :3])[0]
        before = np.concatenate([at_row[:1], at_row[:-1]])
        near = before[:, None] + f * (at_row - before)[:, None]
        dist = tube_distance(e.reshape(-1, 3), env, guide, near.ravel()).reshape(e.shape[:2])
    else:
        dist = sampled_moves(start[:, 0], start[:, 2], values[:, 0], values[:, 2], f, env)
    k = np.argmin(dist, axis=1)
    return dist[np.arange(dist.shape[0]), k], f[k]


def tube_distance(points: np.ndarray, env: EyeEnvelope, guide: Guide, near: np.ndarray | None = None) -> np.ndarray:
    """Distance (mm, < 0 inside) of points (m, 3) in the mandrel frame from the part around a guide
    curve (module docstring: robot poses); near : (m,) stations close to their closest ones."""
    station, rho = guide.project(points, start=near)
    if guide.curve.is_straight:
        # A straight axis (a vessel wound by a robot): the part is the solid of revolution of r_max, and
        # a point's distance from it that of (rho, station) from the meridian, exactly; the tube's first
        # order in the taper errs by millimetres against a dome's pile-ups (a wall nearly square to the axis).
        return part_distance(rho, station, env)
    # The part's ends: the table's (a vessel's laminate stands past 0 and T), not the guide's.
    lo, hi = env.stations[0], env.stations[-1]
    r = env.mandrel_at(station)
    slope = np.interp(np.clip(station, lo, hi), env.stations, np.gradient(env.mandrel_radius, env.stations))
    beyond = np.maximum(lo - station, 0.0) + np.maximum(station - hi, 0.0)
    past = np.hypot(beyond, np.maximum(rho - r, 0.0))  # from the end disc or its rim
    return np.where(beyond > 0.0, past, (rho - r) / np.sqrt(1.0 + slope * slope))


def clearance_gaps(values: np.ndarray, env: EyeEnvelope, machine: MachineConfig, guide: Guide | None = None,
                   joins: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(worst, need) per row (m,): the eye body's least distance from the part along the move to the
    row, and the least it must keep there (check_collision's rule); a row is too close where
    worst < need - GAP_TOL."""
    # env.clearance holds the centre's distance, c + size / 2: the body must keep c, less the chords' cut.
    need = np.full(values.shape[0], 0.0 if env.clearance is None else
                   env.clearance - 0.5 * machine.eye_size - machine.chord_tolerance)
    if joins is not None:
        need[joins] = 0.0
    return move_distances(values, env, guide)[0] - 0.5 * machine.eye_size, need


def check_collision(values: np.ndarray, env: EyeEnvelope, machine: MachineConfig, where,
                    guide: Guide | None = None, joins: np.ndarray | None = None,
                    gaps: tuple[np.ndarray, np.ndarray] | None = None) -> None:
    """Refuse a program (rows (m, 4): carriage, rotation, cross_feed, yaw; with a guide robot poses,
    position first) whose eye comes too close to the part anywhere along a move; where(row) names
    the move's pass. joins : rows whose moves go from one pass to the next without an approach lift
    (a robot's): the eye body must not touch the part there, it need not keep the clearance.
    gaps : clearance_gaps of these values, where the caller has them."""
    if values.shape[0] == 0:
        return
    worst, need = clearance_gaps(values, env, machine, guide, joins) if gaps is None else gaps
    bad = np.flatnonzero(worst < need - GAP_TOL)
    if bad.size:
        row = int(bad[np.argmin(worst[bad] - need[bad])])
        target = (f"X{values[row, 0]:.3f} Y{values[row, 1]:.3f} Z{values[row, 2]:.3f}" if guide is not None
                  else f"X{values[row, 0]:.3f} A{values[row, 1]:.3f}")
        eye = f"{where(row)}: the payout eye (size {machine.eye_size:g} mm)"
        if worst[row] < 0.0:
            # The body is inside the part: its depth says more than a negative distance would.
            keep = f"; it must stay {need[row]:.3f} mm clear" if need[row] > 0.0 else ""
            raise ExportError(f"{eye} cuts {-worst[row]:.3f} mm into the mandrel (as wound so far) on the move "
                              f"to {target}{keep}")
        raise ExportError(f"{eye} comes within {worst[row]:.3f} mm of the mandrel on the move to {target}, "
                          f"closer than {max(need[row], 0.0):.3f} mm")
