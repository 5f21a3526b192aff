"""The 3D view `<name>.ply` (docs/guide/conventions.md): binary little-endian PLY written by trimesh's
exporter; `--format stl|obj|glb` write the same mesh through trimesh in those formats.

One triangle mesh with per-vertex RGBA colors (readable by trimesh and MeshLab):
- the mandrel surface: a grid over the internal station s in [0, length] and theta in [0, 2 pi),
  closed in theta, faces outward, colored MANDREL_COLOR (neutral gray);
- every fiber pass as a ribbon band_width wide, centred on the path in the surface's tangent plane:
  its sides at +-band_width/2 along N x d (N the outward normal, d the fiber direction), lifted by
  LAYER_OFFSET * layer index along N so each layer shows above the mandrel and the layers below.
  Color: the hue names the layer, the shade names the pass kind (KIND_SHADE: forward bright, return
  dark, hoop pale, dwell grayish); every band color is saturated, so no band has the mandrel's gray.
The mesh is not processed (no vertex merging), so the bytes are deterministic. STL carries no colors;
OBJ and GLB carry the vertex colors as trimesh writes them.
"""

from __future__ import annotations

import colorsys
import functools
import math
from typing import TYPE_CHECKING

import numpy as np

from winder.errors import ExportError
from winder.winding.results import FiberPass, PassKind, WindingPlan
from winder.geometry.measure import row_norms

if TYPE_CHECKING:
    import trimesh

MANDREL_COLOR = (190, 190, 190, 255)
LAYER_OFFSET = 0.05  # mm per layer index, along the outward normal
THETA_SAMPLES = 128  # mandrel grid around the section
MIN_STATIONS, MAX_STATIONS = 16, 2048  # mandrel grid along the axis (near-square cells in between)
GOLDEN = 0.618033988749895  # hue step between layers: far-apart hues for neighbouring layers
KIND_SHADE = {  # (saturation, value) of HSV
    PassKind.FORWARD: (0.85, 0.95),
    PassKind.RETURN: (0.85, 0.55),
    PassKind.HOOP: (0.45, 1.00),
    PassKind.DWELL: (0.30, 0.75),
    PassKind.TURNAROUND: (0.30, 0.90),
}


@functools.lru_cache(maxsize=256)
def band_color(layer: int, kind: PassKind) -> tuple[int, int, int, int]:
    """RGBA (0-255) of a band of the given layer (1-based) and pass kind."""
    hue = ((layer - 1) * GOLDEN) % 1.0
    sat, val = KIND_SHADE[kind]
    r, g, b = colorsys.hsv_to_rgb(hue, sat, val)
    return (int(round(255 * r)), int(round(255 * g)), int(round(255 * b)), 255)


def _mandrel(plan: WindingPlan) -> tuple[np.ndarray, int, int]:
    """The mandrel grid's vertices (ns nth, 3), station-major, and its size (ns, nth)."""
    surface = plan.surface
    nth = THETA_SAMPLES
    s_probe = np.linspace(0.0, surface.length, 65)
    th_probe = np.linspace(0.0, 2.0 * np.pi, 65)
    pts = surface.grid_points(s_probe, th_probe).reshape(65, 65, 3)
    meridian = float(np.max(np.sum(np.linalg.norm(np.diff(pts, axis=0), axis=2), axis=0)))
    perimeter = float(np.max(np.sum(np.linalg.norm(np.diff(pts, axis=1), axis=2), axis=1)))
    ns = int(np.clip(math.ceil(meridian / max(perimeter / nth, 1e-9)) + 1, MIN_STATIONS, MAX_STATIONS))
    s = np.linspace(0.0, surface.length, ns)
    th = np.linspace(0.0, 2.0 * np.pi, nth, endpoint=False)
    return surface.grid_points(s, th), ns, nth


def _mandrel_faces(ns: int, nth: int, out: np.ndarray) -> None:
    """The grid's faces into out (2 (ns - 1) nth, 3): the first triangle of every cell, cells
    station-major, then the second; closed in theta."""
    row = (np.arange(ns - 1) * nth)[:, None]
    j = np.arange(nth)
    v00, v01 = (row + j).ravel(), (row + (j + 1) % nth).ravel()
    v10, v11 = v00 + nth, v01 + nth
    k = v00.size
    # Phi_theta x Phi_s points outward (SweepSurface.normals): (v00, v01, v10) is counter-clockwise.
    for col, (a, b) in enumerate(((v00, v01), (v01, v11), (v10, v10))):
        out[:k, col] = a
        out[k:, col] = b


