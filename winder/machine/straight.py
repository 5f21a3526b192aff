"""The axes of a straight-axis program with every contact point's eye found once (winder.machine.program).

Three steps of the program ask for the eye at contact points: the densify check (winder.machine.densify:
the planned points and the smooth path's interval midpoints), the dense resampling of the passes it
flags, and the axes of the program (winder.machine.axis_batch). They share most of their points: a
densified pass keeps its planned points, and where its dense spacing halves an interval (an even
factor: the dense index is exactly k + 1/2) its point is the check's midpoint. The lead, the eye, its
angle and B before unwrapping are pointwise (winder.machine.kinematics.eye_points), so each point's
are computed once and gathered into the program's rows; B is made continuous per pass afterwards,
and A reuses the check's values wherever the program adds no turn. The values are the same, bit for
bit, as those of batch.all_dense followed by axis_batch.straight_axes.

Where a lead cannot be found in a batch (the eye does not clear the mandrel), this returns None and
the program takes those steps instead, which name the pass in their refusal.
"""

from __future__ import annotations

import functools

import numpy as np

from winder.config.machine import MachineConfig
from winder.errors import ExportError
from winder.machine.axis_batch import checked, turn_counts
from winder.machine.densify import clearance_floor, dense_factor, interval_factors, varying_u
from winder.machine.envelope import EyeEnvelope
from winder.machine.kinematics import EyePath, eye_points, rotation_deg, unwrap_each
from winder.machine.leads import lead_straight, unit_rows
from winder.machine.exact import exact_points
from winder.machine.smooth import SmoothPaths
from winder.winding.results import FiberPass, WindingPlan
from winder.geometry.measure import row_norms


class _Points:
    """Contact points with their eyes: p, the unit directions' eyes (e, phi_raw, cross-feed zr, raw
    B), leads lam and on_envelope ok, the contact angles theta."""

    def __init__(self, p: np.ndarray, d: np.ndarray, theta: np.ndarray, env: EyeEnvelope, sense: float) -> None:
        u = unit_rows(d)  # once, for the leads and the eyes (eye_leads would take it again)
        self.lam, self.ok = lead_straight(p, u, env, "eye path")  # ExportError: the eye does not clear the mandrel
        self.p, self.theta = p, theta
        self.e, self.phi, self.zr, self.b = eye_points(p, u, self.lam, sense)

    def scaled(self, theta: np.ndarray, sizes: np.ndarray, arc_radius: float, angle_scale: float):
        """(A (deg) at the contact angles theta, the scaled axes (m, 4) of the point reduction with B
        continuous per run of sizes): what densify's check compares."""
        a = rotation_deg(self.phi, theta)
        b = np.degrees(unwrap_each(self.b, sizes))
        return a, np.column_stack([self.e[:, 2], self.zr, np.radians(a) * arc_radius, np.radians(b) * angle_scale])


def straight_passes(plan: WindingPlan, passes: list[FiberPass], wheres: list[str], env: EyeEnvelope,
                    machine: MachineConfig, sense: float, arc_radius: float, angle_scale: float, tol: float,
                    least: list | None = None):
    """(path, sizes, jumped, us, points) of the non-empty passes in program order, as straight_axes
    gives them after all_dense: the EyePath of every row, each pass's rows, whether it jumped, its
    fractional point indices u (None where not densified); the contact points of every row); None where a lead
    batch fails. arc_radius, angle_scale: the scaled axes of the point reduction (program.py). least:
    per pass None or the least pieces per planned interval for the clearance (chords.refine)."""
    try:
        return _straight(plan, passes, wheres, env, machine, sense, arc_radius, angle_scale, tol, least)
    except _NoLead:
        return None


class _NoLead(Exception):
    pass


def _points(p, d, theta, env, sense) -> _Points:
    try:
        return _Points(p, d, theta, env, sense)
    except ExportError as exc:
        raise _NoLead from exc


