"""The shell finite-element model of a wound part (docs/math/09-structure.md 9.5): the mandrel surface
(the laminate's inner face) meshed with 8-node shells, each element's plies from the layup rows at its
centre, each ply's fiber direction, the pressure, the closed ends' thrust and the supports. Plain arrays;
winder.export.abaqus writes them as an Abaqus / CalculiX deck.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from winder.analysis.layup import LayerRows
from winder.errors import ExportError

NTHETA = 48  # elements around: a multiple of the layup's 24 angles and of 4 (the supports 90 deg apart)
MAX_ROWS = 200  # element rows along the mandrel: past this the deck grows without a better answer
MIN_ROWS = 4


@dataclasses.dataclass(frozen=True)
class ShellModel:
    """nodes : (N, 3) mm. elements : (E, 8) 0-based node indices, S8R order (corners counterclockwise seen
    from outside, then the mid-sides 1-2, 2-3, 3-4, 4-1), normals outward. t, theta : (E,) each element's
    centre (mm, rad). ply_layer : (P,) the layer (1-based) of each ply slot, inner first; ply_angle_deg,
    ply_thickness : (E, P) (thickness 0: the slot is empty there). fiber, across : (E, P, 3) each ply's fiber
    direction and the in-plane normal to it. loads : (N, 3) nodal forces (the ends' thrust, axial force
    and torque). fixed_axial : node indices held along the axis (the start ring); fixed_x, fixed_y : the
    start ring's nodes at 90 and 270 deg held in x, at 0 and 180 deg in y (their tangents): no rigid-body
    motion left, and what the twist of an unbalanced wall puts on them is a couple, not a side force
    that would bend the tube (two nodes alone bent it 0.06 mm at mid-length under 10 MPa).
    rings : (2, K) the corner nodes of the two rings nearest mid-length (what the tests read back),
    ring_t : (2,) their stations."""

    nodes: np.ndarray
    elements: np.ndarray
    t: np.ndarray
    theta: np.ndarray
    ply_layer: np.ndarray
    ply_angle_deg: np.ndarray
    ply_thickness: np.ndarray
    fiber: np.ndarray
    across: np.ndarray
    loads: np.ndarray
    fixed_axial: np.ndarray
    fixed_x: np.ndarray
    fixed_y: np.ndarray
    rings: np.ndarray
    ring_t: np.ndarray


def _extent(rows: tuple[LayerRows, ...]) -> tuple[float, float]:
    lo, hi = [], []
    for r in rows:
        half = 0.5 * float(np.median(np.diff(r.t))) if r.t.size > 1 else 0.0
        lo.append(r.t[0] - half)
        hi.append(r.t[-1] + half)
    return min(lo), max(hi)


def build_model(surface, rows: tuple[LayerRows, ...], band_width: float, pressure: float, closed: bool,
                axial_force: float = 0.0, torque: float = 0.0) -> ShellModel:
    """The shell model of the laminate the rows describe, on `surface` (the bare mandrel)."""
    t_a, t_b = _extent(rows)
    t_a, t_b = max(t_a, 0.0), min(t_b, surface.axial_length)
    s_a, s_b = (float(x) for x in surface.s_of_t(np.array([t_a, t_b])))
    n_s = int(min(MAX_ROWS, max(MIN_ROWS, math.ceil((s_b - s_a) / band_width))))
    s = np.linspace(s_a, s_b, 2 * n_s + 1)  # corner and mid-side stations
    th = np.arange(2 * NTHETA) * math.pi / NTHETA
    grid = surface.grid_points(s, th).reshape(s.size, th.size, 3)
    # node numbers on the (2 n_s + 1) x (2 NTHETA) grid, the element centres (odd, odd) left out
    used = ~((np.arange(s.size)[:, None] % 2 == 1) & (np.arange(th.size)[None, :] % 2 == 1))
    number = np.full(used.shape, -1)
    number[used] = np.arange(int(used.sum()))
    nodes = grid[used]
    i, j = np.meshgrid(2 * np.arange(n_s), 2 * np.arange(NTHETA), indexing="ij")
    i, j = i.ravel(), j.ravel()
    jp = (j + 2) % th.size
    elements = np.stack([number[i, j], number[i, jp], number[i + 2, jp], number[i + 2, j], number[i, j + 1],
                         number[i + 1, jp], number[i + 2, j + 1], number[i + 1, j]], axis=1)
    s_c, th_c = s[i + 1], th[j + 1]
    t_c = surface.t_of_s(s_c)
    # plies: per layer slot(s) inner first, the values of the nearest layup row
    slots, angle, thick = [], [], []
    for r in rows:
        a, h = r.at(t_c, th_c)
        for sign, share in (((1.0, 0.5), (-1.0, 0.5)) if r.helical else ((1.0, 1.0),)):
            slots.append(r.index)
            angle.append(sign * a)
            thick.append(share * h)
    ply_angle, ply_t = np.column_stack(angle), np.column_stack(thick)
    empty = ply_t.sum(axis=1) <= 0.0
    if np.any(empty):
        k = int(np.argmax(empty))
        raise ExportError(f"the shell model has no ply at t = {t_c[k]:.3f} mm (between the layers' rows)")
    ev = surface.evaluate(s_c, th_c, order=1)
    e_m = ev.ps / np.linalg.norm(ev.ps, axis=1)[:, None]
    e_h = ev.pt - np.einsum("ij,ij->i", ev.pt, e_m)[:, None] * e_m
    e_h /= np.linalg.norm(e_h, axis=1)[:, None]
    rad = np.radians(ply_angle)[..., None]
    fiber = np.cos(rad) * e_m[:, None, :] + np.sin(rad) * e_h[:, None, :]
    across = -np.sin(rad) * e_m[:, None, :] + np.cos(rad) * e_h[:, None, :]
    loads = np.zeros_like(nodes)
    for end, row in ((-1.0, 0), (1.0, s.size - 1)):
        _ring_loads(loads, number[row], grid[row], surface, s[row], end, pressure, closed, axial_force, torque)
    start = number[0][number[0] >= 0]
    mid = n_s // 2 * 2
    rings = np.stack([number[mid][::2], number[mid + 2][::2]])
    return ShellModel(nodes, elements, t_c, th_c, np.array(slots), ply_angle, ply_t, fiber, across, loads,
                      start, number[0, [NTHETA // 2, 3 * NTHETA // 2]], number[0, [0, NTHETA]], rings,
                      surface.t_of_s(np.array([s[mid], s[mid + 2]])))


def _ring_loads(loads: np.ndarray, ids: np.ndarray, ring: np.ndarray, surface, s_end: float, end: float,
                pressure: float, closed: bool, axial_force: float, torque: float) -> None:
    """Add an end ring's nodal forces: the pressure's thrust on the area the ring encloses (closed ends)
    plus the axial force along the outward axis, and the torque (+ about the axis at the far end),
    spread per unit length along the ring's S8R edges (1/6, 2/3, 1/6 of each edge's share)."""
    # the axis there: the normal of the ring's plane (a section of the sweep), pointing away from the part
    # (the meridian's tangent is no axis on a dome: near a polar opening it runs almost radially)
    centre = ring.mean(axis=0)
    axis = np.linalg.svd(ring - centre, full_matrices=False)[2][-1]
    along = surface.evaluate(np.full(ring.shape[0], s_end), np.arange(ring.shape[0]) * 2.0 * np.pi / ring.shape[0],
                             order=1).ps.mean(axis=0)
    axis = axis * end * np.sign(axis @ along)
    arm = ring - centre - np.outer((ring - centre) @ axis, axis)
    xy = np.stack([arm @ _perp(axis)[0], arm @ _perp(axis)[1]], axis=1)
    area = 0.5 * abs(np.sum(xy[:, 0] * np.roll(xy[:, 1], -1) - np.roll(xy[:, 0], -1) * xy[:, 1]))
    n = ring.shape[0]
    corner = np.arange(0, n, 2)
    edge = np.linalg.norm(ring[(corner + 2) % n] - ring[corner], axis=1)
    perimeter = edge.sum()
    weight = np.zeros(n)
    np.add.at(weight, corner, edge / 6.0)
    np.add.at(weight, (corner + 2) % n, edge / 6.0)
    np.add.at(weight, corner + 1, 2.0 * edge / 3.0)
    thrust = (pressure * area if closed else 0.0) + axial_force
    loads[ids] += np.outer(weight * thrust / perimeter, axis)
    if torque:
        r2 = np.einsum("ij,ij->i", arm, arm)
        # + torque about +axis at the far end (axis = +e1 there), its reaction at the start (axis = -e1)
        loads[ids] += weight[:, None] * torque / np.sum(weight * r2) * np.cross(axis, arm)


def _perp(axis: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors normal to axis and to each other."""
    helper = np.array([1.0, 0.0, 0.0]) if abs(axis[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    u = np.cross(axis, helper)
    u /= np.linalg.norm(u)
    return u, np.cross(axis, u)
