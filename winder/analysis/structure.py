"""A planned job's structural answer (docs/guide/will-it-hold.md): netting
burst, first-ply failure by Tsai-Wu and by maximum stress, where, per layer and in total, from the gauge
section with the end zones apart; the summary's `analysis` block (winder.analysis.verdict).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from winder.analysis.gauge import default_gauge, gauge_span, in_span
from winder.analysis.job import check_analysis, load_case, netting_allowable
from winder.analysis.layup import layer_rows
from winder.analysis.loads import resultants
from winder.analysis.materials import Lamina, NettingAllowable, allowable_notes
from winder.analysis.netting import optimum_angle
from winder.analysis.stations import StationAnalysis, analyze_stations, surface_geometry

NOT_REVOLUTION = ("the laminate analysis needs a surface of revolution (a straight axis and circular "
                  "sections); see the shell model of --format abaqus")


@dataclasses.dataclass(frozen=True, kw_only=True)
class Structure:
    """The analysis of a plan: success False (with message) where it does not apply; stations the
    per-station results (None then); gauge its name and (t0, t1), in_gauge (n,) the stations inside it;
    plies and allowables per layer of the stations (their order); notes what the allowables rest on."""

    success: bool
    message: str
    stations: StationAnalysis | None = None
    pressure: float = 0.0
    optimum_angle_deg: float = math.nan
    boss_radius: float = 0.0
    gauge: str = "all"
    gauge_span: tuple[float, float] = (-math.inf, math.inf)
    in_gauge: np.ndarray | None = None
    plies: tuple[Lamina, ...] = ()
    allowables: tuple[NettingAllowable, ...] = ()
    notes: tuple[str, ...] = ()


def analyze(plan, job) -> Structure:
    """The structure of a planned job with an `analysis:` section (ConfigError without ply data)."""
    plies = check_analysis(job)
    if not plan.surface.is_revolution:
        return Structure(success=False, message=NOT_REVOLUTION)
    rows = layer_rows(plan)
    if not rows:
        return Structure(success=False, message="no layer lays a laminate")
    index = [r.index - 1 for r in rows]
    laminae = tuple(plies[i] for i in index)
    allowables = tuple(netting_allowable(job, i, p) for i, p in zip(index, laminae))
    notes = []
    for ply, allowable in zip(laminae, allowables):
        notes += [n for n in allowable_notes(ply, allowable) if n not in notes]
    turns = [layer.turnaround_radius for layer in plan.layers if layer.turnaround_radius is not None]
    boss = max(turns) + plan.band_width if turns else 0.0
    case = load_case(job)
    stations = analyze_stations(plan.surface, rows, laminae, allowables, case, boss)
    # the optimum angle where the wall is the part's own: the widest station (a vessel's cylinder)
    widest = surface_geometry(plan.surface, stations.geometry.t[[int(np.argmax(stations.geometry.r))]])
    per_p, held = resultants(widest, case)
    n = case.pressure * per_p[0] + held[0] if case.pressure > 0.0 else per_p[0]
    name = job.analysis.gauge or default_gauge(plan)
    span = gauge_span(plan, name, job.winding.region, boss)
    inside = in_span(stations.geometry.t, span)
    if not np.any(inside & (stations.thickness.sum(axis=1) > 0.0)):  # a gauge with no station: say so, use all
        notes.append(f"the {name} gauge holds no station of the layup: the headline figures are over every station")
        inside = np.ones_like(inside)
    return Structure(success=True, message="", stations=stations, pressure=case.pressure,
                     optimum_angle_deg=math.degrees(optimum_angle(n[0], n[1])), boss_radius=boss, gauge=name,
                     gauge_span=span, in_gauge=inside, plies=laminae, allowables=allowables, notes=tuple(notes))


def summary_block(structure: Structure, job) -> dict:
    """The summary's `analysis` object (winder.analysis.verdict.summary_block)."""
    from winder.analysis.verdict import summary_block as block  # noqa: PLC0415

    return block(structure, job)

