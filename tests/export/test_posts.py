"""Controllers described as data (docs/guide/controllers.md): a post file kept in this
test folder alone (tests/export/posts/shop.post.yaml: block numbers, comments in parentheses, four
decimals, its own tension command) yields the program a hand-written excerpt describes, LinuxCNC's
interpreter reads it, and simulate reads it back; the shipped Sinumerik 840D and Fanuc posts write what
their manuals' syntax allows (block format, comments, program start and end, digits), and simulate reads
their programs back with the same fiber as the plain program's."""

from __future__ import annotations

import re
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from rs274_run import RS274, run_rs274
from winder.app.simulate import simulate
from winder.config.job import parse_config
from winder.export.gcode import program_text
from winder.machine.program import build_program
from winder.machine.tension import pass_tensions, with_tension
from winder.winding.plan import plan as plan_job

HERE = Path(__file__).resolve().parent
SAME_FIBER = 1e-6  # relative: the fiber read back from a program and from the same moves written otherwise
N4 = r"-?\d+\.\d{4}"  # a value with the shop post's four decimals
JOB = {"name": "shop", "mandrel": {"axis": {"type": "line", "length": 300},
                                   "profile": {"type": "constant", "radius": 40}},
       "winding": {"band_width": 10, "region": {"start": 20, "end": 280}, "points": 40, "tension": 40,
                   "layers": [{"type": "helical", "angle": 50, "tension": {"start": 60, "end": 45}},
                              {"type": "hoop", "passes": 2}]},
       "machine": {"eye": {"radius": 70}}}
# The shop post's program as its file says it must read, written by hand: its start (header, the
# preamble numbered from 100 by 5, the first pass's comments, its tension, the rapid, inverse time and
# the first feed) and its end.
START = [r"%", r"\(winder filament-winding program\)", r"\(job: shop\)"]
PREAMBLE = [r"N100 G21 G90 G94 G17 G40 G49 G80 G54", r"N105 G64 P0\.050",
            r"\(layer 1: helical, angle 50\.000 deg \[requested 50\.000\], circuits \d+, pattern \d+, passes \d+, "
            r"fiber \d+\.\d{3} mm\)",
            r"\(layer 1 circuit 1\)", r"\(layer 1 circuit 1 pass 1 forward\)", r"N110 M67 E1 Q60\.00",
            rf"N115 G0 X{N4} A{N4} Z70\.0000 B{N4}", r"N120 G93", rf"N125 G1 X{N4} A{N4} Z70\.0000 B{N4} F\d+\.\d+"]
END = [r"N\d+ G94", r"N\d+ M30", r"%"]


def _job(post: str | None = None, dialect: str | None = None):
    machine = dict(JOB["machine"], **({"post": post} if post else {}), **({"dialect": dialect} if dialect else {}))
    return parse_config({**JOB, "machine": machine}, str(HERE / "shop.yaml"))


@pytest.fixture(scope="module")
def planned():
    return plan_job(_job())


def _text(job, plan) -> str:
    return program_text(with_tension(build_program(plan, job.machine), pass_tensions(job, plan)))


def _matches(patterns: list[str], lines: list[str]) -> bool:
    return len(lines) == len(patterns) and all(re.fullmatch(p, line) for p, line in zip(patterns, lines))


def test_a_post_file_in_the_tests_alone_writes_the_hand_written_program(planned, tmp_path):
    job = _job("posts/shop.post.yaml")
    assert job.machine.dialect == "linuxcnc" and job.machine.controller.name == "shop"
    lines = _text(job, planned).splitlines()
    assert _matches(START, lines[:3])
    first = lines.index("N100 G21 G90 G94 G17 G40 G49 G80 G54")
    assert _matches(PREAMBLE, lines[first:first + len(PREAMBLE)])
    assert _matches(END, lines[-3:])
    # The header says what the controller must be set up for (docs/guide/machine-setup.md).
    assert "(controller: shop [a shop's own LinuxCNC cell])" in lines
    assert "(tension: N per band, set where it changes by M67 E1 Q<N>)" in lines
    code = [line for line in lines if not line.startswith("(") and line != "%"]
    numbers = [int(re.match(r"N(\d+) ", line)[1]) for line in code]
    assert numbers == list(range(100, 100 + 5 * len(code), 5))
    assert all(line.endswith(")") for line in lines if line.startswith("("))
    assert not any(line.startswith(";") for line in lines)
    if RS274 is not None:  # LinuxCNC reads it too: its tension on output 1, synchronized with motion
        canon = run_rs274(tmp_path / "shop.ngc", "\n".join(lines) + "\n")
        assert "STRAIGHT_FEED" in canon and "60.0" in canon


def test_simulate_reads_what_the_post_writes(planned):
    job = _job("posts/shop.post.yaml")
    sim = simulate(job.machine, planned, _text(job, planned))
    plain = simulate(_job(dialect="linuxcnc").machine, planned, _text(_job(dialect="linuxcnc"), planned))
    assert sim.dialect == "shop"
    assert sim.fiber_length_mm == pytest.approx(plain.fiber_length_mm, rel=SAME_FIBER)
    assert sim.max_point_deviation_mm < job.machine.chord_tolerance
    assert [t["tension_n"] for t in sim.tensions] == pytest.approx([60.0, 40.0])


