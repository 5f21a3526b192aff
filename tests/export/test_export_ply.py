"""The PLY view: readable by trimesh, bands of the right area, colors by layer and pass kind."""

from __future__ import annotations

import io
from types import SimpleNamespace

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
FORMAT_AREA_REL = 1e-5  # one mesh in two files: float32 coordinates (OBJ prints 8 significant digits)
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


@pytest.mark.parametrize("name", ["stl", "obj", "glb"])
def test_other_mesh_formats_are_the_same_mesh(plan, name):
    """--format stl|obj|glb: the PLY's mesh through trimesh's exporters, read back by trimesh (STL
    stores float32 facets without colors; OBJ and GLB keep the vertex colors)."""
    from winder.export.registry import chosen  # noqa: PLC0415

    (fmt,) = chosen([name], always=False)
    job = SimpleNamespace(winding=SimpleNamespace(band_width=BAND))
    got = trimesh.load(io.BytesIO(fmt.render(plan, job)), file_type=name, force="mesh", process=False)
    ply = load(ply_bytes(plan, BAND))
    assert len(got.faces) == len(ply.faces)
    assert abs(got.area - ply.area) <= FORMAT_AREA_REL * ply.area
    if name != "stl":
        assert got.visual.kind == "vertex"
        assert np.array_equal(np.unique(got.visual.vertex_colors, axis=0), np.unique(ply.visual.vertex_colors, axis=0))
