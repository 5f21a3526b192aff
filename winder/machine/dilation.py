"""The eye envelope's table kept a clearance's distance from the part between its samples.

winder.machine.envelope dilates the sampled profile r_max by a disc of radius c at its uniform
stations: the discs around the profile's vertices, read at the table's stations. Two gaps remain
where the profile or the envelope is steep (around a dome's polar opening, a boss's rim, the cap past
an end), and the collision check (winder.machine.collision: the distance from the meridian polyline)
measured an eye on the envelope up to ~50 um inside c:

- a polyline segment of length L lies up to L^2 / 8c closer to a point than its two vertices do (the
  profile sampled at 0.25 mm steps in t runs up to 8 mm per step where a dome meets its opening);
- the table is read linearly between its stations, and a chord of the dilated boundary (arcs of
  radius c) cuts into it by up to l^2 / 8c, l the chord's length (large where the envelope is steep).

Here the dilation of the polyline itself (its vertices' discs and its segments moved out by c along
their normals) is evaluated at the table's stations and at LIFT_FRACTIONS of each table segment; a
station lying below it is raised, and a segment whose chord passes below it is raised at both ends
by the deficit. The caller takes the concave majorant again.

The polyline's straight runs (a cylinder) keep only their ends: the band around a segment covers
the discs of its inner vertices, so the dilation is unchanged, and each query then reaches only the
vertices of its own window; queries are measured in groups of window widths padded to the next
power of two (a vertex past a query's window lies more than c beyond it in x, and so does the
segment starting there: the padding changes no maximum, and there are a few groups instead of
hundreds).
"""

from __future__ import annotations

import numpy as np

from winder.machine.reduce import reduce_points

LIFT_FRACTIONS = (0.25, 0.5, 0.75)  # where each table segment's chord is held against the dilation
LIFT_TOL = 1e-4  # mm: a deficit this small is far below the program's last decimal (1 um): left as it is
BLOCK = 1 << 20  # query-vertex pairs per block (memory stays bounded)
STRAIGHT_TOL = 1e-11  # mm: a vertex this close to its neighbours' chord is inside a straight run
SIMPLIFY_TOL = 1e-6  # mm: a long profile is simplified within this (Douglas-Peucker) before it is dilated
SIMPLIFY_FROM = 2000  # vertices: shorter profiles are dilated as they are


def turn(x: np.ndarray, z: np.ndarray, a, b, c):
    """(b - a) x (c - a) of the points (x, z) at indices a, b, c (ints or index arrays): < 0 where b
    lies above the chord a-c (x increasing), 0 on it; twice the triangle's signed area."""
    return (x[b] - x[a]) * (z[c] - z[a]) - (z[b] - z[a]) * (x[c] - x[a])


