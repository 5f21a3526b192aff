"""The winding program: parsed back, run through SPEC's forward kinematics, checked against the plan."""

from __future__ import annotations

import re

import numpy as np
import pytest

from conftest import surface_of
from plans import cylinder_plan, geodesic_pass, make_layer
from winder.config.axes import ArcAxis
from winder.config.mandrel import ConstantProfile, LineAxis
from winder.config.machine import MachineAxes, MachineConfig, MachineLimits
from winder.errors import ExportError
from winder.export.gcode import gcode_text, program_moves
from winder.machine.exact import ARRIVE_TURN, exact_points
from winder.machine.reduce import reduce_points
from winder.machine.smooth import SmoothPaths
from winder.winding.results import PassKind, WindingPlan

TANGENT_TOL = 0.01  # mm: a programmed eye from its contact point's tangent line (SPEC rounding: 3 decimals)
ROUND_SLACK = 0.002  # mm: what 3-decimal rounding may add to a chord deviation
PARSE_TOL = 1e-9  # a rounded value against its text read back: far below the printed 0.001
R = 40.0


@pytest.fixture(scope="module")
def tube():
    return surface_of(LineAxis(300.0), ConstantProfile(R))


@pytest.fixture(scope="module")
def plan(tube):
    return cylinder_plan(tube)


MACHINE = MachineConfig(eye_radius=60.0, eye_clearance=None, chord_tolerance=0.05)


def parse(text: str, letters: str = "XAZB") -> np.ndarray:
    """The G1 lines' axis values (n, 4) in the order of `letters`; checks F on every move."""
    rows = []
    for line in text.splitlines():
        if not line.startswith("G1 "):
            continue
        words = dict((w[0], float(w[1:])) for w in line.split()[1:])
        assert set(words) == set(letters) | {"F"}, line
        rows.append([words[c] for c in letters])
    return np.array(rows)


def forward_kinematics(vals: np.ndarray) -> np.ndarray:
    """SPEC: with the mandrel turned by A, the eye is at mandrel-frame (Z cos(-A), Z sin(-A), X)."""
    x, a, z = vals[:, 0], np.radians(vals[:, 1]), vals[:, 2]
    return np.column_stack([z * np.cos(-a), z * np.sin(-a), x])


def line_distance(e, p, d):
    rel = e - p
    return np.linalg.norm(rel - np.einsum("ij,ij->i", rel, d)[:, None] * d, axis=1)


def passes_by_key(plan):
    return {(fp.layer, fp.number): fp for layer in plan.layers for fp in layer.passes}


def test_preamble_header_and_end(plan):
    text = gcode_text(plan, MACHINE)
    lines = text.splitlines()
    first_code = [ln for ln in lines if not ln.startswith(";")][:3]
    assert first_code == ["G21", "G90", "G94"]
    assert lines[-1] == "M2" and text.endswith("\n")
    comments = "\n".join(ln for ln in lines if ln.startswith(";"))
    assert "job: tube-test" in comments and "source: tests/tube.yaml" in comments
    assert "layer 1: helical, angle 55.000 deg" in comments and "circuits 2, pattern 1" in comments
    assert "layer 2: hoop, angle 86.000 deg" in comments
    assert "; layer 1 circuit 2" in lines
    for ln in lines:
        assert ln.startswith((";", "G1 ")) or ln in ("G21", "G90", "G94", "M2"), ln


def test_round_trip_eye_on_tangent_lines(plan):
    """Every programmed eye (parsed, forward kinematics) is on the tangent line at its contact point,
    ahead of it, and on the eye cylinder."""
    text = gcode_text(plan, MACHINE)
    vals = parse(text)
    moves = program_moves(plan, MACHINE)
    assert len(moves) == len(vals)
    assert np.allclose(np.array([m.values for m in moves]), vals, rtol=0.0, atol=PARSE_TOL)
    eye = forward_kinematics(vals)
    by_key = passes_by_key(plan)
    p = np.array([by_key[(m.layer, m.number)].points[m.index] for m in moves])
    d = np.array([by_key[(m.layer, m.number)].direction[m.index] for m in moves])
    assert line_distance(eye, p, d).max() < TANGENT_TOL
    assert (np.einsum("ij,ij->i", eye - p, d) > 0).all()
    assert np.abs(vals[:, 2] - 60.0).max() < 1e-9
    assert np.abs(vals[:, 3]).max() < 90.0  # yaw from the hoop orientation: within +-90 here
    # Without the index map: the nearest tangent line of the pass's points.
    for m, e in zip(moves[::25], eye[::25]):
        fp = by_key[(m.layer, m.number)]
        assert line_distance(np.tile(e, (len(fp.points), 1)), fp.points, fp.direction).min() < TANGENT_TOL


