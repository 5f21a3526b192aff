"""The part as wound so far: what the payout eye's body keeps its clearance from.

While layer k is laid the part is the mandrel grown by layers 1..k. The grown surface each layer is
planned on (winder.winding.wall) keeps the bare mandrel's axial frame: on a vessel it is trimmed at
the polar-opening planes. But the laminate at a dome's turnarounds piles up (a wall of 10 mm and more
a few millimetres inside the opening plane on a 20-layer tank), and the dome's normal runs nearly
along the axis there: the laminate stands out past the opening plane, where the trimmed surface has
nothing, and an eye kept its clearance from the bare boss region instead (13.8 mm of 30 from the
wound dome of a 22-layer tank). So the part as wound is taken as the larger of

- the grown surface's largest section radius r_max(t) over [t_start, T] (a grown vessel's domes stand
  past the opening planes too, docs/math/17 17.8, but the smoothing lowers a pile-up's crest), and
- on a vessel of revolution with a laminate, the bare meridian moved out along its normal by the wall
  wound so far (winder.winding.dome_wall: the layers' thicknesses summed at the foot of each bare
  point on each layer's own surface, the summary's dome wall), not trimmed: it runs past the
  opening planes as the laminate does.

The eye envelope clears the finished part (every layer, winder.machine.envelope); the invariants
measure each layer's moves against the part as wound by then (winder.machine.invariants).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from winder.geometry.surface import SweepSurface
from winder.geometry.vessel import VesselMeridian
from winder.machine.envelope import ENVELOPE_MAX_SAMPLES, ENVELOPE_STEP, section_top
from winder.winding.results import WindingPlan

BARE_SAMPLES = 8001  # points of the bare meridian moved out by the wall


@dataclasses.dataclass(frozen=True, eq=False)
class WoundProfile:
    """The part as wound by some layers (module docstring).

    surface : the mandrel grown by them. wall_z, wall_r : (j,) float, the bare meridian moved out by
    their wall, as (t, r) (empty where the mandrel is no vessel of revolution with a laminate).
    """

    surface: SweepSurface
    wall_z: np.ndarray
    wall_r: np.ndarray

    @property
    def span(self) -> tuple[float, float]:
        """The stations the part covers: [0, T] and wherever the wall stands past them."""
        T, t0 = float(self.surface.axial_length), float(self.surface.t_start)
        if self.wall_z.size == 0:
            return t0, T
        return min(t0, float(self.wall_z.min())), max(T, float(self.wall_z.max()))

    def beyond(self, stations: np.ndarray) -> np.ndarray:
        """The wall's largest radius at the stations (k,), -inf where it has none."""
        return upper_envelope(self.wall_z, self.wall_r, np.asarray(stations, dtype=float))

    def table(self, step: float = ENVELOPE_STEP) -> tuple[np.ndarray, np.ndarray]:
        """(stations (k,), r_max (k,)): the part's largest radius on uniform stations over its span,
        about `step` apart; 0 where it has nothing."""
        lo, hi = self.span
        n = int(min(ENVELOPE_MAX_SAMPLES, max(257, np.ceil((hi - lo) / step) + 1)))
        stations = np.linspace(lo, hi, n)
        inside = (stations >= self.surface.t_start) & (stations <= self.surface.axial_length)
        r = np.maximum(self.beyond(stations), 0.0)
        r[inside] = np.maximum(r[inside], section_top(self.surface, stations[inside]))
        return stations, r


def upper_envelope(z: np.ndarray, r: np.ndarray, stations: np.ndarray) -> np.ndarray:
    """The largest r of the polyline (z, r) (j,) (z in any order: a fold counts with both sheets) at
    the increasing stations (k,): each segment read where it spans a station, and each vertex raising
    its two neighbouring stations (a peak between them is not lost); -inf where none reaches."""
    out = np.full(stations.shape, -np.inf)
    if z.size < 2 or stations.size == 0:
        return out
    a, b, ra, rb = z[:-1], z[1:], r[:-1], r[1:]
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    first = np.searchsorted(stations, lo, side="left")
    count = np.searchsorted(stations, hi, side="right") - first
    seg = np.repeat(np.arange(a.size), count)
    j = first[seg] + np.arange(seg.size) - np.repeat(np.cumsum(count) - count, count)
    span = b - a
    f = np.where(span[seg] != 0.0, (stations[j] - a[seg]) / np.where(span[seg] != 0.0, span[seg], 1.0), 0.0)
    value = np.where(span[seg] != 0.0, ra[seg] + f * (rb - ra)[seg], np.maximum(ra, rb)[seg])
    np.maximum.at(out, j, value)
    near = np.searchsorted(stations, z)
    for k in (near - 1, near):
        ok = (k >= 0) & (k < stations.size)
        np.maximum.at(out, k[ok], r[ok])
    return out


def wound_profiles(plan: WindingPlan) -> list[WoundProfile]:
    """The part as wound after each layer, in order (one per layer of the plan)."""
    surfaces = [plan.surface_of(layer.index + 1) if layer.index < len(plan.layers) else plan.outer_surface
                for layer in plan.layers]
    walls = _walls(plan)
    if walls is None:
        empty = np.zeros(0)
        return [WoundProfile(s, empty, empty) for s in surfaces]
    return [WoundProfile(s, z, r) for s, (z, r) in zip(surfaces, walls)]


def finished_part(plan: WindingPlan) -> WoundProfile | None:
    """The part as wound by every layer where its wall stands past the grown surface's frame (a
    vessel with a laminate), else None (the grown surface is the whole part)."""
    walls = _walls(plan, last_only=True)
    if walls is None:
        return None
    z, r = walls[-1]
    return WoundProfile(plan.outer_surface, z, r)


def _walls(plan: WindingPlan, last_only: bool = False) -> list[tuple[np.ndarray, np.ndarray]] | None:
    """Per layer (or the last alone) the bare meridian moved out by the wall wound by then, as
    (t (j,), r (j,)); None unless the plan is a vessel of revolution whose every layer has a laminate."""
    prof = plan.surface.profile
    if not (isinstance(prof, VesselMeridian) and plan.surface.is_revolution and plan.layers
            and all(layer.laminate is not None for layer in plan.layers)):
        return None
    from winder.winding.dome_wall import walls_by_layer  # noqa: PLC0415 - vessels with a laminate only

    ev = prof.evaluate(np.linspace(0.0, prof.length, BARE_SAMPLES))
    speed = np.hypot(ev.z1, ev.r1)
    normal = np.column_stack([-ev.r1, ev.z1]) / speed[:, None]  # outward: +r on the cylinder
    bare = np.column_stack([ev.z, ev.r])
    out = []
    for wall in walls_by_layer(plan, bare):
        if not last_only:
            out.append(_moved(bare, normal, wall))
    if last_only:
        out.append(_moved(bare, normal, wall))
    return out


def _moved(bare: np.ndarray, normal: np.ndarray, wall: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    moved = bare + wall[:, None] * normal
    return moved[:, 0], moved[:, 1]
