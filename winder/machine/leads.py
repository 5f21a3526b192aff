"""The eye's lead: the free-fiber length from a contact point along its fiber direction to the eye
envelope (the rule is in winder.machine.kinematics' module docstring). Pointwise, so the leads of a
whole plan's points are found in one call. Around a straight axis, Newton steps (the envelope is
piecewise linear, so its slope is exact) start from the crossing of the envelope's cylinder, which is
mostly within ROOT_TOL already; a scan brackets the lines it fails on. The envelope is round about
the axis, so a contact point and direction turned about it (a helical layer's circuits) have the same
lead: lines that agree about the axis within SAME_LINE are solved once. For robot poses, around the
guide curve, the scan's brackets are closed by regula falsi."""

from __future__ import annotations

import numpy as np

from winder.errors import ExportError
from winder.machine.envelope import EyeEnvelope
from winder.geometry.measure import grid_groups, row_norms

MAX_LEAD_FACTOR = 10.0  # the free fiber is at most this times the largest envelope radius
LEAD_SCAN = 32  # samples of the tangent line when bracketing the envelope crossing
ROOT_ITER = 100  # regula falsi (Illinois) steps on the bracket, at most
ROOT_TOL = 1e-10  # mm: the eye's distance from its envelope
SAME_LINE = 1e-10  # mm (radius, station) and unit-vector components: lines solved once (lead_straight)


def unit_rows(v: np.ndarray) -> np.ndarray:
    n = row_norms(v)
    n = np.where(n > 0.0, n, 1.0)
    return v / n[:, None]


def first_crossing(f, m: int, lmax: float, guess: np.ndarray | None = None,
                   f0: np.ndarray | None = None, fd=None) -> tuple[np.ndarray, np.ndarray]:
    """Smallest lambda in (0, lmax] with f(lambda) = 0 for each of m lines, f(0) < 0 (f vectorized
    over (lambda (k,), line index (k,)), in mm). A scan brackets the first sign change and the
    bracket is closed to ROOT_TOL. Returns (lambda, found); lambda = lmax where the line does not
    reach the envelope.

    fd : (lambda (k,), index (k,)) -> (f, df/dlambda), both (k,), where the caller has the slope: the
    brackets are then closed by Newton steps kept inside them (else by the Illinois variant of regula
    falsi). guess : (m,) estimates of the crossings (with fd), for lines whose f is negative before
    its crossing and not after it (a ray leaving a convex region): Newton starts there, and the sign
    of f at the guess is a bracket with 0 or with the next step, so those lines need no scan; lines
    it fails on are scanned. f0 : (m,) f(0) of every line, where the caller has it."""
    lam = np.full(m, lmax)
    found = np.zeros(m, dtype=bool)
    f0 = f(np.zeros(m), np.arange(m)) if f0 is None else f0
    pending = np.arange(m)
    if guess is not None and fd is not None:
        idx = np.flatnonzero(np.isfinite(guess) & (guess > 0.0) & (guess <= lmax))
        g = guess[idx]
        v, s = fd(g, idx)
        up = v >= 0.0  # the crossing lies in (0, g], else past g (and below lmax if Newton finds it)
        lost = _newton(fd, lam, idx, g, v, s, np.where(up, 0.0, g), np.where(up, g, lmax),
                       np.where(up, f0[idx], v), np.where(up, v, np.nan))
        found[idx] = True
        found[lost] = False
        pending = np.flatnonzero(~found)
    grid = lmax * (np.arange(1, LEAD_SCAN + 1) / LEAD_SCAN) ** 2
    lo, hi = np.zeros(m), np.full(m, lmax)
    flo, fhi = np.zeros(m), np.zeros(m)
    scanned = np.zeros(m, dtype=bool)
    prev_lam, prev_f = 0.0, f0[pending]
    for grid_lam in grid:
        if pending.size == 0:
            break
        val = f(np.full(pending.size, grid_lam), pending)
        hit = val >= 0.0
        sel = pending[hit]
        lo[sel], hi[sel], flo[sel], fhi[sel] = prev_lam, grid_lam, prev_f[hit], val[hit]
        scanned[sel] = True
        pending, prev_f, prev_lam = pending[~hit], val[~hit], grid_lam
    active = np.flatnonzero(scanned)
    found |= scanned
    a, b, fa, fb = lo[active], hi[active], flo[active], fhi[active]
    if fd is None or active.size == 0:
        _illinois(f, lam, active, a, b, fa, fb)
        return lam, found
    with np.errstate(divide="ignore", invalid="ignore"):
        c = np.clip(b - fb * (b - a) / (fb - fa), a, b)  # the bracket's secant point starts Newton
    v, s = fd(c, active)
    up = v >= 0.0
    _newton(fd, lam, active, c, v, s, np.where(up, a, c), np.where(up, c, b), np.where(up, fa, v),
            np.where(up, v, fb))
    return lam, found


