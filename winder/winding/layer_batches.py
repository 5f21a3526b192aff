"""The layers the machine stage takes in one batch (winder.machine.chunks): consecutive layers up to
a number of planned points, a larger layer alone; the whole plan at once where the program is a
robot's poses or its rotation or yaw limits are checked on the joined values. The work budget's memory
estimate counts the largest batch (winder.winding.budget), so both decide by these rules."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from winder.config.machine import MachineConfig
    from winder.geometry.surface import SweepSurface

__all__ = ["point_groups", "robot_poses", "whole_plan"]


def robot_poses(machine: MachineConfig | None, surface: SweepSurface) -> bool:
    """Whether the program is made of robot poses: machine.robot or a bent axis."""
    return bool((machine is not None and machine.robot) or not surface.curve.is_straight)


def whole_plan(machine: MachineConfig | None, surface: SweepSurface) -> bool:
    """Whether the machine stage takes the whole plan in one batch: robot poses, or rotation or yaw
    limits (checked on the joined values)."""
    limited = machine is not None and (machine.limits.rotation is not None or machine.limits.yaw is not None)
    return limited or robot_poses(machine, surface)


def point_groups(points: Sequence[int], most: int) -> list[list[int]]:
    """The indices of consecutive items of points (k,) (each layer's planned points) in groups of at
    most `most` points, an item larger than that alone."""
    groups: list[list[int]] = [[]]
    count = 0
    for i, n in enumerate(points):
        if groups[-1] and count + n > most:
            groups.append([])
            count = 0
        groups[-1].append(i)
        count += n
    return [g for g in groups if g]
