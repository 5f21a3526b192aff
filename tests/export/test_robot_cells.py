"""Robot cells (docs/math/10-robot-cell.md): KRL, RAPID and URScript programs of a bent mandrel read by
structural readers written here, an independent forward kinematics (tests/machine/test_arm_ik.py) from
each program's written poses to the arm's joints, the program's time against the summary's, simulate
reading each back, and an elbow out of reach refused naming the pose and the joint.

The full jobs of samples/elbow.yaml, configs/elbow.yaml and configs/spline_tube.yaml take a minute or
more each: WINDER_NIGHTLY=1 runs them (`WINDER_NIGHTLY=1 pytest tests/export/test_robot_cells.py`);
the fast tests use a shorter elbow with a wider band.
"""

from __future__ import annotations

import dataclasses
import json
import os
import re
from pathlib import Path

import numpy as np
import pytest

from tests.cells import CELLS, SMALL_ELBOW, small_elbow_cells
from tests.machine.test_arm_ik import independent_fk
from winder.app.jobs import run_job
from winder.app.simulate import simulate
from winder.config.arms import ARMS
from winder.config.job import load_config
from winder.config.robot import Pose, RobotCell
from winder.errors import ExportError
from winder.export.dialects import krl, rapid, urscript
from winder.machine.program import build_program as program_of
from winder.export.summary import summary_dict
from winder.machine.cell import cell_motion
from winder.machine.envelope import eye_envelope
from winder.machine.kinematics import make_guide
from winder.winding.plan import plan as plan_job

ROOT = Path(__file__).resolve().parents[2]
FK_TOL_MM = 0.01
FK_TOL_DEG = 0.01
TIME_TOL = 0.01  # relative
QUATERNION_TOL = 1e-8
CYCLE_S = 0.002  # the UR e-Series control cycle
MOVING_M = 1e-6  # a TCP step of more than a micrometre: the arm moves
def _matrix(p: Pose) -> np.ndarray:
    """Rz(rz) Ry(ry) Rx(rx) with the translation, written here with plain matrices."""
    a, b, c = np.radians([p.rz, p.ry, p.rx])
    rz = np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])
    ry = np.array([[np.cos(b), 0, np.sin(b)], [0, 1, 0], [-np.sin(b), 0, np.cos(b)]])
    rx = np.array([[1, 0, 0], [0, np.cos(c), -np.sin(c)], [0, np.sin(c), np.cos(c)]])
    t = np.eye(4)
    t[:3, :3], t[:3, 3] = rz @ ry @ rx, (p.x, p.y, p.z)
    return t


@pytest.fixture(scope="module")
def job_plan():
    job, plan, _ = small_elbow_cells()
    return job, plan


@pytest.fixture(scope="module")
def programs():
    """The program on each arm's cell: {arm: (machine, program)}."""
    return small_elbow_cells()[2]


def _krl_points(dat: str) -> dict[str, dict[str, float]]:
    found = {}
    for m in re.finditer(r"^DECL E6POS (\w+)=\{([^}]*)\}$", dat, re.M):
        found[m[1]] = {k: float(v) for k, v in (part.split() for part in m[2].split(","))}
    return found


def test_krl_structure_and_time(job_plan, programs) -> None:
    machine, program = programs["kuka_kr16"]
    texts = krl.serialize(program)
    src, dat = texts[".src"].splitlines(), texts[".dat"].splitlines()
    code = [line for line in src if line.strip() and not line.startswith((";", "&"))]
    assert code[0] == "DEF small_elbow( )" and code[-1] == "END"
    dat_code = [line for line in dat if not line.startswith("&")]
    assert dat_code[0] == "DEFDAT small_elbow PUBLIC" and dat_code[-1] == "ENDDAT"
    points = _krl_points(texts[".dat"])
    lins = [line.split()[1] for line in code if line.startswith("LIN ")]
    assert len(lins) == len(points) == len(set(lins))  # one E6POS per LIN
    assert all(set(p) >= {"X", "Y", "Z", "A", "B", "C", "S", "T", "E1", "E2", "E3"} for p in points.values())
    total, vel = 0.0, None
    prev = None
    for line in code:
        if line.startswith("$VEL.CP"):
            vel = float(line.split("=")[1])
        if line.startswith("LIN "):
            p = points[line.split()[1]]
            if prev is not None:
                total += np.linalg.norm([p[k] - prev[k] for k in "XYZ"]) / (vel * 1000.0)
            prev = p
    expected = summary_dict(job_plan[1], machine, program)["winding_time_s"]
    assert abs(total - expected) <= TIME_TOL * expected


