"""Fiber tension in a job file (docs/guide/tension.md): N per band.

    winding:
      tension: 40                                   # every layer, every pass
      tension: {schedule: uniform_prestress, residual: 30, max: 120}   # thick walls (docs/math/16)
      layers:
        - {type: hoop, passes: 2, tension: 60}      # a layer's own
        - {type: helical, angle: 30, tension: {start: 60, end: 45}}   # linear over its passes

A layer's own tension replaces the job's. The uniform-prestress schedule computes each layer's
winding tension so that, once the whole wall is wound, every layer keeps `residual` (the tension
the layers above would otherwise take from it: winder.analysis.prestress); `max` is the most the
tensioner (or the fiber) takes, a layer that would need more is refused; `radial_modulus` (MPa) the
wet wall's through-thickness stiffness (default: the ply's E2), `mandrel_modulus` (MPa) the mandrel's
(default: rigid).
"""

from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from winder.config.reader import Reader

# A band's tension past this is a typo (kN typed as N): a 24k carbon tow breaks near 4 kN, a band of
# ten of them is wound below 1 kN.
MAX_TENSION = 20_000.0
MAX_MODULUS = 1.0e6  # MPa, as winder.config.analysis: past this a modulus was typed in Pa or psi
UNIFORM_PRESTRESS = "uniform_prestress"


@dataclasses.dataclass(frozen=True)
class TensionConfig:
    """A tension (N per band): `start` at a layer's first pass, `end` at its last (equal: constant).
    schedule : UNIFORM_PRESTRESS (the job's, computed per layer: residual, limit, moduli), else None."""

    start: float
    end: float
    schedule: str | None = None
    limit: float | None = None  # the schedule's `max`
    radial_modulus: float | None = None
    mandrel_modulus: float | None = None

    def at(self, fractions):
        """The tension at pass positions `fractions` (0 first pass, 1 last): linear from start to end."""
        return [self.start + (self.end - self.start) * f for f in fractions]


def _newtons(rd: Reader, value: Any, path: str) -> float:
    n = rd.number(value, path)
    if not 0.0 < n <= MAX_TENSION:
        raise rd.error(path, f"must be in (0, {MAX_TENSION:g}] N per band (the fiber tension the tensioner holds)",
                       value)
    return n


def parse_tension(rd: Reader, value: Any, path: str, job: bool) -> TensionConfig:
    """`tension:` of the winding (job: the schedule allowed) or of a layer: a number, {start, end},
    or (job) {schedule: uniform_prestress, residual, max, radial_modulus, mandrel_modulus}."""
    if not isinstance(value, dict):
        n = _newtons(rd, value, path)
        return TensionConfig(n, n)
    if "schedule" in value:
        if not job:
            raise rd.error(rd.at(path, "schedule"), "applies to winding.tension (the whole wall's schedule); a "
                           "layer gives a number or {start, end}", value["schedule"])
        m = rd.mapping(value, path, ("schedule", "residual", "max", "radial_modulus", "mandrel_modulus"),
                       required=("residual",))
        if m["schedule"] != UNIFORM_PRESTRESS:
            raise rd.error(rd.at(path, "schedule"), f"must be {UNIFORM_PRESTRESS} (docs/math/16-winding-tension.md)",
                           m["schedule"])
        residual = _newtons(rd, m["residual"], rd.at(path, "residual"))
        limit = _newtons(rd, m["max"], rd.at(path, "max")) if "max" in m else None
        if limit is not None and limit < residual:
            raise rd.error(rd.at(path, "max"), f"must be at least the residual ({residual:g} N)", m["max"])
        moduli = {}
        for key in ("radial_modulus", "mandrel_modulus"):
            if key in m:
                moduli[key] = rd.positive(m[key], rd.at(path, key))
                if moduli[key] > MAX_MODULUS:
                    raise rd.error(rd.at(path, key), f"must be <= {MAX_MODULUS:g} MPa", m[key])
        return TensionConfig(residual, residual, UNIFORM_PRESTRESS, limit, **moduli)
    m = rd.mapping(value, path, ("start", "end"), required=("start", "end"))
    return TensionConfig(_newtons(rd, m["start"], rd.at(path, "start")), _newtons(rd, m["end"], rd.at(path, "end")))


def check_tensions(rd: Reader, layers: tuple, job: TensionConfig | None) -> None:
    """Every layer is wound at a programmed tension, or none is: a controller keeps the last one set,
    so a layer without its own after one with would be wound at the other's."""
    own = [layer.tension is not None for layer in layers]
    if job is None and any(own) and not all(own):
        i = own.index(False)
        raise rd.error(layers[i].label(i), "has no tension while others have one: give "
                       "winding.tension (the default of every layer) or this layer's own")
