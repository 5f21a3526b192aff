"""winder.app.simulate: programs of every dialect read back through the kinematics reproduce the
plan: eyes on the planned tangent lines, the fiber length, the machine time."""

from __future__ import annotations

import re

import os
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import functools

from conftest import surface_of
from every_job import job_of, planned
from plans import cylinder_plan
from winder.config.machine import MachineConfig
from winder.config.mandrel import ConstantProfile, LineAxis
from winder.errors import ConfigError
from winder.readback.contacts import ray_distance
from winder.app.simulate import simulate, simulate_files, simulation_csv
from winder.export.gcode import gcode_text
from winder.machine.program import build_program
from winder.machine.smooth import SmoothPaths
from winder.winding.plan import plan as plan_job

TANGENT_TOL = 0.01  # mm: a programmed eye from the exact tangent line (3-decimal axes)
LENGTH_TOL = 1e-6  # relative: laid fiber against the plan's
TIME_TOL = 1e-3  # relative: the program's time read back (rounded axes) against the plan's program
SAMPLES = Path(__file__).resolve().parents[2] / "samples"
MACHINE = MachineConfig(eye_radius=60.0, eye_clearance=None, chord_tolerance=0.05)


@pytest.fixture(scope="module")
def plan():
    return cylinder_plan(surface_of(LineAxis(300.0), ConstantProfile(40.0)))


@pytest.mark.parametrize("dialect", ["generic", "marlin", "linuxcnc"])
def test_round_trip_every_dialect(plan, dialect):
    machine = replace(MACHINE, dialect=dialect)
    sim = simulate(machine, plan, gcode_text(plan, machine, 10.0))
    assert sim.dialect == dialect
    assert sim.max_point_deviation_mm < TANGENT_TOL
    assert sim.max_deviation_mm < machine.chord_tolerance
    assert sim.fiber_length_mm == pytest.approx(plan.total_fiber_length_mm, rel=LENGTH_TOL)
    assert sim.time_s == pytest.approx(build_program(plan, machine).times.total_s, rel=TIME_TOL)
    lines = simulation_csv(sim).splitlines()
    assert lines[0].startswith("layer,circuit,pass,i,t,theta_deg,x,y,z,alpha_deg,kind")
    assert len(lines) == 1 + len(sim.samples["t"])


def test_contact_angle_on_the_cylinder(plan):
    """The laid fiber's winding angle is the helix angle the plan lays (55 deg, 86 deg hoop)."""
    sim = simulate(MACHINE, plan, gcode_text(plan, MACHINE))
    kinds = np.array(sim.samples["kind"])
    alpha = np.abs(sim.samples["alpha_deg"])
    assert np.allclose(alpha[kinds == "forward"], 55.0, atol=1e-3)
    assert np.allclose(alpha[kinds == "hoop"], 86.0, atol=1e-3)


def test_a_shifted_eye_is_seen(plan):
    """Moving every eye 0.3 mm along the axis puts it off the tangent lines: simulate reports it."""
    text = gcode_text(plan, MACHINE)
    shifted = "\n".join(
        " ".join(f"X{float(w[1:]) + 0.3:.3f}" if w.startswith("X") else w for w in line.split())
        if line.startswith("G1 ") else line for line in text.splitlines())
    sim = simulate(MACHINE, plan, shifted)
    assert 0.05 < sim.max_point_deviation_mm < 0.3 + TANGENT_TOL


def test_program_of_another_job_is_refused(plan):
    text = gcode_text(plan, MACHINE).replace("pass 3 return", "pass 99 return")
    with pytest.raises(ConfigError, match="pass 99 is not in the plan"):
        simulate(MACHINE, plan, text)


# Largest deviation measured per sample (mm, programmed points / move midpoints), chord_tolerance 0.05:
# pipe 0.0007 / 0.035, cone 0.0007 / 0.032, vessel_hemi 0.0016 / 0.036,
# vessel_isotensoid 0.0010 / 0.036, elliptic_tube 0.0008 / 0.033, vessel_laminate 0.0016 / 0.036
# (continuous turnarounds: every move within a layer lays planned fiber and is sampled).
@pytest.mark.parametrize("name", ["pipe", "cone", "vessel_hemi", "vessel_isotensoid", "elliptic_tube",
                                  "vessel_laminate"])
