"""Newton on the chain energy's block-tridiagonal Hessian (docs/math/03-newton.md), one level of the solver.

One surface evaluation per step: the accepted full step's evaluation (with second derivatives) serves
the next iteration. A step below 1e-3 of a segment lets the next one reuse the Cholesky factor (a
chord step: first derivatives and a back-substitution). Steps whose energy decrease is below E's
roundoff cannot be judged by a line search: they are taken while they contract and end the solve
when they stop. Where the Hessian is indefinite, or its direction is not downhill, the
positive-definite Gauss-Newton matrix; Armijo backtracking otherwise.
"""

from __future__ import annotations

import dataclasses
import math
from enum import Enum

import numpy as np

from winder.errors import SolverError
from winder.geometry.surface import SurfaceEval, SweepSurface, jet_of
from winder.paths.energy import (banded_direction, chain_segments, chord_direction, newton_banded,
                                 newton_terms, step_moves)

STEP_TOL = 1e-9  # converged when no vertex moves more than this fraction of the mean segment
LEVEL_STEP_TOL = 1e-5  # looser on the coarse levels: the next level corrects them in a step or two
# A coarse level also stops once its predicted next step is below this fraction of its segment: 8x
# finer, the next level's first step is ~3e-2 of its own segment whatever the coarse level's last
# few 1e-4 (measured on the reference mandrels), and that saves the coarse level's last iteration.
LEVEL_PREDICTED = 3e-4
MAX_NEWTON = 100
ARMIJO = 1e-4
# A predicted next step counts as converged this far below the step tolerance: on the reference
# mandrels the actual next step came out up to 10x the prediction (near roundoff), still below it.
PREDICTED_MARGIN = 5e-2
CHORD_STEP = 1e-3  # a Newton step below this fraction of the segment: the next step reuses the factor
ENERGY_NOISE = 1.4e-14  # E's relative roundoff per sqrt(point) (64 ulp): smaller decreases are noise
COORD_NOISE = 1e-12  # relative to the largest coordinate: a vertex move this small is at roundoff
BOUNDARY_TOL = 1e-9  # a vertex this close (mm) to an end of the mandrel is on it
# With a length tolerance (tolerance mode) a solve may stop once the vertices' remaining error can no
# longer move the smooth length by LENGTH_SHARE of it. The smooth length is stationary at the geodesic,
# so an error of e segments moves it by about L (c2 e^2 + c1 (h k)^3 e), h k = max |y_{i-1} - 2 y_i +
# y_{i+1}| / h the chain's turn per segment: measured on the reference mandrels (bend and elliptic tube,
# n = 31 to 10,323), c2 <= 0.3 and c1 <= 3.7e-3: SETTLE_SECOND and SETTLE_FIRST hold them with a 3x margin,
# and LENGTH_SHARE keeps what they miss far below the tolerance.
LENGTH_SHARE = 1e-2
SETTLE_SECOND = 1.0
SETTLE_FIRST = 1e-2
SETTLE_MAX = 1e-2  # only inside Newton's quadratic range (measured: from 3e-2 of a segment on)
SETTLE_PREDICTED = 3.0  # margin on the predicted next step (Newton's disp^3 / prev^2) as the error


class StopReason(Enum):
    STEP = "the Newton step fell below the step tolerance"
    LENGTH = "the remaining Newton step moves the length by far less than its tolerance"
    ROUNDOFF = "no further decrease of the energy at machine precision"
    LBFGS = "L-BFGS-B stopped on its tolerances"
    MAX_ITER = "the iteration limit was reached"


@dataclasses.dataclass(frozen=True)
class Level:
    """One solve at n interior points: Newton iterations used of its cap, whether it converged."""

    n: int
    iterations: int
    max_iter: int
    converged: bool


