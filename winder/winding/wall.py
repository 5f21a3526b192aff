"""The laminate wall of a job, layer on layer (docs/math/08-laminate-edges.md; docs/math/08-laminate-edges.md).

After each layer is planned, `Buildup.add` measures what it laid (thickness per station from its
bands, volume, masses, the winding angle per station), grows the mandrel by it, and hands the grown
surface to the next layer: layer k + 1 is planned on the mandrel grown by layers 1..k, so its angles,
Clairaut turnarounds, pattern and eye positions follow the grown part. Each layer's record keeps the
surface it was wound on.
"""

from __future__ import annotations

import dataclasses
from dataclasses import asdict, replace

import numpy as np

from winder.config.material import MaterialConfig
from winder.errors import SolverError
from winder.geometry.interp import interp_spline
from winder.geometry.offset import OffsetError
from winder.geometry.surface import SweepSurface
from winder.geometry.vessel import VesselMeridian
from winder.winding.buildup import StationCells, area_rate, index_of, layer_density, station_cells
from winder.winding.growth import grown, smooth_thickness
from winder.winding.laminate import Material
from winder.winding.passes import PlanContext, winding_region
from winder.winding.results import LayerPlan, PassKind


@dataclasses.dataclass(frozen=True, eq=False)
class LayerLaminate:
    """What one layer adds to the wall.

    ply_mm : t_p of its material. thickness_mm : mean thickness at the reference station (t_ref);
    max_thickness_mm : the largest per-station mean (at a vessel's turnarounds).
    volume_mm3 : composite volume laid (= fiber length x composite area). fiber_mass_kg,
    resin_mass_kg : NaN when the material gives no densities. material_length_mm : tow drawn (fiber
    length x tows). outer_radius_mm : mean radius of the grown mandrel at t_ref after this layer.
    t, s : (k,) float, stations (axial, internal) of the cells on the surface it was wound on;
    thickness : (k,) float, its mean thickness there (mm); angle_deg : (k,) float, the length-weighted
    mean |winding angle| of its fiber there (NaN where it lays none).
    """

    ply_mm: float
    thickness_mm: float
    max_thickness_mm: float
    volume_mm3: float
    fiber_mass_kg: float
    resin_mass_kg: float
    material_length_mm: float
    outer_radius_mm: float
    t: np.ndarray
    s: np.ndarray
    thickness: np.ndarray
    angle_deg: np.ndarray


def _turnarounds(surface: SweepSurface, layer: LayerPlan) -> tuple[float, ...]:
    """Where a vessel's helical passes turn tangent to a parallel: their end stations."""
    if not isinstance(surface.profile, VesselMeridian):
        return ()
    first = next((p for p in layer.passes if p.kind is PassKind.FORWARD), None)
    return () if first is None else (float(first.s[0]), float(first.s[-1]))


def layer_angles(cells: StationCells, layer: LayerPlan) -> np.ndarray:
    """Mean |winding angle| (deg) of a layer's fiber per cell, weighted by the fiber length there."""
    num, den = np.zeros(cells.centres.size), np.zeros(cells.centres.size)
    # Circuits on a surface of revolution are turned copies: the same stations, so the same cells
    # at the same fractional indices (found once per stations).
    found: dict[bytes, tuple[np.ndarray, np.ndarray, np.ndarray] | None] = {}
    for p in layer.passes:
        if p.kind is PassKind.DWELL or np.ptp(p.s) <= 0.0:
            continue
        key = p.s.tobytes()
        if key not in found:
            found[key] = _cells_crossed(cells, p.s)
        if found[key] is None:
            continue
        inside, idx, at = found[key]
        alpha = np.interp(at, idx, np.abs(p.alpha_deg))  # |alpha|: +90 on a parallel joins either sign
        # the crossing's weight: fiber length per station, 1 / cos(alpha) (capped at a turnaround)
        w = 1.0 / np.maximum(np.cos(np.radians(alpha)), 1e-3)
        num[inside] += w * alpha
        den[inside] += w
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(den > 0.0, num / den, np.nan)