def test_rapid_structure_and_time(job_plan, programs) -> None:
    machine, program = programs["abb_irb4600"]
    text = rapid.serialize(program)[".mod"]
    lines = [line.strip() for line in text.splitlines() if line.strip() and not line.strip().startswith("!")]
    assert lines[0] == "MODULE small_elbow" and lines[-1] == "ENDMODULE"
    assert "PROC main()" in lines and lines[-2] == "ENDPROC"
    quats = [np.array(m[1].split(","), dtype=float)
             for m in re.finditer(r"robtarget \w+ := \[\[[^\]]*\],\[([^\]]*)\]", text)]
    assert quats and all(abs(np.linalg.norm(q) - 1.0) < QUATERNION_TOL for q in quats)
    times = [float(t) for t in re.findall(r"^\s*MoveL \w+, v1000 \\T:=([0-9.]+), z0, tRing \\WObj:=wMandrel;$",
                                          text, re.M)]
    assert len(times) == len(quats)
    expected = summary_dict(job_plan[1], machine, program)["winding_time_s"]
    assert abs(sum(times) - expected) <= TIME_TOL * expected


def test_urscript_structure_and_time(job_plan, programs) -> None:
    """Every movel at least the 2 ms cycle, blended (r > 0) wherever the arm moves into and out of its
    waypoint, its ring line before it; the times add up to the summary's."""
    machine, program = programs["ur10e"]
    text = urscript.serialize(program)[".script"]
    lines = [line for line in text.splitlines() if line.strip() and not line.strip().startswith("#")]
    assert lines[0] == "def small_elbow():" and lines[-1] == "end"
    moves = re.findall(r"^ +movel\(p\[([^\]]*)\], a=[0-9.]+, v=[0-9.]+, t=([0-9.]+), r=([0-9.]+)\)$", text, re.M)
    assert moves and len(re.findall(r"^ +ring\(", text, re.M)) == len(moves) + 1
    times = np.array([float(t) for _, t, _ in moves])
    radii = np.array([float(r) for _, _, r in moves])
    xyz = np.array([[float(v) for v in p.split(",")[:3]] for p, _, _ in moves])
    assert times.min() >= CYCLE_S
    step = np.linalg.norm(np.diff(xyz, axis=0), axis=1)
    moving = (step[:-1] > MOVING_M) & (step[1:] > MOVING_M)  # waypoints the arm moves into and out of
    assert np.all(radii[1:-1][moving] > 0.0) and radii[-1] == 0.0
    expected = summary_dict(job_plan[1], machine, program)["winding_time_s"]
    assert abs(times.sum() - expected) <= TIME_TOL * expected


def _quat_matrix(q) -> np.ndarray:
    """The rotation of a unit quaternion (w, x, y, z), written out here."""
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def _rotvec_matrix(v) -> np.ndarray:
    """The rotation of a rotation vector (Rodrigues), written out here."""
    angle = float(np.linalg.norm(v))
    if angle == 0.0:
        return np.eye(3)
    k = np.asarray(v) / angle
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * kx + (1 - np.cos(angle)) * kx @ kx


