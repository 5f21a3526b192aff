"""Robot poses for bent mandrels (machine.robot, or a bent axis): one G-code line per kept eye pose in
the mandrel frame, as a five-axis machine's tool pose,

    G1 X<x> Y<y> Z<z> B<b> C<c> F<feed>

X Y Z the eye position (mm, 3 decimals); B and C the free fiber's direction as it leaves the eye
toward its contact point (winder.machine.kinematics.robot_poses), as the spherical angles of a
B-C head: B from the mandrel frame's +Z, C about +Z from +X (deg, 6 decimals: 2e-8 rad; C
unwrapped along the program, so it never jumps a turn between poses). The file is G-code any
interpreter reads (LinuxCNC's rs274 reads it); machine.limits name winder axes and are not applied to
poses. The preamble and comments are those of the G-code dialect.
"""

from __future__ import annotations

import numpy as np

from winder.export.dialects.text import DECIMALS, BaseDialect
from winder.machine.program import MotionProgram

ANGLE_DECIMALS = 6  # deg of B and C
LETTERS = ("X", "Y", "Z", "B", "C")


def angles(directions: np.ndarray) -> np.ndarray:
    """(m, 2) B and C (deg) of unit directions (m, 3): B = acos(k), C = atan2(j, i) unwrapped."""
    d = np.asarray(directions, dtype=float)
    b = np.degrees(np.arccos(np.clip(d[:, 2], -1.0, 1.0)))
    return np.column_stack([b, np.degrees(np.unwrap(np.arctan2(d[:, 1], d[:, 0])))])


def directions(bc: np.ndarray) -> np.ndarray:
    """(m, 3) unit directions of B and C (m, 2) in degrees (the inverse of angles)."""
    b, c = np.radians(bc[:, 0]), np.radians(bc[:, 1])
    return np.column_stack([np.sin(b) * np.cos(c), np.sin(b) * np.sin(c), np.cos(b)])


class RobotPoses(BaseDialect):
    """Eye poses for a robot, written as five-axis G-code."""

    def letters(self, program: MotionProgram) -> tuple[str, ...]:
        return LETTERS

    def decimals(self, program: MotionProgram) -> tuple[int, ...]:
        return (DECIMALS,) * 3 + (ANGLE_DECIMALS,) * 2

    def columns(self, program: MotionProgram) -> np.ndarray:
        return np.column_stack([program.values[:, :3], angles(program.values[:, 3:6])])

    def describe(self, program: MotionProgram) -> list[str]:
        return ["; machine: robot; eye poses in the mandrel frame",
                "; X Y Z: eye position (mm); B C: the fiber's direction from the eye to its contact point, "
                "B from +Z, C about +Z from +X (deg); F feed (mm/min)"]


def make(program: MotionProgram, band_width: float = 0.0) -> RobotPoses:
    """The dialect registry's entry (winder.config.dialects)."""
    return RobotPoses(program.machine.controller)
