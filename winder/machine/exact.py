"""The exact fiber between two planned points, where the program needs points the plan does not have
(densify's midpoints and dense points): the geodesic ODE (winder.paths.ode.geodesic_rhs) from the
interval's first planned point, in its planned direction, over the smooth path's arc length to the
point, instead of the smooth path's Hermite interpolant. The interpolant's position is close (0.016 mm
on a hemispherical dome of 30 points), but its direction is up to 0.15 deg off near a turnaround, and
the eye, 170-210 mm out along the free fiber, then misses the fiber's tangent by 0.45 mm.

An interval is taken as geodesic only where the ODE, run over the whole interval, arrives at the next
planned point within ARRIVE_TOL and in its planned direction within ARRIVE_TURN (a friction-held path, a dwell's free fiber, a turnaround held by the
mandrel's end arrive elsewhere and keep the smooth path). Round sections only, for now: on a
non-circular section (flats and corners) `winder simulate` still measures against the smooth path,
and its contact search there is tuned to it. Classic Runge-Kutta with STEPS steps over the
interval, all intervals of a layer in one batch of (4, k) states: an interval is a few per cent of the
dome's radius, where the step's error is far below a micrometre. A point inside an interval is
reached from the interval's run: from the step before it by one shorter Runge-Kutta step (the same
step bound, four right-hand sides per point instead of a run of its own: the program's dense points
are up to 64 to an interval).

On a surface of revolution the ODE does not depend on theta (Clairaut), and a helical layer's
circuits are turned copies of one another: the same stations and tangent coordinates, theta shifted.
Intervals (and points within them) that agree within COPY_TOL are integrated once, each copy taking its
representative's states with its own theta offset, and its point and direction turned from the
representative's (SweepSurface.turned) rather than read from the surface again. On copv_12 (parts/)
that is 45,000 intervals and 250,000 points a layer group become a few hundred intervals and about
2,000 points (its exact points take 5 s instead of 23 s).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from winder.geometry.measure import grid_groups, row_norms, tangent_coordinates
from winder.machine.smooth import SmoothPaths
from winder.paths.ode import geodesic_rhs

STEPS = 16  # Runge-Kutta steps over an interval between planned points
# The arc length of an interval's points: its speed at ARC_NODES Chebyshev nodes, the polynomial through
# them integrated (the smooth path's speed is smooth within an interval: error far below a nanometre),
# instead of the smooth path's own quadrature per point (arc_at: 5 nodes a point, up to 64 points an
# interval).
ARC_NODES = 8
_ARC_X = 0.5 - 0.5 * np.cos(np.pi * (np.arange(ARC_NODES) + 0.5) / ARC_NODES)  # on [0, 1]
_ARC_FIT = np.linalg.inv(np.vander(_ARC_X, ARC_NODES, increasing=True))  # speeds -> polynomial coefficients
# On a surface of revolution, intervals whose start stations and arc lengths agree within COPY_MM, and
# tangent coordinates (s' and theta' per mm) within COPY_TOL, share one integration, and so do their
# points whose fractions of a step agree within COPY_FRACTION: a copy's point then lies within a few
# nanometres of where its own integration would put it (the program writes micrometres).
COPY_MM = 1e-9
COPY_TOL = 1e-12
COPY_FRACTION = 1e-9
ARRIVE_TOL = 1e-3  # mm: the ODE over an interval lands this close to the next planned point
ARRIVE_TURN = 1e-5  # rad: and this close to its planned direction: a geodesic (a path held by friction
# may land within ARRIVE_TOL over a short interval, its direction far off: on a grown dome 0.145 mm at the eye)


def _step(surface, y: np.ndarray, length: np.ndarray, h: float | np.ndarray) -> np.ndarray:
    """One classic Runge-Kutta step of the fraction h (scalar or (k,)) of the arc length `length` (k,)
    from the states y (4, k) (unit speed)."""

    def f(state):
        return geodesic_rhs(surface, state) * length

    k1 = f(y)
    k2 = f(y + 0.5 * h * k1)
    k3 = f(y + 0.5 * h * k2)
    k4 = f(y + h * k3)
    return y + (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4)


def _run(surface, y0: np.ndarray, length: np.ndarray) -> np.ndarray:
    """States (STEPS + 1, 4, k) at the fractions 0, 1 / STEPS, .., 1 of the arc length `length` (k,)
    from y0 (4, k) along the geodesic (unit speed)."""
    out = np.empty((STEPS + 1, *y0.shape))
    out[0] = y0
    for j in range(STEPS):
        out[j + 1] = _step(surface, out[j], length, 1.0 / STEPS)
    return out


def _arc_within(paths: SmoothPaths, k: np.ndarray, like: np.ndarray, u: np.ndarray) -> np.ndarray:
    """Arc length (m,) of the smooth path from the first node of interval k (m,) to u (m,), each
    interval's speed taken from the interval like (m,) (its representative, module docstring)."""
    used, back = np.unique(like, return_inverse=True)
    speed = paths.speed((used[:, None] + _ARC_X).ravel()).reshape(used.size, ARC_NODES)
    coef = (speed @ _ARC_FIT.T / np.arange(1, ARC_NODES + 1))[back]  # the integral's: h^(k+1) / (k+1)
    h = u - k
    out = coef[:, -1]
    for j in range(ARC_NODES - 2, -1, -1):  # Horner's rule: no (m, nodes) powers
        out = out * h + coef[:, j]
    return out * h


