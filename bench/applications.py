"""The paper's applications: N-round geodesic helices (section 6.1) and path evolution on a deforming
mandrel (section 6.2)."""

from __future__ import annotations

import time
from typing import Any, Callable

import numpy as np

from bench.cases import bent_tube
from bench.settings import Settings
from bench.timing import interleaved
from winder.config.axes import ArcAxis
from winder.config.mandrel import MandrelConfig
from winder.paths.geodesic import geodesic
from winder.paths.shooting import shoot
from winder.geometry.build import build_surface


def helices(settings: Settings, progress: Callable[[str], None]) -> dict[str, Any]:
    """N-round helices on the quarter bend from (t = 0, 0 deg) to (t = end, 90 deg) + N rounds:
    Newton (smooth length, and with Richardson) against tight shooting, timed side by side."""
    surface = build_surface(bent_tube(), "bench", "bend")
    start, end = (0.0, 0.0), (surface.axial_length, np.pi / 2.0)
    a, b = (0.0, 0.0), (surface.length, np.pi / 2.0)
    rows = []
    for rounds in settings.helix_rounds:
        progress(f"helix: {rounds} rounds")
        n = settings.helix_n
        tasks = [
            ("newton", lambda r=rounds, n=n: geodesic(surface, start, end, rounds=r, n=n, estimate=False)),
            ("richardson", lambda r=rounds, n=n: geodesic(surface, start, end, rounds=r, n=n, estimate=True)),
            ("shooting", lambda r=rounds: shoot(surface, a, b, rounds=r, tol=settings.truth_tol)),
        ]
        timed = interleaved(tasks, settings.repeats, settings.min_repeats, settings.budget)
        row: dict[str, Any] = {"rounds": rounds, "n": n}
        sh = timed["shooting"]
        truth = sh.value.length if sh.ok else None
        if sh.ok:
            row["shooting"] = {"seconds": sh.median, "length": truth, "converged": sh.value.converged,
                               "samples": len(sh.samples), "tol": settings.truth_tol}
        else:
            row["shooting"] = {"error": sh.error}
        for key in ("newton", "richardson"):
            t = timed[key]
            if not t.ok:
                row[key] = {"error": t.error}
                continue
            length = t.value.length_extrapolated if key == "richardson" else t.value.length
            row[key] = {"seconds": t.median, "length": length, "samples": len(t.samples),
                        "iterations": t.value.iterations, "converged": t.value.converged,
                        "polyline_length": t.value.polyline_length,
                        "rel_diff_vs_shooting": None if truth is None else (length - truth) / truth}
        rows.append(row)
    return {"mandrel": "quarter bend: ArcAxis(150 mm, 90 deg), ConstantProfile(40 mm)",
            "start": "t = 0, 0 deg", "end": "t = end, 90 deg + N rounds", "rows": rows}


def evolution(settings: Settings, progress: Callable[[str], None]) -> dict[str, Any]:
    """A bend whose angle sweeps bend_deg over `frames` frames (bend radius 150, tube radius 40), the
    path from (t = 0, 0 deg) to (t = end, 90 deg) + 1 round. Each frame: a cold solve, and a warm one
    from the previous frame's warm path (its stations scaled by the length ratio, since the axis
    length changes with the angle), timed side by side."""
    base = bent_tube()
    angles = np.linspace(settings.bend_deg[0], settings.bend_deg[1], settings.frames)
    out: dict[str, Any] = {"frames": settings.frames, "bend_deg": list(settings.bend_deg), "rounds": 1,
                           "runs": []}
    for n in settings.evolution_n:
        progress(f"evolution: {settings.frames} frames at n = {n}")
        prev = None
        prev_len = None
        frames = []
        for k, ang in enumerate(angles):
            t0 = time.perf_counter()
            surface = build_surface(MandrelConfig(ArcAxis(base.axis.radius, float(ang)), base.profile,
                                                  base.section), "bench", "evolving")
            build = time.perf_counter() - t0
            start, end = (0.0, 0.0), (surface.axial_length, np.pi / 2.0)

            def cold(surface=surface, start=start, end=end, n=n):
                return geodesic(surface, start, end, rounds=1, n=n, estimate=False)

            tasks = [("cold", cold)]
            if prev is not None:
                init = (prev.s * (surface.length / prev_len), prev.theta)

                def warm(surface=surface, start=start, end=end, init=init, n=n):
                    return geodesic(surface, start, end, rounds=1, n=n, init=init, estimate=False)

                tasks.append(("warm", warm))
            timed = interleaved(tasks, min(settings.repeats, 5), settings.min_repeats, settings.budget / 4)
            c = timed["cold"]
            w = timed.get("warm")
            frame = {"frame": k, "bend_deg": float(ang), "build_seconds": build,
                     "cold_seconds": c.median if c.ok else None, "cold_iterations": c.value.iterations if c.ok else None}
            if w is not None and w.ok:
                frame.update({"warm_seconds": w.median, "warm_iterations": w.value.iterations,
                              "rel_diff_warm_cold": (w.value.length - c.value.length) / c.value.length
                              if c.ok else None})
                prev = w.value
            elif w is not None:
                frame["warm_error"] = w.error
                prev = c.value if c.ok else None
            else:
                prev = c.value if c.ok else None
            prev_len = surface.length
            frames.append(frame)
        warm_s = [f["warm_seconds"] for f in frames if f.get("warm_seconds") is not None]
        cold_s = [f["cold_seconds"] for f in frames[1:] if f.get("cold_seconds") is not None]
        ratio = [f["cold_seconds"] / f["warm_seconds"] for f in frames
                 if f.get("warm_seconds") and f.get("cold_seconds")]
        diffs = [abs(f["rel_diff_warm_cold"]) for f in frames if f.get("rel_diff_warm_cold") is not None]
        out["runs"].append({
            "n": n, "frames": frames,
            "first_frame_seconds": frames[0]["cold_seconds"] if frames else None,
            "warm_median_seconds": float(np.median(warm_s)) if warm_s else None,
            "cold_median_seconds": float(np.median(cold_s)) if cold_s else None,
            "speedup_median": float(np.median(ratio)) if ratio else None,
            "warm_total_seconds": float(np.sum(warm_s)) if warm_s else None,
            "max_rel_diff_warm_cold": float(np.max(diffs)) if diffs else None,
            "build_median_seconds": float(np.median([f["build_seconds"] for f in frames])) if frames else None,
        })
    return out
