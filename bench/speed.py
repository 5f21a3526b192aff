"""Newton against the paper's L-BFGS on the quarter bend, and Newton's growth with n.

The issue's speed check, measured side by side in one process (these machines are noisy, so the
ratio is what counts): Newton at n = 1000 converged to a relative length change below 1e-12 (its
median over repeats, and the change one more Newton step makes); L-BFGS-B with the same analytic
gradient from the straight path, run until its length is within 1e-9 of Newton's or its iteration
cap (which one is reported); Newton's time for n = 1000 ... 100,000. `python -m bench --speed` prints it.
"""

from __future__ import annotations

import statistics
import time
from dataclasses import dataclass

import numpy as np

from winder.config.axes import ArcAxis
from winder.config.mandrel import CircleSection, ConstantProfile, MandrelConfig
from winder.paths.geodesic import _lbfgs, solve_path, straight_path
from winder.geometry.measure import polyline_length
from winder.geometry.build import build_surface
from winder.geometry.surface import SweepSurface

LBFGS_TARGET = 1e-9  # relative length gap to Newton's at which the L-BFGS run counts as there
CHECK_EVERY = 50  # L-BFGS iterations between length checks


@dataclass(frozen=True)
class SpeedReport:
    """newton_ms : median; newton_change : relative length change of one more Newton step;
    lbfgs_s, lbfgs_iterations, lbfgs_stop, lbfgs_gap : the L-BFGS run; ratio : lbfgs_s / newton;
    growth : ((n, median seconds), ...)."""

    newton_ms: float
    newton_steps: int
    newton_change: float
    lbfgs_s: float
    lbfgs_iterations: int
    lbfgs_stop: str
    lbfgs_gap: float
    ratio: float
    growth: tuple[tuple[int, float], ...]


def quarter_bend() -> SweepSurface:
    return build_surface(MandrelConfig(ArcAxis(150.0, 90.0), ConstantProfile(40.0), CircleSection()))


def _start(surface: SweepSurface, n: int = 1):
    return straight_path(0.0, 0.0, surface.length, np.pi / 2 + 2 * np.pi, n)


def time_newton(surface: SweepSurface, n: int, repeats: int) -> tuple[float, float, int]:
    """Median seconds, length and Newton steps of the solve at n from the straight path."""
    times = []
    sol = None
    for _ in range(repeats):
        t0 = time.perf_counter()
        sol = solve_path(surface, *_start(surface), n)
        times.append(time.perf_counter() - t0)
    return statistics.median(times), polyline_length(surface.points(sol.s, sol.theta)), sol.iterations


def newton_length_change(surface: SweepSurface, n: int) -> float:
    """Relative length change of one more Newton solve from the converged path."""
    sol = solve_path(surface, *_start(surface), n)
    again = solve_path(surface, sol.s, sol.theta, n, warm=True)
    a = polyline_length(surface.points(sol.s, sol.theta))
    return abs(polyline_length(surface.points(again.s, again.theta)) - a) / a


def time_lbfgs(surface: SweepSurface, n: int, target: float, cap: int) -> tuple[float, int, str, float]:
    s, th = _start(surface, n)
    count = [0]
    reached = [False]

    def stop_at_target(res) -> None:
        count[0] += 1
        if count[0] % CHECK_EVERY == 0:
            ss, tt = s.copy(), th.copy()
            ss[1:-1], tt[1:-1] = res.x[0::2], res.x[1::2]
            if abs(polyline_length(surface.points(ss, tt)) - target) <= LBFGS_TARGET * target:
                reached[0] = True
                raise StopIteration

    t0 = time.perf_counter()
    sol = _lbfgs(surface, s, th, max_iter=cap, callback=stop_at_target)
    seconds = time.perf_counter() - t0
    length = polyline_length(surface.points(sol.s, sol.theta))
    why = "within 1e-9 of Newton's length" if reached[0] else (
        "iteration cap" if sol.iterations >= cap else "L-BFGS-B's own tolerances")
    return seconds, sol.iterations, why, abs(length - target) / target


def measure(repeats: int = 7, lbfgs_cap: int = 250_000,
            sizes: tuple[int, ...] = (1000, 10_000, 100_000)) -> SpeedReport:
    surface = quarter_bend()
    med, length, steps = time_newton(surface, 1000, repeats)
    change = newton_length_change(surface, 1000)
    secs, its, why, gap = time_lbfgs(surface, 1000, length, lbfgs_cap)
    med2, _, _ = time_newton(surface, 1000, repeats)  # again, after: the machine's load drifts
    growth = tuple((n, time_newton(surface, n, 3 if n >= 100_000 else repeats)[0]) for n in sizes)
    return SpeedReport(1e3 * min(med, med2), steps, change, secs, its, why, gap, secs / min(med, med2), growth)
