"""What a controller's description (winder.config.controllers) changes in a program's text once the
moves are written: its comment form, block numbers, upper case, line length and digits, and the
lines that set the tension and reset the rotary axis. The generic form (`; comments`, no numbers)
needs no pass over the lines (Controller.plain).
"""

from __future__ import annotations

import re
import textwrap

import numpy as np

from winder.config.controllers import Controller
from winder.errors import ExportError
from winder.escape import gcode_comment
from winder.machine.program import MotionProgram

_IDENTIFIER = re.compile(r"[^A-Za-z0-9_]")


def line_fields(program: MotionProgram) -> dict:
    """The fields a header, preamble or footer line may name."""
    return {"name": _IDENTIFIER.sub("_", program.name), "chord_tolerance": program.machine.chord_tolerance}


def template_lines(lines: tuple[str, ...], program: MotionProgram) -> list[str]:
    fields = line_fields(program)
    return [line.format(**fields) for line in lines]


def controller_lines(program: MotionProgram, controller: Controller) -> list[str]:
    """The header's comments on what the controller must be set up for, where the program asks more
    than the generic dialects do: the controller described, the tension command, the rotary axis kept
    (docs/guide/machine-setup.md). None for a program of the built-in dialects without tension."""
    out = []
    if controller.name not in ("generic", "linuxcnc", "marlin", "robot"):
        out.append(f"; controller: {controller.name}" + (f" ({controller.about})" if controller.about else ""))
    if controller.tension and any(seg.tension is not None for segs in program.segments for seg in segs):
        shown = re.sub(r"\{newtons[^}]*\}", "<N>", controller.tension)
        shown = re.sub(r"\{fraction[^}]*\}", f"<N / {controller.tension_full_scale or 0:g} N>", shown)
        out.append(f"; tension: N per band, set where it changes by {shown}")
    rotary = controller.rotary
    if rotary.mode == "wrap" and not program.robot:
        out.append("; rotary axis: modulo 360 (a roll-over axis taking the shortest way), no move half a turn")
    elif rotary.mode.startswith("reset") and not program.robot:
        where = "layer" if rotary.mode == "reset_per_layer" else "pass"
        out.append(f"; rotary axis: cumulative within a {where}, set to its value modulo 360 at each {where}'s "
                   f"first move ({rotary.reset})" + (f", {rotary.cancel} at the end" if rotary.cancel else ""))
    return out


def reset_line(controller: Controller, letter: str, value: float) -> str:
    """The line that sets the rotary axis `letter` to `value` (deg) (Rotary.reset)."""
    return controller.rotary.reset.format(axis=letter, value=f"{value + 0.0:.{controller.angular}f}")


def comment_text(controller: Controller, text: str) -> str:
    """A comment's text as the controller's form takes it: no character that would end it early."""
    if "(" in controller.comment:  # ISO-style controls read `;` as an end of block (Fanuc's EOB notation)
        text = gcode_comment(text).replace(";", ",")
    return text.upper() if controller.uppercase else text


def render(lines: list[str], controller: Controller, header: int) -> list[str]:
    """The program's lines in the controller's form: the engine's `; ` comments in its comment form,
    block numbers before the code lines, upper case; the first `header` lines (its header) as given.
    ExportError for a code line past max_line_length; a comment is wrapped to fit."""
    if controller.plain:
        return lines
    before, _, after = controller.comment.partition("{text}")
    numbers = controller.block_numbers
    n = numbers[0] if numbers else 0
    room = controller.max_line_length - len(before) - len(after)
    out = [line.upper() if controller.uppercase else line for line in lines[:header]]
    for line in lines[header:]:
        if line.startswith(";"):
            text = comment_text(controller, line[1:].strip())
            pieces = [text] if len(text.encode("utf-8")) <= room else textwrap.wrap(text, max(room, 20))
            out += [f"{before}{piece}{after}" for piece in pieces]
            continue
        code = line.upper() if controller.uppercase else line
        if numbers and line.strip() != "%":
            code = f"N{n} {code}"
            n = n + numbers[1] if n + numbers[1] <= numbers[2] else numbers[0]
        if len(code.encode("utf-8")) > controller.max_line_length:
            raise ExportError(f"a line of the program would have {len(code.encode('utf-8'))} characters, past the "
                              f"controller's {controller.max_line_length} (max_line_length): {code[:60]!r}")
        out.append(code)
    return out


def check_digits(columns: np.ndarray, letters: tuple[str, ...], decimals: tuple[int, ...],
                 controller: Controller) -> None:
    """ExportError where a value as written has more digits than the controller takes (max_digits)."""
    if controller.max_digits is None or columns.size == 0:
        return
    for j, (letter, d) in enumerate(zip(letters, decimals)):
        k = int(np.argmax(np.abs(columns[:, j])))
        value = float(columns[k, j])
        digits = len(str(int(abs(round(value, d))))) + d
        if digits > controller.max_digits:
            hint = ("; keep the rotary axis with rotary: {mode: wrap} (a modulo axis) or {mode: reset_per_layer} in "
                    "a post file" if j == 1 else "")
            raise ExportError(f"{letter}{value:.{d}f} has {digits} digits, past the {controller.max_digits} the "
                              f"{controller.name} controller takes (max_digits){hint}")
