"""Machine kinematics: where the payout eye sits while the fiber is laid (docs/math/06-machine.md, docs/guide/conventions.md).

Conventions (mandrel frame, docs/guide/conventions.md): a straight mandrel axis is +z through the origin.

Eye on the tangent line. d is the unit fiber direction in laying order: it points from the contact
point p toward the part of the path not yet laid. The fiber not yet laid is exactly the free span
between the mandrel and the eye: as the mandrel turns, that span is wound on and the contact point
moves along +d. So the free fiber leaves the mandrel at p along +d, and the eye is on that ray:

    E = p + lambda d,  lambda > 0   (the free-fiber length)

(E = p - lambda d would put the eye over the part already laid, which would peel it off.)
lambda is the smallest positive value that puts E on the eye envelope:
- `eye: {radius: Z}`: a cylinder of radius Z around the axis: |E_xy| = Z, closed form.
- `eye: {clearance: c}` (c + size / 2 for an eye of diameter size, so that its body keeps c): a contour
  of revolution Z_env(X) around the axis that keeps c mm from the
  mandrel: the radial profile r_max(t) (the largest section radius at station t) dilated by a disc
  of radius c, Z_env(X) = max over t of r_max(t) + sqrt(c^2 - (t - X)^2). On a cylinder this is
  exactly r + c; where the profile slopes (cone, dome) the eye keeps c measured in 3D, i.e. somewhat
  more than c radially (a cone of slope k: r + c sqrt(1 + k^2)). It is continuous (no jumps). It is
  then replaced by its concave majorant (the region inside it convex), so that every tangent ray
  leaves it exactly once and the eye moves continuously with the contact point (around a dome's
  polar opening the dilated profile is not concave: a ray grazing it would jump to a crossing far
  past the pole). Beyond an end where the profile is level or rises toward it (a pipe) the contour
  keeps its end value; where it falls toward the end (a dome, a cone's small end) the dilated end
  cap is part of it and the contour goes on down past the cap with the cap's slope (to 0).
Where the tangent line does not reach the envelope within MAX_LEAD_FACTOR times the largest envelope
radius (a fiber running almost parallel to the axis), the eye is held at that lead on the tangent
line (EyePath.on_envelope is False there).

Axes (straight-axis winder, docs/guide/conventions.md):
- X  carriage = E_z.
- Z  cross-feed = |E_xy|.
- A  mandrel rotation = -phi_E in degrees, phi_E = atan2(E_y, E_x) made continuous: phi_E is the
     contact angle theta (unwrapped, as planned) plus the eye's lead angle wrapped to (-180, 180].
     Forward kinematics: the eye is at mandrel-frame point (Z cos(-A), Z sin(-A), X).
- B  eye yaw: the eye's rotation about the cross-feed axis (the outward radial direction r at the
     eye), right-handed, measured from the hoop orientation: the angle, in the eye's tangent plane
     (spanned by u = z x r, the tangential direction, and +z, the carriage direction), from u toward
     +z of the fiber line:  B = atan2(sigma d.z, sigma d.u)  in degrees, made continuous.
     sigma = +1 when the mandrel winds theta+ (A decreasing), -1 otherwise: of the line's two
     orientations it takes the one running with the winding, so B = 0 on a hoop, +(90 - alpha') on
     a forward pass and -(90 - alpha') on a return pass (alpha' the fiber's angle from the carriage
     axis seen in the eye's plane), B in (-90, 90) whenever the fiber runs with the winding sense.
     The eye turns through the hoop orientation at every turnaround, never through the axial one.
     The radial component of d (the fiber climbing from the mandrel to the eye) does not enter B.

Robot mode (bent axis, or machine.robot): the same tangent-line rule with the envelope taken around
the guide curve: the eye's distance from its closest guide point x(t*) equals the envelope radius at
t* (eye_radius, or r_max(t*) + clearance dilated as above). The pose is the eye position and the unit
fiber direction from the eye to its contact point, both in the mandrel frame.
"""

from __future__ import annotations

