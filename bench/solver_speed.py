"""The solver's speed targets (issue 14), side by side in one process, medians of interleaved repeats.

- The quarter bend (the reference tube of docs/math/02-energy.md, 1 extra round) at n = 1000 and n = 100,000, to
  convergence, without the 2n + 1 estimate solve (winder.paths.geodesic.geodesic(estimate=False)).
- Against scipy's solve_bvp *with analytic Jacobians* (fun_jac and bc_jac), the strongest collocation
  baseline: the geodesic equations of the two reference mandrels in closed form (a torus section
  ds^2 = A(theta)^2 dz^2 + r^2 dtheta^2, A = 1 - (r/R) cos theta; the elliptic tube
  ds^2 = dz^2 + G(theta) dtheta^2), the length as a fifth component (L' = |v|). At each accuracy level
  (relative length error 1e-6, 1e-9, 1e-12) solve_bvp's time is that of its fastest `tol` whose
  error meets the level (and every tighter tol's too: it is given the best setting in hindsight);
  winder's is its tolerance mode at level x length (it has to find n itself, estimate included),
  and, like for like, its fastest fixed n whose error meets the level (and every larger n's of
  HINDSIGHT_N too), without the estimate: the best setting in hindsight, as solve_bvp is given.
  The two sides of each ratio are timed interleaved in one loop (bench.timing.interleaved).
"""

from __future__ import annotations

import statistics
import time
from typing import Any, Callable

import numpy as np

BVP_TOLS = (1e-1, 3e-2, 1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5, 3e-6, 1e-6, 3e-7, 1e-7, 3e-8, 1e-8)
LEVELS = (1e-6, 1e-9, 1e-12)
BVP_MAX_NODES = 20_000
# winder at a fixed n, for the like-for-like column: interior points from 15 up, about 1.19x apart
HINDSIGHT_N = tuple(sorted({int(round(15 * 2 ** (k / 4))) for k in range(40)} | {31, 63, 127, 255}))
BVP_CANDIDATES = 3  # solve_bvp's fastest qualifying tols in the sweep, timed again side by side with winder
SIDE_REPEATS = 40  # samples per task in the side-by-side timing at the full settings (speed_repeats = 5)
TARGET_BLOCKS = 9  # n = 1000's samples: blocks of `repeats`, between the n = 100,000 solves
SIDE_BUDGET = 0.4  # s per task at most, about: a slow task gets fewer samples


def torus_equations(bend_radius: float, radius: float):
    """fun, fun_jac of y = (z, theta, z', theta', L) on the tube of radius r around an arc of radius R,
    theta from the inside of the bend (winder's theta = 0 for ArcAxis(toward_deg = 0))."""
    c = radius / bend_radius

    def fun(_x: np.ndarray, y: np.ndarray) -> np.ndarray:
        th, p, q = y[1], y[2], y[3]
        a, a1 = 1.0 - c * np.cos(th), c * np.sin(th)
        return np.vstack([p, q, -2.0 * a1 / a * p * q, a * a1 * p * p / radius**2,
                          np.sqrt(a * a * p * p + radius**2 * q * q)])

    def jac(_x: np.ndarray, y: np.ndarray) -> np.ndarray:
        th, p, q = y[1], y[2], y[3]
        a, a1, a2 = 1.0 - c * np.cos(th), c * np.sin(th), c * np.cos(th)
        w = np.sqrt(a * a * p * p + radius**2 * q * q)
        j = np.zeros((5, 5, th.size))
        j[0, 2] = j[1, 3] = 1.0
        j[2, 1] = -2.0 * p * q * (a2 * a - a1 * a1) / (a * a)
        j[2, 2], j[2, 3] = -2.0 * a1 / a * q, -2.0 * a1 / a * p
        j[3, 1], j[3, 2] = (a1 * a1 + a * a2) * p * p / radius**2, 2.0 * a * a1 * p / radius**2
        j[4, 1], j[4, 2], j[4, 3] = a * a1 * p * p / w, a * a * p / w, radius**2 * q / w
        return j

    return fun, jac