@dataclasses.dataclass(frozen=True, eq=False)
class PathSolve:
    """A solved polyline in the parameter domain.

    s, theta : (n + 2,) float, end points included, theta unwrapped (radians).
    history : (k, 2) float, energy and gradient norm per iteration (finest level).
    """

    s: np.ndarray
    theta: np.ndarray
    iterations: int
    converged: bool
    reason: StopReason
    history: np.ndarray
    nfev: int = 0  # energy evaluations (with or without derivatives)
    ev: SurfaceEval | None = None  # interior vertices, order >= 1
    ends: SurfaceEval | None = None  # the two end points, order 1
    levels: tuple[Level, ...] = ()
    factor: np.ndarray | None = None  # the last Newton Hessian's banded Cholesky factor, if any

    def jacobians(self) -> tuple[np.ndarray, np.ndarray]:
        """(Phi_s, Phi_theta) at all n + 2 vertices, each (n + 2, 3), from the solver's last evaluation."""
        return (np.concatenate([self.ends.ps[:1], self.ev.ps, self.ends.ps[1:]]),
                np.concatenate([self.ends.pt[:1], self.ev.pt, self.ends.pt[1:]]))

    def jacobian_rows(self) -> tuple[np.ndarray, np.ndarray]:
        """jacobians() as (n + 2, 3) views of (3, n + 2) rows, the same values: their transposes (which
        the length's nodes join) then come without a transposing copy."""
        ends, ev = self.ends, self.ev
        return tuple(np.concatenate([e.T[:, :1], f.T, e.T[:, 1:]], axis=1).T
                     for e, f in ((ends.ps, ev.ps), (ends.pt, ev.pt)))

    def with_totals(self, iterations: int, nfev: int, levels: tuple[Level, ...]) -> PathSolve:
        """This solve with these totals: dataclasses.replace's work without its field introspection."""
        return PathSolve(self.s, self.theta, iterations, self.converged, self.reason, self.history, nfev, self.ev,
                         self.ends, levels, self.factor)

    def points(self) -> np.ndarray:
        """The vertices on the surface, (n + 2, 3)."""
        return np.concatenate([self.ends.p[:1], self.ev.p, self.ends.p[1:]])


def evaluate_with_ends(surface: SweepSurface, s: np.ndarray, th: np.ndarray) -> tuple[SurfaceEval, SurfaceEval]:
    """(ends, interior) of the path (s, th) (n + 2,): the two end points at order 1 and the n interior
    ones at order 2, from one evaluation where the surface writes a jet (a cold solve's first two,
    otherwise two evaluations of their own: the same numbers, as the evaluation is per point)."""
    full = surface.evaluate(s, th, order=2)
    jet = jet_of(full, 6)
    if jet is None:
        return surface.evaluate(s[[0, -1]], th[[0, -1]], order=1), surface.evaluate(s[1:-1], th[1:-1], order=2)
    edge, inner = jet[:3, :, ::max(s.shape[0] - 1, 1)].copy(), jet[:, :, 1:-1].copy()
    return SurfaceEval(*edge.transpose(0, 2, 1)), SurfaceEval(*inner.transpose(0, 2, 1))


def _max_step(s: np.ndarray, ds: np.ndarray, s_max: float, moved: np.ndarray | None = None) -> float:
    """Largest alpha <= 1 keeping every interior station inside [0, s_max]; moved : s + ds, if known."""
    if not s.size:
        return 1.0
    moved = s + ds if moved is None else moved
    # the usual case: the full step stays inside (ufunc reductions: ndarray.min's wrapper costs more)
    if np.minimum.reduce(moved) >= 0.0 and np.maximum.reduce(moved) <= s_max:
        return 1.0
    with np.errstate(divide="ignore", invalid="ignore"):
        lim = np.where(ds < 0, -s / ds, np.where(ds > 0, (s_max - s) / ds, np.inf))
    return float(min(1.0, np.min(lim))) if lim.size else 1.0


def chain_bend(y: np.ndarray) -> float:
    """max |y_{i-1} - 2 y_i + y_{i+1}| over the chain y (m, 3) (mm; 0 under three vertices): the chain's
    largest turn per segment h k, times h."""
    a = y[:-2] - 2.0 * y[1:-1] + y[2:]
    return math.sqrt(float(np.maximum.reduce(np.einsum("ij,ij->i", a, a)))) if a.size else 0.0