import dataclasses
from dataclasses import replace

import numpy as np

from winder.config.machine import MachineConfig
from winder.errors import ExportError
from winder.geometry.surface import SweepSurface
from winder.machine.envelope import EyeEnvelope, eye_envelope
from winder.machine.leads import MAX_LEAD_FACTOR, first_crossing, lead_straight, unit_rows
from winder.geometry.measure import row_norms

CURVE_STEP = 0.5  # mm, guide-curve samples for the closest-point search (robot mode)
# The nearest-sample search uses every TREE_EVERY-th sample: a k-d tree's nearest-neighbour query
# visits the samples of the curve's stretch within about the point's distance, so its cost grows as
# distance / spacing (an eye 100 to 2000 mm out on a 0.5 mm grid: most of a robot export's time);
# Newton closes the up to TREE_EVERY * CURVE_STEP / 2 mm left in a step or two more.
TREE_EVERY = 4
PROJECT_NEWTON = 5  # Newton steps refining the closest guide point from the nearest tree sample
PROJECT_TOL = 1e-11  # mm: Newton stops when no station moves by more (the answer moves by ~ its square)
# ... and from a neighbour's station: quadratic from within ~1 mm, where the distance is stationary in
# the station, so a remaining error of d moves it by about d^2 kappa
WARM_NEWTON = 2


# -- results ---------------------------------------------------------------------------------------
@dataclasses.dataclass(frozen=True, eq=False)
class EyePath:
    """Axis values of a straight-axis winder at m contact points (see the module docstring).

    x, a_deg, z, b_deg : (m,) float: carriage (mm), mandrel rotation (deg, cumulative), cross-feed
        (mm), eye yaw (deg, continuous; 0 = hoop orientation).
    eye_xyz : (m, 3) float, the eye in the mandrel frame. lead : (m,) free-fiber length (mm).
    on_envelope : (m,) bool, False where the lead was capped (nearly axial fiber).
    """

    x: np.ndarray
    a_deg: np.ndarray
    z: np.ndarray
    b_deg: np.ndarray
    eye_xyz: np.ndarray
    lead: np.ndarray
    on_envelope: np.ndarray

    def axes(self) -> dict[str, np.ndarray]:
        """The four axis arrays by role name (carriage, rotation, cross_feed, yaw)."""
        return {"carriage": self.x, "rotation": self.a_deg, "cross_feed": self.z, "yaw": self.b_deg}


@dataclasses.dataclass(frozen=True, eq=False)
class RobotPoses:
    """Eye poses in the mandrel frame for a robot (bent mandrels).

    position : (m, 3) eye position (mm). direction : (m, 3) unit vector from the eye to its contact
    point (the free fiber as it leaves the eye). station : (m,) guide station t* of the eye's closest
    axis point (mm). lead : (m,) free-fiber length (mm). on_envelope : (m,) bool, as in EyePath.
    """

    position: np.ndarray
    direction: np.ndarray
    station: np.ndarray
    lead: np.ndarray
    on_envelope: np.ndarray


def _unwrap_each(b: np.ndarray, sizes: np.ndarray) -> np.ndarray:
    """np.unwrap of each consecutive run of b (k,) of the given sizes (to round-off): a run with no
    step of pi or more gets np.unwrap's zero corrections added to its tail, any other run is
    unwrapped on its own."""
    run = np.repeat(np.arange(sizes.size), sizes)
    out = b.copy()
    tail = np.ones(b.size, dtype=bool)
    tail[(np.cumsum(sizes) - sizes)[sizes > 0]] = False
    out[tail] = b[tail] + 0.0
    steps = (np.abs(np.diff(b)) >= np.pi) & (run[1:] == run[:-1])
    starts = np.cumsum(sizes) - sizes
    # The runs with a step, in order; np.unique would do, but it imports numpy.ma (10 ms at start-up).
    for k in np.flatnonzero(np.bincount(run[:-1][steps])):
        out[starts[k]:starts[k] + sizes[k]] = np.unwrap(b[starts[k]:starts[k] + sizes[k]])
    return out