def test_samples_round_trip(name):
    """The shipped references of every straight-axis sample: every programmed eye within TANGENT_TOL
    of its exact tangent line, every move's midpoint (the eye the controller interpolates) within
    chord_tolerance, the fiber as planned."""
    job = job_of(SAMPLES / f"{name}.yaml")
    plan = planned(SAMPLES / f"{name}.yaml")
    text = (SAMPLES / "reference" / name / f"{name}.gcode").read_text()
    sim = simulate(job.machine, plan, text)
    assert sim.max_point_deviation_mm < TANGENT_TOL
    assert sim.max_deviation_mm < job.machine.chord_tolerance
    assert sim.fiber_length_mm == pytest.approx(plan.total_fiber_length_mm, rel=1e-5)
    # Only the moves to a new layer lay no planned fiber: every pass continues where the last ended.
    assert sim.transitions <= len(plan.layers) - 1


def test_cli_simulate_json_and_csv(tmp_path):
    import json

    from click.testing import CliRunner

    from winder.cli import main

    config = SAMPLES / "pipe.yaml"
    program = SAMPLES / "reference" / "pipe" / "pipe.gcode"
    out = tmp_path / "laid.csv"
    result = CliRunner().invoke(main, ["simulate", str(config), str(program), "--json", "-o", str(out)])
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert {"moves", "time_s", "fiber_length_mm", "max_deviation_mm"} <= set(data)
    assert data["max_deviation_mm"] < 0.05 and out.read_text().startswith("layer,circuit,pass,i,")
    bad = tmp_path / "bad.gcode"
    bad.write_text("G21\nG1 X1 A2 Q3 F100\n")
    result = CliRunner().invoke(main, ["simulate", str(config), str(bad)])
    assert result.exit_code == 2 and result.stderr.startswith("Error: ")


@pytest.mark.parametrize("turns", [20, pytest.param(100, marks=pytest.mark.skipif(
    not os.environ.get("WINDER_NIGHTLY"), reason="a minute of simulate: WINDER_NIGHTLY=1"))])
def test_long_swing_dwell_read_back_within_the_tolerance(turns: int):
    """Dwells of many turns where the ends hold the fiber: a move spans turns of the mandrel, and the
    dwell's tangent rays a turn apart nearly coincide; each move's midpoint is still found halfway
    along its own move, within chord_tolerance of the plan (20 turns in the suite, 100 nightly)."""
    from winder.config.job import parse_config  # noqa: PLC0415

    dwell = 360.0 * turns
    job = parse_config({"name": "swing", "mandrel": {"axis": {"type": "line", "length": 500},
                                                     "profile": {"type": "constant", "radius": 50}},
                        "winding": {"band_width": 10, "points": 30, "dwell": {"start": dwell, "end": dwell},
                                    "region": {"start": 10, "end": 490},
                                    "layers": [{"type": "helical", "angle": 45}]},
                        "machine": {"eye": {"clearance": 20}}}, "swing.yaml")
    plan = plan_job(job)
    sim = simulate(job.machine, plan, gcode_text(plan, job.machine))
    assert sim.max_point_deviation_mm < TANGENT_TOL
    assert sim.max_deviation_mm < job.machine.chord_tolerance
    assert sim.fiber_length_mm == pytest.approx(plan.total_fiber_length_mm, rel=1e-4)


def test_bent_axis_read_back_across_the_line_arc_joints():
    """The elbow sample (line - arc - line axis, robot poses): the surface's metric jumps where the
    line meets the arc, and the smooth path keeps the planned tangent on both sides of a point there,
    so the poses read back lie on the planned tangent lines through the joints too (a one-sided
    tangent put the eyes at the joints 5.5 mm off it)."""
    job = job_of(SAMPLES / "elbow.yaml")
    plan = planned(SAMPLES / "elbow.yaml")
    sim = simulate(job.machine, plan, gcode_text(plan, job.machine))
    assert sim.dialect == "robot"
    assert sim.max_point_deviation_mm < TANGENT_TOL
    assert sim.max_deviation_mm < job.machine.chord_tolerance
    assert sim.fiber_length_mm == pytest.approx(plan.total_fiber_length_mm, rel=1e-4)