def _straight(plan, passes, wheres, env, machine, sense, arc_radius, angle_scale, tol, least):
    sizes = np.array([len(fp.points) for fp in passes])
    starts = np.cumsum(sizes) - sizes
    base = _points(np.asarray(np.concatenate([fp.points for fp in passes]), dtype=float).reshape(-1, 3),
                   np.asarray(np.concatenate([fp.direction for fp in passes]), dtype=float).reshape(-1, 3),
                   np.concatenate([np.asarray(fp.theta, dtype=float) for fp in passes]), env, sense)
    # The densify check's midpoints, a layer's in one call each (the smooth path of the surface it was wound on).
    smooth: dict[int, SmoothPaths] = {}
    memos: dict[int, dict] = {}  # per layer: exact_points' runs, shared by its midpoints and dense points
    index_of = {id(fp): k for k, fp in enumerate(passes)}
    two, found = [], []  # (pass, its number in its layer, the layer) of the passes of >= 2 points; their midpoints
    for layer in plan.layers:
        own = [(j, fp) for j, fp in enumerate(layer.passes) if len(fp.points) >= 2]
        if not own:
            continue
        paths = smooth[layer.index] = SmoothPaths(plan.surface_of(layer.index), list(layer.passes))
        found.append(exact_points(paths, np.concatenate([paths.offset[j] + np.arange(len(fp.points) - 1) + 0.5
                                                         for j, fp in own]), memos.setdefault(layer.index, {}))[1:])
        two += [(index_of[id(fp)], j, layer.index) for j, fp in own]
    if not two:
        return _assemble(passes, wheres, machine, (base, None, None), sizes, starts, [None] * len(passes), None)
    th, p, d = (np.concatenate(a) for a in zip(*found))
    mid = _points(p, d, th + 0.0, env, sense)  # + 0.0: densify's zero shift
    k_two = np.array([k for k, _, _ in two])
    n_mid = sizes[k_two] - 1
    mid_start = np.cumsum(n_mid) - n_mid
    a_base, q_base = base.scaled(base.theta, sizes, arc_radius, angle_scale)
    a_mid, q_mid = mid.scaled(mid.theta, n_mid, arc_radius, angle_scale)
    first = np.repeat(starts[k_two] - mid_start, n_mid) + np.arange(q_mid.shape[0])  # each interval's first point
    errs = row_norms(q_mid - 0.5 * (q_base.take(first + 1, axis=0) + q_base.take(first, axis=0)))
    bows = np.maximum.reduceat(errs, mid_start)
    # The clearance's least pieces per interval (densify.clearance_floor), laid out as errs (the passes
    # of >= 2 points in the same order, each its n - 1 intervals).
    floors = clearance_floor(base.e[:, 2], base.zr, sizes, env, tol, least)
    # Which passes densify, and how (densify.densify_many's rule); the dense points neither planned nor midpoints.
    dense: list = [None] * len(passes)
    extra_u: dict[int, list] = {}
    for (k, j, layer), n, bow, m0 in zip(two, (n_mid + 1).tolist(), bows.tolist(), mid_start.tolist()):
        own = errs[m0:m0 + n - 1] if dense_factor(bow, tol) is not None else np.zeros(n - 1)
        factors = interval_factors(own, tol, floors[m0:m0 + n - 1])
        if factors is None:
            continue
        u, planned, at_mid, others, interval, local, pool = _varying_rows(factors)
        dense[k] = [u, planned, at_mid, others, interval, m0, 0, local, pool]
        if others.any():
            extra_u.setdefault(layer, []).append((k, smooth[layer].offset[j] + u[others]))
    extra = None
    if extra_u:
        items = [item for group in extra_u.values() for item in group]
        th, p, d = (np.concatenate(a) for a in zip(*(exact_points(smooth[layer], np.concatenate([v for _, v in group]),
                                                                   memos[layer])[1:]
                                                      for layer, group in extra_u.items())))
        extra = _points(p, d, th + 0.0, env, sense)
        counts = np.array([v.size for _, v in items])
        for (k, _), off in zip(items, (np.cumsum(counts) - counts).tolist()):
            dense[k][6] = off
    return _assemble(passes, wheres, machine, (base, mid, extra), sizes, starts, dense, (a_base, a_mid))


def _dense_rows(n: int, factor: int) -> tuple[np.ndarray, ...]:
    """_varying_rows of a pass of n points whose every interval is cut in factor."""
    return _varying_rows(np.full(n - 1, factor, dtype=np.int64))


