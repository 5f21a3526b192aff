"""The generic G-code dialect of a straight-axis winder (docs/guide/conventions.md).

`G1` moves of the four axes, letters from machine.axes, in the order carriage, rotation, cross-feed,
yaw, with the feed F (mm/min) on every move; values with 3 decimals (mm, deg); the preamble G21 G90
G94 and M2 at the end. The axis values are the motion program's (winder.machine.program), whose
docstring and winder.machine.kinematics define them.
"""

from __future__ import annotations

from winder.export.dialects.text import DECIMALS, BaseDialect
from winder.machine.program import MotionProgram

PREFIX = "G1"


class GenericGcode(BaseDialect):
    """A straight-axis winder's G-code."""

    prefix = PREFIX

    def letters(self, program: MotionProgram) -> tuple[str, ...]:
        ax = program.machine.axes
        return (ax.carriage, ax.rotation, ax.cross_feed, ax.yaw)

    def decimals(self, program: MotionProgram) -> tuple[int, ...]:
        return (DECIMALS,) * 4

    def describe(self, program: MotionProgram) -> list[str]:
        ax = program.machine.axes
        return [f"; machine: straight-axis winder; {ax.carriage} carriage (mm), {ax.rotation} mandrel "
                f"rotation (deg, cumulative), {ax.cross_feed} cross-feed: eye distance from the axis "
                f"(mm), {ax.yaw} eye yaw (deg)",
                f"; kinematics: eye at mandrel-frame ({ax.cross_feed} cos(-{ax.rotation}), "
                f"{ax.cross_feed} sin(-{ax.rotation}), {ax.carriage}), on the tangent line of the "
                "fiber path at its contact point",
                f"; yaw: {ax.yaw} = eye rotation about the cross-feed axis from the hoop orientation: the "
                f"free fiber's direction d at the eye, {ax.yaw} = atan2(d.z, d.u), u the eye's tangential direction",
                f"; yaw: 0 hoop, + forward, - return; on a cylinder of radius R with the eye at {ax.cross_feed}: "
                f"tan({ax.yaw}) = {ax.cross_feed} / (R tan(alpha)), alpha the winding angle on the mandrel",
                "; F: the fiber's feed along its path on the mandrel (machine.feed), not the axes' speed",
                "; F: for a controller that reads F as the axes' speed (G94) use the linuxcnc dialect (inverse "
                "time, from the machine dynamics)"]


def make(program: MotionProgram, band_width: float = 0.0) -> GenericGcode:
    """The dialect registry's entry (winder.config.dialects)."""
    return GenericGcode()
