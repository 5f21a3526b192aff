"""Netting analysis (docs/math/09-structure.md 9.2): the fibers carry the whole load at one allowable
stress; burst pressure per station, sizing of helical and hoop thickness, and the optimum angle.

Angles in radians; thicknesses mm; stresses and pressures MPa; a layer's angle is its fibers' from the
meridian (a +-a helical pair or a hoop); sigma is the allowable on the composite thickness.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

OPTIMUM_ANGLE = math.atan(math.sqrt(2.0))  # 54.7356 deg: a +-a net balanced under N_h = 2 N_m


@dataclasses.dataclass(frozen=True)
class NettingLimits:
    """Burst pressures (MPa) per station, each (n,): axial (meridional) and hoop limits (inf where the load
    does not grow with the pressure) and burst, their least; `index` the station of the least burst."""

    axial: np.ndarray
    hoop: np.ndarray
    burst: np.ndarray

    @property
    def index(self) -> int:
        return int(np.argmin(self.burst))

    @property
    def pressure(self) -> float:
        return float(self.burst[self.index])

    @property
    def limit(self) -> str:
        """Which limit governs at the least burst station: "axial" or "hoop"."""
        i = self.index
        return "axial" if self.axial[i] <= self.hoop[i] else "hoop"


def capacities(sigma: float, thickness: np.ndarray, angle: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The fibers' meridional and hoop load capacity (N/mm): sigma sum t cos^2 a, sigma sum t sin^2 a.

    thickness, angle : (n, k) (k layers; thickness 0 where a layer is absent). Returns two (n,)."""
    t = np.asarray(thickness, float)
    a = np.asarray(angle, float)
    return sigma * np.sum(t * np.cos(a) ** 2, axis=-1), sigma * np.sum(t * np.sin(a) ** 2, axis=-1)


def limits(cap_m: np.ndarray, cap_h: np.ndarray, per_p: np.ndarray, held: np.ndarray) -> NettingLimits:
    """Burst pressures where the demand (per unit pressure per_p, held loads held: (n, 3) [N_m, N_h, N_mh],
    winder.analysis.loads.resultants) reaches the capacities. Shear is left to the laminate analysis."""
    out = []
    for cap, col in ((cap_m, 0), (cap_h, 1)):
        grow = per_p[:, col]
        with np.errstate(divide="ignore", invalid="ignore"):
            p = np.where(grow > 0.0, (cap - held[:, col]) / np.where(grow > 0.0, grow, 1.0), np.inf)
        out.append(np.maximum(p, 0.0))
    return NettingLimits(out[0], out[1], np.minimum(out[0], out[1]))


def cylinder_limits(radius: float, sigma: float, helical_thickness, helical_angle, hoop_thickness: float = 0.0,
                    closed: bool = True, axial_force: float = 0.0) -> NettingLimits:
    """A cylinder's limits (one station): helical layers (thickness, angle: scalars or (k,)) and hoops.

    Closed ends: p_axial = 2 (sigma sum t cos^2 a - F / (2 pi R)) / R; p_hoop = sigma (sum t sin^2 a + t_c) / R.
    """
    t = np.atleast_1d(np.asarray(helical_thickness, float))
    a = np.atleast_1d(np.asarray(helical_angle, float))
    cap_m, cap_h = capacities(sigma, np.append(t, hoop_thickness)[None, :], np.append(a, 0.5 * np.pi)[None, :])
    per_p = np.array([[0.5 * radius if closed else 0.0, radius, 0.0]])
    held = np.array([[axial_force / (2.0 * np.pi * radius), 0.0, 0.0]])
    return limits(cap_m, cap_h, per_p, held)


def sizing(pressure: float, radius: float, sigma: float, angle: float, closed: bool = True,
           axial_force: float = 0.0) -> tuple[float, float]:
    """(helical, hoop) thickness (mm) a cylinder needs for the pressure with helical fibers at `angle`:
    the helical layer takes the axial load, N_m = sigma t_h cos^2 a, the hoops the rest of the hoop load,
    t_c = N_h / sigma - t_h sin^2 a; where that is negative (past the optimum angle) no hoops are needed
    (t_c = 0: the helical layer sized for N_m carries more than N_h). Open ends without an axial force:
    t_h = 0, hoops alone."""
    n_m = (0.5 * pressure * radius if closed else 0.0) + axial_force / (2.0 * np.pi * radius)
    n_h = pressure * radius
    t_h = max(n_m, 0.0) / (sigma * math.cos(angle) ** 2)
    t_c = n_h / sigma - t_h * math.sin(angle) ** 2
    return t_h, max(t_c, 0.0)


def optimum_angle(n_m: float, n_h: float) -> float:
    """The helical angle (rad) at which a +-a net alone carries N_m and N_h: tan^2 a = N_h / N_m
    (atan(sqrt 2) for a closed cylinder under pressure); pi/2 where N_m <= 0 (hoops only)."""
    if n_m <= 0.0:
        return 0.5 * math.pi
    return math.atan(math.sqrt(max(n_h, 0.0) / n_m))
