"""A robot's eye at a dwell round the end of a bent or spline duct (issue 41) keeps its clearance,
measured here by brute force: every eye pose and sample of the moves between the dense poses of the
dwell passes against the part as the union of its sections' discs (a disc of radius r(t) square to
the guide's tangent at x(t), every 0.1 mm of the guide: the tube closed by its end discs), not by
winder's own tube_distance.

The lead of a robot pose is found by Newton from a neighbour's lead, and each Newton step projected
the eye onto the guide from its previous station in WARM_NEWTON steps of at most 2 mm. A dwell's fiber
runs off the end nearly along the axis, so a step carries the eye tens of mm along the guide: the
projection stayed behind, the distance read too large, and Newton closed on a false root next to the
contact point. On the generator's duct_4 the dwell's dense eyes sat at leads of 0.01 to 0.7 mm, 2.633 mm
inside the mandrel where they must stay 11.95 mm clear."""

from __future__ import annotations

import numpy as np
import pytest

from winder.config.job import parse_config
from winder.machine.as_wound import finished_part
from winder.machine.envelope import eye_envelope
from winder.machine.kinematics import make_guide
from winder.machine.robot import robot_rows
from winder.winding.plan import plan as plan_job
from winder.winding.results import PassKind

DISC_STEP = 0.1  # mm between the brute force's section discs
SAMPLES = 8  # points per move between dense poses (its ends excluded)
DUCT_4 = [[0.0, 0.0, 0.0], [0.0, 0.0, 75.0], [35.0, -1.0, 150.0], [36.0, 9.0, 225.0]]


def _job(name: str, axis: dict, radius: float, length: float) -> dict:
    return {"name": name, "mandrel": {"axis": axis, "profile": {"type": "constant", "radius": radius}},
            "winding": {"band_width": 14.0, "friction": 0.15, "points": 30,
                        "layers": [{"type": "hoop", "passes": 2}, {"type": "helical", "angle": 54.5, "slip": "auto"}],
                        "region": {"start": 1.0, "end": length - 1.0}, "material": {"ply_thickness": 0.3}},
            "machine": {"eye": {"clearance": 12.0}, "robot": True}}


DUCTS = {
    # the generator's duct_4: a spline bending in two planes, its dwell at the start refused
    "duct_4": _job("duct_4", {"type": "spline", "points": DUCT_4}, 23.5, 225.0),
    # a spline bending hardest at its far end (the dwell there round a bent guide's end)
    "hooked": _job("hooked", {"type": "spline", "points": [[0.0, 0.0, 0.0], [0.0, 0.0, 70.0], [10.0, 5.0, 140.0],
                                                           [45.0, 20.0, 200.0]]}, 20.0, 200.0),
}


