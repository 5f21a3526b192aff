"""The report's tables, from the summary dict (winder.export.summary.summary_dict) alone, so the page
shows exactly the numbers of `<name>.summary.json` (but for the passes laid, counted from the circuits:
the summary's `passes` counts the CSV's pieces, turnarounds included).

Columns appear only when some layer has the value: a plan from a laminate- or friction-aware planner
adds thickness, masses and the friction used, and the table grows with it.
"""

from __future__ import annotations

import html
from collections.abc import Callable
from typing import Any

COVERED_OK = 0.999  # covered fraction below which the cell is flagged (the planner's own target)


def _num(value: Any, decimals: int) -> str:
    if value is None:
        return "–"
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return html.escape(str(value))
    return f"{value:,.{decimals}f}".replace(",", "\u2009")


def duration(seconds: float | None) -> str:
    """h:mm:ss (or m:ss) of a time in seconds."""
    if seconds is None:
        return "–"
    total = int(round(float(seconds)))
    h, rest = divmod(total, 3600)
    m, s = divmod(rest, 60)
    return f"{h}:{m:02d}:{s:02d}" if h else f"{m}:{s:02d}"


NO_PROGRAM = "no machine program fits this machine: the time is the fiber length at the feed"


def _time(layer: dict[str, Any]) -> float | None:
    """The machine time of a layer, else (no program, or a summary without one) the time at the feed."""
    seconds = layer.get("winding_time_s")
    return layer.get("time_s") if seconds is None else seconds


def _angle(layer: dict[str, Any]) -> str:
    laid, asked = layer.get("angle_deg"), layer.get("requested_angle_deg")
    sign = "±" if layer.get("type") == "helical" else ""
    text = f"{sign}{_num(laid, 3)}"
    if asked is not None and laid is not None and abs(laid - asked) >= 5e-4:
        text += f" <span class=dim>(asked {_num(asked, 3)}, {laid - asked:+.3f})</span>"
    return text


def _passes(layer: dict[str, Any]) -> str:
    """The passes that lay fiber: a circuit is one forward and one return pass, a hoop traverse one
    (the summary's `passes` counts the CSV's pieces, turnarounds and dwells included)."""
    circuits = layer.get("circuits")
    if circuits is None:
        return _num(layer.get("passes"), 0)
    return _num(2 * circuits if layer.get("type") == "helical" else circuits, 0)


def _pair(values: Any, decimals: int, sep: str = " – ") -> str:
    if not values or any(v is None for v in values):
        return "–"
    return sep.join(_num(v, decimals) for v in values)


def _cov(layer: dict[str, Any], key: str) -> Any:
    return (layer.get("coverage") or {}).get(key)


def _covered(layer: dict[str, Any]) -> str:
    value = _cov(layer, "covered_fraction")
    if value is None:
        return "–"
    cls = "" if value >= COVERED_OK else " class=bad"
    return f"<span{cls}>{100.0 * value:.2f} %</span>"


# (header, unit, cell, key that must be present in some layer for the column to show)
Column = tuple[str, str, Callable[[dict[str, Any]], str], str]
COLUMNS: tuple[Column, ...] = (
    ("layer", "", lambda l: _num(l.get("index"), 0), "index"),
    ("type", "", lambda l: html.escape(str(l.get("type", "–"))), "type"),
    ("angle", "deg", _angle, "angle_deg"),
    ("circuits", "", lambda l: _num(l.get("circuits"), 0), "circuits"),
    ("pattern k", "", lambda l: _num(l.get("pattern"), 0) if l.get("type") == "helical" else "–", "pattern"),
    ("passes", "laid", _passes, "passes"),
    ("|α| range", "deg", lambda l: _pair(l.get("alpha_range_deg"), 2), "alpha_range_deg"),
    ("turnaround r", "mm", lambda l: _num(l.get("turnaround_radius_mm"), 2), "turnaround_radius_mm"),
    ("dwell start / end", "deg", lambda l: _pair([l.get("dwell_start_deg"), l.get("dwell_end_deg")], 1, " / "),
     "dwell_start_deg"),
    ("covered", "", _covered, "coverage"),
    ("widest gap", "mm", lambda l: _num(_cov(l, "max_gap_mm"), 3), "coverage"),
    ("widest overlap", "mm", lambda l: _num(_cov(l, "max_overlap_mm"), 3), "coverage"),
    ("band layers", "min – max", lambda l: _pair([_cov(l, "min_layers"), _cov(l, "max_layers")], 0), "coverage"),
    ("friction used", "|k_g / k_n|", lambda l: _num(l.get("max_slip"), 4), "max_slip"),
    ("tension", "N", lambda l: _pair(l.get("tension_range_n"), 1), "tension_n"),
    ("thickness", "mm", lambda l: _num(l.get("thickness_mm"), 3), "thickness_mm"),
    ("fiber mass", "kg", lambda l: _num(l.get("fiber_mass_kg"), 4), "fiber_mass_kg"),
    ("resin mass", "kg", lambda l: _num(l.get("resin_mass_kg"), 4), "resin_mass_kg"),
    ("fiber length", "m", lambda l: _num(_scaled(l.get("fiber_length_mm"), 1e-3), 2), "fiber_length_mm"),
    ("time", "h:mm:ss", lambda l: duration(_time(l)), "time_s"),
)


