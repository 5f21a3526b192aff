"""Accuracy against time for every method on one Table 1 mandrel (the data of Table 1, Figure 7 and
the accuracy-time frontier).

Newton sweeps n, shooting its rtol, solve_bvp its tol, the mesh its resolution; all of them are timed
together, round-robin (timing.interleaved), so that their ratios are measured side by side. The
paper's L-BFGS is too slow to repeat: it runs once per n, up to an iteration cap, recording its length
after every iteration.
"""

from __future__ import annotations

import time
from typing import Any, Callable

import numpy as np

from bench.baselines import bvp_geodesic, mesh_geodesic
from bench.cases import Case, Truth
from bench.settings import Settings
from bench.timing import interleaved
from winder.paths.geodesic import Method, _lbfgs, geodesic, straight_path
from winder.geometry.measure import polyline_length, smooth_length
from winder.paths.shooting import shoot
from winder.geometry.surface import SweepSurface

PAPER_STOP_MM = 1e-3  # the paper's stopping rule: successive lengths differ by less than this (mm)
TRAJECTORY_POINTS = 200  # samples kept of an L-BFGS run's per-iteration history


def _rel(length: float, truth: float) -> float:
    return (length - truth) / truth


def _median(values: list[float]) -> float:
    return float(np.median(values)) if values else float("nan")


def pp3d_available() -> bool:
    try:
        import potpourri3d  # noqa: F401, PLC0415
    except ImportError:
        return False
    return True


def _bvp_probe(surface: SweepSurface, case: Case, truth: float, settings: Settings) -> list[float]:
    """The solve_bvp tolerances worth timing: from loose to tight, stopping once the error is below
    bvp_stop_error, the node limit is hit, or a solve exceeds bvp_time_limit."""
    a, b = case.ends_s(surface)
    keep = []
    for tol in settings.bvp_tols:
        t0 = time.perf_counter()
        res = bvp_geodesic(surface, a, b, case.rounds, tol, settings.bvp_max_nodes)
        dt = time.perf_counter() - t0
        keep.append(tol)
        if res.status != 0 or abs(_rel(res.length, truth)) < settings.bvp_stop_error or dt > settings.bvp_time_limit:
            break
    return keep


def measure_case(case: Case, surface: SweepSurface, truth: Truth, settings: Settings,
                 progress: Callable[[str], None]) -> dict[str, Any]:
    """All timed points of one mandrel: {"points": [...], "lbfgs": [...], "notes": [...]}."""
    L = truth.length
    a, b = case.ends_s(surface)
    notes: list[str] = []
    tasks: list[tuple[Any, Callable[[], Any]]] = []
    for n in settings.all_newton_n:
        tasks.append((("newton", n), lambda n=n: geodesic(surface, case.start, case.end, rounds=case.rounds, n=n,
                                                         estimate=False)))
        tasks.append((("richardson", n), lambda n=n: geodesic(surface, case.start, case.end, rounds=case.rounds,
                                                             n=n, estimate=True)))
    for tol in settings.shoot_tols:
        tasks.append((("shooting", tol), lambda tol=tol: shoot(surface, a, b, rounds=case.rounds, tol=tol)))
    progress(f"{case.key}: probing solve_bvp tolerances")
    for tol in _bvp_probe(surface, case, L, settings):
        tasks.append((("collocation", tol), lambda tol=tol: bvp_geodesic(surface, a, b, case.rounds, tol,
                                                                         settings.bvp_max_nodes)))
    if pp3d_available():
        for tri in settings.mesh_triangles:
            tasks.append((("mesh", tri), lambda tri=tri: mesh_geodesic(surface, a, b, case.rounds, tri)))
    else:
        notes.append("mesh baseline skipped: potpourri3d is not installed (pip install .[bench])")
    progress(f"{case.key}: timing {len(tasks)} configurations side by side")
    timed = interleaved(tasks, settings.repeats, settings.min_repeats, settings.budget)

    points: list[dict[str, Any]] = []
    for (kind, param), t in timed.items():
        if not t.ok:
            points.append({"method": kind, "param": param, "error": t.error})
            continue
        base = {"param": param, "seconds": t.median, "samples": len(t.samples),
                "seconds_min": float(min(t.samples)), "seconds_max": float(max(t.samples))}
        v = t.value
        if kind == "newton":
            common = {**base, "setting": f"n = {param}", "iterations": v.iterations, "converged": v.converged}
            points.append({"method": "newton", **common, "rel_error": _rel(v.length, L)})
            points.append({"method": "newton_polyline", **common, "rel_error": _rel(v.polyline_length, L)})
        elif kind == "richardson":
            points.append({"method": "newton_richardson", **base, "setting": f"n = {param} (+ {2 * param + 1})",
                           "rel_error": _rel(v.length_extrapolated, L),
                           "smooth_rel_error": _rel(v.length, L), "polyline_rel_error": _rel(v.polyline_length, L),
                           "error_estimate_rel": v.error_estimate / L,
                           "smooth_error_estimate_rel": v.smooth_error_estimate / L,
                           "iterations": v.iterations, "converged": v.converged})
        elif kind == "shooting":
            points.append({"method": "shooting", **base, "setting": f"rtol = {param:.0e}",
                           "rel_error": _rel(v.length, L), "converged": v.converged, "fan_integrations": v.nfev})
        elif kind == "collocation":
            points.append({"method": "collocation", **base, "setting": f"tol = {param:.0e}",
                           "rel_error": _rel(v.length, L), "status": v.status, "nodes": v.nodes})
        elif kind == "mesh":
            points.append({"method": "mesh", **base, "setting": f"{v.triangles:,} triangles",
                           "rel_error": _rel(v.length, L), "triangles": v.triangles,
                           "mesh_seconds": _median([r.mesh_seconds for r in t.values]),
                           "precompute_seconds": _median([r.precompute_seconds for r in t.values]),
                           "query_seconds": _median([r.query_seconds for r in t.values])})
    lbfgs = []
    for n in settings.lbfgs_n:
        progress(f"{case.key}: paper's L-BFGS at n = {n} (cap {settings.lbfgs_cap} iterations)")
        lbfgs.append(lbfgs_run(surface, case, n, settings.lbfgs_cap, L))
    return {"points": points, "lbfgs": lbfgs, "notes": notes}


