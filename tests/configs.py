"""Tiny job configs shared by the tests: a straight pipe (300 mm, radius 40) with one helical layer
of 8 points, planned in well under a second."""

from __future__ import annotations

# {name}, {angle} (the helical layer's, deg) and {machine} (YAML lines appended, or "").
TINY_PIPE = """\
name: {name}
mandrel:
  axis: {{type: line, length: 300}}
  profile: {{type: constant, radius: 40}}
winding:
  band_width: 10
  points: 8
  layers:
    - {{type: helical, angle: {angle}}}
{machine}"""


def tiny_pipe(name: str = "tiny", angle: float = 45, machine: str = "") -> str:
    """The tiny pipe's YAML text."""
    return TINY_PIPE.format(name=name, angle=angle, machine=machine)
