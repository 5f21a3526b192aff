"""The eye's lead: the free-fiber length from a contact point along its fiber direction to the eye
envelope (the rule is in winder.machine.kinematics' module docstring). Pointwise, so the leads of a
whole plan's points are found in one call; a scan brackets each line's first crossing of the
envelope and regula falsi closes the bracket (also for robot poses, around the guide curve)."""

from __future__ import annotations

import numpy as np

from winder.errors import ExportError
from winder.machine.envelope import EyeEnvelope
from winder.geometry.measure import row_norms

MAX_LEAD_FACTOR = 10.0  # the free fiber is at most this times the largest envelope radius
LEAD_SCAN = 32  # samples of the tangent line when bracketing the envelope crossing
ROOT_ITER = 100  # regula falsi (Illinois) steps on the bracket, at most
ROOT_TOL = 1e-10  # mm: the eye's distance from its envelope


def unit_rows(v: np.ndarray) -> np.ndarray:
    n = row_norms(v)
    n = np.where(n > 0.0, n, 1.0)
    return v / n[:, None]


def first_crossing(f, m: int, lmax: float, guess: np.ndarray | None = None,
                   f0: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Smallest lambda in (0, lmax] with f(lambda) = 0 for each of m lines, f(0) < 0 (f vectorized
    over (lambda (k,), line index (k,)), in mm). A scan brackets the first sign change, the Illinois
    variant of regula falsi closes the bracket to ROOT_TOL. Returns (lambda, found); lambda = lmax
    where the line does not reach the envelope.

    guess : (m,) estimates of the crossings, for lines whose f is negative before its crossing and
    not after it (a ray leaving a convex region): the scan's bracket is then the grid interval around
    the guess wherever f changes sign across it, two evaluations instead of the scan up to it (the
    same bracket, so the same lambda); elsewhere the lines are scanned. f0 : (m,) f(0) of every
    line, where the caller has it."""
    grid = lmax * (np.arange(1, LEAD_SCAN + 1) / LEAD_SCAN) ** 2
    lam = np.full(m, lmax)
    lo, hi = np.zeros(m), np.full(m, lmax)
    flo, fhi = np.zeros(m), np.zeros(m)
    found = np.zeros(m, dtype=bool)
    pending = np.arange(m)
    prev_lam, prev_f = 0.0, (f(np.zeros(m), pending) if f0 is None else f0)
    if guess is not None:
        k = np.searchsorted(grid, np.where(np.isfinite(guess), guess, np.inf))  # grid[k - 1] < guess <= grid[k]
        idx = np.flatnonzero(k < LEAD_SCAN)
        k = k[idx]
        below = np.where(k > 0, grid[np.maximum(k - 1, 0)], 0.0)
        f_hi = f(grid[k], idx)
        f_lo = np.where(k > 0, f(below, idx), prev_f[idx])
        hit = (f_hi >= 0.0) & (f_lo < 0.0)
        sel = idx[hit]
        lo[sel], hi[sel], flo[sel], fhi[sel] = below[hit], grid[k[hit]], f_lo[hit], f_hi[hit]
        found[sel] = True
        pending = np.flatnonzero(~found)
        prev_f = prev_f[pending]
    for grid_lam in grid:
        if pending.size == 0:
            break
        val = f(np.full(pending.size, grid_lam), pending)
        hit = val >= 0.0
        sel = pending[hit]
        lo[sel], hi[sel], flo[sel], fhi[sel] = prev_lam, grid_lam, prev_f[hit], val[hit]
        found[sel] = True
        pending, prev_f, prev_lam = pending[~hit], val[~hit], grid_lam
    active = np.flatnonzero(found)
    a, b, fa, fb = lo[active], hi[active], flo[active], fhi[active]
    side = np.zeros(active.size, dtype=np.int8)
    for _ in range(ROOT_ITER):
        if active.size == 0:
            break
        c = np.clip(b - fb * (b - a) / (fb - fa), a, b)
        fc = f(c, active)
        done = (np.abs(fc) <= ROOT_TOL) | (b - a <= ROOT_TOL)
        finished = bool(done.any())  # most steps close no bracket: nothing to store, nothing to drop
        if finished:
            lam[active[done]] = c[done]
        up = fc >= 0.0  # c replaces b (the end with f >= 0), else a
        fa = np.where(up & (side == 1), 0.5 * fa, np.where(up, fa, fc))
        fb = np.where(~up & (side == -1), 0.5 * fb, np.where(up, fc, fb))
        a, b = np.where(up, a, c), np.where(up, c, b)
        side = np.where(up, 1, -1).astype(np.int8)
        if finished:
            keep = ~done
            active, a, b, fa, fb, side = active[keep], a[keep], b[keep], fa[keep], fb[keep], side[keep]
    lam[active] = b  # not converged within ROOT_ITER steps: the bracket's end with f >= 0
    return lam, found


def _cylinder_lead(p: np.ndarray, d: np.ndarray, r0: np.ndarray, radius) -> np.ndarray:
    """lambda > 0 putting p + lambda d (m, 3) on the cylinder of the given radius (m,) or () around the z
    axis, r0 = |p_xy| < radius; inf or nan where the line runs along the axis."""
    a = d[:, 0] ** 2 + d[:, 1] ** 2
    b = p[:, 0] * d[:, 0] + p[:, 1] * d[:, 1]
    c = r0**2 - radius * radius  # < 0: p is inside the cylinder, so exactly one positive root
    # The root (-b + sqrt(b^2 - a c)) / a, in the form without cancellation for either sign of b
    # (b < 0: the fiber heads toward the axis, as toward a dome's pole).
    root = np.sqrt(b * b - a * c)
    return np.where(b >= 0.0, -c / (b + root), (root - b) / a)


def lead_straight(p: np.ndarray, d: np.ndarray, env: EyeEnvelope,
                   where: str) -> tuple[np.ndarray, np.ndarray]:
    """lambda putting p + lambda d on the envelope around the z axis; (lead, on_envelope)."""
    m = p.shape[0]
    lmax = MAX_LEAD_FACTOR * env.max_radius
    r0 = np.hypot(p[:, 0], p[:, 1])
    at_p = env.at(p[:, 2])
    inside = r0 < at_p
    if not inside.all():
        k = int(np.argmin(inside))
        raise ExportError(f"{where}: the eye envelope (radius {float(env.at(p[k:k+1, 2])[0]):.3f} mm) does "
                          f"not clear the mandrel at t = {p[k, 2]:.3f} mm (fiber at radius {r0[k]:.3f} mm)")
    if env.constant is not None:
        with np.errstate(divide="ignore", invalid="ignore"):
            lam = _cylinder_lead(p, d, r0, env.constant)
        ok = np.isfinite(lam) & (lam > 0.0) & (lam <= lmax)
        return np.where(ok, lam, lmax), ok

    cols = (*p.T, *d.T)  # gathered per column: fancy indexing rows of (m, 3) costs more than the rest of f

    def f(lam: np.ndarray, i: np.ndarray) -> np.ndarray:
        px, py, pz, dx, dy, dz = cols if i.size == m else (c[i] for c in cols)  # i: sorted line indices
        return np.hypot(px + lam * dx, py + lam * dy) - env.at(pz + lam * dz)

    # The region inside the envelope is convex (its profile concave), so the guess may bracket: the
    # crossing with the cylinder of the envelope's radius where that one would be crossed.
    with np.errstate(divide="ignore", invalid="ignore"):
        guess = _cylinder_lead(p, d, r0, at_p)
        guess = _cylinder_lead(p, d, r0, env.at(p[:, 2] + np.where(np.isfinite(guess), guess, 0.0) * d[:, 2]))
    return first_crossing(f, m, lmax, guess, r0 - at_p)  # f(0): p + 0 d is p


def eye_leads(points: np.ndarray, directions: np.ndarray, envelope: EyeEnvelope,
              where: str = "eye path") -> tuple[np.ndarray, np.ndarray]:
    """The lead lambda (m,) of every contact point (m, 3) along its fiber direction (m, 3) to the
    eye's envelope, and whether it reaches it (m,) bool: pointwise, so a whole plan's points can go in
    one call (eye_path's lead argument) instead of one scan per pass."""
    p = np.asarray(points, dtype=float).reshape(-1, 3)
    return lead_straight(p, unit_rows(np.asarray(directions, dtype=float).reshape(-1, 3)), envelope, where)