CONFIGS = SAMPLES.parent / "configs"


@functools.cache
def _rounded_tube():
    """configs/rounded_tube.yaml's job, plan and its program read back (shared by two tests)."""
    path = CONFIGS / "rounded_tube.yaml"
    job, plan = job_of(path), planned(path)
    return job, plan, simulate(job.machine, plan, gcode_text(plan, job.machine))


def test_flat_faces_read_back_along_the_pass():
    """The rounded tube (flat faces between 15 mm corners): an eye in a face's plane fits every point
    of the flat, and the corner's tangent sweeps past eyes between its points; the contacts still
    move forward along each pass, so the fiber and the time are the plan's (each sample choosing its
    contact on its own swung back and forth along the flats: 2.5 times the fiber, 2.4 times the time)."""
    job, plan, sim = _rounded_tube()
    assert sim.fiber_length_mm == pytest.approx(plan.total_fiber_length_mm, rel=1e-4)
    assert sim.time_s == pytest.approx(build_program(plan, job.machine).times.total_s, rel=FLAT_TIME_TOL)


FLAT_TIME_TOL = 1e-3  # relative: the contacts at a corner trail the program's by a fraction of a mm (2e-4 seen)
DENSE = 200  # brute-force samples per point interval of a pass
SEARCHED_ABOVE = 0.02  # mm: the samples the brute force checks (the farthest off; 1294 of 15641)
SEARCH_TOL = 1e-3  # mm: above the chord tolerance, a ray this much nearer than the one read is a missed contact
# mm: below the tolerance a sample is not searched again (README, simulate): its read may be this much
# farther off than its best contact (0.012 seen: programmed point 2202 reads 0.025, a ray 0.013 lies near)
UNSEARCHED_TOL = 0.015


def test_no_contact_between_the_neighbours_fits_better():
    """On the rounded tube an eye far out (some 200 mm past a flat face) sees a corner's tangent sweep
    millimetres between two of the search's candidates. Every sample reads within the chord tolerance
    (the plan's directions and pieces run in the section's arc length: docs/math/12 12.2; in theta the
    program's eyes stood up to 0.3 mm off the fiber), and the reading is the best there is. Truth by
    brute force: for every sample read back more than SEARCHED_ABOVE off its tangent, no point of the
    planned pass between its neighbours' contacts (the contacts move forward, so that stretch is open
    to it) has a ray nearer its eye (the program's point 3140 was once read 0.51 mm off with a ray
    0.006 mm off between them), by more than the search's precision."""
    job, plan, sim = _rounded_tube()
    assert sim.max_deviation_mm <= job.machine.chord_tolerance
    sm = sim.samples
    by_key = {(fp.layer, fp.circuit, fp.number): fp for layer in plan.layers for fp in layer.passes}
    dense = {}  # a pass's brute-force points: t, p, d
    position = 2 * np.asarray(sm["i"]) - np.asarray(sm["mid"], dtype=int)
    order = np.lexsort((position, sm["pass"], sm["circuit"], sm["layer"]))
    checked = 0
    for j in range(1, order.size - 1):
        k, before, after = order[j], order[j - 1], order[j + 1]
        key = (sm["layer"][k], sm["circuit"][k], sm["pass"][k])
        same = all((sm["layer"][x], sm["circuit"][x], sm["pass"][x]) == key for x in (before, after))
        if not same or sm["kind"][k] not in ("forward", "return") or not sm["deviation_mm"][k] > SEARCHED_ABOVE:
            continue
        if key not in dense:
            fp = by_key[tuple(int(v) for v in key)]
            s, _, p, d = SmoothPaths(plan.surface_of(fp.layer), [fp]).point(
                np.linspace(0.0, len(fp.points) - 1, (len(fp.points) - 1) * DENSE + 1))
            dense[key] = plan.surface_of(fp.layer).t_of_s(s), p, d
        t, p, d = dense[key]
        lo, hi = sorted((sm["t"][before], sm["t"][after]))
        inside = (t >= lo - 1e-9) & (t <= hi + 1e-9)
        if not inside.any():  # the neighbours at one point: nothing between them to choose
            continue
        best = ray_distance(np.repeat(sm["eye"][k][None, :], inside.sum(), axis=0), p[inside], d[inside]).min()
        slack = SEARCH_TOL if sm["deviation_mm"][k] > job.machine.chord_tolerance else UNSEARCHED_TOL
        assert best > sm["deviation_mm"][k] - slack, (key, sm["i"][k], best, sm["deviation_mm"][k])
        checked += 1
    assert checked > 100  # the check ran on the farthest-off samples


