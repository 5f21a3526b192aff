"""Robot poses for bent mandrels (machine.robot, or a bent axis): one line per kept eye pose in the
mandrel frame,

    POSE X<x> Y<y> Z<z> I<i> J<j> K<k> F<feed>

X Y Z the eye position (mm, 3 decimals), I J K the unit vector from the eye to its contact point
(6 decimals), the free fiber as it leaves the eye (winder.machine.kinematics.robot_poses).
machine.limits name winder axes and are not applied to poses. The preamble and comments are those
of the G-code dialect.
"""

from __future__ import annotations

from winder.export.dialects.text import DECIMALS, BaseDialect
from winder.machine.program import MotionProgram

DIRECTION_DECIMALS = 6  # unit vectors of robot poses
PREFIX = "POSE"
LETTERS = ("X", "Y", "Z", "I", "J", "K")


class RobotPoses(BaseDialect):
    """Eye poses for a robot."""

    prefix = PREFIX

    def letters(self, program: MotionProgram) -> tuple[str, ...]:
        return LETTERS

    def decimals(self, program: MotionProgram) -> tuple[int, ...]:
        return (DECIMALS,) * 3 + (DIRECTION_DECIMALS,) * 3

    def describe(self, program: MotionProgram) -> list[str]:
        return ["; machine: robot; eye poses in the mandrel frame",
                "; POSE X Y Z: eye position (mm); I J K: unit fiber direction from the eye to its "
                "contact point; F feed (mm/min)"]


def make(program: MotionProgram, band_width: float = 0.0) -> RobotPoses:
    """The dialect registry's entry (winder.config.dialects)."""
    return RobotPoses()
