"""A job's wall-clock limit (`--time-limit` of run, simulate, geodesic): SIGALRM raises TimeUp in the
main thread when it runs out. The stop signals TERM and INT are winder.app.interrupts'.
"""

from __future__ import annotations

import signal
import time
from collections.abc import Iterator
from contextlib import contextmanager

__all__ = ["TimeUp", "time_limit", "time_up_message"]


class TimeUp(BaseException):
    """A job's wall-clock limit ran out (time_limit). A BaseException, so that it unwinds through
    the solvers' own `except Exception` and the job's writes roll back; run_job reports it (exit 1).
    activity: what the job was doing then (winder.progress.doing), None if it did not say."""

    def __init__(self, activity: str | None = None) -> None:
        super().__init__(activity)
        self.activity = activity


def _time_up(signum: int, frame) -> None:
    from winder.progress import activity  # noqa: PLC0415

    raise TimeUp(activity())


@contextmanager
def time_limit(seconds: float | None) -> Iterator[None]:
    """Raise TimeUp in this (main) thread after seconds of wall-clock time (None: no limit). The
    guard of solvers that cannot converge (an integrator taking ever smaller steps, L-BFGS at its
    iteration cap): whatever the job computes, it ends. A timer set before is restored after."""
    if not seconds:
        yield
        return
    try:
        old_handler = signal.signal(signal.SIGALRM, _time_up)
    except ValueError:  # not the main thread: no signals here
        yield
        return
    old_delay, old_interval = signal.setitimer(signal.ITIMER_REAL, seconds)
    started = time.monotonic()
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old_handler)
        if old_delay > 0:
            left = old_delay - (time.monotonic() - started)
            signal.setitimer(signal.ITIMER_REAL, max(left, 1e-3), old_interval)


def time_up_message(seconds: float | None, activity: str | None) -> str:
    """The message of a job stopped by its time limit, naming what it was doing (winder.progress.doing);
    past the reading and the checks, a job's time goes to its solvers."""
    head = f"the job did not finish within its time limit of {seconds:g} s (--time-limit)"
    if activity is None:
        return f"{head}; its solvers do not converge on this mandrel in reasonable time"
    return f"{head}: stopped while {activity}"
