"""The straight-axis program with each contact point's eye found once (winder.machine.straight)
against the program's steps (batch.all_dense, then axis_batch.straight_axes): the same program, bit
for bit, on samples whose passes densify by even factors (dense points at the midpoints), odd ones
(none there) and not at all."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from every_job import job_of, planned  # each sample planned once per session
from winder.machine import program, straight
from winder.machine.chords import CLEAR_ROUNDS
from winder.winding.plan import plan as plan_job
from roundoff import assert_roundoff

ROOT = Path(__file__).resolve().parents[2]


def _bits(a: np.ndarray) -> np.ndarray:
    return np.ascontiguousarray(a).view(np.uint8)


@pytest.mark.parametrize("sample", ["cone", "pipe", "elliptic_tube", "vessel_isotensoid"])
def test_gathered_program_is_the_steps(sample, monkeypatch):
    job, plan = job_of(ROOT / "samples" / f"{sample}.yaml"), planned(ROOT / "samples" / f"{sample}.yaml")
    calls = []
    real = straight.straight_passes
    monkeypatch.setattr(program, "straight_passes", lambda *a: calls.append(1) or real(*a))
    gathered = program.build_program(plan, job.machine)
    monkeypatch.setattr(program, "straight_passes", lambda *args: None)
    steps = program.build_program(plan, job.machine)
    # once, and once more per round of the clearance's refinement (winder.machine.chords.refine)
    assert 1 <= len(calls) <= 1 + CLEAR_ROUNDS
    for name in ("values", "index", "fiber", "feed"):
        assert_roundoff(getattr(gathered, name), getattr(steps, name), err_msg=name)
    assert gathered.segments == steps.segments


def test_a_program_no_pass_of_which_densifies_is_the_steps(monkeypatch):
    # hoop traverses on a cylinder (fiberpath's simple_cylinder): the rows are the planned points as they are
    from winder.config.job import parse_config  # noqa: PLC0415

    job = parse_config({"name": "hoops", "mandrel": {"axis": {"type": "line", "length": 500},
                                                     "profile": {"type": "constant", "radius": 35}},
                        "winding": {"band_width": 7, "layers": [{"type": "hoop", "passes": 2}]},
                        "machine": {"eye": {"clearance": 20}, "feed": 9000, "chord_tolerance": 0.05}}, "hoops.yaml")
    plan = plan_job(job)
    seen = []
    real = straight._assemble
    monkeypatch.setattr(straight, "_assemble", lambda *a: seen.append(a[6]) or real(*a))
    gathered = program.build_program(plan, job.machine)
    assert seen and all(dn is None for dn in seen[0])
    monkeypatch.setattr(program, "straight_passes", lambda *args: None)
    steps = program.build_program(plan, job.machine)
    for name in ("values", "index", "fiber", "feed"):
        assert_roundoff(getattr(gathered, name), getattr(steps, name), err_msg=name)
    assert gathered.segments == steps.segments


def test_a_lead_that_fails_leaves_it_to_the_steps(monkeypatch):
    job, plan = job_of(ROOT / "samples" / "pipe.yaml"), planned(ROOT / "samples" / "pipe.yaml")

    def refuse(*args, **kwargs):
        raise straight.ExportError("no lead")

    monkeypatch.setattr(straight, "lead_straight", refuse)
    env = program.eye_envelope(plan.outer_surface, job.machine)
    passes = [fp for layer in plan.layers for fp in layer.passes if len(fp.points)]
    assert straight.straight_passes(plan, passes, [""] * len(passes), env, job.machine, 1.0, 1.0, 1.0, 0.05) is None


@pytest.mark.parametrize("n, factor", [(2, 2), (5, 2), (7, 3), (11, 4), (9, 5)])
def test_pool_template_is_the_masked_rows(n, factor):
    """A dense pass's rows from its cached (local, pool) template and three offsets are those of
    the planned / midpoint / other masks, each pool's rows in order."""
    u, planned, at_mid, others, interval, local, pool = straight._dense_rows(n, factor)
    start, mid0, extra0 = 17, 1000, 5000
    want = np.empty(u.size, dtype=np.int64)
    want[planned] = start + interval[planned]
    want[at_mid] = mid0 + interval[at_mid]
    want[others] = extra0 + np.arange(int(np.count_nonzero(others)))
    assert np.array_equal(local + np.array([start, mid0, extra0])[pool], want)
    plain_local, plain_pool = straight._plain_rows(n)
    assert np.array_equal(plain_local + start, np.arange(start, start + n)) and not plain_pool.any()
