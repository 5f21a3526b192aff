"""The shell finite-element model of a wound part (docs/math/09-structure.md 9.5): the mandrel surface
(the laminate's inner face) meshed with 8-node shells, element rows graded where the wall's thickness
changes fast, each element's plies averaged over its area from the laminate's cells, each ply's fiber
direction, the pressure, the closed ends' thrust and the supports. Plain arrays; winder.export.abaqus
writes them as an Abaqus / CalculiX deck.

The ply frame: e_m the unit meridian (increasing t), e_h the unit parallel (increasing theta: right-handed
about the axis' direction of increasing t), the outward normal e_h x e_m. A ply at +a has its fiber
cos a e_m + sin a e_h (a right-handed helix); `across` is -sin a e_m + cos a e_h, the CLT's direction 2
(docs/math 9.3). CalculiX rebuilds its local y as normal x fiber = -across, so its shear comes back with
the sign of the CLT's turned over (winder.analysis.fe_results turns it back).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from winder.analysis.fe_mesh import element_plies, extent, graded_stations
from winder.analysis.layup import LayerRows
from winder.errors import ExportError

NTHETA = 48  # elements around: a multiple of the layup's 24 angles and of 4 (the supports 90 deg apart)
SAMPLES_THETA = 2  # area samples per element around (a surface of revolution's plies do not change there)


@dataclasses.dataclass(frozen=True, kw_only=True)
class ShellModel:
    """nodes : (N, 3) mm. elements : (E, 8) 0-based node indices, S8R order (corners counterclockwise seen
    from outside, then the mid-sides 1-2, 2-3, 3-4, 4-1), normals outward. t, theta : (E,) each element's
    centre (mm, rad). ply_layer : (P,) the layer (1-based) of each ply slot, inner first; ply_angle_deg,
    ply_thickness : (E, P) (thickness 0: the slot is empty there). fiber, across : (E, P, 3) each ply's fiber
    direction and the in-plane normal to it. loads : (N, 3) nodal forces (the ends' thrust, axial force
    and torque). fixed_axial : node indices held along the axis (the ring nearest mid-length, where
    the ends' loads have spread out, on a surface of revolution; the start ring otherwise); fixed_x, fixed_y : that ring's nodes at 90 and 270 deg held in x, at 0
    and 180 deg in y (their tangents): no rigid-body
    motion left, and what the twist of an unbalanced wall puts on them is a couple, not a side force
    that would bend the tube (two nodes alone bent it 0.06 mm at mid-length under 10 MPa).
    rings : (2, K) the corner nodes of the two rings nearest mid-length (what the tests read back),
    ring_t : (2,) their stations. meridian : (m,) the elements of the first column around (theta from 0),
    in order along the mandrel: what `winder analyze` reads back. pressed : (E,) the elements the pressure
    acts on (all but a boss's flange zones). rigid : per boss (its laminate nodes, its reference node, its
    rotation node), the two extra nodes at the end of `nodes`, loads on them its thrust and torque (a
    rigid body's rotation node carries moments as forces). ntheta : elements around."""

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
    meridian: np.ndarray
    pressed: np.ndarray
    rigid: tuple[tuple[np.ndarray, int, int], ...] = ()
    ntheta: int = NTHETA


def build_model(surface, rows: tuple[LayerRows, ...], band_width: float, pressure: float, closed: bool,
                axial_force: float = 0.0, torque: float = 0.0, refine: float = 1.0, ntheta: int = NTHETA,
                bosses: bool = False) -> ShellModel:
    """The shell model of the laminate the rows (every cell: layer_rows(plan, every_cell=True)) describe, on
    `surface` (the bare mandrel); refine scales the element rows' density (2: the mesh doubled along the
    meridian), ntheta the elements around (a multiple of 4); bosses: a vessel's polar bosses, whose flanges
    take the pressure on the laminate's first band width at each opening and bear on it (9.5)."""
    t_a, t_b = extent(rows)
    t_a, t_b = max(t_a, 0.0), min(t_b, surface.axial_length)
    s_a, s_b = (float(x) for x in surface.s_of_t(np.array([t_a, t_b])))
    edges = graded_stations(surface, rows, s_a, s_b, band_width, refine)
    n_s = edges.size - 1
    s = np.empty(2 * n_s + 1)
    s[::2], s[1::2] = edges, 0.5 * (edges[:-1] + edges[1:])  # corner and mid-side stations
    th = np.arange(2 * ntheta) * math.pi / ntheta
    grid = surface.grid_points(s, th).reshape(s.size, th.size, 3)
    # node numbers on the (2 n_s + 1) x (2 ntheta) grid, the element centres (odd, odd) left out
    used = ~((np.arange(s.size)[:, None] % 2 == 1) & (np.arange(th.size)[None, :] % 2 == 1))
    number = np.full(used.shape, -1)
    number[used] = np.arange(int(used.sum()))
    nodes = grid[used]
    i, j = np.meshgrid(2 * np.arange(n_s), 2 * np.arange(ntheta), indexing="ij")
    i, j = i.ravel(), j.ravel()
    jp = (j + 2) % th.size
    elements = np.stack([number[i, j], number[i, jp], number[i + 2, jp], number[i + 2, j], number[i, j + 1],
                         number[i + 1, jp], number[i + 2, j + 1], number[i + 1, j]], axis=1)
    s_c, th_c = s[i + 1], th[j + 1]
    t_c = surface.t_of_s(s_c)
    samples = SAMPLES_THETA if surface.is_revolution else 4
    slots, ply_angle, ply_t = element_plies(surface, rows, edges, np.append(th[::2], 2.0 * math.pi), samples)
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
    area = np.linalg.norm(np.cross(ev.ps, ev.pt), axis=1) * (s[i + 2] - s[i]) * (th[2] - th[0])
    ends = _Ends(surface=surface, grid=grid, s=s, th=th, elements=elements, area=area, band_width=band_width,
                 ntheta=ntheta)
    nodes, loads, pressed, rigid = ends.load(nodes, pressure, closed, axial_force, torque, bosses)
    middle = 0.5 * (s[0] + s[-1])
    mid = int(np.argmin(np.abs(s[::2][:-1] - middle))) * 2
    rings = np.stack([number[mid][::2], number[mid + 2][::2]])
    q = ntheta // 2
    # the supports: on a straight axis the ring nearest mid-length, far from the ends' loads; on a bent or
    # non-circular tube the start ring, whose plane is normal to the global z they hold (the path's start)
    held = number[mid] if surface.is_revolution else number[0]
    return ShellModel(nodes=nodes, elements=elements, t=t_c, theta=th_c, ply_layer=slots, ply_angle_deg=ply_angle,
                      ply_thickness=ply_t, fiber=fiber, across=across, loads=loads, fixed_axial=held[held >= 0],
                      fixed_x=held[[q, 3 * q]], fixed_y=held[[0, 2 * q]], rings=rings,
                      ring_t=surface.t_of_s(np.array([s[mid], s[mid + 2]])), meridian=np.arange(n_s) * ntheta,
                      pressed=pressed, rigid=rigid, ntheta=ntheta)


@dataclasses.dataclass(frozen=True, kw_only=True)
class _Ends:
    """What the ends' loads need of a mesh: the surface, the node grid (stations s x angles th, 3), the
    elements and their areas, the band width and the elements around."""

    surface: object
    grid: np.ndarray
    s: np.ndarray
    th: np.ndarray
    elements: np.ndarray
    area: np.ndarray
    band_width: float
    ntheta: int

    def load(self, nodes: np.ndarray, pressure: float, closed: bool, axial_force: float, torque: float,
             bosses: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray, tuple]:
        """(nodes with a boss's two extra nodes each, nodal loads, the pressed elements, the rigid bosses)."""
        n_s = self.elements.shape[0] // self.ntheta
        edges = self.s[::2]
        # each end's zone: the element rows whose centres lie within a band width of it (at least one; the
        # same count at both ends, so that a mirrored part is loaded alike)
        count = max(1, int(np.count_nonzero(edges[:-1] + 0.5 * np.diff(edges) <= edges[0] + self.band_width)))
        row_of = np.repeat(np.arange(n_s), self.ntheta)
        loads = np.zeros_like(nodes)
        pressed = np.ones(self.elements.shape[0], bool)
        rigid, extra = [], []
        for end, row, zone in ((-1.0, 0, row_of < count), (1.0, self.s.size - 1, row_of >= n_s - count)):
            along = self.surface.evaluate(np.full(self.th.size, self.s[row]), self.th, order=1).ps.mean(axis=0)
            centre, axis = _end_axis(self.grid[row], along, end)
            if not bosses:
                thrust = (pressure * _enclosed(self.grid[row], axis) if closed else 0.0) + axial_force
                _traction(loads, nodes, self.elements, zone, self.area, centre, axis, thrust, torque)
                continue
            # a boss: rigid, the laminate over its flange (the zone) bonded to it, the pressure inside the
            # flange's rim (the zone's far ring) its own, pushing it out along the axis
            rim = self.grid[row - int(end) * 2 * count]
            pressed &= ~zone
            ref = nodes.shape[0] + len(extra)
            extra += [centre, centre]
            rigid.append((np.unique(self.elements[zone]), ref, ref + 1))
            loads = np.vstack([loads, axis * (pressure * _enclosed(rim, axis) + axial_force), axis * torque])
        return (np.vstack([nodes, np.array(extra)]) if extra else nodes), loads, pressed, tuple(rigid)


def _end_axis(ring: np.ndarray, along: np.ndarray, end: float) -> tuple[np.ndarray, np.ndarray]:
    """(centre, axis) of an end ring: the normal of its plane (a section of the sweep) pointing away from
    the part (the meridian's tangent is no axis on a dome: near a polar opening it runs almost radially)."""
    centre = ring.mean(axis=0)
    axis = np.linalg.svd(ring - centre, full_matrices=False)[2][-1]
    return centre, axis * end * np.sign(axis @ along)


def _enclosed(ring: np.ndarray, axis: np.ndarray) -> float:
    """The area (mm^2) a ring of points encloses, projected along the axis."""
    u, v = _perp(axis)
    rel = ring - ring.mean(axis=0)
    x, y = rel @ u, rel @ v
    return 0.5 * abs(float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)))


