"""The job summary `<name>.summary.json` (docs/guide/conventions.md).

One JSON object, keys sorted, indent 2, newline-terminated. Floats are rounded to fixed decimals
(LENGTH_DECIMALS for mm, ANGLE_DECIMALS for degrees, FRACTION_DECIMALS for fractions, TIME_DECIMALS
for seconds) so the file is byte-stable across platforms; a value that is not finite is null. No
wall-clock timings: estimated times are the planner's, at the machine feed.

Keys: name, source, total_fiber_length_mm, estimated_time_s, layer_count, and layers: one object per
layer with index, type, angle_deg, requested_angle_deg, angle_change_deg, circuits, pattern (as planned),
passes (the layer's passes in the job CSV: turnarounds and dwells included), fiber_length_mm, dwell_start_deg, dwell_end_deg, turnaround_radius_mm (null
when the fiber does not turn on a dome) and turnaround_radii_mm [first dome, end dome] (each dome's own), alpha_range_deg [min, max], time_s, coverage
{covered_fraction, max_gap_mm, max_overlap_mm, min_layers, max_layers}, notes (list of text),
max_slip (largest |k_g / k_n| the fibers need) and min_normal_curvature_per_mm (least k_n, > 0),
max_lift_off_mm (how far the fiber stands off a concave stretch it bridges, 0 where it presses
everywhere) with lift_off_t_mm and lift_off_pass (where; null without a lift-off).
With a material (a laminate), each layer also has thickness_mm (mean, at the reference section),
max_thickness_mm, ply_thickness_mm, volume_mm3, fiber_mass_kg, resin_mass_kg, material_length_mm
and outer_radius_mm (after the layer), and the job fiber_mass_kg, resin_mass_kg, mass_kg and
outer_radius_mm; without one these keys are absent. On an open mandrel with densities, mass_per_metre_kg
(the laminate at the reference section) and trimmed {t_mm, length_mm, mass_kg, mass_per_metre_kg}: the part between the
turnaround zones where every layer is laid (winder.analysis.gauge's `wound`). On a vessel, volume_l: the
volume its mandrel encloses, closed at the polar openings' planes. On a vessel with a material, domes: the first and
the end dome's wall at the bosses (docs/math/08-laminate-edges.md 8.11): opening_radius_mm,
max_wall_mm (the largest laminate thickness on the dome) and max_wall_radius_mm (the bare radius there).
With the machine: winding_time_s in total and per layer, the machine's time over the motion program
from machine.dynamics, acceleration and deceleration included (winder.machine.dynamics); null when
no program can be built (an axis limit). estimated_time_s / time_s stay the fiber length at the feed.
And axis_travel: each logical axis's [least, largest] value over the program as written (carriage,
rotation, cross_feed, yaw; for robot poses x, y, z, i, j, k), to set against the machine's travel;
null when no program can be built, and then program_error: why (the axis, the value and the limit).
With a programmed tension (winding.tension, a layer's own), each layer has tension_n (N per band, its
first pass's) and tension_range_n [least, largest] over its passes, as the program writes them.
With prices in the materials (fiber_price_per_kg, resin_price_per_kg), material_cost {fiber, resin,
total}: the layers' masses at their materials' prices.
With an `analysis:` section, the `analysis` block (winder.analysis.verdict.summary_block): the load
case, the gauge section the headline figures come from (gauge, gauge_t_mm), burst_pressure_netting_mpa
(and where, which layer, how), first_ply_failure_pressure_mpa (Tsai-Wu) with its layer and t,
first_ply_failure_max_stress_mpa, burst_ratio and first_ply_failure_ratio (safety_factor: the same, its
older name), the targets' burst_ratio_required and burst_pass, stress_ratio per fiber material,
netting_allowables and notes, netting_optimum_angle_deg, per layer, and end_zones (the same figures
outside the gauge, labelled). `winder analyze` adds the `fe` block (winder.analysis.fe_compare).
"""

from __future__ import annotations

import json
import math
from typing import Any

import numpy as np

from winder.analysis.verdict import DECIMALS as STRUCTURE_DECIMALS
from winder.errors import ExportError, WinderError
from winder.export.dialects.marlin import AXIS_SIGNS
from winder.machine.program import MotionProgram, build_program
from winder.machine.limits import AXIS_DECIMALS
from winder.winding.dome_wall import dome_walls
from winder.winding.results import LayerPlan, WindingPlan

