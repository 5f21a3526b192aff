"""winder.readback.contact_windows: a stretch matched again keeps each sample's contact where its ray fits,
not merely at the nearest of the search's reads.

parts/tank_20.yaml's third layer (a 17.5 deg helical), one circuit: near the first dome's polar
opening the eye, 120 to 125 mm out, swings back along the axis (carriage -11.891, -10.326, -10.930,
-12.114 mm) while the contact point moves 0.6 mm, and the rays sweep past it by about 0.015 mm per
1e-3 of the point index. simulate read the programmed point at t = 4.381 mm 0.091 mm off its ray
(past the 0.05 mm chord tolerance), the program's own contact point there 0.001 mm off it."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from winder.readback.contacts import TIE, ray_distance
from winder.readback.exact_paths import ExactPaths
from winder.app.simulate import eye_positions, simulate
from winder.config.job import load_config
from winder.readback.gcode import ParsedProgram
from winder.export.gcode import gcode_text
from winder.machine.program import as_written, build_program
from winder.winding.plan import plan as plan_job

ROOT = Path(__file__).resolve().parents[2]
LAYER, CIRCUIT = 3, 72  # the layer (1-based) and circuit read 0.091 mm off before
SAME_EYE = 1e-6  # mm: a sample's eye and a written row's: the same printed values


@pytest.fixture(scope="module")
def one_circuit():
    """tank_20's job, the plan of one circuit of its third layer (the layers before it without passes,
    the finished part's surface kept for the eye), its program and that program read back."""
    job = load_config(ROOT / "parts" / "tank_20.yaml")
    plan = plan_job(job)
    layer = plan.layers[LAYER - 1]
    own = tuple(fp for fp in layer.passes if fp.circuit == CIRCUIT)
    small = dataclasses.replace(plan, layers=tuple(dataclasses.replace(other, passes=())
                                                   for other in plan.layers[:LAYER - 1])
                                + (dataclasses.replace(layer, passes=own),))
    program = build_program(small, job.machine)
    return job, small, program, simulate(job.machine, small, gcode_text(small, job.machine))


def test_programmed_points_read_on_the_rays_they_were_written_for(one_circuit):
    """Truth from the program, not from the search: each written row was put on the tangent of the
    fiber at its own contact point (program.index), and the geodesic there is simulate's separate
    integration (ExactPaths, scipy). That ray bounds the one simulate finds: no programmed point reads
    farther off than it (within TIE, the rounding of the printed values), and every sample, move
    midpoints too, lies within the chord tolerance. (The bound is loose in places, 0.016 mm: the
    program writer places a point inside an interval by the smooth path's arc length, ExactPaths by
    the point index, winder.machine.exact and winder.readback.exact_paths.)"""
    job, plan, program, sim = one_circuit
    layer = plan.layers[LAYER - 1]
    paths = ExactPaths(plan.surface_of(LAYER), list(layer.passes))
    laying = program.index >= 0.0
    written = as_written(program.values[laying], False)
    number = {fp.number: j for j, fp in enumerate(layer.passes)}
    rows = np.flatnonzero(laying)
    pass_of = np.searchsorted([seg.start for seg in program.segments[LAYER - 1]], rows, side="right") - 1
    u = paths.offset[[number[program.segments[LAYER - 1][k].number] for k in pass_of]] + program.index[laying]
    _, _, p, d = paths.point(u)
    eye = eye_positions(ParsedProgram("generic", written, np.zeros((written.shape[0], 3)), (), np.zeros(0)))
    bound = ray_distance(eye, p, d)
    sm = sim.samples
    moves = np.flatnonzero(~sm["mid"] & np.isfinite(sm["deviation_mm"]))
    # Each programmed sample's written row (a pass continuing the last one is written from its second row).
    gap = np.linalg.norm(sm["eye"][moves][:, None, :] - eye[None, :, :], axis=2)
    row = np.argmin(gap, axis=1)
    assert np.all(gap[np.arange(moves.size), row] < SAME_EYE)
    assert moves.size > 100
    assert np.all(sm["deviation_mm"][moves] <= bound[row] + TIE)
    assert sim.max_deviation_mm < job.machine.chord_tolerance

