"""Figure 7: error and time against n, convergence orders, and Richardson's estimate against the
true error; plus Newton's time at large n (linear growth; formerly bench/geodesic_speed.py)."""

from __future__ import annotations

from typing import Any, Callable

import numpy as np

from bench.cases import Case
from bench.settings import Settings
from bench.timing import interleaved
from winder.paths.geodesic import geodesic
from winder.geometry.surface import SweepSurface

SLOPE_MIN_N = 50  # fit the order on n >= this (the asymptotic range) ...
SLOPE_FLOOR = 1e-11  # ... and on errors above this (below it, roundoff and the truth's own error)


def slope(n: list[int], err: list[float]) -> float | None:
    """Least-squares slope of log|err| against log(n + 1) over the asymptotic, above-floor points."""
    pairs = [(k, abs(e)) for k, e in zip(n, err) if k >= SLOPE_MIN_N and abs(e) > SLOPE_FLOOR]
    if len(pairs) < 3:
        return None
    x = np.log([k + 1.0 for k, _ in pairs])
    y = np.log([e for _, e in pairs])
    return float(np.polyfit(x, y, 1)[0])


def convergence(case_result: dict[str, Any]) -> dict[str, Any]:
    """Per-n errors, estimates and times of Newton on one mandrel, with the fitted orders."""
    rich = sorted((p for p in case_result["points"] if p["method"] == "newton_richardson" and "rel_error" in p),
                  key=lambda p: p["param"])
    smooth = {p["param"]: p for p in case_result["points"] if p["method"] == "newton" and "rel_error" in p}
    n = [p["param"] for p in rich]
    poly = [p["polyline_rel_error"] for p in rich]
    sm = [p["smooth_rel_error"] for p in rich]
    ext = [p["rel_error"] for p in rich]
    # The polyline at 2n + 1 from the extrapolated and the n lengths: L_2n = (3 L_ext + L_n) / 4.
    poly_2n = [(3.0 * e + p) / 4.0 for e, p in zip(ext, poly)]
    return {
        "n": n,
        "polyline_rel_error": poly,
        "smooth_rel_error": sm,
        "richardson_rel_error": ext,
        "polyline_2n_rel_error": poly_2n,
        "error_estimate_rel": [p["error_estimate_rel"] for p in rich],
        "smooth_error_estimate_rel": [p["smooth_error_estimate_rel"] for p in rich],
        "seconds": [smooth[k]["seconds"] if k in smooth else None for k in n],
        "seconds_with_estimate": [p["seconds"] for p in rich],
        "order": {"polyline": slope(n, poly), "smooth": slope(n, sm), "richardson": slope(n, ext)},
        "estimate_ratio": _ratios(n, [p["error_estimate_rel"] for p in rich], poly_2n),
        "smooth_estimate_ratio": _ratios(n, [p["smooth_error_estimate_rel"] for p in rich], sm),
    }


def _ratios(n: list[int], estimate: list[float], true: list[float]) -> dict[str, float] | None:
    """Median, min and max of estimate / |true error| over the range of the fitted orders (n >= 50,
    true error above the floor)."""
    r = [e / abs(t) for k, e, t in zip(n, estimate, true) if k >= SLOPE_MIN_N and abs(t) > SLOPE_FLOOR]
    if not r:
        return None
    return {"median": float(np.median(r)), "min": float(np.min(r)), "max": float(np.max(r))}


def large_n(case: Case, surface: SweepSurface, settings: Settings,
            progress: Callable[[str], None]) -> list[dict[str, Any]]:
    """Newton's median time (smooth length, no estimate) at large n: the O(n) claim."""
    progress(f"{case.key}: Newton at large n {settings.large_n}")
    tasks = [(n, lambda n=n: geodesic(surface, case.start, case.end, rounds=case.rounds, n=n, estimate=False))
             for n in settings.large_n]
    timed = interleaved(tasks, min(settings.repeats, 5), settings.min_repeats, settings.budget)
    out = []
    for n, t in timed.items():
        if t.ok:
            out.append({"n": n, "seconds": t.median, "samples": len(t.samples),
                        "us_per_point": t.median / n * 1e6, "iterations": t.value.iterations})
        else:
            out.append({"n": n, "error": t.error})
    return out
