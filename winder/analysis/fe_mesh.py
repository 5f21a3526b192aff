"""The shell model's mesh along the meridian and its plies (docs/math/09-structure.md 9.5): element rows
graded by how fast the wall's thickness changes, and each element's plies averaged over its area from
the laminate's cells (thickness, and the thickness-weighted angle).
"""

from __future__ import annotations

import math

import numpy as np

from winder.analysis.layup import LayerRows

GRADE = 0.1  # an element row spans at most this change of the wall's thickness over its local thickness
MAX_ROWS = 400  # element rows along the mandrel (at refine 1): past this the deck grows without a better answer
MIN_ROWS = 4
MIN_LENGTH_BANDS = 1.0 / 16.0  # the shortest row, in band widths: the laminate's own cells
SAMPLES_PER_CELL = 4  # integration points per laminate cell along the meridian
FLOOR = 0.25  # the thickness a gradient is measured against: at least this share of the wall's median


def extent(rows: tuple[LayerRows, ...]) -> tuple[float, float]:
    """(t0, t1): from the first laid cell's start to the last laid cell's end over all layers (a cell's edges
    midway to its neighbours)."""
    lo, hi = [], []
    for r in rows:
        laid = np.nonzero(r.thickness > 0.0)[0]
        if laid.size == 0:
            continue
        edges = np.concatenate([[1.5 * r.t[0] - 0.5 * r.t[1]], 0.5 * (r.t[1:] + r.t[:-1]),
                                [1.5 * r.t[-1] - 0.5 * r.t[-2]]]) if r.t.size > 1 else np.array([r.t[0]] * 2)
        lo.append(edges[laid[0]])
        hi.append(edges[laid[-1] + 1])
    return min(lo), max(hi)


def total_thickness(rows: tuple[LayerRows, ...], t: np.ndarray) -> np.ndarray:
    """The wall's thickness (mm) at stations t (n,): every layer's, at its cell there."""
    return np.sum([r.at(t)[1] for r in rows], axis=0)


