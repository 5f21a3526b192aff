"""Where the headline figures come from (docs/guide/will-it-hold.md, `analysis.gauge`;
docs/math/09-structure.md 9.6): the gauge section of the part, its end zones apart.

- `cylinder`: a vessel's cylinder where the laminate is the one of mid-cylinder (every layer laid there at
  its thickness there, within SPREAD), a band width in from where that changes; on an open mandrel the
  same as `wound`.
- `wound`: a vessel's wall outside the bosses' turnaround zones (r >= the largest turnaround radius plus
  a band width); an open mandrel's trimmed part: where every layer laid at the reference section is laid at
  its thickness there (within SPREAD), a band width in from each end of it (the turnarounds, the pins, the
  layers' edges, tapers and step-backs lie outside).
- `all`: every station.
"""

from __future__ import annotations

import math

import numpy as np

from winder.geometry.vessel import VesselMeridian
from winder.winding.wall import reference_station

EVERYWHERE = (-math.inf, math.inf)
# A layer's wall belongs to the gauge while its thickness stays within this share of its value at the
# reference station: a hoop taper's step-back, a helical's pile-up toward its turnaround fall outside.
SPREAD = 0.25


def is_vessel(surface) -> bool:
    return isinstance(surface.profile, VesselMeridian)


def default_gauge(plan) -> str:
    return "cylinder" if is_vessel(plan.surface) else "wound"


def _run_around(t: np.ndarray, thickness: np.ndarray, at: float) -> tuple[float, float] | None:
    """The contiguous run of cells around station `at` whose thickness is within SPREAD of the thickness
    there (None: not laid there)."""
    if t.size == 0:
        return None
    k = int(np.clip(np.searchsorted(t, at), 0, t.size - 1))
    if not thickness[k] > 0.0:
        return None
    laid = np.abs(thickness - thickness[k]) <= SPREAD * thickness[k]
    gaps = np.nonzero(~laid)[0]
    lo = gaps[gaps < k].max() + 1 if np.any(gaps < k) else 0
    hi = gaps[gaps > k].min() - 1 if np.any(gaps > k) else t.size - 1
    return float(t[lo]), float(t[hi])


def full_laminate(plan, at: float) -> tuple[float, float] | None:
    """The span around station `at` where every layer laid at `at` is laid (contiguously) at its thickness
    there (within SPREAD), a band width in from each end where the span is longer than four band widths;
    None where no layer is laid at `at`."""
    lo, hi = -math.inf, math.inf
    found = False
    for layer in plan.layers:
        lam = layer.laminate
        if lam is None:
            continue
        run = _run_around(lam.t, lam.thickness, at)
        if run is None:
            continue
        found = True
        lo, hi = max(lo, run[0]), min(hi, run[1])
    if not found or not hi > lo:
        return None
    band = plan.band_width
    return (lo + band, hi - band) if hi - lo > 4.0 * band else (lo, hi)


def gauge_span(plan, name: str, region: tuple[float, float] | None = None,
               boss_radius: float = 0.0) -> tuple[float, float]:
    """(t0, t1) of the gauge `name` (cylinder | wound | all) of a planned job; region: the winding
    region of an open mandrel (None: all of it); boss_radius: a vessel's turnaround zones' edge."""
    if name == "all":
        return EVERYWHERE
    surface = plan.surface
    vessel = is_vessel(surface)
    region = region or (0.0, surface.axial_length)
    ref = reference_station(surface, region, plan.band_width)
    if vessel and name == "wound":
        t = np.linspace(0.0, surface.axial_length, 4001)
        r = surface.perimeter(surface.s_of_t(t)) / (2.0 * np.pi)
        inside = np.nonzero(r >= boss_radius)[0]
        return (float(t[inside[0]]), float(t[inside[-1]])) if inside.size else EVERYWHERE
    span = full_laminate(plan, ref)
    if span is None:
        return EVERYWHERE
    if vessel:  # the cylinder's own stretch
        a, b = surface.profile.equator_t
        span = (max(span[0], a), min(span[1], b))
    return span


def in_span(t: np.ndarray, span: tuple[float, float]) -> np.ndarray:
    return (t >= span[0] - 1e-9) & (t <= span[1] + 1e-9)
