"""A liner's dome from a drawing's points (docs/math/17-vessels-as-built.md 17.1).

fit_contour: a parametric quintic P-spline (Eilers and Marx 1996: B-spline least squares with a
third-difference penalty on the coefficients) in the chord length u, with x(0) = (0, R), r'(0) = 0 (the
dome leaves the cylinder tangentially) and the last point held exactly; its penalty is the largest (by
bisection on log lambda) whose fit stays within the tolerance of every point. ContourDome then
re-parametrizes it by its own arc length as C2 quintic Hermite pieces through exact values, unit tangents
and curvatures (the isotensoid's and the grown domes' representation), trimmed at the opening radius.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from winder.geometry.domes import DomeMeridian, _quintic_hermite, table_grid, with_derivatives

DEGREE = 5
MAX_INTERVALS = 400  # knot intervals of the fit (every other point up to this)
LAMBDA_GRID = np.linspace(-14.0, 6.0, 21)  # log10 of the penalty relative to the data's normal matrix
BISECTIONS = 20
SCATTER_REACH = 4.0  # the smoothing stops where a point is this many scatter deviations off
KNOT_SPACING = 0.25  # mm: the arc-length table's spacing (plus the fit's own knots)
MAX_TABLE = 40_000
FOLD_SLOPE = 1e-9  # r' above this (per unit arc) after the fit: the smoothed meridian rises


class ContourError(ValueError):
    """The smoothed contour is not a dome: index of the nearest point and what is wrong."""

    def __init__(self, index: int, what: str):
        super().__init__(what)
        self.index = index


@dataclasses.dataclass(frozen=True, eq=False)
class ContourFit:
    """The fitted meridian: spline (z, r) of the chord length u in [0, u_end]; deviation: the largest
    distance (mm) of the fit from a point; lam: the penalty used (relative)."""

    spline: object
    u_end: float
    deviation: float
    lam: float
    u_points: np.ndarray


def _basis(u: np.ndarray, count: int):
    from scipy.interpolate import BSpline  # noqa: PLC0415 - contour domes only

    inner = np.quantile(u, np.linspace(0.0, 1.0, count + 1)[1:-1]) if count > 1 else np.zeros(0)
    knots = np.concatenate([np.full(DEGREE + 1, u[0]), inner, np.full(DEGREE + 1, u[-1])])
    return knots, BSpline.design_matrix(u, knots, DEGREE).toarray()


def fit_contour(points: np.ndarray, tolerance: float) -> ContourFit:
    """The smoothed meridian through points (n, 2) as (z, r) (module docstring). The penalty is the one
    of least generalized cross-validation score (Craven and Wahba 1979) over LAMBDA_GRID, lowered by
    bisection while the fit is farther than the tolerance from a point: points sampled from a smooth
    curve get almost none, a digitized contour as much as its scatter asks within the tolerance. Raises
    ContourError where even the least penalty cannot follow the points within the tolerance."""
    from scipy.interpolate import BSpline  # noqa: PLC0415
    from scipy.linalg import cho_factor, cho_solve  # noqa: PLC0415

    p = np.asarray(points, dtype=float)
    u = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(p, axis=0).T))])
    count = int(min(MAX_INTERVALS, max(1, (p.shape[0] - 1) // 2)))
    knots, a = _basis(u, count)
    nc = a.shape[1]
    d3 = np.diff(np.eye(nc), 3, axis=0)
    ata, dtd = a.T @ a, d3.T @ d3
    scale = np.trace(ata) / max(np.trace(dtd), 1e-300)
    # Held coefficients (clamped ends): z_0 = 0, z_last; r_0 = R, r_1 = R (r'(0) = 0), r_last.
    fixed = ({0: 0.0, nc - 1: p[-1, 0]}, {0: p[0, 1], 1: p[0, 1], nc - 1: p[-1, 1]})

    def solve(log_lam: float) -> tuple[np.ndarray, float]:
        """Coefficients (nc, 2) and the fit's effective number of parameters (trace of the hat matrix)."""
        coef, dof = np.empty((nc, 2)), 0.0
        m = ata + 10.0**log_lam * scale * dtd
        for j in range(2):
            held = np.array(sorted(fixed[j]))
            free = np.setdiff1d(np.arange(nc), held)
            vals = np.array([fixed[j][i] for i in held])
            rhs = a.T @ p[:, j] - m[:, held] @ vals
            factor = cho_factor(m[np.ix_(free, free)])
            coef[held, j] = vals
            coef[free, j] = cho_solve(factor, rhs[free])
            dof += float(np.trace(cho_solve(factor, ata[np.ix_(free, free)])))
        return coef, dof

    def off(coef: np.ndarray) -> np.ndarray:
        return np.hypot(*(a @ coef - p).T)

    n = 2 * p.shape[0]
    scores = []
    for log_lam in LAMBDA_GRID:
        coef, dof = solve(log_lam)
        rss = float(np.sum((a @ coef - p) ** 2))
        scores.append((n * rss / max(n - dof, 1.0) ** 2, log_lam, coef, rss / max(n - dof, 1.0)))
    _, lam, best, var = min(scores, key=lambda x: x[0])
    dev = off(best)
    # The scatter GCV found (its residual's standard deviation per coordinate) is smoothed away until
    # the largest distance from a point reaches SCATTER_REACH of it (the extreme of that many scattered
    # points), never past the tolerance: the curvature, two derivatives below the points, needs more
    # smoothing than the positions GCV weighs. Points on a smooth curve have no scatter to remove.
    target = min(tolerance, SCATTER_REACH * math.sqrt(var))
    if dev.max() > tolerance:
        target, lo, hi = tolerance, LAMBDA_GRID[0], lam
        best, _ = solve(lo)
        dev = off(best)
        if dev.max() > tolerance:
            i = int(np.argmax(dev))
            raise ContourError(i, f"the smooth meridian cannot follow the contour within the tolerance there "
                                  f"(off by {dev[i]:.3g} mm): a corner sharper than the points' spacing; round "
                                  f"it in the drawing or raise tolerance")
        lam = lo
    else:
        lo, hi = lam, LAMBDA_GRID[-1]
    if dev.max() < target:
        for _ in range(BISECTIONS):
            mid = 0.5 * (lo + hi)
            coef, _ = solve(mid)
            d = off(coef)
            if d.max() <= target:
                lo, best, dev, lam = mid, coef, d, mid
            else:
                hi = mid
    return ContourFit(BSpline(knots, best, DEGREE), float(u[-1]), float(dev.max()), 10.0**lam, u)