def ellipse_equations(a: float, b: float):
    """fun, fun_jac on the straight elliptic tube (semi-axes a along e2, b along e3): G = rho^2 + rho'^2
    = a^2 b^2 P / Q^3 with Q = b^2 + (a^2 - b^2) sin^2, P = b^4 + (a^4 - b^4) sin^2."""

    def parts(th: np.ndarray):
        s2, ds2, dds2 = np.sin(th) ** 2, np.sin(2.0 * th), 2.0 * np.cos(2.0 * th)
        qq, pp = b * b + (a * a - b * b) * s2, b**4 + (a**4 - b**4) * s2
        q1, q2, p1, p2 = (a * a - b * b) * ds2, (a * a - b * b) * dds2, (a**4 - b**4) * ds2, (a**4 - b**4) * dds2
        g = a * a * b * b * pp / qq**3
        k = 0.5 * (p1 / pp - 3.0 * q1 / qq)  # G' / (2 G)
        dk = 0.5 * (p2 / pp - (p1 / pp) ** 2 - 3.0 * q2 / qq + 3.0 * (q1 / qq) ** 2)
        return g, k, dk

    def fun(_x: np.ndarray, y: np.ndarray) -> np.ndarray:
        g, k, _ = parts(y[1])
        p, q = y[2], y[3]
        return np.vstack([p, q, np.zeros_like(p), -k * q * q, np.sqrt(p * p + g * q * q)])

    def jac(_x: np.ndarray, y: np.ndarray) -> np.ndarray:
        g, k, dk = parts(y[1])
        p, q = y[2], y[3]
        w = np.sqrt(p * p + g * q * q)
        j = np.zeros((5, 5, p.size))
        j[0, 2] = j[1, 3] = 1.0
        j[3, 1], j[3, 3] = -dk * q * q, -2.0 * k * q
        j[4, 1], j[4, 2], j[4, 3] = k * g * q * q / w, p / w, g * q / w
        return j

    return fun, jac


def bvp_length(equations, start: tuple[float, float], end: tuple[float, float], tol: float,
               nodes: int) -> tuple[float, int, int]:
    """(length, solve_bvp status, nodes) from the straight start, with fun_jac and bc_jac."""
    from scipy.integrate import solve_bvp  # noqa: PLC0415

    fun, jac = equations
    (s0, th0), (s1, th1) = start, end
    tau = np.linspace(0.0, 1.0, nodes)
    jac_a, jac_b = np.zeros((5, 5)), np.zeros((5, 5))
    jac_a[0, 0] = jac_a[1, 1] = jac_a[4, 4] = 1.0
    jac_b[2, 0] = jac_b[3, 1] = 1.0
    y0 = np.vstack([s0 + tau * (s1 - s0), th0 + tau * (th1 - th0), np.full_like(tau, s1 - s0),
                    np.full_like(tau, th1 - th0), np.zeros_like(tau)])
    with np.errstate(all="ignore"):
        res = solve_bvp(fun, lambda ya, yb: np.array([ya[0] - s0, ya[1] - th0, yb[0] - s1, yb[1] - th1, ya[4]]),
                        tau, y0, tol=tol, max_nodes=BVP_MAX_NODES, fun_jac=jac,
                        bc_jac=lambda ya, yb: (jac_a, jac_b))
    return float(res.y[4, -1]), int(res.status), int(res.x.size)


def _median(fn: Callable[[], Any], repeats: int) -> tuple[float, Any]:
    times, out = [], None
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), out


def _cases(truth_tol: float = 1e-13):
    from bench.cases import cases, truth  # noqa: PLC0415
    from winder.geometry.build import build_surface  # noqa: PLC0415

    eq = {"bend": torus_equations(150.0, 40.0), "ellipse": ellipse_equations(60.0, 35.0)}
    for case in cases():
        if case.key in eq:
            surface = build_surface(case.mandrel, "bench", case.key)
            yield case, surface, eq[case.key], truth(case, surface, truth_tol).length


def measure(repeats: int = 5, progress: Callable[[str], None] | None = None) -> dict[str, Any]:
    """Both parts, for results.json."""
    say = progress or (lambda _msg: None)
    say("solver speed: the quarter bend at n = 1000 and 100,000")
    targets = solver_targets(repeats)
    say("solver speed: against solve_bvp with analytic Jacobians")
    return {"targets": targets, "bvp": against_bvp(repeats)}


