"""The layup at its stations (SPEC.md "Laminate", `--format layup`): where each layer's rows are, and each
layer's angle and thickness at any station, nearest row. The layup CSV, the station analysis and the
shell model all read the laminate through here, so they see the same plies.
"""

from __future__ import annotations

import dataclasses

import numpy as np

LAYUP_STEP_BANDS = 0.5  # station spacing, in band widths


def station_rows(s: np.ndarray, thickness: np.ndarray, band_width: float) -> np.ndarray:
    """Indices of a layer's laminate cells the layup writes: every LAYUP_STEP_BANDS band widths, only
    where it lays fiber. s, thickness : (k,) the layer's cells (LayerLaminate.s, .thickness)."""
    step = max(1, int(round(LAYUP_STEP_BANDS * band_width / max(np.median(np.diff(s)), 1e-12))))
    pick = np.arange(0, s.size, step)
    return pick[thickness[pick] > 0.0]


@dataclasses.dataclass(frozen=True)
class LayerRows:
    """One layer's layup rows along the mandrel (a surface of revolution: the same all around).

    index : the layer (1-based); helical : a +-angle pair (else one hoop ply). t, angle_deg,
    thickness : (m,) at its rows, as the CSV writes them (angle in [0, 90])."""

    index: int
    helical: bool
    t: np.ndarray
    angle_deg: np.ndarray
    thickness: np.ndarray

    def at(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(angle_deg, thickness) of the row nearest each station t (n,); thickness 0 (angle 0) past the
        layer's rows by more than half their spacing."""
        t = np.asarray(t, float)
        if self.t.size == 0:
            return np.zeros_like(t), np.zeros_like(t)
        half = 0.5 * (float(np.median(np.diff(self.t))) if self.t.size > 1 else 0.0)
        if self.t.size == 1:
            j = np.zeros(t.shape, dtype=int)
        else:
            j = np.clip(np.searchsorted(self.t, t), 1, self.t.size - 1)
            j = np.where(t - self.t[j - 1] <= self.t[j] - t, j - 1, j)
        inside = (t >= self.t[0] - half - 1e-9) & (t <= self.t[-1] + half + 1e-9)
        return np.where(inside, self.angle_deg[j], 0.0), np.where(inside, self.thickness[j], 0.0)


def layer_rows(plan) -> tuple[LayerRows, ...]:
    """Every layer's rows of a plan with a laminate (layers without one are left out), rounded as the CSV
    writes them (6 decimals) so that what a model reads back is what the file says."""
    out = []
    for layer in plan.layers:
        lam = layer.laminate
        if lam is None:
            continue
        pick = station_rows(lam.s, lam.thickness, plan.band_width)
        out.append(LayerRows(layer.index, layer.type.value == "helical", np.round(lam.t[pick], 6),
                             np.round(np.nan_to_num(lam.angle_deg[pick]), 6), np.round(lam.thickness[pick], 6)))
    return tuple(out)