def test_a_program_cut_short_is_refused(plan):
    """A program without its end (M2) or whose last row does not end the plan is refused, naming the line."""
    lines = gcode_text(plan, MACHINE).splitlines()
    moves = [k for k, line in enumerate(lines) if line.startswith("G1 ")]
    cut = "\n".join(lines[: moves[len(moves) // 2] + 1])  # half its moves
    with pytest.raises(ConfigError, match=r"line \d+: the program stops without its end \(M2\)") as err:
        simulate(MACHINE, plan, cut)
    assert err.value.exit_code == 2
    ended = cut.rsplit("\n", 1)[0] + "\nM2\n"
    with pytest.raises(ConfigError, match=r"line \d+: the program stops before the end of the plan"):
        simulate(MACHINE, plan, ended)


def test_a_whole_program_of_another_config_is_not_only_called_cut_short():
    """The elbow sample's program (band 10: 18 circuits) read against configs/elbow.yaml (band 8: 23
    circuits, every pass of the program among them): complete, ended by M2, yet short of that plan."""
    job = job_of(SAMPLES.parent / "configs" / "elbow.yaml")
    program = (SAMPLES / "reference" / "elbow" / "elbow.gcode").read_text()
    with pytest.raises(ConfigError) as err:
        simulate(job.machine, planned(SAMPLES.parent / "configs" / "elbow.yaml"), program, "elbow.gcode")
    text = str(err.value)
    assert "the program stops before the end of the plan of" in text and "configs/elbow.yaml" in text
    assert "(layer 1 circuit 23 pass 92): cut short, or written for another config?" in text
    assert "got its last move in layer 1 circuit 18 pass 72" in text


@pytest.mark.parametrize("text", ["", "; a comment only\n", "G21\nG90\nM2\n"])
def test_a_program_without_moves_is_refused_without_a_line_zero(plan, text):
    with pytest.raises(ConfigError) as err:
        simulate(MACHINE, plan, text, "p.gcode")
    assert str(err.value) == "p.gcode: the program has no moves"
    assert err.value.exit_code == 2


def test_a_move_beyond_the_limits_is_refused():
    """An edited X word outside machine.limits.carriage is refused with its line and value."""
    job = job_of(SAMPLES / "pipe.yaml")
    plan = planned(SAMPLES / "pipe.yaml")
    lines = gcode_text(plan, job.machine).splitlines()
    k = next(i for i, line in enumerate(lines) if line.startswith("G1 X")) + 5
    words = lines[k].split()
    lines[k] = " ".join(["G1", "X5140.303"] + words[2:])
    with pytest.raises(ConfigError, match=rf"line {k + 1}: axis X \(carriage\) outside the machine's limits "
                                          r"\[-100, 700\].*got 5140.303"):
        simulate(job.machine, plan, "\n".join(lines))


@pytest.mark.parametrize("dialect", ["generic", "linuxcnc", "marlin"])
def test_a_program_edited_by_hand_reads_as_written(plan, dialect):
    """What a controller reads alike reads alike here: inline comments, letter case, G01 for G1,
    block numbers, tabs, M30 for M2."""
    machine = replace(MACHINE, dialect=dialect)
    text = gcode_text(plan, machine)
    edited = []
    for k, line in enumerate(text.splitlines()):
        if line.startswith("G1 "):
            line = f"N{10 * k} " + line.replace("G1 ", "g01\t", 1).lower() + " ; checked (ok)"
        edited.append("M30" if line == "M2" else line)
    want, got = simulate(machine, plan, text), simulate(machine, plan, "\n".join(edited))
    assert simulation_csv(got) == simulation_csv(want)  # every sample, as read from the written program
    assert got.fiber_length_mm == want.fiber_length_mm and got.time_s == want.time_s


def test_an_eye_entering_the_mandrel_is_refused():
    """A cross-feed edited to 0 at the end of a long move: along it the eye dips into the pipe (radius
    50), deepest (41.25 mm, cross-feed 8.75) at the last sample inside the pipe's length, 7/8 of the way;
    a collision no axis limit shows; refused with its line, exit 2."""
    job = job_of(SAMPLES / "pipe.yaml")
    plan = planned(SAMPLES / "pipe.yaml")
    lines = gcode_text(plan, job.machine).splitlines()
    k = [i for i, line in enumerate(lines) if line.startswith("G1 X")][1]
    lines[k] = " ".join("Z0.000" if w.startswith("Z") else w for w in lines[k].split())
    with pytest.raises(ConfigError, match=rf"line {k + 1}: the eye enters the mandrel 0\.875 of the way along "
                                          r"the move to this point, 41\.250 mm inside") as err:
        simulate(job.machine, plan, "\n".join(lines))
    assert err.value.exit_code == 2


WRITTEN_POSE_TOL = 0.002  # mm: three coordinates rounded to 0.001 move a point at most 0.0009


def test_a_robot_pose_inside_the_mandrel_is_refused():
    """The elbow sample (robot poses): one pose moved halfway toward its closest guide point, 32.5 mm
    from the axis of the 40 mm tube: 7.5 mm inside it (to the program's 3 decimals), at the pose itself."""
    from winder.machine.envelope import eye_envelope  # noqa: PLC0415
    from winder.machine.kinematics import make_guide  # noqa: PLC0415

    job = job_of(SAMPLES / "elbow.yaml")
    plan = planned(SAMPLES / "elbow.yaml")
    lines = gcode_text(plan, job.machine).splitlines()
    k = [i for i, line in enumerate(lines) if line.startswith("G1 ")][500]
    words = lines[k].split()
    eye = np.array([[float(w[1:]) for w in words[1:4]]])
    guide = make_guide(plan.surface, eye_envelope(plan.surface, job.machine))
    rel = guide.project(eye, full=True)[2]
    moved = (eye - 0.5 * rel)[0]
    lines[k] = "G1 X%.3f Y%.3f Z%.3f " % tuple(moved) + " ".join(words[4:])
    with pytest.raises(ConfigError, match=rf"line {k + 1}: the eye enters the mandrel this point, ([\d.]+) mm "
                                          r"inside its surface at t = [\d.]+ mm, got pose X") as err:
        simulate(job.machine, plan, "\n".join(lines))
    assert err.value.exit_code == 2
    depth = float(re.search(r"this point, ([\d.]+) mm inside", str(err.value)).group(1))
    assert abs(depth - 7.5) < WRITTEN_POSE_TOL  # the moved pose is written to 3 decimals per coordinate


@pytest.mark.parametrize("edit, message", [
    (lambda w: w[:2] + ["Ainf"] + w[3:], r"A must be a finite number within \+-1e\+12, got inf"),
    (lambda w: w[:2] + ["A-1e300"] + w[3:], r"A must be a finite number within \+-1e\+12, got -1e\+300"),
    (lambda w: w[:2] + [w[1]] + w[2:], r"X given twice in one move"),
    (lambda w: w[:-1] + ["F0"], r"the feed F must be > 0 \(no controller moves at it\), got 0.0"),
])
def test_a_move_no_controller_runs_is_refused(plan, edit, message):
    """A rotation has no travel limit: an edited A of inf or -1e300 gave a time of NaN (and NaN in the
    JSON); an axis written twice or a zero feed was read as if the controller moved."""
    lines = gcode_text(plan, MACHINE).splitlines()
    k = [i for i, line in enumerate(lines) if line.startswith("G1 X")][1]
    lines[k] = " ".join(edit(lines[k].split()))
    with pytest.raises(ConfigError, match=rf"line {k + 1}: {message}") as err:
        simulate(MACHINE, plan, "\n".join(lines))
    assert err.value.exit_code == 2


@pytest.mark.parametrize("cross_feed", ["Zabc", "Z", "Zinf"])
def test_an_unreadable_fixed_eye_comment_is_refused(plan, cross_feed):
    """marlin's '; fixed eye: cross-feed Z70.000 mm' edited to garbage: an internal error before."""
    machine = replace(MACHINE, dialect="marlin")
    lines = gcode_text(plan, machine).splitlines()
    k = next(i for i, line in enumerate(lines) if line.startswith("; fixed eye: cross-feed Z"))
    lines[k] = "; fixed eye: cross-feed " + cross_feed
    with pytest.raises(ConfigError, match=rf"line {k + 1}: (unreadable cross-feed|the fixed-eye cross-feed)"):
        simulate(machine, plan, "\n".join(lines))


def test_a_program_is_read_as_a_text_file_of_bounded_size_before_planning(tmp_path, monkeypatch):
    """The program is read before the job is planned, as a regular file of at most MAX_PROGRAM_BYTES:
    `simulate CONFIG /dev/zero` read until memory ran out (tests/app/test_hostile.py), a FIFO blocked."""
    import winder.app.simulate  # noqa: PLC0415
    import winder.winding.plan  # noqa: PLC0415

    monkeypatch.setattr(winder.winding.plan, "plan", lambda job: pytest.fail("planned before reading"))
    monkeypatch.setattr(winder.app.simulate, "MAX_PROGRAM_BYTES", 100)
    big = tmp_path / "big.gcode"
    big.write_text("G21\n" * 30)
    with pytest.raises(ConfigError, match=r"big.gcode: the file has 120 bytes, more than a winding program's "
                                          r"limit of 100$"):
        simulate_files(str(SAMPLES / "pipe.yaml"), str(big))
    fifo = tmp_path / "program.gcode"
    os.mkfifo(fifo)
    with pytest.raises(ConfigError, match=r"not a regular file \(a winding program is a text file\)") as err:
        simulate_files(str(SAMPLES / "pipe.yaml"), str(fifo))
    assert err.value.exit_code == 2


def test_laid_path_over_the_program_is_refused(tmp_path):
    """`simulate job.yaml job.gcode -o job.gcode` wrote the laid path over the program it read."""
    program = tmp_path / "pipe.gcode"
    program.write_text("G21\n")
    with pytest.raises(ConfigError, match=r"^-o: is PROGRAM itself, which writing there would destroy"):
        simulate_files(str(SAMPLES / "pipe.yaml"), str(program), str(program))
    assert program.read_text() == "G21\n"


def test_a_program_without_its_pass_comments_is_refused(plan):
    """simulate reads each row's pass from the comments winder writes: a move before any says so (not
    that the pass 0 of layer 0 is not in the plan)."""
    lines = [line for line in gcode_text(plan, MACHINE).splitlines() if not line.startswith("; layer 1 circuit 1 pass 1 ")]
    first = next(k for k, line in enumerate(lines) if line.startswith("G1 "))
    with pytest.raises(ConfigError, match=rf"line {first + 1}: a move before any '; layer L circuit C pass P "
                                          r"kind' comment") as err:
        simulate(MACHINE, plan, "\n".join(lines))
    assert err.value.exit_code == 2


def test_another_jobs_program_is_named_by_its_job_line():
    """The cone sample's program read against the pipe's config: its passes are not the pipe's, and
    the program's own `; job:` line says whose it is."""
    pipe, cone = (job_of(SAMPLES / f"{name}.yaml") for name in ("pipe", "cone"))
    text = gcode_text(planned(SAMPLES / "cone.yaml"), cone.machine)
    with pytest.raises(ConfigError, match=r"is not in the plan of .*pipe\.yaml: the program was written for "
                                          r"another job \('cone', by its job line; this config plans 'pipe'\)"):
        simulate(pipe.machine, planned(SAMPLES / "pipe.yaml"), text)
