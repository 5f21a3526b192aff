"""A corpus of hand-edited robot programs (issue 43's edits, and more of each kind): every one refused by
the readers (winder.readback.krl, rapid, urscript through cells.parse_cell) with one line naming the
program line, as ConfigError (exit 2), never an internal error; the clean programs read as written."""

from __future__ import annotations

import dataclasses
import re

import numpy as np
import pytest

from tests.cells import small_elbow_cells
from winder.errors import ConfigError
from winder.export.dialects import krl, rapid, urscript
from winder.readback.cell_programs import parse_cell

LANGUAGE = {"kuka_kr16": "krl", "abb_irb4600": "rapid", "ur10e": "urscript"}
BRIDGE_TIME_TOL = 0.05  # s: URScript's blend schedule shifts by the stop the bridge makes


@pytest.fixture(scope="module")
def texts():
    """{language: (machine, text, plan)} of the small elbow on each arm's cell."""
    _, plan, programs = small_elbow_cells()
    out = {}
    for arm, (machine, program) in programs.items():
        language = LANGUAGE[arm]
        written = {"krl": krl, "rapid": rapid, "urscript": urscript}[language].serialize(program)
        out[language] = (machine, "".join(written[k] for k in sorted(written, key=lambda s: s != ".src")), plan)
    return out


def _first(text: str, pattern: str, after: int = 0) -> int:
    """The index of the first line matching pattern from line index `after` on."""
    lines = text.splitlines()
    return next(i for i in range(after, len(lines)) if re.search(pattern, lines[i]))


def _replace(text: str, pattern: str, new, after: int = 0) -> str:
    """The text with the first line matching pattern (from `after`) replaced by new(line)."""
    lines = text.splitlines()
    i = _first(text, pattern, after)
    lines[i] = new(lines[i])
    return "\n".join(lines) + "\n"


def _insert(text: str, pattern: str, line: str, after: int = 0) -> str:
    """The text with `line` inserted after the first line matching pattern."""
    lines = text.splitlines()
    i = _first(text, pattern, after)
    return "\n".join(lines[:i + 1] + [line] + lines[i + 1:]) + "\n"


def _sub(pattern: str, repl: str):
    return lambda line: re.sub(pattern, repl, line, count=1)


def _dat_point(text: str, name: str, key: str, value: str) -> str:
    return _replace(text, rf"^DECL E6POS {name}=", _sub(rf"\b{key} [^,}}]+", f"{key} {value}"))


