"""A bracketed scalar root (the pattern's angle, a dome's turnaround station, a trace's crossing,
an integrator's event).

Regula falsi with the Illinois modification: the end that stays put has its value halved, so the
bracket closes from both sides (superlinearly), and a step outside the bracket falls back to
bisection. Replaces scipy.optimize.brentq here: scipy.optimize takes longer to import than a small
job takes to plan.
"""

from __future__ import annotations

import math
from typing import Callable

MAX_ITER = 200


def bracketed_root(f: Callable[[float], float], a: float, b: float, xtol: float = 1e-12,
                   rtol: float = 4.0 * 2.220446049250313e-16, fa: float | None = None,
                   fb: float | None = None) -> float:
    """x in [a, b] with f(x) = 0 to within xtol + rtol |x|; f(a) and f(b) of opposite signs (or zero).

    fa, fb: f(a) and f(b) where the caller has them already. Raises ValueError where the signs do not
    differ (as brentq does)."""
    fa = float(f(a)) if fa is None else float(fa)
    fb = float(f(b)) if fb is None else float(fb)
    if fa == 0.0:
        return a
    if fb == 0.0:
        return b
    if math.copysign(1.0, fa) == math.copysign(1.0, fb):
        raise ValueError(f"f(a) and f(b) must have different signs, got f({a:g}) = {fa:g}, f({b:g}) = {fb:g}")
    stay = 0  # which end stayed put last: -1 a, +1 b
    c = a
    for _ in range(MAX_ITER):
        c = b - fb * (b - a) / (fb - fa)
        if not (min(a, b) < c < max(a, b)):
            c = 0.5 * (a + b)
        fc = float(f(c))
        if fc == 0.0:
            return c
        if math.copysign(1.0, fc) == math.copysign(1.0, fb):
            b, fb = c, fc
            if stay == -1:
                fa *= 0.5
            stay = -1
        else:
            a, fa = c, fc
            if stay == 1:
                fb *= 0.5
            stay = 1
        if abs(b - a) <= xtol + rtol * abs(c):
            return c
    return c
