"""Tension loss in a thick wound wall, and the winding tensions that leave every layer the same prestress
(docs/math/16-winding-tension.md).

The wall at the reference section is a stack of thin rings (one per layer) on the mandrel, joined by
radial springs (the wet layers' through-thickness stiffness). A layer wound at tension T presses on
what is under it; the stack gives way, and every layer below it (and the new one itself) shortens
around the axis and loses tension. Linear and elastic, so the final tension of layer i is
T_i + sum_j G_ij T_j over the layers j >= i wound on top of it (G_ij <= 0); the uniform-prestress
schedule solves (I + G) T = residual, an upper-triangular system.
"""

from __future__ import annotations

import dataclasses

import numpy as np


@dataclasses.dataclass(frozen=True, kw_only=True)
class RingStack:
    """The wall at the reference section, layers in winding order (all (n,) arrays).

    radius : mid-surface radius of each layer (mm). thickness : its thickness (mm). angle_deg : its
    winding angle from the meridian. e1, e2 : its ply's fiber-direction and transverse moduli (MPa).
    band_area : the band's cross-section, width x ply thickness (mm^2): T / band_area is the fiber-
    direction stress of a band wound at T (N). radial_modulus : the through-thickness modulus (MPa,
    (n,), of each layer). mandrel_stiffness : pressure per inward displacement of the mandrel's surface
    (MPa / mm), inf for a rigid mandrel.
    """

    radius: np.ndarray
    thickness: np.ndarray
    angle_deg: np.ndarray
    e1: np.ndarray
    e2: np.ndarray
    band_area: np.ndarray
    radial_modulus: np.ndarray
    mandrel_stiffness: float = np.inf


def tension_changes(stack: RingStack) -> np.ndarray:
    """G (n, n): G[i, j] the tension change (N) of layer i per N of layer j's winding tension, once j is
    wound (0 below the diagonal: a layer changes only those under it and itself).

    Examples
    --------
    A hoop layer on a rigid mandrel loses the share of its tension its spring gives way under:

    >>> one = RingStack(radius=np.array([100.0]), thickness=np.array([1.0]), angle_deg=np.array([90.0]),
    ...                 e1=np.array([1e5]), e2=np.array([1e4]), band_area=np.array([5.0]),
    ...                 radial_modulus=np.array([100.0]))
    >>> float(np.round(tension_changes(one)[0, 0], 6))
    -0.047619
    """
    from scipy.linalg import solve_banded  # noqa: PLC0415 - only for the schedule

    n = stack.radius.size
    s2 = np.sin(np.radians(stack.angle_deg)) ** 2
    c2 = 1.0 - s2
    hoop = (stack.e1 * s2 * s2 + stack.e2 * c2 * c2) * stack.thickness / stack.radius**2  # K_i, MPa / mm
    half = 0.5 * stack.thickness
    gaps = np.concatenate([[half[0]], half[1:] + half[:-1]])  # what each spring spans, below layer i
    moduli = np.concatenate([[stack.radial_modulus[0]], 0.5 * (stack.radial_modulus[1:] + stack.radial_modulus[:-1])])
    spring = moduli / gaps  # k_i between layer i and what is under it, MPa / mm
    elastic = int(np.isfinite(stack.mandrel_stiffness))
    # Per unit tension of layer j: its pressure on the stack, and each layer's loss per inward displacement.
    pressure = s2 * stack.thickness / (stack.band_area * stack.radius)
    loss = -stack.e1 * s2 * stack.band_area / stack.radius
    out = np.zeros((n, n))
    for j in range(n):
        # Unknowns: the mandrel's surface (when elastic), then layers 0..j: a tridiagonal system.
        m = j + 1 + elastic
        diag = np.zeros(m)
        upper = np.zeros(m)
        lower = np.zeros(m)
        k = spring[: j + 1]
        below = np.concatenate([k, [0.0]])[: j + 1]
        above = np.concatenate([k[1:], [0.0]])
        layer_rows = slice(elastic, m)
        diag[layer_rows] = hoop[: j + 1] + below + above
        if elastic:
            diag[0] = k[0] + stack.mandrel_stiffness
            upper[1] = -k[0]
            lower[0] = -k[0]
        upper[elastic + 1:] = -k[1:]
        lower[elastic:m - 1] = -k[1:]
        rhs = np.zeros(m)
        rhs[-1] = pressure[j]
        u = solve_banded((1, 1), np.vstack([upper, diag, lower]), rhs)[elastic:]
        out[: j + 1, j] = loss[: j + 1] * u
    return out


def uniform_prestress(stack: RingStack, residual: float) -> np.ndarray:
    """The winding tension (N, (n,)) of each layer that leaves every layer `residual` N once the whole
    wall is wound: (I + G) T = residual (module docstring)."""
    from scipy.linalg import solve_triangular  # noqa: PLC0415

    g = tension_changes(stack)
    return solve_triangular(np.eye(g.shape[0]) + g, np.full(g.shape[0], float(residual)))


def residual_tensions(stack: RingStack, wound: np.ndarray) -> np.ndarray:
    """Each layer's tension (N) once the whole wall is wound at the tensions `wound` (n,)."""
    return wound + tension_changes(stack) @ wound
