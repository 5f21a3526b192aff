"""Comparing a summary (JSON) with its reference (winder.app.compare for the rules and the other
formats): the same structure (keys, list lengths, types); a number within one unit of the decimals
the summary writes at its key (winder.export.summary.decimals_of), or JSON_RTOL relative for keys
without fixed decimals; integers exact; numbers inside text (notes) by their printed digits.
"""

from __future__ import annotations

import json
import math
from typing import Any

from winder.app.compare import (JSON_ATOL, JSON_RTOL, MAX_SHOWN, Difference, _close, _Collector, _printed_close,
                                _short, _split_numbers, _tol_note, number_tolerance)
from winder.export.summary import decimals_of


def compare_json(expected: str, got: str, rtol: float = JSON_RTOL, atol: float = JSON_ATOL,
                 limit: int = MAX_SHOWN) -> tuple[list[Difference], int]:
    """Differences between two JSON texts (first `limit` of them) and their count."""
    out = _Collector(limit)
    try:
        a = json.loads(expected)
    except (ValueError, RecursionError) as exc:  # RecursionError: nested past Python's stack
        out.add("(reference)", "valid JSON", f"unreadable: {exc}")
        return out.shown, out.count
    try:
        b = json.loads(got)
    except (ValueError, RecursionError) as exc:
        out.add("(output)", "valid JSON", f"unreadable: {exc}")
        return out.shown, out.count
    _walk(a, b, "", out, rtol, atol)
    return out.shown, out.count


def _kind(v: Any) -> str:
    if v is None:
        return "null"
    if isinstance(v, bool):
        return "boolean"
    if isinstance(v, (int, float)):
        return "number"
    if isinstance(v, str):
        return "text"
    return "list" if isinstance(v, list) else "object"


def _walk(a: Any, b: Any, path: str, out: _Collector, rtol: float, atol: float) -> None:
    where = path or "(top level)"
    ka, kb = _kind(a), _kind(b)
    if ka != kb:
        out.add(where, f"{ka} {_short(a)}", f"{kb} {_short(b)}")
    elif ka == "object":
        for key in a:
            sub = f"{path}.{key}" if path else key
            if key not in b:
                out.add(sub, _short(a[key]), "(key missing)")
            else:
                _walk(a[key], b[key], sub, out, rtol, atol)
        for key in b:
            if key not in a:
                sub = f"{path}.{key}" if path else key
                out.add(sub, "(no such key)", _short(b[key]))
    elif ka == "list":
        if len(a) != len(b):
            out.add(where, f"{len(a)} items", f"{len(b)} items")
        for i, (x, y) in enumerate(zip(a, b)):
            _walk(x, y, f"{path}[{i}]", out, rtol, atol)
    elif ka == "number":
        decimals = decimals_of(path) if isinstance(a, float) or isinstance(b, float) else None
        x, y = float(a), float(b)
        if isinstance(a, int) and isinstance(b, int):
            if a != b:
                out.add(where, a, b)
        elif decimals is not None and math.isfinite(x) and math.isfinite(y):
            tol = number_tolerance(10.0 ** -decimals, x, y)
            if abs(x - y) > tol:
                out.add(where, a, b, f"off by {abs(x - y):.3g}, tolerance {tol:.3g}")
        elif not _close(x, y, rtol, atol):
            out.add(where, a, b, _tol_note(x, y, rtol, atol))
    elif ka == "text" and a != b:
        # Text may quote numbers ("dwells lengthened to 14.561 deg"): the same words, and each
        # number within the tolerance, is the same text.
        pa, pb = _split_numbers(a), _split_numbers(b)
        at = 0  # where the first piece that differs starts in a (a round-off digit before it is no difference)
        for k, (x, y) in enumerate(zip(pa, pb)):
            if x != y and (k % 2 == 0 or not _printed_close(x, y)[0]):
                break
            at += len(x)
        else:
            if len(pa) == len(pb):
                return
        out.add(where, *_excerpts(a, b, at))
    elif a != b:
        out.add(where, json.dumps(a), json.dumps(b))


def _excerpts(a: str, b: str, at: int, around: int = 40) -> tuple[str, str]:
    """Two long texts as quoted excerpts around `at`, where they differ (a note of 200 characters
    cut at 100 hid the "friction 0.25" that changed near its end)."""
    start = max(0, at - around)
    return tuple(("..." if start else "") + json.dumps(t[start:at + around])
                 + ("..." if at + around < len(t) else "") for t in (a, b))