LENGTH_DECIMALS = 3
DIRECTION_DECIMALS = 6  # a robot pose's unit direction, as the program writes it
ANGLE_DECIMALS = 4
FRACTION_DECIMALS = 6
CURVATURE_DECIMALS = 8  # 1/mm
TIME_DECIMALS = 2
MASS_DECIMALS = 6  # kg: to the milligram
VOLUME_DECIMALS = 6  # litres: to the cubic millimetre
THICKNESS_DECIMALS = LENGTH_DECIMALS + 1  # a wall grows by tenths of a millimetre a layer
TENSION_DECIMALS = 3  # N per band
COST_DECIMALS = 2  # the config's currency
DEVIATION_DECIMALS = LENGTH_DECIMALS + 1  # the program's points and moves off the fiber: tenths of a micrometre
# The decimals each number is written with, by the end of its key: what `winder regress` compares
# at (one unit in the last place). Keys written otherwise are named in DECIMALS_BY_NAME (a looser
# unit would let a real change pass, a tighter one fail on round-off); axis_travel is written at
# the program's decimals. A key matching none of these is compared relatively (1e-6).
DECIMALS_BY_SUFFIX = (("_mm", LENGTH_DECIMALS), ("_deg", ANGLE_DECIMALS), ("_fraction", FRACTION_DECIMALS),
                      ("_s", TIME_DECIMALS), ("_kg", MASS_DECIMALS), ("_mm3", LENGTH_DECIMALS))
DECIMALS_BY_NAME = {"max_slip": FRACTION_DECIMALS, "min_normal_curvature_per_mm": CURVATURE_DECIMALS,
                    "thickness_mm": THICKNESS_DECIMALS, "max_thickness_mm": THICKNESS_DECIMALS,
                    "ply_thickness_mm": THICKNESS_DECIMALS, "outer_radius_mm": THICKNESS_DECIMALS,
                    "max_wall_mm": THICKNESS_DECIMALS, "max_point_deviation_mm": DEVIATION_DECIMALS,
                    "max_midpoint_deviation_mm": DEVIATION_DECIMALS, "volume_l": VOLUME_DECIMALS,
                    "tension_n": TENSION_DECIMALS, "tension_range_n": TENSION_DECIMALS}
_DIRECTIONS = ("i", "j", "k")  # a robot pose's direction components
DECIMALS_BY_NAME.update(STRUCTURE_DECIMALS)  # the `analysis` block's keys (winder.analysis.verdict)


def decimals_of(key: str) -> int | None:
    """Decimals the summary writes the number at key path `key` with ("layers[0].alpha_range_deg[1]")."""
    name = key.rsplit(".", 1)[-1].split("[", 1)[0]
    if key.startswith("axis_travel.") and "." not in key[len("axis_travel."):]:
        return DIRECTION_DECIMALS if name in _DIRECTIONS else AXIS_DECIMALS
    if name in DECIMALS_BY_NAME:
        return DECIMALS_BY_NAME[name]
    return next((d for suffix, d in DECIMALS_BY_SUFFIX if name.endswith(suffix)), None)


def _num(value: float | None, decimals: int) -> float | None:
    if value is None:
        return None
    value = float(value)
    if not math.isfinite(value):
        return None
    out = round(value, decimals)
    return 0.0 if out == 0.0 else out  # no "-0.0"