def written_flanges(arm: str, program, cell: RobotCell) -> tuple[np.ndarray, list[np.ndarray]]:
    """(the start joints (deg), the flange (4, 4) of every written pose) read from the program's text
    with this test's own parsing and frames: KRL's E6POS and RAPID's robtargets hold the ring in the
    mandrel frame (flange = base^-1 ring S^-1 tool^-1), URScript's movel the mandrel in the base."""
    need = np.linalg.inv(_matrix(cell.base)) @ _matrix(cell.ring)
    tool_inv = np.linalg.inv(_matrix(cell.tool))
    frames = []
    if arm == "kuka_kr16":
        texts = krl.serialize(program)
        start = [float(v) for v in re.search(r"^PTP \{A1 ([^,]+),A2 ([^,]+),A3 ([^,]+),A4 ([^,]+),A5 ([^,]+),A6 ([^,]+),",
                                              texts[".src"], re.M).groups()]
        for p in _krl_points(texts[".dat"]).values():
            frames.append(_matrix(Pose(p["X"], p["Y"], p["Z"], p["C"], p["B"], p["A"])))
    elif arm == "abb_irb4600":
        text = rapid.serialize(program)[".mod"]
        start = [float(v) for v in re.search(r"jointtarget jStart := \[\[([^\]]*)\]", text)[1].split(",")]
        for m in re.finditer(r"robtarget \w+ := \[\[([^\]]*)\],\[([^\]]*)\]", text):
            t = np.eye(4)
            t[:3, :3], t[:3, 3] = _quat_matrix([float(v) for v in m[2].split(",")]), [float(v) for v in m[1].split(",")]
            frames.append(t)
    else:
        text = urscript.serialize(program)[".script"]
        start = np.degrees([float(v) for v in re.search(r"^  movej\(\[([^\]]*)\]", text, re.M)[1].split(",")])
        flanges = []
        for m in re.finditer(r"^ +movel\(p\[([^\]]*)\]", text, re.M):
            v = [float(x) for x in m[1].split(",")]
            t = np.eye(4)
            t[:3, :3], t[:3, 3] = _rotvec_matrix(v[3:]), 1000.0 * np.array(v[:3])
            flanges.append(t @ tool_inv)  # the pose is the mandrel frame in the controller's base
        return np.asarray(start), flanges
    return np.asarray(start), [need @ np.linalg.inv(f) @ tool_inv for f in frames]


@pytest.mark.parametrize("arm", sorted(CELLS))
def test_start_joints_are_the_first_pose(programs, arm: str) -> None:
    """The start joints as written, through the forward kinematics written in tests/machine/test_arm_ik.py
    from the published DH and URDF numbers, put the flange on the first written pose within 0.01 mm."""
    machine, program = programs[arm]
    start, flanges = written_flanges(arm, program, machine.cell)
    got = independent_fk(arm, start)
    assert np.linalg.norm(got[:3, 3] - flanges[0][:3, 3]) < FK_TOL_MM
    turn = got[:3, :3].T @ flanges[0][:3, :3]
    assert np.degrees(np.arccos(np.clip((np.trace(turn) - 1.0) / 2.0, -1.0, 1.0))) < FK_TOL_DEG


@pytest.mark.parametrize("arm", sorted(CELLS))
def test_joints_land_on_every_written_pose(programs, arm: str) -> None:
    """The planned joints through the independent forward kinematics land on the flange each written
    pose needs (KRL's E6POS, RAPID's robtargets, URScript's movel poses), within 0.01 mm and 0.01 deg."""
    machine, program = programs[arm]
    motion = program.cell
    q = motion.reach.arrive
    limits = ARMS[arm].limits
    assert np.all(q >= limits[:, 0]) and np.all(q <= limits[:, 1])
    _, flanges = written_flanges(arm, program, machine.cell)
    rows = [row for _, row in krl_rows(program)]
    assert len(rows) == len(flanges)
    for k, flange in zip(rows, flanges):
        got = independent_fk(arm, q[k])
        assert np.linalg.norm(got[:3, 3] - flange[:3, 3]) < FK_TOL_MM
        turn = got[:3, :3].T @ flange[:3, :3]
        angle = np.degrees(np.arccos(np.clip((np.trace(turn) - 1.0) / 2.0, -1.0, 1.0)))
        assert angle < FK_TOL_DEG


