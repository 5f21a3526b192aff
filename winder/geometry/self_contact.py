"""Whether a bent mandrel comes back onto itself: a part of it inside another, far along the axis.

find_fold (winder.geometry.surface) refuses a section reaching the centre of curvature, which keeps
nearby sections apart; it cannot see a guide curve that returns: a U-turn whose legs are closer than
the tube is thick, a spline that doubles back on itself (a cusp), a loop. Where the fold check holds,
the ball of a section's smallest radius about its centre lies inside the solid mandrel, and no point
of the mandrel's surface or axis lies strictly inside it unless the mandrel meets itself there. So
each station's centre and its section's outline are tested against the balls of the stations
farther than NEAR along the axis (nearer ones are the fold check's): a point inside one is a contact;
but where the axis closes on itself (its ends one point with one tangent: a ring, as a full-circle
bend is), the stations near one end are the other end's neighbours, not far from them.
Stations closer than their largest radii's sum are the only candidates, so a clear mandrel costs a
distance per pair of stations.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from winder.geometry.surface import SweepSurface

MAX_STATIONS = 2000  # stations compared pairwise (their centres' distances: 2 M pairs at most)
STATION_SPACING = 0.5  # of the smallest section radius: a crossing cannot pass between stations
SECTION_ANGLES = 36  # points of each section's outline tested
NEAR = 2.0  # stations nearer than this many largest radii along the axis: the fold check's
INSIDE = 1.0 - 1e-3  # a point this far inside a ball (of its radius) is inside, not touching
CLOSED = 1e-6  # ends this close (of the smallest radius; their tangents' cosine within it of 1): a ring


class Contact(NamedTuple):
    """A point of the section at station t1 (mm) inside the ball of the section at t2: its distance
    from that section's centre and the ball's radius (mm)."""

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
    r_in, r_out = radii.min(axis=1), radii.max(axis=1)
    z = surface.t_of_s(s)
    axis = surface.curve.evaluate(z)
    centre = np.ascontiguousarray(axis.x)
    closed = (float(np.linalg.norm(centre[-1] - centre[0])) <= CLOSED * r_min
              and float(axis.d1[0] @ axis.d1[-1]) >= 1.0 - CLOSED)
    tested = np.concatenate([centre[:, None, :], outline], axis=1)  # (count, 1 + angles, 3)
    near = NEAR * float(r_out.max())
    best: Contact | None = None
    for i in range(count):  # a row of pairs at a time: memory O(count angles), not O(count^2)
        far = np.abs(z - z[i]) > near
        if closed and (z[i] < near or z[i] > z[-1] - near):  # a ring: the other end is nearby
            far &= (z >= near) & (z <= z[-1] - near)
        j = np.flatnonzero(far)
        if not j.size:
            continue
        j = j[np.linalg.norm(centre[j] - centre[i], axis=1) < r_out[i] + r_in[j]]
        if not j.size:
            continue
        gap = np.linalg.norm(tested[i][None, :, :] - centre[j][:, None, :], axis=2).min(axis=1)
        depth = gap / r_in[j]
        k = int(np.argmin(depth))
        if depth[k] < INSIDE and (best is None or depth[k] < best.distance / best.radius):
            best = Contact(float(z[i]), float(z[j[k]]), float(gap[k]), float(r_in[j[k]]))
    return best
