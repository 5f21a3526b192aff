"""What every job proves before it writes (winder.machine.invariants): each invariant holds on a
planned job and is refused, naming the layer, pass and move, where it is broken."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest

from configs import tiny_pipe
from winder.app.jobs import run_job
from winder.config.job import load_config, parse_config
from winder.config.machine import MachineLimits
from winder.errors import SolverError
from winder.machine.as_wound import upper_envelope, wound_profiles
from winder.machine.invariants import mended_and_proved, prove
from winder.machine.program import as_written, build_program
from winder.winding.plan import plan

# A small vessel with thick plies: its first helical piles up 10 mm inside its opening plane, where
# the dome's normal runs nearly along the axis, so its laminate stands past that plane.
SMALL_VESSEL = """\
name: small_vessel
mandrel:
  profile:
    type: vessel
    radius: 60
    cylinder_length: 80
    dome: {type: ellipsoid, polar_opening: 12, depth: 40}
winding:
  band_width: 8
  points: 40
  material: {ply_thickness: 1.0}
  layers:
    - {type: helical, angle: 14, slip: auto}
    - {type: helical, angle: 16, slip: auto}
machine:
  eye: {clearance: 20}
"""
CLEARANCE = 20.0
OFF = 0.3  # mm: how far a tampered row is moved, six chord tolerances


@pytest.fixture(scope="module")
def pipe(tmp_path_factory):
    path = tmp_path_factory.mktemp("pipe") / "pipe.yaml"
    path.write_text(tiny_pipe("pipe", 40), encoding="utf-8")
    job = load_config(path)
    done = plan(job)
    return job, done, build_program(done, job.machine)


def test_a_planned_job_proves_every_invariant(pipe):
    job, done, program = pipe
    found = prove(done, job, program)
    tol = job.machine.chord_tolerance
    assert found.min_covered_fraction >= 0.999
    assert found.max_point_deviation_mm <= tol and found.max_midpoint_deviation_mm <= tol
    assert found.min_clearance_mm >= job.machine.eye_clearance - tol


def test_a_programmed_point_off_its_ray_is_refused(pipe):
    job, done, program = pipe
    values = program.values.copy()
    seg = max(program.segments[0], key=lambda seg: seg.stop - seg.start)
    row = (seg.start + seg.stop) // 2  # inside the pass of most rows
    values[row, 0] += OFF  # the carriage moved along the axis: the eye leaves the fiber's line
    tampered = dataclasses.replace(program, values=values)
    with pytest.raises(SolverError, match=rf"layer 1 \(helical 40 deg\), circuit {seg.circuit}, pass {seg.number} "
                                          rf"\({seg.kind.value}\), "
                                          rf"program move {row + 1}: .* programmed point .*machine.chord_tolerance"):
        prove(done, job, tampered)


def test_axis_limits_hold_as_written(pipe):
    job, done, program = pipe
    top = float(as_written(program.values, False)[:, 0].max())
    at_top = dataclasses.replace(job.machine, limits=MachineLimits(carriage=(-1e4, top)))
    prove(done, job, dataclasses.replace(program, machine=at_top))  # the written value is the limit: kept
    below = dataclasses.replace(job.machine, limits=MachineLimits(carriage=(-1e4, top - 0.001)))
    with pytest.raises(SolverError, match="carriage.*is written.*outside machine.limits.carriage"):
        prove(done, job, dataclasses.replace(program, machine=below))


def test_the_eye_clears_the_laminate_past_a_domes_opening_plane():
    """The laminate stands past the opening plane. Measured against the bare meridian moved out by the
    wall (the summary's dome wall, its own sum of the layers' thicknesses), the eye planned around the
    grown surface alone comes too close (9 mm of 20 when that surface was trimmed at the opening plane;
    19.35 mm since it carries the pile-ups, docs/math/17 17.8, whose crests its smoothing lowers);
    planned around the part as wound, it keeps the clearance."""
    job = parse_config(__import__("yaml").safe_load(SMALL_VESSEL), "small_vessel.yaml")
    done = plan(job)
    first = wound_profiles(done)[-1]
    assert first.span[0] < -1.0  # the laminate stands more than a millimetre past the opening plane
    with pytest.raises(SolverError, match=r"layer \d+ \(helical \d+ deg\).*the part as wound so far"):
        prove(done, job, build_program(done, job.machine, None))  # the eye around the grown surface alone
    found = prove(done, job, build_program(done, job.machine))
    assert found.min_clearance_mm >= CLEARANCE - job.machine.chord_tolerance


def test_upper_envelope_of_a_fold():
    # A polyline doubling back in z: each station takes the larger sheet, the peak vertex raises its
    # neighbours.
    z = np.array([0.0, 2.0, 1.0, 3.0])
    r = np.array([1.0, 3.0, 5.0, 2.0])
    got = upper_envelope(z, r, np.array([-2.0, -1.0, 0.5, 1.5, 2.5, 4.0, 5.0]))
    assert got[0] == -np.inf and got[-1] == -np.inf  # no vertex next to them, no segment over them
    assert got[2] == pytest.approx(5.0) and got[3] == pytest.approx(5.0)  # both neighbours of the vertex (1, 5)
    assert got[4] == pytest.approx(3.0)  # the vertex (2, 3) above the segment (1, 5) -> (3, 2) there (2.75)
    assert got[5] == pytest.approx(2.0)  # the last vertex raises its neighbour past the end


def test_a_spaced_hoop_asks_for_its_coverage(tmp_path: Path):
    spaced = tiny_pipe("spaced", 40).replace("    - {type: helical, angle: 40}", "    - {type: hoop, angle: 75}")
    config = tmp_path / "spaced.yaml"
    config.write_text(spaced, encoding="utf-8")
    report = run_job(config, tmp_path / "out")
    assert report.exit_code == 1 and not list((tmp_path / "out").glob("*"))
    assert "layer 1 (hoop 75 deg): covers" in report.message and "min_coverage" in report.message
    config.write_text(spaced.replace("{type: hoop, angle: 75}", "{type: hoop, angle: 75, min_coverage: 0.15}"),
                      encoding="utf-8")
    report = run_job(config, tmp_path / "out")
    assert report.ok, report.message
    block = json.loads((tmp_path / "out" / "spaced.summary.json").read_text())["invariants"]
    assert 0.15 <= block["min_covered_fraction"] < 0.999
    assert set(block) == {"min_covered_fraction", "max_point_deviation_mm", "max_midpoint_deviation_mm",
                          "min_clearance_mm"}


def test_straying_moves_are_cut_where_the_eye_path_bends():
    """A program reduced at ten times the tolerance (its midpoints up to 0.5 mm off the fiber round
    the domes) proved at the tolerance: the moves past it are cut at their exact contacts
    (winder.machine.mend) until every written point and midpoint keeps it."""
    job = parse_config(__import__("yaml").safe_load(SMALL_VESSEL), "small_vessel.yaml")
    done = plan(job)
    # The eye at a fixed radius: the coarse chords' cut into a clearance is not what is mended here.
    job = dataclasses.replace(job, machine=dataclasses.replace(job.machine, eye_radius=140.0, eye_clearance=None))
    loose = dataclasses.replace(job.machine, chord_tolerance=10 * job.machine.chord_tolerance)
    coarse = dataclasses.replace(build_program(done, loose), machine=job.machine)
    with pytest.raises(SolverError, match="midpoint"):
        prove(done, job, coarse)
    program, found = mended_and_proved(done, job, coarse)
    tol = job.machine.chord_tolerance
    assert program.values.shape[0] > coarse.values.shape[0]
    assert found.max_point_deviation_mm <= tol and found.max_midpoint_deviation_mm <= tol
    assert sum(program.fiber) == pytest.approx(sum(coarse.fiber), rel=1e-12)  # the fiber shared out, none added
