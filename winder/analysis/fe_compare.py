"""The FE answer beside the CLT's (docs/math/09-structure.md 9.9): per layer along the meridian, the fiber
stress and Tsai-Wu index CalculiX gives (winder.analysis.fe_results) and the station analysis' at the same
stations; the summary's `fe` block.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from winder.analysis.gauge import in_span

STRESS_DECIMALS = 2  # MPa
INDEX_DECIMALS = 5


@dataclasses.dataclass(frozen=True, kw_only=True)
class LayerAlong:
    """One layer along the meridian (m element stations): FE and CLT fiber stress (MPa; the larger of a
    helical layer's two plies) and Tsai-Wu index (nan where the layer is absent)."""

    layer: int
    fe_stress: np.ndarray
    clt_stress: np.ndarray
    fe_index: np.ndarray
    clt_index: np.ndarray


@dataclasses.dataclass(frozen=True, kw_only=True)
class Comparison:
    """t (m,) the element stations; layers; in_gauge (m,); the elements and ccx's run (s)."""

    t: np.ndarray
    layers: tuple[LayerAlong, ...]
    in_gauge: np.ndarray
    elements: int
    rows: int
    ntheta: int
    refine: float
    seconds: float


def nearest(stations: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Index of the station nearest each t (stations sorted)."""
    k = np.clip(np.searchsorted(stations, t), 1, max(stations.size - 1, 1))
    return np.where(np.abs(stations[k - 1] - t) <= np.abs(stations[k] - t), k - 1, k)


def compare(results, structure, model, refine: float, seconds: float) -> Comparison:
    """The FE meridian results beside the station analysis (structure.stations) at the same stations; where
    there is none (a bent or non-circular tube: no membrane closed form), the FE alone (CLT values nan)."""
    from winder.analysis.failure import tsai_wu_index  # noqa: PLC0415

    st = structure.stations
    layers = []
    for layer in sorted(set(int(k) for k in results.ply_layer)):
        clt_stress = clt_index = np.full(results.t.size, np.nan)
        if st is not None:
            pos = int(np.nonzero(st.layers == layer)[0][0])
            k = nearest(st.geometry.t, results.t)
            clt_s = st.ply_stress[k][:, st.ply_layer == pos]
            present = st.thickness[k, pos] > 0.0
            ply = structure.plies[pos]
            strengths = (ply.Xt, ply.Xc, ply.Yt, ply.Yc, ply.S)
            clt_stress = np.where(present, clt_s[..., 0].max(axis=1), np.nan)
            clt_index = np.where(present, tsai_wu_index(clt_s, strengths).max(axis=1), np.nan)
        layers.append(LayerAlong(layer=layer, fe_stress=results.by_layer(results.stress[..., 0], layer),
                                 clt_stress=clt_stress, fe_index=results.by_layer(results.tsai_wu, layer),
                                 clt_index=clt_index))
    return Comparison(t=results.t, layers=tuple(layers), in_gauge=in_span(results.t, structure.gauge_span),
                      elements=int(model.elements.shape[0]), rows=int(model.meridian.size), ntheta=model.ntheta,
                      refine=refine, seconds=seconds)


def _list(values: np.ndarray, decimals: int) -> list:
    return [round(float(v), decimals) + 0.0 if math.isfinite(v) else None for v in values]


def _peak(values: np.ndarray, t: np.ndarray, mask: np.ndarray) -> tuple[float | None, float | None]:
    v = np.where(mask & np.isfinite(values), values, -np.inf)
    if not np.any(np.isfinite(v)):
        return None, None
    i = int(np.argmax(v))
    return float(v[i]), float(t[i])


def fe_block(cmp: Comparison) -> dict:
    """The summary's `fe` object: the model, and per layer its largest fiber stress and Tsai-Wu index in the
    gauge and overall (FE and CLT), with the values along the meridian."""
    out = {"solver": "CalculiX ccx", "elements": cmp.elements, "meridian_elements": cmp.rows, "around": cmp.ntheta,
           "refine": cmp.refine, "t_mm": _list(cmp.t, 3), "layers": []}
    for lay in cmp.layers:
        entry = {"layer": lay.layer, "fiber_stress_mpa": _list(lay.fe_stress, STRESS_DECIMALS),
                 "clt_fiber_stress_mpa": _list(lay.clt_stress, STRESS_DECIMALS),
                 "tsai_wu_index": _list(lay.fe_index, INDEX_DECIMALS),
                 "clt_tsai_wu_index": _list(lay.clt_index, INDEX_DECIMALS)}
        for where, mask in (("gauge", cmp.in_gauge), ("all", np.ones_like(cmp.in_gauge))):
            for key, values in (("max_fiber_stress_mpa", lay.fe_stress), ("clt_max_fiber_stress_mpa", lay.clt_stress),
                                ("max_tsai_wu_index", lay.fe_index), ("clt_max_tsai_wu_index", lay.clt_index)):
                peak, at = _peak(values, cmp.t, mask)
                entry[f"{where}_{key}"] = None if peak is None else round(peak, STRESS_DECIMALS if "stress" in key
                                                                           else INDEX_DECIMALS) + 0.0
                if key == "max_fiber_stress_mpa":
                    entry[f"{where}_max_fiber_stress_t"] = None if at is None else round(at, 3) + 0.0
        out["layers"].append(entry)
    return out
