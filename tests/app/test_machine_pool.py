"""The machine stage's layer groups on forked workers (winder.app.machine_pool) against the same groups
built one after the other in this process: the same program; the tasks' order kept; an error raised
in a worker reaching the job as raised; no worker left behind; one process inside a worker."""

from __future__ import annotations

import multiprocessing
import os
from pathlib import Path

import pytest

from roundoff import assert_roundoff
from winder.app.machine_pool import run_groups, usable_workers
from winder.config.job import load_config
from winder.errors import ExportError
from winder.machine.chunks import build_program_in_groups
from winder.winding.plan import plan as plan_job

ROOT = Path(__file__).resolve().parents[2]
EVERY_LAYER_ALONE = 1  # planned points per group: each layer a group of its own


def test_workers_build_the_program_the_groups_build_one_by_one(tmp_path: Path) -> None:
    text = (ROOT / "samples/vessel_hemi.yaml").read_text(encoding="utf-8")
    config = tmp_path / "vessel_clear.yaml"  # the eye at a clearance: approach rows between the groups
    config.write_text(text.replace("eye: {radius: 180}", "eye: {clearance: 25}"), encoding="utf-8")
    job = load_config(config)
    plan = plan_job(job)
    alone = build_program_in_groups(plan, job.machine, EVERY_LAYER_ALONE)
    pooled = build_program_in_groups(plan, job.machine, EVERY_LAYER_ALONE, run_groups=run_groups)
    assert pooled.segments == alone.segments
    for got, want in ((pooled.values, alone.values), (pooled.index, alone.index), (pooled.fiber, alone.fiber),
                      (pooled.times.time_s, alone.times.time_s)):
        assert_roundoff(got, want)
    assert not multiprocessing.active_children()


def test_tasks_come_back_in_order_from_the_workers() -> None:
    got = run_groups(lambda i: (i, os.getpid()), 5)
    assert [i for i, _ in got] == list(range(5))
    if usable_workers() >= 2:
        assert all(pid != os.getpid() for _, pid in got)
    assert not multiprocessing.active_children()


def test_an_error_in_a_worker_reaches_the_job_as_raised() -> None:
    def task(i: int) -> tuple:
        if i == 2:
            raise ExportError("layer 3 circuit 1 pass 2 (forward): the eye comes within 4 mm", file="t.yaml")
        return (i,)

    with pytest.raises(ExportError) as caught:
        run_groups(task, 4)
    assert caught.value.file == "t.yaml" and caught.value.message.startswith("layer 3 circuit 1")
    assert not multiprocessing.active_children()


def _report_workers(queue) -> None:
    queue.put(usable_workers())


def test_one_process_inside_a_worker() -> None:
    ctx = multiprocessing.get_context("fork")
    queue = ctx.Queue()
    child = ctx.Process(target=_report_workers, args=(queue,))
    child.start()
    child.join(timeout=60)
    assert queue.get(timeout=5) == 1