def part_distance(e: np.ndarray, guide, env) -> np.ndarray:
    """Least distance (m,) of points e (m, 3) from the union of the discs of radius r(t) (the envelope's
    part table) square to the guide curve at x(t), every DISC_STEP mm over the part's stations."""
    lo, hi = env.stations[0], env.stations[-1]
    t = np.linspace(lo, hi, int(np.ceil((hi - lo) / DISC_STEP)) + 1)
    x, tan, _ = guide.evaluate(t)
    r = np.interp(t, env.stations, env.mandrel_radius)
    best = np.full(e.shape[0], np.inf)
    for rows in np.array_split(np.arange(e.shape[0]), max(1, e.shape[0] * t.size // (1 << 21))):
        rel = e[rows, None, :] - x[None]
        axial = np.einsum("mkj,kj->mk", rel, tan)
        radial = np.sqrt(np.maximum(np.einsum("mkj,mkj->mk", rel, rel) - axial**2, 0.0))
        best[rows] = np.min(np.hypot(axial, np.maximum(radial - r[None], 0.0)), axis=1)
    return best


@pytest.fixture(scope="module", params=sorted(DUCTS))
def duct(request):
    job = parse_config(DUCTS[request.param], f"{request.param}.yaml")
    plan = plan_job(job)
    env = eye_envelope(plan.outer_surface, job.machine, finished_part(plan))
    guide = make_guide(plan.outer_surface, env)
    tol = float(job.machine.chord_tolerance)
    rows = robot_rows(plan, job.machine, env, guide, tol / np.radians(1.0), tol)
    return plan, job.machine, env, guide, rows


def _dwell_rows(plan, rows) -> list[slice]:
    passes = [fp for layer in plan.layers for fp in layer.passes if len(fp.points)]
    start = np.cumsum(rows.sizes) - rows.sizes
    return [slice(int(s), int(s + k)) for fp, s, k in zip(passes, start, rows.sizes) if fp.kind is PassKind.DWELL]


def test_dwell_poses_keep_clearance(duct) -> None:
    plan, machine, env, guide, rows = duct
    dwells = _dwell_rows(plan, rows)
    assert dwells, "the duct has dwells"
    eyes = np.concatenate([rows.table[s, :3] for s in dwells])
    # the eye on its envelope: its centre's clearance from the part, to the discs' spacing
    gap = part_distance(eyes, guide, env)
    assert gap.min() >= env.clearance - 1e-3, f"an eye pose {env.clearance - gap.min():.3f} mm inside its clearance"
    # and along every move between them, less the chord tolerance
    f = (np.arange(1, SAMPLES + 1) / (SAMPLES + 1))[:, None, None]
    moves = np.concatenate([((1.0 - f) * rows.table[s, :3][:-1] + f * rows.table[s, :3][1:]).reshape(-1, 3)
                            for s in dwells])
    along = part_distance(moves, guide, env)
    assert along.min() >= env.clearance - machine.chord_tolerance, \
        f"a dwell's move {env.clearance - along.min():.3f} mm inside the clearance"


def guide_distance(e: np.ndarray, guide) -> tuple[np.ndarray, np.ndarray]:
    """(station, distance) (m,) of points e (m, 3) from the guide curve extended by its end tangents,
    by brute force: the nearest of its points every DISC_STEP / 2 mm, then every 1 um around it."""
    z = np.linspace(guide.z[0], guide.z[-1], int(np.ceil((guide.z[-1] - guide.z[0]) / (0.5 * DISC_STEP))) + 1)
    x, _, _ = guide.evaluate(z)
    d2 = np.einsum("mj,mj->m", e, e)[:, None] - 2.0 * e @ x.T + np.einsum("kj,kj->k", x, x)[None]
    near = z[np.argmin(d2, axis=1)]
    # and again every 1 um within a step of it: the envelope falls steeply at the ends (slope 3)
    fine = near[:, None] + np.linspace(-0.5 * DISC_STEP, 0.5 * DISC_STEP, 101)[None]
    x, _, _ = guide.evaluate(fine.ravel())
    dist = np.linalg.norm(e[:, None, :] - x.reshape(fine.shape + (3,)), axis=2)
    k = np.argmin(dist, axis=1)
    rows = np.arange(e.shape[0])
    return fine[rows, k], dist[rows, k]


def test_dwell_leads_are_first_crossings(duct) -> None:
    """Each dwell pose's lead is the first crossing of its fiber line with the envelope (the points
    env.at(t*) from their nearest guide point x(t*)): short of it (a 0.5 mm scan) the line stays inside."""
    plan, _, env, guide, rows = duct
    dwells = _dwell_rows(plan, rows)
    contacts = np.concatenate([rows.contacts[s] for s in dwells])
    direction = -np.concatenate([rows.table[s, 3:] for s in dwells])
    lead = np.concatenate([rows.lead[s] for s in dwells])
    assert np.all(rows.on_envelope[np.concatenate([np.arange(s.start, s.stop) for s in dwells])])
    pick = np.linspace(0, lead.size - 1, min(lead.size, 200)).astype(int)
    for p, d, lam in zip(contacts[pick], direction[pick], lead[pick]):
        station, dist = guide_distance(p + np.array([lam])[:, None] * d, guide)
        assert abs(dist[0] - env.at(station)[0]) < 0.01, "the eye on its envelope"
        scan = np.arange(0.0, lam - 0.5, 0.5)
        if scan.size:
            station, dist = guide_distance(p + scan[:, None] * d, guide)
            f = dist - env.at(station)
            assert f.max() < 0.01, f"lead {lam:.3f} mm past an earlier crossing at {scan[np.argmax(f)]:.1f} mm"
