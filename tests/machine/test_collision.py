"""winder.machine.collision: the eye's body keeps its clearance along every move, checked on the
program parsed back from its text (cylinder: closed-form distances)."""

from __future__ import annotations

import numpy as np
import pytest

from conftest import surface_of
from plans import cylinder_plan
from winder.config.machine import MachineConfig
from winder.config.mandrel import ConstantProfile, LineAxis
from winder.errors import ExportError
from winder.export.gcode import gcode_text
from winder.machine.collision import check_collision, part_distance, sampled_moves
from winder.machine.envelope import eye_envelope

R, T = 40.0, 300.0
CUT_TOL = 1e-6  # mm
ROUNDOFF_MM = 1e-12  # mm: two computations of one distance of a point 200 mm out


@pytest.fixture(scope="module")
def tube():
    return surface_of(LineAxis(T), ConstantProfile(R))


def test_part_distance_closed_forms(tube):
    env = eye_envelope(tube, MachineConfig())
    rho = np.array([70.0, 10.0, 40.0, 50.0, 20.0])
    z = np.array([150.0, 310.0, -5.0, 306.0, 150.0])
    expected = np.array([30.0, 10.0, 5.0, np.hypot(10.0, 6.0), -20.0])
    assert part_distance(rho, z, env) == pytest.approx(expected, abs=1e-9)


def test_eye_body_keeps_the_clearance_along_every_move(tube):
    """An eye of 6 mm diameter at clearance 20: its centre runs at R + 23; sampled along every parsed
    move (the axes linear between lines) the body never comes nearer than 20 - chord_tolerance."""
    machine = MachineConfig(eye_clearance=20.0, eye_size=6.0, chord_tolerance=0.05)
    text = gcode_text(cylinder_plan(tube), machine)
    rows = np.array([[float(w[1:]) for w in ln.split()[1:4]] for ln in text.splitlines() if ln.startswith("G1 ")])
    assert np.allclose(rows[:, 2], R + 23.0, atol=1e-3)
    f = np.linspace(0.0, 1.0, 33)
    x = rows[:-1, None, 0] + f * np.diff(rows[:, 0])[:, None]
    rho = rows[:-1, None, 2] + f * np.diff(rows[:, 2])[:, None]
    beyond = np.maximum(np.maximum(-x, x - T), 0.0)
    dist = np.where(beyond > 0, np.hypot(beyond, np.maximum(rho - R, 0.0)), rho - R)
    assert (dist - 3.0 >= 20.0 - 0.05 - CUT_TOL).all()


def test_a_move_through_the_mandrel_is_refused(tube):
    machine = MachineConfig(eye_clearance=20.0, eye_size=4.0)
    env = eye_envelope(tube, machine)
    values = np.array([[0.0, 0.0, 62.0, 0.0], [100.0, 0.0, 62.0, 0.0], [200.0, 0.0, 45.0, 0.0]])
    with pytest.raises(ExportError, match=r"pass X: the payout eye \(size 4 mm\) comes within 3.000 mm"):
        check_collision(values, env, machine, lambda row: "pass X")
    check_collision(values[:2], env, machine, lambda row: "pass X")  # the first move keeps 20 mm


def test_an_eye_inside_the_mandrel_is_said_to_cut_into_it(tube):
    """The eye's centre at 35 mm on a 40 mm tube: its 4 mm body reaches 5 + 2 = 7 mm into the mandrel
    (first on the move to X150), where the body must keep 20 less the chord tolerance,
    said as such rather than as coming "within -7 mm"."""
    machine = MachineConfig(eye_clearance=20.0, eye_size=4.0)
    env = eye_envelope(tube, machine)
    values = np.array([[100.0, 0.0, 62.0, 0.0], [150.0, 0.0, 35.0, 0.0], [200.0, 0.0, 35.0, 0.0]])
    with pytest.raises(ExportError, match=r"pass X: the payout eye \(size 4 mm\) cuts 7.000 mm into the "
                                          r"mandrel \(as wound so far\) on the move to X150.000 A0.000; it must "
                                          r"stay 19.950 mm clear$"):
        check_collision(values, env, machine, lambda row: "pass X")