def krl_rows(program):
    from winder.export.dialects.robot_text import rows  # noqa: PLC0415

    return list(rows(program))


@pytest.mark.parametrize(("arm", "language"), [("kuka_kr16", "krl"), ("abb_irb4600", "rapid"), ("ur10e", "urscript")])
def test_simulate_reads_back(job_plan, programs, arm: str, language: str) -> None:
    machine, program = programs[arm]
    module = {"krl": krl, "rapid": rapid, "urscript": urscript}[language]
    texts = module.serialize(program)
    text = "".join(texts[k] for k in sorted(texts, key=lambda s: s != ".src"))
    sim = simulate(machine, job_plan[1], text, f"program.{language}")
    assert sim.dialect == language
    assert sim.max_deviation_mm <= machine.chord_tolerance
    assert abs(sim.time_s - program.times.total_s) <= TIME_TOL * program.times.total_s
    assert abs(sim.fiber_length_mm - sim.planned_fiber_length_mm) <= 1e-3 * sim.planned_fiber_length_mm


def test_out_of_reach_refused_naming_the_pose_and_joint(job_plan) -> None:
    job, plan = job_plan
    machine = dataclasses.replace(job.machine, cell=RobotCell("kuka_kr16", ring=Pose(x=1000, z=1100, ry=-90, rz=-90)))
    env = eye_envelope(plan.outer_surface, machine)
    program = program_of(plan, dataclasses.replace(job.machine, cell=None, robot=True))
    with pytest.raises(ExportError) as info:
        cell_motion(machine, make_guide(plan.outer_surface, env), program.values, program.fiber,
                    lambda row: f"layer 1 circuit 1 pass {row}")
    message = str(info.value)
    assert re.search(r"layer 1 circuit 1 pass \d+", message) and "joint A5" in message and re.search(r"limit -?130 deg", message)


def test_run_refuses_before_writing(tmp_path) -> None:
    config = tmp_path / "far.yaml"
    config.write_text(SMALL_ELBOW.replace("robot: {arm: kuka_kr16}", "robot: {arm: kuka_kr16, positioner: "
                                          "{origin: {x: 2200, z: 800, ry: -90, rz: -90}}}"))
    report = run_job(config, tmp_path / "out", formats=("csv",))
    assert report.exit_code == 1 and not report.outputs
    assert "circuit" in report.message and "pass" in report.message and "joint" in report.message
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())


NIGHTLY = pytest.mark.skipif(not os.environ.get("WINDER_NIGHTLY"), reason="WINDER_NIGHTLY not set (minutes per job)")


@NIGHTLY
@pytest.mark.parametrize("config", ["samples/elbow.yaml", "configs/elbow.yaml", "configs/spline_tube.yaml"])
def test_shipped_cells(tmp_path, config: str) -> None:
    job = load_config(ROOT / config)
    plan = plan_job(job)
    program = program_of(plan, job.machine)
    module = {"krl": krl, "rapid": rapid, "urscript": urscript}[job.machine.dialect]
    texts = module.serialize(program)
    text = "".join(texts[k] for k in sorted(texts, key=lambda s: s != ".src"))
    sim = simulate(job.machine, plan, text, config)
    assert sim.max_deviation_mm <= job.machine.chord_tolerance
    expected = summary_dict(plan, job.machine)["winding_time_s"]
    assert abs(sim.time_s - expected) <= TIME_TOL * expected


def test_each_language_for_its_arm(programs) -> None:
    """A language only for the arm whose controller runs it: KRL for the KUKA, RAPID for the ABB,
    URScript for the UR; each refuses the others."""
    for arm, (_, program) in programs.items():
        for module, language in ((krl, "krl"), (rapid, "rapid"), (urscript, "urscript")):
            if ARMS[arm].language == language:
                assert module.serialize(program)
            else:
                with pytest.raises(ExportError, match=f"the cell's arm is {arm}"):
                    module.serialize(program)


