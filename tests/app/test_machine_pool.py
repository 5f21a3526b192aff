"""The machine stage's layer groups on forked workers (winder.app.machine_pool) against the same groups
built one after the other in this process: the same program; the tasks' order kept; of two groups'
errors the first group's, whichever fails first; a dying worker an error, not a hang; the time limit
stopping the workers; no worker left behind; one process inside a worker."""

from __future__ import annotations

import multiprocessing
import os
import signal
import time
from pathlib import Path

import pytest

from roundoff import assert_roundoff
from winder.app import machine_pool
from winder.app.machine_pool import run_groups, usable_workers
from winder.app.wall_clock import TimeUp, time_limit
from winder.config.job import load_config
from winder.errors import ExportError
from winder.machine.chunks import build_program_in_groups
from winder.winding.plan import plan as plan_job

ROOT = Path(__file__).resolve().parents[2]
EVERY_LAYER_ALONE = 1  # planned points per group: each layer a group of its own
HANG_GUARD_S = 60  # the pool tests' own limit: a hang fails them instead of the suite


@pytest.fixture
def two_workers(monkeypatch: pytest.MonkeyPatch) -> None:
    """Two workers whatever the cores (on one core they take turns)."""
    monkeypatch.setattr(machine_pool, "usable_workers", lambda: 2)


def test_workers_build_the_program_the_groups_build_one_by_one(tmp_path: Path, two_workers: None) -> None:
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


def test_tasks_come_back_in_order_from_the_workers(two_workers: None) -> None:
    def task(i: int) -> tuple:
        time.sleep(0.2 if i == 0 else 0.0)  # the first finishes last
        return i, os.getpid()

    with time_limit(HANG_GUARD_S):
        got = list(run_groups(task, 5))
    assert [i for i, _ in got] == list(range(5))
    assert all(pid != os.getpid() for _, pid in got)
    assert not multiprocessing.active_children()


def test_the_first_groups_error_whichever_fails_first(two_workers: None) -> None:
    def task(i: int) -> tuple:
        if i == 1:
            time.sleep(0.5)
            raise ExportError("layer 2 circuit 1 pass 2 (forward): the eye comes within 4 mm", file="t.yaml")
        if i == 2:
            raise ExportError("layer 3: another error, met first", file="t.yaml")
        return (i,)

    with time_limit(HANG_GUARD_S), pytest.raises(ExportError) as caught:
        list(run_groups(task, 4))
    assert caught.value.file == "t.yaml" and caught.value.message.startswith("layer 2 circuit 1")
    assert not multiprocessing.active_children()


def test_a_dying_worker_fails_the_program_without_a_hang(two_workers: None) -> None:
    def task(i: int) -> tuple:
        if i == 1:
            os.kill(os.getpid(), signal.SIGKILL)  # as the kernel's out-of-memory killer would
        return (i,)

    with time_limit(HANG_GUARD_S), pytest.raises(ExportError, match="worker process of the machine stage died"):
        list(run_groups(task, 3))
    assert not multiprocessing.active_children()


def test_the_time_limit_stops_the_workers(two_workers: None) -> None:
    started = time.monotonic()
    with pytest.raises(TimeUp), time_limit(1.0):
        list(run_groups(lambda i: time.sleep(HANG_GUARD_S) or (i,), 2))
    assert time.monotonic() - started < HANG_GUARD_S / 2
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
