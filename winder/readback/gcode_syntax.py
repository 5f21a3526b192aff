"""What a G-code reader needs from a controller's description (winder.config.controllers), the same
description its writer follows: the comment form, the tension command, the rotary axis' reset, the
lines around the moves and the one that ends the program. winder.readback.gcode reads through it.
"""

from __future__ import annotations

import re

import numpy as np

from winder.config.controllers import Controller, builtin, read_pattern
from winder.config.machine import MachineConfig

DETECTED = ("generic", "linuxcnc", "marlin", "robot")  # told apart by their text, unless the config says
_BLOCK_NUMBER = re.compile(r"^N[0-9]+\s*", re.I)


class Syntax:
    """The reading rules of one controller (module docstring)."""

    def __init__(self, controller: Controller, code) -> None:
        self.controller = controller
        before, _, after = controller.comment.partition("{text}")
        self._open, self._close = before.strip(), after.strip()
        self.tension = controller.tension_reader()  # the tension (N) a line sets, else None
        reset = controller.rotary.reset if controller.rotary.mode.startswith("reset") else None
        self._reset = read_pattern(reset) if reset else None
        self.wrap = controller.rotary.mode == "wrap"
        end = controller.end_code()
        self.end = (code(end) or None) if end else None  # a footer of comments alone ends nothing
        # A controller whose footer has no end code writes none: its programs are whole without one
        # (simulate still checks that the last move ends the plan, as for marlin).
        self.needs_end = self.end is not None
        lines = (*controller.header, *controller.preamble, *controller.footer)
        if controller.rotary.cancel:
            lines += (controller.rotary.cancel,)
        self._skip = [read_pattern(line, code) for line in lines if "{" in line or code(line) != self.end]
        self._plain = {code(line) for line in lines if "{" not in line} - {self.end}
        self.case_blind = controller.uppercase

    @staticmethod
    def bare(line: str) -> str:
        """A line without its block number."""
        return _BLOCK_NUMBER.sub("", line) if line[:1] in "Nn" else line

    def comment(self, bare: str) -> str | None:
        """The text of a comment line (the controller's form, or winder's `;`), else None."""
        if bare.startswith(";"):
            return bare[1:].strip()
        if self._open and bare.startswith(self._open) and bare.endswith(self._close):
            return bare[len(self._open):len(bare) - len(self._close)].strip()
        return None

    def reset(self, bare: str) -> float | None:
        """The position (deg) a rotary reset line sets the axis to, else None."""
        hit = self._reset.match(bare) if self._reset is not None else None
        return float(hit["value"]) if hit else None

    def skip(self, code: str) -> bool:
        """Whether a code line is one of the controller's own lines around the moves (not its end)."""
        return code in self._plain or any(p.match(code) for p in self._skip)


def syntax_of(machine: MachineConfig, detected: str, code) -> Syntax:
    """The rules a program for `machine` is read by: its post file's or named dialect's, or (the
    dialects told apart by their text) the one its text shows."""
    if machine.controller.cell:  # a robot cell's config: its G-code is the pose listing
        return Syntax(builtin("robot"), code)
    if machine.post is not None or machine.dialect not in DETECTED:
        return Syntax(machine.controller, code)
    return Syntax(builtin(detected), code)


def unwrap(rotation: np.ndarray) -> np.ndarray:
    """A modulo axis' values back to a cumulative rotation: each move the shortest way (what the
    controller does with them)."""
    return np.unwrap(rotation, period=360.0) if rotation.size else rotation