def _traction(loads: np.ndarray, nodes: np.ndarray, elements: np.ndarray, zone: np.ndarray, area: np.ndarray,
              centre: np.ndarray, axis: np.ndarray, thrust: float, torque: float) -> None:
    """Add an end's thrust (N, along the outward axis) and torque (N mm, + about the axis at the far end) as
    a uniform traction over the zone's elements (an end fitting bearing on the laminate's first band width):
    each element's consistent nodal shares of its area, -1/12 at the corners and 1/3 at the mid-sides."""
    weight = np.zeros(nodes.shape[0])
    np.add.at(weight, elements[zone, :4].ravel(), np.repeat(-area[zone] / 12.0, 4))
    np.add.at(weight, elements[zone, 4:].ravel(), np.repeat(area[zone] / 3.0, 4))
    weight /= weight.sum()
    loads += np.outer(weight * thrust, axis)
    if torque:
        arm = nodes - centre - np.outer((nodes - centre) @ axis, axis)
        r2 = np.einsum("ij,ij->i", arm, arm)
        # its reaction at the start: there the axis points the other way
        loads += weight[:, None] * torque / np.sum(weight * r2) * np.cross(axis, arm)


def _perp(axis: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors normal to axis and to each other."""
    helper = np.array([1.0, 0.0, 0.0]) if abs(axis[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    u = np.cross(axis, helper)
    u /= np.linalg.norm(u)
    return u, np.cross(axis, u)
