"""Baselines that winder is measured against, all on winder's own surface code where they can be.

- collocation: scipy.integrate.solve_bvp on the geodesic ODE (docs/math/04-checks.md), fixed end points,
  parametrized by a normalized parameter tau in [0, 1]; the length is a fifth ODE component
  (L' = |J u'|, L(0) = 0), so the solver's error control covers it.
- mesh: the surface triangulated on a regular (s, theta) grid (trimesh), then potpourri3d's
  edge-flip geodesic (Sharp & Crane) seeded with a vertex chain that winds the path's rounds.
- LO (the paper's "length optimization" baseline, its ref. [20]): minimize the polyline's total
  length sum |y_{i+1} - y_i| directly with L-BFGS-B and its analytic gradient.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Callable

import numpy as np
from scipy.integrate import solve_bvp
from scipy.optimize import minimize

from winder.geometry.surface import SweepSurface

TWO_PI = 2.0 * np.pi


# -- collocation ------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class BvpResult:
    length: float
    status: int  # solve_bvp's: 0 converged, 1 node limit, 2 singular Jacobian, 3 tolerance below roundoff
    nodes: int
    message: str


def bvp_nodes(rounds: int) -> int:
    """Initial collocation nodes: 10 plus 8 per round swept."""
    return 10 + 8 * (abs(rounds) + 1)


def bvp_geodesic(surface: SweepSurface, start: tuple[float, float], end: tuple[float, float], rounds: int,
                 tol: float, max_nodes: int = 50_000) -> BvpResult:
    """The geodesic from start to end ((s, theta), end angle + 2 pi rounds) by solve_bvp.

    State y = (s, theta, s', theta', L) over tau in [0, 1]; the geodesic equation is invariant under
    affine reparametrization, so u'' = -g^{-1} J^T (Phi_ss s'^2 + 2 Phi_st s' theta' + Phi_tt theta'^2)
    holds in tau as in arc length. Initial guess: the straight segment in the parameter domain.
    solve_bvp's Jacobians are its default finite differences (what a user would start from).
    """
    s0, th0 = start
    s1, th1 = end[0], end[1] + TWO_PI * rounds
    tau = np.linspace(0.0, 1.0, bvp_nodes(rounds))
    ds, dth = s1 - s0, th1 - th0

    def fun(_x: np.ndarray, y: np.ndarray) -> np.ndarray:
        ev = surface.evaluate(y[0], y[1], order=2)
        u1, u2 = y[2][:, None], y[3][:, None]
        acc = ev.pss * (u1 * u1) + 2.0 * ev.pst * (u1 * u2) + ev.ptt * (u2 * u2)
        b0 = -np.einsum("ij,ij->i", ev.ps, acc)
        b1 = -np.einsum("ij,ij->i", ev.pt, acc)
        g00 = np.einsum("ij,ij->i", ev.ps, ev.ps)
        g01 = np.einsum("ij,ij->i", ev.ps, ev.pt)
        g11 = np.einsum("ij,ij->i", ev.pt, ev.pt)
        det = g00 * g11 - g01 * g01
        vel = ev.ps * u1 + ev.pt * u2
        return np.vstack([y[2], y[3], (g11 * b0 - g01 * b1) / det, (g00 * b1 - g01 * b0) / det,
                          np.sqrt(np.einsum("ij,ij->i", vel, vel))])

    def bc(ya: np.ndarray, yb: np.ndarray) -> np.ndarray:
        return np.array([ya[0] - s0, ya[1] - th0, yb[0] - s1, yb[1] - th1, ya[4]])

    y0 = np.vstack([s0 + tau * ds, th0 + tau * dth, np.full_like(tau, ds), np.full_like(tau, dth),
                    np.zeros_like(tau)])
    with np.errstate(all="ignore"):
        res = solve_bvp(fun, bc, tau, y0, tol=tol, max_nodes=max_nodes)
    return BvpResult(float(res.y[4, -1]), int(res.status), int(res.x.size), str(res.message))


# -- mesh ------------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Grid:
    """A regular (s, theta) triangulation: ns stations (both ends included) by nt angles (periodic)."""

    ns: int
    nt: int

    @property
    def triangles(self) -> int:
        return 2 * (self.ns - 1) * self.nt


def grid_for(surface: SweepSurface, triangles: int, angles: tuple[float, ...]) -> Grid:
    """A grid of about `triangles` triangles with roughly square cells, whose angle count puts every
    angle in `angles` (rad, e.g. the end points') on a grid line: nt is a multiple of the smallest
    count that does (4 for angles that are multiples of 90 deg)."""
    unit = 1
    for a in angles:
        frac = (a % TWO_PI) / TWO_PI
        for k in range(1, 361):
            if abs(frac * k - round(frac * k)) < 1e-9:
                unit = int(np.lcm(unit, k))
                break
        else:
            raise ValueError(f"angle {a} rad is not a rational fraction of a turn with a small denominator")
    perimeter = surface.perimeter(0.5 * surface.length)
    nt = np.sqrt(0.5 * triangles * perimeter / surface.length)
    nt = max(unit, int(round(nt / unit)) * unit)
    ns = max(2, int(round(0.5 * triangles / nt)) + 1)
    return Grid(ns, nt)


def triangulate(surface: SweepSurface, grid: Grid):
    """The grid's trimesh.Trimesh (vertex k = i * nt + j at (s_i, theta_j))."""
    import trimesh  # noqa: PLC0415 - a dependency of winder, but only the mesh baseline needs it here

    s = np.linspace(0.0, surface.length, grid.ns)
    th = np.arange(grid.nt) * (TWO_PI / grid.nt)
    ss, tt = np.meshgrid(s, th, indexing="ij")
    verts = surface.points(ss.ravel(), tt.ravel())
    i = np.arange(grid.ns - 1)[:, None]
    j = np.arange(grid.nt)[None, :]
    a = i * grid.nt + j
    b = i * grid.nt + (j + 1) % grid.nt
    c, d = a + grid.nt, b + grid.nt
    faces = np.concatenate([np.stack([a, b, d], -1).reshape(-1, 3), np.stack([a, d, c], -1).reshape(-1, 3)])
    return trimesh.Trimesh(vertices=verts, faces=faces, process=False)


def seed_chain(surface: SweepSurface, grid: Grid, start: tuple[float, float], end: tuple[float, float],
               rounds: int) -> list[int]:
    """Grid vertices along the straight parameter-domain segment, 8 per round swept (at least 8):
    the edge-flip solver joins consecutive ones by shortest paths, so the chain winds the rounds."""
    th1 = end[1] + TWO_PI * rounds
    k = max(8, int(np.ceil(8.0 * abs(th1 - start[1]) / TWO_PI)))
    f = np.linspace(0.0, 1.0, k + 1)
    s = start[0] + f * (end[0] - start[0])
    th = start[1] + f * (th1 - start[1])
    ii = np.rint(s / surface.length * (grid.ns - 1)).astype(int)
    jj = np.rint(th / TWO_PI * grid.nt).astype(int) % grid.nt
    chain = ii * grid.nt + jj
    keep = np.r_[True, np.diff(chain) != 0]
    return [int(v) for v in chain[keep]]


@dataclass(frozen=True)
class MeshResult:
    length: float
    triangles: int
    mesh_seconds: float  # grid evaluation and trimesh construction
    precompute_seconds: float  # potpourri3d's solver construction
    query_seconds: float  # the N-round edge-flip path


def mesh_geodesic(surface: SweepSurface, start: tuple[float, float], end: tuple[float, float], rounds: int,
                  triangles: int) -> MeshResult:
    """Mesh the surface and find the edge-flip geodesic; the three phases are timed apart."""
    import potpourri3d as pp3d  # noqa: PLC0415 - optional (the bench extra)

    grid = grid_for(surface, triangles, (start[1], end[1]))
    t0 = time.perf_counter()
    mesh = triangulate(surface, grid)
    t1 = time.perf_counter()
    solver = pp3d.EdgeFlipGeodesicSolver(np.asarray(mesh.vertices), np.asarray(mesh.faces))
    t2 = time.perf_counter()
    path = solver.find_geodesic_path_poly(seed_chain(surface, grid, start, end, rounds))
    t3 = time.perf_counter()
    length = float(np.sum(np.linalg.norm(np.diff(np.asarray(path), axis=0), axis=1)))
    return MeshResult(length, grid.triangles, t1 - t0, t2 - t1, t3 - t2)


# -- LO: length minimization ------------------------------------------------------------------------
def length_and_gradient(surface: SweepSurface, s: np.ndarray, th: np.ndarray) -> tuple[float, np.ndarray]:
    """Polyline length L = sum |y_{i+1} - y_i| and dL/du_i = J_i^T (d_{i-1}/|d_{i-1}| - d_i/|d_i|)."""
    ev = surface.evaluate(s[1:-1], th[1:-1], order=1)
    ends = surface.points(s[[0, -1]], th[[0, -1]])
    y = np.concatenate([ends[:1], ev.p, ends[1:]])
    d = np.diff(y, axis=0)
    lens = np.linalg.norm(d, axis=1)
    u = d / lens[:, None]
    w = u[:-1] - u[1:]
    grad = np.stack([np.einsum("ij,ij->i", ev.ps, w), np.einsum("ij,ij->i", ev.pt, w)], axis=1)
    return float(lens.sum()), grad


def length_optimization(surface: SweepSurface, s: np.ndarray, th: np.ndarray, max_iter: int,
                        callback: Callable[[np.ndarray], None] | None = None) -> tuple[np.ndarray, np.ndarray, int]:
    """LO: L-BFGS-B on the total length from the path (s, th) (end points fixed).

    callback(x) after each iteration, x the interleaved (s_1, th_1, s_2, ...) interior parameters.
    Returns the final (s, th) and the iteration count.
    """
    n = s.shape[0] - 2

    def fun(x: np.ndarray) -> tuple[float, np.ndarray]:
        ss, tt = s.copy(), th.copy()
        ss[1:-1], tt[1:-1] = x[0::2], x[1::2]
        value, grad = length_and_gradient(surface, ss, tt)
        return value, grad.ravel()

    def record(intermediate_result) -> None:
        if callback is not None:
            callback(intermediate_result.x)

    x0 = np.stack([s[1:-1], th[1:-1]], axis=1).ravel()
    res = minimize(fun, x0, jac=True, method="L-BFGS-B", bounds=[(0.0, surface.length), (None, None)] * n,
                   callback=record, options={"maxiter": max_iter, "maxfun": 2 * max_iter, "ftol": 1e-16,
                                             "gtol": 1e-12, "maxcor": 10})
    s_out, th_out = s.copy(), th.copy()
    s_out[1:-1], th_out[1:-1] = res.x[0::2], res.x[1::2]
    return s_out, th_out, int(res.nit)
