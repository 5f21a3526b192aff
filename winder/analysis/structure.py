"""A planned job's structural answer (SPEC.md "Structural analysis"): netting burst, first-ply failure by
Tsai-Wu and by maximum stress, where, per layer and in total; the summary's `analysis` block.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from winder.analysis.job import check_analysis, load_case, netting_stress
from winder.analysis.layup import layer_rows
from winder.analysis.netting import optimum_angle
from winder.analysis.stations import StationAnalysis, analyze_stations, surface_geometry
from winder.analysis.loads import resultants

PRESSURE_DECIMALS = 3  # MPa: a kPa
INDEX_DECIMALS = 6
# The decimals of the block's keys (export.summary compares and writes them at these).
DECIMALS = {"pressure_mpa": PRESSURE_DECIMALS, "burst_pressure_netting_mpa": PRESSURE_DECIMALS,
            "first_ply_failure_pressure_mpa": PRESSURE_DECIMALS, "first_ply_failure_max_stress_mpa": PRESSURE_DECIMALS,
            "t": 3, "max_stress_t": 3, "burst_netting_t": 3, "tsai_wu_index": INDEX_DECIMALS,
            "max_stress_index": INDEX_DECIMALS, "safety_factor": INDEX_DECIMALS, "axial_force_n": 3,
            "torque_nmm": 3, "netting_optimum_angle_deg": 4}
NOT_REVOLUTION = ("the laminate analysis needs a surface of revolution (a straight axis and circular "
                  "sections); see the shell model of --format abaqus")


@dataclasses.dataclass(frozen=True)
class Structure:
    """The analysis of a plan: success False (with message) where it does not apply; stations the
    per-station results (None then)."""

    success: bool
    message: str
    stations: StationAnalysis | None = None
    pressure: float = 0.0
    optimum_angle_deg: float = math.nan
    boss_radius: float = 0.0


def analyze(plan, job) -> Structure:
    """The structure of a planned job with an `analysis:` section (ConfigError without ply data)."""
    plies = check_analysis(job)
    if not plan.surface.is_revolution:
        return Structure(False, NOT_REVOLUTION)
    rows = layer_rows(plan)
    if not rows:
        return Structure(False, "no layer lays a laminate")
    index = [r.index - 1 for r in rows]
    laminae = tuple(plies[i] for i in index)
    sigma = np.array([netting_stress(job, i, p) for i, p in zip(index, laminae)])
    turns = [layer.turnaround_radius for layer in plan.layers if layer.turnaround_radius is not None]
    boss = max(turns) + plan.band_width if turns else 0.0
    case = load_case(job)
    stations = analyze_stations(plan.surface, rows, laminae, sigma, case, boss)
    # the optimum angle where the wall is the part's own: the widest station (a vessel's cylinder)
    widest = surface_geometry(plan.surface, stations.geometry.t[[int(np.argmax(stations.geometry.r))]])
    per_p, held = resultants(widest, case)
    n = case.pressure * per_p[0] + held[0] if case.pressure > 0.0 else per_p[0]
    return Structure(True, "", stations, case.pressure, math.degrees(optimum_angle(n[0], n[1])), boss)


def _round(value: float, decimals: int) -> float | None:
    value = float(value)
    return round(value, decimals) + 0.0 if math.isfinite(value) else None


def _least(values: np.ndarray, t: np.ndarray) -> tuple[float, float]:
    """(least value, its station) over the stations of a (n,) array (inf, nan when none is finite)."""
    if values.size == 0 or not np.any(np.isfinite(values)):
        return math.inf, math.nan
    i = int(np.argmin(values))
    return float(values[i]), float(t[i])


def summary_block(structure: Structure, job) -> dict:
    """The summary's `analysis` object (keys in DECIMALS' units; null where not finite)."""
    case = job.analysis
    out: dict = {"pressure_mpa": _round(case.pressure, PRESSURE_DECIMALS), "axial_force_n": _round(case.axial_force, 3),
                 "torque_nmm": _round(case.torque, 3), "ends": case.ends, "success": structure.success,
                 "message": structure.message}
    st = structure.stations
    if st is None:
        return out
    t = st.geometry.t
    layers = []
    for k, index in enumerate(st.layers):
        tw, tw_t = _least(st.tsai_wu[:, k], t)
        ms, ms_t = _least(st.max_stress[:, k], t)
        with np.errstate(all="ignore"):
            tw_i = np.nanmax(st.tsai_wu_index[:, k]) if np.any(np.isfinite(st.tsai_wu_index[:, k])) else math.nan
            ms_i = np.nanmax(st.max_stress_index[:, k]) if np.any(np.isfinite(st.max_stress_index[:, k])) else math.nan
        layers.append({"layer": int(index), "first_ply_failure_pressure_mpa": _round(tw, PRESSURE_DECIMALS),
                       "t": _round(tw_t, 3), "first_ply_failure_max_stress_mpa": _round(ms, PRESSURE_DECIMALS),
                       "max_stress_t": _round(ms_t, 3), "tsai_wu_index": _round(tw_i, INDEX_DECIMALS),
                       "max_stress_index": _round(ms_i, INDEX_DECIMALS)})
    tw_all = st.tsai_wu.min(axis=1)
    ms_all = st.max_stress.min(axis=1)
    tw, tw_t = _least(tw_all, t)
    ms, ms_t = _least(ms_all, t)
    burst, burst_t = _least(np.where(st.netting_applies, st.netting.burst, np.inf), t)
    where = int(np.argmin(np.where(st.netting_applies, st.netting.burst, np.inf)))
    out.update({
        "burst_pressure_netting_mpa": _round(burst, PRESSURE_DECIMALS), "burst_netting_t": _round(burst_t, 3),
        "burst_netting_limit": "axial" if st.netting.axial[where] <= st.netting.hoop[where] else "hoop",
        "netting_optimum_angle_deg": _round(structure.optimum_angle_deg, 4),
        "first_ply_failure_pressure_mpa": _round(tw, PRESSURE_DECIMALS), "t": _round(tw_t, 3),
        "layer": int(st.layers[int(np.argmin(st.tsai_wu[int(np.argmin(tw_all))]))]) if math.isfinite(tw) else None,
        "first_ply_failure_max_stress_mpa": _round(ms, PRESSURE_DECIMALS), "max_stress_t": _round(ms_t, 3),
        "max_stress_layer": (int(st.layers[int(np.argmin(st.max_stress[int(np.argmin(ms_all))]))])
                             if math.isfinite(ms) else None),
        "safety_factor": _round(tw / structure.pressure, INDEX_DECIMALS) if structure.pressure > 0 else None,
        "layers": layers,
    })
    return out
