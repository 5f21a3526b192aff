"""Axis travel limits (machine.limits): a program exceeding them is refused, naming the pass, the axis,
the value and the limits. The limits name winder axes; robot poses have none.

The limits hold for the values as the program writes them (AXIS_DECIMALS decimals): a yaw of 44.42996
is written B44.430 and breaks a limit of 44.4298, while a cross-feed of 80.00000000000001 is written
Z80.000 and keeps a limit of 80."""

from __future__ import annotations

import numpy as np

from winder.config.machine import MachineConfig
from winder.errors import ExportError
from winder.machine.kinematics import EyePath

ROLE_UNITS = {"carriage": "mm", "rotation": "deg", "cross_feed": "mm", "yaw": "deg"}
AXIS_DECIMALS = 3  # decimals of mm and deg in every program (winder.export.dialects.text writes them)


def as_written(values: np.ndarray, near: tuple[float, ...], decimals: int = AXIS_DECIMALS) -> np.ndarray:
    """values (k,) as the program prints them, rounded to decimals. np.round scales by 10^decimals,
    which can differ from the printed (correctly rounded) text at a tie; the values within one unit
    of the last decimal of a number in near (the limits) are therefore rounded through the text."""
    rounded = np.round(values, decimals)
    step = 10.0 ** -decimals
    close = np.zeros(values.shape, dtype=bool)
    for bound in near:
        close |= np.abs(values - bound) <= step
    for k in np.flatnonzero(close):
        rounded[k] = float(f"{values[k]:.{decimals}f}")
    return rounded


def check_limits(path: EyePath, machine: MachineConfig, where: str) -> None:
    """Refuse axis values outside machine.limits; the message names the axis, value, limit, where."""
    letters = machine.axes
    for role, (lo, hi) in machine.limits.items():
        values = path.axes()[role]
        if values.size == 0:
            continue
        values = np.asarray(values, dtype=float)
        margin = 10.0 ** -AXIS_DECIMALS  # farther inside than this, rounding as written cannot leave the limits
        if values.min() > lo + margin and values.max() < hi - margin:
            continue
        values = as_written(values, (lo, hi))
        bad = np.flatnonzero((values < lo) | (values > hi))
        if bad.size:
            k = int(bad[np.argmax(np.maximum(lo - values[bad], values[bad] - hi))])
            unit = ROLE_UNITS[role]
            raise ExportError(
                f"{where}: machine.limits.{role}: axis {getattr(letters, role)} ({role.replace('_', '-')}) "
                f"would reach {values[k]:.3f} {unit} (at point {k} of the pass, carriage at {path.x[k]:.3f} mm), "
                f"outside the limits [{lo:g}, {hi:g}] {unit}")
