"""The layers the machine stage takes in one batch (winder.machine.chunks): consecutive layers up to
a number of planned points, a larger layer alone. The work budget's memory estimate counts the
largest batch (winder.winding.budget), so both group the layers by this one rule."""

from __future__ import annotations

from collections.abc import Sequence

__all__ = ["point_groups"]


def point_groups(points: Sequence[int], most: int) -> list[list[int]]:
    """The indices of consecutive items of points (k,) (each layer's planned points) in groups of at
    most `most` points, an item larger than that alone."""
    groups: list[list[int]] = [[]]
    count = 0
    for i, n in enumerate(points):
        if groups[-1] and count + n > most:
            groups.append([])
            count = 0
        groups[-1].append(i)
        count += n
    return [g for g in groups if g]