def _brute_distance(rho: np.ndarray, z: np.ndarray, t: np.ndarray, r: np.ndarray) -> np.ndarray:
    """Distance of (z, rho) from every meridian segment at once, the least kept (no search)."""
    q = np.column_stack([z, rho])[:, None, :]
    a = np.column_stack([t[:-1], r[:-1]])[None]
    seg = np.column_stack([np.diff(t), np.diff(r)])[None]
    u = np.clip(np.sum((q - a) * seg, axis=2) / np.sum(seg * seg, axis=2), 0.0, 1.0)
    return np.min(np.linalg.norm(q - a - u[..., None] * seg, axis=2), axis=1)


@pytest.mark.parametrize("profile", ["cylinder", "cone", "dome"])
def test_part_distance_is_the_least_over_all_segments(profile):
    """The slab search (and the nearest-vertex rule on a finely tabulated dome) against the distance
    from every segment of the meridian, at points outside the part within and past the ends."""
    t = np.linspace(0.0, 200.0, 801)
    r = {"cylinder": np.full_like(t, 40.0), "cone": 40.0 - 0.1 * t,
         "dome": np.sqrt(np.maximum(100.0**2 - (t - 100.0) ** 2, 0.0)) * 0.5 + 10.0}[profile]
    env = type("Env", (), {"stations": t, "mandrel_radius": r})()
    rng = np.random.default_rng(7)
    z = rng.uniform(0.0, 200.0, 4000)
    rho = np.interp(z, t, r) + rng.uniform(0.5, 30.0, z.size)
    assert part_distance(rho, z, env) == pytest.approx(_brute_distance(rho, z, t, r), abs=CUT_TOL)


# -- robot poses around a bent guide -----------------------------------------------------------------
BEND_R, TUBE_R = 150.0, 40.0


@pytest.fixture(scope="module")
def bend():
    from winder.config.axes import ArcAxis  # noqa: PLC0415

    return surface_of(ArcAxis(BEND_R, 90.0), ConstantProfile(TUBE_R))


def test_tube_distance_closed_forms(bend):
    """Around a quarter torus: a point at rho from the arc lies rho - r from the tube; past an end,
    from its disc or the disc's rim."""
    from winder.machine.collision import tube_distance  # noqa: PLC0415
    from winder.machine.kinematics import make_guide  # noqa: PLC0415

    env = eye_envelope(bend, MachineConfig(eye_clearance=20.0))
    guide = make_guide(bend, env)
    x0, t0 = guide.x0, guide.t0  # the arc's start and its tangent there
    side = np.cross(t0, [0.0, 0.0, 1.0]) if abs(t0[2]) < 0.9 else np.cross(t0, [1.0, 0.0, 0.0])
    side /= np.linalg.norm(side)
    mid = guide.evaluate(np.array([0.5 * guide.T]))
    normal = np.cross(mid[1][0], side)
    normal /= np.linalg.norm(normal)
    points = np.array([mid[0][0] + 70.0 * normal, mid[0][0] + 10.0 * side, x0 - 5.0 * t0 + 50.0 * side,
                       x0 - 5.0 * t0 + 20.0 * side])
    expected = [70.0 - TUBE_R, 10.0 - TUBE_R, np.hypot(5.0, 10.0), 5.0]
    assert tube_distance(points, env, guide) == pytest.approx(expected, abs=1e-6)


def test_robot_chords_keep_the_clearance(bend):
    """A robot's moves between poses are chords around the envelope (radius 60 around the arc): with
    poses a fiber point apart they cut into the clearance by L^2 / 8R; the program densifies them,
    and every move, sampled, keeps the clearance less the chord tolerance."""
    from plans import geodesic_pass, make_layer  # noqa: PLC0415
    from winder.machine.collision import move_distances  # noqa: PLC0415
    from winder.machine.kinematics import make_guide  # noqa: PLC0415
    from winder.machine.program import build_program  # noqa: PLC0415
    from winder.winding.results import PassKind, WindingPlan  # noqa: PLC0415

    fw = geodesic_pass(bend, (20.0, 0.0), (215.0, np.radians(150.0)), 40, rounds=1, layer=1, circuit=1,
                       number=1, kind=PassKind.FORWARD)
    plan = WindingPlan("elbow", "elbow.yaml", bend, (make_layer(1, [fw], circuits=1),))
    machine = MachineConfig(eye_clearance=20.0, robot=True, chord_tolerance=0.05)
    program = build_program(plan, machine)
    env = eye_envelope(plan.outer_surface, machine)
    dist, _ = move_distances(program.values, env, make_guide(plan.outer_surface, env))
    assert program.values.shape[0] > len(fw.points)  # densified
    assert dist.min() >= 20.0 - 0.05 - CUT_TOL


