"""A rotary axis a controller keeps (issue 49): a post file may reset the axis to its value modulo 360
at each layer's (pass's) first move (LinuxCNC's G92) or wrap it (a modulo axis, the shortest way:
tests/export/test_posts.py's Fanuc). LinuxCNC's own interpreter reads the reset program and moves the
axis exactly where the cumulative program does (its G92 offset added back), and simulate reads the same
fiber from it."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from rs274_run import RS274, run_rs274
from winder.app.simulate import simulate
from winder.config.job import parse_config
from winder.export.gcode import program_text
from winder.machine.limits import AXIS_DECIMALS
from winder.machine.program import build_program
from winder.readback.gcode import parse_program
from winder.winding.plan import plan as plan_job

HERE = Path(__file__).resolve().parent
POSITION_TOL = 0.6 * 10.0**-AXIS_DECIMALS  # deg: a value as written against the program's
WRITTEN_TOL = 1.1 * 10.0**-AXIS_DECIMALS  # deg: the same row written less whole turns, rounded again
SAME_FIBER = 1e-6  # relative
_NUMBERS = re.compile(r"(STRAIGHT_FEED|SET_G92_OFFSET)\(([^)]*)\)")
JOB = {"name": "turns", "mandrel": {"axis": {"type": "line", "length": 400},
                                    "profile": {"type": "constant", "radius": 60}},
       "winding": {"band_width": 12, "region": {"start": 20, "end": 380}, "points": 30,
                   "layers": [{"type": "helical", "angle": 30}, {"type": "hoop", "passes": 2},
                              {"type": "helical", "angle": 60}]},
       "machine": {"eye": {"radius": 90}, "dialect": "linuxcnc"}}


def _job(post: str | None = None):
    machine = dict(JOB["machine"], **({"post": post} if post else {}))
    return parse_config({**JOB, "machine": machine}, str(HERE / "turns.yaml"))


@pytest.fixture(scope="module")
def planned():
    return plan_job(_job())


@pytest.fixture(scope="module")
def program(planned):
    return build_program(planned, _job().machine)


@pytest.mark.parametrize("mode", ["reset_per_layer", "reset_per_pass"])
def test_the_reset_program_reads_back_the_same_moves(planned, program, mode):
    job = _job(f"posts/{mode}.post.yaml")
    text = program_text(_with(program, job))
    resets = [line for line in text.splitlines() if line.startswith("G92 A")]
    layers = len(planned.layers)
    passes = sum(len(layer.passes) for layer in planned.layers)
    assert len(resets) == (layers - 1 if mode == "reset_per_layer" else passes - 1)
    assert text.splitlines()[-4:] == ["G92.1", "G94", "M2", "%"]
    continuous = program_text(_with(program, _job()))
    read, plain = parse_program(text, job.machine), parse_program(continuous, _job().machine)
    assert np.abs(read.values - plain.values).max() <= WRITTEN_TOL
    written = [float(w[1:]) for line in text.splitlines() if line.startswith(("G1 ", "G0 "))
               for w in line.split() if w[0] == "A"]
    # Each value within a turn of the span of its layer (pass) alone, not of the whole program's turns.
    spans = [np.ptp(program.values[seg.start - 1 if seg.start else 0:seg.stop, 1]) for segs in program.segments
             for seg in segs if seg.stop > seg.start] if mode == "reset_per_pass" else [
        np.ptp(program.values[segs[0].start - 1 if segs[0].start else 0:segs[-1].stop, 1]) for segs in program.segments]
    assert max(abs(a) for a in written) <= max(spans) + 360.0 < np.ptp(program.values[:, 1])
    sim, ref = simulate(job.machine, planned, text), simulate(_job().machine, planned, continuous)
    assert sim.fiber_length_mm == pytest.approx(ref.fiber_length_mm, rel=SAME_FIBER)
    assert sim.max_point_deviation_mm < job.machine.chord_tolerance


@pytest.mark.skipif(RS274 is None, reason="rs274 not installed (Debian package linuxcnc-uspace)")
def test_rs274_moves_the_axis_where_the_cumulative_program_does(planned, program, tmp_path):
    job = _job("posts/reset_per_layer.post.yaml")
    canon = run_rs274(tmp_path / "turns.ngc", program_text(_with(program, job)))
    offset, machine_a = 0.0, []
    for name, numbers in _NUMBERS.findall(canon):
        a = float(numbers.split(",")[3])
        if name == "SET_G92_OFFSET":
            offset = a
        else:
            machine_a.append(a + offset)
    shown = np.round(program.values, AXIS_DECIMALS)
    rows = np.flatnonzero(np.concatenate([[True], np.any(shown[1:] != shown[:-1], axis=1)]))[1:]  # G0 first
    assert len(machine_a) == rows.size
    assert np.abs(np.array(machine_a) - program.values[rows, 1]).max() < POSITION_TOL
    assert canon.count("SET_G92_OFFSET") >= len(planned.layers)  # the start's, then one per reset


def _with(program, job):
    from dataclasses import replace  # noqa: PLC0415

    return replace(program, machine=job.machine)


def test_a_value_past_the_controllers_digits_is_refused_naming_the_remedy(program):
    from winder.errors import ExportError  # noqa: PLC0415

    job = _job("posts/six_digits.post.yaml")
    turned = np.abs(np.round(program.values[:, 1], AXIS_DECIMALS)).max()
    digits = len(str(int(turned))) + AXIS_DECIMALS
    with pytest.raises(ExportError, match=rf"has {digits} digits, past the 6 the six_digits controller takes "
                                          r"\(max_digits\); keep the rotary axis with rotary: \{mode: wrap\}"):
        program_text(_with(program, job))


@pytest.mark.skipif(RS274 is None, reason="rs274 not installed (Debian package linuxcnc-uspace)")
def test_a_wrapped_program_read_by_rs274_unwinds_to_the_cumulative_moves(planned, program, tmp_path):
    """rs274 reads A as written (modulo 360); every move within a third of a turn, so turning each the
    shortest way (what a modulo axis does) gives back the cumulative program, cut into pieces."""
    from winder.machine.rotary import split_turns  # noqa: PLC0415

    job = _job("posts/wrap.post.yaml")
    text = program_text(_with(program, job))
    feeds = [float(numbers.split(",")[3]) for name, numbers in _NUMBERS.findall(run_rs274(tmp_path / "w.ngc", text))
             if name == "STRAIGHT_FEED"]
    assert min(feeds) >= 0.0 and max(feeds) < 360.0
    cut = split_turns(program).values
    shown = np.round(cut, AXIS_DECIMALS)
    rows = np.flatnonzero(np.concatenate([[True], np.any(shown[1:] != shown[:-1], axis=1)]))[1:]
    first = float(np.round(cut[0, 1], AXIS_DECIMALS))  # the G0 to the start, as written: first mod 360
    turns = 360.0 * np.floor(first / 360.0)  # the whole turns a modulo axis does not show
    unwound = np.unwrap(np.concatenate([[first - turns], feeds]), period=360.0)[1:] + turns
    assert len(feeds) == rows.size
    assert np.abs(unwound - cut[rows, 1]).max() < POSITION_TOL + 1e-9
    continuous = program_text(_with(program, _job()))
    sim, ref = simulate(job.machine, planned, text), simulate(_job().machine, planned, continuous)
    assert sim.fiber_length_mm == pytest.approx(ref.fiber_length_mm, rel=SAME_FIBER)
