"""`python -m bench`: run every experiment and write the results page (Markdown, JSON, PNG)."""

from __future__ import annotations

import json
import math
import re
import statistics
import time
import traceback
from datetime import datetime, timezone
from pathlib import Path
from typing import Any, Callable

import numpy as np

from bench.applications import evolution, helices
from bench.cases import cases, truth
from bench.convergence import convergence, large_n
from bench.iterations import iteration_histories
from bench.settings import FULL, Settings
from bench.sweeps import measure_case
from bench.table1 import frontier, speedups, table1, verdicts
from bench.timing import blas_threads, environment

Progress = Callable[[str], None]


def _agreement(entry: dict[str, Any]) -> dict[str, float]:
    """Closest approach of each method to the truth (min |relative error|): how well they agree."""
    out: dict[str, float] = {}
    for p in entry["points"]:
        if "rel_error" in p:
            out[p["method"]] = min(out.get(p["method"], math.inf), abs(p["rel_error"]))
    return out


def blas_check(progress: Progress) -> dict[str, Any]:
    """scipy's L-BFGS-B per iteration with the BLAS thread pools as found against one thread,
    alternated three times (the reason the bench limits BLAS to one thread)."""
    from bench.cases import bent_tube  # noqa: PLC0415
    from winder.paths.geodesic import _lbfgs, straight_path  # noqa: PLC0415
    from winder.geometry.build import build_surface  # noqa: PLC0415

    progress("BLAS threads: L-BFGS-B per iteration, default threads vs one")
    surface = build_surface(bent_tube(), "bench", "bend")
    s, th = straight_path(0.0, 0.0, surface.length, np.pi / 2 + 2 * np.pi, 200)
    iters = 200
    res: dict[str | int, list[float]] = {"default": [], 1: []}
    for _ in range(3):
        for lim in ("default", 1):
            with blas_threads(None if lim == "default" else 1):
                t0 = time.perf_counter()
                sol = _lbfgs(surface, s, th, max_iter=iters)
                res[lim].append((time.perf_counter() - t0) / max(sol.iterations, 1))
    d, o = statistics.median(res["default"]), statistics.median(res[1])
    return {"n": 200, "iterations": iters, "ms_per_iteration_default_threads": d * 1e3,
            "ms_per_iteration_one_thread": o * 1e3, "ratio": d / o}


def derive(entry: dict[str, Any], table_n: tuple[int, ...] | list[int]) -> None:
    """The tables, frontier and verdicts of one mandrel, from its measured points (in place)."""
    entry["agreement"] = _agreement(entry)
    entry["frontier"] = frontier(entry)
    entry["verdicts"] = verdicts(entry["frontier"])
    entry["speedups"] = speedups(entry["frontier"])
    entry["table1"] = table1(entry, tuple(table_n))
    entry["convergence"] = convergence(entry)


def _guarded(results: dict[str, Any], name: str, fn: Callable[[], Any]) -> Any:
    """Run one experiment; if it raises, record the error (a note on the page, the traceback in the
    JSON) and go on with the others. Returns fn's value or None."""
    try:
        return fn()
    except Exception as exc:  # noqa: BLE001 - one failing experiment must not lose the others
        results["notes"].append(f"{name} failed and is left out: {type(exc).__name__}: {exc}")
        results.setdefault("errors", []).append({"experiment": name, "traceback": traceback.format_exc()})
        return None


def _case_entry(case, settings: Settings, say: Progress) -> dict[str, Any]:
    surface = case.surface()
    say(f"{case.key}: ground truth")
    tr = truth(case, surface, settings.truth_tol)
    entry: dict[str, Any] = {
        "key": case.key, "title": case.title, "radius_case": case.radius_case,
        "description": case.description, "rounds": case.rounds,
        "truth": {"length_mm": tr.length, "source": tr.source, "shoot_length_mm": tr.shoot_length,
                  "shoot_rel_diff": tr.shoot_vs_truth, "shoot_seconds": tr.shoot_seconds,
                  "shoot_converged": tr.shoot_converged, "shoot_tol": settings.truth_tol},
    }
    entry.update(measure_case(case, surface, tr, settings, say))
    derive(entry, settings.table_n)
    if case.key == "bend" and settings.large_n:
        entry["large_n"] = large_n(case, surface, settings, say)
    entry["figure8"] = iteration_histories(case, surface, tr.length, settings.fig8_n, settings.fig8_cap, say)
    return entry


