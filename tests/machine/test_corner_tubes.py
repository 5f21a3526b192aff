"""Straight tubes of rounded-rectangle section with tight corners at steep helical angles (issue 41):
the program's move midpoints against the fiber, re-measured here without the program's own machinery.

On such a tube the eye is tied while the contact runs along a flat (the flat's tangent rays are one
line) and sweeps the whole corner while the contact rounds it, within a small part of a planned
interval: moves over a corner bow far from the eye's path, and the mend (winder.machine.mend) must cut
them where the eye travels. The truth: on the straight part of the tube the fiber is a geodesic of
a developable surface, a straight line in the unrolled (perimeter, axial) plane; its contacts and
tangents are computed here from the section's own geometry (four flats and four quarter circles) and
the planned points, and each move's midpoint eye (the written rows' axes interpolated linearly, by the
machine's forward kinematics) is measured against the tangent rays of every contact between the move's
two (least_distance: exactly over the flats, sampled and at the tangent planes through the eye over
the corners).
"""

from __future__ import annotations

import numpy as np
import pytest

from winder.config.job import parse_config
from winder.machine.invariants import mended_and_proved
from winder.machine.exact import exact_points
from winder.machine.program import build_program
from winder.machine.smooth import SmoothPaths
from winder.winding.plan import plan
from winder.winding.results import PassKind

TOL = 0.05  # machine.chord_tolerance's default
ARC_SAMPLES = 257  # contacts sampled over a corner within a move's range

# (width, height, corner radius, helical angle, eye clearance): corners 5 to 20 mm, 150 to 300 mm
# wide, 45 to 75 deg, clearance 20 to 60 mm; the second is issue 41's generated tube_6.
TUBES = [
    (150.0, 90.0, 5.0, 45.0, 20.0),
    (214.0, 111.5, 7.5, 70.5, 40.0),
    (300.0, 160.0, 20.0, 75.0, 60.0),
    (250.0, 120.0, 10.0, 60.0, 30.0),
    (180.0, 140.0, 15.0, 68.0, 50.0),
    (260.0, 100.0, 6.0, 73.0, 55.0),
]


