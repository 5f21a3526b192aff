"""Refusals that name the remedies that work (issue 49: every refusal that has a remedy names it,
tested by applying it).

A layer refused for a physical reason (a fiber that would slip, bridge, or turn around before the end
of the region) is not told to "raise the friction" or "lower the angle" from the figure it failed on:
friction moves the turnarounds, so the friction a layer needs changes with the friction it is given,
and a steeper angle may bridge. Each candidate change (winding.friction, step_back, no region: the
mandrel's ends holding the fiber, a hoop taper, the hoops wound outside, the angle, slip: auto,
bridging_tolerance) is applied to the job and the layers up to the refused one planned again; the
least value that plans is named, and a change that plans at no value tried is left out. The search is
bounded in attempts and time (a refusal costs at most a few plans of the job).
"""

from __future__ import annotations

import dataclasses
import math
import re
import time
from collections.abc import Callable
from dataclasses import replace

from winder.config.job import JobConfig
from winder.config.vessel import VesselProfile
from winder.config.winding import SLIP_AUTO, LayerType
from winder.errors import ConfigError, SolverError, WinderError

MAX_TRIES = 10  # plans of the job's prefix over all remedies of one refusal
MAX_SECONDS = 40.0  # and the time they may take together (a refusal costs a few plans of the job)
FRICTION_STEP = 0.01  # friction is named to this resolution, rounded up
MAX_FRICTION_ROUNDS = 4  # a friction that plans is sought this many times (each asks the next figure)
BAND_SHARES = (0.5, 1.0, 2.0, 4.0)  # step_back and taper tried at these multiples of the band width
ANGLE_STEPS = (2.5, 5.0, 10.0)  # deg away from the refused angle, in turn
LIFT_STEP = 0.1  # mm: bridging_tolerance is named to this resolution, rounded up

_NUMBER = r"([0-9]+(?:\.[0-9]*)?(?:e[-+]?[0-9]+)?)"


@dataclasses.dataclass(frozen=True)
class Refusal:
    """What a refusal's message says: its kind (slip, bridge, turn) and its figure (the friction needed,
    the lift-off in mm; nan where it names none)."""

    kind: str
    figure: float

    @classmethod
    def of(cls, message: str) -> Refusal | None:
        if "k_g / k_n" in message and "above the friction" in message:
            found = re.findall(r"(?:least mu (?:that holds this layer )?is|k_g / k_n\| (?:=|up to)|needs "
                               r"\|k_g / k_n\| = ?) ?" + _NUMBER, message)
            return cls("slip", max((float(v) for v in found), default=math.nan))
        if "bridges" in message:
            lift = re.search(r"stands " + _NUMBER + " mm off", message)
            return cls("bridge", float(lift.group(1)) if lift else math.nan)
        if "turns around" in message:
            return cls("turn", math.nan)
        return None


@dataclasses.dataclass
class _Budget:
    """The planner (a job -> its plan, refusing without remedies) and what the search has spent."""

    plan: Callable[[JobConfig], object]
    start: float
    tries: int = 0

    def spent(self) -> bool:
        return self.tries >= MAX_TRIES or time.monotonic() - self.start > MAX_SECONDS


def _with_layers(job: JobConfig, layers) -> JobConfig:
    return replace(job, winding=replace(job.winding, layers=tuple(layers)))


def _with_layer(job: JobConfig, index: int, **changes) -> JobConfig:
    layers = list(job.winding.layers)
    layers[index] = replace(layers[index], **changes)
    return _with_layers(job, layers)


def _attempt(job: JobConfig, index: int, budget: _Budget) -> Refusal | None | bool:
    """Plan the job's layers up to index: True where they plan, else the refusal met (None: not physical)."""
    budget.tries += 1
    try:
        budget.plan(_with_layers(job, job.winding.layers[:index + 1]))
    except (SolverError, ConfigError) as exc:
        return Refusal.of(exc.message)
    except WinderError:
        return None
    return True


def _ladder(job: JobConfig, index: int, budget: _Budget, values, make: Callable[[JobConfig, float], JobConfig],
            text: Callable[[float], str]) -> str | None:
    """The first of values (in order) whose change plans the layer, named by text."""
    for v in values:
        if budget.spent():
            return None
        if _attempt(make(job, v), index, budget) is True:
            return text(v)
    return None


def _friction(job: JobConfig, index: int, need: float, budget: _Budget) -> str | None:
    """The least friction (to FRICTION_STEP) that plans: each refused try names the figure of the next."""
    mu = job.winding.friction
    ask = max(need, mu + FRICTION_STEP) if math.isfinite(need) else mu + FRICTION_STEP
    for _ in range(MAX_FRICTION_ROUNDS):
        ask = math.ceil(ask / FRICTION_STEP - 1e-9) * FRICTION_STEP
        if ask > 1.0 or budget.spent():
            return None
        out = _attempt(replace(job, winding=replace(job.winding, friction=ask)), index, budget)
        if out is True:
            return f"winding.friction: {ask:.2f}"
        if not isinstance(out, Refusal) or out.kind != "slip":
            return None  # more friction meets another refusal: not the remedy
        ask = max(out.figure if math.isfinite(out.figure) else 0.0, ask + FRICTION_STEP)
    return None