@dataclasses.dataclass(frozen=True)
class IntervalRuns:
    """The geodesic runs over intervals of a SmoothPaths, kept between the calls of exact_points on
    the same paths (the program asks for the midpoints, then for the dense points of some passes).

    intervals, length : (k,) the intervals (sorted) and their arc lengths. rep : (k,) each one's
    representative's column of runs, like : (k,) that representative's interval, turn : (k,) its
    theta offset from it (module docstring). runs : (STEPS + 1, 4, g) the representatives' states.
    good : (k,) whether the run arrives as a geodesic (ARRIVE_TOL, ARRIVE_TURN)."""

    intervals: np.ndarray
    length: np.ndarray
    rep: np.ndarray
    like: np.ndarray
    turn: np.ndarray
    runs: np.ndarray
    good: np.ndarray


def interval_runs(paths: SmoothPaths, intervals: np.ndarray) -> IntervalRuns:
    """The IntervalRuns of the sorted intervals (k,) of paths."""
    surface = paths.surface
    arc = paths.arc
    length = arc[intervals + 1] - arc[intervals]
    ev = surface.evaluate(paths.s[intervals], paths.th[intervals], order=1)
    a, b = tangent_coordinates(ev.ps.T, ev.pt.T, paths.d[intervals].T)
    speed = row_norms(ev.ps * a[:, None] + ev.pt * b[:, None])
    ok_speed = speed > 0.0
    scale = np.where(ok_speed, speed, 1.0)
    y0 = np.vstack([paths.s[intervals], paths.th[intervals], a / scale, b / scale])
    # On a surface of revolution each group of copies is integrated once (module docstring).
    first, group = (grid_groups(np.column_stack([y0[0], y0[2], y0[3], length]),
                                np.array([COPY_MM, COPY_TOL, COPY_TOL, COPY_MM]))
                    if surface.is_revolution else (np.arange(intervals.size), np.arange(intervals.size)))
    with np.errstate(all="ignore"):
        runs = _run(surface, y0[:, first], length[first])
    turn = y0[1] - y0[1, first][group]
    end = runs[-1][:, group]
    end[1] += turn
    finite = np.all(np.isfinite(end), axis=0)
    arrive = np.full(intervals.size, np.inf)
    if finite.any():
        got = surface.points(end[0, finite], end[1, finite])
        want = surface.points(paths.s[intervals + 1][finite], paths.th[intervals + 1][finite])
        arrive[finite] = row_norms(got - want)
        ev_end = surface.evaluate(end[0, finite], end[1, finite], order=1)
        dir_end = ev_end.ps * end[2, finite][:, None] + ev_end.pt * end[3, finite][:, None]
        dir_want = paths.d[intervals + 1][finite]
        cos = np.einsum("ij,ij->i", dir_end, dir_want) / (row_norms(dir_end) * row_norms(dir_want))
        arrive[finite] = np.where(np.arccos(np.clip(cos, -1.0, 1.0)) <= ARRIVE_TURN, arrive[finite], np.inf)
    good = (arrive <= ARRIVE_TOL) & ok_speed & (length > 0.0)
    return IntervalRuns(intervals, length, group, intervals[first][group], turn, runs, good)


