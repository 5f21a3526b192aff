"""Comparing an output with its reference, as readable differences.

Comparison: a difference is reported only where it could not come from round-off in the last
printed digit. Each number is compared within one unit in the last place its writer prints, plus a
relative part for large values (REL_NOISE: the computation's reproducibility across machines, BLAS
builds and process counts); integers must match exactly; a writer's periodic fields are compared
modulo their period. See samples/README.md.
- the summary (JSON): the same structure (keys, list lengths, types); a number within one unit
  of the decimals the summary writes at its key (winder.export.summary.decimals_of), or 1e-6
  relative for keys without fixed decimals. Numbers inside text (notes) by their printed digits.
- CSV: the same header and row count, the same fields per row; a number within one unit of its
  printed last place; text identical. `alpha_deg` is a line angle (winder.export.job_csv:
  PERIODIC_COLUMNS) compared modulo 180.
- G-code (and any other text): the same lines and words; each number within one unit of its
  printed last place.
- PLY: header and faces exact, vertex floats within their last bit (winder.app.compare_ply).
- anything else: byte for byte.
winder.app.compare_files picks the comparison by the file's kind.
"""

from __future__ import annotations

import dataclasses
import json
import math
import re
from dataclasses import dataclass, field

from winder.export.job_csv import PERIODIC_COLUMNS

JSON_RTOL = 1e-6  # summary numbers under a key without fixed decimals
JSON_ATOL = 1e-9
REL_NOISE = 1e-8  # relative reproducibility of the computation (ill-conditioned bends), on top of the printed unit
PRINT_SLACK = 1.0 + 1e-6  # one printed unit, and the binary round-off of the difference itself
MAX_SHOWN = 5  # differences listed per file


@dataclasses.dataclass(frozen=True)
class Difference:
    """One difference: where (line/field or key path), what was expected, what came out."""

    where: str
    expected: str
    got: str
    note: str = ""

    def __str__(self) -> str:
        note = f" ({self.note})" if self.note else ""
        return f"{self.where}: expected {self.expected}, got {self.got}{note}"


@dataclass
class _Collector:
    """Keeps the first MAX_SHOWN differences and counts all of them."""

    limit: int = MAX_SHOWN
    shown: list[Difference] = field(default_factory=list)
    count: int = 0

    def add(self, where: str, expected: object, got: object, note: str = "") -> None:
        self.count += 1
        if len(self.shown) < self.limit:
            self.shown.append(Difference(where, _short(expected), _short(got), note))


def _short(value: object) -> str:
    text = value if isinstance(value, str) else json.dumps(value)
    return text if len(text) <= 100 else text[:97] + "..."


def _close(a: float, b: float, rtol: float, atol: float) -> bool:
    if math.isnan(a) or math.isnan(b):
        return math.isnan(a) and math.isnan(b)
    if math.isinf(a) or math.isinf(b):
        return a == b
    return abs(a - b) <= max(atol, rtol * max(abs(a), abs(b)))


def _tol_note(a: float, b: float, rtol: float, atol: float) -> str:
    tol = max(atol, rtol * max(abs(a), abs(b))) if math.isfinite(a) and math.isfinite(b) else 0.0
    return f"off by {abs(a - b):.3g}, tolerance {tol:.3g}" if math.isfinite(a - b) else ""


UNIT_POWER_RANGE = 308  # decimal exponents of a float's range: a printed place outside is inf or 0


def printed_unit(text: str) -> float:
    """One unit in the last place of a number as printed: "391.680" -> 1e-3; 0.0 for an integer."""
    mantissa, _, exponent = text.lower().partition("e")
    decimals = len(mantissa.partition(".")[2]) if "." in mantissa else 0
    if decimals == 0 and not exponent:
        return 0.0
    try:
        power = int(exponent or 0) - decimals
    except ValueError:  # an exponent of thousands of digits (past int's string limit): far out either way
        power = -UNIT_POWER_RANGE if exponent.startswith("-") else UNIT_POWER_RANGE
    if power >= UNIT_POWER_RANGE:  # "0.0e999": a place past every float, no tolerance from it
        return math.inf
    return 10.0 ** max(power, -UNIT_POWER_RANGE)


def number_tolerance(unit: float, a: float, b: float) -> float:
    """What two printed numbers may differ by: a unit in the last place plus REL_NOISE relative."""
    if unit == 0.0:
        return 0.0
    return unit * PRINT_SLACK + REL_NOISE * max(abs(a), abs(b))


