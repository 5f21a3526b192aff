"""The layup at its stations (docs/math/08-laminate-edges.md, `--format layup`): where each layer's rows are, and each
layer's angle and thickness at any station, nearest row. The layup CSV, the station analysis and the
shell model all read the laminate through here, so they see the same plies.
"""

from __future__ import annotations

import dataclasses

import numpy as np

LAYUP_STEP_BANDS = 0.5  # station spacing, in band widths
LAYUP_ANGLES = 24  # rows around each station, 15 deg apart


def station_rows(s: np.ndarray, thickness: np.ndarray, band_width: float, every_cell: bool = False) -> np.ndarray:
    """Indices of a layer's laminate cells the layup writes: every LAYUP_STEP_BANDS band widths over the span
    where it lays fiber, placed symmetrically about that span's middle (so the two ends of a mirrored part
    are sampled alike), only cells where it lays fiber; with every_cell each cell, empty ones included (the
    shell model's). s, thickness : (k,) the layer's cells (LayerLaminate.s, .thickness)."""
    if every_cell:  # the empty cells too: each laid cell then keeps its own edges
        return np.arange(s.size)
    laid = np.nonzero(thickness > 0.0)[0]
    if laid.size == 0:
        return laid
    step = max(1, int(round(LAYUP_STEP_BANDS * band_width / max(np.median(np.diff(s)), 1e-12))))
    lo, hi = int(laid[0]), int(laid[-1])
    middle = 0.5 * (lo + hi)
    offsets = np.arange(0.0, 0.5 * (hi - lo) + 1.0, step)
    pick = np.unique(np.concatenate([np.floor(middle + offsets), np.ceil(middle - offsets)]).astype(int))
    pick = pick[(pick >= lo) & (pick <= hi)]
    return pick[thickness[pick] > 0.0]


@dataclasses.dataclass(frozen=True)
class LayerRows:
    """One layer's layup rows along the mandrel.

    index : the layer (1-based); helical : a +-angle pair (else one hoop ply). t, angle_deg,
    thickness : (m,) at its rows, the section's mean (angle in [0, 90]). share : (m, LAYUP_ANGLES) the
    thickness around the section over its mean (1 on surfaces of revolution; buildup.share_around)."""

    index: int
    helical: bool
    t: np.ndarray
    angle_deg: np.ndarray
    thickness: np.ndarray
    share: np.ndarray | None = None

    def at(self, t: np.ndarray, theta: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """(angle_deg, thickness) of the row nearest each station t (n,) (and angle theta (n,) rad, the
        nearest of the LAYUP_ANGLES around), as the CSV writes them (6 decimals); thickness 0 (angle 0)
        past the layer's rows by more than half their spacing."""
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
        thick = self.thickness[j]
        if self.share is not None and theta is not None:
            around = np.rint(np.mod(theta, 2.0 * np.pi) / (2.0 * np.pi) * LAYUP_ANGLES).astype(int) % LAYUP_ANGLES
            thick = np.round(thick * self.share[j, around], 6)
        return np.where(inside, np.round(self.angle_deg[j], 6), 0.0), np.where(inside, np.round(thick, 6), 0.0)


def layer_rows(plan, every_cell: bool = False) -> tuple[LayerRows, ...]:
    """Every layer's rows of a plan with a laminate (layers without one are left out): the layup CSV's, or
    with every_cell each laminate cell (what the shell model averages over its elements)."""
    from winder.winding.buildup import share_around  # noqa: PLC0415 - bends and non-circular sections only

    out = []
    theta = np.arange(LAYUP_ANGLES) * 2.0 * np.pi / LAYUP_ANGLES
    for layer in plan.layers:
        lam = layer.laminate
        if lam is None:
            continue
        pick = station_rows(lam.s, lam.thickness, plan.band_width, every_cell)
        surface = plan.surface_of(layer.index)
        share = None if surface.is_revolution else share_around(surface, layer.passes, plan.band_width,
                                                                 lam.s[pick], theta)
        out.append(LayerRows(layer.index, layer.type.value == "helical", np.round(lam.t[pick], 6),
                             np.nan_to_num(lam.angle_deg[pick]), lam.thickness[pick], share))
    return tuple(out)
