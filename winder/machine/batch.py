"""Pointwise work of the motion program for every pass at once: robot poses, eye leads, the densify
check's midpoints and dense resamplings. The solver and the eye's lead scan cost per call, so a
layer's (or a plan's) points go in one call; the values are the same as pass by pass. Where a batch
fails (the eye cannot clear the mandrel), the program goes pass by pass and names the pass."""

from __future__ import annotations

import numpy as np

from winder.config.machine import MachineConfig
from winder.errors import ExportError
from winder.machine.densify import densify, densify_many
from winder.machine.exact import exact_points
from winder.machine.kinematics import RobotPoses, robot_poses
from winder.machine.leads import eye_leads
from winder.winding.results import FiberPass, WindingPlan


def pass_where(plan: WindingPlan, fp: FiberPass) -> str:
    """How messages name a pass (a FiberPass, or a program's Segment of one): file, layer, circuit,
    pass and kind."""
    return f"{plan.source}: layer {fp.layer} circuit {fp.circuit} pass {fp.number} ({fp.kind.value})"


def all_poses(plan: WindingPlan, machine: MachineConfig, env, guide) -> list[RobotPoses]:
    """Robot poses of every non-empty pass, solved in one batch (the solver's cost is per call)."""
    passes = [fp for layer in plan.layers for fp in layer.passes if len(fp.points)]
    return batch_poses(plan, machine, env, guide, passes, [fp.points for fp in passes],
                       [fp.direction for fp in passes])


def batch_poses(plan: WindingPlan, machine: MachineConfig, env, guide, passes: list[FiberPass],
                points: list[np.ndarray], directions: list[np.ndarray],
                guess: np.ndarray | None = None) -> list[RobotPoses]:
    """Robot poses at the contact points (k_i, 3) with fiber directions of each pass in passes, all
    in one solve (guess: the leads of all points, as robot_poses takes it); where that fails, pass by
    pass, so that the refusal names the pass."""
    if not passes:
        return []
    try:
        batch = robot_poses(np.concatenate(points), np.concatenate(directions), plan.surface, machine,
                            envelope=env, guide=guide, guess=guess)
    except ExportError:
        for fp, p, d in zip(passes, points, directions):  # name the pass that fails
            robot_poses(p, d, plan.surface, machine, envelope=env, guide=guide, where=pass_where(plan, fp))
        raise
    cuts = np.cumsum([len(p) for p in points])[:-1]
    parts = [np.split(np.asarray(getattr(batch, f)), cuts) for f in
             ("position", "direction", "station", "lead", "on_envelope")]
    return [RobotPoses(*fields) for fields in zip(*parts)]


def all_leads(plan: WindingPlan, env) -> list[tuple[np.ndarray, np.ndarray] | None]:
    """eye_leads of every non-empty pass in plan order, from one call over all their points (the lead
    is pointwise, so the values are the same as pass by pass). Where the eye cannot clear the mandrel,
    None for every pass: eye_path then finds it pass by pass and names the pass in its refusal."""
    passes = [fp for layer in plan.layers for fp in layer.passes if len(fp.points)]
    if not passes:
        return []
    try:
        lam, ok = eye_leads(np.concatenate([fp.points for fp in passes]),
                            np.concatenate([fp.direction for fp in passes]), env)
    except ExportError:
        return [None] * len(passes)
    cuts = np.cumsum([len(fp.points) for fp in passes])[:-1]
    return list(zip(np.split(lam, cuts), np.split(ok, cuts)))