def _hoops_before(job: JobConfig, index: int) -> list[int]:
    return [i for i, layer in enumerate(job.winding.layers[:index]) if layer.type is LayerType.HOOP]


def _outside(job: JobConfig, index: int, hoops: list[int]) -> JobConfig:
    """The layer wound before the hoops that lie under it (the hoops outside it)."""
    layers = list(job.winding.layers)
    moved = layers.pop(index)
    layers.insert(hoops[0], moved)
    return _with_layers(job, layers)


def remedies(job: JobConfig, index: int, message: str, planner: Callable[[JobConfig], object]) -> list[str]:
    """The changes that plan layer `index` (0-based) of job, refused with message (none where the
    refusal is not a physical one these changes address); planner plans a job without remedies."""
    refusal = Refusal.of(message)
    if refusal is None:
        return []
    w, cfg = job.winding, job.winding.layers[index]
    budget = _Budget(planner, time.monotonic())
    band = w.band_width
    vessel = isinstance(job.mandrel.profile, VesselProfile)
    helical = cfg.type is LayerType.HELICAL
    found: list[str | None] = []
    if refusal.kind == "slip":
        found.append(_friction(job, index, refusal.figure, budget))
    if helical and vessel and refusal.kind in ("slip", "bridge") and index > 0:
        found.append(_ladder(job, index, budget, [s * band for s in BAND_SHARES if s * band > cfg.step_back],
                             lambda j, v: _with_layer(j, index, step_back=v),
                             lambda v: f"step_back: {v:g} on {cfg.label(index)}"))
    if not vessel and w.region is not None and refusal.kind in ("slip", "bridge"):
        found.append(_ladder(job, index, budget, [None], lambda j, v: replace(j, winding=replace(j.winding, region=v)),
                             lambda v: "no winding.region (the whole mandrel wound, its ends holding the fiber: pins "
                                       "or a flange)"))
    hoops = _hoops_before(job, index) if helical else []
    if hoops and refusal.kind in ("slip", "bridge"):
        def tapered(j: JobConfig, v: float) -> JobConfig:
            return _with_layers(j, [replace(x, taper=v) if i in hoops else x for i, x in enumerate(j.winding.layers)])

        found.append(_ladder(job, index, budget, [s * band for s in BAND_SHARES], tapered,
                             lambda v: f"taper: {v:g} on the hoops under it ("
                                       + ", ".join(w.layers[i].label(i) for i in hoops) + ")"))
        found.append(_ladder(job, index, budget, [0.0], lambda j, v: _outside(j, index, hoops),
                             lambda v: f"{cfg.label(index)} wound before the hoops (they go outside)"))
    if helical and not vessel and refusal.kind == "turn" and cfg.slip == 0.0:
        found.append(_ladder(job, index, budget, [SLIP_AUTO], lambda j, v: _with_layer(j, index, slip=v),
                             lambda v: "slip: auto (friction holds the angle where the geodesic turns)"))
    if helical and refusal.kind in ("turn", "bridge"):
        sign = -1.0 if refusal.kind == "turn" else 1.0
        angles = [cfg.angle_deg + sign * d for d in ANGLE_STEPS if 0.0 < cfg.angle_deg + sign * d < 90.0]
        found.append(_ladder(job, index, budget, angles, lambda j, v: _with_layer(j, index, angle_deg=v),
                             lambda v: f"angle: {v:g}"))
    if refusal.kind == "bridge" and math.isfinite(refusal.figure):
        tol = math.ceil(refusal.figure / LIFT_STEP) * LIFT_STEP
        found.append(_ladder(job, index, budget, [tol],
                             lambda j, v: replace(j, winding=replace(j.winding, bridging_tolerance=v)),
                             lambda v: f"winding.bridging_tolerance: {v:.1f} (accepts that lift-off)"))
    return [f for f in found if f]


def with_remedies(job: JobConfig, index: int, exc: SolverError, planner: Callable[[JobConfig], object]) -> SolverError:
    """exc with the remedies that plan appended (itself where there are none); planner as remedies'."""
    if "; what " in exc.message:  # named already, from a closed form
        return exc
    fixes = remedies(job, index, exc.message, planner)
    if not fixes:
        return exc
    return SolverError(f"{exc.message}; what plans it: " + "; ".join(fixes), file=exc.file, key_path=exc.key_path)

