"""The fiber tension in the robot cells' languages (docs/guide/tension.md): an
analog output, as each controller's description says (KRL $ANOUT[1] a share of the output's full
scale, RAPID SetAO in N, URScript set_standard_analog_out a share), one command per change as
written, and each language's reader (what simulate reads a program through: winder.readback.cells)
giving it back per layer; simulate itself once, on KRL."""

from __future__ import annotations

import dataclasses
import re

import pytest

from winder.app.simulate import simulate
from winder.readback.gcode import parse_program
from winder.readback.parsed import layer_tensions
from winder.config.controllers import builtin
from winder.config.job import parse_config
from winder.config.reader import load_yaml
from winder.config.robot import Pose, RobotCell
from winder.export.dialects import krl, rapid, urscript
from winder.machine.program import build_program
from winder.machine.tension import pass_tensions, with_tension
from winder.winding.plan import plan as plan_job

WRITTEN_TOL = 0.05 + 1e-9  # N: one decimal of N, or a share of 200 N to four decimals (0.01 N)
ELBOW = """
name: tension_elbow
mandrel:
  axis:
    type: path
    segments: [{line: 60}, {arc: {radius: 150, angle: 90, toward: 0}}, {line: 60}]
  profile: {type: constant, radius: 40}
winding:
  band_width: 40                    # few circuits: the readers are the point, not the pattern
  points: 40
  friction: 0.3
  tension: {start: 50, end: 35}     # over the layer's passes
  layers:
    - {type: helical, angle: 45, slip: auto}
machine:
  eye: {clearance: 25}
  robot: {arm: kuka_kr16}
"""
CELLS = {"krl": ("kuka_kr16", krl, r"\$ANOUT\[1\] = (0\.\d{4})", 200.0),
         "rapid": ("abb_irb4600", rapid, r"SetAO aoTension, (\d+\.\d);", 1.0),
         "urscript": ("ur10e", urscript, r"set_standard_analog_out\(0, (0\.\d{4})\)", 200.0)}
RING = {"kuka_kr16": Pose(x=1000, z=800, ry=-90, rz=-90), "abb_irb4600": Pose(x=1000, z=800, ry=-90, rz=-90),
        "ur10e": Pose(x=800, z=500, ry=-90, rz=-90)}


@pytest.fixture(scope="module")
def job_plan():
    job = parse_config(load_yaml(ELBOW), "tension_elbow.yaml")
    return job, plan_job(job)


@pytest.mark.parametrize("language", sorted(CELLS))
def test_each_language_sets_and_reads_back_the_tension(job_plan, language):
    job, plan = job_plan
    arm, module, pattern, scale = CELLS[language]
    machine = dataclasses.replace(job.machine, cell=RobotCell(arm, ring=RING[arm]), dialect=language)
    program = with_tension(build_program(plan, machine), pass_tensions(job, plan))
    texts = module.serialize(program)
    text = "".join(texts[k] for k in sorted(texts, key=lambda s: s != ".src"))
    written = [float(v) * scale for v in re.findall(pattern, text, re.M)]
    assert written[0] == pytest.approx(50.0, abs=WRITTEN_TOL) and written[-1] == pytest.approx(35.0, abs=WRITTEN_TOL)
    assert all(a > b for a, b in zip(written, written[1:]))  # one command per change as written, falling
    read = layer_tensions(parse_program(text, machine, f"program.{language}"))
    if language == "krl":  # simulate reads the same (its contact matching a few seconds a language)
        assert simulate(machine, plan, text, "program.krl").tensions == read
    (layer,) = read
    assert layer["tension_n"] == pytest.approx(50.0, abs=WRITTEN_TOL)
    assert layer["tension_range_n"] == pytest.approx([35.0, 50.0], abs=WRITTEN_TOL)


def test_the_pose_listing_sets_the_tension_and_rs274_reads_it(job_plan, tmp_path):
    """The robot pose listing (`<name>.gcode` of a robot cell) is G-code: M68 E0 Q<N> per change, read by
    LinuxCNC's interpreter in order."""
    from rs274_run import RS274, run_rs274  # noqa: PLC0415
    from winder.export.gcode import program_text  # noqa: PLC0415

    job, plan = job_plan
    program = with_tension(build_program(plan, job.machine), pass_tensions(job, plan))
    text = program_text(program)
    written = [float(line.split("Q")[1]) for line in text.splitlines() if line.startswith("M68 E0 Q")]
    assert written[0] == 50.0 and written[-1] == 35.0 and all(a > b for a, b in zip(written, written[1:]))
    if RS274 is None:
        pytest.skip("rs274 not installed (Debian package linuxcnc-uspace)")
    canon = run_rs274(tmp_path / "p.ngc", text)
    read = [float(v) for v in re.findall(r"SET_AUX_OUTPUT_VALUE\(0,\s*([-0-9.]+)\)", canon)]
    assert read == pytest.approx(written, abs=1e-9)


def test_a_tension_past_the_outputs_full_scale_is_refused():
    from winder.errors import ExportError  # noqa: PLC0415

    krl_post = builtin("krl")
    assert krl_post.tension_line(200.0) == "$ANOUT[1] = 1.0000"
    with pytest.raises(ExportError, match=r"a tension of 250 N is past the krl controller's analog output, 200 N"):
        krl_post.tension_line(250.0)
