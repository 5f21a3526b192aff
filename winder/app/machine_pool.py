"""The machine stage's layer groups (winder.machine.chunks) on two processes at once.

A large plan's motion program is built a group of layers at a time, and the groups do not depend on
one another until they are joined, so a job run alone (not inside a batch's worker, which already has
the cores busy) builds them on up to WORKERS forked processes. Fork, not spawn: a worker inherits the
plan and the imported modules (no pickling of the plan, no second start-up); only a group's number
goes to it and only its rows (a few MB) come back. Each worker holds one group's dense arrays, so the
stage's memory is WORKERS groups' arrays on top of the plan the workers share with the parent.

A worker writes no file: TERM or INT end it at once, and it gets TERM when its parent dies (Linux,
winder.app.interrupts.worker_init); the parent stops the pool on any way out (an error, the job's time
limit, an interrupt), so no worker outlives the job.
"""

from __future__ import annotations

import multiprocessing
import os
from collections.abc import Callable

from winder.app.interrupts import worker_init
from winder.winding.memory_model import MACHINE_WORKERS as WORKERS  # the work budget counts their memory

_TASK: Callable[[int], tuple] | None = None  # the job's group task, inherited by the forked workers


def _run(i: int) -> tuple:
    assert _TASK is not None
    return _TASK(i)


def usable_workers() -> int:
    """The processes the machine stage may use: 1 inside a worker process (a batch's, or this
    pool's), where fork is not available, or on one core; else up to WORKERS."""
    if multiprocessing.parent_process() is not None or "fork" not in multiprocessing.get_all_start_methods():
        return 1
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:  # not Linux
        cores = os.cpu_count() or 1
    return max(1, min(WORKERS, cores))


def run_groups(task: Callable[[int], tuple], n: int) -> list[tuple]:
    """task(0), .., task(n - 1) in order, on up to usable_workers() forked processes (module docstring)."""
    global _TASK  # noqa: PLW0603 - handed to the forked workers
    workers = min(usable_workers(), n)
    if workers < 2:
        return [task(i) for i in range(n)]
    _TASK = task
    try:
        with multiprocessing.get_context("fork").Pool(workers, initializer=worker_init) as pool:
            return pool.map(_run, range(n), chunksize=1)
    finally:
        _TASK = None
