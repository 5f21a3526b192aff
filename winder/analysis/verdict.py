"""The summary's `analysis` block (docs/guide/will-it-hold.md): the headline
figures from the gauge section, the end zones' apart and labelled, the ratios against the user's targets,
and what the netting allowables rest on (docs/math/09-structure.md 9.2, 9.6, 9.7).
"""

from __future__ import annotations

import math

import numpy as np

PRESSURE_DECIMALS = 3  # MPa: a kPa
INDEX_DECIMALS = 6
RATIO_DECIMALS = 4
# The decimals of the block's keys (export.summary compares and writes them at these).
DECIMALS = {"pressure_mpa": PRESSURE_DECIMALS, "burst_pressure_netting_mpa": PRESSURE_DECIMALS,
            "first_ply_failure_pressure_mpa": PRESSURE_DECIMALS, "first_ply_failure_max_stress_mpa": PRESSURE_DECIMALS,
            "t": 3, "max_stress_t": 3, "burst_netting_t": 3, "tsai_wu_index": INDEX_DECIMALS,
            "max_stress_index": INDEX_DECIMALS, "safety_factor": INDEX_DECIMALS, "axial_force_n": 3,
            "torque_nmm": 3, "netting_optimum_angle_deg": 4, "first_ply_failure_ratio": RATIO_DECIMALS,
            "burst_ratio": RATIO_DECIMALS, "burst_ratio_required": RATIO_DECIMALS, "achieved": RATIO_DECIMALS,
            "required": RATIO_DECIMALS, "burst_pressure_required_mpa": PRESSURE_DECIMALS,
            "fiber_allowable_mpa": 1, "fiber_compression_allowable_mpa": 1, "ply_xt_over_vf_mpa": 1,
            "fiber_volume_fraction": 4, "fiber_stress_mpa": 1,
            "fiber_stress_at_burst_pressure_mpa": 1}
END_ZONES = ("outside the gauge section: the domes' turnaround bands and bosses, layer edges and step-backs, "
             "an open mandrel's trimmed ends")


def _round(value, decimals: int) -> float | None:
    value = float(value)
    return round(value, decimals) + 0.0 if math.isfinite(value) else None


def _least(values: np.ndarray, t: np.ndarray) -> tuple[float, float, int]:
    """(least value, its station, its index) over (n,) values (inf, nan, -1 when none is finite)."""
    if values.size == 0 or not np.any(np.isfinite(values)):
        return math.inf, math.nan, -1
    i = int(np.argmin(values))
    return float(values[i]), float(t[i]), i


def _figures(st, mask: np.ndarray) -> dict:
    """Netting burst and first-ply failure (Tsai-Wu, max stress), where and which layer, over the stations
    in mask."""
    t = st.geometry.t
    burst = np.where(mask & st.netting_applies, st.netting.burst, np.inf)
    b, b_t, bi = _least(burst, t)
    tw_all = np.where(mask[:, None], st.tsai_wu, np.inf)
    ms_all = np.where(mask[:, None], st.max_stress, np.inf)
    tw, tw_t, ti = _least(tw_all.min(axis=1), t)
    ms, ms_t, mi = _least(ms_all.min(axis=1), t)
    out = {"burst_pressure_netting_mpa": _round(b, PRESSURE_DECIMALS), "burst_netting_t": _round(b_t, 3),
           "first_ply_failure_pressure_mpa": _round(tw, PRESSURE_DECIMALS), "t": _round(tw_t, 3),
           "layer": int(st.layers[int(np.argmin(tw_all[ti]))]) if ti >= 0 else None,
           "first_ply_failure_max_stress_mpa": _round(ms, PRESSURE_DECIMALS), "max_stress_t": _round(ms_t, 3),
           "max_stress_layer": int(st.layers[int(np.argmin(ms_all[mi]))]) if mi >= 0 else None}
    if bi >= 0:
        k = int(st.netting.layer[bi])
        out["burst_netting_layer"] = int(st.layers[k]) if k >= 0 else None
        out["burst_netting_limit"] = ("uncarried" if k < 0 else
                                      ("compression" if st.netting.compression[bi] else "tension"))
        from winder.analysis.netting import GROUPS  # noqa: PLC0415

        out["burst_netting_wall"] = GROUPS[int(st.netting.group[bi])]
    return out


def _per_layer(st, mask: np.ndarray) -> list[dict]:
    t = st.geometry.t
    out = []
    for k, index in enumerate(st.layers):
        tw, tw_t, _ = _least(np.where(mask, st.tsai_wu[:, k], np.inf), t)
        ms, ms_t, _ = _least(np.where(mask, st.max_stress[:, k], np.inf), t)
        with np.errstate(all="ignore"):
            tw_i = np.nanmax(np.where(mask, st.tsai_wu_index[:, k], np.nan)) if np.any(mask) else math.nan
            ms_i = np.nanmax(np.where(mask, st.max_stress_index[:, k], np.nan)) if np.any(mask) else math.nan
        out.append({"layer": int(index), "first_ply_failure_pressure_mpa": _round(tw, PRESSURE_DECIMALS),
                    "t": _round(tw_t, 3), "first_ply_failure_max_stress_mpa": _round(ms, PRESSURE_DECIMALS),
                    "max_stress_t": _round(ms_t, 3), "tsai_wu_index": _round(tw_i, INDEX_DECIMALS),
                    "max_stress_index": _round(ms_i, INDEX_DECIMALS)})
    return out


