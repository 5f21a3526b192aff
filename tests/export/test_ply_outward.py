"""Every face of every PLY faces outward, mandrel and bands, on every sample and config, read with
trimesh and judged from the mesh alone (not from winder's surface normals): a mandrel face against
the direction from the mandrel's axis (the centre of its ring of the grid, THETA_SAMPLES vertices a
station), a band face against the mandrel mesh's own vertex normal nearest to it."""

from __future__ import annotations

import io

import numpy as np
import pytest
from scipy.spatial import cKDTree

from every_job import EVERY, IDS, job_of, planned
from winder.export.ply import MANDREL_COLOR, THETA_SAMPLES, ply_bytes

AREA_TOL = 1e-9  # mm^2: faces smaller than this have no direction to check


def inward_faces(data: bytes) -> tuple[int, int, int]:
    """(mandrel faces inward, band faces inward, faces) of a winder PLY."""
    import trimesh  # noqa: PLC0415

    mesh = trimesh.load(io.BytesIO(data), file_type="ply", process=False)
    verts, faces = np.asarray(mesh.vertices, dtype=float), np.asarray(mesh.faces)
    gray = np.all(np.asarray(mesh.visual.vertex_colors) == MANDREL_COLOR, axis=1)
    on_mandrel = np.all(gray[faces], axis=1)
    tri = verts[faces]
    normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    big = np.linalg.norm(normal, axis=1) > 2.0 * AREA_TOL
    centroid = tri.mean(axis=1)
    centres = verts[gray].reshape(-1, THETA_SAMPLES, 3).mean(axis=1)  # the axis, station by station
    _, ring = cKDTree(centres).query(centroid[on_mandrel])
    mandrel_in = big[on_mandrel] & (np.einsum("ij,ij->i", normal[on_mandrel], centroid[on_mandrel] - centres[ring]) <= 0)
    grid = np.flatnonzero(gray)
    outward = np.asarray(trimesh.Trimesh(verts, faces[on_mandrel], process=False).vertex_normals)[grid]
    _, near = cKDTree(verts[grid]).query(centroid[~on_mandrel])
    band_in = big[~on_mandrel] & (np.einsum("ij,ij->i", normal[~on_mandrel], outward[near]) <= 0)
    return int(np.count_nonzero(mandrel_in)), int(np.count_nonzero(band_in)), faces.shape[0]


@pytest.mark.parametrize("path", EVERY, ids=IDS)
def test_every_face_outward(path):
    pytest.importorskip("trimesh")
    job, plan = job_of(path), planned(path)
    mandrel_in, band_in, total = inward_faces(ply_bytes(plan, job.winding.band_width))
    assert (mandrel_in, band_in) == (0, 0), f"{mandrel_in} mandrel and {band_in} band faces of {total} face inward"
