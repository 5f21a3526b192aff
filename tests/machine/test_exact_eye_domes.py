"""The programmed eye on the tangent line of the exact fiber over ellipsoidal domes, with
`points: 30`: the reference is Clairaut's geodesic by quadrature from the ellipse's own equation
(tests/machine/dome_geodesic.py, docs/math/12-exact-eye.md 12.1) on each dome and the helix on the
cylinder, fitted to the plan's own points (c from the helix, one azimuth per dome), never to winder's
interpolant or path. The eyes are read back from the written generic program. Geodesic helical layers
wound on the bare mandrel only (a grown dome is an ellipse's offset, not an ellipse)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml

from tests.machine.dome_geodesic import fit_dome, program_eyes
from tests.machine.test_exact_eye import EYE_TOL, ON_CYLINDER, eye_points, helix_distance
from winder.config.job import parse_config
from winder.export.gcode import program_text
from winder.machine.program import build_program
from winder.winding.plan import plan as plan_job

ROOT = Path(__file__).resolve().parents[2]
FORM_TOL = 1e-4  # mm: the plan's points on the ellipse and on the Clairaut geodesic


def _vessel(source: str, angle: float | None = None, **changes):
    data = yaml.safe_load((ROOT / source).read_text())
    data["winding"]["points"] = 30
    if angle is not None:
        data["winding"]["layers"][0]["angle"] = angle
    data["mandrel"]["profile"].update(changes)
    return parse_config(data, source)


CASES = {
    "configs_ellipsoid_vessel": lambda: _vessel("configs/ellipsoid_vessel.yaml"),
    # Unequal ellipsoids and bosses: a deep dome (d > R / 2) at the start, a flat one at the end.
    "ellipsoid_unequal": lambda: _vessel(
        "configs/ellipsoid_vessel.yaml", angle=25, radius=100, cylinder_length=200,
        dome={"type": "ellipsoid", "polar_opening": 25, "depth": 80},
        end_dome={"type": "ellipsoid", "polar_opening": 30, "depth": 40}),
}


def _domes(job) -> tuple[float, tuple[tuple[float, float, float], ...]]:
    """R and each dome's (d, z_e, side) from the config alone: a dome of semi-axis d with an opening
    of radius r0 reaches d sqrt(1 - (r0 / R)^2) past its equator; the start pole's plane is z = 0."""
    profile = job.mandrel.profile
    R = float(profile.radius)
    start, end = profile.dome, profile.end_dome
    assert start.type.value == "ellipsoid" and end.type.value == "ellipsoid"
    z1 = float(start.depth) * np.sqrt(1.0 - (float(start.polar_opening) / R) ** 2)
    z2 = z1 + float(profile.cylinder_length)
    return R, ((float(start.depth), z1, -1.0), (float(end.depth), z2, 1.0))


@pytest.fixture(scope="module", params=sorted(CASES))
def written(request):
    job = CASES[request.param]()
    plan = plan_job(job)
    return request.param, job, plan, program_text(build_program(plan, job.machine))


def _clairaut_constant(fp, radius: float) -> float:
    """c = R sin(alpha) of a pass from the helix fitted to its cylinder points (pitch dz/dtheta)."""
    r = np.hypot(fp.points[:, 0], fp.points[:, 1])
    cyl = np.abs(r - radius) < ON_CYLINDER
    phi = np.unwrap(np.arctan2(fp.points[cyl, 1], fp.points[cyl, 0]))
    pitch = np.polyfit(phi, fp.points[cyl, 2], 1)[0]
    return float(radius * radius / np.hypot(radius, pitch))


def test_every_eye_on_the_clairaut_tangent(written):
    name, job, plan, text = written
    R, domes = _domes(job)
    worst, checked = 0.0, 0
    for layer in plan.layers:
        if layer.type.value != "helical" or layer.index != 1:  # on the bare mandrel
            continue
        blocks = program_eyes(text, layer.index)
        assert len(blocks) == len(layer.passes)
        c = float(np.median([_clairaut_constant(fp, R) for fp in layer.passes]))
        eyes = [eye_points(rows) for rows in blocks]
        best = [np.full(e.shape[0], np.inf) for e in eyes]
        for fp, eye, b in zip(layer.passes, eyes, best):
            cyl = np.abs(np.hypot(fp.points[:, 0], fp.points[:, 1]) - R) < ON_CYLINDER
            b[:] = helix_distance(eye, fp.points[cyl], R)
        for depth, z_e, side in domes:
            # Every pass's geodesic over this dome is one curve turned about the axis (and mirrored
            # for the other sense): all eyes of the layer, moved with their pass's, in one search.
            moved, owner, reference = [], [], None
            for j, (fp, eye) in enumerate(zip(layer.passes, eyes)):
                cyl = np.abs(np.hypot(fp.points[:, 0], fp.points[:, 1]) - R) < ON_CYLINDER
                on = ~cyl & (side * (fp.points[:, 2] - z_e) > 0.0)
                if np.count_nonzero(on) < 3:
                    continue
                geodesic = fit_dome(fp.points[on], R, depth, z_e, side, c, FORM_TOL)
                reference = geodesic.canonical()
                moved.append(geodesic.to_canonical(eye))
                owner.append(np.full(eye.shape[0], j))
            if reference is None:
                continue
            d = reference.distance(np.concatenate(moved))
            owner_all = np.concatenate(owner)
            for j in np.unique(owner_all):
                best[j] = np.minimum(best[j], d[owner_all == j])
        for b in best:
            worst = max(worst, float(b.max()))
            checked += b.size
    assert checked > 1000
    assert worst < EYE_TOL, f"{name}: an eye {worst:.4f} mm off the exact tangent ({checked} eyes)"
