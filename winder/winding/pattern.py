"""The circuit pattern of a helical layer (docs/math/05-winding.md): how many circuits, which skip, how it closes.

A circuit is a forward and a return pass; the mandrel turns one way throughout. With N_c circuits
and a circuit advance of k / N_c of a turn (gcd(k, N_c) = 1), circuit j starts in slot j k mod N_c
and after N_c circuits every slot holds exactly one circuit. Advances here are fractions of a turn
of the section's perimeter (arc length), so the same arithmetic serves non-circular sections.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Callable

import numpy as np

from winder.errors import ConfigError, SolverError


def circuits_for_coverage(perimeter: float, angle_rad: float, band_width: float) -> int:
    """N_c = ceil(P cos(alpha) / B): the fewest circuits whose bands cover the perimeter.

    Parameters
    ----------
    perimeter : float
        P, the reference section's perimeter (mm).
    angle_rad : float
        The winding angle alpha from the meridian (rad).
    band_width : float
        B (mm).

    Returns
    -------
    int
        At least 1.

    Examples
    --------
    A 55 deg layer of 10 mm bands on a tube of radius 50: 2 pi 50 cos(55 deg) / 10 = 18.02.

    >>> circuits_for_coverage(2 * math.pi * 50, math.radians(55), 10)
    19
    """
    need = perimeter * math.cos(angle_rad) / band_width
    return max(1, math.ceil(need - 1e-9))


def coprime_skips(circuits: int) -> list[int]:
    """The skips k in [1, N_c) with gcd(k, N_c) = 1 (k = 1 alone for a single circuit).

    Examples
    --------
    >>> coprime_skips(12)
    [1, 5, 7, 11]
    """
    if circuits == 1:
        return [1]
    return [k for k in range(1, circuits) if math.gcd(k, circuits) == 1]


def _check_skip(pattern: int | None, circuits: int, key: str) -> list[int]:
    skips = coprime_skips(circuits)
    if pattern is None:
        return skips
    if circuits > 1 and math.gcd(pattern, circuits) != 1:
        raise ConfigError(f"{key}: pattern {pattern} shares a factor with the {circuits} circuits this layer "
                          f"needs, so some slots would be wound twice and others never; allowed: "
                          f"{', '.join(map(str, skips[:12]))}{' ...' if len(skips) > 12 else ''} or auto")
    return [pattern % circuits if circuits > 1 else 1]


@dataclasses.dataclass(frozen=True)
class OpenPattern:
    """Pattern of an open mandrel: the passes' natural advance plus the dwells close it.

    advance : circuit advance (turns) = natural + dwell_start + dwell_end = k / N_c (mod 1).
    """

    circuits: int
    pattern: int
    natural: float
    dwell_start: float
    dwell_end: float

    @property
    def advance(self) -> float:
        return self.natural + self.dwell_start + self.dwell_end


def close_open_pattern(circuits: int, natural: float, min_start: float, min_end: float,
                       pattern: int | None, key: str) -> OpenPattern:
    """Choose k and the dwells (turns, each >= its minimum) so the circuit advance is k / N_c.

    The extra dwell is the least non-negative amount that closes the pattern; it is shared equally
    by the two ends. pattern: a given k, or None for the k needing the least extra dwell.

    Examples
    --------
    Five circuits whose passes and turnarounds advance 2.13 turns: skip 1 needs 0.07 turn more
    (2.2 = 11 / 5), shared by the two ends.

    >>> closed = close_open_pattern(5, 2.13, 0.0, 0.0, None, "layer 1 (helical 30 deg).pattern")
    >>> closed.pattern, round(closed.dwell_start, 9), round(closed.advance % 1.0, 9)
    (1, 0.035, 0.2)
    """
    best = None
    for k in _check_skip(pattern, circuits, key):
        extra = (k / circuits - (natural + min_start + min_end)) % 1.0
        if extra > 1.0 - 1e-12:
            extra = 0.0
        if best is None or extra < best[1] - 1e-12:
            best = (k, extra)
    k, extra = best
    return OpenPattern(circuits, k, natural, min_start + extra / 2.0, min_end + extra / 2.0)


def close_vessel_pattern(advance: Callable[[np.ndarray], np.ndarray], c0: float, c_lo: float, c_hi: float,
                         circuits: int, pattern: int | None, key: str) -> tuple[int, float]:
    """Move the turnaround radius c (hence the angle) so that advance(c) = k / N_c (mod 1 turn).

    advance : circuit advance in turns as a function of c, increasing on (c_lo, c_hi), taking and
    giving (n,) arrays (winder.winding.layers.vessel_advance.circuit_advance).
    Returns (k, c) with the least |c - c0|.
    """
    a_lo, a_hi, a0 = (float(v) for v in advance(np.array([c_lo, c_hi, c0])))
    # Every skip offers the targets just above and below a0; advance(c) is smooth and increasing, so
    # the few targets nearest a0 hold the least |c - c0|: solve those alone, together (each step of
    # the root finder one quadrature of all of them), each bracketed on its side of c0.
    candidates = []
    for k in _check_skip(pattern, circuits, key):
        up = a0 + (k / circuits - a0) % 1.0
        candidates += [(abs(t - a0), k, t) for t in (up, up - 1.0) if a_lo <= t <= a_hi]
    nearest = sorted(candidates)[:4]
    solve = [(k, t) for _, k, t in nearest if abs(t - a0) >= 1e-13]
    found = [(k, c0) for _, k, t in nearest if abs(t - a0) < 1e-13]
    if solve:
        from scipy.optimize.elementwise import find_root  # noqa: PLC0415 - a hoop job never closes a pattern

        target = np.array([t for _, t in solve])
        res = find_root(lambda x, t: advance(x) - t, (np.where(target > a0, c0, c_lo), np.where(target > a0, c_hi, c0)),
                        args=(target,), tolerances={"xatol": 1e-13, "xrtol": 1e-14})
        found += [(k, float(c)) for (k, _), c, ok in zip(solve, res.x, res.success) if ok]
    best = None
    for k, c in found:
        if best is None or abs(c - c0) < abs(best[1] - c0):
            best = (k, c)
    if best is None:
        raise SolverError(f"{key}: no turnaround radius between {c_lo:.4g} and {c_hi:.4g} mm closes a pattern "
                          f"of {circuits} circuits; change the angle or the band width")
    return best


def vessel_closures(advance: Callable[[np.ndarray], np.ndarray], c0: float, c_lo: float, c_hi: float,
                    counts: list[int], pattern: int | None) -> list[tuple[int, int, float]]:
    """Every (N, k, c) closing a pattern of N circuits (N in counts) at the turnaround radius c in
    [c_lo, c_hi] nearest c0 from above and from below, for each skip k (or the given pattern): the
    choices a vessel layer has (winder patterns lists them); solved together (one quadrature of all
    per step of the root finder)."""
    a_lo, a_hi, a0 = (float(v) for v in advance(np.array([c_lo, c_hi, c0])))
    wanted = []
    for n in counts:
        for k in (coprime_skips(n) if pattern is None else ([pattern % n or 1] if math.gcd(pattern, n) == 1 else [])):
            up = a0 + (k / n - a0) % 1.0
            wanted += [(n, k, t) for t in (up, up - 1.0) if a_lo <= t <= a_hi]
    if not wanted:
        return []
    from scipy.optimize.elementwise import find_root  # noqa: PLC0415

    target = np.array([t for _, _, t in wanted])
    lo, hi = np.where(target > a0, c0, c_lo), np.where(target > a0, c_hi, c0)
    res = find_root(lambda x, t: advance(x) - t, (lo, hi), args=(target,),
                    tolerances={"xatol": 1e-13, "xrtol": 1e-14})
    return [(n, k, float(c)) for (n, k, _), c, ok in zip(wanted, res.x, res.success) if ok]


def slot_of_circuit(circuit: int, circuits: int, pattern: int) -> int:
    """The slot (0 .. N_c - 1) that circuit j (0-based) starts in."""
    return (circuit * pattern) % circuits


def slots_filled(circuits: int, pattern: int) -> np.ndarray:
    """How many circuits start in each slot: all ones for a closed, even pattern. (N_c,) int.

    Examples
    --------
    A skip coprime with the circuits fills every slot once; one sharing a factor winds some slots
    several times and others never.

    >>> slots_filled(12, 5).tolist()
    [1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1]
    >>> slots_filled(12, 4).tolist()
    [4, 0, 0, 0, 4, 0, 0, 0, 4, 0, 0, 0]
    """
    return np.bincount([slot_of_circuit(j, circuits, pattern) for j in range(circuits)], minlength=circuits)
