"""Whether a bent mandrel comes back onto itself: a part of it inside another, far along the axis.

find_fold (winder.geometry.surface) refuses a section reaching the centre of curvature, which keeps
nearby sections apart; it cannot see a guide curve that returns: a U-turn whose legs are closer than
the tube is thick, a spline that doubles back on itself (a cusp), a loop. The solid mandrel near a
station is, to within the station spacing, the slice of its normal plane inside the section's outline
R(s, theta), thickened along the axis to its neighbours' planes (and not past the mandrel's ends). So
each station's centre and outline are tested against the slices of the stations farther than NEAR
along the axis (nearer ones are the fold check's): a point strictly inside one is a contact. Where the
axis closes on itself (its ends one point with one tangent: a ring, as a full-circle bend is), the
stations near one end are the other end's neighbours. Stations whose centres are farther apart than
their largest radii's sum are not compared, so a clear mandrel costs a distance per pair of stations.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from winder.geometry.surface import SweepSurface

MAX_STATIONS = 2000  # stations compared pairwise (their centres' distances: 2 M pairs at most)
STATION_SPACING = 0.5  # of the smallest section radius: a crossing cannot pass between stations
SECTION_ANGLES = 36  # points of each section's outline tested
NEAR = 2.0  # stations nearer than this many largest radii along the axis: the fold check's
INSIDE = 1.0 - 1e-3  # a point this far inside the outline (of its radius there) is inside, not touching
SLICE_OVERLAP = 1.05  # neighbouring slices overlap a little: no point of the solid between them
CLOSED = 1e-6  # ends this close (of the smallest radius; their tangents' cosine within it of 1): a ring


class Contact(NamedTuple):
    """A point of the mandrel at station t1 (mm) inside its slice at station t2: the point's distance
    from the axis there and the section's radius in its direction (mm)."""

    t1: float
    t2: float
    distance: float
    radius: float


def find_self_contact(surface: SweepSurface) -> Contact | None:
    """The deepest contact between far-apart parts of the mandrel, or None (also for a straight guide
    line, which cannot come back)."""
    if surface.curve.max_curvature() == 0.0:
        return None
    th = np.linspace(0.0, 2.0 * np.pi, SECTION_ANGLES, endpoint=False)
    coarse = np.linspace(0.0, surface.length, 65)
    r_min = float(surface.radius(np.repeat(coarse, th.size), np.tile(th, coarse.size)).min())
    count = int(min(MAX_STATIONS, max(65, np.ceil(surface.length / (STATION_SPACING * max(r_min, 1e-9))) + 1)))
    s = np.linspace(0.0, surface.length, count)
    outline = surface.points(np.repeat(s, th.size), np.tile(th, count)).reshape(count, th.size, 3)
    radii = surface.radius(np.repeat(s, th.size), np.tile(th, count)).reshape(count, th.size)
    r_out = radii.max(axis=1)
    z = surface.t_of_s(s)
    axis = surface.curve.evaluate(z)
    centre = np.ascontiguousarray(axis.x)
    closed = (float(np.linalg.norm(centre[-1] - centre[0])) <= CLOSED * r_min
              and float(axis.d1[0] @ axis.d1[-1]) >= 1.0 - CLOSED)
    tested = np.concatenate([centre[:, None, :], outline], axis=1)  # (count, 1 + angles, 3)
    spacing = float(s[1] - s[0]) if count > 1 else surface.length
    # half the slice's thickness: the planes fan out on a bend's outside (1 + R kappa)
    half = 0.5 * spacing * (1.0 + r_out * np.linalg.norm(axis.d2, axis=1)) * SLICE_OVERLAP
    back = half if closed else np.minimum(half, z - z[0])  # not past the mandrel's ends
    ahead = half if closed else np.minimum(half, z[-1] - z)
    near = NEAR * float(r_out.max())
    best: Contact | None = None
    for i in range(count):  # a row of pairs at a time: memory O(count angles), not O(count^2)
        far = np.abs(z - z[i]) > near
        if closed and (z[i] < near or z[i] > z[-1] - near):  # a ring: the other end is nearby
            far &= (z >= near) & (z <= z[-1] - near)
        j = np.flatnonzero(far)
        if not j.size:
            continue
        j = j[np.linalg.norm(centre[j] - centre[i], axis=1) < r_out[i] + r_out[j]]
        if not j.size:
            continue
        rel = tested[i][None, :, :] - centre[j][:, None, :]  # (k, points, 3)
        along = np.einsum("kpc,kc->kp", rel, axis.d1[j])
        x, y = np.einsum("kpc,kc->kp", rel, axis.e2[j]), np.einsum("kpc,kc->kp", rel, axis.e3[j])
        reach = surface.radius(np.repeat(s[j], rel.shape[1]), np.arctan2(y, x).ravel()).reshape(x.shape)
        depth = np.hypot(x, y) / reach
        slab = (along >= -back[j][:, None]) & (along <= ahead[j][:, None])
        depth = np.where(slab, depth, np.inf)
        k, q = np.unravel_index(int(np.argmin(depth)), depth.shape)
        if depth[k, q] < INSIDE and (best is None or depth[k, q] < best.distance / best.radius):
            best = Contact(float(z[i]), float(z[j[k]]), float(np.hypot(x[k, q], y[k, q])), float(reach[k, q]))
    return best