def _cells_crossed(cells: StationCells, s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """(inside (k,) bool: the cells whose centres the stations s (m,) span, idx (m,): the point
    indices, at: the fractional point index of each such centre), or None where it spans none."""
    lo, hi = min(s[0], s[-1]), max(s[0], s[-1])
    inside = (cells.centres >= lo) & (cells.centres <= hi)
    if not np.any(inside):
        return None
    idx = np.arange(s.size, dtype=float)
    return inside, idx, index_of(interp_spline(idx, s), s, cells.centres[inside])


def _fill(angle: np.ndarray, laid: np.ndarray) -> np.ndarray:
    """Angles where fiber lies but no pass crosses: a vessel turnaround's band beyond its centre line
    and a dwell's ring both run along the parallel there, at 90 deg."""
    return np.where(laid & np.isnan(angle), 90.0, angle)


def reference_station(surface: SweepSurface, region: tuple[float, float], band_width: float) -> float:
    """t of the reference section: a vessel's mid-cylinder; else the largest section of the region at
    least a band width inside its ends (the middle one of equals)."""
    prof = surface.profile
    if isinstance(prof, VesselMeridian):
        return float(0.5 * sum(prof.equator_t))
    a, b = region
    if b - a > 4.0 * band_width:
        a, b = a + band_width, b - band_width
    t = np.linspace(a, b, 201)
    per = surface.perimeter(surface.s_of_t(t))
    best = np.nonzero(per >= per.max() * (1.0 - 1e-9))[0]
    return float(t[best[best.size // 2]])


def mean_radius(surface: SweepSurface, t: float) -> float:
    """Mean radius (perimeter / 2 pi) of the section at axial station t."""
    return float(surface.perimeter(surface.s_of_t(np.array([t])))[0] / (2.0 * np.pi))


@dataclasses.dataclass(frozen=True)
class Buildup:
    """The build-up state between layers: the surface the next layer winds on."""

    surface: SweepSurface
    band_width: float
    t_ref: float
    source: str = ""

    def add(self, layer: LayerPlan, material: Material, key: str) -> tuple[LayerPlan, Buildup]:
        """The layer with its laminate record and surface, and the state for the next layer.

        key : how messages name the layer (`job.yaml: layer 5 (helical 16 deg)`: PlanContext.key). Raises
        SolverError where the grown mandrel is not a regular surface (a laminate folding over a concave region).
        """
        surf, band = self.surface, self.band_width
        area = material.composite_area(band)
        cells = station_cells(surf, band)
        turns = _turnarounds(surf, layer)
        volumes: dict = {}  # each pass's volumes, for both densities
        density = layer_density(surf, cells, layer.passes, area, band, turns, seen=volumes)
        thickness = density / area_rate(surf, cells.centres)
        # the dwells' rings lie at an open mandrel's very ends, where the next layer turns too: the
        # shape it winds on leaves them out (hoops would slip on them), the wall keeps them
        laid = layer_density(surf, cells, layer.passes, area, band, turns, dwells=False, seen=volumes)
        try:
            nxt = grown(surf, cells, smooth_thickness(surf, cells, laid, band))
        except OffsetError as exc:
            raise SolverError(f"{key}: the mandrel grown by this layer is not a smooth surface: {exc}") from exc
        s_ref = float(surf.s_of_t(np.array([self.t_ref]))[0])
        length = layer.fiber_length_mm
        record = LayerLaminate(
            ply_mm=material.ply(band),
            thickness_mm=float(np.interp(s_ref, cells.centres, thickness)),
            max_thickness_mm=float(thickness.max()),
            volume_mm3=float(np.sum(density * cells.widths)),
            fiber_mass_kg=material.fiber_mass_kg(length, band),
            resin_mass_kg=material.resin_mass_kg(length, band),
            material_length_mm=material.material_length_mm(length),
            outer_radius_mm=mean_radius(nxt, self.t_ref),
            t=surf.t_of_s(cells.centres), s=cells.centres, thickness=thickness,
            angle_deg=_fill(layer_angles(cells, layer), thickness > 0.0))
        return replace(layer, surface=surf, laminate=record), replace(self, surface=nxt)


def material_of(cfg: MaterialConfig) -> Material:
    """The laminate Material of a MaterialConfig."""
    return Material(**asdict(cfg))


def start_buildup(ctx: PlanContext) -> Buildup:
    """The build-up state before the first layer (ctx: the planner's PlanContext)."""
    region = winding_region(ctx)
    band = ctx.winding.band_width
    return Buildup(ctx.surface, band, reference_station(ctx.surface, region, band), ctx.job.source)
