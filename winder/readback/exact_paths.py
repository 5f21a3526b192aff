"""The fiber path `winder simulate` measures against: the geodesic ODE through the plan's points.

Between planned points i and i + 1 of a pass the fiber laid is the geodesic from point i in its planned
direction (docs/math/12-exact-eye.md), not the smooth path's Hermite interpolant, whose direction is up
to 0.15 deg off near a dome's turnaround (an eye 180 mm out: 0.45 mm off the fiber). ExactPaths is
SmoothPaths (winder.machine.smooth) with `point` read on that geodesic wherever it stands for the
interval: all intervals of a layer are one system of ODEs for scipy's solve_ivp (DOP853; each
interval's arc length scaled to [0, 1], so one step sequence serves all), read at GRID even nodes
per interval, then cubic Hermite in between from the states and their derivatives (the right-hand
side). This is an integration of its own, not the machine's (winder.machine.exact), so the program's
eye is checked against a separate reconstruction.

An interval is geodesic only where the ODE over its length lands on the planned point i + 1 within
ARRIVE_TOL and on its planned direction within ARRIVE_TURN (a friction-held path on a bend may land
within ARRIVE_TOL over a short interval, its direction 0.007 rad off): a friction-held path, a dwell's free fiber, a
turnaround held by the mandrel's end arrive elsewhere and keep the smooth path. So do, as a whole,
non-circular sections (flats and corners: the contact search, winder.readback.contacts, is tuned to the
smooth path there) and guides with joints (a line meeting an arc: the elbow).
"""

from __future__ import annotations

from functools import cached_property

import numpy as np

from winder.geometry.joints import joint_stations
from winder.geometry.measure import grid_groups, row_norms, tangent_coordinates
from winder.machine.exact import COPY_MM, COPY_TOL
from winder.machine.smooth import SmoothPaths
from winder.paths.ode import geodesic_rhs

GRID = 32  # even reads of each interval's geodesic (an interval a few per cent of a dome's radius)
RTOL, ATOL = 1e-10, 1e-10  # solve_ivp's tolerances over the scaled interval
ARRIVE_TOL = 1e-3  # mm: the ODE lands this close to the next planned point
ARRIVE_TURN = 1e-5  # rad: and this close to its planned direction (an eye 200 mm out: 0.002 mm): a geodesic
CHUNK = 65_536  # parameters read at once by point


