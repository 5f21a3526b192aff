"""Fiber tension (docs/guide/tension.md): N per band, per layer or over a layer's
passes, carried in the motion program and written into every program as its controller's command;
LinuxCNC's own interpreter reads the M68 lines (one per change), and simulate reads back the tension
of every layer as the config plans it."""

from __future__ import annotations

import re
from dataclasses import replace

import numpy as np
import pytest

from rs274_run import RS274, run_rs274
from winder.app.simulate import simulate
from winder.config.job import parse_config
from winder.export.gcode import program_text
from winder.machine.program import build_program
from winder.machine.tension import pass_tensions, with_tension
from winder.winding.plan import plan as plan_job

WRITTEN_TOL = 0.05 + 1e-9  # N: a tension as written (one decimal) against the planned
_AUX = re.compile(r"SET_AUX_OUTPUT_VALUE\((\d+),\s*([-0-9.]+)\)")
JOB = {"name": "tensioned", "mandrel": {"axis": {"type": "line", "length": 300},
                                        "profile": {"type": "constant", "radius": 40}},
       "winding": {"band_width": 10, "region": {"start": 20, "end": 280}, "points": 40, "tension": 40,
                   "layers": [{"type": "helical", "angle": 50, "tension": {"start": 60, "end": 45}},
                              {"type": "hoop", "passes": 2}]},
       "machine": {"eye": {"radius": 70}, "dialect": "linuxcnc"}}


@pytest.fixture(scope="module")
def job():
    return parse_config(JOB, "tensioned.yaml")


@pytest.fixture(scope="module")
def planned(job):
    return plan_job(job)


def _program(job, plan, dialect: str):
    machine = replace(job.machine, dialect=dialect)
    return with_tension(build_program(plan, machine), pass_tensions(job, plan))


def _planned_tensions(plan) -> list[float]:
    """The config's tension of every pass, by hand: layer 1 linear from 60 to 45 over its passes,
    layer 2 the job's 40."""
    first = plan.layers[0].passes
    return [60.0 + (45.0 - 60.0) * k / (len(first) - 1) for k in range(len(first))] + [40.0] * len(
        plan.layers[1].passes)


def test_every_pass_carries_its_tension(job, planned):
    program = _program(job, planned, "linuxcnc")
    got = [seg.tension for segs in program.segments for seg in segs]
    assert np.allclose(got, _planned_tensions(planned), rtol=0, atol=1e-12)
    assert program.layer_tensions[0] == pytest.approx((60.0, 45.0, 60.0))
    assert program.layer_tensions[1] == pytest.approx((40.0, 40.0, 40.0))


@pytest.mark.skipif(RS274 is None, reason="rs274 not installed (Debian package linuxcnc-uspace)")
def test_rs274_reads_one_m68_per_change(job, planned, tmp_path):
    text = program_text(_program(job, planned, "linuxcnc"))
    written = [float(line.split("Q")[1]) for line in text.splitlines() if line.startswith("M68 E0 Q")]
    # One line per change of the tension as written (one decimal): never the same value twice in a row.
    expected = [v for k, v in enumerate(np.round(_planned_tensions(planned), 1).tolist())
                if k == 0 or v != np.round(_planned_tensions(planned), 1)[k - 1]]
    assert written == pytest.approx(expected, abs=1e-9)
    canon = run_rs274(tmp_path / "tensioned.ngc", text)
    read = [(int(m[1]), float(m[2])) for m in _AUX.finditer(canon)]
    assert [output for output, _ in read] == [0] * len(written)
    assert [value for _, value in read] == pytest.approx(written, abs=1e-9)
    assert canon.index("SET_AUX_OUTPUT_VALUE") < canon.index("STRAIGHT_FEED")  # set before the first feed


@pytest.mark.parametrize("dialect", ["generic", "linuxcnc", "marlin"])
def test_simulate_reads_the_tension_of_every_layer(job, planned, dialect):
    program = _program(job, planned, dialect)
    machine = replace(job.machine, dialect=dialect)
    sim = simulate(machine, planned, program_text(program, 10.0))
    planned_t = _planned_tensions(planned)
    split = len(planned.layers[0].passes)
    for entry, values in zip(sim.tensions, (planned_t[:split], planned_t[split:])):
        assert entry["tension_n"] == pytest.approx(values[0], abs=WRITTEN_TOL)
        assert entry["tension_range_n"] == pytest.approx([min(values), max(values)], abs=WRITTEN_TOL)
    assert [entry["layer"] for entry in sim.tensions] == [1, 2]
    assert sim.max_point_deviation_mm < machine.chord_tolerance


def test_no_tension_no_command(job, planned):
    """A job without a tension writes none: the programs of the jobs before tension are unchanged."""
    plain = parse_config({**JOB, "winding": {k: v for k, v in JOB["winding"].items() if k != "tension"}
                          | {"layers": [{"type": "helical", "angle": 50}, {"type": "hoop", "passes": 2}]}},
                         "plain.yaml")
    assert pass_tensions(plain, planned) is None
    text = program_text(build_program(planned, plain.machine))
    assert "M68" not in text
