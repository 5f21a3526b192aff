"""The feasible patterns of a helical layer, side by side (docs/math/11-pattern-choices.md).

A choice is a circuit count N and a skip k coprime with it; the planner closes it as it closes its own
(open mandrels: the dwells lengthened, at the angle asked; vessels: the turnaround radius, hence the
angle, moved). Every figure comes from the planner's own code: each circuit count is planned (passes,
coverage, slip) and, on an open surface of revolution or straight tube of one section, where a skip
changes only the dwells and moves the return bands as a whole, each skip's dwells come from close_open_pattern, its bands' union from
layer_coverage on the planned passes turned, its fiber from the dwell's length per turn measured on two
plans. Elsewhere each choice is planned in full. Cost: one plan per circuit count plus one coverage
evaluation per choice (there); one plan per choice elsewhere (at most
MAX_PLANNED of them, nearest the angle first).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import replace

import numpy as np

from winder.config.job import JobConfig
from winder.config.winding import SLIP_AUTO, LayerConfig, LayerType
from winder.errors import ConfigError, SolverError
from winder.geometry.vessel import VesselMeridian
from winder.winding.coverage import layer_coverage
from winder.winding.layers.helical_open import COVERED_TARGET, open_closure
from winder.winding.passes import PlanContext
from winder.winding.pattern import close_open_pattern, coprime_skips
from winder.winding.plan import layer_contexts, plan_layer
from winder.winding.results import LayerPlan, PassKind

EXTRA_CIRCUITS = 2  # circuit counts listed: the planner's and this many more (more overlap, finer patterns)
MAX_CROSSOVERS = 10  # skips listed: those whose pattern repeats within this many circuits, and the planner's
MAX_PLANNED = 8  # choices planned in full where a skip changes the passes themselves (bends, other sections)
MAX_PLANNED_VESSEL = 4  # on a vessel each costs its turnaround's root solve and passes (~1 s on a sample)
DEFAULT_WITHIN = 2.0  # deg: vessel choices whose closed angle lies this near the angle asked
ANGLE_DECIMALS = 2  # the sort compares angles to 0.01 deg


@dataclasses.dataclass(frozen=True)
class PatternChoice:
    """One feasible pattern of a layer; `chosen` marks the planner's own (the config as written).

    dwell_added_deg: the mandrel turn added to the least dwells to close it (open mandrels; 0 on vessels).
    crossovers: p, the circuits laid before a band lands beside the first (p k = +-1 mod N): the pattern
        shows p diamonds around the part (fiberpath's patternNumber); lead: `leading` (+1) or `lagging`.
    evaluated: `planned` (this choice's own plan) or `turned` (its circuit count's plan, the return
        bands turned by the dwell change, the dwell's fiber added).
    """

    layer: int
    circuits: int
    pattern: int
    angle_deg: float
    requested_angle_deg: float
    dwell_start_deg: float
    dwell_end_deg: float
    dwell_added_deg: float
    turnaround_radius_mm: float | None
    crossovers: int
    lead: str
    covered_fraction: float
    max_gap_mm: float
    max_overlap_mm: float
    min_layers: int
    max_layers: int
    fiber_length_mm: float
    time_s: float
    max_slip: float
    chosen: bool
    evaluated: str


@dataclasses.dataclass(frozen=True)
class PatternTable:
    """The choices of one layer, sorted by SORT_RULE; plans: how many layer plans were computed."""

    layer: int
    requested_angle_deg: float
    choices: tuple[PatternChoice, ...]
    plans: int
    method: str


SORT_RULE = ("complete coverage first, then the angle laid nearest the angle asked (to 0.01 deg), the fewest "
             "circuits, the least dwell added, the fewest crossovers, the shortest time")


def crossovers(circuits: int, pattern: int) -> tuple[int, str]:
    """(p, lead): the least p >= 1 with p k = +1 (leading) or -1 (lagging) mod N."""
    if circuits <= 2:
        return 1, "leading"
    for p in range(1, circuits + 1):
        r = (p * pattern) % circuits
        if r in (1, circuits - 1):
            return p, "leading" if r == 1 else "lagging"
    return circuits, "leading"  # unreachable for k coprime with N


def _skips(circuits: int, own: int | None) -> list[int]:
    return [k for k in coprime_skips(circuits) if crossovers(circuits, k)[0] <= MAX_CROSSOVERS or k == own]


def _choice(index: int, asked: float, plan: LayerPlan, chosen: bool, evaluated: str, added: float, **over) -> PatternChoice:
    cov = plan.coverage
    p, lead = crossovers(plan.circuits, plan.pattern)
    fields = dict(layer=index + 1, circuits=plan.circuits, pattern=plan.pattern, angle_deg=plan.angle_deg,
                  requested_angle_deg=asked, dwell_start_deg=plan.dwell_start_deg, dwell_end_deg=plan.dwell_end_deg,
                  dwell_added_deg=added, turnaround_radius_mm=plan.turnaround_radius, crossovers=p, lead=lead,
                  covered_fraction=cov.covered_fraction, max_gap_mm=cov.max_gap_mm, max_overlap_mm=cov.max_overlap_mm,
                  min_layers=cov.min_layers, max_layers=cov.max_layers, fiber_length_mm=plan.fiber_length_mm,
                  time_s=plan.time_s, max_slip=plan.max_slip, chosen=chosen, evaluated=evaluated)
    fields.update(over)
    if over:
        p, lead = crossovers(fields["circuits"], fields["pattern"])
        fields.update(crossovers=p, lead=lead)
    return PatternChoice(**fields)


def _geodesic_kind(ctx: PlanContext, cfg: LayerConfig) -> str:
    """`open` (helical_open's planner, a surface of revolution), `vessel` (helical_vessel's), or `other`."""
    surf, slip = ctx.surface, cfg.slip
    if isinstance(surf.profile, VesselMeridian):
        prof = surf.profile
        c_min = max(prof.dome.end_radius, prof.end_dome.end_radius) + 0.5 * ctx.winding.band_width
        outside = prof.radius * math.sin(math.radians(cfg.angle_deg)) > c_min
        geodesic = cfg.turnaround_radius is None and (slip == 0.0 or (slip == SLIP_AUTO and outside))
        return "vessel" if geodesic else "other"
    if slip == 0.0 or (slip == SLIP_AUTO and surf.curve.is_straight):
        # a surface of revolution, or a straight tube of one section (no profile): unrolled, its passes
        # are the same lines moved along the section (docs/math/11-pattern-choices.md 11.2)
        cylinder = surf.curve.is_straight and surf.profile is None
        return "open" if surf.is_revolution or cylinder else "other"
    return "other"


def pattern_choices(job: JobConfig, index: int, angle: float | None = None, within: float = DEFAULT_WITHIN,
                    context: tuple[PlanContext, float] | None = None, planned: LayerPlan | None = None) -> PatternTable:
    """The feasible patterns of helical layer `index` (0-based), at `angle` (deg; None: the layer's);
    context: the layer's context and start angle, planned: its plan as configured (both from
    winding.plan.layer_contexts), when the caller has them."""
    cfg = job.winding.layers[index]
    if cfg.type is not LayerType.HELICAL:
        raise ConfigError(f"{job.source}: {cfg.label(index)}: a hoop layer has no pattern to choose "
                          f"(winder patterns lists helical layers)")
    if angle is not None:
        cfg = replace(cfg, angle_deg=float(angle))
    if context is None:
        contexts, done = layer_contexts(job, index + 1)
        context, planned = contexts[index], done.layers[index]
    ctx, theta0 = context
    own = planned if planned is not None and angle is None else plan_layer(ctx, cfg, index, theta0)
    kind = _geodesic_kind(ctx, cfg)
    # The planner's count and more; a count the config gives is listed beside them
    auto = own if cfg.circuits is None else plan_layer(ctx, replace(cfg, circuits=None, pattern=None), index, theta0)
    counts = sorted({own.circuits, *range(auto.circuits, auto.circuits + EXTRA_CIRCUITS + 1)})
    free = replace(cfg, pattern=None)
    if kind == "open":
        choices, plans = _open_choices(ctx, free, index, theta0, own, counts)
        method = "one plan per circuit count; each skip's return bands moved by its dwells"
    elif kind == "vessel":
        choices, plans = _vessel_choices(ctx, free, index, theta0, own, counts, within)
        method = f"each choice planned (vessel: the angle moves with the skip; the {MAX_PLANNED_VESSEL} nearest)"
    else:
        choices, plans = _planned_choices(ctx, free, index, theta0, own, counts)
        method = f"each choice planned (the passes change with the skip; the {MAX_PLANNED} fewest crossovers)"
    asked = float(cfg.angle_deg)
    choices.sort(key=lambda c: (c.covered_fraction < COVERED_TARGET, round(abs(c.angle_deg - asked), ANGLE_DECIMALS),
                                c.circuits, round(c.dwell_added_deg, 6), c.crossovers, c.time_s))
    return PatternTable(index + 1, asked, tuple(choices), plans + 1, method)


def _open_choices(ctx: PlanContext, cfg: LayerConfig, index: int, theta0: float, own: LayerPlan,
                  counts) -> tuple[list[PatternChoice], int]:
    closure = open_closure(ctx, cfg, index)
    key = ctx.key(index, "pattern")
    least = 360.0 * (closure.least[0] + closure.least[1])
    asked = float(cfg.angle_deg)
    stations = own.coverage.stations
    choices: list[PatternChoice] = []
    per_turn = None  # fiber (mm) per turn of dwell per circuit, from two plans of one circuit count
    plans = 0
    for n in counts:
        skips = _skips(n, own.pattern if n == own.circuits else None)
        base = own if n == own.circuits else plan_layer(ctx, replace(cfg, circuits=n), index, theta0)
        plans += base is not own
        dwell_b = base.dwell_start_deg + base.dwell_end_deg
        if per_turn is None and len(skips) > 1:
            far = max(skips, key=lambda k: close_open_pattern(n, closure.natural, *closure.least, k, key).advance)
            other = plan_layer(ctx, replace(cfg, circuits=n, pattern=far), index, theta0)
            plans += 1
            turns = (other.dwell_start_deg + other.dwell_end_deg - dwell_b) / 360.0
            per_turn = (other.fiber_length_mm - base.fiber_length_mm) / (n * turns) if turns > 1e-9 else 0.0
        fwd = [p for p in base.passes if p.kind is PassKind.FORWARD]
        ret = [p for p in base.passes if p.kind is PassKind.RETURN]
        for k in skips:
            pat = close_open_pattern(n, closure.natural, *closure.least, k, key)
            dwell = 360.0 * (pat.dwell_start + pat.dwell_end)
            chosen = n == own.circuits and k == own.pattern
            if k == base.pattern:
                choices.append(_choice(index, asked, base, chosen, "planned", dwell - least))
                continue
            shift = pat.dwell_end - base.dwell_end_deg / 360.0  # of the perimeter, along the section
            turned = [replace(p, theta=ctx.arcs.theta(ctx.arcs.fraction(p.theta) + shift)) for p in ret]
            cov = layer_coverage(ctx.surface, ctx.arcs, fwd + turned, ctx.winding.band_width, stations)
            length = base.fiber_length_mm + n * (per_turn or 0.0) * (dwell - dwell_b) / 360.0
            choices.append(_choice(index, asked, base, chosen, "turned", dwell - least, pattern=k,
                                   dwell_start_deg=360.0 * pat.dwell_start, dwell_end_deg=360.0 * pat.dwell_end,
                                   covered_fraction=cov.covered_fraction, max_gap_mm=cov.max_gap_mm,
                                   max_overlap_mm=cov.max_overlap_mm, min_layers=cov.min_layers,
                                   max_layers=cov.max_layers, fiber_length_mm=length,
                                   time_s=length / ctx.feed * 60.0))
    return choices, plans


def _vessel_choices(ctx: PlanContext, cfg: LayerConfig, index: int, theta0: float, own: LayerPlan, counts,
                    within: float) -> tuple[list[PatternChoice], int]:
    from winder.winding.layers.helical_vessel import vessel_closure  # noqa: PLC0415 - vessels only

    advance, c0, c_min, c_hi = vessel_closure(ctx, cfg, index)
    big_r = ctx.surface.profile.radius
    asked = float(cfg.angle_deg)
    # The advance grows with c: the window's targets k / N + m lie between its values at the window's
    # ends, and each skip closes at the target nearest a0 (close_vessel_pattern), so only those
    # within the window are planned (an advance costs a profile integral: three of them at once here).
    a0, lo, hi = (float(v) for v in advance(np.array([
        c0, max(c_min, big_r * math.sin(math.radians(max(asked - within, 0.0)))),
        min(c_hi, big_r * math.sin(math.radians(min(asked + within, 89.0))))])))
    near = []
    for n in counts:
        for k in _skips(n, None):
            up = a0 + (k / n - a0) % 1.0
            target = min((up, up - 1.0), key=lambda t: abs(t - a0))
            if lo <= target <= hi and not (n == own.circuits and k == own.pattern):
                near.append((abs(target - a0), n, k))
    choices = [_choice(index, asked, own, True, "planned", 0.0)]
    for _, n, k in sorted(near)[:MAX_PLANNED_VESSEL]:
        try:
            plan = plan_layer(ctx, replace(cfg, circuits=n, pattern=k), index, theta0)
        except SolverError:  # its turnaround cannot be wound (inside the opening on a grown mandrel): not feasible
            continue
        choices.append(_choice(index, asked, plan, False, "planned", 0.0))
    return choices, len(choices) - 1


def _planned_choices(ctx: PlanContext, cfg: LayerConfig, index: int, theta0: float, own: LayerPlan,
                     counts) -> tuple[list[PatternChoice], int]:
    asked = float(cfg.angle_deg)
    wanted = sorted((crossovers(n, k)[0], n, k) for n in counts for k in _skips(n, None)
                    if not (n == own.circuits and k == own.pattern))
    choices = [_choice(index, asked, own, True, "planned", 0.0)]
    for _, n, k in wanted[:MAX_PLANNED]:
        try:
            plan = plan_layer(ctx, replace(cfg, circuits=n, pattern=k), index, theta0)
        except SolverError:  # this one cannot be wound (a slip past the friction): not feasible
            continue
        choices.append(_choice(index, asked, plan, False, "planned", 0.0))
    low = min(c.dwell_start_deg + c.dwell_end_deg for c in choices)
    return [replace(c, dwell_added_deg=c.dwell_start_deg + c.dwell_end_deg - low) for c in choices], len(choices) - 1


def all_helical(job: JobConfig) -> list[int]:
    """The 0-based indices of the job's helical layers."""
    return [i for i, layer in enumerate(job.winding.layers) if layer.type is LayerType.HELICAL]


__all__ = ["PatternChoice", "PatternTable", "SORT_RULE", "all_helical", "crossovers", "pattern_choices"]