def _scaled(value: float | None, factor: float) -> float | None:
    return None if value is None else value * factor


def layer_table(summary: dict[str, Any]) -> str:
    """The per-layer table (HTML), with the notes of each layer below it."""
    layers = summary.get("layers") or []
    cols = [c for c in COLUMNS if any(c[3] in layer or (c[3] == "time_s" and "winding_time_s" in layer)
                                      for layer in layers)]
    head = "".join(f"<th>{html.escape(h)}" + (f"<br><span class=unit>{html.escape(u)}</span>" if u else "")
                   + "</th>" for h, u, _, _ in cols)
    rows = "".join("<tr>" + "".join(f"<td>{cell(layer)}</td>" for _, _, cell, _ in cols) + "</tr>"
                   for layer in layers)
    notes = "".join(f"<li><b>layer {_num(layer.get('index'), 0)}</b>: {html.escape(str(note))}</li>"
                    for layer in layers for note in layer.get("notes") or [])
    out = f"<table class=layers><thead><tr>{head}</tr></thead><tbody>{rows}</tbody></table>"
    return out + (f"<ul class=notes>{notes}</ul>" if notes else "")


# The unit and the decimals of each logical axis of axis_travel as the program writes them.
_AXIS_UNITS = {"carriage": "mm", "rotation": "deg", "cross_feed": "mm", "yaw": "deg", "x": "mm", "y": "mm",
               "z": "mm"}


def _travel_rows(travel: dict[str, list[float]] | None) -> list[tuple[str, str]]:
    """One row per axis of the program's travel: what a shop sets against its machine before winding
    (the eye runs well past the mandrel's ends at the turnarounds). A robot's eye position only: its
    direction components bound no axis."""
    return [(f"{axis.replace('_', '-')} travel", f"{_num(low, 3)} to {_num(high, 3)} {_AXIS_UNITS[axis]}")
            for axis, (low, high) in (travel or {}).items() if axis in _AXIS_UNITS]


def job_table(summary: dict[str, Any], extra: list[tuple[str, str]]) -> str:
    """The job's totals (HTML): layers, fiber length, time, mass / outer radius when present, and the
    travel of each machine axis over the program."""
    time_s = summary.get("winding_time_s")
    why = ""
    if time_s is None:  # the summary's null: no program could be built (its key is absent without a machine)
        if "winding_time_s" in summary:
            cause = summary.get("program_error")
            why = f" <span class=bad>{html.escape(NO_PROGRAM + (f' ({cause})' if cause else ''))}</span>"
        time_s = summary.get("estimated_time_s")
    rows = [("layers", _num(summary.get("layer_count"), 0)),
            ("fiber length", f"{_num(_scaled(summary.get('total_fiber_length_mm'), 1e-3), 3)} m"),
            ("winding time", f"{duration(time_s)} <span class=dim>({_num(time_s, 1)} s)</span>{why}")]
    if summary.get("mass_kg") is not None:
        rows.append(("laminate mass", f"{_num(summary['mass_kg'], 4)} kg"))
    if summary.get("outer_radius_mm") is not None:
        rows.append(("outer radius", f"{_num(summary['outer_radius_mm'], 3)} mm"))
    rows += _travel_rows(summary.get("axis_travel"))
    rows += extra
    body = "".join(f"<tr><th>{html.escape(k)}</th><td>{v}</td></tr>" for k, v in rows)
    return f"<table class=job>{body}</table>"
