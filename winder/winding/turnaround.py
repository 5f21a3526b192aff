"""Turnarounds at the ends of an open mandrel: the fiber laid while the carriage reverses and the
mandrel keeps turning (docs/math/06-machine.md 6.4).

A pass ends at the end of the winding region at heading h (from the meridian toward +theta; every
plan turns the mandrel toward +theta, so 0 < h < 180). Past the region the fiber runs on into the
mandrel's end zone held by friction, lambda = k_g / k_n = TURN_SLIP_SHARE * mu turning it toward the
parallel (docs/math/07-friction.md; on a cylinder sin(alpha(z)) = sin(alpha0) / (1 - lambda z sin(alpha0) / R)):
- where it reaches the parallel (heading 90 deg) before the mandrel ends, it has turned around within
  friction: the way back is the mirror image of the way in (the mandrel is a surface of revolution),
  and a dwell there (mandrel turning, carriage still) only where the config asks for one;
- where the mandrel ends first (a short or no end zone), the fiber is held by the end (pins or a
  flange) at the heading it reached: it lies along the end's parallel while the mandrel turns at
  least SWING_MIN_DEG, and the free fiber swings meanwhile from the heading it came with, through the
  hoop, to the heading it leaves with. FiberPass.direction on such a dwell is that swing (the
  direction the free fiber leaves the contact point, so the eye reverses while the mandrel turns),
  not the parallel's tangent.
The ways in and out are traced on surfaces of revolution (straight axis, circular sections); on
other sections the turnaround is held at the region's end as on an end without room.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from winder.geometry.surface import SweepSurface
from winder.paths.headings import heading_of_velocity, velocity_of_heading
from winder.geometry.measure import row_norms, tangent_coordinates

TURN_SLIP_SHARE = 0.9  # of the friction coefficient, used by a turnaround (a margin for its scatter)
# Least dwell while the free fiber swings round an end that holds it, in degrees of a full turn of
# the perimeter (on a circular section: of the mandrel's turn).
SWING_MIN_DEG = 10.0
ROOM_TOL = 1e-6  # mm: an end zone shorter than this has no room for a friction turnaround
LEG_STEP_MM = 2.0  # sampling of a turnaround leg along the fiber
LEG_MIN_POINTS = 9
LEG_MAX_POINTS = 400  # a long way in (a low angle, little friction) is sampled more coarsely
LEG_CURVE_STEPS = 20  # a leg's steps per radius of the meridian's curvature, at least
LEG_PROBE = 64  # points of a leg where that curvature is read
HOOP_HEADING_TOL = 1e-9  # deg: a heading this close to 90 runs along the parallel
TRACE_TOL = 1e-10


@dataclasses.dataclass(frozen=True, eq=False)
class Leg:
    """The fiber from a pass's end into the end zone, at theta = 0 of its start.

    s, dtheta : (m,) float: station and angle from the start (rad), from the pass's end to the apex.
    ds, dth : (m,) float: unit-speed parameter velocity (s', theta') along the way in.
    length : mm. apex_heading_deg : the heading reached at the apex (90 where friction turned it
    around, less where the mandrel's end holds it: `held_by_end`). slip : the lambda used (signed).
    """

    s: np.ndarray
    dtheta: np.ndarray
    ds: np.ndarray
    dth: np.ndarray
    length: float
    apex_heading_deg: float
    slip: float

    @property
    def held_by_end(self) -> bool:
        return abs(self.apex_heading_deg - 90.0) > HOOP_HEADING_TOL

    @property
    def turn(self) -> float:
        """Mandrel turn (rad) of the way in and out together."""
        return 2.0 * float(self.dtheta[-1]) if self.s.size else 0.0


def heading_deg(surface: SweepSurface, s: np.ndarray, theta: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """Heading (deg, from the meridian toward +theta) of unit directions (m, 3) at (s, theta) (m,)."""
    ev = surface.evaluate(s, theta, order=1)
    u, v = tangent_coordinates(ev.ps.T, ev.pt.T, np.asarray(direction, dtype=float).T)
    return np.degrees(heading_of_velocity(surface, s, theta, u, v)[0])


def directions_of_heading(surface: SweepSurface, s: np.ndarray, theta: np.ndarray,
                          heading: np.ndarray) -> np.ndarray:
    """Unit directions (m, 3) at (s, theta) (m,) along headings (m,) deg."""
    ds, dth = velocity_of_heading(surface, s, theta, np.radians(heading))
    ev = surface.evaluate(s, theta, order=1)
    d = ev.ps * ds[:, None] + ev.pt * dth[:, None]
    return d / row_norms(d)[:, None]


def swing_headings(fraction: np.ndarray, heading_in: float, heading_out: float) -> np.ndarray:
    """Headings (deg) over a dwell, fraction (m,) in [0, 1]: from heading_in to the hoop (90) in the
    first half, on to heading_out in the second (linear in the mandrel turn)."""
    f = np.asarray(fraction, dtype=float)
    return (heading_in + (90.0 - heading_in) * np.clip(2.0 * f, 0.0, 1.0)
            + (heading_out - 90.0) * np.clip(2.0 * f - 1.0, 0.0, 1.0))


def turnaround_points(surface: SweepSurface, s_ends: tuple[float, float]) -> int:
    """The most points one turnaround at each of the stations s_ends lays (winder.winding.budget):
    two ways of LEG_MAX_POINTS where there is room, the swing's dwell (the pattern's dwell apart)."""
    swing = int(math.ceil(SWING_MIN_DEG / 2.0)) + 1
    return sum(swing + (2 * LEG_MAX_POINTS if end_room(surface, s, out) > ROOM_TOL else 0)
               for s, out in zip(s_ends, (-1.0, 1.0)))


def end_room(surface: SweepSurface, s_end: float, outward: float) -> float:
    """Arc length of mandrel (station units) past s_end in the direction outward (+1 / -1)."""
    return float(surface.length - s_end if outward > 0 else s_end)


def _leg_step(surface: SweepSurface, tr) -> float:
    """The leg's sampling step (mm): LEG_STEP_MM, finer where the meridian curves tighter than
    LEG_CURVE_STEPS steps a radius (a laminate's edge past the region, a few mm wide: 2 mm steps read a
    slip of 0.31 off a leg traced at 0.18). The slip check measures the leg from these points."""
    s = tr.state(np.linspace(0.0, tr.length, LEG_PROBE))[0]
    ev = surface.profile.evaluate(s) if surface.profile is not None else None
    if ev is None:
        return LEG_STEP_MM
    r1, r2 = ev[4], ev[5]
    z1 = ev[1] if not surface.is_axial_parameter else 1.0
    kappa = float(np.max(np.abs(r2) / (z1 * z1 + r1 * r1) ** 1.5)) if surface.is_axial_parameter else 0.0
    return min(LEG_STEP_MM, 1.0 / (LEG_CURVE_STEPS * kappa)) if kappa > 0.0 else LEG_STEP_MM


def trace_leg(surface: SweepSurface, s_end: float, heading: float, outward: float, friction: float) -> Leg:
    """The way in past the station s_end (at theta 0) of a pass arriving at `heading` deg, toward
    outward (+1: the far end, -1: the start), on a surface of revolution (module docstring)."""
    room = end_room(surface, s_end, outward)
    empty = np.zeros(0)
    if room <= ROOM_TOL or not surface.is_revolution or abs(heading - 90.0) <= HOOP_HEADING_TOL:
        return Leg(empty, empty, empty, empty, 0.0, float(heading), 0.0)
    slip = TURN_SLIP_SHARE * friction * (1.0 if heading < 90.0 else -1.0)
    r = float(np.max(surface.radius(np.array([s_end]), np.array([0.0]))))
    # The trace stops where the fiber reaches the parallel or the mandrel's end, whichever first.
    span = 50.0 * (room + r) / max(abs(math.cos(math.radians(heading))), 1e-3)
    from winder.paths.friction import trace_friction  # noqa: PLC0415 - only where a mandrel has room past the end

    tr = trace_friction(surface, (s_end, 0.0), heading, slip, span, rtol=TRACE_TOL, atol=TRACE_TOL,
                        stop_at_turnaround=True)
    m = min(LEG_MAX_POINTS, max(LEG_MIN_POINTS, int(math.ceil(tr.length / _leg_step(surface, tr))) + 1))
    y = tr.state(np.linspace(0.0, tr.length, m))
    s, th, ds, dth = (np.asarray(v, dtype=float) for v in y)
    if tr.event == "turnaround":
        apex = 90.0
    else:
        s[-1] = surface.length if outward > 0 else 0.0
        apex = float(np.degrees(heading_of_velocity(surface, s[-1:], th[-1:], ds[-1:], dth[-1:])[0][0]))
    return Leg(s, th - th[0], ds, dth, float(tr.length), apex, slip)


def leg_way(surface: SweepSurface, leg: Leg, theta0: float, back: bool):
    """(s, theta, directions (m, 3)) of the way in (back False) from theta0, or of the way out (back
    True) from the apex at theta0: the mirror image of the way in, run backwards."""
    if back:
        s, th = leg.s[::-1], theta0 + leg.dtheta[-1] - leg.dtheta[::-1]
        ds, dth = -leg.ds[::-1], leg.dth[::-1]
    else:
        s, th, ds, dth = leg.s, theta0 + leg.dtheta, leg.ds, leg.dth
    ev = surface.evaluate(s, th, order=1)
    d = ev.ps * ds[:, None] + ev.pt * dth[:, None]
    return s, th, d / row_norms(d)[:, None]


def end_note(surface: SweepSurface, leg: Leg, end: str) -> str:
    """One line for the layer's notes: how the fiber turns around at this end of the mandrel."""
    if not leg.held_by_end:
        span = float(np.ptp(surface.t_of_s(leg.s)))
        return (f"turnaround at the {end}: friction turns the fiber round {span:.3f} mm past the winding "
                f"region (|k_g / k_n| = {abs(leg.slip):.3g})")
    reached = f" at {leg.apex_heading_deg if leg.apex_heading_deg <= 90 else 180 - leg.apex_heading_deg:.3f} deg"
    room = "past the winding region " if leg.s.size else ""
    return (f"turnaround at the {end}: the mandrel's end holds the fiber{reached} (pins or a flange), where "
            f"the end zone {room}is too short for friction to turn it; the mandrel turns at least "
            f"{SWING_MIN_DEG:g} deg there while the eye reverses")