def eye_path(points: np.ndarray, directions: np.ndarray, surface: SweepSurface, machine: MachineConfig,
             *, theta: np.ndarray | None = None, envelope: EyeEnvelope | None = None,
             sense: float | None = None, where: str = "eye path",
             lead: tuple[np.ndarray, np.ndarray] | None = None, sizes: np.ndarray | None = None) -> EyePath:
    """Axis values of a straight-axis winder laying the fiber through contact points (m, 3) with unit
    fiber directions (m, 3) (toward the part not yet laid). theta : (m,) the contact angles, unwrapped
    (default: the polar angles of the points, unwrapped); they fix A's turn count. envelope : from
    eye_envelope (computed here when left out). sense : the winding sense sigma of B (> 0: theta
    increasing; default: the sense the fiber runs in here). `where` prefixes error messages. lead :
    eye_leads of these points, when the caller computed them for many passes at once. sizes : the
    points are those of consecutive passes this long, each pass's B made continuous on its own (the
    same values as pass by pass; sense must be given); default one pass."""
    if not surface.curve.is_straight:
        raise ExportError(f"{where}: the mandrel axis is bent: a straight-axis winder cannot follow it; "
                          "use robot poses (machine.robot)")
    p = np.asarray(points, dtype=float).reshape(-1, 3)
    d = unit_rows(np.asarray(directions, dtype=float).reshape(-1, 3))
    env = envelope if envelope is not None else eye_envelope(surface, machine)
    lam, ok = lead if lead is not None else lead_straight(p, d, env, where)
    path, phi_raw = eye_frames(p, d, (lam, ok), sense, sizes)
    if theta is None:
        theta = np.unwrap(np.arctan2(p[:, 1], p[:, 0]))
    return replace(path, a_deg=rotation_deg(phi_raw, np.asarray(theta, dtype=float)))


def eye_frames(p: np.ndarray, d: np.ndarray, lead: tuple[np.ndarray, np.ndarray], sense: float | None = None,
               sizes: np.ndarray | None = None) -> tuple[EyePath, np.ndarray]:
    """eye_path's values that do not depend on the contact angles theta, of points p (m, 3) with unit
    directions d (m, 3) and their leads: the path with a_deg left empty, and the eye's polar angle
    phi_raw (m,) (rad, in (-pi, pi]) from which rotation_deg makes A once theta is known. Pointwise
    but for B's continuity (per run of `sizes`), so a whole program's passes go in one call."""
    lam, ok = lead
    e, phi_raw, zr, d_u = _eye(p, d, lam)
    if sense is None:
        sense = -1.0 if np.sum(d_u) < 0.0 else 1.0
    b = yaw_raw(d, d_u, sense)
    b = np.unwrap(b) if sizes is None else _unwrap_each(b, np.asarray(sizes, dtype=int))
    return EyePath(x=e[:, 2].copy(), a_deg=np.zeros(0), z=zr, b_deg=np.degrees(b), eye_xyz=e,
                   lead=lam, on_envelope=ok), phi_raw


def _eye(p: np.ndarray, d: np.ndarray, lam: np.ndarray) -> tuple[np.ndarray, ...]:
    """(eye e (m, 3), its polar angle phi_raw (m,), cross-feed |e_xy| (m,), d's tangential
    component d_u (m,)) of contact points p with unit directions d and leads lam: pointwise."""
    e = p + lam[:, None] * d
    phi_raw = np.arctan2(e[:, 1], e[:, 0])
    zr = np.hypot(e[:, 0], e[:, 1])
    d_u = -np.sin(phi_raw) * d[:, 0] + np.cos(phi_raw) * d[:, 1]
    return e, phi_raw, zr, d_u


def yaw_raw(d: np.ndarray, d_u: np.ndarray, sense: float) -> np.ndarray:
    """B (rad, in (-pi, pi], not yet made continuous) of unit directions d (m, 3) with tangential
    components d_u (m,) for the winding sense `sense`: pointwise."""
    sigma = -1.0 if sense < 0.0 else 1.0
    return np.arctan2(sigma * d[:, 2], sigma * d_u)


