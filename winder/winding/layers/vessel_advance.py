"""The Clairaut geodesic's turnarounds and theta advance over a domed vessel, for many c at once.

A geodesic on a surface of revolution keeps r sin(alpha) = c; it turns around on each dome where
r = c. The circuit advance is a function of c by quadrature (docs/math/05-winding.md). Closing a layer's pattern
solves advance(c) = k / N_c for a few candidate skips (winder.winding.pattern.close_vessel_pattern):
every function here takes c as a float or as an (n,) array, so that the candidates are solved
together, each step of the root finder one quadrature of all of them.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from winder.geometry.vessel import VesselMeridian

QUAD_NODES = 64  # Gauss-Legendre nodes per half dome for the turnaround advance (converged to 1e-14)
RADIUS_TABLE = 65  # stations tabulated to start the inversion r -> s
RADIUS_NEWTON = 12  # at most this many Newton steps from the table's guess (quadratic: 3 or 4 reach the last bits)
_SETTLED = 4.0 * np.finfo(float).eps  # a Newton step below this share of the station: converged (round-off)


@functools.cache
def _gauss() -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Legendre nodes and weights (computed on first use: 35 ms, a hoop job never needs them)."""
    return np.polynomial.legendre.leggauss(QUAD_NODES)


def _stations_of_radius(prof: VesselMeridian, radius: np.ndarray, s_a: np.ndarray, s_b: np.ndarray) -> np.ndarray:
    """Stations (n, k) in [s_a, s_b] (each (n,): a stretch of one dome where r is monotone) at which
    r = radius (n, k): a table's linear guess, then Newton kept inside the stretch."""
    n, k = radius.shape
    lin = np.linspace(0.0, 1.0, RADIUS_TABLE)
    table = s_a[:, None] + (s_b - s_a)[:, None] * lin
    r_tab = prof.evaluate(table.ravel()).r.reshape(table.shape)
    order = np.argsort(r_tab, axis=1)
    r_tab, table = np.take_along_axis(r_tab, order, axis=1), np.take_along_axis(table, order, axis=1)
    # Each radius between the table's entries j - 1 and j (clamped at the ends, as np.interp).
    j = np.clip((r_tab[:, None, :] < radius[:, :, None]).sum(axis=2), 1, RADIUS_TABLE - 1)
    r0, r1 = np.take_along_axis(r_tab, j - 1, axis=1), np.take_along_axis(r_tab, j, axis=1)
    t0, t1 = np.take_along_axis(table, j - 1, axis=1), np.take_along_axis(table, j, axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        f = np.clip(np.where(r1 > r0, (radius - r0) / (r1 - r0), 0.0), 0.0, 1.0)
    s = t0 + f * (t1 - t0)
    lo, hi = np.minimum(s_a, s_b)[:, None], np.maximum(s_a, s_b)[:, None]
    settled = _SETTLED * np.maximum(hi, 1.0)  # stations are >= 0: a few ulp of the largest
    for _ in range(RADIUS_NEWTON):
        e = prof.evaluate(s.ravel())
        step = ((e.r - radius.ravel()) / e.r1).reshape(n, k)
        new = np.clip(s - step, lo, hi)
        done = np.all(np.abs(new - s) <= settled)
        s = new
        if done:
            break
    return s


def turnaround_stations(prof: VesselMeridian, c: float | np.ndarray) -> tuple:
    """Stations s where r = c on the first and the end dome: floats for a float c, (n,) arrays each
    for c (n,)."""
    cc = np.atleast_1d(np.asarray(c, dtype=float))
    e1, e2 = prof.equator_s
    zero = np.zeros_like(cc)
    first = _stations_of_radius(prof, cc[:, None], zero, zero + e1)[:, 0]
    end = _stations_of_radius(prof, cc[:, None], zero + e2, zero + prof.length)[:, 0]
    return (float(first[0]), float(end[0])) if np.ndim(c) == 0 else (first, end)


def advances(prof: VesselMeridian, c: float | np.ndarray) -> tuple:
    """theta advances (rad) of the geodesic of Clairaut constant c: over the first dome (turnaround
    to equator), the cylinder, and the end dome (equator to turnaround): floats for a float c, (n,)
    arrays for c (n,). The cylinder is exact; each dome is _dome_advance."""
    cc = np.atleast_1d(np.asarray(c, dtype=float))
    s1, s2 = turnaround_stations(prof, cc)
    e1, e2 = prof.equator_s
    cylinder = cc * prof.cylinder_length / (prof.radius * np.sqrt(prof.radius**2 - cc * cc))
    out = (_dome_advance(prof, cc, s1, e1), cylinder, _dome_advance(prof, cc, s2, e2))
    return tuple(float(v[0]) for v in out) if np.ndim(c) == 0 else out


def half_advance(prof: VesselMeridian, c: float | np.ndarray) -> float | np.ndarray:
    """theta advance (rad) from one turnaround to the other (a float for a float c, else (n,))."""
    first, cylinder, end = advances(prof, c)
    return first + cylinder + end


def _dome_advance(prof: VesselMeridian, c: np.ndarray, s_c: np.ndarray, s_eq: float) -> np.ndarray:
    """theta advance (rad) (n,) from the turnarounds r = c (n,) (near stations s_c (n,)) to the
    equator s_eq.

    dtheta/ds = c / (r sqrt(r^2 - c^2)). From the turnaround to the dome's middle station s_m it is
    integrated in v, r = c cosh(v): dtheta = dv / (cosh(v) |dr/ds|), smooth, and r - c is exact,
    so the result does not hang on r^2 - c^2 near the turnaround, which round-off knows only to
    ulp(r^2), nor on the turnaround station, known only to ulp(r) / r'. (Integrated in s there, the
    advance jittered by 5e-11 rad between Clairaut constants 1e-14 mm apart, and the pattern closing
    amplified that to a few units of the CSV's last digit.) From s_m to the equator, where r > c,
    in s.
    """
    x, w = _gauss()
    half = 0.5 * (x + 1.0)
    s_m = 0.5 * (s_c + s_eq)
    v_m = np.arccosh(prof.evaluate(s_m).r / c)
    v = v_m[:, None] * half
    s = _stations_of_radius(prof, c[:, None] * np.cosh(v), s_c, s_m)
    r1 = prof.evaluate(s.ravel()).r1.reshape(s.shape)
    near = 0.5 * v_m * ((1.0 / (np.cosh(v) * np.abs(r1))) @ w)
    r = prof.evaluate((s_m[:, None] + (s_eq - s_m)[:, None] * half).ravel()).r.reshape(s.shape)
    far = 0.5 * np.abs(s_eq - s_m) * ((c[:, None] / (r * np.sqrt(r * r - c[:, None] ** 2))) @ w)
    return near + far


def dome_advance_to(prof: VesselMeridian, c: float, s_c: float, s_x: float) -> float:
    """theta advance (rad) of the geodesic of Clairaut constant c from its turnaround station s_c to the
    station s_x on the same dome (r > c there)."""
    return float(_dome_advance(prof, np.array([c]), np.array([s_c]), s_x)[0])


def circuit_advance(prof: VesselMeridian, c: float | np.ndarray) -> float | np.ndarray:
    """A circuit's advance in turns (two half advances), as close_vessel_pattern takes it."""
    return 2.0 * half_advance(prof, c) / (2.0 * math.pi)