EDITS = {  # language: [(what, edit(text) -> text)]
    "krl": [
        ("a PTP to other joints", lambda t: _insert(t, r"^LIN P20\b", "PTP {A1 0,A2 -90,A3 90,A4 0,A5 0,A6 0,E1 0,E2 0,E3 65}")),
        ("a CIRC", lambda t: _insert(t, r"^LIN P20\b", "CIRC P21, P22")),
        ("$BASE moved 500 mm", lambda t: _replace(t, r"^\$BASE", _sub(r"X 1000\.000", "X 1500.000"))),
        ("$TOOL moved 1 m", lambda t: _replace(t, r"^\$TOOL", _sub(r"Z 250\.000", "Z 1250.000"))),
        ("a LIN without its point", lambda t: _replace(t, r"^LIN P20\b", lambda _: "LIN C_DIS")),
        ("$VEL.CP = 0", lambda t: _replace(t, r"^\$VEL\.CP", lambda _: "$VEL.CP = 0")),
        ("$VEL.CP = nan", lambda t: _replace(t, r"^\$VEL\.CP", lambda _: "$VEL.CP = nan")),
        ("$VEL.CP negative", lambda t: _replace(t, r"^\$VEL\.CP", lambda _: "$VEL.CP = -0.02")),
        ("$VEL.CP = abc", lambda t: _replace(t, r"^\$VEL\.CP", lambda _: "$VEL.CP = abc")),
        ("$VEL.CP = 1e999", lambda t: _replace(t, r"^\$VEL\.CP", lambda _: "$VEL.CP = 1e999")),
        ("Arabic-Indic digits in the .dat", lambda t: _dat_point(t, "P7", "Y", "\u0663\u0662.\u0661")),
        ("nan in the .dat", lambda t: _dat_point(t, "P7", "X", "nan")),
        ("1e999 in the .dat", lambda t: _dat_point(t, "P7", "X", "1e999")),
        ("a point without X", lambda t: _replace(t, r"^DECL E6POS P7=", _sub(r"X [^,]+,", ""))),
        ("a 23-digit pass number", lambda t: _replace(t, r"^; layer 1 circuit 1 pass 2 ", _sub("pass 2", "pass " + "9" * 23))),
        ("a pose out of reach", lambda t: _dat_point(t, "P7", "Z", "2992.0")),
        ("a pose 458 mm off (another configuration)", lambda t: _dat_point(t, "P30", "X", "458.0")),
        ("start joints past their limits", lambda t: _replace(t, r"^PTP ", _sub(r"A5 [^,]+", "A5 170.0"))),
        ("start joints off the first pose", lambda t: _replace(t, r"^PTP ", _sub(r"A1 [^,]+", "A1 0.0"))),
        ("E4 set", lambda t: _dat_point(t, "P7", "E4", "5.0")),
        ("an unknown system variable", lambda t: _insert(t, r"^LIN P20\b", "$OV_PRO = 50")),
    ],
    "rapid": [
        ("a second start MoveAbsJ", lambda t: _insert(t, r"MoveL p20,", "    MoveAbsJ jStart, v100, fine, tRing \\WObj:=wMandrel;")),
        ("the ring's tool frame moved 1 m", lambda t: _replace(t, r"PERS tooldata tRing", _sub(r"\[\[1000\.000", "[[2000.000"))),
        ("the work object moved", lambda t: _replace(t, r"PERS wobjdata wMandrel", _sub(r"250\.000", "260.000"))),
        ("\\T:=nan", lambda t: _replace(t, r"MoveL p20,", _sub(r"\\T:=[^,]+", r"\\T:=nan"))),
        ("\\T:=0", lambda t: _replace(t, r"MoveL p20,", _sub(r"\\T:=[^,]+", r"\\T:=0"))),
        ("\\T:=-5", lambda t: _replace(t, r"MoveL p20,", _sub(r"\\T:=[^,]+", r"\\T:=-5"))),
        ("\\T:=1e300", lambda t: _replace(t, r"MoveL p20,", _sub(r"\\T:=[^,]+", r"\\T:=1e300"))),
        ("a quaternion of nan", lambda t: _replace(t, r"CONST robtarget p7 ", _sub(r"\],\[[^\]]*\]", "],[nan,0,0,0]"))),
        ("a target at 1e308", lambda t: _replace(t, r"CONST robtarget p7 ", _sub(r"\[\[[^,]+", "[[1e308"))),
        ("a target at 9E9", lambda t: _replace(t, r"CONST robtarget p7 ", _sub(r"\[\[[^,]+", "[[9E9"))),
        ("a target out of reach", lambda t: _replace(t, r"CONST robtarget p7 ", _sub(r"\[\[[^,]+", "[[2500.0"))),
        ("a MoveJ", lambda t: _insert(t, r"MoveL p20,", "    MoveJ p21, v1000, z0, tRing \\WObj:=wMandrel;")),
        ("start joints past their limits", lambda t: _replace(t, r"CONST jointtarget jStart", _sub(r"\[\[[^,]+", "[[190"))),
    ],
    "urscript": [
        ("a movej to other joints", lambda t: _insert(t, r"^  movel\(", "  movej([0, -1.57, 1.57, 0, 0, 0], a=1.0, v=1.0)", 40)),
        ("set_tcp again", lambda t: _insert(t, r"^  movel\(", "  set_tcp(p[0, 0, 0.3, 0, 0, 0])", 40)),
        ("a pose in mm", lambda t: _replace(t, r"^  movel\(", _sub(r"p\[([-0-9.]+), ([-0-9.]+), ([-0-9.]+)", r"p[800.0, -52.0, 500.0"), 40)),
        ("t=-1", lambda t: _replace(t, r"^  movel\(", _sub(r"t=[^,]+", "t=-1"), 40)),
        ("t below the 2 ms cycle", lambda t: _replace(t, r"^  movel\(", _sub(r"t=[^,]+", "t=0.0001"), 40)),
        ("nan in a pose", lambda t: _replace(t, r"^  movel\(", _sub(r"p\[[^,]+", "p[nan"), 40)),
        ("a sum in a pose", lambda t: _replace(t, r"^  movel\(", _sub(r"p\[([^,]+)", r"p[\1 + 1"), 40)),
        ("ring(1e999, ...)", lambda t: _replace(t, r"^  ring\(", _sub(r"ring\([^,]+", "ring(1e999"), 40)),
        ("a blend radius of 50 mm", lambda t: _replace(t, r"^  movel\(", _sub(r"r=[^)]+", "r=0.05"), 40)),
        ("a movel without its ring line", lambda t: _replace(t, r"^  ring\(", lambda _: "  # ring line removed", 40)),
        ("start joints off the first pose", lambda t: _replace(t, r"^  movej\(", _sub(r"movej\(\[[^,]+", "movej([0.5"))),
        ("the TCP moved", lambda t: _replace(t, r"^  set_tcp", _sub(r"0\.2500000", "0.3000000"))),
    ],
}
CASES = [(language, what, edit) for language, edits in EDITS.items() for what, edit in edits]


