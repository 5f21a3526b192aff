"""fiberpath (the bench extra) reads winder's marlin programs as drawn: `fiberpath plot` of the pipe's
helical layer draws every pass across the mandrel where the program moves the fiber (a move is cut
at each full turn of A: fiberpath's plot wraps a move's end at 360 deg), and the summary's
axis_travel is the program's A as written."""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
import yaml

from winder.config.job import parse_config
from winder.export.dialects.marlin import turn_cuts
from winder.export.gcode import gcode_text
from winder.export.summary import summary_dict
from winder.machine.program import build_program
from winder.winding.plan import plan as plan_job
from winder.winding.results import PassKind

FIBERPATH = shutil.which("fiberpath") or (str(Path(__import__("sys").executable).parent / "fiberpath")
                                          if (Path(__import__("sys").executable).parent / "fiberpath").exists() else None)
pytestmark = pytest.mark.skipif(FIBERPATH is None, reason="fiberpath not installed (pip install winder[bench])")
PIPE = Path(__file__).resolve().parents[2] / "samples" / "pipe.yaml"
DRAWN = 0.99  # share of the sampled points of each pass that fiberpath's plot colours
EDGE_PX = 3  # px: points this close to A = 0 / 360 deg (where the plot wraps) are not sampled


@pytest.fixture(scope="module")
def helical_pipe():
    """The pipe sample with its helical layer only (the hoop layer would cover the whole plot)."""
    data = yaml.safe_load(PIPE.read_text())
    data["winding"]["layers"] = data["winding"]["layers"][:1]
    data["machine"]["dialect"] = "marlin"
    data["machine"]["eye"] = {"radius": 70}
    job = parse_config(data, str(PIPE))
    return job, plan_job(job)


def drawn_share(image: np.ndarray, x: np.ndarray, a: np.ndarray) -> float:
    """Share of the points (carriage mm, A deg) fiberpath's plot (1 px per mm and per deg) coloured."""
    y = np.mod(a, 360.0)
    keep = (y > EDGE_PX) & (y < 360.0 - EDGE_PX) & (x >= 0.0) & (x < image.shape[1] - 1)
    px, py = np.round(x[keep]).astype(int), np.round(y[keep]).astype(int)
    white = np.all(image[py, px] == 255, axis=-1)
    return 1.0 - float(np.mean(white)) if white.size else 1.0


def test_fiberpath_plot_draws_every_pass(helical_pipe, tmp_path):
    from PIL import Image  # noqa: PLC0415 - fiberpath's own dependency

    job, plan = helical_pipe
    program = build_program(plan, job.machine)
    source = tmp_path / "pipe.gcode"
    source.write_text(gcode_text(plan, job.machine, job.winding.band_width))
    png = tmp_path / "pipe.png"
    subprocess.run([FIBERPATH, "plot", str(source), "-o", str(png)], check=True, capture_output=True, timeout=300)
    image = np.asarray(Image.open(png).convert("RGB"))
    passes = 0
    for seg in program.segments[0]:
        if seg.kind not in (PassKind.FORWARD, PassKind.RETURN):
            continue
        rows = program.values[seg.start:seg.stop]
        f = np.linspace(0.0, 1.0, 200)[:, None]
        # The straight axis-space moves between the pass's rows, A in fiberpath's sense.
        pts = np.concatenate([r0 + f * (r1 - r0) for r0, r1 in zip(rows[:-1], rows[1:])])
        share = drawn_share(image, pts[:, 0], -pts[:, 1])
        assert share >= DRAWN, (seg, share)
        passes += 1
    assert passes == 38  # 19 circuits forward and back


def test_marlin_moves_within_one_turn_and_travel_as_written(helical_pipe):
    job, plan = helical_pipe
    text = gcode_text(plan, job.machine, job.winding.band_width)
    a = np.array([float(w[1:]) for line in text.splitlines() if line.startswith("G1 ")
                  for w in line.split() if w[0] == "A"])
    crossing = np.floor(a[1:] / 360.0) != np.floor(a[:-1] / 360.0)
    assert all(turn_cuts(a0, a1).size == 0 for a0, a1 in zip(a[:-1][crossing], a[1:][crossing]))
    assert np.all(np.abs(np.diff(a)) < 360.0 + 1e-3)
    travel = summary_dict(plan, job.machine)["axis_travel"]["rotation"]
    assert travel == pytest.approx([a.min(), a.max()], abs=1e-9)
    assert travel[0] > 0.0  # A grows as the mandrel winds (fiberpath's sense), as written


def test_fiberpath_simulate_reads_it(helical_pipe, tmp_path):
    job, plan = helical_pipe
    source = tmp_path / "pipe.gcode"
    source.write_text(gcode_text(plan, job.machine, job.winding.band_width))
    out = subprocess.run([FIBERPATH, "simulate", "--json", str(source)], check=True, capture_output=True,
                         text=True, timeout=300)
    result = json.loads(out.stdout)
    assert result["tow_length_mm"] > plan.total_fiber_length_mm * 0.99
