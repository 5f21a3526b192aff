"""The paper's discrete energy (Eq. 14; docs/math/02-energy.md) evaluated exactly on the surface, with its
gradient and its block-tridiagonal Hessian, and the Hessian's banded Cholesky solve: what the
variational solvers of winder.paths.geodesic minimize.

The chain terms come from one surface evaluation at the interior points (the solver reuses it for the
line search, the next step and the length); the Hessian is assembled straight into LAPACK's lower
banded storage (bandwidth 3 in the interleaved order s_1, theta_1, s_2, ...).
"""

from __future__ import annotations

import numpy as np

from winder.geometry.surface import SurfaceEval, SweepSurface, jet_of



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


def chain_segments(p: np.ndarray, ends: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """The chain y (n + 2, 3) of the interior points p (n, 3) between the end points ends (2, 3), its
    segments d (n + 1, 3) (np.diff's arithmetic) and E = sum |d|^2: a trial point's energy, which
    the next Newton step's terms take again."""
    y = np.concatenate([ends[:1], p, ends[1:]])
    d = y[1:] - y[:-1]
    return y, d, float(np.einsum("ij,ij->", d, d))


def chain_energy(p: np.ndarray, ends: np.ndarray) -> float:
    """E of the chain: interior points p (n, 3) between the end points ends (2, 3)."""
    return chain_segments(p, ends)[2]


def step_moves(ev: SurfaceEval, step: np.ndarray) -> np.ndarray:
    """|Phi_s ds + Phi_theta dth|^2 at each vertex for the step (n, 2): (n,)."""
    jet = jet_of(ev, 3)
    if jet is None:  # the fields in the curve's own layout: as chain_terms' products (see _row_terms)
        move = ev.ps * step[:, :1] + ev.pt * step[:, 1:]
        return _dot_cols(move, move)
    move = jet[1] * step[:, 0] + jet[2] * step[:, 1]
    return np.einsum("ji,ji->i", move, move)


def _row_terms(ev: SurfaceEval, d: np.ndarray, hessian: bool | None):
    """newton_terms' grad, gram, curv and off where the fields have no jet (a general guide curve's,
    often (n, 3) C-ordered): the row-wise products themselves. einsum sums a contiguous row of three
    in another order than a strided one, so these stay the products the solver has always taken."""
    ps, pt = ev.ps, ev.pt
    a = d[:-1] - d[1:]
    grad = np.empty((ps.shape[0], 2))
    grad[:, 0] = 2.0 * _dot(ps, a)
    grad[:, 1] = 2.0 * _dot(pt, a)
    if hessian is None:
        return grad, None, None, None
    st = _dot_cols(ps, pt)
    gram = np.array([[_dot_cols(ps, ps), st], [st, _dot_cols(pt, pt)]])
    curv = np.array([_dot(a, ev.pss), _dot(a, ev.pst), _dot(a, ev.ptt)]) if hessian else None
    off = np.array([[_dot_cols(ps[:-1], ps[1:]), _dot_cols(ps[:-1], pt[1:])],
                    [_dot_cols(pt[:-1], ps[1:]), _dot_cols(pt[:-1], pt[1:])]])
    return grad, gram, curv, off


def newton_terms(ev: SurfaceEval, ends: np.ndarray, chain: tuple | None = None, hessian: bool | None = True):
    """chain_terms' quantities in the layout the banded solve takes, with fewer numpy calls.

    chain : chain_segments(ev.p, ends) where the caller has it (the trial point's energy).
    Returns E, grad (n, 2), the chain y (n + 2, 3), gram (2, 2, n) J_i^T J_i, curv (3, n) a_i.Phi_ss,
    a_i.Phi_st, a_i.Phi_thth (None without hessian) and off (2, 2, n - 1) J_i^T J_{i+1} (block row
    letter first), the plain dot products without chain_terms' factors 4, 2 and -2; hessian None:
    E, grad and y only. On a jet each product sums its three components in order along (3, n) rows,
    as the row-wise products over the jet's (n, 3) views do (the same values to round-off).
    """
    y, d, e = chain_segments(ev.p, ends) if chain is None else chain
    n = d.shape[0] - 1
    jet = jet_of(ev, 6 if hessian else 3)
    if jet is None:
        grad, gram, curv, off = _row_terms(ev, d, hessian)
        return e, grad, y, gram, curv, off
    # a_i = 2 y_i - y_{i-1} - y_{i+1} as (3, n) rows: the products below then run along the points
    a = np.subtract(d.T[:, :-1], d.T[:, 1:], out=np.empty((3, n)))
    jac, hess = jet[1:3], (jet[3:6] if hessian else None)
    grad = np.einsum("akm,km->ma", jac, a, out=np.empty((n, 2)))
    grad *= 2.0
    if hessian is None:
        return e, grad, y, None, None, None
    gram = np.einsum("akm,bkm->abm", jac, jac)
    curv = np.einsum("akm,km->am", hess, a) if hessian else None
    off = np.einsum("akm,bkm->abm", jac[:, :, :-1], jac[:, :, 1:])
    return e, grad, y, gram, curv, off


def chain_terms(ev: SurfaceEval, ends: np.ndarray, full_hessian: bool | None = True):
    """E, gradient (n, 2) and the Hessian's entries from one surface evaluation at the interior points.

    Returns E, grad, gram (3, n) = 4 J^T J entries [ss, st, tt], curv (3, n) = the second-derivative
    term 2 sum_k a_k Hess(Phi_k) (None without full_hessian), off (4, n - 1) = -2 J_i^T J_{i+1}
    entries [ss, st, ts, tt] (first letter: row i, second: column i + 1). full_hessian None: E and
    the gradient only.
    """
    e, grad, _, gram, curv, off = newton_terms(ev, ends, hessian=full_hessian)
    if full_hessian is None:
        return e, grad, None, None, None
    return (e, grad, 4.0 * np.array([gram[0, 0], gram[0, 1], gram[1, 1]]),
            2.0 * curv if full_hessian else None, -2.0 * off.reshape(4, -1))


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


def newton_banded(gram: np.ndarray, curv: np.ndarray | None, off: np.ndarray) -> np.ndarray:
    """banded(4 gram + 2 curv, -2 off) from newton_terms' plain dot products (curv None: the
    Gauss-Newton matrix 4 gram), the same entries, written in place: (4, 2n) Fortran order."""
    n = gram.shape[2]
    ab = np.zeros((2 * n, 4)).T
    # Column 2i + j of ab is blk[i, j]: its rows are the diagonal, then the three below it.
    blk = ab.T.reshape(n, 2, 4)
    g4 = 4.0 * gram
    if curv is None:
        blk[:, 0, :2] = g4[0].T  # [ss, st]
        blk[:, 1, 0] = g4[1, 1]
    else:
        c2 = 2.0 * curv
        np.add(g4[0], c2[:2], out=blk[:, 0, :2].T)
        np.add(g4[1, 1], c2[2], out=blk[:, 1, 0])
    np.multiply(off[0], -2.0, out=blk[:-1, 0, 2:].T)  # column s_i: off ss, st
    np.multiply(off[1], -2.0, out=blk[:-1, 1, 1:3].T)  # column theta_i: off ts, tt
    return ab


def newton_direction(diag: np.ndarray, off: np.ndarray, grad: np.ndarray):
    """The step -H^-1 grad (n, 2) by banded Cholesky and the factor, for chord steps; (None, None)
    where H is not positive definite. LAPACK pbsv through scipy.linalg.lapack: on configs/elliptic_tube.yaml's
    plan (658 steps) cholesky_banded and cho_solve_banded took 1.0 s under cProfile, this 0.5 s."""
    return banded_direction(banded(diag, off), grad)


def banded_direction(ab: np.ndarray, grad: np.ndarray):
    """newton_direction from H in lower banded storage ab (4, 2n), which it overwrites."""
    from scipy.linalg.lapack import dpbsv  # noqa: PLC0415

    factor, step, info = dpbsv(ab, -grad.ravel(), lower=1, overwrite_ab=1, overwrite_b=1)
    if info != 0 or not np.all(np.isfinite(step)):  # info > 0: not positive definite
        return None, None
    return step.reshape(-1, 2), factor


def chord_direction(factor: np.ndarray, grad: np.ndarray) -> np.ndarray:
    """-H^-1 grad with an earlier iterate's Cholesky factor (LAPACK pbtrs): (n, 2)."""
    from scipy.linalg.lapack import dpbtrs  # noqa: PLC0415

    step, _ = dpbtrs(factor, -grad.ravel(), lower=1, overwrite_b=1)
    return step.reshape(-1, 2)