def all_midpoints(plan: WindingPlan, smooth: dict, number: dict, env) -> dict:
    """id(pass) -> (points, directions, theta, leads) of its smooth path's interval midpoints, a layer
    in one call each (the densify check's input; the leads are pointwise). Empty where the eye cannot
    clear the mandrel: densify then finds it pass by pass and names the pass in its refusal."""
    out = {}
    for layer in plan.layers:
        passes = [fp for fp in layer.passes if len(fp.points) >= 2]
        if not passes:
            continue
        paths = smooth[layer.index]
        sizes = [len(fp.points) - 1 for fp in passes]
        u = np.concatenate([paths.offset[number[id(fp)]] + np.arange(k) + 0.5 for fp, k in zip(passes, sizes)])
        _, th, p, d = exact_points(paths, u)
        try:
            lam, ok = eye_leads(p, d, env)
        except ExportError:
            return {}
        cuts = np.cumsum(sizes)[:-1]
        for fp, *parts in zip(passes, *(np.split(a, cuts) for a in (p, d, th, lam, ok))):
            out[id(fp)] = (parts[0], parts[1], parts[2], (parts[3], parts[4]))
    return out


def all_dense(plan: WindingPlan, smooth: dict, number: dict, leads: dict, mids: dict, env, axes_of,
              tol: float, axes_many=None, least: dict | None = None) -> dict:
    """id(pass) -> (points, directions, theta, u, leads) of every pass the chord tolerance makes
    densify (winder.machine.densify), theta at the plan's own turn count (the bow does not depend on
    it), the dense points' leads in one call. axes_of(fp) -> the pass's axes function for densify;
    axes_many: that of many passes at once (winder.machine.densify.densify_many), used for a layer
    whose leads and midpoints were all found in their batches. least: id(pass) -> the least pieces
    per planned interval for the clearance (winder.machine.chords.refine), where it has some."""
    least = least or {}
    out = {}
    for layer in plan.layers:
        passes = [fp for fp in layer.passes if len(fp.points) >= 2]
        if not passes:
            continue
        if axes_many is not None and all(leads.get(id(fp)) is not None and id(fp) in mids for fp in passes):
            base_lead = tuple(np.concatenate([leads[id(fp)][k] for fp in passes]) for k in (0, 1))
            mid = [np.concatenate([mids[id(fp)][k] for fp in passes]) for k in range(3)]
            mid_lead = tuple(np.concatenate([mids[id(fp)][3][k] for fp in passes]) for k in (0, 1))
            found = densify_many(smooth[layer.index], [number[id(fp)] for fp in passes], passes, axes_many, tol,
                                 base_lead, (*mid, mid_lead), env, [least.get(id(fp)) for fp in passes])
        else:  # pass by pass: a failure names its pass
            found = [densify(smooth[layer.index], number[id(fp)], fp, np.asarray(fp.theta, dtype=float),
                             axes_of(fp), tol, leads.get(id(fp)), mids.get(id(fp)), env, least.get(id(fp)))
                     for fp in passes]
        out.update((id(fp), dense) for fp, dense in zip(passes, found) if dense is not None)
    if not out:
        return {}
    # The dense points at integer u are the planned ones, whose lead is known (the lead is pointwise).
    planned = [_planned_rows(d[3]) if leads.get(key) is not None else np.zeros(len(d[3]), dtype=bool)
               for key, d in out.items()]
    try:
        lam, ok = eye_leads(np.concatenate([d[0][~k] for d, k in zip(out.values(), planned)]),
                            np.concatenate([d[1][~k] for d, k in zip(out.values(), planned)]), env)
    except ExportError:
        return {key: (*d, None) for key, d in out.items()}
    cuts = np.cumsum([np.count_nonzero(~k) for k in planned])[:-1]
    found = {}
    for (key, d), k, lam_new, ok_new in zip(out.items(), planned, np.split(lam, cuts), np.split(ok, cuts)):
        lam_all, ok_all = np.empty(k.size), np.empty(k.size, dtype=bool)
        lam_all[~k], ok_all[~k] = lam_new, ok_new
        if k.any():
            lam_all[k], ok_all[k] = leads[key]
        found[key] = (*d, (lam_all, ok_all))
    return found


def _planned_rows(u: np.ndarray) -> np.ndarray:
    """Which rows of a densified pass (fractional point indices u (k,), the planned points exactly at
    the integers, winder.machine.densify.varying_u) are its planned points."""
    return u == np.floor(u)
