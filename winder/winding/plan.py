"""The winding planner: `plan(job) -> WindingPlan` (docs/math/05-winding.md; paper 6.1).

Each layer is planned by its own module: helical layers on open mandrels (helical.py), on domed
vessels (vessel.py), and hoop layers (hoop.py); passes.py holds what they share.
"""

from __future__ import annotations

import math
from dataclasses import replace

from winder.config.job import JobConfig
from winder.config.winding import LayerConfig, LayerType
from winder.geometry.vessel import VesselMeridian
from winder.errors import ConfigError, SolverError
from winder.progress import Progress, monotone
from winder.winding.layers.friction import friction_layer
from winder.winding.layers.helical_open import open_helical_layer
from winder.winding.layers.hoop import hoop_layer
from winder.winding.passes import PlanContext
from winder.winding.results import LayerPlan, WindingPlan
from winder.winding.turnaround import SWING_MIN_DEG
from winder.geometry.sections import arc_map
from winder.geometry.build import build_surface


def plan(job: JobConfig, progress: Progress | None = None,
         contexts: list[tuple[PlanContext, float]] | None = None, remedies: bool = True) -> WindingPlan:
    """Plan every layer of a job: circuits, patterns, passes, coverage (docs/math/05-winding.md).

    Parameters
    ----------
    job : JobConfig
        A validated config with a `winding:` section (winder.config.job.load_config).
    progress : callable, optional
        Told the fraction of the job done, per layer and per circuit (winder.progress).
    contexts : list, optional
        Gets each layer's context and start angle (rad) as the layer is planned in them.
    remedies : bool, optional
        A layer refused for a physical reason is refused naming the changes that plan it
        (winder.winding.remedies); False: the refusal alone (the remedies' own trial plans).

    Returns
    -------
    WindingPlan
        The layers in winding order, each with its passes (FiberPass: t, s, theta, points,
        directions), circuits, pattern, angle laid, coverage and laminate; the surface it was planned on.

    Raises
    ------
    ConfigError
        What the config cannot do (no winding section, a layer the mandrel does not allow).
    SolverError
        What cannot be computed: an infeasible winding (a fiber that would slip or bridge), no
        convergence.

    Examples
    --------
    A 55 deg layer on a pipe of radius 50 with 10 mm bands: ceil(2 pi 50 cos(55 deg) / 10) = 19
    circuits close evenly with a skip coprime with 19.

    >>> from winder.config.job import parse_config
    >>> job = parse_config({"name": "pipe",
    ...                     "mandrel": {"axis": {"type": "line", "length": 500},
    ...                                 "profile": {"type": "constant", "radius": 50}},
    ...                     "winding": {"band_width": 10, "points": 30, "region": {"start": 20, "end": 480},
    ...                                 "layers": [{"type": "helical", "angle": 55}]}}, "pipe.yaml")
    >>> layer = plan(job).layers[0]
    >>> layer.circuits, layer.pattern, layer.angle_deg
    (19, 13, 55.0)
    >>> round(float(layer.coverage.covered_fraction), 9)
    1.0
    """
    if job.winding is None:
        raise ConfigError(f"{job.source}: winding: missing; `winder run` needs the winding plan (band_width, "
                          f"layers)")
    surface = build_surface(job.mandrel, job.source, job.name)
    ctx = PlanContext(job, job.winding, surface, arc_map(surface.section), job.machine.feed, monotone(progress))
    layers = []
    theta0 = 0.0
    build = None
    if job.winding.has_laminate:
        # Layer planners and the laminate load with the jobs that need them: a small job's time is
        # mostly start-up, and each module costs its import.
        from winder.winding.wall import material_of, start_buildup  # noqa: PLC0415
        build = start_buildup(ctx)
    for index, cfg in enumerate(job.winding.layers):
        if contexts is not None:
            contexts.append((ctx, theta0))
        try:
            layer = plan_layer(ctx, cfg, index, theta0)
        except SolverError as exc:
            if not remedies:
                raise
            from winder.winding.remedies import with_remedies  # noqa: PLC0415 - refusals only

            raise with_remedies(job, index, exc, lambda j: plan(j, remedies=False)) from exc
        if build is not None:  # the next layer winds on the mandrel grown by this one
            layer, build = build.add(layer, material_of(job.winding.material_of(index)), ctx.key(index))
            ctx = replace(ctx, surface=build.surface)
        layers.append(layer)
        if cfg.type is not LayerType.HOOP and layer.turnaround_radii is not None:  # for the next step_back
            ctx = replace(ctx, previous_turnaround=layer.turnaround_radii)
        ctx.report(index, 1.0, "planned")
        # The next layer starts a little further on: the mandrel keeps turning while the eye moves
        # from this layer's last direction to the next one's first.
        theta0 = float(layer.passes[-1].theta[-1]) + math.radians(SWING_MIN_DEG)
    return WindingPlan(job.name, job.source, surface, tuple(layers), float(job.winding.band_width),
                       outer=build.surface if build is not None else None)


def plan_layer(ctx: PlanContext, cfg: LayerConfig, index: int, theta0: float) -> LayerPlan:
    """One layer planned in ctx (the mandrel as the layers before it left it), from theta0 (rad)."""
    if cfg.type is LayerType.HOOP:
        return hoop_layer(ctx, cfg, index, theta0)
    if (held := friction_layer(ctx, cfg, index, theta0)) is not None:
        return held
    if isinstance(ctx.surface.profile, VesselMeridian):
        from winder.winding.layers.vessel_tolerance import tolerant_vessel_layer  # noqa: PLC0415
        return tolerant_vessel_layer(ctx, cfg, index, theta0)
    return open_helical_layer(ctx, cfg, index, theta0)


def layer_contexts(job: JobConfig, count: int) -> tuple[list[tuple[PlanContext, float]], WindingPlan]:
    """The contexts and start angles (rad) `plan` plans the first count layers in (the mandrel grown
    by the layers before each, where the job has a laminate), and the plan of those layers: one plan."""
    contexts: list[tuple[PlanContext, float]] = []
    done = plan(replace(job, winding=replace(job.winding, layers=job.winding.layers[:count])), contexts=contexts)
    return contexts, done
