"""The small elbow on each arm's robot cell, planned and built once per test session (the robot-cell
tests of tests/export and tests/readback share it): a shorter elbow with a wider band than
samples/elbow.yaml, whose full job takes a minute or more."""

from __future__ import annotations

import dataclasses
import functools
import tempfile
from pathlib import Path

from winder.config.robot import Pose, RobotCell

SMALL_ELBOW = """
name: small_elbow
mandrel:
  axis:
    type: path
    segments:
      - line: 60
      - arc: {radius: 150, angle: 90, toward: 0}
      - line: 60
  profile: {type: constant, radius: 40}
winding:
  band_width: 25
  friction: 0.3
  layers:
    - {type: helical, angle: 45, slip: auto}
machine:
  eye: {clearance: 25}
  robot: {arm: kuka_kr16}
"""
CELLS = {"kuka_kr16": Pose(x=1000, z=800, ry=-90, rz=-90), "abb_irb4600": Pose(x=1000, z=800, ry=-90, rz=-90),
         "ur10e": Pose(x=800, z=500, ry=-90, rz=-90)}


@functools.cache
def small_elbow_cells():
    """(job, plan, {arm: (machine, program)}) of the small elbow on every arm's cell of CELLS."""
    from winder.config.job import load_config  # noqa: PLC0415
    from winder.machine.program import build_program  # noqa: PLC0415
    from winder.winding.plan import plan as plan_job  # noqa: PLC0415

    path = Path(tempfile.mkdtemp(prefix="cells")) / "small_elbow.yaml"
    path.write_text(SMALL_ELBOW)
    job = load_config(path)
    plan = plan_job(job)
    programs = {}
    for arm, ring in CELLS.items():
        machine = dataclasses.replace(job.machine, cell=RobotCell(arm, ring=ring))
        programs[arm] = (machine, build_program(plan, machine))
    return job, plan, programs