def graded_stations(surface, rows: tuple[LayerRows, ...], s_a: float, s_b: float, band_width: float,
                    refine: float = 1.0) -> np.ndarray:
    """Element row boundaries s (m + 1,) on [s_a, s_b]: rows at most a band width / refine long, and at most
    GRADE h / |dh/ds| / refine where the thickness h (averaged over a band) changes fast (openings, layer
    ends, step-backs), never below MIN_LENGTH_BANDS band widths; equidistributed, so a symmetric wall
    gets a symmetric mesh."""
    step = MIN_LENGTH_BANDS * band_width / 2.0
    s = np.linspace(s_a, s_b, max(3, int(math.ceil((s_b - s_a) / step)) + 1))
    # a quarter step either side: no sample on a cell's edge, where the nearest cell is a tie
    h = 0.5 * sum(total_thickness(rows, surface.t_of_s(s + d)) for d in (-0.25 * step, 0.25 * step))
    window = 2 * int(round(0.5 * band_width / (s[1] - s[0]))) + 1  # odd: centred, so a symmetric wall stays so
    kernel = np.ones(window) / window
    smooth = np.convolve(np.pad(h, window // 2 + 1, mode="edge"), kernel, mode="same")[window // 2 + 1:-(window // 2 + 1)]
    laid = smooth[smooth > 0.0]
    floor = FLOOR * (float(np.median(laid)) if laid.size else 1.0)
    slope = np.abs(np.gradient(smooth, s))
    length = np.minimum(band_width, GRADE * np.maximum(smooth, floor) / np.maximum(slope, 1e-300)) / refine
    length = np.maximum(length, MIN_LENGTH_BANDS * band_width / refine)
    density = 1.0 / length
    cumulative = np.concatenate([[0.0], np.cumsum(0.5 * (density[1:] + density[:-1]) * np.diff(s))])
    total = cumulative[-1]
    unit = min(max(1.0, total / (MAX_ROWS * refine)), total / MIN_ROWS)  # a row a unit of density, within bounds
    half = float(np.interp(0.5 * (s_a + s_b), s, cumulative))
    # rows of one unit of the density from each end to the middle, the middle row taking what is left: an
    # end's rows depend on the wall between it and the middle only, so a part mirrored there is meshed alike
    # at both ends whatever differs elsewhere
    first = np.arange(0.0, half, unit)
    second = total - np.arange(0.0, total - half, unit)[::-1]
    if second[0] - first[-1] < 0.5 * unit:
        first = first[:-1]
    return np.interp(np.concatenate([first, second]), cumulative, s)


def _cell_edges(surface, rows: tuple[LayerRows, ...]) -> tuple[np.ndarray, float]:
    """The laminate cells' edges along the meridian (s, mm: where the station is midway between a layer's
    cells, as LayerRows.at parts them) and the shortest layer's median cell length (inf without cells)."""
    out, length = [], math.inf
    for r in rows:
        if r.t.size > 1:
            out.append(surface.s_of_t(0.5 * (r.t[1:] + r.t[:-1])))
            length = min(length, float(np.median(np.diff(surface.s_of_t(r.t)))))
    return (np.concatenate(out) if out else np.zeros(0)), length


def element_plies(surface, rows: tuple[LayerRows, ...], s_edges: np.ndarray, th_edges: np.ndarray,
                  samples_theta: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each element's plies averaged over its area: (slots (P,) layer indices, angle_deg (E, P), thickness
    (E, P)), elements row-major over s_edges (m + 1,) by th_edges (k + 1,). A helical layer is two slots
    (+a, t/2) and (-a, t/2), a hoop one (a, t); thickness the area mean of the layer's cells, angle the
    thickness-weighted mean. Along s the integrals are exact for the cells' piecewise constant thickness
    (the grid holds every cell edge and element edge, the area's trapezoids between, SAMPLES_PER_CELL
    intervals a cell at least); around, samples_theta midpoints an element."""
    m, k = s_edges.size - 1, th_edges.size - 1
    cells, spacing = _cell_edges(surface, rows)
    spacing = min(spacing, (s_edges[-1] - s_edges[0]) / 64.0)
    uniform = np.linspace(s_edges[0], s_edges[-1], int(math.ceil((s_edges[-1] - s_edges[0]) / spacing
                                                                 * SAMPLES_PER_CELL)) + 1)
    inside = cells[(cells > s_edges[0]) & (cells < s_edges[-1])]
    fine = np.unique(np.concatenate([uniform, s_edges, inside]))
    mid = 0.5 * (fine[1:] + fine[:-1])
    ut = (np.arange(samples_theta) + 0.5) / samples_theta
    tt = (th_edges[:-1, None] + np.diff(th_edges)[:, None] * ut[None, :]).ravel()  # (k Qt,)
    ev = surface.evaluate(np.repeat(fine, tt.size), np.tile(tt, fine.size), order=1)
    density = np.linalg.norm(np.cross(ev.ps, ev.pt), axis=1).reshape(fine.size, k, samples_theta)
    area = 0.5 * (density[1:] + density[:-1]) * np.diff(fine)[:, None, None]  # (intervals, k, Qt)
    station = np.repeat(surface.t_of_s(mid), tt.size)
    theta = np.tile(tt, mid.size)
    at = np.searchsorted(fine, s_edges)

    def per_element(values: np.ndarray) -> np.ndarray:  # (intervals, k) -> (m k,) sums over each element
        total = np.vstack([np.zeros((1, k)), np.cumsum(values, axis=0)])
        return np.diff(total[at], axis=0).ravel()

    whole = per_element(area.sum(axis=2))
    slots, angle, thick = [], [], []
    for r in rows:
        a, h = (x.reshape(mid.size, k, samples_theta) for x in r.at(station, theta))
        laid = per_element((area * h).sum(axis=2))
        with np.errstate(invalid="ignore", divide="ignore"):
            mean_a = np.where(laid > 0.0, per_element((area * h * a).sum(axis=2)) / laid, 0.0)
        for sign, share in (((1.0, 0.5), (-1.0, 0.5)) if r.helical else ((1.0, 1.0),)):
            slots.append(r.index)
            angle.append(sign * mean_a)
            thick.append(np.round(share * laid / whole, 6))
    return np.array(slots), np.column_stack(angle), np.column_stack(thick)
