"""Every line of every program within MAX_LINE characters (docs/math/06-machine.md 6.4:
LinuxCNC refuses a longer line, comments included), in every dialect, on every sample and config;
a job name and a source path of any length shortened to fit."""

from __future__ import annotations

from dataclasses import replace

import pytest

from every_job import EVERY, GCODE_DIALECTS, IDS, program_of, text_of
from winder.export.dialects.text import JOB_LINE, MAX_LINE
from winder.export.gcode import program_text


def long_lines(text: str) -> list[str]:
    return [line for line in text.splitlines() if len(line.encode("utf-8")) > MAX_LINE]


@pytest.mark.parametrize("path", EVERY, ids=IDS)
def test_every_line_within_the_limit(path):
    written = 0
    for dialect in (*GCODE_DIALECTS, "robot"):
        text = text_of(path, dialect)
        if text is None:
            continue
        written += 1
        assert not long_lines(text), (dialect, long_lines(text)[:1])
    assert written >= 1


def test_long_name_and_source_shortened():
    program = program_of(EVERY[0])
    name, source = "tank-" * 80 + "end", "/very/" + "long/" * 70 + "dir/ünïcode-tank.yaml"
    text = program_text(replace(program, name=name, source=source))
    assert not long_lines(text)
    lines = text.splitlines()
    job = next(line for line in lines if line.startswith(JOB_LINE))
    assert job.startswith(f"{JOB_LINE} tank-tank-") and job.endswith("...")
    src = next(line for line in lines if line.startswith("; source:"))
    assert src.endswith("dir/ünïcode-tank.yaml") and "..." in src
