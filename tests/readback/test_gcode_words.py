"""The G-code reader takes what each dialect writes and nothing else (issue 45: `G64 P5`, LinuxCNC's path
blending, was skipped inside a generic program, which never writes it)."""

from __future__ import annotations

import pytest

from winder.config.job import load_config
from winder.errors import ConfigError
from winder.readback.gcode import parse_program
from tests.configs import tiny_pipe

MACHINE = ("machine:\n  axes: {carriage: X, rotation: A, cross_feed: Z, yaw: B}\n  eye: {clearance: 20}\n"
           "  feed: 3000\n  chord_tolerance: 0.05\n  limits: {carriage: [-500, 800], cross_feed: [0, 300], yaw: [-90, 90]}\n")


@pytest.fixture(scope="module")
def program(tmp_path_factory):
    from winder.export.gcode import gcode_text  # noqa: PLC0415
    from winder.winding.plan import plan  # noqa: PLC0415

    path = tmp_path_factory.mktemp("g64") / "t.yaml"
    path.write_text(tiny_pipe("t", 45, MACHINE), encoding="utf-8")
    job = load_config(path)
    return job, gcode_text(plan(job), job.machine)


def _with_line(text: str, extra: str) -> str:
    lines = text.split("\n")
    first = next(k for k, line in enumerate(lines) if line.startswith("G1 "))
    return "\n".join(lines[:first] + [extra] + lines[first:])


@pytest.mark.parametrize("extra", ["G64 P5", "g64 p0.05", "G64 P0.050"])
def test_path_blending_is_refused_in_a_generic_program(program, extra: str) -> None:
    job, text = program
    parse_program(text, job.machine)  # as written: read
    with pytest.raises(ConfigError, match=r"line \d+: not a move of a generic program: '" + extra):
        parse_program(_with_line(text, extra), job.machine)
