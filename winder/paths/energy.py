"""The paper's discrete energy (Eq. 14; MATH.md 2) evaluated exactly on the surface, with its
gradient and its block-tridiagonal Hessian, and the Hessian's banded Cholesky solve: what the
variational solvers of winder.paths.geodesic minimize.

The chain terms come from one surface evaluation at the interior points (the solver reuses it for the
line search, the next step and the length); the Hessian is assembled straight into LAPACK's lower
banded storage (bandwidth 3 in the interleaved order s_1, theta_1, s_2, ...).
"""

from __future__ import annotations

import numpy as np

from winder.geometry.lapack import lapack as scipy_lapack
from winder.geometry.surface import SurfaceEval, SweepSurface


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.einsum("ij,ij->i", a, b)


def _dot_cols(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """_dot of two (m, 3) views of (3, m) storage (a surface evaluation's fields): einsum then runs
    along the contiguous rows, 2-4x faster from m ~ 1000 on, the same sums in the same order."""
    return np.einsum("ji,ji->i", a.T, b.T)


def energy(surface: SweepSurface, s: np.ndarray, th: np.ndarray) -> float:
    """E = sum |y_{i+1} - y_i|^2 of the polyline (s, th) (n + 2,) on the surface."""
    y = surface.points(s, th)
    return float(np.sum(np.diff(y, axis=0) ** 2))


def chain_energy(p: np.ndarray, ends: np.ndarray) -> float:
    """E of the chain: interior points p (n, 3) between the end points ends (2, 3)."""
    d = np.diff(np.concatenate([ends[:1], p, ends[1:]]), axis=0)
    return float(np.einsum("ij,ij->", d, d))


def chain_terms(ev: SurfaceEval, ends: np.ndarray, full_hessian: bool | None = True):
    """E, gradient (n, 2) and the Hessian's entries from one surface evaluation at the interior points.

    Returns E, grad, gram (3, n) = 4 J^T J entries [ss, st, tt], curv (3, n) = the second-derivative
    term 2 sum_k a_k Hess(Phi_k) (None without full_hessian), off (4, n - 1) = -2 J_i^T J_{i+1}
    entries [ss, st, ts, tt] (first letter: row i, second: column i + 1). full_hessian None: E and
    the gradient only.
    """
    d = np.diff(np.concatenate([ends[:1], ev.p, ends[1:]]), axis=0)
    a = d[:-1] - d[1:]
    ps, pt = ev.ps, ev.pt
    grad = np.empty((ps.shape[0], 2))
    grad[:, 0] = 2.0 * _dot(ps, a)
    grad[:, 1] = 2.0 * _dot(pt, a)
    e = float(np.einsum("ij,ij->", d, d))
    if full_hessian is None:
        return e, grad, None, None, None
    gram = 4.0 * np.array([_dot_cols(ps, ps), _dot_cols(ps, pt), _dot_cols(pt, pt)])
    curv = 2.0 * np.array([_dot(a, ev.pss), _dot(a, ev.pst), _dot(a, ev.ptt)]) if full_hessian else None
    off = -2.0 * np.array([_dot_cols(ps[:-1], ps[1:]), _dot_cols(ps[:-1], pt[1:]), _dot_cols(pt[:-1], ps[1:]),
                           _dot_cols(pt[:-1], pt[1:])])
    return e, grad, gram, curv, off


def energy_terms(surface: SweepSurface, s: np.ndarray, th: np.ndarray, full_hessian: bool = True):
    """E, gradient (n, 2), Hessian diagonal blocks (n, 2, 2), off-diagonal blocks (n - 1, 2, 2).

    s, th : (n + 2,) float with the fixed end points. H_ii = 4 J_i^T J_i + 2 sum_k a_ik Hess(Phi_k),
    a_i = 2 y_i - y_{i-1} - y_{i+1}; H_{i,i+1} = -2 J_i^T J_{i+1}. Without full_hessian, Gauss-Newton.
    Also returns the Jacobians J (n, 3, 2).
    """
    ev = surface.evaluate(s[1:-1], th[1:-1], order=2 if full_hessian else 1)
    e, grad, gram, curv, off = chain_terms(ev, surface.points(s[[0, -1]], th[[0, -1]]), full_hessian)
    diag = gram + curv if full_hessian else gram
    hd = np.stack([diag[0], diag[1], diag[1], diag[2]], axis=1).reshape(-1, 2, 2)
    ho = off.T.reshape(-1, 2, 2)
    return e, grad, hd, ho, np.stack([ev.ps, ev.pt], axis=2)


def banded(diag: np.ndarray, off: np.ndarray) -> np.ndarray:
    """Lower banded storage (4, 2n), Fortran order for LAPACK, of the interleaved (s_1, th_1, s_2, ...)
    block-tridiagonal H from its entries diag (3, n) [ss, st, tt] and off (4, n - 1) [ss, st, ts, tt].

    Lower, not upper: LAPACK's unblocked band Cholesky then updates each column's contiguous
    sub-diagonal run, about 30 % faster at bandwidth 3 (measured with OpenBLAS, n = 1000).
    """
    n = diag.shape[1]
    ab = np.empty((4, 2 * n), order="F")
    ab[0, 0::2], ab[0, 1::2] = diag[0], diag[2]
    ab[1, 0::2] = diag[1]
    ab[1, 1:-1:2] = off[2]
    ab[2, 0:-2:2] = off[0]
    ab[2, 1:-2:2] = off[3]
    ab[3, 0:-2:2] = off[1]
    ab[1, -1] = ab[2, -2:] = ab[3, -3:] = ab[3, 1::2] = 0.0
    return ab


def newton_direction(diag: np.ndarray, off: np.ndarray, grad: np.ndarray):
    """The step -H^-1 grad (n, 2) by banded Cholesky (LAPACK pbsv) and the factor, for chord steps;
    (None, None) where H is not positive definite."""
    lapack = scipy_lapack()

    factor, step, info = lapack.dpbsv(banded(diag, off), -grad.ravel(), lower=1, overwrite_ab=1, overwrite_b=1)
    if info != 0 or not np.all(np.isfinite(step)):
        return None, None
    return step.reshape(-1, 2), factor


def chord_direction(factor: np.ndarray, grad: np.ndarray) -> np.ndarray:
    """-H^-1 grad with an earlier iterate's Cholesky factor (LAPACK pbtrs): (n, 2)."""
    lapack = scipy_lapack()

    step, _ = lapack.dpbtrs(factor, -grad.ravel(), lower=1, overwrite_b=1)
    return step.reshape(-1, 2)
