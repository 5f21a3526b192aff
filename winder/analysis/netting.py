"""Netting analysis (docs/math/09-structure.md 9.2): the fibers carry the whole load, each fiber family
(a helical layer's +a and -a, a hoop layer's one direction) its own force; the burst pressure is where the
first family reaches its allowable. Sizing of helical and hoop thickness and the optimum angle.

Angles in radians from the meridian; thicknesses mm; stresses and pressures MPa; forces N/mm. Allowables
are on the composite thickness (the fibers' allowable times V_f, winder.analysis.materials).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

OPTIMUM_ANGLE = math.atan(math.sqrt(2.0))  # 54.7356 deg: a +-a net balanced under N_h = 2 N_m
# Layers whose cos^2 a differ by less than this share one direction: a net of one direction (and its
# mirror) is a mechanism, balanced by the classic direction-wise netting (9.2).
SPAN_TOL = 0.05
GROUPS = ("mechanism", "determinate", "compatibility")  # how a station's fiber forces were found


@dataclasses.dataclass(frozen=True, kw_only=True)
class Wall:
    """The fiber families of the layers at stations (n) for layers (L).

    angle : (n, L) rad (0 where absent); thickness : (n, L) mm; helical : (L,) bool (a +-a pair, else one
    family); modulus : (L,) the ply's E1 (MPa: the fibers' share of the load where the net is statically
    indeterminate); tension, compression : (L,) allowables on the composite thickness (MPa)."""

    angle: np.ndarray
    thickness: np.ndarray
    helical: np.ndarray
    modulus: np.ndarray
    tension: np.ndarray
    compression: np.ndarray

    @property
    def families(self) -> tuple[np.ndarray, np.ndarray]:
        """(layer (F,), sign (F,)): each family's layer position and +1 / -1 (a hoop's one family +1)."""
        layer = np.concatenate([[k, k] if h else [k] for k, h in enumerate(self.helical)]).astype(int)
        sign = np.concatenate([[1.0, -1.0] if h else [1.0] for h in self.helical])
        return layer, sign


@dataclasses.dataclass(frozen=True, kw_only=True)
class NettingLimits:
    """Per station (n): burst (MPa; inf where no family ever fails), the governing layer position (-1: the
    load no fiber carries, `uncarried`) and family sign, whether it failed in compression, and how the
    forces were found (an index of GROUPS). stress_a, stress_b : (n, F, 2) each family's fiber stress on the
    composite thickness as [per MPa, held] in the two branches of a mechanism (equal elsewhere); the
    stress at pressure p is the larger branch (9.2). family_layer, family_sign : (F,) Wall.families."""

    burst: np.ndarray
    layer: np.ndarray
    sign: np.ndarray
    compression: np.ndarray
    group: np.ndarray
    stress_a: np.ndarray
    stress_b: np.ndarray
    family_layer: np.ndarray
    family_sign: np.ndarray

    @property
    def index(self) -> int:
        return int(np.argmin(self.burst))

    @property
    def pressure(self) -> float:
        return float(self.burst[self.index])

    def stress(self, pressure: float) -> np.ndarray:
        """(n, F) each family's fiber stress (on the composite thickness) at `pressure`."""
        return np.maximum(self.stress_a[..., 0] * pressure + self.stress_a[..., 1],
                          self.stress_b[..., 0] * pressure + self.stress_b[..., 1])


