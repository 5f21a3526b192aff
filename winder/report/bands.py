"""Bands on the unrolled surface, where the coverage map counts them.

The unrolled plane is (t, u): t the axial station (mm), u the arc-length position around the section,
as a fraction of the perimeter from theta = 0 (turns; the figures show 360 u, "degrees of arc", which
is theta itself on a circle). The section is scaled uniformly along the mandrel, so u of a polar angle
is the same at every station and a band keeps its place when the mandrel narrows.

A pass crosses the station t once (it is monotone in t); its band, B wide across the fiber, covers
B / sin(beta) of the perimeter there, beta the angle between the fiber and the section curve, centred on
the crossing (docs/math/05-winding.md, the definition winder.coverage measures). The crossing and the fiber direction
come from winder.winding.coverage.crossings_many, the same crossings the summary's coverage counts.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from winder.geometry.sections import ArcMap
from winder.geometry.surface import SweepSurface
from winder.winding.coverage import crossings_many
from winder.winding.results import FiberPass, PassKind


@dataclasses.dataclass(frozen=True, eq=False)
class Crossings:
    """Where a group of passes crosses a set of stations (rows).

    row : (m,) int, the station index of each crossing.
    centre : (m,) float, u of the crossing, in [0, 1) (turns).
    half : (m,) float, the band's half-width along the perimeter there (turns).
    """

    row: np.ndarray
    centre: np.ndarray
    half: np.ndarray

    def rows_hit(self, n_rows: int) -> np.ndarray:
        """(n_rows,) bool: the stations this group crosses at all (where it is laid)."""
        return np.bincount(self.row, minlength=n_rows) > 0


def coverage_groups(passes: tuple[FiberPass, ...]) -> list[list[FiberPass]]:
    """The passes that must each cover the perimeter once: the forward passes, the return passes, and
    every hoop traverse on its own (a +-alpha layer is even where each direction covers once)."""
    groups = [[p for p in passes if p.kind is kind] for kind in (PassKind.FORWARD, PassKind.RETURN)]
    groups += [[p] for p in passes if p.kind is PassKind.HOOP]
    return [g for g in groups if g]


def crossings(surface: SweepSurface, arcs: ArcMap, passes: list[FiberPass], rows: np.ndarray,
              band_width: float) -> Crossings:
    """The crossings of the passes with the stations rows ((n,) float, mm), as coverage finds them."""
    row, frac, half = crossings_many(surface, arcs, passes, rows, band_width)
    return Crossings(row, np.mod(frac, 1.0), half)


def _arcs(c: Crossings) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The bands as stretches [lo, hi) of [0, 1) per row; a stretch past 1 is split in two."""
    width = np.minimum(2.0 * c.half, 1.0)
    lo = np.mod(c.centre - 0.5 * width, 1.0)
    hi = lo + width
    over = hi > 1.0
    return (np.concatenate([c.row, c.row[over]]), np.concatenate([lo, np.zeros(int(over.sum()))]),
            np.concatenate([np.minimum(hi, 1.0), hi[over] - 1.0]))


def covered_fraction(c: Crossings, n_rows: int) -> np.ndarray:
    """(n_rows,) float: the fraction of each row's perimeter under at least one band (exact union)."""
    row, lo, hi = _arcs(c)
    if row.size == 0:
        return np.zeros(n_rows)
    # Rows are set 2 apart on one line, so a running maximum never carries from one row to the next.
    lo, hi = lo + 2.0 * row, hi + 2.0 * row
    order = np.lexsort((lo, row))
    row, lo, hi = row[order], lo[order], hi[order]
    reach = np.concatenate([[-np.inf], np.maximum.accumulate(hi)[:-1]])
    new = np.maximum(hi - np.maximum(lo, reach), 0.0)
    return np.minimum(np.bincount(row, weights=new, minlength=n_rows), 1.0)


def band_counts(c: Crossings, n_rows: int, n_cols: int) -> np.ndarray:
    """(n_rows, n_cols) int: bands over each cell centre u = (j + 1/2) / n_cols of each row."""
    row, lo, hi = _arcs(c)
    first = np.ceil(lo * n_cols - 0.5).astype(int)
    stop = np.ceil(hi * n_cols - 0.5).astype(int)
    steps = np.zeros((n_rows, n_cols + 1), dtype=np.int32)
    np.add.at(steps, (row, np.clip(first, 0, n_cols)), 1)
    np.add.at(steps, (row, np.clip(stop, 0, n_cols)), -1)
    return np.cumsum(steps, axis=1)[:, :n_cols]
