"""Densifying a pass where the eye moves fast: the controller interpolates the axes linearly between
two programmed points, and the exact eye path between two planned points can bow far from that line
(near a dome's turnaround the mandrel turns quickly while the contact point hardly moves).

Per pass: the axis values at the midpoints of the planned point intervals (on the smooth path,
winder.machine.smooth; inside a geodesic interval the exact
geodesic, winder.machine.exact) against the chords' midpoints give each interval's bow e (in the scaled axis
space of the point reduction). A smooth curve's bow falls as 1 / K^2 when its interval is cut in K,
so each interval is resampled at its own K = ceil(sqrt(e / (tol / 4))) points (at most MAX_FACTOR),
which puts the exact eye path within a quarter of the chord tolerance of the dense polyline; the point
reduction then keeps what the rest of the chord tolerance allows. Where the axes are linear in the
point index (a helix on a cylinder) e = 0 and the interval is left as planned: on a vessel only the
dome turnarounds are densified, not the whole pass for its worst stretch (the dense points, and with
them the machine stage's memory, follow the output).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from winder.machine.chords import CLEAR_MAX_FACTOR, move_cuts, pieces
from winder.machine.exact import exact_points
from winder.machine.smooth import SmoothPaths
from winder.winding.results import FiberPass
from winder.geometry.measure import row_norms

MAX_FACTOR = 64  # dense points per planned interval, at most
DENSE_SHARE = 0.25  # of the chord tolerance, left to the dense polyline's own bow
NEIGHBOURS = 4  # intervals either side whose factor an interval takes too (interval_factors); with 2 a dome
# turnaround's move midpoints strayed 0.062 mm from the plan on vessel_hemi, past its 0.05 chord tolerance


def dense_factor(bow: float, tol: float) -> int | None:
    """The dense points per planned interval of a pass whose intervals bow up to `bow` off their
    chords, or None where the planned points suffice (module docstring)."""
    factor = int(pieces(np.array([bow]), DENSE_SHARE * tol, MAX_FACTOR)[0])
    return None if factor <= 1 else factor


def interval_factors(bows: np.ndarray, tol: float, floor: np.ndarray | None = None) -> np.ndarray | None:
    """(n - 1,) int: the dense points of each planned interval of a pass whose intervals bow `bows`
    (n - 1,) off their chords, at least floor (n - 1,) (the clearance's, clearance_floor), or None
    where the planned points suffice (module docstring)."""
    factors = pieces(bows, DENSE_SHARE * tol, MAX_FACTOR)
    if np.any(factors > 1):
        # A midpoint can miss a corner of the eye's path inside its interval (the eye rounding a tube's
        # end during a dwell, where the midpoint's eye still lies on the level part): each interval takes
        # the largest factor of the NEIGHBOURS intervals either side. The clearance's floor measures the
        # moves themselves and needs no such margin.
        padded = np.pad(factors, NEIGHBOURS, mode="edge")
        width = factors.size
        factors = np.max(np.stack([padded[k:k + width] for k in range(2 * NEIGHBOURS + 1)]), axis=0)
    if floor is not None:
        factors = np.maximum(factors, floor)
    return factors if np.any(factors > 1) else None


def varying_u(factors: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(u, interval): the dense fractional point indices ((sum factors) + 1,) of a pass whose planned
    interval i is cut in factors[i], the planned points exactly at the integers (u = i + j / K_i, the
    midpoint exactly i + 0.5 where K_i is even), and each dense point's interval (the last point's n - 1)."""
    factors = np.asarray(factors, dtype=np.int64)
    interval = np.repeat(np.arange(factors.size + 1), np.append(factors, 1))
    first = np.cumsum(factors) - factors
    j = np.arange(interval.size - 1) - np.repeat(first, factors)
    u = interval.astype(float)
    u[:-1] += j / np.repeat(factors, factors)
    return u, interval


def dense_u(n: int, factor: int) -> np.ndarray:
    """((n - 1) factor + 1,) the dense fractional point indices of a pass of n points, the planned
    points exactly every factor-th."""
    u = np.linspace(0.0, n - 1.0, (n - 1) * factor + 1)
    u[::factor] = np.arange(n)  # the planned points exactly
    return u


def clearance_floor(x: np.ndarray, z: np.ndarray, sizes: np.ndarray, env, tol: float,
                    least: list | None = None) -> np.ndarray:
    """(sum(sizes - 1),) int: the pieces each planned interval of runs of sizes (k,) planned points
    (carriage x and cross-feed z (m,) of their eyes) is cut in at least for the clearance
    (docs/math/13-clearance-chords.md 13.3: its chord's cut, and least, per run None or (size - 1,),
    where the dense polyline was measured before, winder.machine.chords.refine); ones without env."""
    sizes = np.asarray(sizes, dtype=np.int64)
    moves = np.maximum(sizes - 1, 0)
    if env is None:
        floor = np.ones(int(moves.sum()), dtype=np.int64)
    else:
        floor = pieces(move_cuts(x, z, sizes, env), DENSE_SHARE * tol, CLEAR_MAX_FACTOR)
    for start, more in zip((np.cumsum(moves) - moves).tolist(), least or ()):
        if more is not None:
            floor[start:start + more.size] = np.maximum(floor[start:start + more.size], more)
    return floor


def dense_index(bows: np.ndarray, tol: float, floor: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray] | None:
    """(planned, u): which dense points are planned ones and the dense point indices of a pass whose
    intervals bow `bows` (n - 1,), cut at least in floor (n - 1,), or None where the planned points
    suffice."""
    factors = interval_factors(bows, tol, floor)
    if factors is None:
        return None
    u, _ = varying_u(factors)
    return u == np.floor(u), u


def midpoints(paths: SmoothPaths, j: int, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(points (n-1, 3), directions (n-1, 3), theta (n-1,)) on the smooth path of pass j (n points)
    halfway between its planned points."""
    _, th, p, d = exact_points(paths, paths.offset[j] + np.arange(n - 1) + 0.5)
    return p, d, th


def densify(paths: SmoothPaths, j: int, fp: FiberPass, theta: np.ndarray, axes: Callable, tol: float,
            base_lead=None, mid=None, env=None, least: np.ndarray | None = None):
    """(points (k, 3), directions (k, 3), theta (k,), u (k,) fractional planned point index) of pass
    j resampled for the chord tolerance, or None where the planned points suffice. theta : (n,) the
    pass's program angles (unwrapped, with the program's turn count). axes(points, directions, theta,
    lead) -> (k, c) the scaled axis values of those contact points (lead: their eye leads, or None).
    base_lead : the planned points' leads; mid : (points, directions, theta, leads) of the midpoints,
    when the caller computed them for many passes at once (the leads are pointwise). env, least:
    the eye envelope and the pass's least pieces per interval for the clearance (clearance_floor)."""
    n = len(fp.s)
    if n < 2:
        return None
    shift = float(theta[0] - fp.theta[0])  # whole turns the program adds
    base = axes(fp.points, fp.direction, theta, base_lead)
    if mid is None:
        p_mid, d_mid, th_mid = midpoints(paths, j, n)
        mid_lead = None
    else:
        p_mid, d_mid, th_mid, mid_lead = mid
    q_mid = axes(p_mid, d_mid, th_mid + shift, mid_lead)
    floor = clearance_floor(base[:, 0], base[:, 1], np.array([n]), env, tol, [least])
    found = dense_index(row_norms(q_mid - 0.5 * (base[1:] + base[:-1])), tol, floor)
    if found is None:
        return None
    planned, u = found
    _, th, p, d = exact_points(paths, paths.offset[j] + u)
    p[planned], d[planned], th[planned] = fp.points, fp.direction, fp.theta
    return p, d, th + shift, u


def densify_many(paths: SmoothPaths, numbers: list[int], passes: list[FiberPass], axes_many: Callable,
                 tol: float, base_lead: tuple[np.ndarray, np.ndarray],
                 mid: tuple[np.ndarray, np.ndarray, np.ndarray, tuple[np.ndarray, np.ndarray]],
                 env=None, least: list | None = None) -> list:
    """densify of the passes (each >= 2 points) of one smooth-path set at their planned turn counts,
    in one batch: the same (points, directions, theta, u) or None per pass. numbers : each pass's j.
    axes_many(points, directions, theta, lead, sizes) -> the scaled axis values of consecutive runs of
    contact points of those sizes. base_lead : the passes' points' leads, concatenated; mid : the
    concatenated (points, directions, theta, leads) of their midpoints (sizes n_i - 1). env, least:
    as densify's, least per pass."""
    sizes = np.array([len(fp.s) for fp in passes])
    base = axes_many(np.concatenate([fp.points for fp in passes]), np.concatenate([fp.direction for fp in passes]),
                     np.concatenate([np.asarray(fp.theta, dtype=float) for fp in passes]), base_lead, sizes)
    p_mid, d_mid, th_mid, mid_lead = mid
    q_mid = axes_many(p_mid, d_mid, th_mid + 0.0, mid_lead, sizes - 1)  # + 0.0: densify's zero shift
    last = np.zeros(len(base), dtype=bool)
    last[np.cumsum(sizes) - 1] = True
    k = np.flatnonzero(~last)  # each interval's first point
    err = row_norms(q_mid - 0.5 * (base[k + 1] + base[k]))
    cuts = np.cumsum(sizes - 1)[:-1]
    floors = np.split(clearance_floor(base[:, 0], base[:, 1], sizes, env, tol, least), cuts)
    todo, us = [], []
    for i, (bows, floor) in enumerate(zip(np.split(err, cuts), floors)):
        found = dense_index(bows, tol, floor)
        if found is None:
            continue
        planned, u = found
        todo.append((i, planned, u))
        us.append(paths.offset[numbers[i]] + u)
    out: list = [None] * len(passes)
    if not todo:
        return out
    _, th, p, d = exact_points(paths, np.concatenate(us))
    cuts = np.cumsum([u.size for _, _, u in todo])[:-1]
    for (i, planned, u), th_i, p_i, d_i in zip(todo, np.split(th, cuts), np.split(p, cuts), np.split(d, cuts)):
        fp = passes[i]
        p_i[planned], d_i[planned], th_i[planned] = fp.points, fp.direction, fp.theta
        out[i] = (p_i, d_i, th_i + 0.0, u)
    return out