def stress_ratios(structure, mask: np.ndarray, job) -> list[dict]:
    """Per fiber material: the achieved stress ratio (the fibers' allowable over their netting stress at the
    working pressure, the most loaded family of that material in the gauge) against the required; that
    family's fiber stress at the working pressure and, with analysis.burst_pressure, at the minimum burst."""
    st = structure.stations
    if structure.pressure <= 0.0:
        return []
    layer = st.netting.family_layer
    stress = st.netting.stress(structure.pressure)  # (n, F)
    out = []
    for name in dict.fromkeys(p.name for p in structure.plies):
        mine = np.array([structure.plies[k].name == name for k in layer])
        allow = np.array([structure.allowables[k].composite for k in layer])
        laid = (st.thickness[:, layer] > 0.0) & mine[None, :] & (mask & st.netting_applies)[:, None]
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.where(laid & (stress > 0.0), allow[None, :] / stress, np.inf)
        i, f = np.unravel_index(int(np.argmin(ratio)), ratio.shape) if ratio.size else (0, 0)
        achieved = float(ratio[i, f]) if ratio.size else math.inf
        required = job.analysis.required_ratio(name)
        burst = job.analysis.burst_pressure
        at_burst = (st.netting.stress(burst)[i, f] / structure.allowables[layer[f]].fraction
                    if burst is not None and math.isfinite(achieved) else math.nan)
        out.append({"material": name, "layers": [int(st.layers[k]) for k in sorted(set(layer[mine]))],
                    "fiber_stress_at_burst_pressure_mpa": _round(at_burst, 1),
                    "fiber_allowable_mpa": _round(structure.allowables[layer[f]].fiber, 1) if ratio.size else None,
                    "achieved": _round(achieved, RATIO_DECIMALS), "required": required,
                    "fiber_stress_mpa": _round(stress[i, f] / structure.allowables[layer[f]].fraction, 1)
                    if math.isfinite(achieved) else None,
                    "t": _round(st.geometry.t[i], 3) if math.isfinite(achieved) else None,
                    "pass": None if required is None else bool(achieved >= required)})
    return out


def _allowables(structure) -> list[dict]:
    return [{"layer": int(i), "material": p.name, "fiber_allowable_mpa": _round(a.fiber, 1),
             "fiber_compression_allowable_mpa": _round(a.fiber_compression, 1), "source": a.source,
             "ply_xt_over_vf_mpa": _round(a.ply_fiber, 1), "fiber_volume_fraction": _round(a.fraction, 4),
             "above_ply": a.above_ply}
            for i, p, a in zip(structure.stations.layers, structure.plies, structure.allowables)]


def summary_block(structure, job) -> dict:
    """The summary's `analysis` object (keys in DECIMALS' units; null where not finite)."""
    case = job.analysis
    out: dict = {"pressure_mpa": _round(case.pressure, PRESSURE_DECIMALS), "axial_force_n": _round(case.axial_force, 3),
                 "torque_nmm": _round(case.torque, 3), "ends": case.ends, "success": structure.success,
                 "message": structure.message}
    st = structure.stations
    if st is None:
        return out
    gauge = structure.in_gauge
    laid = st.thickness.sum(axis=1) > 0.0
    out.update(_figures(st, gauge))
    p = structure.pressure
    fpf = out["first_ply_failure_pressure_mpa"]
    burst = out["burst_pressure_netting_mpa"]
    out.update({
        "gauge": structure.gauge,
        "gauge_t_mm": [_round(x, 3) for x in structure.gauge_span] if structure.gauge != "all" else None,
        "netting_optimum_angle_deg": _round(structure.optimum_angle_deg, 4),
        "safety_factor": _round(fpf / p, INDEX_DECIMALS) if p > 0 and fpf is not None else None,
        "first_ply_failure_ratio": _round(fpf / p, RATIO_DECIMALS) if p > 0 and fpf is not None else None,
        "burst_ratio": _round(burst / p, RATIO_DECIMALS) if p > 0 and burst is not None else None,
        "layers": _per_layer(st, gauge),
        "netting_allowables": _allowables(structure),
        "stress_ratio": stress_ratios(structure, gauge, job),
        "notes": list(structure.notes),
    })
    if case.burst_pressure is not None:
        out["burst_pressure_required_mpa"] = _round(case.burst_pressure, PRESSURE_DECIMALS)
        out["burst_ratio_required"] = _round(case.burst_pressure / p, RATIO_DECIMALS) if p > 0 else None
        out["burst_pass"] = bool(burst is not None and burst >= case.burst_pressure)
    ends = laid & ~gauge
    out["end_zones"] = ({"label": END_ZONES, **_figures(st, ends)} if np.any(ends) else None)
    return out