def _layer(layer: LayerPlan) -> dict[str, Any]:
    cov = layer.coverage
    return {
        "index": int(layer.index),
        "type": layer.type.value,
        "angle_deg": _num(layer.angle_deg, ANGLE_DECIMALS),
        "requested_angle_deg": _num(layer.requested_angle_deg, ANGLE_DECIMALS),
        "angle_change_deg": _num(layer.angle_change_deg, ANGLE_DECIMALS),
        "circuits": int(layer.circuits),
        "pattern": None if layer.pattern is None else int(layer.pattern),
        "passes": len(layer.passes),
        "fiber_length_mm": _num(layer.fiber_length_mm, LENGTH_DECIMALS),
        "dwell_start_deg": _num(layer.dwell_start_deg, ANGLE_DECIMALS),
        "dwell_end_deg": _num(layer.dwell_end_deg, ANGLE_DECIMALS),
        "turnaround_radius_mm": _num(layer.turnaround_radius, LENGTH_DECIMALS),
        "turnaround_radii_mm": (None if layer.turnaround_radii is None
                                else [_num(r, LENGTH_DECIMALS) for r in layer.turnaround_radii]),
        "max_slip": _num(layer.max_slip, FRACTION_DECIMALS),
        "min_normal_curvature_per_mm": _num(layer.min_normal_curvature, CURVATURE_DECIMALS),
        "alpha_range_deg": [_num(layer.alpha_min_deg, ANGLE_DECIMALS), _num(layer.alpha_max_deg, ANGLE_DECIMALS)],
        "time_s": _num(layer.time_s, TIME_DECIMALS),
        "coverage": {
            "covered_fraction": _num(cov.covered_fraction, FRACTION_DECIMALS),
            "max_gap_mm": _num(cov.max_gap_mm, LENGTH_DECIMALS),
            "max_overlap_mm": _num(cov.max_overlap_mm, LENGTH_DECIMALS),
            "min_layers": int(cov.min_layers),
            "max_layers": int(cov.max_layers),
        },
        "notes": [str(n) for n in layer.notes],
        **_laminate(layer),
        **_lift_off(layer),
    }


def _lift_off(layer: LayerPlan) -> dict[str, Any]:
    """max_lift_off_mm (0 where the fiber presses everywhere) and where: lift_off_t_mm, lift_off_pass
    (null without a lift-off); docs/math/08-laminate-edges.md 8.10."""
    bridged = layer.max_lift_off_mm > 0.0
    return {"max_lift_off_mm": _num(layer.max_lift_off_mm, LENGTH_DECIMALS),
            "lift_off_t_mm": _num(layer.lift_off_t, LENGTH_DECIMALS) if bridged else None,
            "lift_off_pass": int(layer.lift_off_pass) if bridged else None}


def _laminate(layer: LayerPlan) -> dict[str, Any]:
    """A layer's wall keys (docs/math/08-laminate-edges.md); none without a material, so such summaries stay as
    they were."""
    lam = layer.laminate
    if lam is None:
        return {}
    return {
        "thickness_mm": _num(lam.thickness_mm, THICKNESS_DECIMALS),
        "max_thickness_mm": _num(lam.max_thickness_mm, THICKNESS_DECIMALS),
        "ply_thickness_mm": _num(lam.ply_mm, THICKNESS_DECIMALS),
        "volume_mm3": _num(lam.volume_mm3, LENGTH_DECIMALS),
        "fiber_mass_kg": _num(lam.fiber_mass_kg, MASS_DECIMALS),
        "resin_mass_kg": _num(lam.resin_mass_kg, MASS_DECIMALS),
        "material_length_mm": _num(lam.material_length_mm, LENGTH_DECIMALS),
        "outer_radius_mm": _num(lam.outer_radius_mm, THICKNESS_DECIMALS),
    }


def _totals(plan: WindingPlan) -> dict[str, Any]:
    walls = [layer.laminate for layer in plan.layers if layer.laminate is not None]
    if not walls:
        return {}
    fiber = sum(w.fiber_mass_kg for w in walls)
    resin = sum(w.resin_mass_kg for w in walls)
    out = {"fiber_mass_kg": _num(fiber, MASS_DECIMALS), "resin_mass_kg": _num(resin, MASS_DECIMALS),
           "mass_kg": _num(fiber + resin, MASS_DECIMALS),
           "outer_radius_mm": _num(walls[-1].outer_radius_mm, THICKNESS_DECIMALS)}
    domes = dome_walls(plan)
    if domes is not None:
        out["domes"] = [{"opening_radius_mm": _num(d.opening_radius_mm, LENGTH_DECIMALS),
                         "max_wall_mm": _num(d.max_wall_mm, THICKNESS_DECIMALS),
                         "max_wall_radius_mm": _num(d.max_wall_radius_mm, LENGTH_DECIMALS)} for d in domes]
    return out


