"""The program built a few layers at a time (winder.machine.chunks) against build_program's one batch:
the same rows (A and B continued over the groups by whole turns, the approach rows where a group's
first pass starts elsewhere), the same segments, times and written program."""

from __future__ import annotations

from pathlib import Path

from roundoff import assert_roundoff
from every_job import planned  # each sample planned once per session
from winder.config.job import load_config
from winder.export.gcode import program_text
from winder.machine.chunks import build_program_in_groups, layer_groups
from winder.machine.program import build_program
from winder.winding.plan import plan as plan_job

ROOT = Path(__file__).resolve().parents[2]
EVERY_LAYER_ALONE = 1  # planned points per group: each layer a group of its own
MAX_TIES = 2  # written lines that may differ in a last digit (a value within 1e-11 of a rounding tie)


def test_groups_follow_the_planned_points() -> None:
    plan = planned(ROOT / "samples/vessel_hemi.yaml")
    sizes = [sum(len(fp.t) for fp in layer.passes) for layer in plan.layers]
    assert [len(g) for g in layer_groups(plan, EVERY_LAYER_ALONE)] == [1] * len(sizes)
    assert [len(g) for g in layer_groups(plan, sum(sizes))] == [len(sizes)]
    assert [len(g) for g in layer_groups(plan, sizes[0])] == [1, 1]


def test_layer_by_layer_is_the_one_batch_program(tmp_path: Path) -> None:
    # A helical layer ending on a dome, then hoops; the eye follows the part at a clearance, so that
    # it is taken out and around to the hoops' start (the approach rows).
    text = (ROOT / "samples/vessel_hemi.yaml").read_text(encoding="utf-8")
    config = tmp_path / "vessel_clear.yaml"
    config.write_text(text.replace("eye: {radius: 180}", "eye: {clearance: 25}"), encoding="utf-8")
    job = load_config(config)
    plan = plan_job(job)
    whole = build_program(plan, job.machine)
    grouped = build_program_in_groups(plan, job.machine, EVERY_LAYER_ALONE)
    assert grouped.segments == whole.segments
    assert sum(seg.approach for seg in grouped.segments[1]) > 0  # the hoops are reached around the part
    for got, want in ((grouped.values, whole.values), (grouped.index, whole.index), (grouped.fiber, whole.fiber),
                      (grouped.times.time_s, whole.times.time_s), (grouped.feed, whole.feed)):
        assert_roundoff(got, want)
    # Written, the two differ at most where round-off meets a tie of the last decimal: none here.
    lines = [program_text(p, plan.band_width).splitlines() for p in (grouped, whole)]
    assert len(lines[0]) == len(lines[1])
    assert sum(a != b for a, b in zip(*lines)) <= MAX_TIES, [(a, b) for a, b in zip(*lines) if a != b][:3]
