"""Densify in one batch per layer (densify_many) writes the very program of densify pass by pass."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from every_job import job_of, planned  # each sample planned once per session
from winder.machine import batch, program
from roundoff import assert_roundoff

ROOT = Path(__file__).resolve().parents[2]


def test_batched_densify_is_pass_by_pass(monkeypatch):
    job, plan = job_of(ROOT / "samples/vessel_isotensoid.yaml"), planned(ROOT / "samples/vessel_isotensoid.yaml")
    batched = program.build_program(plan, job.machine)
    calls = []

    def one_by_one(*args, **kwargs):
        calls.append(len(args))
        return batch.all_dense(*args[:8], **kwargs)  # without axes_many: densify pass by pass

    monkeypatch.setattr(program, "straight_passes", lambda *args: None)  # the steps, not the one gather
    monkeypatch.setattr(program, "all_dense", one_by_one)
    plain = program.build_program(plan, job.machine)
    assert calls == [9]
    assert np.any(batched.index != np.round(batched.index))  # some passes were densified
    for name in ("values", "index", "fiber"):
        assert_roundoff(getattr(batched, name), getattr(plain, name), err_msg=name)
