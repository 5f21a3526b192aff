"""The paper's discrete energy (Eq. 14; MATH.md 2) evaluated exactly on the surface, with its
gradient and its block-tridiagonal Hessian: what the variational solvers of winder.paths.geodesic
minimize."""

from __future__ import annotations

import numpy as np

from winder.geometry.surface import SweepSurface


def energy(surface: SweepSurface, s: np.ndarray, th: np.ndarray) -> float:
    """E = sum |y_{i+1} - y_i|^2 of the polyline (s, th) (n + 2,) on the surface."""
    y = surface.points(s, th)
    return float(np.sum(np.diff(y, axis=0) ** 2))


def energy_terms(surface: SweepSurface, s: np.ndarray, th: np.ndarray, full_hessian: bool = True):
    """E, gradient (n, 2), Hessian diagonal blocks (n, 2, 2), off-diagonal blocks (n - 1, 2, 2).

    s, th : (n + 2,) float with the fixed end points. H_ii = 4 J_i^T J_i + 2 sum_k a_ik Hess(Phi_k),
    a_i = 2 y_i - y_{i-1} - y_{i+1}; H_{i,i+1} = -2 J_i^T J_{i+1}. Without full_hessian, Gauss-Newton.
    """
    ev = surface.evaluate(s[1:-1], th[1:-1], order=2 if full_hessian else 1)
    ends = surface.points(s[[0, -1]], th[[0, -1]])
    y = np.concatenate([ends[:1], ev.p, ends[1:]])
    d = np.diff(y, axis=0)
    a = d[:-1] - d[1:]
    jac = np.stack([ev.ps, ev.pt], axis=2)  # (n, 3, 2)
    grad = 2.0 * np.einsum("nki,nk->ni", jac, a)
    hd = 4.0 * np.einsum("nki,nkj->nij", jac, jac)
    if full_hessian:
        hd[:, 0, 0] += 2.0 * np.einsum("nk,nk->n", a, ev.pss)
        cross = 2.0 * np.einsum("nk,nk->n", a, ev.pst)
        hd[:, 0, 1] += cross
        hd[:, 1, 0] += cross
        hd[:, 1, 1] += 2.0 * np.einsum("nk,nk->n", a, ev.ptt)
    ho = -2.0 * np.einsum("nki,nkj->nij", jac[:-1], jac[1:])
    return float(np.sum(d * d)), grad, hd, ho, jac
