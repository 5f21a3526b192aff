"""Figure 8: length and gradient norm per iteration for Newton, the paper's L-BFGS and LO.

All three start from the same straight parameter-domain path at the same n. Newton here is the
single-level solver (winder.paths.geodesic._newton, no coarse-to-fine) so that its iterations are
comparable; its k-th iterate is the result of a run capped at k iterations (the solver is
deterministic). L-BFGS is winder's (_lbfgs, the paper's method); LO minimizes the polyline's total
length (baselines.length_optimization). Gradient norms are reported for the energy E (what Newton and
L-BFGS minimize) and for the length L (what LO minimizes). |grad L| is a common yardstick but does not
vanish exactly at E's minimizer: grad L = grad E / (2h) only where neighbouring segments are equal, and
the minimizer of E is equally spaced only up to O(h^2).
"""

from __future__ import annotations

import time
from typing import Any, Callable

import numpy as np

from bench.baselines import length_and_gradient, length_optimization
from bench.cases import Case
from bench.sweeps import PAPER_STOP_MM
from winder.paths.energy import energy_terms
from winder.paths.geodesic import STEP_TOL, _lbfgs, _newton, solve_path, straight_path
from winder.geometry.measure import polyline_length, spacing_deviation
from winder.geometry.surface import SweepSurface

MAX_NEWTON_ITER = 100
METRIC_POINTS = 150  # iterates at which the gradient norms are evaluated (log-spaced)


def _chord_depth(surface: SweepSurface, s: np.ndarray, th: np.ndarray) -> float:
    """How far (mm) the chords of the polyline stray from the surface: the largest distance between a
    chord's midpoint and the surface point at the parameter midpoint. Large when vertices bunch up and
    chords cut through the mandrel."""
    pts = surface.points(s, th)
    mid = surface.points(0.5 * (s[1:] + s[:-1]), 0.5 * (th[1:] + th[:-1]))
    return float(np.max(np.linalg.norm(0.5 * (pts[1:] + pts[:-1]) - mid, axis=1)))


def _metrics(surface: SweepSurface, iterates: list[tuple[np.ndarray, np.ndarray]], truth: float,
             seconds_per_iteration: float) -> dict[str, Any]:
    lengths = [polyline_length(surface.points(s, th)) for s, th in iterates]
    k = len(iterates)
    idx = np.unique(np.round(np.geomspace(1, k, min(k, METRIC_POINTS))).astype(int) - 1)
    grad_e, grad_l = [], []
    for i in idx:
        s, th = iterates[i]
        _, g, *_ = energy_terms(surface, s, th, full_hessian=False)
        grad_e.append(float(np.linalg.norm(g)))
        grad_l.append(float(np.linalg.norm(length_and_gradient(surface, s, th)[1])))
    stop = next((j for j in range(1, k) if abs(lengths[j] - lengths[j - 1]) < PAPER_STOP_MM), None)
    return {
        "iteration": idx.tolist(),  # iterate 0 is the start; log-spaced samples of the history
        "rel_error": [(lengths[i] - truth) / truth for i in idx],
        "grad_energy": grad_e,
        "grad_length": grad_l,
        "paper_stop_iteration": stop,
        "final_rel_error": (lengths[-1] - truth) / truth,
        "final_spacing_deviation": spacing_deviation(surface.points(*iterates[-1])),
        "final_max_chord_depth": _chord_depth(surface, *iterates[-1]),
        "iterations": k - 1,
        "seconds_per_iteration": seconds_per_iteration,
    }


def iteration_histories(case: Case, surface: SweepSurface, truth: float, n: int, cap: int,
                        progress: Callable[[str], None]) -> dict[str, Any]:
    a, b = case.ends_s(surface)
    s0, th0 = straight_path(a[0], a[1], b[0], b[1] + 2.0 * np.pi * case.rounds, n)
    out: dict[str, Any] = {"n": n, "cap": cap}

    progress(f"{case.key}: Figure 8, Newton per iteration (n = {n})")
    t0 = time.perf_counter()
    full = _newton(surface, s0, th0, STEP_TOL, max_iter=MAX_NEWTON_ITER)
    per_it = (time.perf_counter() - t0) / max(full.iterations, 1)
    iterates = [(s0, th0)]
    for k in range(1, full.iterations + 1):
        sol = full if k == full.iterations else _newton(surface, s0, th0, STEP_TOL, max_iter=k)
        iterates.append((sol.s, sol.theta))
    out["newton"] = _metrics(surface, iterates, truth, per_it)
    out["newton"]["converged"] = full.converged
    out["newton_coarse_to_fine_iterations"] = solve_path(surface, s0[[0, -1]], th0[[0, -1]], n).iterations

    for name, runner in (("lbfgs", _lbfgs), ("lo", length_optimization)):
        progress(f"{case.key}: Figure 8, {name} per iteration (n = {n}, cap {cap})")
        xs: list[np.ndarray] = []

        def keep(x, xs=xs) -> None:
            xs.append(np.array(x.x if hasattr(x, "x") else x, copy=True))

        t0 = time.perf_counter()
        runner(surface, s0, th0, max_iter=cap, callback=keep)
        per_it = (time.perf_counter() - t0) / max(len(xs), 1)
        iterates = [(s0, th0)]
        for x in xs:
            s, th = s0.copy(), th0.copy()
            s[1:-1], th[1:-1] = x[0::2], x[1::2]
            iterates.append((s, th))
        out[name] = _metrics(surface, iterates, truth, per_it)
    return out