def _ribbons(plan: WindingPlan, passes: list[FiberPass], band_width: float) -> tuple[np.ndarray, np.ndarray]:
    """The ribbons of passes of one layer (each >= 2 points), one after the other: vertices (2 m, 3),
    two per point (left, right), and faces (2 (m - passes), 3) indexing them, pass by pass the first
    triangle of every interval, then the second. One surface evaluation for the whole layer."""
    sizes = np.array([len(fp.points) for fp in passes])
    nrm = plan.surface_of(passes[0].layer).normals(np.concatenate([np.asarray(fp.s, float) for fp in passes]),
                                                   np.concatenate([np.asarray(fp.theta, float) for fp in passes]))
    d = np.concatenate([np.asarray(fp.direction, dtype=float) for fp in passes])
    side = np.cross(nrm, d)
    side /= row_norms(side)[:, None]
    points = np.concatenate([np.asarray(fp.points, dtype=float) for fp in passes])
    centre = points + LAYER_OFFSET * passes[0].layer * nrm
    left = centre - 0.5 * band_width * side
    right = centre + 0.5 * band_width * side
    verts = np.empty((2 * len(d), 3))
    verts[0::2], verts[1::2] = left, right
    last = np.zeros(len(d), dtype=bool)
    last[np.cumsum(sizes) - 1] = True
    k = np.flatnonzero(~last)  # every interval's first point
    lo, ro, ln, rn = 2 * k, 2 * k + 1, 2 * k + 2, 2 * k + 3
    # side = N x d, so (left, right-next, right) and (left, left-next, right-next) face along +N.
    # Pass by pass (its intervals from cumsum(n) - n in k): its first triangles, then its second.
    n = sizes - 1
    start = np.repeat(2 * (np.cumsum(n) - n), n)
    i = np.arange(k.size) - np.repeat(np.cumsum(n) - n, n)
    faces = np.empty((2 * k.size, 3), dtype=np.int64)
    first, second = start + i, start + np.repeat(n, n) + i
    for col, (a, b) in enumerate(((lo, lo), (rn, ln), (ro, rn))):  # a column at a time: no (k, 3) temporaries
        faces[first, col] = a
        faces[second, col] = b
    _face_outward(verts, faces, nrm)
    return verts, faces


def _face_outward(verts: np.ndarray, faces: np.ndarray, nrm: np.ndarray) -> None:
    """Swap the winding of the faces (f, 3) whose normal points into the mandrel, in place: a pass
    whose points run against its fiber direction d (a dwell's ribbon, where the carriage stands and
    d is the fiber's) would otherwise face inward. nrm (v / 2, 3): the outward normal at each point."""
    a, b, c = verts[faces[:, 0]], verts[faces[:, 1]], verts[faces[:, 2]]
    out = nrm[faces[:, 0] // 2] + nrm[faces[:, 1] // 2] + nrm[faces[:, 2] // 2]
    inward = np.einsum("ij,ij->i", np.cross(b - a, c - a), out) < 0.0
    faces[inward, 1], faces[inward, 2] = faces[inward, 2], faces[inward, 1].copy()


def _band_pieces(plan: WindingPlan, band_width: float) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """Each layer's ribbons (winding order): vertices (v, 3) float, faces (f, 3) int indexing them,
    vertex colors (v, 4) uint8 RGBA."""
    if not (math.isfinite(band_width) and band_width > 0.0):
        raise ExportError(f"{plan.source}: winding.band_width: must be > 0 for the PLY bands, got {band_width!r}")
    pieces = []
    for layer in plan.layers:
        passes = [fp for fp in layer.passes if len(fp.points) >= 2]
        if not passes:
            continue
        v, f = _ribbons(plan, passes, band_width)
        shade = np.array([band_color(fp.layer, fp.kind) for fp in passes], dtype=np.uint8)
        pieces.append((v, f, np.repeat(shade, [2 * len(fp.points) for fp in passes], axis=0)))
    return pieces


def mesh(plan: WindingPlan, band_width: float) -> trimesh.Trimesh:
    """The colored mesh, unprocessed: the mandrel first, then the bands in winding order."""
    import trimesh  # noqa: PLC0415 - only when a mesh is written

    pieces = _band_pieces(plan, band_width)
    verts, ns, nth = _mandrel(plan)
    mandrel_faces = np.empty((2 * (ns - 1) * nth, 3), dtype=np.int64)
    _mandrel_faces(ns, nth, mandrel_faces)
    offsets = np.cumsum([len(verts)] + [len(v) for v, _, _ in pieces])
    return trimesh.Trimesh(
        vertices=np.concatenate([verts] + [v for v, _, _ in pieces]),
        faces=np.concatenate([mandrel_faces] + [f + off for (_, f, _), off in zip(pieces, offsets)]),
        vertex_colors=np.concatenate([np.tile(np.array(MANDREL_COLOR, dtype=np.uint8), (len(verts), 1))]
                                     + [c for _, _, c in pieces]),
        process=False, validate=False)


def ply_bytes(plan: WindingPlan, band_width: float) -> bytes:
    """The binary PLY file's bytes (float32 xyz, uchar RGBA, triangle faces)."""
    return mesh(plan, band_width).export(file_type="ply", encoding="binary")


def export(plan: WindingPlan, job) -> bytes:
    """The registry's entry for `ply` (winder.export.registry)."""
    return ply_bytes(plan, job.winding.band_width)


def export_stl(plan: WindingPlan, job) -> bytes:
    """The registry's entry for `stl`: binary STL, no colors."""
    return mesh(plan, job.winding.band_width).export(file_type="stl")


def export_obj(plan: WindingPlan, job) -> str:
    """The registry's entry for `obj`: Wavefront OBJ text with the vertex colors."""
    return mesh(plan, job.winding.band_width).export(file_type="obj")


def export_glb(plan: WindingPlan, job) -> bytes:
    """The registry's entry for `glb`: binary glTF with the vertex colors."""
    return mesh(plan, job.winding.band_width).export(file_type="glb")
