"""The PLY view: readable by trimesh, bands of the right area, colors by layer and pass kind."""

from __future__ import annotations

import io

import numpy as np
import pytest
import trimesh

from conftest import surface_of
from plans import cylinder_plan, geodesic_pass, make_layer
from winder.config.axes import ArcAxis
from winder.config.mandrel import ConstantProfile, LineAxis
from winder.errors import ExportError
from winder.export.ply import MANDREL_COLOR, band_color, ply_bytes
from winder.winding.results import PassKind, WindingPlan

AREA_REL = 0.01  # band area against fiber length x band width (brief: 1 %)
MANDREL_AREA_REL = 1e-3  # a 128-gon cylinder: area factor 1 - (pi/128)^2 / 6 ~ 1 - 1e-4
BAND = 8.0
R = 40.0


@pytest.fixture(scope="module")
def plan():
    return cylinder_plan(surface_of(LineAxis(300.0), ConstantProfile(R)))


def load(data: bytes, process: bool = False) -> trimesh.Trimesh:
    return trimesh.load(io.BytesIO(data), file_type="ply", process=process)


def band_faces(mesh: trimesh.Trimesh) -> np.ndarray:
    """Faces whose vertices all carry a saturated color (the mandrel is neutral gray)."""
    rgb = mesh.visual.vertex_colors[:, :3].astype(int)
    saturated = (rgb.max(axis=1) - rgb.min(axis=1)) > 20
    return saturated[mesh.faces].all(axis=1)


def test_loads_and_is_binary(plan):
    data = ply_bytes(plan, BAND)
    assert data.startswith(b"ply\nformat binary_little_endian 1.0\n")
    mesh = load(data)
    assert len(mesh.faces) > 1000
    assert mesh.visual.kind == "vertex"
    assert len(load(data, process=True).faces) > 0  # trimesh's default (merging) load works too


def test_band_area_is_length_times_width(plan):
    mesh = load(ply_bytes(plan, BAND))
    bands = band_faces(mesh)
    area = float(mesh.area_faces[bands].sum())
    length = plan.total_fiber_length_mm
    assert abs(area - length * BAND) / (length * BAND) < AREA_REL


def test_mandrel_area_and_outward_faces(plan):
    mesh = load(ply_bytes(plan, BAND))
    mandrel = ~band_faces(mesh)
    assert np.all(mesh.visual.vertex_colors[mesh.faces[mandrel].ravel()] == MANDREL_COLOR)
    area = float(mesh.area_faces[mandrel].sum())
    assert abs(area - 2 * np.pi * R * 300.0) / (2 * np.pi * R * 300.0) < MANDREL_AREA_REL
    # Outward: every face normal points away from the axis (mandrel and bands alike).
    centres = mesh.triangles_center
    radial = centres[:, :2] / np.linalg.norm(centres[:, :2], axis=1)[:, None]
    assert (np.einsum("ij,ij->i", mesh.face_normals[:, :2], radial) > 0.5).all()


def test_bands_lifted_per_layer(plan):
    mesh = load(ply_bytes(plan, BAND))
    v = mesh.vertices
    r = np.hypot(v[:, 0], v[:, 1])
    colors = mesh.visual.vertex_colors
    for layer, kind, lift, alpha in ((1, PassKind.FORWARD, 0.05, 55.0), (1, PassKind.RETURN, 0.05, 55.0),
                                     (1, PassKind.DWELL, 0.05, 90.0), (2, PassKind.HOOP, 0.10, 86.0)):
        sel = np.all(colors == band_color(layer, kind), axis=1)
        assert sel.any()
        # Band edges are half a band width out along the tangent plane, across a helix at alpha:
        # (B/2) cos(alpha) around the section, (B/2) sin(alpha) along the axis.
        half_around = BAND / 2 * np.cos(np.radians(alpha))
        assert np.allclose(r[sel], np.hypot(R + lift, half_around), atol=1e-4)


