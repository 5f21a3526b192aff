"""Machine kinematics: the eye on the fiber's tangent line and on its envelope (docs/math/06-machine.md).

Also home of the small plan builders the export tests share (the planner is not needed: passes are
helices on a cylinder, exact geodesics of a developable surface, or solved two-point geodesics).
"""

from __future__ import annotations

import numpy as np
import pytest

from conftest import surface_of
from winder.config.axes import ArcAxis
from winder.config.mandrel import ConstantProfile, LineAxis
from winder.config.profiles import ConeProfile
from winder.config.sections import EllipseSection
from winder.config.machine import MachineConfig, MachineLimits
from plans import R, cylinder_plan, geodesic_pass, helix
from winder.errors import ExportError
from winder.machine.envelope import eye_envelope
from winder.machine.kinematics import eye_path, robot_poses
from winder.machine.limits import check_limits
from winder.winding.results import PassKind

ON_LINE_TOL = 1e-9  # mm: the eye is constructed on the tangent line
ENVELOPE_TOL = 1e-9  # mm: radius mode is a closed form
CLEARANCE_TOL = 1e-6  # mm: clearance mode is a bisection on a tabulated contour
CONE_TOL = 0.02  # mm: the dilated cone contour is tabulated at 0.25 mm steps
ROBOT_TOL = 1e-6  # mm: distance of the robot eye from the bend's guide circle

T = 300.0


@pytest.fixture(scope="module")
def tube():
    return surface_of(LineAxis(T), ConstantProfile(R))


def _radius_machine(z=60.0, **kw):
    return MachineConfig(eye_radius=z, eye_clearance=None, **kw)


# -- straight-axis kinematics ---------------------------------------------------------------------
def _tangent_residual(p, d, e):
    """Distance of e from the line p + lambda d, and lambda."""
    lam = np.einsum("ij,ij->i", e - p, d)
    return np.linalg.norm(e - p - lam[:, None] * d, axis=1), lam


@pytest.mark.parametrize("alpha", [15.0, 55.0, 85.0])
def test_cylinder_closed_form(tube, alpha):
    """Helix at alpha on radius R, eye cylinder Z: the tangent line climbs as sqrt(R^2 + l^2 sin^2
    alpha), so l = sqrt(Z^2 - R^2) / sin(alpha); the eye leads the contact by atan(l sin alpha / R)
    around the axis and by l cos(alpha) along it."""
    z = 60.0
    adv = 260.0 * np.tan(np.radians(alpha)) / R
    fp = helix(tube, 20.0, 280.0, 0.0, adv, 50, layer=1, circuit=1, number=1, kind=PassKind.FORWARD)
    path = eye_path(fp.points, fp.direction, tube, _radius_machine(z), theta=fp.theta)
    sa, ca = np.sin(np.radians(alpha)), np.cos(np.radians(alpha))
    lam = np.sqrt(z * z - R * R) / sa
    lead = np.arctan(lam * sa / R)
    assert np.allclose(path.lead, lam, atol=1e-9)
    assert np.allclose(path.x, fp.t + lam * ca, atol=1e-9)
    assert np.allclose(path.z, z, atol=ENVELOPE_TOL)
    assert np.allclose(path.a_deg, -np.degrees(fp.theta + lead), atol=1e-9)
    # Yaw from the hoop orientation: d = (cos a) z + (sin a) e_theta, and the eye's tangential
    # direction u is e_theta turned by the lead angle, so d.u = sin(a) cos(lead).
    assert np.allclose(path.b_deg, np.degrees(np.arctan2(ca, sa * np.cos(lead))), atol=1e-9)
    assert path.on_envelope.all()


def test_eye_ahead_on_tangent_line_and_forward_kinematics(tube):
    """E = p + lambda d with lambda > 0 (the free fiber is the part not yet laid), and SPEC's forward
    kinematics (Z cos(-A), Z sin(-A), X) gives back E."""
    plan = cylinder_plan(tube)
    for fp in plan.layers[0].passes + plan.layers[1].passes:
        path = eye_path(fp.points, fp.direction, tube, _radius_machine(), theta=fp.theta)
        res, lam = _tangent_residual(fp.points, fp.direction, path.eye_xyz)
        assert res.max() < ON_LINE_TOL and (lam > 0).all()
        a = np.radians(path.a_deg)
        fk = np.column_stack([path.z * np.cos(-a), path.z * np.sin(-a), path.x])
        assert np.abs(fk - path.eye_xyz).max() < 1e-9
        assert np.abs(np.hypot(path.eye_xyz[:, 0], path.eye_xyz[:, 1]) - 60.0).max() < ENVELOPE_TOL


