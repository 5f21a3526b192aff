"""Progress of a long computation, reported through a callback: the library never prints.

A Progress callback receives (fraction, label): how much of the whole task is done, in [0, 1],
non-decreasing, and what is being done now ("layer 2 of 3: circuit 14 of 59"). The command line
draws it as a bar on stderr; everything else passes None, and nothing is reported.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager

Progress = Callable[[float, str], None]


def monotone(progress: Progress | None) -> Progress | None:
    """The callback with its fraction never stepping back (a layer planned again with more circuits
    starts its circuits over; the bar holds still instead)."""
    if progress is None:
        return None
    best = [0.0]

    def report(fraction: float, label: str) -> None:
        best[0] = max(best[0], float(fraction))
        progress(best[0], label)

    return report


def part(progress: Progress | None, start: float, end: float) -> Progress | None:
    """The callback of a sub-task that spans [start, end] of the whole: its own 0..1 mapped there."""
    if progress is None:
        return None

    def report(fraction: float, label: str) -> None:
        progress(start + (end - start) * min(max(float(fraction), 0.0), 1.0), label)

    return report


_DOING: list[str] = []  # what this process is doing now, innermost last (doing)


@contextmanager
def doing(what: str) -> Iterator[None]:
    """Say what this process does while inside, for a message that stops it there: a job's time
    limit names it (waiting for a folder's lock, reading a config) instead of guessing."""
    _DOING.append(what)
    try:
        yield
    finally:
        _DOING.pop()


def activity() -> str | None:
    """What doing says this process is doing now (the innermost), or None."""
    return _DOING[-1] if _DOING else None