def test_no_consecutive_identical_moves_and_deterministic(plan):
    text = gcode_text(plan, MACHINE)
    moves = [ln.split(" F")[0] for ln in text.splitlines() if ln.startswith("G1 ")]
    assert all(a != b for a, b in zip(moves, moves[1:]))
    assert gcode_text(plan, MACHINE) == text
    assert not re.search(r"-0\.000(?![0-9])", text)


def test_duplicate_points_give_one_move(tube):
    """A pass repeating its points (and the next pass starting where it ended) writes each move once."""
    base = cylinder_plan(tube, circuits=1, hoop=False, points=20)
    fp = base.layers[0].passes[0]
    twice = fp.__class__(**{**fp.__dict__, **{k: np.repeat(getattr(fp, k), 2, axis=0) for k in
                                              ("t", "s", "theta", "points", "direction", "alpha_deg")}})
    plan = WindingPlan("dup", "dup.yaml", tube, (make_layer(1, [twice, *base.layers[0].passes[1:]]),))
    lines = [ln.split(" F")[0] for ln in gcode_text(plan, MACHINE).splitlines() if ln.startswith("G1 ")]
    assert all(a != b for a, b in zip(lines, lines[1:]))


def test_chord_tolerance_respected(plan):
    """Dropped points lie within chord_tolerance of the kept move. Their eye positions are recomputed
    here (closed form on the cylinder); their axis values X = E_z, Z = |E_xy|, A = -(theta + lead)
    are compared with the straight axis-space move in mm (A as the arc at the 60 mm eye radius), and
    the eye itself with the move's eye in 3D at the same point of the move."""
    tol = 0.05
    moves = program_moves(plan, MACHINE)
    by_key = passes_by_key(plan)
    total = sum(len(fp.points) for fp in by_key.values())
    assert len(moves) < total / 3  # the helices reduce a lot: A, X, Z are linear on a cylinder
    kept: dict = {}
    for m in moves:
        kept.setdefault((m.layer, m.number), []).append(m.index)
    moves_by = {(m.layer, m.number, m.index): np.array(m.values) for m in moves}
    checked = 0
    for key, fp in by_key.items():
        idx = np.array(kept[key])
        assert idx[0] == 0 and idx[-1] == len(fp.points) - 1
        lam = np.sqrt(60.0**2 - R**2) / np.hypot(fp.direction[:, 0], fp.direction[:, 1])
        e = fp.points + lam[:, None] * fp.direction
        lead = np.angle(np.exp(1j * (np.arctan2(e[:, 1], e[:, 0]) - fp.theta)))
        a = -(fp.theta + lead)  # radians, up to the program's whole turns for this pass
        a += 2 * np.pi * np.round((np.radians(moves_by[key + (0,)][1]) - a[0]) / (2 * np.pi))
        axis = np.column_stack([e[:, 2], np.hypot(e[:, 0], e[:, 1]), a * 60.0])
        for i0, i1 in zip(idx[:-1], idx[1:]):
            if i1 - i0 < 2:
                continue
            v0, v1 = moves_by[key + (i0,)], moves_by[key + (i1,)]
            q0 = np.array([v0[0], v0[2], np.radians(v0[1]) * 60.0])
            q1 = np.array([v1[0], v1[2], np.radians(v1[1]) * 60.0])
            seg = q1 - q0
            rel = axis[i0 + 1:i1] - q0
            u = np.clip(rel @ seg / (seg @ seg), 0.0, 1.0)
            dev = np.linalg.norm(rel - u[:, None] * seg, axis=1)
            assert dev.max() < tol + ROUND_SLACK
            on_move = forward_kinematics(v0[None, :] + u[:, None] * (v1 - v0)[None, :])
            assert np.linalg.norm(e[i0 + 1:i1] - on_move, axis=1).max() < tol + ROUND_SLACK
            checked += i1 - i0 - 1
    assert checked > 500