@pytest.mark.parametrize(("language", "what", "edit"), CASES, ids=[f"{c[0]}: {c[1]}" for c in CASES])
def test_edited_program_refused_naming_its_line(texts, language: str, what: str, edit) -> None:
    machine, text, _ = texts[language]
    edited = edit(text)
    assert edited != text, what
    with pytest.raises(ConfigError) as info:
        parse_cell(edited, machine, "program", language)
    message = str(info.value)
    assert "\n" not in message
    assert re.match(r"program: line [0-9]+: ", message), message


@pytest.mark.parametrize("language", ["krl", "rapid", "urscript"])
def test_clean_program_reads(texts, language: str) -> None:
    machine, text, _ = texts[language]
    parsed = parse_cell(text, machine, "program", language)
    assert np.all(np.isfinite(parsed.move_s)) and np.all(parsed.move_s[1:] > 0.0)
    assert parsed.job == "small_elbow" and parsed.job_line is not None


def test_another_jobs_program_names_its_job_line(texts) -> None:
    from winder.app.simulate import simulate  # noqa: PLC0415

    machine, text, plan = texts["krl"]
    edited = _replace(text, r"^; job:", lambda _: "; job: another_job")
    with pytest.raises(ConfigError, match=r"program: line [0-9]+: the program was written for another job"):
        simulate(machine, plan, edited, "program")


@pytest.mark.parametrize("arm", ["kuka_kr16", "abb_irb4600", "ur10e"])
def test_a_bridge_is_written_and_read_back(arm: str) -> None:
    """A bridge (winder.machine.bridges) after a row of the program: each language writes its joint
    move after an exact stop (KRL PTP, RAPID MoveAbsJ, URScript movej with the movel before it at
    r=0), and the reader lands its joints on the pose and adds its time. The bridge here keeps the
    configuration (the small elbow needs none), which exercises the writing and the reading alike."""
    from winder.export.dialects.robot_text import rows  # noqa: PLC0415
    from winder.machine.bridges import Bridge, swap_time  # noqa: PLC0415

    _, _, programs = small_elbow_cells()
    machine, program = programs[arm]
    cell = program.cell
    row = [r for _, r in rows(program)][40]
    q = cell.reach.joints[row]
    bridged = dataclasses.replace(program, cell=dataclasses.replace(cell, bridges=(Bridge(row, q, q, swap_time(cell.arm, q, q)),)))
    language = LANGUAGE[arm]
    written = {"krl": krl, "rapid": rapid, "urscript": urscript}[language].serialize(bridged)
    text = "".join(written[k] for k in sorted(written, key=lambda s: s != ".src"))
    assert re.search(r"^\s*(PTP \{A1|MoveAbsJ jBridge|movej\(\[.*t=)", text, re.M | re.S)
    parsed = parse_cell(text, machine, "program", language)
    plain = parse_cell("".join(v for _, v in sorted(
        {"krl": krl, "rapid": rapid, "urscript": urscript}[language].serialize(program).items(),
        key=lambda kv: kv[0] != ".src")), machine, "program", language)
    assert abs(np.sum(parsed.move_s) - np.sum(plain.move_s) - swap_time(cell.arm, q, q)) < BRIDGE_TIME_TOL