def _shop_figures(plan: WindingPlan, job) -> dict[str, Any]:
    """A vessel's enclosed volume (volume_l); an open mandrel's laminate mass per metre at its reference
    section and over its trimmed part (the `wound` gauge: winder.analysis.gauge), with a material's densities."""
    from winder.analysis import gauge, quantities  # noqa: PLC0415
    from winder.winding.wall import reference_station  # noqa: PLC0415

    if not plan.surface.is_revolution:
        return {}
    if gauge.is_vessel(plan.surface):
        return {"volume_l": _num(quantities.enclosed_volume(plan.surface.profile) * 1e-6, VOLUME_DECIMALS)}
    densities = quantities.layer_densities(plan)
    if densities.size == 0 or not np.all(np.isfinite(densities)):
        return {}
    region = getattr(getattr(job, "winding", None), "region", None)
    span = gauge.gauge_span(plan, "wound", region)
    if not np.all(np.isfinite(span)):
        return {}
    ref = reference_station(plan.surface, region or (0.0, plan.surface.axial_length), plan.band_width)
    per_m = float(quantities.mass_per_length(plan, np.array([ref]))[0]) * 1000.0
    mass = quantities.trimmed_mass(plan, span)
    return {"mass_per_metre_kg": _num(per_m, MASS_DECIMALS),
            "trimmed": {"t_mm": [_num(span[0], LENGTH_DECIMALS), _num(span[1], LENGTH_DECIMALS)],
                        "length_mm": _num(span[1] - span[0], LENGTH_DECIMALS), "mass_kg": _num(mass, MASS_DECIMALS),
                        "mass_per_metre_kg": _num(mass / (span[1] - span[0]) * 1000.0, MASS_DECIMALS)}}


def _program_times(plan: WindingPlan, program: MotionProgram | Exception
                   ) -> tuple[float | None, list[float | None], dict | None, str | None]:
    """(total, per layer) machine time from the dynamics, the axis travel and None; None, None and
    why where no program could be built (program: the build's ExportError)."""
    if isinstance(program, ExportError):
        return None, [None] * len(plan.layers), None, str(program)
    if isinstance(program, Exception):
        raise program
    layers = list(program.layer_times_s)
    return program.times.total_s, layers, _axis_travel(program), None


def _axis_travel(program) -> dict[str, list[float]]:
    """Each logical axis's [least, largest] value over the program, as it is written (a shop checks
    them against its machine's travel; robot poses: position mm and direction components; marlin:
    A and B in fiberpath's sense, marlin.AXIS_SIGNS)."""
    values = program.values
    if values.shape[0] == 0:
        return {}
    if not program.robot and program.machine.dialect == "marlin":
        values = values * np.array(AXIS_SIGNS)
    lows, highs = values.min(axis=0).tolist(), values.max(axis=0).tolist()
    decimals = [DIRECTION_DECIMALS if axis in _DIRECTIONS else AXIS_DECIMALS for axis in program.axes]
    return {axis: [round(lo, k) + 0.0, round(hi, k) + 0.0]  # + 0.0: no -0.0 at a rounded zero
            for axis, lo, hi, k in zip(program.axes, lows, highs, decimals)}


def summary_dict(plan: WindingPlan, machine=None, program: MotionProgram | Exception | None = None,
                 job=None) -> dict[str, Any]:
    """The summary as plain Python data (what summary_text serializes); machine: a MachineConfig
    for the winding times (left out: no winding_time_s keys); program: its motion program (or the
    error of its build), built here when not given; job: its `analysis:` section gives the
    `analysis` block (winder.analysis.structure)."""
    out = {
        "name": plan.name,
        "source": plan.source,
        "total_fiber_length_mm": _num(plan.total_fiber_length_mm, LENGTH_DECIMALS),
        "estimated_time_s": _num(plan.total_time_s, TIME_DECIMALS),
        "layer_count": len(plan.layers),
        "layers": [_layer(layer) for layer in plan.layers],
        **_totals(plan),
        **_shop_figures(plan, job),
    }
    if machine is not None and program is None:
        from winder.machine.tension import job_program  # noqa: PLC0415

        try:
            program = job_program(plan, job) if job is not None else build_program(plan, machine)
        except ExportError as exc:
            program = exc
    _tensions(out["layers"], plan, program, job)
    if machine is not None:
        total, layers, travel, why = _program_times(plan, program)
        out["winding_time_s"] = _num(total, TIME_DECIMALS)
        out["axis_travel"] = travel
        if why is not None:
            out["program_error"] = why
        for entry, seconds in zip(out["layers"], layers):
            entry["winding_time_s"] = _num(seconds, TIME_DECIMALS)
    cost = material_cost(out["layers"], job)
    if cost is not None:
        out["material_cost"] = cost
    out["invariants"] = _invariants(plan, program)
    if job is not None and getattr(job, "analysis", None) is not None:
        from winder.analysis.structure import analyze, summary_block  # noqa: PLC0415

        out["analysis"] = summary_block(analyze(plan, job), job)
    return out