def _printed_close(x: str, y: str, period: float | None = None) -> tuple[bool, str]:
    """Whether two printed numbers are the same value at their printed precision; a note if not."""
    a, b = float(x), float(y)
    if not (math.isfinite(a) and math.isfinite(b)):
        return (a == b or (math.isnan(a) and math.isnan(b))), ""
    # Where the two are printed to different places (%g drops trailing zeros: "0.2" is "0.20"), the
    # finer place is the precision; an integer-looking one ("5" for 5.00001) has no place of its own.
    units = [u for u in (printed_unit(x), printed_unit(y)) if u > 0.0]
    tol = number_tolerance(min(units, default=0.0), a, b)
    diff = abs(a - b)
    if period:
        diff = abs((a - b + 0.5 * period) % period - 0.5 * period)
    ok = diff <= tol
    return ok, ("" if ok else f"off by {diff:.3g}" + (f" modulo {period:g}" if period else "")
                + f", tolerance {tol:.3g}")


# -- CSV -------------------------------------------------------------------------------------------
# Columns naming a row of the job CSV, shown with a difference to say where it is.
_ROW_KEYS = ("layer", "circuit", "pass", "i")


def _number(text: str) -> float | None:
    try:
        value = float(text)
    except ValueError:
        return None
    return value


def compare_csv(expected: str, got: str, limit: int = MAX_SHOWN,
                periodic: dict[str, float] = PERIODIC_COLUMNS) -> tuple[list[Difference], int]:
    """Differences between two CSV texts, field by field: numbers at their printed precision (the
    columns in `periodic` modulo their period), text identical."""
    out = _Collector(limit)
    a_lines, b_lines = expected.splitlines(), got.splitlines()
    if not a_lines or not b_lines:
        if a_lines != b_lines:
            out.add("file", f"{len(a_lines)} lines", f"{len(b_lines)} lines")
        return out.shown, out.count
    header = a_lines[0].split(",")
    keys = [j for j, col in enumerate(header) if col in _ROW_KEYS]
    if a_lines[0] != b_lines[0]:
        out.add("line 1 (header)", a_lines[0], b_lines[0])
    if len(a_lines) != len(b_lines):
        out.add("rows", f"{len(a_lines) - 1} rows", f"{len(b_lines) - 1} rows")
    for n, (la, lb) in enumerate(zip(a_lines[1:], b_lines[1:]), start=2):
        if la == lb:
            continue
        fa, fb = la.split(","), lb.split(",")
        if len(fa) != len(fb):
            out.add(f"line {n}", f"{len(fa)} fields: {la}", f"{len(fb)} fields: {lb}")
            continue
        for j, (x, y) in enumerate(zip(fa, fb)):
            if x == y:
                continue
            col = header[j] if j < len(header) else f"field {j + 1}"
            row = ", ".join(f"{header[k]} {fa[k]}" for k in keys if k != j)
            where = f"line {n}" + (f" ({row})" if row else "") + f", column {col}"
            if _number(x) is None or _number(y) is None:
                out.add(where, x, y)
                continue
            ok, note = _printed_close(x, y, periodic.get(col))
            if not ok:
                out.add(where, x, y, note)
    return out.shown, out.count


# -- G-code and other text: words and numbers ------------------------------------------------------
_NUM = re.compile(r"([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)")


def _split_numbers(line: str) -> list[str]:
    """Alternating text, number, text, ... pieces (text pieces may be empty)."""
    return _NUM.split(line)


def compare_lines(expected: str, got: str, limit: int = MAX_SHOWN) -> tuple[list[Difference], int]:
    """Differences between two line-oriented texts (G-code): the same lines with the same words;
    each number at its printed precision. A difference names the line and the word (`X`, `A`, ...)."""
    out = _Collector(limit)
    a_lines, b_lines = expected.splitlines(), got.splitlines()
    if len(a_lines) != len(b_lines):
        out.add("lines", f"{len(a_lines)} lines", f"{len(b_lines)} lines")
    for n, (la, lb) in enumerate(zip(a_lines, b_lines), start=1):
        if la == lb:
            continue
        pa, pb = _split_numbers(la), _split_numbers(lb)
        if len(pa) != len(pb) or any(x != y for x, y in zip(pa[0::2], pb[0::2])):
            out.add(f"line {n}", la, lb)
            continue
        for k in range(1, len(pa), 2):
            ok, note = _printed_close(pa[k], pb[k])
            if not ok:
                prev = pa[k - 1].rstrip()
                if ";" in "".join(pa[:k]):
                    # In a comment the number follows a word ("circuits 19"), not an axis letter.
                    words = re.findall(r"[A-Za-z_]+", prev)
                    where = (f"line {n}, {words[-1]}" if words else f"line {n}, number {k // 2 + 1}") + " (in a comment)"
                else:
                    where = f"line {n}, word {prev[-1]}" if prev[-1:].isalpha() else f"line {n}, number {k // 2 + 1}"
                out.add(where, pa[k], pb[k], note + f"; line: {lb.strip()}")
    return out.shown, out.count


def compare_bytes(expected: bytes, got: bytes) -> tuple[list[Difference], int]:
    if expected == got:
        return [], 0
    at = next((i for i, (x, y) in enumerate(zip(expected, got)) if x != y), min(len(expected), len(got)))
    return [Difference(f"byte {at}", f"{len(expected)} bytes", f"{len(got)} bytes",
                       "binary files differ")], 1