def test_reduce_points_guarantee():
    rng = np.random.default_rng(7)
    q = np.cumsum(rng.normal(size=(400, 3)) * 0.02, axis=0)
    keep = reduce_points(q, 0.05)
    assert keep[0] == 0 and keep[-1] == 399 and len(keep) < 400
    for a, b in zip(keep[:-1], keep[1:]):
        seg = q[b] - q[a]
        for j in range(a + 1, b):
            u = np.clip((q[j] - q[a]) @ seg / (seg @ seg), 0, 1)
            assert np.linalg.norm(q[j] - q[a] - u * seg) <= 0.05 + 1e-12


def test_a_cumulative_across_layers(plan):
    """Layer 2's angles restart near 0; the program turns on (A keeps decreasing with theta+) from
    where layer 1 ended, by less than a turn."""
    moves = program_moves(plan, MACHINE)
    vals = np.array([m.values for m in moves])
    first2 = next(i for i, m in enumerate(moves) if m.layer == 2)
    a_end, a_start = vals[first2 - 1, 1], vals[first2, 1]
    assert -360.0 < a_start - a_end <= 0.0
    assert a_start < -1000.0  # not restarted near 0
    # The mandrel turns one way throughout (theta increases in every pass, so A decreases).
    assert (np.diff(vals[:, 1]) <= 0.0).all()


def test_custom_axis_letters(plan):
    machine = MachineConfig(axes=MachineAxes("U", "C", "W", "V"), eye_radius=60.0, eye_clearance=None)
    text = gcode_text(plan, machine)
    vals = parse(text, "UCWV")
    assert np.array_equal(vals, parse(gcode_text(plan, MACHINE)))


def test_carriage_limits_narrower_than_mandrel(plan):
    machine = MachineConfig(eye_radius=60.0, eye_clearance=None, limits=MachineLimits(carriage=(0.0, 250.0)))
    with pytest.raises(ExportError) as err:
        gcode_text(plan, machine)
    msg = str(err.value)
    assert msg.startswith("tests/tube.yaml: layer 1 circuit 1 pass 1 (forward): machine.limits.carriage: axis X")
    assert "outside the limits [0, 250] mm" in msg


def test_cross_feed_limit(plan):
    machine = MachineConfig(eye_clearance=20.0, limits=MachineLimits(cross_feed=(0.0, 55.0)))
    with pytest.raises(ExportError, match=r"machine.limits.cross_feed: axis Z .* 60.000 mm"):
        gcode_text(plan, machine)


def test_clearance_mode_program(plan):
    machine = MachineConfig(eye_clearance=20.0)
    vals = parse(gcode_text(plan, machine))
    assert np.abs(vals[:, 2] - 60.0).max() < 1e-9