def test_check_refuses_a_ring_beyond_the_arm(tmp_path) -> None:
    from winder.app.validate import validate  # noqa: PLC0415
    from winder.errors import ConfigError  # noqa: PLC0415

    config = tmp_path / "far.yaml"
    config.write_text(SMALL_ELBOW.replace("robot: {arm: kuka_kr16}", "robot: {arm: kuka_kr16, positioner: "
                                          "{origin: {x: 4000, z: 800, ry: -90, rz: -90}}}"))
    with pytest.raises(ConfigError, match="machine.robot.positioner.origin: the ring is 4079 mm") as info:
        validate(config)
    assert info.value.exit_code == 2


def test_ring_too_close_to_a_link_refused_naming_it(job_plan) -> None:
    """A ring 300 mm up beside the UR10e's base: the base link's capsule (fitted to ROS-Industrial's
    collision mesh) touches the ring, refused (exit 1) naming the link, the layer and the pass."""
    job, plan = job_plan
    machine = dataclasses.replace(job.machine, cell=RobotCell("ur10e", ring=Pose(x=500, z=300, ry=-90, rz=-90)))
    with pytest.raises(ExportError, match=r"layer 1 circuit \d+ pass \d+ .*the ur10e's link 1 \(base\) comes within 5 mm "
                                          r"of the ring") as info:
        program_of(plan, machine)
    assert info.value.exit_code == 1


def test_krl_structure(programs) -> None:
    """No KRL grammar installs from PyPI (krllint checks style only): a structural check of the .src
    and .dat against KSS 8's syntax: DEF/END and DEFDAT/ENDDAT, names of at most 24 characters, every
    statement one winder writes, every LIN's point declared once in the .dat as a full E6POS."""
    _, program = programs["kuka_kr16"]
    texts = krl.serialize(program)
    statements = (r"&ACCESS RVP", r"&REL 1", r"DEF [A-Za-z_]\w{0,23}\( \)", r"BAS\(#INITMOV, 0\)", r"END",
                  r"\$(TOOL|BASE) = \{X [-0-9.]+,Y [-0-9.]+,Z [-0-9.]+,A [-0-9.]+,B [-0-9.]+,C [-0-9.]+\}( +;.*)?",
                  r"\$IPO_MODE = #TCP", r"\$APO\.CDIS = [0-9.]+", r"\$VEL_EXTAX\[[1-6]\] = [0-9.]+", r"\$VEL\.CP = [0-9.]+",
                  r"PTP \{(A[1-6] [-0-9.]+,){6}(E[1-3] [-0-9.]+,){2}E3 [-0-9.]+\}( +;.*)?", r"LIN P\d+( C_DIS)?")
    src = [line.strip() for line in texts[".src"].splitlines() if line.strip() and not line.strip().startswith(";")]
    for line in src:
        assert any(re.fullmatch(s, line) for s in statements), line
    assert src[2].startswith("DEF ") and src[-1] == "END" and src.count("END") == 1
    dat = [line for line in texts[".dat"].splitlines() if line.strip()]
    assert dat[:3] == ["&ACCESS RVP", "&REL 1", "DEFDAT small_elbow PUBLIC"] and dat[-1] == "ENDDAT"
    keys = "X Y Z A B C S T E1 E2 E3 E4 E5 E6".split()
    entry = r"DECL E6POS P\d+=\{" + ",".join(f"{k} [-0-9.]+" for k in keys) + r"\}"
    assert all(re.fullmatch(entry, line) for line in dat[3:-1])
    lins = [line.split()[1] for line in src if line.startswith("LIN ")]
    assert sorted(lins) == sorted(line.split()[2].split("=")[0] for line in dat[3:-1])


