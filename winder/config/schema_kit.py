"""Building blocks of the config's JSON Schema (winder.config.schema): numbers whose description says
their unit and range, closed objects, and the `type`-tagged kinds the readers parse with Reader.typed.

Every description is written for a process engineer reading it in an editor's tooltip: what the key
is, its unit, its range and its default, in that order.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from winder.config.reader import MAX_SIZE

Schema = dict[str, Any]


def _bound(value: float) -> str:
    return f"{value:g}"


def _range_text(lo: float | None, hi: float | None, lo_open: bool, hi_open: bool) -> str:
    """`> 0`, `in [0, 1]`, `<= 1e+06`: the range as the readers' messages write it."""
    if lo is not None and hi is not None:
        return f"in {'(' if lo_open else '['}{_bound(lo)}, {_bound(hi)}{')' if hi_open else ']'}"
    if lo is not None:
        return f"{'>' if lo_open else '>='} {_bound(lo)}"
    if hi is not None:
        return f"{'<' if hi_open else '<='} {_bound(hi)}"
    return "any finite number"


def number(what: str, unit: str = "", *, lo: float | None = None, hi: float | None = None, lo_open: bool = False,
           hi_open: bool = False, default: Any = None, integer: bool = False) -> Schema:
    """A number (or a whole number) with its unit and range in the description and the keywords.

    Examples
    --------
    >>> number("Band width as laid", "mm", lo=0, lo_open=True)["description"]
    'Band width as laid. mm, > 0.'
    >>> number("Points per pass", integer=True, lo=3, hi=100000, default=200)["description"]
    'Points per pass. Whole number, in [3, 100000]. Default 200.'
    """
    out: Schema = {"type": "integer" if integer else "number"}
    if lo is not None:
        out["exclusiveMinimum" if lo_open else "minimum"] = lo
    if hi is not None:
        out["exclusiveMaximum" if hi_open else "maximum"] = hi
    head = ("Whole number" if integer else "") + (", " if integer and unit else "") + unit
    text = f"{what}. {head + ', ' if head else ''}{_range_text(lo, hi, lo_open, hi_open)}."
    if default is not None:
        out["default"] = default
        text += f" Default {default:g}." if isinstance(default, (int, float)) else f" Default {default}."
    out["description"] = text
    return out


def positive(what: str, unit: str, hi: float | None = None, default: Any = None) -> Schema:
    """A size > 0 (Reader.positive): lengths, feeds, tolerances."""
    return number(what, unit, lo=0, lo_open=True, hi=hi, default=default)


def length(what: str, default: Any = None) -> Schema:
    """A length in mm, > 0 and <= MAX_SIZE (Reader.positive)."""
    return positive(what, "mm", MAX_SIZE, default)


def choice(what: str, values: Sequence[str], default: str | None = None) -> Schema:
    """One of a few words."""
    out: Schema = {"enum": list(values), "description": f"{what}: one of {', '.join(values)}."}
    if default is not None:
        out["default"] = default
        out["description"] += f" Default {default}."
    return out


def closed(what: str, properties: Mapping[str, Schema], required: Sequence[str] = (), **extra: Any) -> Schema:
    """A mapping refusing keys it does not name (Reader.mapping)."""
    out: Schema = {"type": "object", "description": what, "properties": dict(properties),
                   "additionalProperties": False}
    if required:
        out["required"] = list(required)
    out.update(extra)
    return out


def tagged(what: str, kinds: Mapping[str, tuple[str, Mapping[str, Schema], Sequence[str]]],
           tag: str = "type") -> Schema:
    """A mapping whose `type` names its kind (Reader.typed): kinds maps each name to (what it is, its
    keys but the tag, the required ones). One closed object per kind, so an editor completes the keys of
    the kind typed and refuses the others'."""
    variants = []
    for name, (meaning, properties, required) in kinds.items():
        keys = {tag: {"const": name, "description": meaning}, **properties}
        variants.append(closed(f"{name}: {meaning}.", keys, (tag, *required)))
    return {"type": "object", "description": f"{what} ({tag}: {', '.join(kinds)}).", "oneOf": variants}


def pair(what: str, first: str, second: str, unit: str = "") -> Schema:
    """A list of two numbers, [first, second]."""
    return {"type": "array", "description": f"{what}: [{first}, {second}]{', ' + unit if unit else ''}.",
            "items": {"type": "number"}, "minItems": 2, "maxItems": 2}


def nullable(schema: Schema) -> Schema:
    """schema, or null: an empty section (`winding:`) reads as left out."""
    out = dict(schema)
    out["type"] = [schema["type"], "null"]
    return out
