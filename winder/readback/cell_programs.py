"""A robot cell's program read back (docs/math/10-robot-cell.md 10.8): its language's reader
(winder.readback.krl, rapid, urscript), the arm followed through it (winder.readback.cells.follow),
the eye at every pose and halfway along every move, each move's time with the bridges'."""

from __future__ import annotations

import numpy as np

from winder.config.arms import ARMS
from winder.config.machine import MachineConfig
from winder.errors import ConfigError
from winder.machine.cell_frames import eye_of
from winder.readback.cells import bridge_times, follow, midpoints
from winder.readback.krl import read_krl
from winder.readback.parsed import ParsedProgram
from winder.readback.rapid import read_rapid
from winder.readback.urscript import read_urscript

READERS = {"krl": read_krl, "rapid": read_rapid, "urscript": read_urscript}


def parse_cell(text: str, machine: MachineConfig, source: str, dialect: str) -> ParsedProgram:
    """The ParsedProgram (winder.readback.gcode) of a robot cell's program."""
    if machine.cell is None:
        raise ConfigError(f"{source}: a {dialect} program needs the robot cell it was written for: the config's "
                          f"machine.robot must be a mapping with an arm")
    arm = ARMS[machine.cell.arm]
    if arm.language != dialect:
        raise ConfigError(f"{source}: a {dialect} program, but the config's arm {arm.name} ({arm.maker}) runs "
                          f"{arm.language}: the program was written for another cell")
    read = READERS[dialect](text, machine, source)
    rows = read.rows
    if not rows.keys:
        raise ConfigError(f"{source}: the program has no moves")
    joints = follow(machine, read, source)
    if read.then is not None:
        read.then()
    move_s = np.array(rows.times) + bridge_times(machine, read, joints)
    eye = eye_of(read.frames, read.external)
    values = np.column_stack([eye, np.zeros_like(eye)])
    return ParsedProgram(dialect, values, np.array(rows.keys, dtype=np.int64).reshape(-1, 3), tuple(rows.kinds),
                         np.full(len(rows.keys), np.nan), np.array(rows.lines, dtype=int), rows.job,
                         job_line=rows.job_line,
                         mids=read.mids if read.mids is not None else midpoints(read.frames, read.external),
                         move_s=move_s, tension=np.array(rows.tensions, dtype=float))