def test_robot_poses_for_bent_mandrel():
    bend = surface_of(ArcAxis(150.0, 90.0), ConstantProfile(40.0))
    fw = geodesic_pass(bend, (20.0, 0.0), (215.0, np.radians(150.0)), 100, rounds=1, layer=1, circuit=1,
                       number=1, kind=PassKind.FORWARD)
    rt = geodesic_pass(bend, (215.0, np.radians(150.0)), (20.0, np.radians(300.0)), 100, rounds=1, layer=1,
                       circuit=1, number=2, kind=PassKind.RETURN)
    plan = WindingPlan("elbow", "elbow.yaml", bend, (make_layer(1, [fw, rt], circuits=1),))
    machine = MachineConfig(eye_clearance=20.0, robot=True)
    text = gcode_text(plan, machine)
    assert text == gcode_text(plan, machine)
    poses = []
    for ln in text.splitlines():
        if ln.startswith("G1 "):
            w = dict((x[0], float(x[1:])) for x in ln.split()[1:])
            assert set(w) == set("XYZBCF")
            b, c = np.radians(w["B"]), np.radians(w["C"])  # the fiber's direction: B from +Z, C about +Z
            poses.append([w["X"], w["Y"], w["Z"], np.sin(b) * np.cos(c), np.sin(b) * np.sin(c), np.cos(b)])
    poses = np.array(poses)
    moves = program_moves(plan, machine)
    assert len(moves) == len(poses)
    # Each pose's contact point at its fractional index on the smooth path (a densified pass's rows
    # lie between the planned points, which are every factor-th row).
    paths = SmoothPaths(bend, [fw, rt])
    number = {(fp.layer, fp.number): j for j, fp in enumerate((fw, rt))}
    u = np.array([paths.offset[number[(m.layer, m.number)]] + m.u for m in moves])
    _, _, p, d = paths.point(u)
    assert line_distance(poses[:, :3], p, d).max() < TANGENT_TOL
    # The direction as written (6 decimals of a degree: 1e-6 below): at a planned point the plan's own;
    # between planned points the exact fiber's (winder.machine.exact: the geodesic's ODE from the
    # interval's planned point), which a robot's dense poses read since b043ddf, not the smooth path's
    # Hermite interpolant: the two agree only within the exact fiber's arrival test (ARRIVE_TURN,
    # 1e-5 rad; 4.8e-6 on this elbow), so the smooth path is held to that, not to the written digits.
    node = u == np.floor(u)
    planned = np.concatenate([fw.direction, rt.direction])[(u[node]).astype(int)]
    planned /= np.linalg.norm(planned, axis=1)[:, None]
    assert node.sum() > 100 and np.allclose(poses[node, 3:], -planned, atol=1e-6)
    _, _, _, d_exact = exact_points(paths, u)
    assert np.allclose(poses[:, 3:], -d_exact, atol=1e-6)
    assert np.allclose(poses[:, 3:], -d, atol=ARRIVE_TURN)
    # The eye (from its contact point, back along I J K) is ahead of the contact point.
    assert (np.einsum("ij,ij->i", poses[:, :3] - p, d) > 0).all()
    assert "G21" in text.splitlines() and "; X Y Z: eye position (mm); B C:" in text


def test_robot_envelope_inside_mandrel_names_the_pass():
    bend = surface_of(ArcAxis(150.0, 90.0), ConstantProfile(40.0))
    fw = geodesic_pass(bend, (20.0, 0.0), (215.0, np.radians(150.0)), 40, layer=1, circuit=1, number=1,
                       kind=PassKind.FORWARD)
    plan = WindingPlan("elbow", "elbow.yaml", bend, (make_layer(1, [fw], circuits=1),))
    machine = MachineConfig(eye_radius=30.0, eye_clearance=None, robot=True)
    with pytest.raises(ExportError, match=r"^elbow.yaml: layer 1 circuit 1 pass 1 \(forward\): the eye envelope"):
        gcode_text(plan, machine)


def test_yaw_header_and_values_agree(plan):
    """The header's rule, checked on the values written: on a cylinder of radius R with the eye at
    Z, tan(B) = Z / (R tan(alpha)) on fiber moves (+ forward, - return), B = 0 on dwells."""
    text = gcode_text(plan, MACHINE)
    assert "tan(B) = Z / (R tan(alpha))" in text
    moves = program_moves(plan, MACHINE)
    by_key = passes_by_key(plan)
    checked = 0
    for m in moves:
        fp = by_key[(m.layer, m.number)]
        if fp.kind not in (PassKind.FORWARD, PassKind.RETURN):
            continue
        alpha = np.radians(abs(fp.alpha_deg[m.index]))
        want = np.degrees(np.arctan2(60.0, R * np.tan(alpha)))
        want = want if fp.kind is PassKind.FORWARD else -want
        assert m.values[3] == pytest.approx(want, abs=1.5e-3), (m, fp.kind)  # 3 decimals written
        checked += 1
    assert checked > 4
