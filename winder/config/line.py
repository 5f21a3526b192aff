"""The straight guide of `mandrel.axis`: the round tube's axis (winder.config.mandrel) and a segment
of a bent path (winder.config.axes), in a module of its own so that neither imports the other."""

from __future__ import annotations

import dataclasses

__all__ = ["LineAxis"]


@dataclasses.dataclass(frozen=True)
class LineAxis:
    """A straight guide along +z; length in mm."""

    length: float