def test_rapid_through_its_grammar(programs) -> None:
    """The .mod through rapidchecker's RAPID grammar (pyparsing), on a module of the program's first
    and last moves (the grammar parses a whole 6,000-move module too slowly for the fast suite)."""
    check_format = pytest.importorskip("rapidchecker.check").check_format
    _, program = programs["abb_irb4600"]
    lines = rapid.serialize(program)[".mod"].splitlines()
    moves = [i for i, line in enumerate(lines) if line.strip().startswith("MoveL ")]
    keep = set(moves[:8] + moves[-8:])
    names = {re.search(r"MoveL (\w+),", lines[i])[1] for i in keep}
    short = [line for i, line in enumerate(lines)
             if not (line.strip().startswith(("MoveL ", "CONST robtarget")) or line.strip().startswith("!"))
             or i in keep or (line.strip().startswith("CONST robtarget") and line.split()[2] in names)]
    assert check_format("\n".join(short) + "\n") == []


def test_another_arms_language_refused_before_planning(tmp_path) -> None:
    """`--format krl` for a UR cell: exit 2 before any planning, nothing written."""
    config = tmp_path / "ur.yaml"
    config.write_text(SMALL_ELBOW.replace("robot: {arm: kuka_kr16}", "robot: {arm: ur10e}"))
    report = run_job(config, tmp_path / "out", formats=("krl",))
    assert report.exit_code == 2 and not report.outputs
    assert "KRL is not the language of the cell's arm: ur10e's Universal Robots controller runs urscript" in report.message


def test_krl_serialized_once_per_program(monkeypatch, job_plan, programs) -> None:
    """The .src and the .dat are two formats of one serialization (winder.export.robot_programs)."""
    from winder.export import robot_programs  # noqa: PLC0415

    _, program = programs["kuka_kr16"]
    calls = []
    real = krl.serialize
    monkeypatch.setattr(krl, "serialize", lambda p: calls.append(p) or real(p))
    job, plan = job_plan
    src = robot_programs.krl_src(plan, job, program)
    dat = robot_programs.krl_dat(plan, job, program)
    assert src.startswith("&ACCESS") and dat.startswith("&ACCESS") and len(calls) == 1


def _limited(program, limit: int):
    """The program with its cell's program limit set to limit bytes."""
    cell = dataclasses.replace(program.cell, cell=dataclasses.replace(program.cell.cell, program_limit=limit))
    return dataclasses.replace(program, cell=cell)


def _joined(texts: dict[str, str]) -> str:
    """The texts as simulate reads a program's files (winder.readback.program_file): every .src, the
    main one first, then every .dat."""
    return "".join(texts[k] for k in sorted(texts, key=lambda s: (s.endswith(".dat"), s not in (".src", ".dat"), s)))


def _close(a, b, path: str = "") -> None:
    """Two simulate summaries equal: numbers within 1e-9 relative (1e-6 absolute), line numbers aside."""
    if isinstance(a, dict):
        assert set(a) == set(b), path
        for k in a:
            if "line" not in k:
                _close(a[k], b[k], f"{path}.{k}")
    elif isinstance(a, (list, tuple)):
        assert len(a) == len(b), path
        for i, (x, y) in enumerate(zip(a, b)):
            _close(x, y, f"{path}[{i}]")
    elif isinstance(a, float) and isinstance(b, (int, float)):
        assert abs(a - b) <= 1e-6 + 1e-9 * abs(a), (path, a, b)
    else:
        assert a == b, (path, a, b)


SPLIT = {  # language: (the main program's call of layer 1, its definition)
    "krl": (r"^small_elbow_L1\( \)  ; .*$", r"^DEF small_elbow_L1\( \)$"),
    "rapid": (r"^    layer_1;$", r"^  PROC layer_1\(\)$"),
    "urscript": (r"^  layer_1\(\)$", r"^  def layer_1\(\):$"),
}