def exact_points(paths: SmoothPaths, u: np.ndarray,
                 memo: dict | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(s, theta, p (n, 3), unit d (n, 3)) at global parameters u (n,): SmoothPaths.point's, with
    the points inside a geodesic interval on the exact geodesic (module docstring). memo: a dict
    kept by the caller between calls on the same paths: the runs of the first call's intervals are
    kept there and serve a later call whose intervals are among them."""
    u = np.asarray(u, dtype=float)
    if u.size == 0 or paths.s.size < 2 or not paths.surface.section.is_circle:
        return paths.point(u)
    k, h = paths._interval(u)
    inside = np.flatnonzero((h > 0.0) & (h < 1.0) & ~paths.free[k] & ~paths.free[k + 1])
    if inside.size == 0:
        return paths.point(u)
    surface = paths.surface
    intervals, back = np.unique(k[inside], return_inverse=True)
    known = None if memo is None else memo.get("runs")
    at = None if known is None else np.minimum(np.searchsorted(known.intervals, intervals), known.intervals.size - 1)
    if at is None or not np.array_equal(known.intervals[at], intervals):
        known, at = interval_runs(paths, intervals), np.arange(intervals.size)
        if memo is not None:
            memo["runs"] = known
    take = np.flatnonzero(known.good[at][back])
    if take.size == 0:
        return paths.point(u)
    # Each point from the step of its interval's run before it, by one step of the rest of the way.
    own = at[back[take]]  # each point's interval among the runs'
    length = known.length[own]
    frac = np.clip(_arc_within(paths, known.intervals[own], known.like[own], u[inside[take]]) / length, 0.0, 1.0)
    frac *= STEPS
    j = np.minimum(np.floor(frac).astype(np.intp), STEPS - 1)
    h = (frac - j) / STEPS
    rep = known.rep[own]
    start = known.runs[j, :, rep].T
    start[1] += known.turn[own]
    # A point of a copy is its representative's, its theta offset as its interval's.
    pick, copy = (grid_groups(np.column_stack([rep, j, h]), np.array([1.0, 1.0, COPY_FRACTION]))
                  if surface.is_revolution else (np.arange(own.size), np.arange(own.size)))
    with np.errstate(all="ignore"):
        y_rep = _step(surface, start[:, pick], length[pick], h[pick])
    turn = start[1] - start[1, pick][copy]  # each copy's theta offset from its representative
    y = y_rep[:, copy]
    y[1] += turn
    fine = np.all(np.isfinite(y), axis=0)
    use = take[fine]
    if use.size == 0:
        return paths.point(u)
    ys = y[:, fine]
    rows = inside[use]
    # The surface read at the representatives, each copy's point and direction turned from its own.
    rep_ok = np.all(np.isfinite(y_rep), axis=0)
    at_rep = np.cumsum(rep_ok) - 1  # a finite representative's row among those read
    ev = surface.evaluate(y_rep[0, rep_ok], y_rep[1, rep_ok], order=1)
    dd_rep = ev.ps * y_rep[2, rep_ok][:, None] + ev.pt * y_rep[3, rep_ok][:, None]
    mine = at_rep[copy[fine]]
    p_rows, dd = ev.p[mine], dd_rep[mine]
    if surface.is_revolution:
        p_rows, dd = surface.turned(p_rows, turn[fine]), surface.turned(dd, turn[fine], point=False)
    # The smooth path's points only where the geodesic does not stand for it.
    s, th, p, d = np.empty(u.size), np.empty(u.size), np.empty((u.size, 3)), np.empty((u.size, 3))
    rest = np.ones(u.size, dtype=bool)
    rest[rows] = False
    if rest.any():
        s[rest], th[rest], p[rest], d[rest] = paths.point(u[rest])
    s[rows], th[rows], p[rows] = ys[0], ys[1], p_rows
    d[rows] = dd / row_norms(dd)[:, None]
    return s, th, p, d
