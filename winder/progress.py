"""Progress of a long computation, reported through a callback: the library never prints.

A Progress callback receives (fraction, label): how much of the whole task is done, in [0, 1],
non-decreasing, and what is being done now ("layer 2 of 3: circuit 14 of 59"). The command line
draws it as a bar on stderr; everything else passes None, and nothing is reported.
"""

from __future__ import annotations

from collections.abc import Callable

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