def solver_targets(repeats: int = 7) -> dict[str, Any]:
    """The quarter bend at n = 1000 and 100,000 (median seconds, Newton iterations, length).

    This machine's speed drifts by up to 2x over seconds: n = 1000's samples (about 2 ms each) are
    taken in TARGET_BLOCKS blocks between the 100,000-point solves, so that its median spans their
    seconds rather than one tenth of a second; its block medians' range is kept too.
    """
    from winder.paths.geodesic import geodesic  # noqa: PLC0415

    out: dict[str, Any] = {}
    for case, surface, _, truth_len in _cases():
        if case.key != "bend":
            continue
        solves = {n: (lambda n=n: geodesic(surface, case.start, case.end, rounds=case.rounds, n=n, estimate=False))
                  for n in (1000, 100_000)}
        samples: dict[int, list[float]] = {1000: [], 100_000: []}
        blocks: list[float] = []
        results = {n: solve() for n, solve in solves.items()}  # warm-up
        for block in range(TARGET_BLOCKS):
            times = [_timed(solves[1000]) for _ in range(repeats)]
            samples[1000] += times
            blocks.append(statistics.median(times))
            if block < max(3, repeats // 2):
                samples[100_000].append(_timed(solves[100_000]))
        for n, res in results.items():
            out[f"bend_n{n}"] = {"seconds": statistics.median(samples[n]), "iterations": res.iterations,
                                 "rel_error": (res.length - truth_len) / truth_len, "samples": len(samples[n]),
                                 "target_s": 0.003 if n == 1000 else 0.25}
        out["bend_n1000"]["block_medians_s"] = [min(blocks), max(blocks)]
    return out


def _timed(fn: Callable[[], Any]) -> float:
    t0 = time.perf_counter()
    fn()
    return time.perf_counter() - t0


def against_bvp(repeats: int = 5) -> dict[str, Any]:
    """solve_bvp (analytic Jacobians, best tol in hindsight) against winder per level, side by side.

    The tol sweep (each tol a median of `repeats`) finds which tols meet each level; then, per level,
    the qualifying candidates (solve_bvp's BVP_CANDIDATES fastest tols in the sweep, winder's fixed n of
    _hindsight_ns) and winder's tolerance mode are timed interleaved (bench.timing.interleaved), and the
    fastest median of each side counts: a burst of load hits both sides of a ratio alike.
    """
    from winder.paths.geodesic import geodesic  # noqa: PLC0415

    out: dict[str, Any] = {}
    for case, surface, eq, truth_len in _cases():
        a, b = case.ends_s(surface)
        start, end = (float(a[0]), float(a[1])), (float(b[0]), float(b[1]) + 2.0 * np.pi * case.rounds)
        nodes = 10 + 8 * (abs(case.rounds) + 1)
        sweep = []
        for tol in BVP_TOLS:
            sec, (length, status, m) = _median(lambda tol=tol: bvp_length(eq, start, end, tol, nodes), repeats)
            sweep.append({"tol": tol, "seconds": sec, "rel_error": abs(length - truth_len) / truth_len,
                          "status": status, "nodes": m})
        rows = []
        fixed_errors = _fixed_errors(case, surface, truth_len)
        for level in LEVELS:
            ok = [p for k, p in enumerate(sweep) if all(q["rel_error"] <= level and q["status"] == 0 for q in sweep[k:])]
            bvp_cands = sorted(ok, key=lambda p: p["seconds"])[:BVP_CANDIDATES]
            tasks: list[tuple[Any, Callable[[], Any]]] = [
                (("tolerance",), lambda level=level: geodesic(surface, case.start, case.end, rounds=case.rounds,
                                                              tolerance=level * truth_len))]
            tasks += [(("bvp", p["tol"]), lambda tol=p["tol"]: bvp_length(eq, start, end, tol, nodes)) for p in bvp_cands]
            tasks += [(("fixed", n), lambda n=n: geodesic(surface, case.start, case.end, rounds=case.rounds, n=n,
                                                          estimate=False))
                      for n in _hindsight_ns(fixed_errors, level)]
            timed = _side_by_side(tasks, repeats)
            res, sec = timed[("tolerance",)].value, timed[("tolerance",)].median
            err = abs(res.length - truth_len)
            best = min(({**p, "seconds": timed[("bvp", p["tol"])].median} for p in bvp_cands),
                       key=lambda p: p["seconds"], default=None)
            fixed = min(({"n": key[1], "seconds": t.median, "rel_error": fixed_errors[key[1]]}
                         for key, t in timed.items() if key[0] == "fixed"), key=lambda r: r["seconds"], default=None)
            rows.append({"level": level, "bvp": best, "winder_s": sec, "winder_n": res.n,
                         "winder_rel_error": err / truth_len, "samples": len(timed[("tolerance",)].samples),
                         "estimate_over_true": res.smooth_error_estimate / err if err > 0 else None,
                         "ratio": best["seconds"] / sec if best else None, "fixed": fixed,
                         "fixed_ratio": best["seconds"] / fixed["seconds"] if best and fixed else None})
        out[case.key] = {"title": case.title, "sweep": sweep, "levels": rows}
    return out


def _side_by_side(tasks: list[tuple[Any, Callable[[], Any]]], repeats: int):
    """The tasks timed round-robin: SIDE_REPEATS x repeats / 5 samples each (fewer for a slow one)."""
    from bench.timing import interleaved  # noqa: PLC0415

    return interleaved(tasks, repeats=max(3, SIDE_REPEATS * repeats // 5), min_repeats=min(repeats, 5),
                       budget=SIDE_BUDGET)


def _fixed_errors(case, surface, truth_len: float) -> dict[int, float]:
    """winder's relative length error at each n of HINDSIGHT_N (one solve each, no estimate)."""
    from winder.paths.geodesic import geodesic  # noqa: PLC0415

    out = {}
    for n in HINDSIGHT_N:
        res = geodesic(surface, case.start, case.end, rounds=case.rounds, n=n, estimate=False)
        out[n] = abs(res.length - truth_len) / truth_len if res.converged else float("inf")
        if out[n] < 1e-14:
            break
    return out


def _hindsight_ns(errors: dict[int, float], level: float) -> list[int]:
    """The fixed n that count for winder's like-for-like column: those whose error meets the level, as
    every larger n measured does (solve_bvp's rule), from the least such n up to twice it (a smaller n
    can cost more, solved from a coarser level); empty where none does."""
    ns = sorted(errors)
    ok = [n for k, n in enumerate(ns) if all(errors[m] <= level for m in ns[k:])]
    return [m for m in ok if m <= 2 * ok[0]]


def markdown(data: dict[str, Any]) -> list[str]:
    """The section of RESULTS.md."""
    targets, bvp = data["targets"], data["bvp"]
    lines = ["## Solver speed (issue 14)", "",
             "Quarter bend (ArcAxis 150 mm, radius 40 mm, 1 extra round), solved to convergence from the "
             "straight path, without the 2n + 1 estimate solve; medians of repeats (n = 1000: in blocks between "
             "the n = 100,000 solves, each block's median in the last column, as this machine's speed drifts).", "",
             "| case | median | target | Newton iterations | relative error | samples | block medians |",
             "|---|---:|---:|---:|---:|---:|---:|"]
    for key, r in targets.items():
        spread = r.get("block_medians_s")
        blocks = f"{spread[0] * 1e3:.2f} to {spread[1] * 1e3:.2f} ms" if spread else "-"
        lines.append(f"| {key.replace('bend_n', 'n = ')} | {r['seconds'] * 1e3:.2f} ms | <= {r['target_s'] * 1e3:g} ms | "
                     f"{r['iterations']} | {r['rel_error']:+.1e} | {r.get('samples', '-')} | {blocks} |")
    lines += ["", "Against scipy's solve_bvp with analytic Jacobians (fun_jac, bc_jac) on the closed-form geodesic "
              "equations, like for like: each at its best setting in hindsight, solve_bvp at its fastest tol "
              "whose error meets the level, winder at its fastest fixed n whose error meets it (one solve "
              "without the estimate, `--points N`). Target: winder >= 5x faster. Beside it, winder's tolerance "
              "mode at level x length, against the same hindsight solve_bvp: it finds n itself, and its time "
              "includes the 2n + 1 solve of the error bound it reports, which solve_bvp does not give. The sweeps "
              "pick the candidates; the fastest few of each side are then timed interleaved, round-robin, and "
              "each ratio is of two medians from that one loop.", "",
              "| mandrel | level | solve_bvp | winder, n in hindsight | bvp / winder | winder, tolerance mode "
              "| bvp / winder | winder n | estimate / true error |",
              "|---|---|---:|---:|---:|---:|---:|---:|---:|"]
    for key, c in bvp.items():
        for r in c["levels"]:
            b = r["bvp"]
            bcell = f"{b['seconds'] * 1e3:.1f} ms (tol {b['tol']:.0e}, {b['nodes']} nodes)" if b else "not reached"
            ratio = f"{r['ratio']:.2f}x" if r["ratio"] else "-"
            est = f"{r['estimate_over_true']:.2f}" if r["estimate_over_true"] else "-"
            fx = r.get("fixed")
            fcell = f"{fx['seconds'] * 1e3:.2f} ms (n = {fx['n']})" if fx else "not reached"
            fratio = f"{r['fixed_ratio']:.2f}x" if r.get("fixed_ratio") else "-"
            lines.append(f"| {c['title']} | {r['level']:.0e} | {bcell} | {fcell} | {fratio} | "
                         f"{r['winder_s'] * 1e3:.1f} ms | {ratio} | {r['winder_n']} | {est} |")
    asked = [f"{c['title']}: {p['seconds'] * 1e3:.1f} ms (relative error {p['rel_error']:.1e})"
             for c in bvp.values() for p in c.get("sweep", ()) if p["tol"] == LEVELS[0] and p["status"] == 0]
    if asked:
        lines += ["", f"solve_bvp asked for tol = {LEVELS[0]:g} itself, the setting a user without hindsight would "
                  "type (in the sweep, median of repeats): " + "; ".join(asked) + "."]
    return lines + [""]
