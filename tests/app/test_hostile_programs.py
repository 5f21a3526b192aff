"""Hostile programs for `simulate` (issue 34): each made from the pipe sample's reference program by one
edit, read in a child process under 2 GB (tests/sandbox.py): exit 0 (read as the controller reads
it) or 2 with one `Error:` line naming the line, never a traceback or an internal error."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from tests.sandbox import run_limited

ROOT = Path(__file__).resolve().parents[2]
PIPE = ROOT / "samples" / "pipe.yaml"
PROGRAM = ROOT / "samples" / "reference" / "pipe" / "pipe.gcode"
HANG_GUARD_S = 120  # a hang becomes a failure; the 20 s is asserted on the child's own clock
BUSY_MACHINE_S = 20.0


def _edit(name: str, lines: list[str]) -> list[str]:
    k = next(i for i, line in enumerate(lines) if line.startswith("G1 X"))
    p = next(i for i, line in enumerate(lines) if line.startswith("; layer 1 circuit 1 pass 1"))
    at_k = {"underscore": lines[k].replace("X", "X1_", 1),
            "arabic_digits": re.sub("X[0-9]", "X\u0661", lines[k], count=1),
            "zero_e999": re.sub(r"Z[0-9.]+", "Z0e999", lines[k], count=1)}
    if name in at_k:
        return lines[:k] + [at_k[name]] + lines[k + 1:]
    if name == "blank_30k":
        return lines[:k] + [""] * 30_000 + lines[k:]
    if name == "paren_only":
        return lines[:k] + ["( a comment line )", "(G1 X0)", "   "] + lines[k:]
    if name == "paren_200k":
        return lines[:k] + ["(" * 200_000] + lines[k:]
    if name == "compact":
        return [line.replace(" ", "") if line.startswith("G1 ") else line for line in lines]
    if name == "pass_2e20":
        return lines[:p] + ["; layer 1 circuit 1 pass 99999999999999999999 forward"] + lines[p + 1:]
    if name == "other_job_line":
        return [line.replace("; job: pipe", "; job: vessel") for line in lines]
    if name == "not_in_plan":
        return lines[:p] + ["; layer 7 circuit 1 pass 1 forward"] + lines[p + 1:]
    raise KeyError(name)


# program -> (exit status, words of the Error line)
CASES = {
    "blank_30k": (0, None),
    "paren_only": (0, None),
    "compact": (0, None),
    "paren_200k": (2, "line 19: not a move"),
    "underscore": (2, "line 19: unreadable number"),
    "arabic_digits": (2, "line 19: unreadable number"),
    "zero_e999": (2, "line 19: E is no axis"),
    "pass_2e20": (2, "line 18: a layer, circuit or pass number past 1e+09"),
    "other_job_line": (2, "line 2: the program was written for another job: its job line names 'vessel'"),
    "not_in_plan": (2, "line 19: layer 7 circuit 1 pass 1 is not in the plan"),
}


@pytest.fixture(scope="module")
def results(tmp_path_factory) -> dict[str, dict]:
    folder = tmp_path_factory.mktemp("programs")
    lines = PROGRAM.read_text(encoding="utf-8").splitlines()
    cases = []
    for name in sorted(CASES):
        path = folder / f"{name}.gcode"
        path.write_text("\n".join(_edit(name, lines)) + "\n", encoding="utf-8")
        cases.append([["simulate", str(PIPE), str(path), "--json"]])
    return {n: r[0] for n, r in zip(sorted(CASES), run_limited(cases, workers=2, seconds=HANG_GUARD_S))}


@pytest.mark.parametrize("name", sorted(CASES))
def test_hostile_program(results, name: str) -> None:
    result = results[name]
    code, words = CASES[name]
    assert result["uncaught"] is None and "Traceback" not in result["stderr"], result
    assert "internal error" not in result["stderr"], result["stderr"]
    assert result["code"] == code, result
    assert result["seconds"] < BUSY_MACHINE_S, result["seconds"]
    errors = [line for line in result["stderr"].splitlines() if line.startswith("Error:")]
    if code:
        assert len(errors) == 1 and words in errors[0], result["stderr"]
    else:
        assert errors == [] and '"moves": 614' in result["stdout"], result


def test_a_program_of_a_million_moves_is_refused_within_the_budget(tmp_path: Path) -> None:
    """1e6 moves (25 MB, inside the 256 MB file limit) for a plan of 9,758 points: refused while reading,
    not after an 8 GiB allocation."""
    lines = PROGRAM.read_text(encoding="utf-8").splitlines()
    k = next(i for i, line in enumerate(lines) if line.startswith("G1 X"))
    path = tmp_path / "million.gcode"
    path.write_text("\n".join(lines[:k] + [lines[k]] * 1_000_000 + lines[k + 1:]) + "\n", encoding="utf-8")
    (result,), = run_limited([[["simulate", str(PIPE), str(path)]]], seconds=HANG_GUARD_S)
    assert result["code"] == 2 and "internal error" not in result["stderr"], result
    assert "moves, past what simulate reads for this job" in result["stderr"], result["stderr"]
    assert result["seconds"] < BUSY_MACHINE_S and result["peak_mb"] < 2048, result


def test_a_config_check_refuses_is_not_planned_by_simulate(tmp_path: Path) -> None:
    """A config past the work budget and a 60-byte program: check's refusal, at once (it ran 106 s to an
    internal MemoryError)."""
    config = tmp_path / "big.yaml"
    config.write_text(PIPE.read_text(encoding="utf-8").replace("band_width: 10", "band_width: 0.001"),
                      encoding="utf-8")
    program = tmp_path / "p.gcode"
    program.write_text("; layer 1 circuit 1 pass 1 forward\nG1 X0 A0 Z70 B0 F3000\nM2\n", encoding="utf-8")
    (check, sim), = run_limited([[["check", str(config)], ["simulate", str(config), str(program)]]],
                                seconds=HANG_GUARD_S)
    assert check["code"] == 2 and sim["code"] == 2, (check, sim)
    assert sim["stderr"] == check["stderr"], (check["stderr"], sim["stderr"])
    assert sim["seconds"] < BUSY_MACHINE_S