def _layer_sums(wall: Wall, load: np.ndarray, span: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each layer's fiber force sum S (n, L) under [N_m, N_h] load (n, 2), two branches, and the axial and
    hoop loads the fibers leave uncarried (n, 2) bool-able magnitudes (mechanisms with no such fiber)."""
    c2, s2 = np.cos(wall.angle) ** 2, np.sin(wall.angle) ** 2
    et = wall.modulus * wall.thickness  # (n, L)
    # compatibility: one membrane strain [e_m, e_h], S_k = E t_k n_k . e (statics where two directions)
    k = np.stack([np.stack([np.sum(et * c2 * c2, 1), np.sum(et * c2 * s2, 1)], -1),
                  np.stack([np.sum(et * c2 * s2, 1), np.sum(et * s2 * s2, 1)], -1)], -2)
    safe = np.where(span[:, None, None], k, np.eye(2))
    strain = np.linalg.solve(safe, load[..., None])[..., 0]
    both = et * (c2 * strain[:, :1] + s2 * strain[:, 1:])
    # mechanism: the classic direction-wise netting, S = max(N_m / c^2, N_h / s^2) shared by E t
    total = np.maximum(np.sum(et, 1), 1e-300)
    cm, sm = np.sum(et * c2, 1) / total, np.sum(et * s2, 1) / total
    with np.errstate(divide="ignore", invalid="ignore"):
        by_m = np.where(cm > 1e-12, load[:, 0] / cm, 0.0)
        by_h = np.where(sm > 1e-12, load[:, 1] / sm, 0.0)
    share = et / total[:, None]
    a = np.where(span[:, None], both, share * by_m[:, None])
    b = np.where(span[:, None], both, share * by_h[:, None])
    uncarried = np.stack([np.where(~span & (cm <= 1e-12), load[:, 0], 0.0),
                          np.where(~span & (sm <= 1e-12), load[:, 1], 0.0)], -1)
    return a, b, uncarried


def _shear(wall: Wall, n_mh: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each helical layer's force difference D = f+ - f- (n, L) under the shear n_mh (n,), by compatibility
    of the fibers' shear strain (statics with one helical layer); and the shear no fiber carries (n,)."""
    sc = np.where(wall.helical, np.sin(wall.angle) * np.cos(wall.angle), 0.0)
    et = wall.modulus * wall.thickness
    stiff = np.sum(et * sc * sc, 1)
    gamma = np.where(stiff > 0.0, n_mh / np.where(stiff > 0.0, stiff, 1.0), 0.0)
    return et * sc * gamma[:, None], np.where(stiff > 0.0, 0.0, n_mh)


def family_stresses(wall: Wall, per_p: np.ndarray, held: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray,
                                                                               np.ndarray]:
    """Each family's fiber stress (n, F, 2) [per MPa, held] in the two branches, the loads no fiber carries
    (n, 3, 2) [per MPa, held] for [N_m, N_h, N_mh], and each station's GROUPS index (n,).

    per_p, held : (n, 3) [N_m, N_h, N_mh] per MPa of pressure and from the held loads (winder.analysis.loads)."""
    present = wall.thickness > 0.0
    c2 = np.where(present, np.cos(wall.angle) ** 2, np.nan)
    with np.errstate(invalid="ignore"):
        spread = np.where(present.any(1), np.nanmax(c2, 1) - np.nanmin(c2, 1), 0.0)
        steps = np.sum(np.diff(np.sort(c2, 1), axis=1) > SPAN_TOL, 1)
    span = spread > SPAN_TOL
    group = np.where(~span, 0, np.where(steps == 1, 1, 2))
    layer, sign = wall.families
    t = np.where(present, wall.thickness, np.inf)[:, layer]
    out_a, out_b, lost = [], [], []
    for load in (per_p, held):
        a, b, un = _layer_sums(wall, load[:, :2], span)
        d, un_shear = _shear(wall, load[:, 2])
        out_a.append((a[:, layer] + sign * d[:, layer]) / t)
        out_b.append((b[:, layer] + sign * d[:, layer]) / t)
        lost.append(np.column_stack([un, un_shear]))
    return np.stack(out_a, -1), np.stack(out_b, -1), np.stack(lost, -1), group


def _interval(slope: np.ndarray, value: np.ndarray, bound, above: bool) -> tuple[np.ndarray, np.ndarray]:
    """The pressures p >= 0 (an interval [lo, hi], lo > hi: none) where slope p + value >= bound (above)
    or <= bound."""
    if not above:
        slope, value, bound = -slope, -value, -np.asarray(bound)
    with np.errstate(divide="ignore", invalid="ignore"):
        cross = (bound - value) / slope
    lo = np.where(slope > 0.0, np.maximum(cross, 0.0), np.where(value >= bound, 0.0, np.inf))
    hi = np.where(slope < 0.0, cross, np.where((slope == 0.0) & (value < bound), -np.inf, np.inf))
    return lo, hi


def _least(interval: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
    lo, hi = interval
    return np.where(lo <= hi, lo, np.inf)


def limits(wall: Wall, per_p: np.ndarray, held: np.ndarray) -> NettingLimits:
    """The netting burst at each station (n): the least pressure at which a fiber family reaches its
    tension or compression allowable, with the held loads acting; 0 where they alone break it."""
    sa, sb, lost, group = family_stresses(wall, per_p, held)
    layer, sign = wall.families
    ft, fc = wall.tension[layer], wall.compression[layer]
    pulled = np.minimum(_least(_interval(sa[..., 0], sa[..., 1], ft, True)),
                        _least(_interval(sb[..., 0], sb[..., 1], ft, True)))
    lo_a, hi_a = _interval(sa[..., 0], sa[..., 1], -fc, False)
    lo_b, hi_b = _interval(sb[..., 0], sb[..., 1], -fc, False)
    pushed = _least((np.maximum(lo_a, lo_b), np.minimum(hi_a, hi_b)))
    present = (wall.thickness > 0.0)[:, layer]
    fail = np.where(present, np.minimum(pulled, pushed), np.inf)
    # a load no fiber carries breaks the net as soon as it is not zero
    unc = np.where(np.any(np.abs(lost) > 0.0, axis=(1, 2)), 0.0, np.inf)
    rows = np.arange(fail.shape[0])
    j = np.argmin(fail, 1)
    worst = fail[rows, j]
    burst = np.minimum(worst, unc)
    by_fiber = np.isfinite(worst) & (worst <= unc)
    return NettingLimits(burst=burst, layer=np.where(by_fiber, layer[j], -1), sign=np.where(by_fiber, sign[j], 0.0),
                         compression=by_fiber & (pushed[rows, j] < pulled[rows, j]), group=group,
                         stress_a=sa, stress_b=sb, family_layer=layer, family_sign=sign)


def cylinder_wall(helical_thickness, helical_angle, hoop_thickness: float, modulus: float = 1.0,
                  tension: float = 1.0, compression: float = math.inf) -> Wall:
    """One station of helical layers (thickness, angle rad: scalars or (k,)) and one hoop layer (at 90 deg)."""
    t = np.atleast_1d(np.asarray(helical_thickness, float))
    a = np.atleast_1d(np.asarray(helical_angle, float))
    k = t.size + 1
    return Wall(angle=np.append(a, 0.5 * np.pi)[None, :], thickness=np.append(t, hoop_thickness)[None, :],
                helical=np.array([True] * t.size + [False]), modulus=np.full(k, modulus),
                tension=np.full(k, tension), compression=np.full(k, compression))


def cylinder_loads(radius: float, closed: bool = True, axial_force: float = 0.0,
                   torque: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """A cylinder's [N_m, N_h, N_mh] per MPa and held (each (1, 3)), docs/math 9.1."""
    per_p = np.array([[0.5 * radius if closed else 0.0, radius, 0.0]])
    held = np.array([[axial_force / (2.0 * np.pi * radius), 0.0, torque / (2.0 * np.pi * radius ** 2)]])
    return per_p, held


def sizing(pressure: float, radius: float, sigma: float, angle: float, closed: bool = True,
           axial_force: float = 0.0, torque: float = 0.0) -> tuple[float, float]:
    """(helical, hoop) thickness (mm) a cylinder needs for the pressure with helical fibers at `angle`
    and hoops, each family at most at sigma (statically determinate, 9.2): the helical pair's force sum
    S = N_m / cos^2 a and difference D = N_mh / (sin a cos a) put its more loaded family at (S + |D|) / t_h;
    the hoops take N_h - S sin^2 a. Where that is negative (past the optimum angle) no hoops are needed."""
    n_m = (0.5 * pressure * radius if closed else 0.0) + axial_force / (2.0 * np.pi * radius)
    n_h = pressure * radius
    n_mh = torque / (2.0 * np.pi * radius ** 2)
    c2 = math.cos(angle) ** 2
    total = max(n_m, 0.0) / c2 if c2 > 0.0 else 0.0
    diff = abs(n_mh) / (math.sin(angle) * math.cos(angle)) if 0.0 < angle < 0.5 * math.pi else 0.0
    t_h = (total + diff) / sigma
    t_c = (n_h - total * math.sin(angle) ** 2) / sigma
    return t_h, max(t_c, 0.0)


def optimum_angle(n_m: float, n_h: float) -> float:
    """The helical angle (rad) at which a +-a net alone carries N_m and N_h: tan^2 a = N_h / N_m
    (atan(sqrt 2) for a closed cylinder under pressure); pi/2 where N_m <= 0 (hoops only)."""
    if n_m <= 0.0:
        return 0.5 * math.pi
    return math.atan(math.sqrt(max(n_h, 0.0) / n_m))