@pytest.mark.parametrize(("arm", "language"), [("kuka_kr16", "krl"), ("abb_irb4600", "rapid"), ("ur10e", "urscript")])
def test_split_reads_back_as_the_whole(job_plan, programs, arm: str, language: str) -> None:
    """A limit below the program's size (docs/math/10-robot-cell.md 10.10) writes each layer as a
    subprogram the main program calls once; simulate reads it as the whole program: the same summary
    (fiber, time, deviations) but for the lines it names."""
    from winder.config.robot import MIN_PROGRAM_LIMIT, PROGRAM_LIMIT  # noqa: PLC0415

    machine, program = programs[arm]
    module = {"krl": krl, "rapid": rapid, "urscript": urscript}[language]
    whole = module.serialize(program)
    assert sum(len(t) for t in whole.values()) <= PROGRAM_LIMIT[language]  # the small elbow fits
    assert not any(re.search(SPLIT[language][0], t, re.M) for t in whole.values())
    split = module.serialize(_limited(program, MIN_PROGRAM_LIMIT))
    main = next(t for k, t in split.items() if k != ".dat")
    calls = re.findall(r"(?im)^\s*(?:small_elbow_L|layer_)\d+(?:\( \)|;|\(\))(?:  ;.*)?$", main)
    assert len(calls) == len(program.layers) == 1
    assert re.search(SPLIT[language][0], main, re.M)
    if language == "krl":  # a .src + .dat pair per layer; the main .dat holds no point
        assert list(split) == [".src", ".dat", "_L1.src", "_L1.dat"]
        assert re.search(SPLIT[language][1], split["_L1.src"], re.M)
        assert split[".dat"].splitlines()[2:] == ["DEFDAT small_elbow PUBLIC", "ENDDAT"]
        assert split["_L1.dat"].splitlines()[3:] == whole[".dat"].splitlines()[3:]
        assert len(split[".src"]) < 2000 and "LIN " not in split[".src"]
    else:  # the layer a routine or function of the one file
        assert set(split) == set(whole)
        assert re.search(SPLIT[language][1], main, re.M)
    sims = [simulate(machine, job_plan[1], _joined(t), f"program.{language}") for t in (whole, split)]
    _close(sims[0].summary(), sims[1].summary())
    assert sims[1].time_s == pytest.approx(program.times.total_s, rel=TIME_TOL)


@pytest.mark.parametrize(("language", "break_it", "message"), [
    ("krl", lambda t: re.sub(r"\nsmall_elbow_L1\( \).*\n", "\n", t), "never called"),
    ("krl", lambda t: re.sub(r"\n(small_elbow_L1\( \).*)\n", r"\n\1\n\1\n", t), "called twice"),
    ("krl", lambda t: t.replace("DEFDAT small_elbow_L1 PUBLIC", "DEFDAT small_elbow_L2 PUBLIC"), "small_elbow_L1's"),
    ("rapid", lambda t: t.replace("    layer_1;", "    layer_2;"), "not defined"),
    ("urscript", lambda t: t.replace("\n  layer_1()\n", "\n"), "never called"),
])
def test_split_program_miscalled_refused(job_plan, programs, language, break_it, message) -> None:
    from winder.config.robot import MIN_PROGRAM_LIMIT  # noqa: PLC0415
    from winder.errors import ConfigError  # noqa: PLC0415

    arm = {"krl": "kuka_kr16", "rapid": "abb_irb4600", "urscript": "ur10e"}[language]
    machine, program = programs[arm]
    module = {"krl": krl, "rapid": rapid, "urscript": urscript}[language]
    texts = module.serialize(_limited(program, MIN_PROGRAM_LIMIT))
    text = break_it(_joined(texts))
    with pytest.raises(ConfigError, match=message):
        simulate(machine, job_plan[1], text, f"program.{language}")


def test_program_limit_in_config(tmp_path) -> None:
    """machine.robot.program_limit (bytes) is read, and one below MIN_PROGRAM_LIMIT refused."""
    from winder.errors import ConfigError  # noqa: PLC0415

    path = tmp_path / "small_elbow.yaml"
    path.write_text(SMALL_ELBOW.replace("robot: {arm: kuka_kr16}", "robot: {arm: kuka_kr16, program_limit: 5000}"))
    assert load_config(path).machine.cell.program_limit == 5000
    path.write_text(SMALL_ELBOW.replace("robot: {arm: kuka_kr16}", "robot: {arm: kuka_kr16, program_limit: 10}"))
    with pytest.raises(ConfigError, match="program_limit"):
        load_config(path)


