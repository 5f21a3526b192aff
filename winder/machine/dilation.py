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
"""

from __future__ import annotations

import numpy as np

LIFT_FRACTIONS = (0.25, 0.5, 0.75)  # where each table segment's chord is held against the dilation
LIFT_TOL = 1e-4  # mm: a deficit this small is far below the program's last decimal (1 um): left as it is
BLOCK = 1 << 20  # query-vertex pairs per block (memory stays bounded)


def polyline_dilation(xq: np.ndarray, t: np.ndarray, r: np.ndarray, c: float) -> np.ndarray:
    """The upper boundary of the polyline (t, r) (k,) dilated by a disc of radius c, at xq (m,);
    -inf where no part of the polyline lies within c in x."""
    xq = np.asarray(xq, dtype=float)
    out = np.full(xq.shape, -np.inf)
    if t.size == 0:
        return out
    lo = np.searchsorted(t, xq - c, side="left")
    hi = np.searchsorted(t, xq + c, side="right")
    width = int(np.max(hi - lo + 2)) if xq.size else 0
    rows = max(1, BLOCK // max(width, 1))
    dt, dr = np.diff(t), np.diff(r)
    length = np.hypot(dt, dr)
    safe = np.where(length > 0.0, length, 1.0)
    nx, nz = -dr / safe, dt / safe  # the upward unit normal of each segment
    for a in range(0, xq.size, rows):
        b = min(a + rows, xq.size)
        j = lo[a:b, None] - 1 + np.arange(width)  # vertices (and the segments starting at them) in reach
        valid = (j >= 0) & (j < t.size)
        jv = np.clip(j, 0, t.size - 1)
        dx = xq[a:b, None] - t[jv]
        rise = np.sqrt(np.maximum(c * c - dx * dx, 0.0))
        best = np.where(valid & (np.abs(dx) <= c), r[jv] + rise, -np.inf)
        js = np.clip(j, 0, max(t.size - 2, 0))
        if t.size >= 2:
            x0 = t[js] + c * nx[js]
            x1 = t[js + 1] + c * nx[js]
            span = x1 - x0
            f = (xq[a:b, None] - x0) / np.where(span != 0.0, span, 1.0)
            on = valid & (j < t.size - 1) & (span > 0.0) & (f >= 0.0) & (f <= 1.0) & (length[js] > 0.0)
            seg = r[js] + c * nz[js] + f * (r[js + 1] - r[js])
            best = np.maximum(best, np.where(on, seg, -np.inf))
        out[a:b] = best.max(axis=1)
    return out


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