def without_straight_runs(t: np.ndarray, r: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The polyline (t, r) (k,) without the vertices inside its straight runs (a cylinder keeps its two
    ends). Each vertex dropped lies within STRAIGHT_TOL of its neighbours' chord (a profile bent less
    would have a radius of curvature of thousands of km)."""
    if t.size < 3:
        return t, r
    i = np.arange(t.size)
    cross = np.abs(turn(t, r, i[:-2], i[1:-1], i[2:]))
    keep = np.concatenate([[True], cross > STRAIGHT_TOL * np.hypot(t[2:] - t[:-2], r[2:] - r[:-2]), [True]])
    return t[keep], r[keep]


def polyline_dilation(xq: np.ndarray, t: np.ndarray, r: np.ndarray, c: float) -> np.ndarray:
    """The upper boundary of the polyline (t, r) (k,) dilated by a disc of radius c, at xq (m,);
    -inf where no part of the polyline lies within c in x."""
    xq = np.asarray(xq, dtype=float)
    out = np.full(xq.shape, -np.inf)
    t, r = without_straight_runs(np.asarray(t, dtype=float), np.asarray(r, dtype=float))
    if t.size == 0:
        return out
    if t.size > SIMPLIFY_FROM:
        # A laminate's profile is straight but for its bands' overlaps (1e-6 mm): no run is straight
        # to STRAIGHT_TOL and every query reached hundreds of vertices (6 s of a 3 m strut's 21). The
        # polyline within SIMPLIFY_TOL of it, dilated by c + SIMPLIFY_TOL, lies above the true dilation.
        keep = reduce_points(np.column_stack([t, r]), SIMPLIFY_TOL)
        t, r, c = t[keep], r[keep], c + SIMPLIFY_TOL
    lo = np.searchsorted(t, xq - c, side="left")
    need = np.searchsorted(t, xq + c, side="right") - lo + 2
    widths = np.left_shift(1, np.ceil(np.log2(need)).astype(np.int64))  # padded (module docstring)
    dt, dr = np.diff(t), np.diff(r)
    length = np.hypot(dt, dr)
    safe = np.where(length > 0.0, length, 1.0)
    nx, nz = -dr / safe, dt / safe  # the upward unit normal of each segment
    for width in np.flatnonzero(np.bincount(widths)).tolist():
        rows = np.flatnonzero(widths == width)
        for block in np.array_split(rows, max(1, rows.size * width // BLOCK)):
            out[block] = _reach(xq[block], lo[block], width, t, r, c, (length, nx, nz))
    return out


def _reach(xq: np.ndarray, lo: np.ndarray, width: int, t: np.ndarray, r: np.ndarray, c: float,
           normals: tuple[np.ndarray, np.ndarray, np.ndarray]) -> np.ndarray:
    """polyline_dilation at xq (m,) from the `width` vertices from lo - 1 on (and the segments
    starting at them); normals: each segment's length and upward unit normal (x, z)."""
    length, nx, nz = normals
    j = lo[:, None] - 1 + np.arange(width)  # vertices (and the segments starting at them) in reach
    valid = (j >= 0) & (j < t.size)
    jv = np.clip(j, 0, t.size - 1)
    dx = xq[:, None] - t[jv]
    rise = np.sqrt(np.maximum(c * c - dx * dx, 0.0))
    best = np.where(valid & (np.abs(dx) <= c), r[jv] + rise, -np.inf)
    if t.size >= 2:
        js = np.clip(j, 0, t.size - 2)
        x0 = t[js] + c * nx[js]
        x1 = t[js + 1] + c * nx[js]
        span = x1 - x0
        f = (xq[:, None] - x0) / np.where(span != 0.0, span, 1.0)
        on = valid & (j < t.size - 1) & (span > 0.0) & (f >= 0.0) & (f <= 1.0) & (length[js] > 0.0)
        seg = r[js] + c * nz[js] + f * (r[js + 1] - r[js])
        best = np.maximum(best, np.where(on, seg, -np.inf))
    return best.max(axis=1)


def lift_table(x: np.ndarray, z: np.ndarray, t: np.ndarray, r: np.ndarray, c: float) -> np.ndarray:
    """The envelope table z (k,) at stations x raised where it or its chords lie below the dilation
    of the polyline (t, r) by c (module docstring); z itself where nothing is."""
    exact = polyline_dilation(x, t, r, c)
    low = exact > z + LIFT_TOL
    out = np.where(low, exact, z) if low.any() else z.copy()
    if x.size < 2:
        return out
    deficit = np.zeros(x.size - 1)
    for f in LIFT_FRACTIONS:
        xm = x[:-1] + f * np.diff(x)
        chord = out[:-1] + f * (out[1:] - out[:-1])
        deficit = np.maximum(deficit, polyline_dilation(xm, t, r, c) - chord)
    deficit = np.where(deficit > LIFT_TOL, deficit, 0.0)
    if deficit.any():  # both ends of a segment raised by its deficit raise its whole chord by it
        out += np.maximum(np.append(deficit, 0.0), np.insert(deficit, 0, 0.0))
    return out
