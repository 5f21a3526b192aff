"""winder.app.simulate on a hoop layer of an elliptic tube (winder.readback.contact_bands): one pass of 100
turns, a point every few degrees, read back within the tolerances in bounded time and memory (the whole
pass's table was 2,110 samples x 58,429 candidates on 88 turns, 123 million entries, and the program
was refused as another job's); the band's contacts are the whole table's; another job's program is
still refused."""

from __future__ import annotations

import copy
import time

import numpy as np
import pytest

import winder.readback.contact_bands as contact_bands
import winder.app.simulate as simulate_module
from winder.readback.contacts import candidates, monotone_points
from winder.readback.exact_paths import ExactPaths
from winder.app.simulate import eye_positions, simulate
from winder.config.job import parse_config
from winder.errors import ConfigError
from winder.readback.gcode import parse_program
from winder.export.gcode import gcode_text
from winder.winding.plan import plan as plan_job

TANGENT_TOL = 0.01  # mm: a programmed eye from the exact tangent line (3-decimal axes)
LENGTH_TOL = 1e-6  # relative: laid fiber against the plan's (7e-8 seen)
SIMULATE_S = 60.0  # s: the read-back (plan excluded; about 2 s), generous for a loaded 2-core machine
BAND_TABLE = 2_000_000  # entries: the band needs 0.5 million here, the whole pass's table 140 million
TURNS = 100

TUBE = {
    "name": "elliptic_hoop",
    "mandrel": {"axis": {"type": "line", "length": 1100}, "section": {"type": "ellipse", "a": 90, "b": 55}},
    "winding": {"band_width": 10, "region": {"start": 50, "end": 50 + 10 * TURNS},
                "layers": [{"type": "hoop", "passes": 2}]},
    "machine": {"eye": {"clearance": 25}, "limits": {"carriage": [-300, 2800]}},
}


def _job(**winding):
    data = copy.deepcopy(TUBE)
    data["winding"].update(winding)
    return parse_config(data, "elliptic_hoop.yaml")


@pytest.fixture(scope="module")
def tube():
    job = _job()
    plan = plan_job(job)
    return job, plan, gcode_text(plan, job.machine)


def test_a_hoop_of_a_hundred_turns_reads_back(tube, monkeypatch):
    """Every sample on its planned tangent within the chord tolerance, every programmed point within
    the axes' rounding, the fiber the plan's; with the table limit far below the whole pass's table."""
    job, plan, text = tube
    monkeypatch.setattr(simulate_module, "MAX_TABLE_ENTRIES", BAND_TABLE)
    began = time.perf_counter()
    sim = simulate(job.machine, plan, text)
    seconds = time.perf_counter() - began
    assert seconds < SIMULATE_S
    assert sim.max_point_deviation_mm < TANGENT_TOL
    assert sim.max_deviation_mm < job.machine.chord_tolerance
    assert sim.fiber_length_mm == pytest.approx(plan.total_fiber_length_mm, rel=LENGTH_TOL)


def test_the_band_finds_the_whole_tables_contacts():
    """A hoop of 20 turns, small enough for the whole table: its contacts found in a band (every
    chain banded) are the ones the dynamic program over the whole pass picks, sample for sample."""
    job = _job(region={"start": 50, "end": 250})
    plan = plan_job(job)
    parsed = parse_program(gcode_text(plan, job.machine), job.machine)
    passes = list(plan.layers[0].passes)
    number = {fp.number: j for j, fp in enumerate(passes)}
    pass_of = np.array([number[int(k[2])] for k in parsed.keys])
    hoop = np.array([kind == "hoop" for kind in parsed.kinds])
    eye, pass_of = eye_positions(parsed)[hoop], pass_of[hoop]
    chain, position = pass_of.copy(), np.arange(pass_of.size)
    cu, cp, cd, cstart = candidates(ExactPaths(plan.surface_of(1), passes))
    whole = monotone_points(eye, chain, position, pass_of, cp, cd, cstart)
    banded = contact_bands.contact_points(eye, chain, position, pass_of, cp, cd, cstart,
                                          job.machine.chord_tolerance, BAND_TABLE, band_above=0)
    assert np.array_equal(banded, whole)


def test_another_jobs_hoop_program_is_refused(tube):
    """The program of a tube wound with a 9 mm band (111 turns, the same passes and job name) ends
    short of this plan's hoop; one whose job line names another job is refused by it."""
    job, plan, text = tube
    other = _job(band_width=9)
    with pytest.raises(ConfigError, match=r"the program stops before the end of the plan of elliptic_hoop\.yaml"):
        simulate(job.machine, plan, gcode_text(plan_job(other), other.machine), "other.gcode")
    with pytest.raises(ConfigError, match="its job line names 'tube'"):
        simulate(job.machine, plan, text.replace("; job: elliptic_hoop", "; job: tube"), "named.gcode")


def test_a_band_past_the_table_limit_is_refused_before_it_is_allocated(tube, monkeypatch):
    job, plan, text = tube
    monkeypatch.setattr(simulate_module, "MAX_TABLE_ENTRIES", 10_000)
    with pytest.raises(ConfigError, match=r"a pass read from [\d,]+ samples, each against a band of up to "
                                          r"[\d,]+ points of its plan, would need a table of"):
        simulate(job.machine, plan, text, "p.gcode")
