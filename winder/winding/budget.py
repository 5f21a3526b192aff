"""The work a job will do, decided from the config and the built surface before any path is solved.

The planner's sizes follow from a few numbers: the circuits of a helical layer N_c = ceil(P cos(alpha)
/ B) (docs/math/05-winding.md, P the perimeter, so the surface is needed), the turns of a hoop layer (region length
over pitch, HOOP_STEP_DEG per point), the dwells (DWELL_STEP_DEG per point) and the points per pass.
From them: circuits, passes, points per pass, points in total and a memory estimate
(winder.winding.memory_model: docs/math/14-work-estimates.md 14.2), each held against a limit. A job
past a limit is refused (ConfigError, exit 2) naming the key that drives it and the limit, instead of
running for minutes and dying of memory. `check` and `run` both call `check_budget`, so what `check`
accepts, `run` will not refuse for its size.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from winder.config.job import JobConfig
from winder.config.winding import DEFAULT_POINTS, SLIP_AUTO, LayerConfig, LayerType, WindingConfig
from winder.errors import ConfigError, SolverError
from winder.geometry.sections import arc_map
from winder.geometry.surface import SweepSurface
from winder.geometry.vessel import VesselMeridian
from winder.winding.layers.helical_open import MAX_CIRCUIT_FACTOR
from winder.winding.layers.helical_vessel import PIECE_MIN_POINTS, turnaround_refusal
from winder.winding.layers.hoop import HOOP_STEP_DEG
from winder.winding.layer_batches import robot_poses, whole_plan
from winder.winding.memory_model import PROGRAM_CHUNK_POINTS, peak_bytes, solve_bytes_per_point
from winder.winding.passes import DWELL_STEP_DEG, REFINE_MAX_POINTS, TANGENT_REFINE, PlanContext, pass_points
from winder.winding.pattern import circuits_for_coverage, coprime_skips
from winder.winding.turnaround import turnaround_points

__all__ = ["Budget", "LayerBudget", "MAX_CIRCUITS", "MAX_LAYERS", "MAX_MEMORY_BYTES", "MAX_PASSES", "MAX_PASS_POINTS", "MAX_PASS_TURNS",
           "MAX_TOTAL_POINTS", "PROGRAM_CHUNK_POINTS", "check_budget", "job_budget"]

MAX_CIRCUITS = 20_000  # per helical layer: a 1 m vessel at 10 deg with 1 mm bands needs 3,100
MAX_PASSES = 10_000  # per hoop layer
# Turns of one helical pass (length x tan(alpha) / perimeter): the solvers' work grows with them (24
# points per turn on the coarsest level, ODE traces of the natural advance); a 12 m pipe of radius
# 50 at 80 deg makes 215.
MAX_PASS_TURNS = 500
MAX_PASS_POINTS = 1_000_000  # points of one pass as planned (a hoop of 13,900 turns)
MAX_TOTAL_POINTS = 1_500_000  # points of the whole job; about a minute and 0.9 GB to plan and write
MAX_LAYERS = 1_000  # layers of one job: real tanks have 10 to 40
# Of the estimate (winder.winding.memory_model): room for numpy, scipy and their libraries in 2 GB.
MAX_MEMORY_BYTES = 1_200_000_000
REGION_STATIONS = 41  # stations sampled for the largest perimeter, as the planner does
START_SAMPLES = 257  # start fractions of a turn sampled for a pass's widest angle span
BENT_ROUNDS_SHARE = 0.8  # of a bent tube's estimated rounds, what `check` holds the points to


@dataclasses.dataclass(frozen=True)
class LayerBudget:
    """The work of one layer: circuits (1 for a hoop), laid passes, points of its longest pass,
    points in total (dwells included) and points of the largest single solve."""

    circuits: int
    passes: int
    pass_points: int
    points: int
    solve_points: int


@dataclasses.dataclass(frozen=True)
class Budget:
    """The work of a job: per layer, and in total (points, estimated peak memory in bytes)."""

    layers: tuple[LayerBudget, ...]
    points: int
    memory_bytes: int


def _region(surface: SweepSurface, winding: WindingConfig) -> tuple[float, float]:
    if winding.region is not None:
        return winding.region
    return 0.0, surface.axial_length


def _largest_perimeter(surface: SweepSurface, t_a: float, t_b: float) -> float:
    ts = np.linspace(t_a, t_b, REGION_STATIONS)
    return float(np.max(surface.perimeter(surface.s_of_t(ts))))


def _refuse(source: str, key: str, what: str) -> ConfigError:
    return ConfigError(what, file=source, key_path=key)


def _helical(job: JobConfig, surface: SweepSurface, cfg: LayerConfig, key: str, bare: bool) -> LayerBudget:
    """bare : the layer winds on the mandrel itself (not on a laminate grown by earlier layers)."""
    w = job.winding
    vessel = isinstance(surface.profile, VesselMeridian)
    if vessel:
        perimeter = 2.0 * math.pi * surface.profile.radius
        t_a, t_b = surface.profile.equator_t
    else:
        t_a, t_b = _region(surface, w)
        perimeter = _largest_perimeter(surface, t_a, t_b)
    turns = (t_b - t_a) * math.tan(math.radians(cfg.angle_deg)) / perimeter
    if turns > MAX_PASS_TURNS:
        raise _refuse(job.source, f"{key}.angle",
                      f"a pass at {cfg.angle_deg:g} deg would make {turns:.4g} turns over {t_b - t_a:g} mm of "
                      f"perimeter {perimeter:.6g} mm, more than the limit of {MAX_PASS_TURNS} (a shorter region "
                      f"or a lower angle), got {cfg.angle_deg:g}")
    need = perimeter * math.cos(math.radians(cfg.angle_deg)) / w.band_width
    if need > MAX_CIRCUITS:
        raise _refuse(job.source, "winding.band_width",
                      f"{key} needs {need:.4g} circuits (perimeter {perimeter:.6g} mm x cos "
                      f"{cfg.angle_deg:g} deg / band width), more than the limit of {MAX_CIRCUITS} (a wider "
                      f"band needs fewer), got {w.band_width:g}")
    circuits = cfg.circuits or circuits_for_coverage(perimeter, math.radians(cfg.angle_deg), w.band_width)
    if cfg.pattern is not None and circuits > 1 and math.gcd(cfg.pattern, circuits) != 1:
        skips = coprime_skips(circuits)
        raise _refuse(job.source, f"{key}.pattern",
                      f"shares a factor with the {circuits} circuits this layer needs, so some slots would "
                      f"be wound twice and others never; allowed: {', '.join(map(str, skips[:12]))}"
                      f"{' ...' if len(skips) > 12 else ''} or auto, got {cfg.pattern}")
    slip = getattr(cfg, "slip", 0.0)
    # Where a vessel's geodesic turnaround R sin(alpha) misses the opening: closed form on the bare mandrel
    why = turnaround_refusal(surface.profile, cfg.angle_deg, w.band_width) if vessel else None
    if vessel and bare and slip == 0.0 and cfg.turnaround_radius is None and why is not None:
        raise _refuse(job.source, f"{key}.angle", f"{why} (or slip: auto, a friction-held turnaround just "
                      f"outside it), got {cfg.angle_deg:g}")  # on a grown mandrel: run refuses it
    if vessel and bare and cfg.turnaround_radius is not None:
        _check_turnaround_radius(job, surface.profile, cfg.turnaround_radius, key)
    # The geodesic planner's layers (winding.layers.friction: slip auto is geodesic where that covers)
    geodesic = slip in (0.0, SLIP_AUTO) if not vessel else cfg.turnaround_radius is None and (
        slip == 0.0 or (slip == SLIP_AUTO and why is None))
    if not vessel and bare and slip == SLIP_AUTO and _held_by_friction(job, surface, cfg, key, (t_a, t_b)):
        geodesic = False
    if bare and geodesic:
        _check_pass_points(job, surface, cfg, key, vessel, (t_a, t_b))
    if not vessel and slip not in (0.0, SLIP_AUTO):
        from winder.winding.layers.friction_open import is_bent_tube  # noqa: PLC0415 - friction jobs only
        from winder.winding.layers.slip_revolution import tapers  # noqa: PLC0415
        ctx = PlanContext(job, w, surface, arc_map(surface.section), job.machine.feed)
        # as winder.winding.layers.friction refuses it, before any path
        if not is_bent_tube(ctx) and not (surface.curve.is_straight and tapers(surface, t_a, t_b)):
            raise _refuse(job.source, f"{key}.slip", f"a number applies to vessels, bent tubes of lines and arcs, "
                          f"and tapered surfaces of revolution (cones, poles); geodesics cover this mandrel "
                          f"evenly: use 0 or auto, got {slip:g}")
    grows = not vessel and not surface.is_revolution and cfg.pattern is None and cfg.circuits is None
    most = circuits * (MAX_CIRCUIT_FACTOR if grows else 1)
    n = w.points or DEFAULT_POINTS
    pass_points = n + 2
    dwell_points = 0
    if not vessel:  # each end: the configured dwell plus less than a turn to close the pattern
        dwell_points = sum(int(math.ceil((d + 360.0) / DWELL_STEP_DEG)) + 1
                           for d in (w.dwell_start_deg, w.dwell_end_deg))
        if dwell_points > MAX_PASS_POINTS:
            raise _refuse(job.source, "winding.dwell",
                          f"dwells of {w.dwell_start_deg:g} and {w.dwell_end_deg:g} deg need {dwell_points} "
                          f"points per circuit, more than the limit of {MAX_PASS_POINTS}")  # both ends: no one value
        # and the turnarounds past the region (winder.winding.turnaround)
        dwell_points += turnaround_points(surface, tuple(float(v) for v in surface.s_of_t(np.array([t_a, t_b]))))
    # A pass is refined up to REFINE_MAX_POINTS with a tolerance, else at most twice (2n + 1, where
    # it does not converge: winder.winding.passes.fine_geodesic); its tangents come from a solve on
    # TANGENT_REFINE times finer segments, with its Richardson twin.
    refined = max(REFINE_MAX_POINTS, n) if w.tolerance is not None else min(4 * n + 3, max(REFINE_MAX_POINTS, n))
    solve = 2 * (TANGENT_REFINE * (refined + 1))
    return LayerBudget(most, 2 * most, pass_points, most * (2 * pass_points + dwell_points), solve)


def _held_by_friction(job: JobConfig, surface: SweepSurface, cfg: LayerConfig, key: str,
                      region: tuple[float, float]) -> bool:
    """Whether a slip: auto layer on an open surface of revolution is held at its angle by friction
    (its geodesic turns around inside the region: winder.winding.layers.friction_revolution); refuses
    one that the friction cannot hold, naming the friction it needs (closed form, docs/math/09)."""
    if not surface.curve.is_straight:
        return False
    from winder.winding.layers.friction_revolution import (geodesic_reaches, held_need,  # noqa: PLC0415
                                                           is_open_revolution, need_message)

    if not is_open_revolution(surface) or geodesic_reaches(surface, *region, cfg.angle_deg):
        return False
    mu = job.winding.friction
    need, at, presses = held_need(surface, *region, cfg.angle_deg)
    why = need_message(surface, region, cfg.angle_deg, mu, need, at, presses)
    if why is not None:  # a bridge is the angle's; too little friction, the friction's
        raise _refuse(job.source, "winding.friction" if presses else f"{key}.angle",
                      f"{key}: {why}, got {mu if presses else cfg.angle_deg:g}")
    return True


def _check_turnaround_radius(job: JobConfig, prof: VesselMeridian, radii: tuple[float | None, float | None],
                             key: str) -> None:
    """turnaround_radius the friction-held planner (winding.layers.friction_vessel) can lay on the bare
    vessel: each dome's below the cylinder's radius and clear of its own polar opening by half a band."""
    half = 0.5 * job.winding.band_width
    same = radii[0] == radii[1]
    for end, radius, dome in zip(("start", "end"), radii, (prof.dome, prof.end_dome)):
        if radius is None:
            continue
        where = f"{key}.turnaround_radius" + ("" if same else f".{end}")
        if radius >= prof.radius:
            raise _refuse(job.source, where, f"must be smaller than the vessel's radius ({prof.radius:g} mm): the "
                          f"fiber turns around on the domes, got {radius:g}")
        c_min = dome.end_radius + half
        if radius < c_min - 1e-9:  # the planner's own comparison
            which = "first" if end == "start" else "end"
            raise _refuse(job.source, where, f"must be at least the {which} dome's polar opening "
                          f"({dome.end_radius:.3f} mm) plus half a band ({c_min:.3f} mm), or the band runs off the "
                          f"dome, got {radius:g}")


def _check_pass_points(job: JobConfig, surface: SweepSurface, cfg: LayerConfig, key: str, vessel: bool,
                       region: tuple[float, float]) -> None:
    """Refuse, from the geodesic's closed forms, what the planner would refuse on the bare mandrel:
    an open-mandrel layer whose geodesic turns around (Clairaut) before the end of the region, and
    too few points for the rounds a pass sweeps (winder.paths.resolution.check_points). Vessels: the
    cylinder piece alone, with all the points (a lower bound on what the planner needs); mandrels
    without a closed form (bends, varying non-circular sections): left to the planner."""
    from winder.paths.resolution import check_points  # noqa: PLC0415 - the solver's own rule

    w = job.winding
    n = w.points or DEFAULT_POINTS
    alpha = math.radians(cfg.angle_deg)
    if vessel:
        prof = surface.profile
        rounds = prof.cylinder_length * math.tan(alpha) / prof.radius / (2.0 * math.pi)
        n = max(n, PIECE_MIN_POINTS)
    else:
        from winder.winding.advance import reach_theta  # noqa: PLC0415 - open helical layers only
        from winder.winding.passes import reference_section  # noqa: PLC0415

        ctx = PlanContext(job, w, surface, arc_map(surface.section), job.machine.feed)
        s_a, s_b = (float(v) for v in surface.s_of_t(np.array(region)))
        s_ref, _ = reference_section(ctx, *region)
        ends = []
        try:
            for heading, s_end in ((cfg.angle_deg, s_b), (cfg.angle_deg + 180.0, s_a)):
                th = reach_theta(surface, s_ref, np.array([0.0]), heading, s_end)
                if th is None:
                    _check_bent_points(job, surface, cfg, region)
                    return
                ends.append(th)
        except SolverError as exc:  # the geodesic turns around on a narrowing mandrel
            from winder.winding.layers.friction_revolution import is_open_revolution, turn_remedies  # noqa: PLC0415

            hint = turn_remedies(surface, region, cfg.angle_deg, w.friction) if is_open_revolution(surface) else ""
            raise _refuse(job.source, f"{key}.angle", f"{exc.message}{hint}, got {cfg.angle_deg:g}") from exc
        natural = float(np.mean(ctx.arcs.fraction(ends[0]) - ctx.arcs.fraction(ends[1])))
        # A pass spans natural turns of the perimeter from where it starts; on a non-circular section
        # its angle's span depends on that start: the narrowest, so that what is refused here every
        # pass would be refused for (the planner refuses the widest; exact on a circle).
        starts = np.linspace(0.0, 1.0, START_SAMPLES)
        span = ctx.arcs.theta(starts + natural) - ctx.arcs.theta(starts)
        rounds = float(np.min(np.abs(span))) / (2.0 * math.pi)
    n = pass_points(w, rounds) or n  # the planner's own: more than the default for a pass of many rounds
    try:
        check_points(n, rounds, max(REFINE_MAX_POINTS, n))
    except ConfigError as exc:
        raise _refuse(job.source, "winding.points", exc.message) from exc


def _check_bent_points(job: JobConfig, surface: SweepSurface, cfg: LayerConfig, region: tuple[float, float]) -> None:
    """Too few points for a pass on a bent tube of circular section (no closed form: the planner
    traces the geodesic for minutes before its solver refuses n): the rounds estimated as on the
    straightened tube, the integral of tan(alpha) / perimeter along the axis
    (docs/math/14-work-estimates.md), refused where even BENT_ROUNDS_SHARE of them would be refused
    (the bend moves the rounds a little)."""
    from winder.paths.resolution import MIN_SEGMENTS_PER_ROUND, POINTS_PER_ROUND  # noqa: PLC0415

    if not surface.section.is_circle:
        return
    t = np.linspace(*region, REGION_STATIONS)
    per = np.asarray(surface.perimeter(surface.s_of_t(t)), dtype=float)
    rounds = math.tan(math.radians(cfg.angle_deg)) * float(np.mean(1.0 / per)) * (region[1] - region[0])
    n = pass_points(job.winding, BENT_ROUNDS_SHARE * rounds) or DEFAULT_POINTS
    least = math.ceil(MIN_SEGMENTS_PER_ROUND * BENT_ROUNDS_SHARE * rounds) - 1
    if n < least:
        raise _refuse(job.source, "winding.points",
                      f"must be at least {least} for a pass of about {rounds:.4g} rounds "
                      f"({region[1] - region[0]:.6g} mm of axis at {cfg.angle_deg:g} deg): with fewer, a segment "
                      f"spans over a third of a turn and cuts across the mandrel (an accurate length wants {POINTS_PER_ROUND} per round: "
                      f"{math.ceil(POINTS_PER_ROUND * rounds)}), got {n}")


def _hoop(job: JobConfig, surface: SweepSurface, cfg: LayerConfig, key: str) -> LayerBudget:
    w = job.winding
    prof = surface.profile
    t_a, t_b = prof.equator_t if isinstance(prof, VesselMeridian) else _region(surface, w)
    if isinstance(prof, VesselMeridian) and not t_b > t_a:  # hoops are laid on the cylinder alone
        raise _refuse(job.source, "mandrel.profile.cylinder_length",
                      f"{key} is laid on the vessel's cylinder: it must be longer than 0 mm, "
                      f"got {prof.cylinder_length:g}")
    perimeter = _largest_perimeter(surface, t_a, t_b)
    if cfg.passes > MAX_PASSES:
        raise _refuse(job.source, f"{key}.passes", f"must be <= {MAX_PASSES}, got {cfg.passes}")
    if cfg.angle_deg is None:
        ratio = w.band_width / perimeter
        if ratio >= 1.0:  # the planner's own refusal (winding.layers.hoop), known from the config
            raise _refuse(job.source, "winding.band_width",
                          f"wider than the perimeter where {key} is laid ({perimeter:.6g} mm at "
                          f"most): a hoop cannot be laid, got {w.band_width:g}")
        # pitch = P / tan(acos(B / P)) = B / sqrt(1 - (B / P)^2): one band width per turn
        pitch = w.band_width / math.sqrt(1.0 - ratio * ratio) if ratio < 1.0 else math.inf
        cause, value = "winding.band_width", f"{w.band_width:g}"
    else:
        pitch = perimeter / math.tan(math.radians(cfg.angle_deg))
        cause, value = f"{key}.angle", f"{cfg.angle_deg:g}"
    turns = (t_b - t_a) / pitch
    pass_points = int(math.ceil(turns * 360.0 / HOOP_STEP_DEG)) + 1 if math.isfinite(turns) else 3
    if pass_points > MAX_PASS_POINTS:
        raise _refuse(job.source, cause,
                      f"{key} would lay {turns:.4g} turns of pitch {pitch:.3g} mm over {t_b - t_a:g} mm, "
                      f"{pass_points:.4g} points per pass, more than the limit of {MAX_PASS_POINTS}, got {value}")
    # Between traverses the carriage turns back at one end or the other (winder.winding.turnaround).
    ends = tuple(float(v) for v in surface.s_of_t(np.array([t_a, t_b])))
    reversals = (cfg.passes - 1) * turnaround_points(surface, ends)
    return LayerBudget(1, cfg.passes, pass_points, pass_points * cfg.passes + reversals, pass_points)


def job_budget(job: JobConfig, surface: SweepSurface) -> Budget:
    """The work of a job with a winding section; raises ConfigError where one layer alone is past
    a limit (check_budget also holds the totals)."""
    if job.winding is None:
        return Budget((), 0, 0)
    if len(job.winding.layers) > MAX_LAYERS:
        raise _refuse(job.source, "winding.layers", f"{len(job.winding.layers)} layers, more than the limit of "
                      f"{MAX_LAYERS} (real tanks have 10 to 40)")
    layers = []
    laminate = job.winding.has_laminate  # once: it looks at every layer
    total = 0
    for index, cfg in enumerate(job.winding.layers):
        key = cfg.label(index)
        layers.append(_hoop(job, surface, cfg, key) if cfg.type is LayerType.HOOP
                      else _helical(job, surface, cfg, key, index == 0 or not laminate))
        total += layers[-1].points
        if total > MAX_TOTAL_POINTS:  # past the limit already: check_budget refuses it, the rest unread
            break
    w = job.winding
    vessel = isinstance(surface.profile, VesselMeridian)
    if w.region is None and not vessel and surface.axial_length < w.band_width:
        # as winding.region refuses a region shorter than the band: no pass has length to be solved on
        raise _refuse(job.source, "winding.band_width", f"must not exceed the mandrel's length "
                      f"({surface.axial_length:.6g} mm), or no band fits on it, got {w.band_width:g}")
    if w.tolerance is not None:
        from winder.paths.geodesic import ROUNDOFF_FLOOR  # noqa: PLC0415 - tolerance jobs only

        t_a, t_b = surface.profile.equator_t if vessel else _region(surface, w)
        floor = ROUNDOFF_FLOOR * (t_b - t_a)  # every pass is longer than the wound stretch
        if w.tolerance <= floor:
            raise _refuse(job.source, "winding.tolerance", f"must be above what double precision resolves on a "
                          f"pass ({floor:.2g} mm for the {t_b - t_a:.6g} mm wound), got {w.tolerance:g}")
    points = sum(layer.points for layer in layers)
    solve = max((layer.solve_points for layer in layers), default=0)
    helical = [0 if cfg.type is LayerType.HOOP else layer.passes for cfg, layer in zip(w.layers, layers)]
    memory = peak_bytes([layer.points for layer in layers], helical, solve, float(surface.axial_length),
                        vessel=vessel, robot=robot_poses(job.machine, surface),
                        whole=whole_plan(job.machine, surface))
    return Budget(tuple(layers), points, memory)


def check_budget(job: JobConfig, surface: SweepSurface) -> Budget:
    """job_budget, refusing a job past the total limits (ConfigError naming the key and the limit)."""
    budget = job_budget(job, surface)
    if budget.points > MAX_TOTAL_POINTS:
        worst = max(range(len(budget.layers)), key=lambda i: budget.layers[i].points)
        layer = budget.layers[worst]
        hoop = job.winding.layers[worst].type is LayerType.HOOP
        label = job.winding.layers[worst].label(worst)
        raise _refuse(job.source, f"{label}.passes" if hoop else "winding.points",
                      f"the job would plan {budget.points:.4g} points ({layer.points:.4g} in {label}: "
                      f"{layer.passes} passes of up to {layer.pass_points} points), more than the limit of "
                      f"{MAX_TOTAL_POINTS}; fewer passes, fewer points per pass or a wider band")
    if budget.memory_bytes > MAX_MEMORY_BYTES:
        largest = max(range(len(budget.layers)), key=lambda i: budget.layers[i].solve_points)
        per_point = solve_bytes_per_point(isinstance(surface.profile, VesselMeridian),
                                          robot_poses(job.machine, surface))
        solver = budget.layers[largest].solve_points * per_point
        # A hoop's points come from its turns (band width and length), not from winding.points.
        hoop = job.winding.layers[largest].type is LayerType.HOOP
        key = job.winding.layers[largest].label(largest) if hoop else "winding.points"
        raise _refuse(job.source, key if 2 * solver > budget.memory_bytes else "winding",
                      f"the job would need about {budget.memory_bytes / 1e9:.3g} GB of memory, more than the "
                      f"limit of {MAX_MEMORY_BYTES / 1e9:g} GB; fewer points or a wider band")
    return budget
