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
    tension: np.ndarray | None = None  # (m,) the tension (N per band) set when each row's move runs, nan: none
    case_blind: bool = False  # the controller writes its comments in upper case (the job line's name too)

    @property
    def robot(self) -> bool:
        return self.dialect in ("robot", "krl", "rapid", "urscript")


def layer_tensions(parsed: ParsedProgram) -> tuple[dict, ...]:
    """Per layer whose rows run at a tension read back: {"layer", "tension_n" (its first row's),
    "tension_range_n" [least, largest]} (N per band), in layer order; () without any tension."""
    if parsed.tension is None or not np.any(np.isfinite(parsed.tension)):
        return ()
    out = []
    for layer in np.unique(parsed.keys[:, 0]).tolist():
        read = parsed.tension[parsed.keys[:, 0] == layer]
        read = read[np.isfinite(read)]
        if read.size:
            out.append({"layer": int(layer), "tension_n": round(float(read[0]), 3),
                        "tension_range_n": [round(float(read.min()), 3), round(float(read.max()), 3)]})
    return tuple(out)