def _settled(err: float, y: np.ndarray, h: float, length_tol: float, turn: list[float]) -> bool:
    """Whether a vertex error of err segments moves the smooth length of the chain y (n + 2, 3), mean
    segment h (mm), by at most LENGTH_SHARE length_tol (mm); see SETTLE_FIRST. turn : the chain's
    turn per segment once known (a one-element list the caller keeps per iterate), else empty."""
    if err > SETTLE_MAX:
        return False
    budget = LENGTH_SHARE * length_tol / (h * (y.shape[0] - 1))
    if SETTLE_SECOND * err * err > budget:
        return False
    if not turn:
        turn.append(chain_bend(y) / h)
    return SETTLE_SECOND * err * err + SETTLE_FIRST * turn[0]**3 * err <= budget


def _newton(surface: SweepSurface, s: np.ndarray, th: np.ndarray, step_tol: float,
            max_iter: int = MAX_NEWTON, ends: SurfaceEval | None = None,
            predicted_tol: float | None = None, length_tol: float | None = None,
            ev: SurfaceEval | None = None, factor: np.ndarray | None = None) -> PathSolve:
    """Newton from (s, th) (n + 2,) to a step below step_tol of the mean segment; predicted_tol: stop
    after a step once the predicted next one is below this fraction of a segment (default
    PREDICTED_MARGIN step_tol). length_tol (mm): also stop once the remaining step cannot move the
    smooth length by LENGTH_SHARE of it (_settled): without taking a step that small, or after a
    step whose predicted successor is. ev, factor : the surface at (s, th) (order >= 1) and a Newton
    factor from near it, to go on from an earlier solve's end: its first step is then a chord step."""
    predicted_tol = PREDICTED_MARGIN * step_tol if predicted_tol is None else predicted_tol
    si, ti = s[1:-1].copy(), th[1:-1].copy()  # the interior vertices: the end points stay fixed
    points = si.size + 2
    s_max = surface.length
    history = []
    reason = StopReason.MAX_ITER
    converged = False
    it = 0
    prev_disp = np.inf
    # factor: the last Newton Hessian's Cholesky factor, while a chord step can reuse it
    if ends is None:
        ends = surface.evaluate(s[[0, -1]], th[[0, -1]], order=1)
    nfev = 0
    if ev is None:
        ev, nfev, factor = surface.evaluate(si, ti, order=2), 1, None
    chain = None  # chain_segments at ev, where the line search has them
    for it in range(1, max_iter + 1):
        chord = factor is not None
        if not chord and ev.pss is None:  # a damped trial point, evaluated for its energy only
            ev, chain = surface.evaluate(si, ti, order=2), None
            nfev += 1
        e, grad, y, gram, curv, off = newton_terms(ev, ends.p, chain, hessian=None if chord else True)
        # Not np.linalg.norm: its BLAS dot runs threaded on long vectors, and on a loaded machine the
        # threads' hand-off took milliseconds per call (measured: 6 ms at n = 10,000, 2 cores busy).
        history.append((e, math.sqrt(np.einsum("ij,ij->", grad, grad))))
        if chord:
            step, newton = chord_direction(factor, grad), True
            slope = float(np.add.reduce(step * grad, axis=None))
        else:
            step, factor = banded_direction(newton_banded(gram, curv, off), grad)
            slope = float(np.add.reduce(step * grad, axis=None)) if step is not None else 0.0
            newton = step is not None and slope < 0.0
            if not newton:
                step, factor = banded_direction(newton_banded(gram, None, off), grad)
                if step is None:
                    raise SolverError("the Gauss-Newton matrix is singular: the surface parametrization is "
                                      "degenerate on the path")
                factor = None
                slope = float(np.add.reduce(step * grad, axis=None))
        ds, dth = step[:, 0], step[:, 1]
        disp = math.sqrt(float(np.maximum.reduce(step_moves(ev, step))))  # the largest vertex move
        h = math.sqrt(e / (points - 1))
        turn: list[float] = []  # the chain's turn at this iterate, for _settled
        if newton and disp <= step_tol * h:
            # Already converged: this step is below the tolerance (and usually at roundoff).
            converged, reason = True, StopReason.STEP
            break
        if length_tol is not None and newton and _settled(disp / h, y, h, length_tol, turn):
            # The step is the iterate's error to second order: the length no longer needs it.
            converged, reason = True, StopReason.LENGTH
            break
        contracting = newton and disp < 0.5 * prev_disp < np.inf
        # Newton's error squares per step (the next step is about disp^3 / prev_disp^2); a chord step's
        # contracts by a factor of about disp / prev_disp. Stop after this step when the predicted next
        # one is well below the tolerance (the prediction is rough), or this one is below it: that
        # saves the last, roundoff-only iteration.
        predicted = disp**2 / prev_disp if chord else disp**3 / prev_disp**2
        last = disp <= step_tol * h or (contracting and predicted <= predicted_tol * h)
        settle = (length_tol is not None and not last and contracting
                  and _settled(SETTLE_PREDICTED * predicted / h, y, h, length_tol, turn))
        last = last or settle
        # A step this small hardly changes the Hessian: the next iteration reuses its factor.
        chord_next = newton and not last and disp <= CHORD_STEP * h
        order = 1 if last or chord_next else 2
        moved = si + ds  # the full step's stations
        alpha = _max_step(si, ds, s_max, moved)
        bounded = alpha < 1.0
        if bounded:
            alpha *= 0.999
        if -slope <= ENERGY_NOISE * math.sqrt(points) * e and not bounded:
            # The step's energy decrease is below E's roundoff, so a line search cannot judge it; the
            # step itself still carries the gradient's information while it contracts, and is noise
            # once it stops contracting.
            if math.isfinite(prev_disp) and not contracting:
                converged, reason = True, StopReason.ROUNDOFF
                break
            si, ti = moved, ti + dth
            ev, chain = surface.evaluate(si, ti, order=order), None
            nfev += 1
        else:
            while True:
                # 1.0 * x is x: the full step (the usual one) skips the products
                s_try, th_try = (moved, ti + dth) if alpha == 1.0 else (si + alpha * ds, ti + alpha * dth)
                # A full step is the usual one and is usually accepted: its evaluation then serves the
                # next iteration (with second derivatives unless that one is a chord step or none).
                ev_try = surface.evaluate(s_try, th_try, order=order if alpha == 1.0 else 0)
                chain_try = chain_segments(ev_try.p, ends.p)
                e_try = chain_try[2]
                nfev += 1
                if e_try <= e + ARMIJO * alpha * slope or alpha < 1e-12:
                    break
                alpha *= 0.5
            if e_try >= e:
                # A step below the points' own roundoff (a path of 1e-7 mm at 50 mm from the origin: E is
                # then all noise) is converged too: nothing finer is representable.
                floor = COORD_NOISE * float(np.maximum.reduce(np.abs(y), axis=None)) if y.size else 0.0
                if -slope <= 1e-13 * e or disp * alpha <= step_tol * h or disp <= floor:
                    converged, reason = True, StopReason.ROUNDOFF
                elif bounded and alpha < 1e-9:
                    _raise_left(surface, si)
                break
            si, ti, ev, chain = s_try, th_try, ev_try, chain_try
        if alpha == 1.0 and last:
            converged, reason = True, StopReason.LENGTH if settle else StopReason.STEP
            break
        prev_disp = disp if alpha == 1.0 else np.inf
        factor = factor if chord_next and alpha == 1.0 else None
    if si.size and (si.min() <= BOUNDARY_TOL or si.max() >= s_max - BOUNDARY_TOL):
        _raise_left(surface, si)
    if ev.ps is None:
        ev = surface.evaluate(si, ti, order=1)
    return PathSolve(np.concatenate([s[:1], si, s[-1:]]), np.concatenate([th[:1], ti, th[-1:]]), it, converged,
                     reason, np.array(history), nfev, ev, ends, factor=factor)


def _raise_left(surface: SweepSurface, s: np.ndarray) -> None:
    """Refuse a path whose interior stations s (n,) reach an end of the mandrel."""
    # The end it crossed: a path from near one end may run off the other (a cone's small end).
    low = s.min() <= BOUNDARY_TOL and not s.max() >= surface.length - BOUNDARY_TOL
    edge = "polar opening" if not surface.is_axial_parameter else "end"
    where = f"t = 0 (the first {edge})" if low else f"t = {surface.axial_length:.6g} (the far {edge})"
    raise SolverError(f"the shortest path between these points runs off the mandrel past {where}: no "
                      f"geodesic on the surface joins them with this number of rounds; move the end "
                      f"points away from the edge or change the number of rounds")