class ContourDome(DomeMeridian):
    """A dome through a contour's points, trimmed at the opening radius r0 (the last point's radius if
    None). Raises ContourError where the smoothed meridian does not fall toward the pole."""

    kind = "contour"

    def __init__(self, radius: float, points: np.ndarray, tolerance: float, r0: float | None = None):
        fit = fit_contour(points, tolerance)
        self.fit = fit
        spl = fit.spline
        u_end = fit.u_end
        if r0 is not None and float(spl(u_end)[1]) < r0 - 1e-12:
            from scipy.optimize import brentq  # noqa: PLC0415

            grid = np.linspace(0.0, u_end, 4001)
            r = spl(grid)[:, 1]
            j = int(np.argmax(r <= r0))
            u_end = brentq(lambda x: float(spl(x)[1]) - r0, grid[max(j - 1, 0)], grid[j], xtol=1e-13)
        inner = spl.t[(spl.t > 0.0) & (spl.t < u_end)]
        grid = table_grid(0.0, u_end, max(min(KNOT_SPACING, u_end / 64.0), u_end / MAX_TABLE), inner)
        d1, d2 = spl(grid, 1), spl(grid, 2)
        speed = np.hypot(d1[:, 0], d1[:, 1])
        self._refuse_folds(fit, grid, d1)
        psi = np.arctan2(d1[:, 1], d1[:, 0])
        psi[0] = 0.0
        k = (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / speed**3
        xg, wg = np.polynomial.legendre.leggauss(8)
        half = 0.5 * np.diff(grid)
        q = spl((grid[:-1, None] + half[:, None] * (xg + 1.0)).ravel(), 1)
        v = np.hypot(q[:, 0], q[:, 1]).reshape(-1, 8)
        sig = np.concatenate([[0.0], np.cumsum((v * wg).sum(axis=1) * half)])
        pos = spl(grid)
        H, Rr = pos[:, 0] - pos[0, 0], pos[:, 1]
        H[0], Rr[0] = 0.0, radius
        c, s = np.cos(psi), np.sin(psi)
        self._pp = with_derivatives([_quintic_hermite(sig, H, c, -s * k), _quintic_hermite(sig, Rr, s, c * k)])
        self.radius, self.semi_axis = float(radius), None
        self.length, self.depth = float(sig[-1]), float(H[-1])
        self.end_radius = float(Rr[-1])
        self.polar_opening = self.end_radius
        self.deviation = fit.deviation
        self._tab_sigma, self._tab_h = sig, H

    @staticmethod
    def _refuse_folds(fit: ContourFit, grid: np.ndarray, d1: np.ndarray) -> None:
        """The smoothed meridian must keep moving toward the pole (z' > 0) with r never rising."""
        speed = np.hypot(d1[:, 0], d1[:, 1])
        bad = (d1[:, 1] / speed > FOLD_SLOPE) | (d1[:, 0] <= 0.0)
        bad[0] = False  # r' = 0 there by construction
        if np.any(bad):
            j = int(np.argmax(bad))
            i = int(np.argmin(np.abs(fit.u_points - grid[j])))
            what = "turns back toward the equator" if d1[j, 0] <= 0.0 else "rises toward the pole"
            raise ContourError(i, f"the smoothed contour {what} near this point (the dome folds); the points "
                                  f"must fall steadily from the cylinder to the opening")

    def _eval2(self, sigma: np.ndarray, u: np.ndarray) -> tuple[np.ndarray, ...]:
        h, h1, h2, r, r1, r2 = self._pp(np.asarray(sigma, dtype=float)).T
        return (self.depth - h, h, h1, h2, r, r1, r2)