def test_a_follows_planned_turns(tube):
    """A is cumulative and fixed by the planned (unwrapped) theta: 5 turns of contact are -1800 deg."""
    fp = helix(tube, 20.0, 280.0, 0.0, 10 * np.pi, 400, layer=1, circuit=1, number=1, kind=PassKind.HOOP)
    path = eye_path(fp.points, fp.direction, tube, _radius_machine(), theta=fp.theta)
    assert path.a_deg[-1] - path.a_deg[0] == pytest.approx(-1800.0, abs=1e-9)
    assert (np.diff(path.a_deg) < 0).all()
    shifted = eye_path(fp.points, fp.direction, tube, _radius_machine(), theta=fp.theta + 4 * np.pi)
    assert np.allclose(shifted.a_deg, path.a_deg - 720.0, atol=1e-9)


def test_return_pass_yaw_mirrors_forward(tube):
    """The mandrel turns one way: the return pass's yaw mirrors the forward's about the hoop (0)."""
    adv = 260.0 * np.tan(np.radians(50.0)) / R
    fw = helix(tube, 20.0, 280.0, 0.0, adv, 30, layer=1, circuit=1, number=1, kind=PassKind.FORWARD)
    rt = helix(tube, 280.0, 20.0, adv, 2 * adv, 30, layer=1, circuit=1, number=2, kind=PassKind.RETURN)
    m = _radius_machine()
    bf = eye_path(fp := fw.points, fw.direction, tube, m, theta=fw.theta).b_deg
    br = eye_path(rt.points, rt.direction, tube, m, theta=rt.theta).b_deg
    assert fp.shape[0] == 30
    assert np.allclose(bf + br, 0.0, atol=1e-9)
    assert (bf > 0).all() and (bf < 90).all()
    # A dwell (a hoop at the end) is yaw 0.
    dw = helix(tube, 280.0, 280.0, adv, adv + 1.0, 5, layer=1, circuit=1, number=2, kind=PassKind.DWELL)
    assert np.allclose(eye_path(dw.points, dw.direction, tube, m, theta=dw.theta).b_deg, 0.0, atol=1e-9)
    # Winding the other way (theta decreasing) mirrors B: the forward pass is then negative.
    back = helix(tube, 20.0, 280.0, 0.0, -adv, 30, layer=1, circuit=1, number=1, kind=PassKind.FORWARD)
    bb = eye_path(back.points, back.direction, tube, m, theta=back.theta).b_deg
    assert np.allclose(bb, -bf, atol=1e-9)


def test_elliptic_section_eye_on_tangent_and_envelope():
    surface = surface_of(LineAxis(400.0), None, EllipseSection(60.0, 35.0))
    fp = geodesic_pass(surface, (10.0, np.radians(-20.0)), (390.0, np.radians(70.0)), 150, rounds=2,
                       layer=1, circuit=1, number=1, kind=PassKind.FORWARD)
    path = eye_path(fp.points, fp.direction, surface, _radius_machine(90.0), theta=fp.theta)
    res, lam = _tangent_residual(fp.points, fp.direction, path.eye_xyz)
    assert res.max() < ON_LINE_TOL and (lam > 0).all()
    assert np.abs(path.z - 90.0).max() < ENVELOPE_TOL
    # A tracks the planned turns: two rounds and 90 degrees, within the eye's lead change.
    a = np.radians(path.a_deg)
    assert np.allclose(-a - fp.theta, np.angle(np.exp(1j * (-a - fp.theta))), atol=1e-12)