def _varying_rows(factors: np.ndarray) -> tuple[np.ndarray, ...]:
    """(u, planned, at_mid, others, interval, local, pool) of a pass whose planned interval i is cut in
    factors[i] (densify.varying_u): the dense point indices, which are planned points, which fall
    exactly on an interval's midpoint, which are neither, each one's interval, and each one's pool
    (0 planned, 1 midpoints, 2 others) and place in the pass's share of it; read-only."""
    u, interval = varying_u(factors)
    planned = u == interval
    at_mid = ~planned & (u == interval + 0.5)
    others = ~planned & ~at_mid
    local = interval.astype(np.int64)
    local[others] = np.arange(int(np.count_nonzero(others)))
    pool = np.where(planned, 0, np.where(at_mid, 1, 2)).astype(np.int64)
    out = (u, planned, at_mid, others, interval, local, pool)
    for a in out:
        a.flags.writeable = False
    return out


@functools.lru_cache(maxsize=256)
def _plain_rows(n: int) -> tuple[np.ndarray, np.ndarray]:
    """_dense_rows' (local, pool) of a pass of n points that keeps its planned points: all in pool 0."""
    out = (np.arange(n, dtype=np.int64), np.zeros(n, dtype=np.int64))
    for a in out:
        a.flags.writeable = False
    return out


def _assemble(passes, wheres, machine, pools, sizes, starts, dense, checked_a):
    """The program's rows, each point's values gathered from the pools (planned points, midpoints,
    other dense points; see the module docstring): straight_passes' result."""
    base, mid, extra = pools
    n_base, n_mid = base.theta.size, (0 if mid is None else mid.theta.size)
    # Each row's pool (0 planned, 1 midpoints, 2 other dense points) and place within its pass's share
    # of that pool, per pass size and factor (cached); the passes' offsets into the pools added at once.
    names = ("e", "phi", "zr", "lam", "ok", "p", "theta", "b")
    if all(dn is None for dn in dense):
        # No pass densifies: the rows are the planned points in order (g the identity), the planned
        # pool's own arrays (made here, changed by nothing below).
        final, g = sizes.astype(np.int64), None
        e, phi, zr, lam, ok, p, theta, b = (getattr(base, name) for name in names)
    else:
        templates = [_plain_rows(n) if dn is None else (dn[7], dn[8]) for n, dn in zip(sizes.tolist(), dense)]
        final = np.array([local.size for local, _ in templates], dtype=np.int64)
        offsets = np.empty((len(dense), 3), dtype=np.int64)
        offsets[:, 0] = starts
        offsets[:, 1] = [0 if dn is None else n_base + dn[5] for dn in dense]
        offsets[:, 2] = [0 if dn is None else n_base + n_mid + dn[6] for dn in dense]
        pool = np.concatenate([code for _, code in templates])
        g = np.concatenate([local for local, _ in templates]) + offsets.ravel().take(
            np.repeat(3 * np.arange(len(dense)), final) + pool)
        used = [q for q in pools if q is not None]
        # take, not [g]: the same rows, and numpy's fancy indexing of (m, 3) rows is several times slower.
        e, phi, zr, lam, ok, p, theta, b = (np.concatenate([getattr(q, name) for q in used]).take(g, axis=0)
                                            for name in names)
        on_dense = np.repeat([dn is not None for dn in dense], final)
        theta[on_dense] += 0.0  # a dense pass's angles carry densify's zero shift (-0.0 becomes 0.0)
    b = np.degrees(unwrap_each(b, final))
    last = np.cumsum(final) - 1
    first = last - final + 1
    dense_last = [None if dn is None else theta[last[k]] for k, dn in enumerate(dense)]
    shift, b_shift, jumped = turn_counts(passes, dense_last, phi[first], phi[last], b[first], b[last])
    theta = theta + np.repeat(shift, final)
    a = np.empty(theta.size)
    same = np.zeros(theta.size, dtype=bool)
    if checked_a is not None and g is None:  # A of the densify check, where the program's angle is the check's
        same = theta.view(np.int64) == base.theta.view(np.int64)
        a[same] = checked_a[0][same]
    elif checked_a is not None:
        pad = [] if extra is None else [np.full(extra.theta.size, np.nan)]
        before = np.concatenate([base.theta, mid.theta] + pad)[g]
        same = theta.view(np.int64) == before.view(np.int64)
        a[same] = np.concatenate([*checked_a] + pad)[g[same]]
    a[~same] = rotation_deg(phi[~same], theta[~same])
    whole = EyePath(e[:, 2].copy(), a, zr, b + np.repeat(b_shift, final), e, lam, ok)
    checked(whole, final, wheres, machine)
    us = [None if dn is None else dn[0] for dn in dense]
    return whole, final, jumped, us, p