def _tensions(entries: list[dict], plan: WindingPlan, program, job) -> None:
    """tension_n (the layer's first pass's, N per band) and tension_range_n [least, largest] of each
    layer with a programmed tension: the program's, else the job's (no program built)."""
    if isinstance(program, MotionProgram):
        found = program.layer_tensions
    elif job is not None and getattr(job, "winding", None) is not None:
        from winder.machine.tension import pass_tensions  # noqa: PLC0415

        per_pass = pass_tensions(job, plan) or ()
        found = tuple((v[0], min(v), max(v)) if v else None for v in per_pass)
    else:
        return
    for entry, tension in zip(entries, found):
        if tension is not None:
            entry["tension_n"] = _num(tension[0], TENSION_DECIMALS)
            entry["tension_range_n"] = [_num(tension[1], TENSION_DECIMALS), _num(tension[2], TENSION_DECIMALS)]


def material_cost(entries: list[dict], job) -> dict[str, float] | None:
    """{fiber, resin, total}: each layer's fiber and resin mass at its material's price per kg (in the
    config's currency; a mass or price not given counts nothing); None when no material has a price."""
    winding = getattr(job, "winding", None)
    materials = [winding.material_of(i) for i in range(len(winding.layers))] if winding is not None else []
    if not any(m is not None and (m.fiber_price_per_kg is not None or m.resin_price_per_kg is not None)
               for m in materials):
        return None
    sums = {"fiber": 0.0, "resin": 0.0}
    for entry, m in zip(entries, materials):
        for part in sums:
            mass, price = entry.get(f"{part}_mass_kg"), getattr(m, f"{part}_price_per_kg", None) if m else None
            if mass is not None and price is not None:
                sums[part] += mass * price
    return {**{k: _num(v, COST_DECIMALS) for k, v in sums.items()}, "total": _num(sum(sums.values()), COST_DECIMALS)}


def _invariants(plan: WindingPlan, program) -> dict[str, float | None]:
    """The job's margins (winder.machine.invariants): the program's where it proved them, else the
    plan's coverage alone."""
    proved = getattr(program, "invariants", None)
    least = min((layer.coverage.covered_fraction for layer in plan.layers), default=1.0)
    figures = {
        "min_covered_fraction": float(least) if proved is None else proved.min_covered_fraction,
        "max_point_deviation_mm": None if proved is None else proved.max_point_deviation_mm,
        "max_midpoint_deviation_mm": None if proved is None else proved.max_midpoint_deviation_mm,
        "min_clearance_mm": None if proved is None else proved.min_clearance_mm,
    }
    return {key: _num(value, decimals_of(key)) for key, value in figures.items()}


def summary_text(plan: WindingPlan, machine=None, program: MotionProgram | Exception | None = None,
                 job=None) -> str:
    """The summary JSON text (sorted keys, indent 2, newline-terminated)."""
    return json.dumps(summary_dict(plan, machine, program, job), sort_keys=True, indent=2, allow_nan=False) + "\n"


def export(plan: WindingPlan, job, program: MotionProgram | Exception | None = None) -> str:
    """The registry's entry (winder.export.registry). The summary must be JSON (regress and other
    tools read it): anything else is refused here rather than written to a file nobody can read."""
    text = summary_text(plan, job.machine, program, job)
    try:
        json.loads(text)
    except ValueError as exc:
        raise WinderError(f"{job.source}: internal error: the summary is not valid JSON ({exc}); "
                          "please report it") from exc
    return text
