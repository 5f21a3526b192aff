"""Newton on the chain energy's block-tridiagonal Hessian (MATH.md 3), one level of the solver.

One surface evaluation per step: the accepted full step's evaluation (with second derivatives) serves
the next iteration. A step below 1e-3 of a segment lets the next one reuse the Cholesky factor (a
chord step: first derivatives and a back-substitution). Steps whose energy decrease is below E's
roundoff cannot be judged by a line search: they are taken while they contract and end the solve
when they stop. Where the Hessian is indefinite, or its direction is not downhill, the
positive-definite Gauss-Newton matrix; Armijo backtracking otherwise.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import Enum

import numpy as np

from winder.errors import SolverError
from winder.geometry.surface import SurfaceEval, SweepSurface
from winder.paths.energy import _dot_cols, chain_energy, chain_terms, chord_direction, newton_direction

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


@dataclass(frozen=True)
class Level:
    """One solve at n interior points: Newton iterations used of its cap, whether it converged."""

    n: int
    iterations: int
    max_iter: int
    converged: bool


@dataclass(frozen=True, eq=False)
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

    def points(self) -> np.ndarray:
        """The vertices on the surface, (n + 2, 3)."""
        return np.concatenate([self.ends.p[:1], self.ev.p, self.ends.p[1:]])


def _max_step(s: np.ndarray, ds: np.ndarray, s_max: float) -> float:
    """Largest alpha <= 1 keeping every interior station inside [0, s_max]."""
    if not s.size:
        return 1.0
    moved = s + ds
    if moved.min() >= 0.0 and moved.max() <= s_max:  # the usual case: the full step stays inside
        return 1.0
    with np.errstate(divide="ignore", invalid="ignore"):
        lim = np.where(ds < 0, -s / ds, np.where(ds > 0, (s_max - s) / ds, np.inf))
    return float(min(1.0, np.min(lim))) if lim.size else 1.0


def chain_bend(y: np.ndarray) -> float:
    """max |y_{i-1} - 2 y_i + y_{i+1}| over the chain y (m, 3) (mm; 0 under three vertices): the chain's
    largest turn per segment h k, times h."""
    a = y[:-2] - 2.0 * y[1:-1] + y[2:]
    return math.sqrt(float(np.max(np.einsum("ij,ij->i", a, a)))) if a.size else 0.0


def _settled(err: float, p: np.ndarray, ends: np.ndarray, h: float, length_tol: float) -> bool:
    """Whether a vertex error of err segments moves the smooth length of the chain p (n, 3) between
    ends (2, 3), mean segment h (mm), by at most LENGTH_SHARE length_tol (mm); see SETTLE_FIRST."""
    if err > SETTLE_MAX:
        return False
    budget = LENGTH_SHARE * length_tol / (h * (p.shape[0] + 1))
    if SETTLE_SECOND * err * err > budget:
        return False
    turn = chain_bend(np.concatenate([ends[:1], p, ends[1:]])) / h
    return SETTLE_SECOND * err * err + SETTLE_FIRST * turn**3 * err <= budget


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
    s, th = s.copy(), th.copy()
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
        ev, nfev, factor = surface.evaluate(s[1:-1], th[1:-1], order=2), 1, None
    for it in range(1, max_iter + 1):
        chord = factor is not None
        if not chord and ev.pss is None:  # a damped trial point, evaluated for its energy only
            ev = surface.evaluate(s[1:-1], th[1:-1], order=2)
            nfev += 1
        e, grad, gram, curv, off = chain_terms(ev, ends.p, full_hessian=None if chord else True)
        # Not np.linalg.norm: its BLAS dot runs threaded on long vectors, and on a loaded machine the
        # threads' hand-off took milliseconds per call (measured: 6 ms at n = 10,000, 2 cores busy).
        history.append((e, float(np.sqrt(np.einsum("ij,ij->", grad, grad)))))
        if chord:
            step, newton = chord_direction(factor, grad), True
            slope = float(np.sum(step * grad))
        else:
            step, factor = newton_direction(gram + curv, off, grad)
            slope = float(np.sum(step * grad)) if step is not None else 0.0
            newton = step is not None and slope < 0.0
            if not newton:
                step, factor = newton_direction(gram, off, grad)
                if step is None:
                    raise SolverError("the Gauss-Newton matrix is singular: the surface parametrization is "
                                      "degenerate on the path")
                factor = None
                slope = float(np.sum(step * grad))
        move = ev.ps * step[:, :1] + ev.pt * step[:, 1:]
        disp = float(np.sqrt(_dot_cols(move, move).max()))
        h = math.sqrt(e / (s.shape[0] - 1))
        if newton and disp <= step_tol * h:
            # Already converged: this step is below the tolerance (and usually at roundoff).
            converged, reason = True, StopReason.STEP
            break
        if length_tol is not None and newton and _settled(disp / h, ev.p, ends.p, h, length_tol):
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
                  and _settled(SETTLE_PREDICTED * predicted / h, ev.p, ends.p, h, length_tol))
        last = last or settle
        # A step this small hardly changes the Hessian: the next iteration reuses its factor.
        chord_next = newton and not last and disp <= CHORD_STEP * h
        order = 1 if last or chord_next else 2
        alpha = _max_step(s[1:-1], step[:, 0], s_max)
        bounded = alpha < 1.0
        if bounded:
            alpha *= 0.999
        if -slope <= ENERGY_NOISE * math.sqrt(s.shape[0]) * e and not bounded:
            # The step's energy decrease is below E's roundoff, so a line search cannot judge it; the
            # step itself still carries the gradient's information while it contracts, and is noise
            # once it stops contracting.
            if np.isfinite(prev_disp) and not contracting:
                converged, reason = True, StopReason.ROUNDOFF
                break
            s[1:-1] += step[:, 0]
            th[1:-1] += step[:, 1]
            ev = surface.evaluate(s[1:-1], th[1:-1], order=order)
            nfev += 1
        else:
            while True:
                s_try = s.copy()
                th_try = th.copy()
                # 1.0 * x is x: the full step (the usual one) skips the products
                s_try[1:-1] += alpha * step[:, 0] if alpha != 1.0 else step[:, 0]
                th_try[1:-1] += alpha * step[:, 1] if alpha != 1.0 else step[:, 1]
                # A full step is the usual one and is usually accepted: its evaluation then serves the
                # next iteration (with second derivatives unless that one is a chord step or none).
                ev_try = surface.evaluate(s_try[1:-1], th_try[1:-1], order=order if alpha == 1.0 else 0)
                e_try = chain_energy(ev_try.p, ends.p)
                nfev += 1
                if e_try <= e + ARMIJO * alpha * slope or alpha < 1e-12:
                    break
                alpha *= 0.5
            if e_try >= e:
                if -slope <= 1e-13 * e or disp * alpha <= step_tol * h:
                    converged, reason = True, StopReason.ROUNDOFF
                elif bounded and alpha < 1e-9:
                    _raise_left(surface, s)
                break
            s, th, ev = s_try, th_try, ev_try
        if alpha == 1.0 and last:
            converged, reason = True, StopReason.LENGTH if settle else StopReason.STEP
            break
        prev_disp = disp if alpha == 1.0 else np.inf
        factor = factor if chord_next and alpha == 1.0 else None
    interior = s[1:-1]
    if interior.size and (interior.min() <= BOUNDARY_TOL or interior.max() >= s_max - BOUNDARY_TOL):
        _raise_left(surface, s)
    if ev.ps is None:
        ev = surface.evaluate(s[1:-1], th[1:-1], order=1)
    return PathSolve(s, th, it, converged, reason, np.array(history), nfev, ev, ends, factor=factor)


def _raise_left(surface: SweepSurface, s: np.ndarray) -> None:
    # The end it crossed: a path from near one end may run off the other (a cone's small end).
    low = s[1:-1].min() <= BOUNDARY_TOL and not s[1:-1].max() >= surface.length - BOUNDARY_TOL
    edge = "polar opening" if not surface.is_axial_parameter else "end"
    where = f"t = 0 (the first {edge})" if low else f"t = {surface.axial_length:.6g} (the far {edge})"
    raise SolverError(f"the shortest path between these points runs off the mandrel past {where}: no "
                      f"geodesic on the surface joins them with this number of rounds; move the end "
                      f"points away from the edge or change the number of rounds")


