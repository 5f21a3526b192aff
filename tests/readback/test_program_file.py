"""A program file read line by line (winder.readback.program_file): the same lines and the same
dialect as the whole text gives, no line read whole past its limit, a refusal before any work."""

from __future__ import annotations

from pathlib import Path

import pytest

from winder.errors import ConfigError
from winder.readback import program_file
from winder.readback.cells import detect_cell
from winder.readback.gcode import detect
from winder.readback.program_file import ProgramFile

ROOT = Path(__file__).resolve().parents[2]
NO_LIMIT = 10**9


def test_lines_are_those_of_the_whole_text(tmp_path: Path) -> None:
    raw = "\ufeff; a\r\nG1 X1\rG1 X2\n\n\nlast \u00e9\x0bafter\u2028end"
    path = tmp_path / "p.gcode"
    path.write_bytes(raw.encode("utf-8") + b"\n(\xe9 latin-1)\n")
    text = path.read_bytes().decode("utf-8", errors="replace").removeprefix("\ufeff")
    assert list(ProgramFile(str(path), NO_LIMIT).lines()) == text.splitlines()


@pytest.mark.parametrize("sample", ["pipe", "elbow"])
def test_the_dialect_is_the_whole_text_s(tmp_path: Path, sample: str) -> None:
    folder = ROOT / "samples" / "reference" / sample
    path = folder / f"{sample}.gcode"
    text = path.read_text(encoding="utf-8")
    variants = {"as_written": text, "linuxcnc": text.replace("\nM2", "\nG93\nM2"),
                "pose_then_g93": text.replace("\nM2", "\nPOSE X1\nG93\nM2"),
                "rapid": text + "MODULE x\n", "urscript_after_krl": text + "DEF a( )\ndef b():\n"}
    for name, variant in variants.items():
        p = tmp_path / f"{name}.gcode"
        p.write_text(variant, encoding="utf-8")
        cell, dialect, lines = ProgramFile(str(p), NO_LIMIT).survey(NO_LIMIT)
        assert (cell, dialect, lines) == (detect_cell(variant), detect(variant), len(variant.splitlines())), name


def test_a_line_past_the_limit_is_refused_naming_it(tmp_path: Path, monkeypatch) -> None:
    monkeypatch.setattr(program_file, "MAX_LINE_BYTES", 1000)
    path = tmp_path / "long.gcode"
    path.write_text("; a\n; b\n" + "(" * 5000 + "\nM2\n", encoding="utf-8")
    with pytest.raises(ConfigError, match=r"long\.gcode: line 3: longer than 1,000 bytes"):
        list(ProgramFile(str(path), NO_LIMIT).lines())


def test_not_a_file_or_too_large_is_refused_at_once(tmp_path: Path) -> None:
    with pytest.raises(ConfigError, match="not a regular file"):
        ProgramFile("/dev/zero", NO_LIMIT)
    path = tmp_path / "p.gcode"
    path.write_text("M2\n")
    with pytest.raises(ConfigError, match="the file has 3 bytes, more than a winding program's limit of 2"):
        ProgramFile(str(path), 2)
    (tmp_path / "p.src").write_text("DEF p( )\n")  # a KRL program without the .dat of its points
    with pytest.raises(ConfigError, match=r"p\.dat: cannot read the file"):
        ProgramFile(str(tmp_path / "p.src"), NO_LIMIT)


def test_the_survey_stops_past_its_lines(tmp_path: Path) -> None:
    path = tmp_path / "many.gcode"
    path.write_text("\n" * 100_000, encoding="utf-8")
    assert ProgramFile(str(path), NO_LIMIT).survey(10)[2] == 11