def eye_points(p: np.ndarray, d: np.ndarray, lam: np.ndarray, sense: float) -> tuple[np.ndarray, ...]:
    """eye_frames' pointwise values: (e (m, 3), phi_raw (m,), cross-feed (m,), B (m,) rad before
    unwrapping), so that points placed by several steps of a program are computed once."""
    e, phi_raw, zr, d_u = _eye(p, d, lam)
    return e, phi_raw, zr, yaw_raw(d, d_u, sense)


def unwrap_each(b: np.ndarray, sizes: np.ndarray) -> np.ndarray:
    """B made continuous within each consecutive run of the given sizes (eye_frames' own rule)."""
    return _unwrap_each(b, np.asarray(sizes, dtype=int))


def rotation_deg(phi_raw: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """A (deg) of eyes at polar angles phi_raw (k,) laying contact points at the unwrapped angles
    theta (k,): -(theta + the lead angle phi_raw - theta wrapped to (-pi, pi]). Pointwise."""
    lead_angle = np.angle(np.exp(1j * (phi_raw - theta)))  # wrapped to (-pi, pi]
    return -np.degrees(theta + lead_angle)


# -- robot mode ------------------------------------------------------------------------------------
class Guide:
    """Closest points on the guide curve, extended beyond its ends by its end tangents."""

    def __init__(self, surface: SweepSurface, extend: float) -> None:
        T = surface.axial_length
        self.T = T
        curve = surface.curve
        n = int(max(257, np.ceil(T / CURVE_STEP) + 1))
        z = np.linspace(0.0, T, n)
        ends = curve.evaluate(np.array([0.0, T]))
        self.x0, self.x1 = ends.x[0], ends.x[1]
        self.t0, self.t1 = unit_rows(ends.d1)[0], unit_rows(ends.d1)[1]
        ne = int(np.ceil(extend / CURVE_STEP)) + 1
        ext = np.linspace(0.0, extend, ne)[1:]
        self.z = np.concatenate([-ext[::-1], z, T + ext])
        self.x = np.concatenate([self.x0 - ext[::-1, None] * self.t0, curve.evaluate(z).x,
                                 self.x1 + ext[:, None] * self.t1])
        self.curve = curve
        from scipy.spatial import cKDTree  # noqa: PLC0415 - scipy.spatial is slow to import

        every = np.unique(np.r_[np.arange(0, self.z.size, TREE_EVERY), self.z.size - 1])
        self.tree_z = self.z[every]
        self.tree = cKDTree(self.x[every])

    def evaluate(self, z: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Point, unit tangent and curvature vector x'' of the extended guide at stations z."""
        zi = np.clip(z, 0.0, self.T)
        x, d1, kap = self.curve.centerline(zi)  # without the frame
        tan = unit_rows(d1)
        lo, hi = z < 0.0, z > self.T
        x[lo] = self.x0 + z[lo, None] * self.t0
        tan[lo] = self.t0
        x[hi] = self.x1 + (z[hi] - self.T)[:, None] * self.t1
        tan[hi] = self.t1
        kap[lo | hi] = 0.0
        return x, tan, kap

    def project(self, e: np.ndarray, full: bool = False, start: np.ndarray | None = None) -> tuple[np.ndarray, ...]:
        """(station t*, distance) of the closest guide point of each point e (m, 3); full: also
        e - x(t*), the unit tangent and x'' there (each (m, 3)). start : (m,) stations within a
        millimetre or so of the answers (a point's neighbour's): WARM_NEWTON steps from there."""
        if start is None:
            _, k = self.tree.query(e)
            z, steps = self.tree_z[k], PROJECT_NEWTON
        else:
            z, steps = np.clip(start, self.z[0], self.z[-1]), WARM_NEWTON
        # Newton on g(z) = (e - x(z)) . x'(z) = 0, each point until its step is below PROJECT_TOL (its
        # last evaluation then stands) or for `steps` steps (then evaluated once more where it ended)
        x, tan, kap = np.empty_like(e), np.empty_like(e), np.empty_like(e)
        z = np.array(z, dtype=float)
        active = np.arange(z.size)
        for it in range(steps + 1):
            x[active], tan[active], kap[active] = self.evaluate(z[active])
            if it == steps:
                break
            rel = e[active] - x[active]
            slope = 1.0 - np.einsum("ij,ij->i", rel, kap[active])  # -g'(z), > 0 outside the centre of curvature
            step = np.einsum("ij,ij->i", rel, tan[active]) / np.where(slope > 0.1, slope, 1.0)
            moving = np.abs(step) > PROJECT_TOL
            active, step = active[moving], np.clip(step[moving], -CURVE_STEP * 4, CURVE_STEP * 4)
            if active.size == 0:
                break
            z[active] = np.clip(z[active] + step, self.z[0], self.z[-1])
        rel = e - x
        return (z, row_norms(rel), rel, tan, kap) if full else (z, row_norms(rel))


def robot_poses(points: np.ndarray, directions: np.ndarray, surface: SweepSurface, machine: MachineConfig,
                *, envelope: EyeEnvelope | None = None, guide: Guide | None = None,
                where: str = "eye poses", guess: np.ndarray | None = None) -> RobotPoses:
    """Eye poses (mandrel frame) for contact points (m, 3) with fiber directions (m, 3), any axis.
    guess : (m,) estimates of the leads (from poses nearby): Newton starts there instead of a scan."""
    p = np.asarray(points, dtype=float).reshape(-1, 3)
    d = unit_rows(np.asarray(directions, dtype=float).reshape(-1, 3))
    env = envelope if envelope is not None else eye_envelope(surface, machine)
    lmax = MAX_LEAD_FACTOR * env.max_radius
    g = guide if guide is not None else Guide(surface, lmax)
    z0, r0 = g.project(p)
    clear = r0 < env.at(z0)
    if not clear.all():
        k = int(np.argmin(clear))
        raise ExportError(f"{where}: the eye envelope (radius {float(env.at(z0[k:k+1])[0]):.3f} mm) does not "
                          f"clear the mandrel at t = {z0[k]:.3f} mm")

    def f(lam: np.ndarray, i: np.ndarray) -> np.ndarray:
        zs, dist = g.project(p[i] + lam[:, None] * d[i])
        return dist - env.at(zs)

    def fd(lam: np.ndarray, i: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        # d/dlambda of the distance is the unit normal's share of d; the station moves by
        # (d . tan) / (1 - rel . kap), from the closest-point condition (e - x(t*)) . x'(t*) = 0.
        zs, dist, rel, tan, kap = g.project(p[i] + lam[:, None] * d[i], full=True, start=near[i])
        near[i] = zs
        slope = 1.0 - np.einsum("ij,ij->i", rel, kap)
        dz = np.einsum("ij,ij->i", d[i], tan) / np.where(slope > 0.1, slope, 1.0)
        rate = np.einsum("ij,ij->i", rel, d[i]) / np.where(dist > 0.0, dist, 1.0)
        return dist - env.at(zs), rate - env.slope(zs) * dz

    if guess is None:
        lam, ok = first_crossing(f, p.shape[0], lmax)
    else:  # fd starts each line's closest station from the last one found on it
        near = g.project(p + np.clip(guess, 0.0, lmax)[:, None] * d)[0]
        lam, ok = first_crossing(f, p.shape[0], lmax, guess=guess, fd=fd)
    e = p + lam[:, None] * d
    station, _ = g.project(e)
    return RobotPoses(position=e, direction=-d, station=station, lead=lam, on_envelope=ok)


def make_guide(surface: SweepSurface, envelope: EyeEnvelope) -> Guide:
    """The closest-point helper of robot_poses, built once per job."""
    return Guide(surface, MAX_LEAD_FACTOR * envelope.max_radius)
