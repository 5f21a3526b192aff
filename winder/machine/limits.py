"""Axis travel limits (machine.limits): a program exceeding them is refused, naming the pass, the axis,
the value and the limits. The limits name winder axes; robot poses have none."""

from __future__ import annotations

import numpy as np

from winder.config.machine import MachineConfig
from winder.errors import ExportError
from winder.machine.kinematics import EyePath

ROLE_UNITS = {"carriage": "mm", "rotation": "deg", "cross_feed": "mm", "yaw": "deg"}


def check_limits(path: EyePath, machine: MachineConfig, where: str) -> None:
    """Refuse axis values outside machine.limits; the message names the axis, value, limit, where."""
    letters = machine.axes
    for role, (lo, hi) in machine.limits.items():
        values = path.axes()[role]
        if values.size == 0:
            continue
        bad = np.flatnonzero((values < lo) | (values > hi))
        if bad.size:
            k = int(bad[np.argmax(np.maximum(lo - values[bad], values[bad] - hi))])
            unit = ROLE_UNITS[role]
            raise ExportError(
                f"{where}: machine.limits.{role}: axis {getattr(letters, role)} ({role.replace('_', '-')}) "
                f"would reach {values[k]:.3f} {unit} (at point {k} of the pass, carriage at {path.x[k]:.3f} mm), "
                f"outside the limits [{lo:g}, {hi:g}] {unit}")
