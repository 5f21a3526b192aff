"""A winding program read back (winder.readback.gcode for G-code, cells for robot languages)."""

from __future__ import annotations

import dataclasses

import numpy as np


@dataclasses.dataclass(frozen=True, eq=False)
class ParsedProgram:
    """A program read back.

    dialect : the dialect it was read as. values : (m, 4) or (m, 6) rows (module docstring).
    keys : (m, 3) int, (layer, circuit, pass) of each row. kinds : (m,) the pass kind words.
    feed : (m,) the F word of each row (nan where none). line : (m,) the line number of each row.
    job : the name on the program's `; job:` line, if it has one.
    """

    dialect: str
    values: np.ndarray
    keys: np.ndarray
    kinds: tuple[str, ...]
    feed: np.ndarray
    line: np.ndarray | None = None
    job: str | None = None
    job_line: int | None = None  # the line number of the `; job:` line
    mids: np.ndarray | None = None  # (m, 3) a robot cell's eye halfway along each move (winder.readback.cells)
    move_s: np.ndarray | None = None  # (m,) a robot cell's move times, as its program states them

    @property
    def robot(self) -> bool:
        return self.dialect in ("robot", "krl", "rapid", "urscript")
