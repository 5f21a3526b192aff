"""Classical lamination theory (docs/math/09-structure.md 9.3), vectorized over stations and plies.

Axes: x the meridian, y the hoop direction; 1 the fiber, 2 transverse. Strains are engineering
(gamma = 2 eps_12); vectors [x, y, xy] or [1, 2, 12]. Units MPa and mm: A N/mm, B N, D N mm.
"""

from __future__ import annotations

import numpy as np

from winder.analysis.materials import Lamina


def reduced_stiffness(ply: Lamina) -> np.ndarray:
    """Q (3, 3) of a ply in its own axes (plane stress)."""
    d = 1.0 - ply.nu12 * ply.nu21
    q11, q22, q12 = ply.E1 / d, ply.E2 / d, ply.nu12 * ply.E2 / d
    return np.array([[q11, q12, 0.0], [q12, q22, 0.0], [0.0, 0.0, ply.G12]])


def stress_rotation(angle: np.ndarray) -> np.ndarray:
    """T_sigma (..., 3, 3): sigma_12 = T_sigma sigma_xy for fibers at angle (rad) from x toward y."""
    m, n = np.cos(angle), np.sin(angle)
    return np.stack([np.stack([m * m, n * n, 2 * m * n], -1), np.stack([n * n, m * m, -2 * m * n], -1),
                     np.stack([-m * n, m * n, m * m - n * n], -1)], -2)


def strain_rotation(angle: np.ndarray) -> np.ndarray:
    """T_eps (..., 3, 3): eps_12 = T_eps eps_xy (engineering shear)."""
    m, n = np.cos(angle), np.sin(angle)
    return np.stack([np.stack([m * m, n * n, m * n], -1), np.stack([n * n, m * m, -m * n], -1),
                     np.stack([-2 * m * n, 2 * m * n, m * m - n * n], -1)], -2)


def rotated_stiffness(q: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """Qbar = T_sigma^-1 Q T_eps (..., 3, 3) of plies at angle (...) rad; q (3, 3) or (..., 3, 3)."""
    return np.linalg.solve(stress_rotation(angle), q @ strain_rotation(angle))


def abd(qbar: np.ndarray, thickness: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A, B, D (n, 3, 3) of laminates of k plies stacked from the inner face outward.

    qbar : (n, k, 3, 3); thickness : (n, k) mm (0 for a ply absent there). z from each laminate's
    mid-plane: A = sum Qb dz, B = sum Qb d(z^2) / 2, D = sum Qb d(z^3) / 3.
    """
    t = np.asarray(thickness, float)
    top = np.cumsum(t, axis=-1) - 0.5 * t.sum(axis=-1, keepdims=True)
    bottom = top - t
    w = np.stack([top - bottom, (top ** 2 - bottom ** 2) / 2.0, (top ** 3 - bottom ** 3) / 3.0])
    a, b, d = (np.einsum("nk,nkij->nij", wi, qbar) for wi in w)
    return a, b, d


def membrane_strains(a: np.ndarray, n: np.ndarray) -> np.ndarray:
    """eps0 = A^-1 N (n, 3): the membrane state of a shell of revolution (9.3). a (n, 3, 3), n (n, 3)."""
    return np.linalg.solve(a, n[..., None])[..., 0]


def ply_response(eps0: np.ndarray, angle: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Ply strains and stresses in ply axes, each (n, k, 3), under membrane strains eps0 (n, 3) (the same
    through the thickness); angle (n, k) rad; q (k, 3, 3) or (n, k, 3, 3) each ply's Q."""
    eps12 = np.einsum("nkij,nj->nki", strain_rotation(angle), eps0)
    return eps12, np.einsum("...ij,...j->...i", np.broadcast_to(q, eps12.shape + (3,)), eps12)
