"""The numbers a shop asks first (docs/guide/will-it-hold.md): a vessel's enclosed volume, and the
laminate's mass per metre and over the trimmed part of a pipe (the gauge span, winder.analysis.gauge).
"""

from __future__ import annotations

import numpy as np

GAUSS_NODES = 48  # Gauss-Legendre nodes per piece: a dome's r(s)^2 z'(s) is smooth, exact to round-off
GAUSS_PIECES = 64  # sub-intervals per meridian piece (a dome, the cylinder)


def _gauss(lo: float, hi: float) -> tuple[np.ndarray, np.ndarray]:
    """Nodes and weights of a composite Gauss-Legendre rule on [lo, hi]."""
    x, w = np.polynomial.legendre.leggauss(GAUSS_NODES)
    edges = np.linspace(lo, hi, GAUSS_PIECES + 1)
    half = 0.5 * np.diff(edges)[:, None]
    mid = 0.5 * (edges[:-1] + edges[1:])[:, None]
    return (mid + half * x).ravel(), (half * w).ravel()


def enclosed_volume(profile) -> float:
    """The volume (mm^3) a vessel's mandrel surface encloses, closed by the planes of its polar openings:
    integral of pi r^2 dz along the meridian, piece by piece (the domes and the cylinder).

    Examples
    --------
    A hemisphere of radius R opened at r0 holds pi (R^2 h - h^3 / 3), h = sqrt(R^2 - r0^2).
    """
    total = 0.0
    for lo, hi in profile.dome_ranges:
        if hi <= lo:
            continue
        s, w = _gauss(lo, hi)
        ev = profile.evaluate(s)
        total += float(np.sum(w * np.pi * ev.r ** 2 * np.abs(ev.z1)))
    return total


def layer_densities(plan) -> np.ndarray:
    """Each laminate layer's composite density (kg/mm^3; NaN without densities): its mass over its volume."""
    walls = [layer.laminate for layer in plan.layers if layer.laminate is not None]
    return np.array([(w.fiber_mass_kg + w.resin_mass_kg) / w.volume_mm3 if w.volume_mm3 > 0 else np.nan
                     for w in walls])


def mass_per_length(plan, t: np.ndarray) -> np.ndarray:
    """The laminate's mass per mm of axis (kg/mm) at stations t (n,) of a surface of revolution: each layer
    a ring of its thickness on the rings below, 2 pi h (r + h / 2) per unit length along the meridian over
    cos(phi) per unit of axis; NaN without densities."""
    walls = [layer.laminate for layer in plan.layers if layer.laminate is not None]
    surface = plan.surface
    s = surface.s_of_t(t)
    ev = surface.evaluate(s, np.zeros_like(s), order=1)
    r = np.hypot(ev.p[:, 0], ev.p[:, 1])
    stretch = np.linalg.norm(ev.ps, axis=1) / np.maximum(np.abs(ev.ps[:, 2]), 1e-12)  # ds / dt
    below = np.zeros_like(t, dtype=float)
    out = np.zeros_like(t, dtype=float)
    for w, rho in zip(walls, layer_densities(plan)):
        h = np.interp(t, w.t, w.thickness, left=0.0, right=0.0)
        out += rho * 2.0 * np.pi * h * (r + below + 0.5 * h) * stretch
        below += h
    return out


def trimmed_mass(plan, span: tuple[float, float]) -> float:
    """The laminate's mass (kg) between stations span = (t0, t1): mass_per_length integrated."""
    t, w = _gauss(*span)
    return float(np.sum(w * mass_per_length(plan, t)))