def test_a_robot_chord_into_the_clearance_is_refused_but_a_join_may_pass(bend):
    """Two poses on the envelope 60 mm apart around the arc's middle section: their chord dips to
    60 cos(theta/2) from the arc; inside a pass refused, as the move joining two passes only if the
    eye touches the part."""
    from winder.machine.collision import check_collision  # noqa: PLC0415
    from winder.machine.kinematics import make_guide  # noqa: PLC0415

    machine = MachineConfig(eye_clearance=20.0, robot=True)
    env = eye_envelope(bend, machine)
    guide = make_guide(bend, env)
    x, tan, _ = guide.evaluate(np.array([0.5 * guide.T]))
    u = np.cross(tan[0], [0.0, 0.0, 1.0]) if abs(tan[0, 2]) < 0.9 else np.cross(tan[0], [1.0, 0.0, 0.0])
    u /= np.linalg.norm(u)
    v = np.cross(tan[0], u)
    half = np.radians(30.0)
    poses = np.array([np.concatenate([x[0] + 60.0 * (np.cos(a) * u + np.sin(a) * v), -u]) for a in (-half, half)])
    dip = 60.0 * np.cos(half) - TUBE_R  # 11.96 mm from the tube at the chord's middle
    with pytest.raises(ExportError, match=rf"pass X: the payout eye \(size 0 mm\) comes within {dip:.3f} mm of "
                                          r"the mandrel on the move to X[-\d.]+ Y[-\d.]+ Z[-\d.]+, closer than 19\.950"):
        check_collision(poses, env, machine, lambda row: "pass X", guide)
    check_collision(poses, env, machine, lambda row: "pass X", guide, joins=np.array([1]))


@pytest.mark.parametrize("profile", ["cylinder", "dome"])
def test_copies_of_moves_are_sampled_once_and_never_further(profile):
    """Moves repeated with round-off noise on their ends (the eye paths of turned circuits), some
    exactly: each sample within CUT_TOL of its own brute-force distance and never above it by more than
    round-off (the shared sampling takes the 1-Lipschitz bound: it may only come nearer)."""
    t = np.linspace(0.0, 200.0, 801)
    r = {"cylinder": np.full_like(t, 40.0),
         "dome": np.sqrt(np.maximum(100.0**2 - (t - 100.0) ** 2, 0.0)) * 0.5 + 10.0}[profile]
    env = type("Env", (), {"stations": t, "mandrel_radius": r})()
    rng = np.random.default_rng(11)
    # Short moves outside the part (its slope under 0.7 there: a 0.5 mm step rises under 0.35 mm).
    za = rng.uniform(20.0, 180.0, 300)
    zb = za + rng.uniform(-0.5, 0.5, za.size)
    ends = [np.interp(za, t, r) + rng.uniform(5.0, 30.0, za.size), za,
            np.interp(zb, t, r) + rng.uniform(5.0, 30.0, zb.size), zb]
    noisy = [np.tile(v, 40) + rng.uniform(-3e-11, 3e-11, 40 * v.size) * (rng.random(40 * v.size) < 0.5)
             for v in ends]
    rho0, z0, rho1, z1 = noisy
    f = np.linspace(0.0, 1.0, 5)
    got = sampled_moves(z0, rho0, z1, rho1, f, env)
    rho, z = rho0[:, None] + f * (rho1 - rho0)[:, None], z0[:, None] + f * (z1 - z0)[:, None]
    want = _brute_distance(rho.ravel(), z.ravel(), t, r).reshape(rho.shape)
    assert got == pytest.approx(want, abs=CUT_TOL)
    assert np.all(got <= want + ROUNDOFF_MM)