def test_colors_distinct_by_layer_and_kind():
    colors = {band_color(layer, kind) for layer in (1, 2, 3) for kind in PassKind}
    assert len(colors) == 3 * len(PassKind)
    assert MANDREL_COLOR not in colors
    for c in colors:
        assert max(c[:3]) - min(c[:3]) > 20


def test_deterministic_bytes(plan):
    assert ply_bytes(plan, BAND) == ply_bytes(plan, BAND)


def test_bent_mandrel_band_area():
    bend = surface_of(ArcAxis(150.0, 90.0), ConstantProfile(40.0))
    fw = geodesic_pass(bend, (20.0, 0.0), (215.0, np.radians(150.0)), 200, rounds=1, layer=1, circuit=1,
                       number=1, kind=PassKind.FORWARD)
    plan = WindingPlan("elbow", "elbow.yaml", bend, (make_layer(1, [fw], circuits=1),))
    mesh = load(ply_bytes(plan, 5.0))
    area = float(mesh.area_faces[band_faces(mesh)].sum())
    assert abs(area - fw.length * 5.0) / (fw.length * 5.0) < AREA_REL


def test_bad_band_width(plan):
    with pytest.raises(ExportError, match="band_width"):
        ply_bytes(plan, 0.0)


def _assembled(plan: WindingPlan, band_width: float) -> bytes:
    """The file built the plain way: the whole mesh's arrays concatenated (mandrel faces from the
    meshgrid, every piece's faces offset by the vertices before it), then cast into the records."""
    from winder.export.ply import _HEADER, _mandrel, _ribbons  # noqa: PLC0415

    verts, ns, nth = _mandrel(plan)
    i, j = (a.ravel() for a in np.meshgrid(np.arange(ns - 1), np.arange(nth), indexing="ij"))
    v00, v01, v10, v11 = i * nth + j, i * nth + (j + 1) % nth, (i + 1) * nth + j, (i + 1) * nth + (j + 1) % nth
    all_v = [verts]
    all_f = [np.concatenate([np.column_stack([v00, v01, v10]), np.column_stack([v01, v11, v10])])]
    colors = [np.tile(np.array(MANDREL_COLOR, dtype=np.uint8), (len(verts), 1))]
    base = len(verts)
    for layer in plan.layers:
        passes = [fp for fp in layer.passes if len(fp.points) >= 2]
        v, f = _ribbons(plan, passes, band_width)
        all_v.append(v)
        all_f.append(f + base)
        shade = np.array([band_color(fp.layer, fp.kind) for fp in passes], dtype=np.uint8)
        colors.append(np.repeat(shade, [2 * len(fp.points) for fp in passes], axis=0))
        base += len(v)
    verts, faces = np.concatenate(all_v), np.concatenate(all_f)
    vertex = np.empty(len(verts), dtype=[("xyz", "<f4", (3,)), ("rgba", "u1", (4,))])
    vertex["xyz"], vertex["rgba"] = verts, np.concatenate(colors)
    face = np.empty(len(faces), dtype=[("count", "u1"), ("index", "<i4", (3,))])
    face["count"], face["index"] = 3, faces
    return b"".join([_HEADER.format(v=len(verts), f=len(faces)).encode("ascii"), vertex.data, face.data])


def test_pieces_written_in_place_are_the_assembled_mesh(plan):
    assert ply_bytes(plan, BAND) == _assembled(plan, BAND)
    bend = surface_of(ArcAxis(150.0, 90.0), ConstantProfile(40.0))
    fw = geodesic_pass(bend, (20.0, 0.0), (215.0, np.radians(150.0)), 60, layer=1, circuit=1, number=1,
                       kind=PassKind.FORWARD)
    bent = WindingPlan("elbow", "elbow.yaml", bend, (make_layer(1, [fw], circuits=1),))
    assert ply_bytes(bent, 5.0) == _assembled(bent, 5.0)
