"""What `check` can say of a robot cell without planning (docs/math/10-robot-cell.md 10.4): a ring
farther from the arm's base than any flange of the arm can be, plus the mandrel's mount and the
mandrel's own extent, can wind nothing; the job is refused as invalid (exit 2, by `check` as by `run`)
before any computation (a robot language the cell's arm does not run, or whose module name the job's
name cannot be, is refused likewise: winder.export.robot_programs.require_cell)."""

from __future__ import annotations

import numpy as np

from winder.config.arms import ARMS
from winder.config.robot import RobotCell
from winder.errors import ConfigError
from winder.geometry.surface import SweepSurface

EXTENT_SAMPLES = 512  # guide stations sampled for the mandrel's extent from its origin


def arm_span(name: str) -> float:
    """The farthest the flange can be from the arm's base origin (mm): the sum of its link lengths
    (a bound by the triangle inequality, larger than the maker's reach)."""
    arm = ARMS[name]
    d, a = np.abs(arm.dh[:, 0]), np.abs(arm.dh[:, 1])
    return float(np.sum(d) + np.sum(a))


def check_cell_reach(cell: RobotCell, surface: SweepSurface, source: str | None = None) -> None:
    """ConfigError where no station of the mandrel can be brought to the ring."""
    t = np.linspace(0.0, surface.axial_length, EXTENT_SAMPLES)
    extent = float(np.max(np.linalg.norm(surface.curve.evaluate(t).x, axis=1)))
    tool = float(np.linalg.norm(cell.tool.matrix()[:3, 3]))
    ring = cell.ring.matrix()[:3, 3] - cell.base.matrix()[:3, 3]
    distance = float(np.linalg.norm(ring))
    span = arm_span(cell.arm)
    if distance > span + tool + extent:
        raise ConfigError(
            f"the ring is {distance:.0f} mm from the {cell.arm}'s base, but its flange reaches at most {span:.0f} mm "
            f"and the mandrel's stations lie within {tool + extent:.0f} mm of the flange (mount {tool:.0f} mm, "
            f"mandrel {extent:.0f} mm): no pose can be reached", file=source, key_path="machine.robot.positioner.origin")