def _newton(fd, lam: np.ndarray, act: np.ndarray, x: np.ndarray, fx: np.ndarray, sx: np.ndarray,
            a: np.ndarray, b: np.ndarray, fa: np.ndarray, fb: np.ndarray) -> np.ndarray:
    """Newton steps on the lines act (k,) from x (f there fx, slope sx), each kept inside its bracket
    [a, b] (f(a) = fa < 0 <= fb = f(b)), bisecting where a step leaves it; the roots go to lam in
    place. fb nan: no end with f >= 0 known yet (b an upper limit only), so a step leaving [a, b]
    cannot be replaced: those lines are returned (sorted indices) for the caller to scan."""
    lost = []
    for _ in range(ROOT_ITER):
        done = (np.abs(fx) <= ROOT_TOL) | (b - a <= ROOT_TOL)
        if done.any():
            lam[act[done]] = x[done]
            keep = ~done
            act, x, fx, sx, a, b, fa, fb = (u[keep] for u in (act, x, fx, sx, a, b, fa, fb))
        if act.size == 0:
            break
        with np.errstate(divide="ignore", invalid="ignore"):
            c = x - fx / sx
        inside = (c > a) & (c < b)  # false for nan steps (a zero slope)
        stuck = ~inside & np.isnan(fb)
        if stuck.any():
            lost.append(act[stuck])
            keep = ~stuck
            act, c, inside, a, b, fa, fb = (u[keep] for u in (act, c, inside, a, b, fa, fb))
        x = np.where(inside, c, 0.5 * (a + b))
        fx, sx = fd(x, act)
        up = fx >= 0.0
        a, fa = np.where(up, a, x), np.where(up, fa, fx)
        b, fb = np.where(up, x, b), np.where(up, fx, fb)
    known = ~np.isnan(fb)  # not converged within ROOT_ITER steps: the bracket's end with f >= 0
    lam[act[known]] = b[known]
    lost.append(act[~known])
    return np.sort(np.concatenate(lost))


def _illinois(f, lam: np.ndarray, active: np.ndarray, a: np.ndarray, b: np.ndarray, fa: np.ndarray,
              fb: np.ndarray) -> None:
    """The Illinois variant of regula falsi on the brackets [a, b] (k,) of the lines active (k,),
    f(a) = fa < 0 <= fb = f(b), to ROOT_TOL; the roots go to lam in place."""
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
    # Each line as seen from the axis: radius, station, and the direction's radial, turning and
    # axial parts (module docstring).
    safe = np.where(r0 > 0.0, r0, 1.0)
    radial, turning = (p[:, 0] * d[:, 0] + p[:, 1] * d[:, 1]) / safe, (p[:, 0] * d[:, 1] - p[:, 1] * d[:, 0]) / safe
    keys = np.column_stack([r0, p[:, 2], radial, turning, d[:, 2]])
    first, group = grid_groups(np.where(np.isfinite(keys), keys, 0.0), SAME_LINE)
    if first.size == m:
        return _lead_on_table(p, d, env, lmax, r0, at_p)
    lam, ok = _lead_on_table(p[first], d[first], env, lmax, r0[first], at_p[first])
    return lam[group], ok[group]


def _lead_on_table(p: np.ndarray, d: np.ndarray, env: EyeEnvelope, lmax: float, r0: np.ndarray,
                   at_p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """lead_straight on a tabulated envelope: p, d (m, 3), r0 and at_p (m,) the points' radii and
    the envelope's radius at their stations."""
    m = p.shape[0]
    cols = (*p.T, *d.T)  # gathered per column: fancy indexing rows of (m, 3) costs more than the rest of f
    # A level table (a cylinder's clearance) is its one value at every finite station, with slope 0:
    # the same numbers without the table look-ups (finite points and directions keep the stations finite).
    level = env.level if np.isfinite(p).all() and np.isfinite(d).all() else None

    def f(lam: np.ndarray, i: np.ndarray) -> np.ndarray:
        px, py, pz, dx, dy, dz = cols if i.size == m else (c[i] for c in cols)  # i: sorted line indices
        r = np.hypot(px + lam * dx, py + lam * dy)
        return r - level if level is not None else r - env.at(pz + lam * dz)

    def fd(lam: np.ndarray, i: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        px, py, pz, dx, dy, dz = cols if i.size == m else (c[i] for c in cols)
        x, y = px + lam * dx, py + lam * dy
        r = np.hypot(x, y)
        if level is not None:
            at, slope = level, 0.0
        else:
            z = pz + lam * dz
            at, slope = env.at(z), env.slope(z)
        with np.errstate(divide="ignore", invalid="ignore"):  # r = 0: a nan slope, no Newton step
            return r - at, (x * dx + y * dy) / r - slope * dz

    # The region inside the envelope is convex (its profile concave), so the guess may bracket: the
    # crossing with the cylinder of the envelope's radius where that one would be crossed.
    with np.errstate(divide="ignore", invalid="ignore"):
        guess = _cylinder_lead(p, d, r0, at_p)
        if level is None:  # else the envelope's radius there is at_p's own
            guess = _cylinder_lead(p, d, r0, env.at(p[:, 2] + np.where(np.isfinite(guess), guess, 0.0) * d[:, 2]))
    return first_crossing(f, m, lmax, guess, r0 - at_p, fd)  # f(0): p + 0 d is p


def eye_leads(points: np.ndarray, directions: np.ndarray, envelope: EyeEnvelope,
              where: str = "eye path") -> tuple[np.ndarray, np.ndarray]:
    """The lead lambda (m,) of every contact point (m, 3) along its fiber direction (m, 3) to the
    eye's envelope, and whether it reaches it (m,) bool: pointwise, so a whole plan's points can go in
    one call (eye_path's lead argument) instead of one scan per pass."""
    p = np.asarray(points, dtype=float).reshape(-1, 3)
    return lead_straight(p, unit_rows(np.asarray(directions, dtype=float).reshape(-1, 3)), envelope, where)
