"""First-ply failure (docs/math/09-structure.md 9.4): Tsai-Wu and maximum stress, as a failure index and as
the load factor on the pressure, vectorized over any leading shape.

Stresses [s1, s2, s12] (MPa) in ply axes, (..., 3); strengths the Lamina's (magnitudes) as (...,) arrays or
scalars. The stresses are affine in the pressure p: sigma = p sigma_p + sigma_0.
"""

from __future__ import annotations

import numpy as np


def tsai_wu_coefficients(xt, xc, yt, yc, s):
    """(F1, F2, F11, F22, F66, F12), F12 = -sqrt(F11 F22) / 2."""
    f11, f22 = 1.0 / (xt * xc), 1.0 / (yt * yc)
    return 1.0 / xt - 1.0 / xc, 1.0 / yt - 1.0 / yc, f11, f22, 1.0 / (s * s), -0.5 * np.sqrt(f11 * f22)


def tsai_wu_index(stress: np.ndarray, strengths: tuple) -> np.ndarray:
    """F(sigma) (...,): 1 at failure."""
    f1, f2, f11, f22, f66, f12 = tsai_wu_coefficients(*strengths)
    s1, s2, s6 = stress[..., 0], stress[..., 1], stress[..., 2]
    return f1 * s1 + f2 * s2 + f11 * s1 ** 2 + f22 * s2 ** 2 + f66 * s6 ** 2 + 2.0 * f12 * s1 * s2


def max_stress_index(stress: np.ndarray, strengths: tuple) -> np.ndarray:
    """max(s1 / X, s2 / Y, |s12| / S) with X, Y the tensile or compressive strength by sign (...,)."""
    xt, xc, yt, yc, s = strengths
    s1, s2, s6 = stress[..., 0], stress[..., 1], stress[..., 2]
    return np.maximum.reduce([np.where(s1 >= 0, s1 / xt, -s1 / xc), np.where(s2 >= 0, s2 / yt, -s2 / yc),
                              np.abs(s6) / s])


def _bilinear(f: tuple, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """The quadratic form of Tsai-Wu between stress vectors u and v."""
    _, _, f11, f22, f66, f12 = f
    return (f11 * u[..., 0] * v[..., 0] + f22 * u[..., 1] * v[..., 1] + f66 * u[..., 2] * v[..., 2]
            + f12 * (u[..., 0] * v[..., 1] + u[..., 1] * v[..., 0]))


def tsai_wu_pressure(per_p: np.ndarray, held: np.ndarray, strengths: tuple) -> np.ndarray:
    """The least pressure p >= 0 with F(p per_p + held) = 1 (...,); inf where no positive p fails.

    a p^2 + b p + c = 0 with a = q(per_p), b = F_lin(per_p) + 2 q(per_p, held), c = F(held) - 1.
    """
    f = tsai_wu_coefficients(*strengths)
    a = _bilinear(f, per_p, per_p)
    b = f[0] * per_p[..., 0] + f[1] * per_p[..., 1] + 2.0 * _bilinear(f, per_p, held)
    c = tsai_wu_index(held, strengths) - 1.0
    with np.errstate(divide="ignore", invalid="ignore"):
        disc = np.sqrt(np.maximum(b * b - 4.0 * a * c, 0.0))
        # the larger root of a p^2 + b p + c (a >= 0 for Tsai-Wu's positive definite quadratic part)
        root = np.where(a > 0.0, (-b + disc) / (2.0 * a), np.where(b > 0.0, -c / b, np.inf))
    root = np.where(c >= 0.0, 0.0, root)  # the held loads alone fail it, whatever the pressure does next
    return np.where(np.isfinite(root) & (root >= 0.0), root, np.inf)


def max_stress_pressure(per_p: np.ndarray, held: np.ndarray, strengths: tuple) -> np.ndarray:
    """The least pressure p >= 0 at which a stress component reaches its strength (...,); inf if none. A
    component the held loads alone already take past its strength fails at 0, whichever way the pressure
    moves it (the ply is broken before the pressure comes: a later pressure easing it mends nothing)."""
    xt, xc, yt, yc, s = strengths
    out = np.full(per_p.shape[:-1], np.inf)
    for i, (hi, lo) in enumerate(((xt, xc), (yt, yc), (s, s))):
        g, h = per_p[..., i], held[..., i]
        with np.errstate(divide="ignore", invalid="ignore"):
            up = np.where(g > 0.0, (hi - h) / np.where(g > 0.0, g, 1.0), np.inf)
            down = np.where(g < 0.0, (-lo - h) / np.where(g < 0.0, g, 1.0), np.inf)
        broken = (h >= hi) | (h <= -lo)
        out = np.minimum(out, np.where(broken, 0.0, np.maximum(np.minimum(up, down), 0.0)))
    return out
