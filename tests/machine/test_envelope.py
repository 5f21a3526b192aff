"""winder.machine.envelope: the eye's envelope keeps its clearance from the part and is concave (the
region inside convex), so that every tangent ray leaves it once and the eye never jumps; and the
approach to a new layer goes around the part (winder.machine.program.approach)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from winder.config.job import load_config
from winder.config.machine import MachineConfig
from winder.geometry.build import build_surface
from winder.machine.collision import part_distance
from winder.machine.envelope import eye_envelope
from winder.machine.program import APPROACH, build_program
from winder.winding.plan import plan as plan_job
from roundoff import assert_roundoff

ROOT = Path(__file__).resolve().parents[2]
CLEAR = 20.0
CONCAVE_TOL = 1e-9  # mm: second differences of the tabulated envelope
# mm: the table's chords between stations 0.25 mm apart cut into a dilated end cap where it turns
# steep (about 0.01 mm); the collision check of every move allows the chord tolerance (0.05 mm).
TABLE_TOL = 0.02


@pytest.mark.parametrize("config", ["configs/ellipsoid_vessel.yaml", "configs/vessel_friction.yaml",
                                    "samples/cone.yaml", "samples/pipe.yaml"])
def test_envelope_is_concave_and_clear(config):
    job = load_config(ROOT / config)
    surface = build_surface(job.mandrel, job.source, job.name)
    env = eye_envelope(surface, MachineConfig(eye_clearance=CLEAR, eye_radius=None))
    x = np.linspace(-3.0 * CLEAR, surface.axial_length + 3.0 * CLEAR, 4001)
    z = env.at(x)
    # Concave where it encloses anything (it goes on straight past the table, down to the axis).
    inside = (z[:-2] > 0) & (z[1:-1] > 0) & (z[2:] > 0)
    assert np.all(np.diff(z, 2)[inside] <= CONCAVE_TOL * (1.0 + z[1:-1][inside]))
    clear = part_distance(z[z > 0], x[z > 0], env)
    assert clear.min() >= CLEAR - TABLE_TOL  # never closer than the clearance (the disc's dilation)
    # Over the mandrel it is no farther out than needed: the dilation's hull, r_max + c on a cylinder.
    mid = surface.axial_length / 2.0
    assert float(env.at(np.array([mid]))[0]) == pytest.approx(float(env.mandrel_at(np.array([mid]))[0]) + CLEAR,
                                                               abs=1e-6) or "vessel" not in config


def test_new_layer_is_approached_around_the_part():
    """configs/ellipsoid_vessel.yaml: layer 1 ends near a pole, the hoop starts at the equator; the
    straight move between cut through the dome's shoulder. The program goes out to the envelope's
    largest radius, along, and in, the mandrel turning on."""
    job = load_config(ROOT / "configs/ellipsoid_vessel.yaml")
    program = build_program(plan_job(job), job.machine)  # its collision check passes
    seg = program.segments[1][0]
    assert seg.approach == 2
    rows = program.values[seg.start - 1:seg.start + 3]
    top = float(np.max(program.values[:, 2]))
    assert rows[1, 2] == pytest.approx(top) and rows[2, 2] == pytest.approx(top)
    assert np.all(np.diff(rows[:, 1]) * np.sign(program.values[-1, 1] - program.values[0, 1]) > 0)
    assert np.all(program.fiber[seg.start:seg.start + 2] == 0.0) and APPROACH == "approach"


@pytest.mark.parametrize("shape", ["noise", "arc_below_ends", "concave"])
def test_concave_majorant_is_the_upper_hull(shape):
    """The pruning sweeps (and the monotone chain they hand over to) against the definition: the least
    concave majorant at x_i is the largest chord value over the pairs of points straddling it."""
    from winder.machine.envelope import _concave_majorant

    x = np.linspace(0.0, 100.0, 301)
    z = {"noise": np.random.default_rng(3).normal(size=x.size),
         "arc_below_ends": -((x - 50.0) ** 2) / 100.0 + np.where((x == 0.0) | (x == 100.0), 200.0, 0.0),
         "concave": -((x - 50.0) ** 2) / 100.0}[shape]
    i, j = np.triu_indices(x.size, 1)
    best = z.copy()
    for k in range(x.size):
        span = (x[i] <= x[k]) & (x[j] >= x[k])
        w = (x[k] - x[i[span]]) / (x[j[span]] - x[i[span]])
        best[k] = max(best[k], np.max(z[i[span]] + w * (z[j[span]] - z[i[span]])))
    assert _concave_majorant(x, z) == pytest.approx(best, abs=1e-9)


def _dilate_every_step(stations, r_max, c, h, k_max, caps):
    """_dilate with every one of its k_max steps taken: its reference."""
    before, after = (k_max if caps[0] else 0), (k_max if caps[1] else 0)
    r_ext = np.concatenate([np.full(before, -np.inf), r_max, np.full(after, -np.inf)])
    dil = r_ext + c
    for k in range(1, k_max + 1):
        rise = np.sqrt(max(c * c - (k * h) ** 2, 0.0))
        dil[k:] = np.maximum(dil[k:], r_ext[:-k] + rise)
        dil[:-k] = np.maximum(dil[:-k], r_ext[k:] + rise)
    return np.maximum(dil, 0.0)


@pytest.mark.parametrize("profile", ["cylinder", "gentle", "cone", "bumps", "step"])
def test_dilation_skipping_no_op_steps_is_every_step_bit_for_bit(profile):
    from winder.machine.envelope import _dilate  # noqa: PLC0415

    stations = np.linspace(0.0, 500.0, 2001)
    h = stations[1] - stations[0]
    rng = np.random.default_rng(4)
    r_max = {"cylinder": np.full(stations.size, 35.0), "gentle": 35.0 + 1e-3 * np.sin(stations / 40.0),
             "cone": 20.0 + 0.1 * stations, "bumps": 35.0 + rng.uniform(0.0, 0.3, stations.size),
             "step": np.where(stations < 250.0, 35.0, 35.0 + 1e-12)}[profile]
    for c in (20.5, 3.0):
        k_max = int(np.floor(c / h))
        for caps in ((False, False), (True, False), (True, True)):
            got, _ = _dilate(stations, r_max, c, h, k_max, caps)
            assert_roundoff(got, _dilate_every_step(stations, r_max, c, h, k_max, caps), err_msg=str((c, caps)))