def lbfgs_run(surface: SweepSurface, case: Case, n: int, cap: int, truth: float) -> dict[str, Any]:
    """The paper's method as winder runs it (geodesic(..., method=Method.LBFGS, estimate=False) is
    L-BFGS-B from the straight path, winder.paths.geodesic._lbfgs), capped at `cap` iterations, with the
    polyline length after every iteration (its evaluation is excluded from the times)."""
    a, b = case.ends_s(surface)
    s, th = straight_path(a[0], a[1], b[0], b[1] + 2.0 * np.pi * case.rounds, n)
    times: list[float] = []
    lengths: list[float] = []
    overhead = 0.0
    t0 = time.perf_counter()

    def record(res) -> None:
        nonlocal overhead
        t_in = time.perf_counter()
        times.append(t_in - t0 - overhead)
        ss, tt = s.copy(), th.copy()
        ss[1:-1], tt[1:-1] = res.x[0::2], res.x[1::2]
        lengths.append(polyline_length(surface.points(ss, tt)))
        overhead += time.perf_counter() - t_in

    sol = _lbfgs(surface, s, th, max_iter=cap, callback=record)
    total = time.perf_counter() - t0 - overhead
    poly = polyline_length(surface.points(sol.s, sol.theta))
    smooth = smooth_length(surface, sol.s, sol.theta)
    stop = next((k for k in range(1, len(lengths)) if abs(lengths[k] - lengths[k - 1]) < PAPER_STOP_MM), None)
    idx = np.unique(np.round(np.geomspace(1, max(len(lengths), 1), TRAJECTORY_POINTS)).astype(int) - 1)
    idx = idx[idx < len(lengths)]
    return {
        "method": Method.LBFGS.value, "n": n, "cap": cap, "iterations": sol.iterations,
        "stopped_by": "cap" if sol.iterations >= cap else "scipy tolerances",
        "seconds": total, "rel_error": _rel(poly, truth), "smooth_rel_error": _rel(smooth, truth),
        "paper_stop": None if stop is None else {
            "iteration": stop + 1, "seconds": times[stop], "rel_error": _rel(lengths[stop], truth)},
        "trajectory": {"iteration": (idx + 1).tolist(), "seconds": [times[i] for i in idx],
                       "rel_error": [_rel(lengths[i], truth) for i in idx]},
    }
