"""Speed of the geodesic solver (issue: Newton vs the paper's L-BFGS, growth with n).

Run: python bench/geodesic_speed.py [--repeats 7]
Measures, side by side in one process (these machines are noisy, so ratios are what count):
- Newton on the quarter-bend tube (bend radius 150, tube radius 40, one extra round), n = 1000,
  converged to a relative length change below 1e-12: median wall time;
- the paper's method (scipy L-BFGS-B, same analytic gradient, straight start) run until its length
  is within 1e-9 (relative) of Newton's, or until its iteration cap: time, iterations, which one;
- Newton's time against n = 1000 ... 100,000 (linear growth).
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from winder.config import ArcAxis, CircleSection, ConstantProfile, MandrelConfig
from winder.geodesic import _lbfgs, solve_path, straight_path
from winder.measure import polyline_length
from winder.surface import build_surface


def quarter_bend():
    return build_surface(MandrelConfig(ArcAxis(150.0, 90.0), ConstantProfile(40.0), CircleSection()))


def time_newton(surface, n: int, repeats: int) -> tuple[float, float, int]:
    start = straight_path(0.0, 0.0, surface.length, np.pi / 2 + 2 * np.pi, 1)
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        sol = solve_path(surface, *start, n)
        times.append(time.perf_counter() - t0)
    length = polyline_length(surface.points(sol.s, sol.theta))
    return statistics.median(times), length, sol.iterations


def newton_length_change(surface, n: int) -> float:
    """Relative length change of one more Newton step from the converged path: the convergence."""
    sol = solve_path(surface, *straight_path(0.0, 0.0, surface.length, np.pi / 2 + 2 * np.pi, 1), n)
    again = solve_path(surface, sol.s, sol.theta, n, warm=True)
    a = polyline_length(surface.points(sol.s, sol.theta))
    b = polyline_length(surface.points(again.s, again.theta))
    return abs(b - a) / a


class _Reached(Exception):
    pass


def time_lbfgs(surface, n: int, target: float, cap: int) -> tuple[float, int, str, float]:
    s, th = straight_path(0.0, 0.0, surface.length, np.pi / 2 + 2 * np.pi, n)
    count = [0]
    reached = [False]

    def stop_at_target(res) -> None:
        count[0] += 1
        if count[0] % 50 == 0:
            ss, tt = s.copy(), th.copy()
            ss[1:-1], tt[1:-1] = res.x[0::2], res.x[1::2]
            if abs(polyline_length(surface.points(ss, tt)) - target) <= 1e-9 * target:
                reached[0] = True
                raise StopIteration

    t0 = time.perf_counter()
    sol = _lbfgs(surface, s, th, max_iter=cap, callback=stop_at_target)
    seconds = time.perf_counter() - t0
    length = polyline_length(surface.points(sol.s, sol.theta))
    why = "reached 1e-9 of Newton's length" if reached[0] else (
        "iteration cap" if sol.iterations >= cap else "L-BFGS-B stopped on its own tolerances")
    return seconds, sol.iterations, why, abs(length - target) / target


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeats", type=int, default=7)
    ap.add_argument("--lbfgs-cap", type=int, default=300_000)
    args = ap.parse_args()
    surface = quarter_bend()
    med, length, iters = time_newton(surface, 1000, args.repeats)
    print(f"newton  n=1000: median {med * 1e3:.2f} ms over {args.repeats} runs, {iters} Newton steps "
          f"(all levels), length {length:.12f} mm, one more step changes it by "
          f"{newton_length_change(surface, 1000):.1e} (relative)")
    secs, its, why, rel = time_lbfgs(surface, 1000, length, args.lbfgs_cap)
    med2, _, _ = time_newton(surface, 1000, args.repeats)
    print(f"lbfgs   n=1000: {secs:.2f} s, {its} iterations, stopped: {why}; relative length gap {rel:.1e}")
    print(f"ratio lbfgs / newton: {secs / min(med, med2):.0f}x (newton re-measured after: {med2 * 1e3:.2f} ms)")
    print("n        newton median   per point")
    for n in (1000, 10_000, 100_000):
        m, _, _ = time_newton(surface, n, 3 if n >= 100_000 else args.repeats)
        print(f"{n:<8d} {m * 1e3:10.1f} ms   {m / n * 1e6:6.2f} us")


if __name__ == "__main__":
    main()