def test_clearance_mode_cylinder(tube):
    """eye: {clearance: c}: on a cylinder the eye keeps Z = R + c, also beyond the mandrel's ends."""
    plan = cylinder_plan(tube, hoop=False)
    machine = MachineConfig(eye_clearance=15.0)
    env = eye_envelope(tube, machine)
    for fp in plan.layers[0].passes:
        path = eye_path(fp.points, fp.direction, tube, machine, theta=fp.theta, envelope=env)
        assert np.abs(path.z - (R + 15.0)).max() < CLEARANCE_TOL
        res, lam = _tangent_residual(fp.points, fp.direction, path.eye_xyz)
        assert res.max() < ON_LINE_TOL and (lam > 0).all()
    assert np.allclose(env.at(np.array([-50.0, 0.0, 150.0, 300.0, 400.0])), R + 15.0)


def test_clearance_mode_cone_keeps_distance_in_3d():
    """A cone r = 60 - 0.1 t: the contour keeps c from the surface in 3D, which is
    Z = r(X) + c sqrt(1 + k^2) radially (k = 0.1) away from the ends."""
    cone = surface_of(LineAxis(300.0), ConeProfile(60.0, 30.0))
    c, k = 10.0, 0.1
    machine = MachineConfig(eye_clearance=c)
    fp = geodesic_pass(cone, (20.0, 0.0), (250.0, np.radians(200.0)), 120, layer=1, circuit=1, number=1,
                       kind=PassKind.FORWARD)
    path = eye_path(fp.points, fp.direction, cone, machine, theta=fp.theta)
    inner = (path.x > 20.0) & (path.x < 280.0)
    assert inner.sum() > 50
    expect = 60.0 - k * path.x + c * np.sqrt(1 + k * k)
    assert np.abs(path.z - expect)[inner].max() < CONE_TOL
    # Distance from the cone's surface line in the meridian plane: (Z - r(X)) / sqrt(1 + k^2) = c.
    dist = (path.z - (60.0 - k * path.x)) / np.sqrt(1 + k * k)
    assert np.abs(dist[inner] - c).max() < CONE_TOL
    res, lam = _tangent_residual(fp.points, fp.direction, path.eye_xyz)
    assert res.max() < ON_LINE_TOL and (lam > 0).all()


def test_nearly_axial_fiber_caps_the_lead(tube):
    d = np.array([[0.0, 1e-9, 1.0], [0.0, 1.0, 1.0]])
    p = np.array([[R, 0.0, 100.0], [R, 0.0, 100.0]])
    path = eye_path(p, d, tube, _radius_machine())
    assert not path.on_envelope[0] and path.on_envelope[1]
    assert path.lead[0] == pytest.approx(600.0)  # MAX_LEAD_FACTOR x 60 mm
    res, _ = _tangent_residual(p, d / np.linalg.norm(d, axis=1)[:, None], path.eye_xyz)
    assert res.max() < ON_LINE_TOL


def test_limits_refused_with_clear_message(tube):
    fp = helix(tube, 20.0, 280.0, 0.0, 6.0, 40, layer=1, circuit=1, number=3, kind=PassKind.FORWARD)
    machine = _radius_machine(limits=MachineLimits(carriage=(0.0, 200.0)))
    path = eye_path(fp.points, fp.direction, tube, machine, theta=fp.theta)
    with pytest.raises(ExportError) as err:
        check_limits(path, machine, "job.yaml: layer 1 circuit 1 pass 3 (forward)")
    msg = str(err.value)
    assert "machine.limits.carriage" in msg and "axis X" in msg and "[0, 200]" in msg
    assert "layer 1 circuit 1 pass 3" in msg
    assert f"{path.x.max():.3f}" in msg
    check_limits(path, _radius_machine(limits=MachineLimits(carriage=(-500.0, 900.0))), "ok")


def test_envelope_inside_mandrel_refused(tube):
    fp = helix(tube, 20.0, 280.0, 0.0, 6.0, 10, layer=1, circuit=1, number=1, kind=PassKind.FORWARD)
    with pytest.raises(ExportError, match="does not clear the mandrel"):
        eye_path(fp.points, fp.direction, tube, _radius_machine(30.0))


# -- bent mandrels: robot poses -------------------------------------------------------------------
@pytest.fixture(scope="module")
def bend():
    return surface_of(ArcAxis(150.0, 90.0), ConstantProfile(40.0))


