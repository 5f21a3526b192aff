"""The exact geodesic over an ellipsoidal (or hemispherical) dome from the ellipse's own equation and
Clairaut's relation, by quadrature (docs/math/12-exact-eye.md, 12.1): an independent reference for
the programmed eye, built from neither winder's profile interpolant nor its paths. Also the reader of
a written generic program's eye points, pass by pass."""

from __future__ import annotations

import dataclasses
import functools
import re

import numpy as np
from scipy.integrate import solve_ivp
from scipy.interpolate import CubicHermiteSpline

QUAD_TOL = 1e-12  # solve_ivp's rtol = atol for Theta(v)
GRID = 1201  # even reads of v over the dome before the golden-section refinement
GOLDEN_STEPS = 40  # golden-section steps between a grid minimum's neighbours (0.618^40 of 2 steps: 1e-11)
CANDIDATES = 4  # grid minima refined per eye
CANDIDATE_MM = 1.0  # a grid minimum this close to the grid's least is refined too (a grid step moves
# the tangent line of an eye 200 mm out by well under a millimetre)
TABLE = 4097  # quadrature reads of Theta(v), cubic Hermite between them with the exact rate (error ~1e-14)
PASS_LINE = re.compile(r"^; layer (\d+) circuit (\d+) pass (\d+) (\w+)")
WORD = re.compile(r"([XAZB])(-?\d+(?:\.\d*)?)")