def test_sinumerik_840d_program_follows_its_manual(planned):
    job = _job(dialect="sinumerik_840d")
    lines = _text(job, planned).splitlines()
    assert lines[0] == "%_N_SHOP_MPF".replace("SHOP", "shop") and lines[1] == ";$PATH=/_N_MPF_DIR"
    code = [line for line in lines[2:] if not line.startswith(";")]
    blocks = [re.fullmatch(r"N(\d+) ([^;()]+)", line) for line in code]
    assert all(blocks), next(line for line, b in zip(code, blocks) if not b)
    numbers = [int(b[1]) for b in blocks]
    assert numbers == sorted(set(numbers))  # ascending, each once
    words = [b[2] for b in blocks]
    assert words[0] == "G71 G90 G94 G17 G40 G54" and words[-1] == "M30" and words[-2] == "G94"
    assert words.index("G93") < next(i for i, w in enumerate(words) if w.startswith("G1 "))
    assert all(re.fullmatch(r"\$A_OUTA\[1\]=\d+\.\d", w) for w in words if w.startswith("$"))
    assert max(len(line) for line in lines) <= 512  # the manual's block length
    sim = simulate(job.machine, planned, "\n".join(lines) + "\n")
    assert sim.max_point_deviation_mm < job.machine.chord_tolerance
    assert [t["tension_n"] for t in sim.tensions] == pytest.approx([60.0, 40.0])


def test_fanuc_program_follows_its_manual(planned):
    job = _job(dialect="fanuc")
    text = _text(job, planned)
    lines = text.splitlines()
    assert lines[0] == "%" and re.fullmatch(r"O\d{4} \([A-Z0-9_]+\)", lines[1]) and lines[-1] == "%"
    assert re.fullmatch(r"N\d{1,5} M30", lines[-2])
    assert "(ROTARY AXIS: MODULO 360 [A ROLL-OVER AXIS TAKING THE SHORTEST WAY], NO MOVE HALF A TURN)" in lines
    assert not re.search(r"[a-z;]", text)  # upper case (lower case is ignored on input), no `;` comments
    body = lines[2:-1]
    comments = [line for line in body if line.startswith("(")]
    assert all(re.fullmatch(r"\([^()]*\)", line) for line in comments)  # never nested
    code = [line for line in body if not line.startswith("(")]
    assert all(re.match(r"N\d{1,5} ", line) for line in code)
    values = [w for line in code for w in line.split()[1:] if w[0] in "XAZBF"]
    assert max(len(re.sub(r"\D", "", w)) for w in values) <= 8  # the digits of a word
    rotary = np.array([float(w[1:]) for w in values if w[0] == "A"])
    assert rotary.min() >= 0.0 and rotary.max() < 360.0  # rolled over
    turns = np.abs((np.diff(rotary) + 180.0) % 360.0 - 180.0)
    assert turns.max() < 180.0  # each move the shortest way: the roll-over takes it so
    assert all(re.fullmatch(r"N\d+ G65 P9010 Q\d+\.\d", line) for line in code if "G65" in line)
    sim = simulate(job.machine, planned, text)
    plain = simulate(_job(dialect="linuxcnc").machine, planned, _text(_job(dialect="linuxcnc"), planned))
    assert sim.fiber_length_mm == pytest.approx(plain.fiber_length_mm, rel=SAME_FIBER)
    assert sim.max_point_deviation_mm < job.machine.chord_tolerance
    assert sim.time_s == pytest.approx(plain.time_s, rel=1e-3)


def test_a_program_without_an_end_code_reads_back_whole_and_cut_short_refused(planned):
    """A post whose footer has no end code writes none; simulate reads its programs as whole, and
    still refuses one cut short (the last move does not end the plan)."""
    from winder.errors import ConfigError  # noqa: PLC0415

    job = _job("posts/no_end.post.yaml")
    text = _text(job, planned)
    assert text.splitlines()[-1] == "; end of the winding program" and "\nM2\n" not in text
    assert simulate(job.machine, planned, text).max_point_deviation_mm < job.machine.chord_tolerance
    cut = "\n".join(text.splitlines()[:-200]) + "\n"
    with pytest.raises(ConfigError, match="stops before the end of the plan"):
        simulate(job.machine, planned, cut)


def test_inverse_time_is_a_key_of_the_description(planned):
    """A post extending generic with feed: inverse_time writes LinuxCNC's moves (G0 to the start, G93,
    F = 60 / the move's time) under the generic program's own lines, and reads back the same."""
    job, plain = _job("posts/generic_inverse.post.yaml"), _job(dialect="linuxcnc")
    moves = [line for line in _text(job, planned).splitlines() if line.startswith(("G0 ", "G1 ", "G93"))]
    assert moves == [line for line in _text(plain, planned).splitlines() if line.startswith(("G0 ", "G1 ", "G93"))]
    assert moves[0].startswith("G0 ") and moves[1] == "G93"
    sim = simulate(job.machine, planned, _text(job, planned))
    assert sim.time_s == pytest.approx(simulate(plain.machine, planned, _text(plain, planned)).time_s, rel=1e-9)