def run_bench(settings: Settings = FULL, progress: Progress | None = None) -> dict[str, Any]:
    """Run the bench; returns the results (JSON-ready). Nothing is written."""
    say = progress or (lambda _msg: None)
    t_start = time.perf_counter()
    results: dict[str, Any] = {"meta": {"settings": settings.name, "table_n": list(settings.table_n),
                                        "started": datetime.now(timezone.utc).isoformat(timespec="seconds")},
                               "cases": [], "notes": []}
    with blas_threads(settings.blas_threads) as limited:
        results["meta"]["environment"] = environment(settings.blas_threads if limited else None)
        if settings.blas_threads is not None and not limited:
            results["notes"].append("threadpoolctl is not installed: the BLAS threads were not limited "
                                    "(pip install .[bench])")
        for case in cases():
            if case.key in settings.cases:
                entry = _guarded(results, f"the {case.title} measurements", lambda c=case: _case_entry(c, settings, say))
                if entry is not None:
                    results["cases"].append(entry)
        if settings.helix_rounds:
            results["helix"] = _guarded(results, "section 6.1 (helices)", lambda: helices(settings, say))
        if settings.frames and settings.evolution_n:
            results["evolution"] = _guarded(results, "section 6.2 (evolution)", lambda: evolution(settings, say))
        if settings.job:
            from bench.job import compare_job  # noqa: PLC0415

            results["job"] = _guarded(results, "the whole-job comparison", lambda: compare_job(settings, say))
        if settings.speed:
            from bench import solver_speed  # noqa: PLC0415

            results["solver_speed"] = _guarded(results, "the solver speed figures",
                                               lambda: solver_speed.measure(settings.speed_repeats, say))
    if settings.speed:
        from bench import fiberpath_jobs  # noqa: PLC0415

        say("whole jobs against fiberpath, start-up" if settings.fiberpath_jobs else "start-up")
        results["fiberpath_jobs"] = _guarded(
            results, "the whole jobs against fiberpath",
            lambda: fiberpath_jobs.measure(settings.speed_repeats, jobs=settings.fiberpath_jobs))
    if settings.blas_check:
        results["blas_check"] = _guarded(results, "the BLAS-thread check", lambda: blas_check(say))
    results["meta"]["total_seconds"] = time.perf_counter() - t_start
    return results


# -- output ------------------------------------------------------------------------------------------------
_NUMBER_LIST = re.compile(r"\[\s*((?:-?[0-9][0-9.eE+-]*|null)(?:,\s*(?:-?[0-9][0-9.eE+-]*|null))*)\s*\]")


def _dumps(data: dict[str, Any]) -> str:
    """Indented JSON with lists of numbers kept on one line (short, readable diffs)."""
    text = json.dumps(data, indent=1, allow_nan=False)
    return _NUMBER_LIST.sub(lambda m: "[" + " ".join(m.group(1).split()) + "]", text) + "\n"


def _clean(value: Any) -> Any:
    """JSON-ready: numpy scalars to Python, non-finite floats to None, floats to 12 significant digits."""
    if isinstance(value, dict):
        return {str(k): _clean(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_clean(v) for v in value]
    if isinstance(value, np.ndarray):
        return [_clean(v) for v in value.tolist()]
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        v = float(value)
        return float(f"{v:.12g}") if math.isfinite(v) else None
    return value


def write_outputs(results: dict[str, Any], out_dir: str | Path, progress: Progress | None = None) -> list[Path]:
    """results.json, RESULTS.md and the figures (PNG, if matplotlib is installed); returns the paths."""
    from bench.figures import make_figures  # noqa: PLC0415
    from bench.report import markdown  # noqa: PLC0415

    say = progress or (lambda _msg: None)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    clean = _clean(results)
    written = []
    say("writing figures")
    figures, fig_notes = make_figures(clean, out)
    written += figures
    path = out / "results.json"
    clean["figures"] = [p.name for p in figures]
    clean["figure_notes"] = fig_notes
    path.write_text(_dumps(clean))
    written.append(path)
    md = out / "RESULTS.md"
    md.write_text(markdown(clean))
    written.append(md)
    return written


def report_from_json(out_dir: str | Path) -> Path:
    """Rewrite RESULTS.md (and the figures) from an existing results.json, without measuring again; the
    derived tables (frontier, verdicts, Table 1, orders) are recomputed from the measured points."""
    from bench.figures import make_figures  # noqa: PLC0415
    from bench.report import markdown  # noqa: PLC0415

    out = Path(out_dir)
    clean = json.loads((out / "results.json").read_text())
    for entry in clean["cases"]:
        derive(entry, clean["meta"].get("table_n", [50, 500, 1000]))
    clean = _clean(clean)
    figures, notes = make_figures(clean, out)
    clean["figures"] = [p.name for p in figures]
    clean["figure_notes"] = notes
    (out / "results.json").write_text(_dumps(clean))
    md = out / "RESULTS.md"
    md.write_text(markdown(clean))
    return md