class ExactPaths(SmoothPaths):
    """SmoothPaths whose points inside a geodesic interval lie on the exact geodesic (module docstring)."""

    @cached_property
    def _table(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None:
        """(use (n - 1,) bool: interval on the geodesic, row (n - 1,) int: its column of y (-1: none),
        y (4, m, GRID + 1) the states at the even reads, f the same shape: their derivatives in the
        scaled parameter, shift (n - 1,): theta of each interval less its column's), or None where no
        interval is."""
        from scipy.integrate import solve_ivp  # noqa: PLC0415

        count = self.s.size
        if count < 2 or not self.surface.section.is_circle:
            return None
        # Where the guide's curvature jumps (a line meeting an arc) (s', theta') of a smooth fiber jump
        # too, which the ODE in (s, theta) does not carry: such a mandrel keeps the smooth path.
        if joint_stations(self.surface).size:
            return None
        k = np.arange(count - 1)
        k = k[~self._is_last[k] & ~self.free[k] & ~self.free[k + 1]]
        length = self.arc[k + 1] - self.arc[k]
        ev = self.surface.evaluate(self.s[k], self.th[k], order=1)
        a, b = tangent_coordinates(ev.ps.T, ev.pt.T, self.d[k].T)
        speed = row_norms(ev.ps * a[:, None] + ev.pt * b[:, None])
        k, a, b, speed, length = (v[(speed > 0.0) & (length > 0.0)] for v in (k, a, b, speed, length))
        if not k.size:
            return None
        y0 = np.stack([self.s[k], self.th[k], a / speed, b / speed])
        # On a surface of revolution an interval's geodesic is its start's station, heading and length
        # turned about the axis: the rotated circuits of a layer share one integration (class inv).
        rep, inv = self._classes(y0, length)
        m = rep.size
        length_m = length[rep]
        surface = self.surface

        def rhs(_h: float, y: np.ndarray) -> np.ndarray:
            return (geodesic_rhs(surface, y.reshape(4, m)) * length_m).reshape(-1)

        grid = np.linspace(0.0, 1.0, GRID + 1)
        with np.errstate(all="ignore"):
            sol = solve_ivp(rhs, (0.0, 1.0), y0[:, rep].reshape(-1), method="DOP853", t_eval=grid,
                            rtol=RTOL, atol=ATOL)
        if not sol.success:
            return None
        y = sol.y.reshape(4, m, GRID + 1)
        f = (geodesic_rhs(surface, y.reshape(4, -1)) * np.repeat(length_m, GRID + 1)).reshape(y.shape)
        shift = np.zeros(count - 1)
        shift[k] = self.th[k] - y0[1, rep[inv]]
        end = y[:, inv, -1]
        end[1] += shift[k]
        arrive = row_norms(surface.points(end[0], end[1]) - surface.points(self.s[k + 1], self.th[k + 1]))
        ev = surface.evaluate(end[0], end[1], order=1)
        got = ev.ps * end[2][:, None] + ev.pt * end[3][:, None]
        want = self.d[k + 1]
        cos = np.einsum("ij,ij->i", got, want) / (row_norms(got) * row_norms(want))
        turn = np.arccos(np.clip(cos, -1.0, 1.0))
        use = np.zeros(count - 1, dtype=bool)
        use[k] = np.isfinite(arrive) & (arrive <= ARRIVE_TOL) & np.isfinite(turn) & (turn <= ARRIVE_TURN)
        row = np.full(count - 1, -1)
        row[k] = inv
        return use, row, y, f, shift

    def _classes(self, y0: np.ndarray, length: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(rep (m,): one interval of each class, inv (k,): each interval's class) of the intervals
        whose start states y0 (4, k) and lengths (k,) agree but for theta within the machine stage's
        COPY_MM and COPY_TOL (winder.machine.exact; a start heading 1e-12 apart is 1e-11 mm apart after
        10 mm, far inside RTOL); every interval its own class off a surface of revolution."""
        if not self.surface.is_revolution:
            return np.arange(length.size), np.arange(length.size)
        return grid_groups(np.column_stack([y0[0], y0[2], y0[3], length]),
                           np.array([COPY_MM, COPY_TOL, COPY_TOL, COPY_MM]))

    def point(self, u: np.ndarray):
        """(s, theta, p (n, 3), unit d (n, 3)) at global parameters u (n,): on the geodesic inside a
        geodesic interval, else SmoothPaths.point's; read CHUNK parameters at a time (the surface's
        evaluation holds tens of temporaries per point)."""
        u = np.asarray(u, dtype=float).reshape(-1)
        if u.size <= CHUNK:
            return self._point(u)
        parts = [self._point(u[i:i + CHUNK]) for i in range(0, u.size, CHUNK)]
        return tuple(np.concatenate([part[j] for part in parts]) for j in range(4))

    def _point(self, u: np.ndarray):
        table = self._table
        if table is None or u.size == 0:
            return super().point(u)
        use, row, y, f, shift = table
        k, h = self._interval(u)
        inside = use[k] & (h > 0.0) & (h < 1.0)
        on = np.flatnonzero(inside)
        if not on.size:
            return super().point(u)
        # The smooth path only where the geodesic does not stand for it (each is a surface evaluation).
        s, th, p, d = np.empty(u.size), np.empty(u.size), np.empty((u.size, 3)), np.empty((u.size, 3))
        off = np.flatnonzero(~inside)
        if off.size:
            s[off], th[off], p[off], d[off] = super().point(u[off])
        r = row[k[on]]
        x = h[on] * GRID
        j = np.minimum(np.floor(x).astype(int), GRID - 1)
        t = x - j
        step = 1.0 / GRID
        y0, y1, f0, f1 = y[:, r, j], y[:, r, j + 1], f[:, r, j] * step, f[:, r, j + 1] * step
        # Cubic Hermite of the state on a 1/GRID step (the interval's geodesic read 33 times).
        t2, t3 = t * t, t * t * t
        state = ((2 * t3 - 3 * t2 + 1) * y0 + (t3 - 2 * t2 + t) * f0
                 + (-2 * t3 + 3 * t2) * y1 + (t3 - t2) * f1)
        ev = self.surface.evaluate(state[0], state[1] + shift[k[on]], order=1)
        dd = ev.ps * state[2][:, None] + ev.pt * state[3][:, None]
        s[on], th[on], p[on] = state[0], state[1] + shift[k[on]], ev.p
        d[on] = dd / row_norms(dd)[:, None]
        return s, th, p, d
