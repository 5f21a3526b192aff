"""The wall at the bosses (docs/math/08-laminate-edges.md 8.11): on each dome of a vessel, the largest
sum of the layers' reported thicknesses, each read at the foot of the bare point on its own surface,
and the bare radius where it is."""

from __future__ import annotations

import dataclasses
from collections.abc import Iterator

import numpy as np

from winder.geometry.vessel import VesselMeridian
from winder.winding.results import WindingPlan

WALL_SAMPLES = 4001  # points of each meridian polyline and of each bare dome


@dataclasses.dataclass(frozen=True)
class DomeWall:
    """One dome's wall: the bare mandrel's opening radius, the largest wall (mm) and the bare radius
    (mm) where it is."""

    opening_radius_mm: float
    max_wall_mm: float
    max_wall_radius_mm: float


def _foot(points: np.ndarray, prof: VesselMeridian) -> np.ndarray:
    """Station (m,) on the meridian of prof nearest each point (m, 2) as (z, r): on one of the two
    segments of its polyline around the point's nearest vertex."""
    from scipy.spatial import cKDTree  # noqa: PLC0415 - vessels with a laminate only

    s = np.linspace(0.0, prof.length, WALL_SAMPLES)
    ev = prof.evaluate(s)
    line = np.column_stack([ev.z, ev.r])
    _, k = cKDTree(line).query(points)
    best, station = np.full(points.shape[0], np.inf), np.zeros(points.shape[0])
    for j in (np.maximum(k - 1, 0), np.minimum(k, s.size - 2)):
        a, seg = line[j], line[j + 1] - line[j]
        u = np.clip(np.einsum("ij,ij->i", points - a, seg) / np.einsum("ij,ij->i", seg, seg), 0.0, 1.0)
        d = np.linalg.norm(points - a - u[:, None] * seg, axis=1)
        nearer = d < best
        best[nearer], station[nearer] = d[nearer], (s[j] + u * (s[j + 1] - s[j]))[nearer]
    return station


def layer_walls(plan: WindingPlan, bare: np.ndarray) -> np.ndarray:
    """Each layer's reported thickness (mm), (layers, m), at points (m, 2) as (z, r) of the bare mandrel's
    meridian: read at the foot of each point on the surface the layer was wound on."""
    out = np.zeros((len(plan.layers), bare.shape[0]))
    for k, layer in enumerate(plan.layers):
        lam = layer.laminate
        out[k] = np.interp(_foot(bare, plan.surface_of(layer.index).profile), lam.s, lam.thickness, left=0.0, right=0.0)
    return out


def wall_at(plan: WindingPlan, bare: np.ndarray) -> np.ndarray:
    """W (m,) (mm) at points (m, 2) as (z, r) of the bare mandrel's meridian (module docstring)."""
    return layer_walls(plan, bare).sum(axis=0)


def walls_by_layer(plan: WindingPlan, bare: np.ndarray) -> Iterator[np.ndarray]:
    """The wall (m,) (mm) at the bare points (m, 2) as (z, r) after each layer in turn: layers 1..k
    for k = 1, 2, .. (wall_at's sum, one layer more each time)."""
    yield from np.cumsum(layer_walls(plan, bare), axis=0)


def dome_walls(plan: WindingPlan) -> tuple[DomeWall, DomeWall] | None:
    """The first and the end dome's walls; None unless the mandrel is a vessel of revolution and
    every layer has a laminate (a material)."""
    prof = plan.surface.profile
    if not (isinstance(prof, VesselMeridian) and plan.surface.is_revolution and plan.layers
            and all(layer.laminate is not None for layer in plan.layers)):
        return None
    # Both domes' bare points in one reading of each layer's meridian.
    ev = prof.evaluate(np.concatenate([np.linspace(*prof.dome_ranges.dome, WALL_SAMPLES),
                                       np.linspace(*prof.dome_ranges.end_dome, WALL_SAMPLES)]))
    wall = wall_at(plan, np.column_stack([ev.z, ev.r])).reshape(2, WALL_SAMPLES)
    r = ev.r.reshape(2, WALL_SAMPLES)
    first, end = (DomeWall(float(opening), float(w.max()), float(radius[int(np.argmax(w))]))
                  for opening, w, radius in ((r[0, 0], wall[0], r[0]), (r[1, -1], wall[1], r[1])))
    return first, end
