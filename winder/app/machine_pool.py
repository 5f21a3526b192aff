"""The machine stage's layer groups (winder.machine.chunks) on two processes at once, and the outputs
that need no motion program rendered aside while it is built.

A large plan's motion program is built a group of layers at a time, and the groups do not depend on
one another until they are joined, so a job run alone on Linux (not inside a batch's worker, whose
siblings already have the cores busy) builds them on up to WORKERS forked processes. Fork, not spawn:
a worker inherits the plan and the imported modules (no pickling of the plan, no second start-up);
only a group's number goes to it and only its rows (a few MB) come back.

The results come back in the groups' order, each as its group is joined, so the job meets the same
error first that it meets building the groups one by one (a group's own, or a join's), whichever
worker finished first. A worker writes no file: TERM or INT end it at once, and it gets TERM when its
parent dies (winder.app.interrupts.worker_init); the workers start with the stop signals held back
(as a batch's do) and are stopped on any way out: an error, the job's time limit, an interrupt. A
worker that dies (killed, out of memory) fails the program with an ExportError, never a hang.
"""

from __future__ import annotations

import multiprocessing
import os
import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import TypeVar

from winder.app.interrupts import stop_signals_held_back, stop_workers, worker_init
from winder.errors import ExportError
from winder.winding.memory_model import MACHINE_WORKERS as WORKERS  # the work budget counts their memory

_TASK: Callable[[int], tuple] | None = None  # in a worker: the job's group task, handed over at the fork
T = TypeVar("T")


def _start(task: Callable[[int], tuple]) -> None:
    global _TASK  # noqa: PLW0603 - this worker's own copy
    worker_init()
    _TASK = task


def _run(i: int) -> tuple:
    assert _TASK is not None
    return _TASK(i)


def usable_workers() -> int:
    """The processes the machine stage may use: 1 inside another process's worker (a batch's jobs
    have the cores busy, and a pool's workers are not to start pools), off Linux (a worker would not
    end with its parent) or on one core; else up to WORKERS."""
    if multiprocessing.parent_process() is not None or not sys.platform.startswith("linux"):
        return 1
    return max(1, min(WORKERS, len(os.sched_getaffinity(0))))


def run_groups(task: Callable[[int], tuple], n: int) -> Iterator[tuple]:
    """task(0), .., task(n - 1), yielded in order, on up to usable_workers() forked processes
    (module docstring); one after the other in this process where one is all there is."""
    workers = min(usable_workers(), n)
    if workers < 2:
        yield from (task(i) for i in range(n))
        return
    from concurrent.futures import ProcessPoolExecutor  # noqa: PLC0415 - a job of one group never needs it
    from concurrent.futures.process import BrokenProcessPool  # noqa: PLC0415

    # Fork hands the task (a closure over the plan) to the workers as it is, unpickled.
    pool = ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("fork"),
                               initializer=_start, initargs=(task,))
    try:
        with stop_signals_held_back():  # the workers and the pool's threads start here
            futures = [pool.submit(_run, i) for i in range(n)]
        for i in range(n):
            try:
                rows = futures[i].result()
            except BrokenProcessPool as exc:
                raise ExportError("a worker process of the machine stage died before its layers were built "
                                  "(killed, or out of memory)") from exc
            futures[i] = None  # the rows are the caller's now
            yield rows
    except BaseException:  # an error, the time limit, an interrupt, or the caller done early
        stop_workers(pool)
        raise
    pool.shutdown(wait=True)


@contextmanager
def aside(task: Callable[[], T]) -> Iterator[Callable[[], T]]:
    """task() on one forked process while the caller goes on; yields the function that waits for its
    result (or raises its error). Where usable_workers() is 1, task runs when its result is asked for.

    A job's outputs that need no motion program (the CSV, the meshes) are rendered so while the
    program is built: their work, and the mesh library's import, leave the job's wall time.
    """
    if usable_workers() < 2:
        yield task
        return
    from concurrent.futures import ProcessPoolExecutor  # noqa: PLC0415
    from concurrent.futures.process import BrokenProcessPool  # noqa: PLC0415

    pool = ProcessPoolExecutor(max_workers=1, mp_context=multiprocessing.get_context("fork"),
                               initializer=_start, initargs=(lambda _i: task(),))

    def result() -> T:
        try:
            return future.result()
        except BrokenProcessPool as exc:
            raise ExportError("a worker process rendering the outputs died before it finished "
                              "(killed, or out of memory)") from exc

    try:
        with stop_signals_held_back():
            future = pool.submit(_run, 0)
        yield result
    except BaseException:
        stop_workers(pool)
        raise
    pool.shutdown(wait=True)