@dataclasses.dataclass(frozen=True)
class DomeGeodesic:
    """The geodesic r sin(alpha) = c over one dome: r = R cos(psi), z = z_e + side d sin(psi),
    psi = psi_c - v^2, theta = theta_t + sigma sign(v) Theta(|v|), v in [-sqrt(psi_c), sqrt(psi_c)]."""

    radius: float
    depth: float  # the ellipse's axial semi-axis d
    z_e: float  # the equator's z
    side: float  # +1: the dome beyond the equator (z > z_e), -1: before it
    c: float
    sigma: float
    theta_t: float
    theta: object  # scipy OdeSolution of Theta(v), v >= 0

    @property
    def psi_c(self) -> float:
        return float(np.arccos(self.c / self.radius))

    def at(self, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(points (n, 3), unit tangents (n, 3)) at v (n,)."""
        v = np.asarray(v, dtype=float)
        R, d = self.radius, self.depth
        psi = self.psi_c - v * v
        big = self.theta(np.abs(v))[0]
        th = self.theta_t + self.sigma * np.sign(v) * big
        r = R * np.cos(psi)
        p = np.column_stack([r * np.cos(th), r * np.sin(th), self.z_e + self.side * d * np.sin(psi)])
        dr = 2.0 * v * R * np.sin(psi)
        dz = -self.side * 2.0 * v * d * np.cos(psi)
        dth = self.sigma * theta_rate(np.abs(v), R, d, self.c)
        t = np.column_stack([dr * np.cos(th) - r * np.sin(th) * dth, dr * np.sin(th) + r * np.cos(th) * dth, dz])
        return p, t / np.linalg.norm(t, axis=1)[:, None]

    def canonical(self) -> DomeGeodesic:
        """The same geodesic turned to theta_t = 0 and wound in the + sense (sigma = 1)."""
        return dataclasses.replace(self, theta_t=0.0, sigma=1.0)

    def to_canonical(self, eye: np.ndarray) -> np.ndarray:
        """Eyes (k, 3) moved with this geodesic onto canonical()'s: turned by -theta_t about the axis,
        mirrored in the plane theta = 0 where sigma is -1 (distances kept)."""
        co, si = np.cos(self.theta_t), np.sin(self.theta_t)
        x = co * eye[:, 0] + si * eye[:, 1]
        y = -si * eye[:, 0] + co * eye[:, 1]
        return np.column_stack([x, self.sigma * y, eye[:, 2]])

    def distance(self, eye: np.ndarray) -> np.ndarray:
        """Each eye's (k, 3) distance from the nearest tangent line of this geodesic (k,): every local
        minimum of an even grid of v within CANDIDATE_MM of the grid's least (up to CANDIDATES of them:
        where two tangencies nearly meet, the grid's least need not be next to the true one), each
        refined by golden section between its grid neighbours."""
        top = np.sqrt(self.psi_c)
        grid = np.linspace(-top, top, GRID)
        p, t = self.at(grid)
        k = eye.shape[0]
        near = np.zeros((k, CANDIDATES), dtype=int)
        for rows in np.array_split(np.arange(k), max(1, k // 64)):  # (64, GRID, 3) at a time
            dist = _line_distance(eye[rows, None, :] - p[None], t[None])
            inner = (dist[:, 1:-1] <= dist[:, :-2]) & (dist[:, 1:-1] <= dist[:, 2:])
            local = np.full(dist.shape, np.inf)
            local[:, 1:-1] = np.where(inner, dist[:, 1:-1], np.inf)
            local[:, [0, -1]] = dist[:, [0, -1]]
            local[local > dist.min(axis=1, keepdims=True) + CANDIDATE_MM] = np.inf
            pick = np.argsort(local, axis=1)[:, :CANDIDATES]
            # Left-over picks (fewer minima than CANDIDATES) repeat the best one.
            ok = np.isfinite(np.take_along_axis(local, pick, axis=1))
            near[rows] = np.where(ok, pick, pick[:, :1])
        lo = grid[np.maximum(near - 1, 0)].reshape(-1)
        hi = grid[np.minimum(near + 1, GRID - 1)].reshape(-1)
        many = np.repeat(eye, CANDIDATES, axis=0)
        golden = (np.sqrt(5.0) - 1.0) / 2.0

        def dist_at(v: np.ndarray) -> np.ndarray:
            pp, tt = self.at(v)
            return _line_distance(many - pp, tt)

        for _ in range(GOLDEN_STEPS):
            a = hi - golden * (hi - lo)
            b = lo + golden * (hi - lo)
            left = dist_at(a) < dist_at(b)
            hi = np.where(left, b, hi)
            lo = np.where(left, lo, a)
        return dist_at(0.5 * (lo + hi)).reshape(k, CANDIDATES).min(axis=1)


def _line_distance(a: np.ndarray, t: np.ndarray) -> np.ndarray:
    """|a x t| for unit t along the last axis: sqrt(|a|^2 - (a . t)^2)."""
    along = np.einsum("...i,...i->...", a, t)
    return np.sqrt(np.maximum(np.einsum("...i,...i->...", a, a) - along * along, 0.0))


def theta_rate(v: np.ndarray, radius: float, depth: float, c: float) -> np.ndarray:
    """|dtheta/dv| on the dome (12.1), regular at the turnaround v = 0."""
    psi_c = np.arccos(c / radius)
    psi = psi_c - v * v
    x = 0.5 * v * v
    sinc = np.sinc(x / np.pi)  # sin(x) / x
    dm = np.sqrt((radius * np.sin(psi)) ** 2 + (depth * np.cos(psi)) ** 2)
    r = radius * np.cos(psi)
    return 2.0 * c * dm / (r * radius * np.sqrt(np.sin(0.5 * (psi + psi_c)) * (np.cos(psi) + np.cos(psi_c)) * sinc))


@functools.lru_cache(maxsize=64)
def theta_quadrature(radius: float, depth: float, c: float) -> CubicHermiteSpline:
    """Theta(v) = integral of theta_rate from 0: solve_ivp read at TABLE even v, cubic Hermite in
    between with theta_rate as the derivative (called with (v,), returns (1, n) like an OdeSolution)."""
    top = np.sqrt(np.arccos(c / radius))
    grid = np.linspace(0.0, top, TABLE)
    sol = solve_ivp(lambda v, y: theta_rate(np.asarray(v), radius, depth, c), (0.0, top), [0.0],
                    method="DOP853", rtol=QUAD_TOL, atol=QUAD_TOL, t_eval=grid)
    assert sol.success, sol.message
    return CubicHermiteSpline(grid, sol.y, theta_rate(grid, radius, depth, c)[None, :], axis=1)


def fit_dome(pts: np.ndarray, radius: float, depth: float, z_e: float, side: float, c: float,
             form_tol: float) -> DomeGeodesic:
    """The dome geodesic through a pass's points on one dome (ordered along the pass): theta_t the
    one constant fitted; every point checked on the ellipse and on the curve within form_tol (mm)."""
    r = np.hypot(pts[:, 0], pts[:, 1])
    psi = np.arcsin(np.clip(side * (pts[:, 2] - z_e) / depth, -1.0, 1.0))
    on_ellipse = np.abs(r - radius * np.cos(psi))
    assert on_ellipse.max() < form_tol, f"plan point {on_ellipse.max():.2e} mm off the ellipse"
    psi_c = np.arccos(c / radius)
    v = np.sqrt(np.maximum(psi_c - psi, 0.0))
    theta = theta_quadrature(radius, depth, round(c, 9))  # one quadrature per layer and dome
    big = theta(v)[0]
    th = np.unwrap(np.arctan2(pts[:, 1], pts[:, 0]))
    sigma = 1.0 if th[-1] >= th[0] else -1.0
    turn = int(np.argmax(psi))
    if np.count_nonzero(psi) and (turn == 0 or turn == pts.shape[0] - 1):
        # The pass starts (ends) at or near the turnaround: it is all the way out (in).
        branch = np.full(pts.shape[0], 1.0 if turn == 0 else -1.0)
    else:
        branch = np.where(np.arange(pts.shape[0]) < turn, -1.0, 1.0)
    guess = th - sigma * branch * big
    ref = np.median(guess)
    wrap = lambda a: (a + np.pi) % (2.0 * np.pi) - np.pi  # noqa: E731
    # The point nearest the turnaround may sit on either side of it: take the branch that fits.
    other = th - sigma * -branch * big
    guess = np.where(np.abs(wrap(other - ref)) < np.abs(wrap(guess - ref)), other, guess)
    theta_t = ref + float(np.median(wrap(guess - ref)))
    miss = np.abs(wrap(guess - theta_t)) * r
    assert miss.max() < form_tol, f"plan point {miss.max():.2e} mm off the Clairaut geodesic (c = {c:.4f})"
    return DomeGeodesic(radius, depth, z_e, side, c, sigma, theta_t, theta)


def program_eyes(text: str, layer: int) -> list[np.ndarray]:
    """Each pass's programmed (X, A, Z, B) rows (n, 4) of one layer, read from a generic program's text
    (a pass's block starts at its `; layer L circuit C pass P kind` line; approach blocks left out)."""
    passes: list[list[list[float]]] = []
    current: list[list[float]] | None = None
    last = [np.nan] * 4
    for line in text.splitlines():
        head = PASS_LINE.match(line)
        if head:
            keep = int(head.group(1)) == layer and head.group(4) != "approach"
            current = [] if keep else None
            if keep:
                passes.append(current)
            continue
        if line.startswith(("G0", "G1")):
            words = dict(WORD.findall(line))
            last = [float(words[a]) if a in words else last[i] for i, a in enumerate("XAZB")]
            if current is not None:
                current.append(list(last))
    return [np.asarray(p, dtype=float).reshape(-1, 4) for p in passes]