class Section:
    """A rounded rectangle (width along x, height along y, centred): its perimeter coordinate sigma
    (counter-clockwise from (W/2, -b)), the point and unit tangent at sigma, sigma of a point on it."""

    def __init__(self, width: float, height: float, r: float) -> None:
        self.a, self.b, self.r = width / 2 - r, height / 2 - r, r
        q = np.pi * r / 2
        # pieces in order: right flat, arc (a, b), top flat, arc (-a, b), left flat, arc (-a, -b), bottom, arc (a, -b)
        self.lengths = np.array([2 * self.b, q, 2 * self.a, q, 2 * self.b, q, 2 * self.a, q])
        self.starts = np.concatenate([[0.0], np.cumsum(self.lengths)[:-1]])
        self.perimeter = float(self.lengths.sum())

    def at(self, sigma: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        a, b, r = self.a, self.b, self.r
        s = np.mod(sigma, self.perimeter)
        k = np.clip(np.searchsorted(self.starts, s, side="right") - 1, 0, 7)
        t = s - self.starts[k]
        p, d = np.zeros((s.size, 2)), np.zeros((s.size, 2))
        flats = {0: ((a + r, -b), (0, 1)), 2: ((a, b + r), (-1, 0)), 4: ((-a - r, b), (0, -1)), 6: ((-a, -b - r), (1, 0))}
        for piece, (start, tangent) in flats.items():
            m = k == piece
            p[m] = np.asarray(start) + t[m, None] * np.asarray(tangent, dtype=float)
            d[m] = tangent
        arcs = {1: ((a, b), 0.0), 3: ((-a, b), np.pi / 2), 5: ((-a, -b), np.pi), 7: ((a, -b), 1.5 * np.pi)}
        for piece, (centre, phi0) in arcs.items():
            m = k == piece
            phi = phi0 + t[m] / r
            p[m] = np.asarray(centre) + r * np.column_stack([np.cos(phi), np.sin(phi)])
            d[m] = np.column_stack([-np.sin(phi), np.cos(phi)])
        return p, d

    def sigma(self, xy: np.ndarray) -> np.ndarray:
        a, b, r = self.a, self.b, self.r
        x, y = xy[:, 0], xy[:, 1]
        out = np.empty(x.size)
        for i, (xi, yi) in enumerate(zip(x, y)):
            if abs(yi) <= b and xi > 0:
                out[i] = yi + b
            elif abs(xi) <= a and yi > 0:
                out[i] = self.starts[2] + (a - xi)
            elif abs(yi) <= b:
                out[i] = self.starts[4] + (b - yi)
            elif abs(xi) <= a:
                out[i] = self.starts[6] + (xi + a)
            else:
                cx, cy = np.sign(xi) * a, np.sign(yi) * b
                piece, phi0 = {(1, 1): (1, 0.0), (-1, 1): (3, np.pi / 2), (-1, -1): (5, np.pi),
                               (1, -1): (7, 1.5 * np.pi)}[(int(np.sign(xi)), int(np.sign(yi)))]
                phi = np.mod(np.arctan2(yi - cy, xi - cx) - phi0, 2 * np.pi)
                phi = phi if phi < np.pi else phi - 2 * np.pi
                out[i] = self.starts[piece] + r * phi
        return np.mod(out, self.perimeter)


def tube_job(width, height, r, angle, clearance, length=500.0):
    return parse_config({
        "name": "corner_tube",
        "mandrel": {"axis": {"type": "line", "length": length},
                    "section": {"type": "rounded_rectangle", "width": width, "height": height, "corner_radius": r}},
        "winding": {"band_width": 13.5, "friction": 0.29, "points": 30,
                    "layers": [{"type": "helical", "angle": angle, "slip": "auto"}]},
        "machine": {"eye": {"clearance": clearance}},
    }, "corner_tube.yaml")


def unrolled(sec: Section, fp) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(sigma (n,) unwrapped along the pass, x (n,), geodesic (n - 1,) bool): the planned points in
    the unrolled plane, and which intervals lie on one straight line with both neighbours (the
    geodesic of the straight part, not a turnaround)."""
    pts = np.asarray(fp.points, dtype=float)
    s = sec.sigma(pts[:, :2])
    _, tangent = sec.at(s)
    sense = np.sign(np.einsum("ij,ij->i", np.asarray(fp.direction)[:, :2], tangent))
    step = np.mod(np.diff(s), sec.perimeter)
    step = np.where(sense[:-1] > 0, step, step - sec.perimeter)  # the way the pass winds
    sigma = np.concatenate([[s[0]], s[0] + np.cumsum(step)])
    x = pts[:, 2]
    seg = np.column_stack([np.diff(sigma), np.diff(x)])
    unit = seg / np.linalg.norm(seg, axis=1)[:, None]
    same = np.abs(unit[1:, 0] * unit[:-1, 1] - unit[1:, 1] * unit[:-1, 0]) < 1e-6
    straight = np.ones(seg.shape[0], dtype=bool)
    straight[1:] &= same
    straight[:-1] &= same
    # and the plan's own tangents at both ends are the line's (a turnaround's are not)
    _, d0 = contacts(sec, sigma, x, np.arange(seg.shape[0], dtype=float))
    _, d1 = contacts(sec, sigma, x, np.arange(1, seg.shape[0] + 1, dtype=float) - 1e-12)
    direction = np.asarray(fp.direction, dtype=float)
    straight &= np.linalg.norm(d0 - direction[:-1], axis=1) < 1e-6
    straight &= np.linalg.norm(d1 - direction[1:], axis=1) < 1e-6
    return sigma, x, straight


def ray_distance(e, p, d):
    w = e - p
    along = np.maximum(np.einsum("ij,ij->i", w, d), 0.0)
    return np.linalg.norm(w - along[:, None] * d, axis=1)


def contacts(sec, sigma, x, u):
    """Contact points and unit tangents (k, 3) at fractional planned indices u on the unrolled lines."""
    i = np.clip(np.floor(u).astype(int), 0, sigma.size - 2)
    f = u - i
    s = sigma[i] + f * (sigma[i + 1] - sigma[i])
    xa = x[i] + f * (x[i + 1] - x[i])
    p2, t2 = sec.at(s)
    ds, dx = sigma[i + 1] - sigma[i], x[i + 1] - x[i]
    d = np.column_stack([t2 * ds[:, None], dx])
    return np.column_stack([p2, xa]), d / np.linalg.norm(d, axis=1)[:, None]


def least_distances(sec, sigma, x, e, t0, t1):
    """The least distance (m,) of the eyes e (m, 3) from the rays of the contacts t in [t0, t1] (m,)
    (the line's parameter: the planned point index, linear in the perimeter and axial coordinates).

    Each range is cut where the contact passes from a flat to a corner. Over a flat the rays lie on one
    line, and the distance (to the line where the eye is ahead of the contact, else to the contact) is
    least at an end of the piece. Over a corner the rays turn fast: ARC_SAMPLES samples, and the
    contacts whose tangent plane holds the eye (h = (e - p) . n changes sign; the least distance is a
    notch there far narrower than any grid) by bisection."""
    idx = np.arange(sigma.size, dtype=float)
    order = np.argsort(sigma)
    lo_t, hi_t = np.minimum(t0, t1), np.maximum(t0, t1)
    s_a, s_b = np.interp(lo_t, idx, sigma), np.interp(hi_t, idx, sigma)
    s_lo, s_hi = np.minimum(s_a, s_b), np.maximum(s_a, s_b)
    turns = np.arange(np.floor(s_lo.min() / sec.perimeter), np.floor(s_hi.max() / sec.perimeter) + 1)
    breaks = np.sort((turns[:, None] * sec.perimeter + sec.starts[None, :]).ravel())
    t_breaks = np.interp(breaks, sigma[order], idx[order])
    owner, a_t, b_t = [], [], []
    for k in range(e.shape[0]):
        inner = t_breaks[(breaks > s_lo[k]) & (breaks < s_hi[k])]
        ends = np.unique(np.concatenate([[lo_t[k], hi_t[k]], inner]))
        owner += [k] * (ends.size - 1)
        a_t.append(ends[:-1])
        b_t.append(ends[1:])
    owner, a_t, b_t = np.array(owner), np.concatenate(a_t), np.concatenate(b_t)

    def dist_h(who, t):
        p, d = contacts(sec, sigma, x, t)
        _, tangent = sec.at(np.interp(t, idx, sigma))
        normal = np.column_stack([tangent[:, 1], -tangent[:, 0], np.zeros(t.size)])  # outward (counter-clockwise)
        return ray_distance(e[who], p, d), np.einsum("ij,ij->i", e[who] - p, normal)

    best = np.full(e.shape[0], np.inf)
    np.minimum.at(best, owner, np.minimum(dist_h(owner, a_t)[0], dist_h(owner, b_t)[0]))
    middle = np.mod(np.interp(0.5 * (a_t + b_t), idx, sigma), sec.perimeter)
    arc = (np.searchsorted(sec.starts, middle, side="right") - 1) % 2 == 1
    who, a, b = owner[arc], a_t[arc], b_t[arc]
    if who.size:
        t = a[:, None] + np.linspace(0.0, 1.0, ARC_SAMPLES)[None, :] * (b - a)[:, None]
        rows = np.repeat(who, ARC_SAMPLES)
        dist, h = (v.reshape(t.shape) for v in dist_h(rows, t.ravel()))
        np.minimum.at(best, who, dist.min(axis=1))
        i, j = np.nonzero(np.signbit(h[:, :-1]) != np.signbit(h[:, 1:]))
        ta, tb, ha, root_of = t[i, j], t[i, j + 1], h[i, j], who[i]
        for _ in range(50):
            tm = 0.5 * (ta + tb)
            hm = dist_h(root_of, tm)[1]
            left = np.signbit(hm) == np.signbit(ha)
            ta, ha, tb = np.where(left, tm, ta), np.where(left, hm, ha), np.where(left, tb, tm)
        np.minimum.at(best, root_of, dist_h(root_of, 0.5 * (ta + tb))[0])
    return best


@pytest.mark.parametrize("width, height, r, angle, clearance", TUBES,
                         ids=[f"w{t[0]:g}_r{t[2]:g}_a{t[3]:g}_c{t[4]:g}" for t in TUBES])
def test_corner_tube_moves_keep_the_fiber(width, height, r, angle, clearance):
    job = tube_job(width, height, r, angle, clearance)
    done = plan(job)
    program, found = mended_and_proved(done, job, build_program(done, job.machine))  # refuses a straying move
    assert found.max_midpoint_deviation_mm <= TOL and found.max_point_deviation_mm <= TOL
    sec = Section(width, height, r)
    values = np.round(program.values, 3)  # as written (AXIS_DECIMALS)
    checked, corner_moves, worst = 0, 0, 0.0
    for layer, segments in zip(done.layers, program.segments):
        paths = SmoothPaths(done.surface_of(layer.index), list(layer.passes))
        for number, (fp, seg) in enumerate(zip(layer.passes, segments)):
            if seg.stop - seg.start < 2:
                continue
            if fp.kind not in (PassKind.FORWARD, PassKind.RETURN):
                continue  # a turnaround at an end: no unrolled line
            sigma, x, straight = unrolled(sec, fp)
            # the whole pass one geodesic, the plan's tangents the unrolled line's
            assert straight.all()
            rows = np.arange(seg.start + seg.approach, seg.stop)
            # each row's contact: the line's point at the axial station of the plan's contact (the
            # program's index is the plan's parameter, not the line's); x runs linearly along the line
            _, _, at, _ = exact_points(paths, paths.offset[number] + program.index[rows])
            order = np.argsort(x)
            t = np.interp(at[:, 2], x[order], np.arange(x.size, dtype=float)[order])
            moves = rows[1:]
            half = 0.5 * (values[moves - 1] + values[moves])
            a = -np.radians(half[:, 1])
            eyes = np.column_stack([half[:, 2] * np.cos(a), half[:, 2] * np.sin(a), half[:, 0]])
            dist = least_distances(sec, sigma, x, eyes, t[:-1], t[1:])
            worst = max(worst, float(dist.max()))
            checked += moves.size
            # moves whose contacts round a corner: their ends' tangents differ
            _, tan0 = sec.at(np.interp(t[:-1], np.arange(x.size), sigma))
            _, tan1 = sec.at(np.interp(t[1:], np.arange(x.size), sigma))
            corner_moves += int(np.count_nonzero(np.einsum("ij,ij->i", tan0, tan1) < 1.0 - 1e-9))
    assert checked > 200 and corner_moves > 50, (checked, corner_moves)
    assert worst <= TOL + 1e-6, worst