def test_run_writes_a_split_krl_program_as_one_set(tmp_path, job_plan, programs) -> None:
    """`run` writes a KRL program past program_limit as the main .src + .dat and a .src + .dat per
    layer, in one set (winder.app.writes); simulate reads the main .src with the modules it calls
    as the whole program; a job name ending in _L and a number is refused."""
    from winder.app.simulate import simulate_files  # noqa: PLC0415
    from winder.config.robot import name_problem  # noqa: PLC0415

    config = tmp_path / "small_elbow.yaml"
    config.write_text(SMALL_ELBOW.replace("robot: {arm: kuka_kr16}", "robot: {arm: kuka_kr16, program_limit: 1000}"))
    report = run_job(config, tmp_path / "out", formats=("krl",), summary=False)
    assert report.ok, report.message
    names = [Path(p).name for p in report.outputs]
    assert names == ["small_elbow.src", "small_elbow_L1.src", "small_elbow_L1.dat", "small_elbow.dat"]
    got = json.loads(simulate_files(str(config), str(tmp_path / "out" / "small_elbow.src"), as_json=True))
    machine, program = programs["kuka_kr16"]  # the same cell, its program written whole
    whole = simulate(machine, job_plan[1], _joined(krl.serialize(program)), "program.src").summary()
    _close(whole, got)
    (tmp_path / "out" / "small_elbow_L1.dat").unlink()
    with pytest.raises(Exception, match="small_elbow_L1.dat"):
        simulate_files(str(config), str(tmp_path / "out" / "small_elbow.src"), as_json=True)
    assert name_problem("tank_L2", "krl") and name_problem("tank_L2", "rapid") is None


def test_krl_layer_module_name_within_24_characters() -> None:
    assert krl.layer_module("small_elbow", 12) == "small_elbow_L12"
    with pytest.raises(ExportError, match="24 characters: shorten the job's name to 21"):
        krl.layer_module("a" * 22, 1)


def test_two_layers_split_into_two_krl_modules(tmp_path) -> None:
    """A second layer on the small elbow, split: the main .src calls small_elbow_L1( ) then
    small_elbow_L2( ), each its own .src + .dat, and simulate reads them as the whole program."""
    from winder.config.robot import MIN_PROGRAM_LIMIT  # noqa: PLC0415

    path = tmp_path / "small_elbow.yaml"
    layer = "    - {type: helical, angle: 45, slip: auto}"
    path.write_text(SMALL_ELBOW.replace(layer, f"{layer}\n    - {{type: helical, angle: 55, slip: auto}}"))
    job = load_config(path)
    plan = plan_job(job)
    machine = dataclasses.replace(job.machine, cell=RobotCell("kuka_kr16", ring=CELLS["kuka_kr16"]))
    program = program_of(plan, machine)
    whole, split = krl.serialize(program), krl.serialize(_limited(program, MIN_PROGRAM_LIMIT))
    assert list(split) == [".src", ".dat", "_L1.src", "_L1.dat", "_L2.src", "_L2.dat"]
    calls = re.findall(r"^(small_elbow_L\d)\( \)", split[".src"], re.M)
    assert calls == ["small_elbow_L1", "small_elbow_L2"]
    points = [re.findall(r"^LIN (P\d+)", split[f"_L{k}.src"], re.M) for k in (1, 2)]
    assert points[0] and points[1] and int(points[0][-1][1:]) + 1 == int(points[1][0][1:])
    for k in (1, 2):  # each layer's points in its own .dat
        assert sorted(re.findall(r"^DECL E6POS (P\d+)=", split[f"_L{k}.dat"], re.M)) == sorted(points[k - 1])
    sims = [simulate(machine, plan, _joined(t), "program.src") for t in (whole, split)]
    _close(sims[0].summary(), sims[1].summary())