def test_straight_winder_refuses_bent_axis(bend):
    with pytest.raises(ExportError, match="bent"):
        eye_path(np.zeros((1, 3)), np.array([[0.0, 0.0, 1.0]]), bend, MachineConfig())


@pytest.mark.parametrize("machine, radius", [(MachineConfig(eye_radius=70.0, eye_clearance=None, robot=True), 70.0),
                                             (MachineConfig(eye_clearance=12.0, robot=True), 52.0)])
def test_robot_poses_on_tangent_line_and_tube(bend, machine, radius):
    """The quarter bend's guide is the circle of radius 150 about (150, 0, 0) in the xz plane: a
    point's distance from it is sqrt((rho - 150)^2 + y^2), rho its distance from the centre in xz."""
    fp = geodesic_pass(bend, (30.0, 0.0), (200.0, np.radians(120.0)), 120, rounds=1, layer=1, circuit=1,
                       number=1, kind=PassKind.FORWARD)
    pose = robot_poses(fp.points, fp.direction, bend, machine)
    assert np.allclose(pose.direction, -fp.direction, atol=1e-12)
    res, lam = _tangent_residual(fp.points, fp.direction, pose.position)
    assert res.max() < ON_LINE_TOL and (lam > 0).all() and pose.on_envelope.all()
    e = pose.position
    rel = e - np.array([150.0, 0.0, 0.0])
    rho = np.hypot(rel[:, 0], rel[:, 2])
    angle = np.degrees(np.arctan2(rel[:, 2], -rel[:, 0]))  # 0 at the start of the arc, 90 at its end
    within = (angle > 0.5) & (angle < 89.5)
    assert within.sum() > 60
    dist = np.hypot(rho - 150.0, rel[:, 1])
    assert np.abs(dist - radius)[within].max() < ROBOT_TOL
    assert np.allclose(pose.station[within], np.radians(angle[within]) * 150.0, atol=1e-6)


@pytest.fixture(scope="module")
def vessel():
    from winder.config.mandrel import MandrelConfig  # noqa: PLC0415
    from winder.config.vessel import Dome, DomeType, VesselProfile  # noqa: PLC0415
    from winder.geometry.build import build_surface  # noqa: PLC0415
    dome = Dome(DomeType.HEMISPHERE, 30.0)
    return build_surface(MandrelConfig(None, VesselProfile(100.0, 300.0, dome, dome)), "v.yaml", "v")


def test_vessel_dome_eye_modes(vessel):
    """A pass running from the cylinder over the first hemisphere toward its pole (the fiber heads
    toward the axis there). Radius mode: on the 180 mm cylinder. Clearance mode: the eye keeps c
    from the mandrel in 3D (distance from the meridian profile), exactly c where it is closest."""
    fp = geodesic_pass(vessel, (200.0, 0.0), (8.0, 2.0), 200, layer=1, circuit=1, number=1,
                       kind=PassKind.RETURN)
    path = eye_path(fp.points, fp.direction, vessel, _radius_machine(180.0), theta=fp.theta)
    res, lam = _tangent_residual(fp.points, fp.direction, path.eye_xyz)
    assert res.max() < ON_LINE_TOL and (lam > 0).all() and path.on_envelope.all()
    assert np.abs(path.z - 180.0).max() < ENVELOPE_TOL
    c = 20.0
    path = eye_path(fp.points, fp.direction, vessel, MachineConfig(eye_clearance=c), theta=fp.theta)
    res, lam = _tangent_residual(fp.points, fp.direction, path.eye_xyz)
    assert res.max() < ON_LINE_TOL and (lam > 0).all()
    s = np.linspace(0.0, vessel.length, 20001)
    prof = np.column_stack([vessel.t_of_s(s), vessel.radius(s, 0.0 * s)])
    dist = np.hypot(path.x[:, None] - prof[None, :, 0], path.z[:, None] - prof[None, :, 1]).min(axis=1)
    assert dist.min() > c - 0.01 and dist.min() < c + 0.01
    assert (path.z >= np.interp(np.clip(path.x, 0, vessel.axial_length), prof[:, 0], prof[:, 1]) + c - 1e-6).all()
